"""The contact stiffness K of a clearance joint, pinned against its closed form (Lankarani & Nikravesh 1990; paper
Eq. 17 as corrected in reference/paper-notes.md):

    K = 4 / (3 (h_i + h_j)) * sqrt(R_i R_j / (R_i - R_j)),   h_k = (1 - nu_k^2) / E_k,

and the same value wherever jointwear uses it: the settings, the kernel arrays, the kernel's worn radii and the
initial preload.
"""

import math

import numpy as np
import pytest

from jointwear.config import load_config
from jointwear.contact.geometry import ClearanceGeometry
from jointwear.contact.laws import compliance, contact_stiffness, contact_stiffness_py
from jointwear.mechanism import build_model
from jointwear.mechanism import kernel as K
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.simulate import simulate


def closed_form(e_i, nu_i, e_j, nu_j, r_i, r_j):
    hsum = (1.0 - nu_i**2) / e_i + (1.0 - nu_j**2) / e_j
    return 4.0 / (3.0 * hsum) * math.sqrt(r_i * r_j / (r_i - r_j))


def test_steel_pin_in_a_steel_hole():
    """E = 207 GPa, nu = 0.3 on both sides, R_i = 10.05 mm, R_j = 10 mm: h = 0.91 / 207 GPa = 4.396e-12 1/Pa,
    R_i R_j / (R_i - R_j) = 2.01 m, K = 4 / (3 * 8.792e-12) * sqrt(2.01) = 2.150e11 N/m^1.5 (by hand)."""
    assert compliance(207e9, 0.3) == pytest.approx(4.396e-12, rel=1e-4)
    assert contact_stiffness_py(207e9, 0.3, 207e9, 0.3, 10.05e-3, 10e-3) == pytest.approx(2.150e11, rel=1e-3)
    assert contact_stiffness(2 * compliance(207e9, 0.3), 10.05e-3, 10e-3) == contact_stiffness_py(
        207e9, 0.3, 207e9, 0.3, 10.05e-3, 10e-3)


@pytest.mark.parametrize("preset", ["jin2025_flapping_wing", "flores_slider_crank"])
def test_every_user_of_k_agrees_with_the_closed_form(preset):
    model = build_model(load_config(preset))
    cj = model.clearance_joints[0]
    s = cj.spec
    bm, jm = s.bearing_material, s.journal_material
    k0 = closed_form(bm.youngs_modulus, bm.poissons_ratio, jm.youngs_modulus, jm.poissons_ratio,
                     s.bearing_radius, s.journal_radius)
    assert s.stiffness == pytest.approx(k0, rel=1e-14)
    assert model.kernel_arrays()["cpar"][0, K.C_K0] == pytest.approx(k0, rel=1e-14)
    # the initial preload along the nominal K and along the K of the (unworn) geometry: one state
    unworn = [ClearanceGeometry(j.spec.bearing_radius, j.spec.journal_radius) for j in model.clearance_joints]
    a, b = initial_state(model), initial_state(model, geometry=unworn)
    np.testing.assert_array_equal(a.y, b.y)
    # a uniform growth g: the arrays and the kernel take K at the worn radii R_i + g/2, R_j - g/2
    g = 4e-6
    grown = [ClearanceGeometry(j.spec.bearing_radius, j.spec.journal_radius, g) for j in model.clearance_joints]
    kg = closed_form(bm.youngs_modulus, bm.poissons_ratio, jm.youngs_modulus, jm.poissons_ratio,
                     s.bearing_radius + g / 2, s.journal_radius - g / 2)
    assert model.kernel_arrays(grown)["cpar"][0, K.C_K0] == pytest.approx(kg, rel=1e-14)
    trace = simulate(model, 0.02, geometry=grown, settle_cycles=0.0).joints[0]
    np.testing.assert_allclose(trace.stiffness, kg, rtol=1e-14)
