"""Random-variable targets: dotted paths into the config, including the points of a general mechanism."""

import math

import numpy as np
import pytest

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism import build_model
from jointwear.schema import ConfigError
from jointwear.study import apply_sample
from jointwear.uncertainty.targets import point_shift, target_error


def _point_distance(model, body, p, q):
    b = model.body(body)
    return math.dist(b.points[p], b.points[q])


def test_point_coordinates_of_a_general_mechanism_are_targets():
    base = load_config("watt_six_bar_two_clearances")
    data = base.model_dump()
    for path in ("mechanism.bodies.coupler.points.B.y", "mechanism.bodies.1.points.B.1",
                 "mechanism.ground_points.C.x"):
        assert target_error(data, path) is None, path
    m0 = build_model(base)
    ab0 = _point_distance(m0, "coupler", "A", "B")  # 35 mm in the drawing
    # the coupler's B 0.2 mm higher: the coupler is 0.2 mm longer, the rocker unchanged, the linkage re-assembles
    cfg = apply_sample(base, ["mechanism.bodies.coupler.points.B.y"], [0.0352])
    m1 = build_model(cfg)
    assert _point_distance(m1, "coupler", "A", "B") == pytest.approx(ab0 + 0.0002, rel=1e-12)
    assert _point_distance(m1, "rocker", "C", "B") == pytest.approx(_point_distance(m0, "rocker", "C", "B"), rel=1e-12)
    # index and name address the same field; a ground pivot moves the rocker's fixed point
    same = apply_sample(base, ["mechanism.bodies.1.points.B.1"], [0.0352]).model_dump()
    assert same["mechanism"]["bodies"][1]["points"]["B"] == cfg.model_dump()["mechanism"]["bodies"][1]["points"]["B"]
    g = apply_sample(base, ["mechanism.ground_points.C.x"], [0.0301])
    assert g.model_dump()["mechanism"]["ground_points"]["C"] == pytest.approx((0.0301, 0.02))
    assert base.model_dump()["mechanism"]["ground_points"]["C"] == pytest.approx((0.03, 0.02))  # base untouched


def test_bad_point_targets_are_named():
    data = load_config("watt_six_bar_two_clearances").model_dump()
    assert "not a field" in target_error(data, "mechanism.bodies.nobody.points.B.x")
    assert "not a field" in target_error(data, "mechanism.bodies.coupler.points.Z.x")
    assert "not a field" in target_error(data, "mechanism.bodies.coupler.points.B.z")
    assert "not a numeric field" in target_error(data, "mechanism.bodies.coupler.points.B")


def test_a_target_typo_is_told_where_it_leaves_the_config_with_the_likely_fix():
    """A target typo was told only "'...hardnes' is not a field of the config", where a key typo gets 'did you mean'."""
    data = load_config("watt_six_bar_two_clearances").model_dump()
    assert target_error(data, "clearance_joints.A.bearing_material.hardnes") == (
        "'clearance_joints.A.bearing_material.hardnes' is not a field of the config: 'hardnes' is not in "
        "clearance_joints.A.bearing_material (did you mean 'hardness'?)")
    assert target_error(data, "mechanism.bodys.coupler.points.B.x").endswith(
        ": 'bodys' is not in mechanism (did you mean 'bodies'?)")
    named = [b["name"] for b in data["mechanism"]["bodies"]]
    assert target_error(data, "mechanism.bodies.nobody.points.B.x").endswith(
        f": 'nobody' is not in mechanism.bodies (it has: {', '.join(named)})")
    assert target_error(data, "mechanism.bodies.coupler.points.B.z").endswith(
        ": 'z' is not in mechanism.bodies.coupler.points.B (it has: x, y, 0, 1)")
    assert target_error(data, "clearance_joints.A.width.x").endswith(
        ": clearance_joints.A.width is a number, with no 'x' in it")


def test_a_study_config_with_a_point_variable_validates_and_samples():
    data = load_config("watt_six_bar_two_clearances").model_dump()
    data["uncertainty"] = {"variables": [{"name": "yB", "target": "mechanism.bodies.coupler.points.B.y",
                                          "distribution": "normal", "mean": 0.035, "std": 1e-5}]}
    cfg = config_from_dict(data, source="test")
    specs = cfg.uncertainty.all_specs()
    assert [s.target for s in specs][-1] == "mechanism.bodies.coupler.points.B.y"
    x = np.array([0.03501])
    m = build_model(apply_sample(cfg, [s.target for s in specs], np.concatenate([[s.frozen().mean() for s in
                                                                                   specs[:-1]], x])))
    assert _point_distance(m, "coupler", "A", "B") == pytest.approx(0.03501, rel=1e-9)
    data["uncertainty"]["variables"][0]["target"] = "mechanism.bodies.coupler.points.Q.y"
    with pytest.raises(ConfigError, match="points.Q.y"):
        config_from_dict(data, source="test")


def test_a_moved_point_is_reassembled_not_refused_as_a_drawing_gap():
    # The sensitivity moves the tutorial's crank pin by 20 % (2 mm): more than the drawing's closure tolerance
    # (5 % of the 25 mm median link), so the shifted drawing used to be refused. The move is the sample's, not a
    # drawing error: the assembly closes the loop with the other links as drawn, or says why it cannot.
    from pathlib import Path

    cfg = load_config(str(Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml"))
    m0 = build_model(cfg)
    for length in (0.008, 0.012):
        m = build_model(apply_sample(cfg, ["mechanism.bodies.crank.points.A.x"], [length]))
        assert _point_distance(m, "crank", "O", "A") == pytest.approx(length, rel=1e-12)
        assert _point_distance(m, "coupler", "A", "B") == pytest.approx(_point_distance(m0, "coupler", "A", "B"),
                                                                        rel=1e-12)
    with pytest.raises(ConfigError, match="does not close"):  # a 30 mm crank cannot drive this four-bar
        build_model(apply_sample(cfg, ["mechanism.bodies.crank.points.A.x"], [0.03]))
    # only drawn points count as moves (gravity is a pair of numbers too)
    data = cfg.model_dump()
    assert point_shift(data, "mechanism.ground_points.O.x", 0.001) == pytest.approx(0.001)
    assert point_shift(data, "mechanism.gravity.1", -9.0) == 0.0
    # a sample that moves no point keeps the drawing's own tolerance: a gap drawn by the user is still refused
    data["mechanism"]["bodies"][1]["points"]["A"] = (0.0120, 0.0)  # coupler.A 2 mm from crank.A
    with pytest.raises(ConfigError, match="draw them at the same place"):
        build_model(apply_sample(data, ["clearance_joints.B.clearance"], [20e-6]))


def test_a_sample_of_the_wrong_length_is_refused():
    base = load_config("watt_six_bar_two_clearances")
    with pytest.raises(ConfigError, match="2 values for 1 targets"):
        apply_sample(base, ["mechanism.ground_points.C.x"], [0.0301, 0.02])
