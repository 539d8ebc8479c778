"""Where the Hertz contact law holds: the simulate stage measures each joint's contact half-angle at its largest
normal force and warns, in the stage and the report, past contact.geometry.HERTZ_HALF_ANGLE_LIMIT."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import jointwear
from jointwear.config import load_config, updated
from jointwear.contact.geometry import HERTZ_HALF_ANGLE_LIMIT, hertz_half_angle

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml"


def test_the_half_angle_is_johnsons_line_contact_half_width_over_the_bore_radius():
    # steel on steel, R_b = 10.05 mm, R_j = 10 mm, L = 10 mm, 100 N: b = sqrt(4 F R* h / (pi L)) by hand
    h = 2 * (1 - 0.3 ** 2) / 207e9
    r_star = 10.05e-3 * 10e-3 / 0.05e-3
    b = math.sqrt(4 * 100.0 * r_star * h / (math.pi * 10e-3))
    assert hertz_half_angle(100.0, 10.05e-3, 10e-3, h, 10e-3) == pytest.approx(b / 10.05e-3, rel=1e-12)
    assert hertz_half_angle(-1.0, 10.05e-3, 10e-3, h, 10e-3) == 0.0  # no contact, no width


@pytest.mark.parametrize("modulus, warned", [(110e9, False), (3e6, True)])
def test_a_soft_bushing_is_warned_and_a_bronze_one_is_not(tmp_path, modulus, warned):
    """The tutorial's bronze bushing (0.55 deg) and the same bushing of a 3 MPa elastomer (80 deg, penetrations
    beyond the clearance: docs/dynamics.md, 'Where the contact law holds')."""
    cfg = updated(load_config(EXAMPLE), {"clearance_joints.B.bearing_material.youngs_modulus": modulus})
    messages = []
    study = jointwear.Study(cfg, out=tmp_path, echo=messages.append)
    sim = study.simulate(cycles=1)
    (joint,) = sim.joints
    cj = cfg.clearance_joints[0]
    expected = hertz_half_angle(joint["normal_force_max_N"], cj.bearing_radius, cj.journal_radius, cj.hsum, cj.width)
    assert joint["contact_half_angle_deg"] == pytest.approx(math.degrees(expected), rel=1e-12)
    assert (joint["contact_half_angle_deg"] > math.degrees(HERTZ_HALF_ANGLE_LIMIT)) is warned
    assert any("Where the contact law holds" in m for m in messages) is warned
    # and names what sets the width, where a unit slip would be (a modulus in MPa for GPa, a width in um for mm)
    assert any("check clearance_joints.B.width and its materials' youngs_modulus" in m for m in messages) is warned
    page = study.report().read_text(encoding="utf-8")
    assert ("Outside the contact law" in page) is warned
