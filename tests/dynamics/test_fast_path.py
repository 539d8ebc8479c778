"""The natural-coordinate four-bar kernel gives the same answers as the general Cartesian kernel."""

import numpy as np
import pytest

from jointwear.config import load_config
from jointwear.contact import ClearanceGeometry
from jointwear.mechanism import build_model, simulate


@pytest.fixture(scope="module")
def model():
    return build_model(load_config("jin2025_flapping_wing"))


def test_fast_path_selected(model):
    assert simulate(model, 0.01, settle_cycles=0).extra["kernel"] == "natural_fourbar"
    assert simulate(model, 0.01, settle_cycles=0, fast=False).extra["kernel"] == "cartesian"
    assert simulate(build_model(load_config("flores_slider_crank")), 0.01, settle_cycles=0).extra["kernel"] == "tree"


@pytest.mark.parametrize("use_profile", [False, True])
def test_same_trajectory_short_window(model, use_profile):
    """Over 2 ms (~120 steps, before the rattling makes trajectories diverge) both kernels agree to
    well within the integration tolerance times the number of steps."""
    prof = 0.3e-6 * (1 + np.cos(np.linspace(0, 2 * np.pi, 360, endpoint=False)))
    geo = [ClearanceGeometry(1.002e-3, 1e-3, 0.0, prof, 0.5 * prof, use_profile=use_profile)]
    n = 0.016  # cycles
    a = simulate(model, n, geometry=geo, settle_cycles=0, fast=False, rtol=1e-9, atol=1e-13)
    b = simulate(model, n, geometry=geo, settle_cycles=0, fast=True, rtol=1e-9, atol=1e-13)
    t = np.linspace(a.t[0], a.t[-1], 50)
    fa = np.interp(t, a.t, a.joints[0].force_normal)
    fb = np.interp(t, b.t, b.joints[0].force_normal)
    # relative to the peak: 1e-3 in continuous contact; 5e-3 with the worn profile, whose larger
    # clearance starts the journal in free flight, so narrow impact pulses are interpolated between
    # the kernels' different step sequences (measured 2e-4 and 3e-3)
    assert np.max(np.abs(fa - fb)) < (5e-3 if use_profile else 1e-3) * np.max(np.abs(fa))
    for k in range(a.q.shape[1]):
        qa = np.interp(t, a.t, a.q[:, k])
        qb = np.interp(t, b.t, b.q[:, k])
        # positions 1e-10 m (0.005 % of the clearance), angles 1e-8 rad: linear interpolation between
        # the two kernels' different step sequences limits the comparison (measured 1e-11 m, 2e-9 rad)
        # (worn profile: free flight and impacts from the start amplify differences: 5e-10 m, 5e-8 rad)
        tol = (5e-8 if k % 3 == 2 else 5e-10) if use_profile else (1e-8 if k % 3 == 2 else 1e-10)
        assert np.max(np.abs(qa - qb)) < tol
    ta = np.interp(t, a.t, np.unwrap(a.joints[0].theta_bearing))
    tb = np.interp(t, b.t, np.unwrap(b.joints[0].theta_bearing))
    assert np.max(np.abs(ta - tb)) < 1e-4
    np.testing.assert_allclose(a.joints[0].bearing_body_angle[-1], b.joints[0].bearing_body_angle[-1], atol=1e-9)


def test_same_cycle_statistics(model):
    a = simulate(model, 2, settle_cycles=1, fast=False)
    b = simulate(model, 2, settle_cycles=1, fast=True)
    ta, tb = a.joints[0], b.joints[0]
    # 2 %: cycle-to-cycle scatter of the mean force from the rattling near force reversals is ~1 %
    assert tb.mean_force == pytest.approx(ta.mean_force, rel=0.02)
    assert tb.contact_fraction == pytest.approx(ta.contact_fraction, abs=0.02)
    # both report accelerations in Cartesian coordinates
    assert a.qdd.shape[1] == b.qdd.shape[1] == 6
    # the rocker swing is kinematic: same extremes (1e-5 rad ~ 0.1 um at B, clearance-sized differences)
    ia = a.free_body_names.index("rocker")
    ib = b.free_body_names.index("rocker")
    assert a.q[:, 3 * ia + 2].max() == pytest.approx(b.q[:, 3 * ib + 2].max(), abs=1e-5)
    assert a.q[:, 3 * ia + 2].min() == pytest.approx(b.q[:, 3 * ib + 2].min(), abs=1e-5)
