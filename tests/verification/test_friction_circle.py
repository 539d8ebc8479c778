"""The friction circle of a steadily loaded pin (docs/verification.md, case 1)."""

import math

import numpy as np
import pytest

from jointwear.mechanism import simulate

from .closed_form import friction_circle


@pytest.fixture(scope="module")
def steady(rig_model):
    return simulate(rig_model, 4, settle_cycles=3, rtol=5e-7, atol=5e-10)


def test_contact_sits_atan_mu_from_the_load_line_with_n_equal_w_cos_phi(steady, rig):
    phi, n_expected, psi = friction_circle(rig)
    tr = steady.joints[0]
    w = tr.dt_weight
    # bearing frame: x along the pendulum (down at rest), so the load line (up) is 180 deg; the pin turns CCW, its
    # surface slides to -x at the top and drags the bore that way: the contact moves to the bore's +x side, i.e.
    # clockwise from the load line in the bearing frame, and the frame itself turns by the tilt psi.
    theta = math.degrees(np.angle(np.sum(w * np.exp(1j * tr.theta_bearing)))) % 360.0
    expected = 180.0 - math.degrees(phi) - math.degrees(psi)
    # 0.05 deg: the pin's centripetal acceleration (1 mm x omega^2 = 0.4 % of g) turns the load line by +-0.23 deg
    # once per cycle, and the pendulum's free swing (undamped while the pin slides: the friction torque is constant)
    # turns the bearing frame by up to 0.8 deg at a 0.73 s period; neither averages out exactly over the 4 s window
    assert theta == pytest.approx(expected, abs=0.05)
    n_mean = float(np.sum(w * tr.force_normal) / np.sum(w))
    # 0.1 %: the same +-0.4 % load wobble, first order zero over whole cycles; the centrifugal part of the swing
    # (m arm psi_dot^2 ~ 1e-4 N) is negligible
    assert n_mean == pytest.approx(n_expected, rel=1e-3)


def test_pendulum_tilt_is_the_friction_circle_offset(steady, rig):
    _, _, psi = friction_circle(rig)
    t = steady.t
    pend = steady.body_names.index("pendulum")
    tilt = steady.body_angles[:, pend] + math.pi / 2  # drawn hanging straight down (-90 deg)
    # the tilt is psi plus the undamped free swing at the pendulum's own frequency and the forced response at the
    # crank frequency; a least-squares fit with both frequencies (closed form: omega_n^2 = m g arm / I_pin)
    w_n = math.sqrt(rig.mass * 9.80665 * rig.arm / (rig.inertia + rig.mass * rig.arm**2))
    basis = np.column_stack([np.ones_like(t), np.cos(w_n * t), np.sin(w_n * t), np.cos(rig.omega * t),
                             np.sin(rig.omega * t)])
    coef, *_ = np.linalg.lstsq(basis, tilt, rcond=None)
    # 1 %: the fit residual is 3e-3 deg on a 0.29 deg offset; the friction circle uses the bore radius for the
    # contact point, which the penetration and the eccentricity move by (c0 + delta) / arm ~ 3e-4 relative
    assert coef[0] == pytest.approx(psi, rel=1e-2)
    assert abs(coef[1]) + abs(coef[2]) > 0.0  # the fit does see the free swing (it is not a constant)
