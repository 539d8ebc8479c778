"""The indicator of uniform mode's range (docs/wear.md, "When uniform mode is fair") on the pendulum rig.

conformity = acos(c0 / (c0 + h)) / (b / R_b), with Johnson's half-width b at the mean contact force on the unworn
bore; uniform mode is fair while it stays <= 1, i.e. below the depth h* = c0 (1 / cos(b / R_b) - 1).
"""

from __future__ import annotations

import math
from pathlib import Path

from jointwear.config import load_config, updated
from jointwear.mechanism import build_model
from jointwear.study import Study
from jointwear.wear import wear_history

RIG = Path(__file__).resolve().parent / "rigs" / "pendulum.toml"


def test_rig_half_width_and_conformity_against_johnson():
    cfg = updated(load_config(str(RIG)), {"wear.geometry_mode": "uniform"})
    joint = wear_history(build_model(cfg), cfg.wear, 500).joints[0]
    cj = cfg.clearance_joints[0]
    mat_b, mat_j = cj.bearing_material, cj.journal_material
    # Johnson (Contact Mechanics, Eq. 4.43): b^2 = 4 N R* / (pi L E*), N = W cos(atan mu) (friction circle)
    n = 100.0 * math.cos(math.atan(cj.friction.mu_d))
    r_star = cj.bearing_radius * cj.journal_radius / (cj.bearing_radius - cj.journal_radius)
    inv_e = (1 - mat_b.poissons_ratio**2) / mat_b.youngs_modulus + (1 - mat_j.poissons_ratio**2) / mat_j.youngs_modulus
    b = math.sqrt(4.0 * n * r_star * inv_e / (math.pi * cj.width))
    # 1 %: b goes as the square root of the mean force, which the pendulum's swing (0.4 % of g) and the contact's
    # ringing move by < 1 %
    assert abs(joint.contact_half_width / b - 1.0) < 0.01, (joint.contact_half_width, b)
    c0 = cj.bearing_radius - cj.journal_radius
    h = joint.max_bearing_wear
    assert math.isclose(joint.conformity, math.acos(c0 / (c0 + h)) / (b / cj.bearing_radius), rel_tol=0.01)
    h_star = c0 * (1.0 / math.cos(b / cj.bearing_radius) - 1.0)  # 0.056 um: a few revolutions of wear
    assert h > 10 * h_star and joint.conformity > 1.0 and joint.uniform_mode_valid is False


def test_the_wear_stage_says_when_uniform_mode_is_out_of_range(tmp_path):
    lines: list[str] = []
    cfg = updated(load_config(str(RIG)), {"wear.geometry_mode": "uniform", "wear.cycles": 500})
    Study(cfg, out=tmp_path / "u", echo=lines.append).wear()
    assert any("uniform mode is outside its range" in line and '"profile"' in line for line in lines), lines
    lines.clear()
    Study(updated(cfg, {"wear.geometry_mode": "profile"}), out=tmp_path / "p", echo=lines.append).wear()
    assert lines and not any("outside its range" in line for line in lines), lines
