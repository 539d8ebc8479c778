"""The pendulum's eye rocking on the pin at the frequency of its linearisation (docs/verification.md, case 7)."""

import dataclasses

import numpy as np
import pytest

from jointwear.config import updated
from jointwear.mechanism import build_model, simulate

from .closed_form import rocking_frequency, spectral_peak


@pytest.fixture(scope="module")
def frictionless_model(rig_config):
    # without friction the contact stays on the load line (N = W) and nothing damps the rocking: the crank's start
    # excites it and it keeps its frequency
    return build_model(updated(rig_config, {"clearance_joints.0.friction.law": "none"}))


@pytest.mark.parametrize("growth", [0.0, 100e-6])  # the unworn bore (196 Hz) and a clearance grown 5-fold (89 Hz)
def test_eye_rocks_on_the_pin_at_sqrt_n_over_e_m(frictionless_model, rig, growth):
    g0 = frictionless_model.initial_geometry()
    res = simulate(frictionless_model, 3, geometry=[dataclasses.replace(g0[0], clearance_growth=growth)],
                   settle_cycles=1)
    e = res.joints[0].eccentricity_global
    angle = np.unwrap(np.arctan2(e[:, 1], e[:, 0]))  # the eye's position along the bore
    measured = spectral_peak(res.joints[0].t, angle, above=10.0)
    # 0.5 %: the pin's centripetal acceleration (0.4 % of g) modulates N, hence the frequency by +-0.2 %, once per
    # cycle (sidebands 1 Hz off the peak, not a shift of it); the path's curvature shifts the frequency by
    # (amplitude)^2 / 16 ~ 1e-4 and the pendulum's own swing (1.37 Hz) couples in at (1.37 Hz / f)^2 < 3e-4
    assert measured == pytest.approx(rocking_frequency(rig, rig.weight, growth), rel=5e-3)
