"""A general linkage that passes near a dead point is warned of by `check` (audit 61-K, D1): the assembly sweep
records the smallest ratio sv_min / sv_max of the scaled constraint Jacobian, where it occurs and the links, and
``transmission_warnings`` compares it with ``DEAD_POINT_RATIO_WARNING`` (calibrated on four-bars against the
transmission angle)."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import pytest

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism.assembly import general_parts
from jointwear.study.checks import DEAD_POINT_RATIO_WARNING, transmission_warnings

ROOT = Path(__file__).resolve().parents[2]


def general_four_bar(crank: float, rod: float, rocker: float, ground: float):
    """examples/my_linkage.toml with its links resized (mm), the drawn points by loop closure at crank angle 0:
    O at the origin, the rocker's pivot C at (ground, 0), B above the line A-C."""
    with open(ROOT / "examples" / "my_linkage.toml", "rb") as fh:
        data = tomllib.load(fh)
    for key in ("uncertainty", "reliability", "sensitivity"):
        data.pop(key, None)
    data = copy.deepcopy(data)
    ax, cx = crank, ground
    dd = cx - ax
    a = (rod * rod - rocker * rocker + dd * dd) / (2.0 * dd)
    bx, by = ax + a, math.sqrt(rod * rod - a * a)
    m = data["mechanism"]
    m["ground_points_mm"] = {"O": [0.0, 0.0], "C": [cx, 0.0]}
    bodies = {b["name"]: b for b in m["bodies"]}
    bodies["crank"].update(points_mm={"O": [0.0, 0.0], "A": [ax, 0.0]}, com_mm=[ax / 2, 0.0])
    bodies["coupler"].update(points_mm={"A": [ax, 0.0], "B": [bx, by]}, com_mm=[(ax + bx) / 2, by / 2])
    bodies["rocker"].update(points_mm={"C": [cx, 0.0], "B": [bx, by]}, com_mm=[(cx + bx) / 2, by / 2])
    return config_from_dict(data)


def ground_for_max_angle(crank: float, rod: float, rocker: float, mu_max_deg: float) -> float:
    """The ground length that makes the largest transmission angle (crank pointing away from C, at 180 deg)
    mu_max: law of cosines on the distance A-C = ground + crank."""
    ac = math.sqrt(rod * rod + rocker * rocker - 2.0 * rod * rocker * math.cos(math.radians(mu_max_deg)))
    return ac - crank


def test_a_general_four_bar_near_a_dead_point_is_warned_naming_the_driver_angle_and_the_links():
    # crank 10, rod 40, rocker 25 mm; the transmission angle reaches 175 deg (5 deg from the dead point) at 180 deg
    cfg = general_four_bar(10.0, 40.0, 25.0, ground_for_max_angle(10.0, 40.0, 25.0, 175.0))
    margin = general_parts(cfg.mechanism).dead_point
    assert margin.driver_angle_deg == pytest.approx(180.0, abs=1.0)
    assert set(margin.links) == {"coupler", "rocker"}
    # the calibration: the ratio is about 0.23 sin of the distance from the dead point
    assert margin.ratio == pytest.approx(0.23 * math.sin(math.radians(5.0)), rel=0.1)
    warnings = transmission_warnings(cfg)
    assert len(warnings) == 1
    text = warnings[0]
    assert text.startswith("mechanism: the linkage passes near a dead point at links coupler, rocker")
    assert "joint 'O') is at 180 deg" in text
    assert "grow without bound" in text and "wear climb" in text


def test_the_same_general_four_bar_at_a_healthy_transmission_angle_is_not_warned():
    # the same links with a ground length that keeps the transmission angle within 40-140 deg
    cfg = general_four_bar(10.0, 40.0, 25.0, ground_for_max_angle(10.0, 40.0, 25.0, 140.0))
    margin = general_parts(cfg.mechanism).dead_point
    assert margin.ratio == pytest.approx(0.23 * math.sin(math.radians(40.0)), rel=0.1)
    assert margin.ratio > DEAD_POINT_RATIO_WARNING
    assert transmission_warnings(cfg) == []


@pytest.mark.parametrize("mu_worst, warned", [(10.0, True), (30.0, False)])
def test_the_threshold_warns_a_10_deg_four_bar_and_not_a_30_deg_one_even_with_a_long_rod(mu_worst, warned):
    # the proportion of the calibration with the smallest ratio per sin(mu): rod 15 cranks, rocker 4 cranks
    cfg = general_four_bar(10.0, 150.0, 40.0, ground_for_max_angle(10.0, 150.0, 40.0, 180.0 - mu_worst))
    assert bool(transmission_warnings(cfg)) is warned


@pytest.mark.parametrize("source", ["watt_six_bar_two_clearances", str(ROOT / "examples" / "my_linkage.toml"),
                                    str(ROOT / "examples" / "piston_pump.toml")])
def test_the_general_presets_and_examples_are_not_warned(source):
    cfg = load_config(source)
    margin = general_parts(cfg.mechanism).dead_point
    assert margin is not None and margin.ratio > DEAD_POINT_RATIO_WARNING
    assert transmission_warnings(cfg) == []


def test_a_slider_crank_drawn_as_a_general_linkage_is_not_misread_by_its_prismatic_joint():
    # piston_pump: crank 15, rod 60 mm, no offset, so its transmission angle stays above 75.5 deg; the prismatic
    # joint's angle row is scaled to lengths, else it alone would set the ratio (0.02)
    margin = general_parts(load_config(str(ROOT / "examples" / "piston_pump.toml")).mechanism).dead_point
    assert margin.ratio > 0.25
    assert set(margin.links) == {"rod", "piston"}


def test_a_linkage_with_free_degrees_of_freedom_is_out_of_scope():
    cfg = load_config(str(ROOT / "tests" / "wear" / "rigs" / "pendulum.toml"))
    assert cfg.mechanism.free_degrees_of_freedom() > 0
    assert transmission_warnings(cfg) == []
