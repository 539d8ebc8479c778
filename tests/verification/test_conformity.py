"""The indicator of uniform mode's range (docs/wear.md, "When uniform mode is fair") on the pendulum rig.

conformity = acos(c0 / (c0 + h)) / (b / R_b), with Johnson's half-width b at the mean contact force on the unworn
bore; uniform mode is fair while it stays <= 1, i.e. below the depth h* = c0 (1 / cos(b / R_b) - 1).
"""

import math

import pytest

from jointwear.config import updated
from jointwear.study import Study
from jointwear.wear import wear_history

from .closed_form import friction_circle, half_width

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def test_rig_half_width_and_conformity_against_johnson(rig, rig_config, rig_model):
    settings = updated(rig_config, {"wear.geometry_mode": "uniform"}).wear
    joint = wear_history(rig_model, settings, 500).joints[0]
    _, n_force, _ = friction_circle(rig)
    b = half_width(n_force, rig.r_b, rig.r_j, rig.hsum, rig.width)
    # 1 %: b goes as the square root of the mean force, which the pendulum's swing (0.4 % of g) and the contact's
    # ringing move by < 1 %
    assert abs(joint.contact_half_width / b - 1.0) < 0.01, (joint.contact_half_width, b)
    c0 = rig.clearance
    h = joint.max_bearing_wear  # the pocket: the rig's journal does not wear and its bore's far side is unworn
    assert joint.pocket_depth == h
    assert math.isclose(joint.conformity, math.acos(c0 / (c0 + h)) / (b / rig.r_b), rel_tol=0.01)
    h_star = c0 * (1.0 / math.cos(b / rig.r_b) - 1.0)  # 0.056 um: a few revolutions of wear
    assert h > 10 * h_star and joint.conformity > 1.0 and joint.uniform_mode_valid is False


def test_the_pocket_is_the_depths_range_of_the_bore_and_of_the_pin(rig_config, rig_model):
    """A ring worn evenly round the bore (a load that turns with the journal: uniform and profile modes agree to
    0.1 %) is no pocket; a flat worn on a pin under a load fixed on it is one (uniform mode 9.5x too deep there)."""
    import dataclasses

    import numpy as np

    settings = updated(rig_config, {"wear.geometry_mode": "uniform"}).wear
    joint = wear_history(rig_model, settings, 100).joints[0]
    flat = 1e-6 * np.exp(-0.5 * ((joint.theta - np.pi) / 0.2) ** 2)  # a 1 um flat, as the rig's bore pocket
    ring = dataclasses.replace(joint, bearing_wear=np.full_like(joint.theta, 1e-6), journal_wear=0 * joint.theta)
    assert ring.pocket_depth == 0.0 and ring.conformity == 0.0 and ring.uniform_mode_valid
    pin = dataclasses.replace(joint, bearing_wear=0 * joint.theta, journal_wear=flat)
    bore = dataclasses.replace(joint, bearing_wear=flat, journal_wear=0 * joint.theta)
    assert pin.pocket_depth == bore.pocket_depth == flat.max() - flat.min()
    assert pin.conformity == bore.conformity > 1.0 and not pin.uniform_mode_valid


def test_the_wear_stage_says_when_uniform_mode_is_out_of_range(rig_config, tmp_path):
    lines: list[str] = []
    cfg = updated(rig_config, {"wear.geometry_mode": "uniform", "wear.cycles": 500})
    Study(cfg, out=tmp_path / "u", echo=lines.append).wear()
    assert any("uniform mode is outside its range" in line and '"profile"' in line for line in lines), lines
    lines.clear()
    Study(updated(cfg, {"wear.geometry_mode": "profile"}), out=tmp_path / "p", echo=lines.append).wear()
    assert lines and not any("outside its range" in line for line in lines), lines
    # and says that its answer is the one to trust here (the conformity > 1)
    assert any(line.startswith("wear: profile mode follows the worn shape here (conformity") for line in lines), lines
