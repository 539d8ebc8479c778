"""A prismatic joint's point drawn off its guide is measured as a revolute joint's gap is: refused beyond
closure_tolerance x the median link size, warned of above GAP_WARNING of it (a user's ram drawn 10 mm off its guide
was moved there without a word, tilting the lower link by 4.8 deg, where the same gap on a pin joint was refused)."""

from pathlib import Path

import pytest

from jointwear.config import load_config, updated
from jointwear.mechanism.assembly import GAP_WARNING, check_assembly, drawn_link_size, joint_gaps
from jointwear.schema import ConfigError
from jointwear.study.checks import drawing_warnings

PUMP = Path(__file__).resolve().parents[2] / "examples" / "piston_pump.toml"


def _pump_with_guide_at(offset_mm: float):
    # G is the guide's point: moving it across the guide's direction [1, 0] leaves the piston's pin B off it
    return updated(load_config(PUMP), {"mechanism.ground_points_mm": {"O": [0.0, 0.0], "G": [0.0, offset_mm]}})


def test_the_gap_is_the_points_distance_from_the_guide_line():
    config = load_config(PUMP)
    m = config.mechanism
    gaps = {j.name: gap for _, j, gap in joint_gaps(m)}
    assert gaps["P"] == 0.0  # drawn on its guide
    # along the guide the point may lie anywhere: G moved along [1, 0] leaves no gap
    along = updated(config, {"mechanism.ground_points_mm": {"O": [0.0, 0.0], "G": [40.0, 0.0]}}).mechanism
    assert {j.name: gap for _, j, gap in joint_gaps(along)}["P"] == pytest.approx(0.0, abs=1e-15)


def test_a_small_gap_is_warned_of_and_a_large_one_refused():
    m = load_config(PUMP).mechanism
    size = drawn_link_size([b.points.values() for b in m.bodies])
    small = 20 * GAP_WARNING * size * 1e3  # mm: above the warning, below closure_tolerance
    assert small < m.closure_tolerance * size * 1e3
    (warning,) = [w for w in drawing_warnings(_pump_with_guide_at(small)) if "prismatic joint 'P'" in w]
    assert f"lies {small:.4g} mm off its guide" in warning and "draw the point on the guide" in warning
    with pytest.raises(ConfigError, match="prismatic joint 'P' lies 30 mm off its guide"):
        check_assembly(_pump_with_guide_at(30.0))  # the assembly check that follows the schema
