"""A target given as a factor of today's life (``life_factor``) carries the study's error of that life: the design
stage records the study's 95 % interval of it and tells the range N* inherits (a user's design lead read N* = 1.2 x
the study's life as exact, where that life was 3 % short of the true model's)."""

import copy
import json

import pytest
from design_fixtures import DESIGN, analytic_config, analytic_context

from jointwear.design import run_design
from jointwear.study import run_reliability

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

FACTOR = 1.05


@pytest.fixture(scope="module")
def relative():
    spec = copy.deepcopy(DESIGN)
    spec["targets"] = [{"reliability": 0.9, "life_factor": FACTOR}]
    cfg = analytic_config(spec)
    ctx, _ = analytic_context(cfg)
    rel = run_reliability(ctx)
    return rel, run_design(ctx, rel)


def test_the_target_records_the_studys_life_interval_and_tells_the_range_it_inherits(relative, tmp_path):
    rel, design = relative
    low, high = rel.life_interval(0.9)
    assert low is not None and high is not None  # the analytic curve holds the life at 0.9
    assert design.baseline_life_cycles == pytest.approx(rel.life(0.9))  # exact: the same reading of the same curve
    assert design.target_life_cycles == pytest.approx(FACTOR * design.baseline_life_cycles)
    assert design.baseline_life_interval == pytest.approx([low, high])
    sentence = design.relative_target_sentence()
    assert f"N* is {FACTOR * low:,.0f}-{FACTOR * high:,.0f} cycles" in sentence and "jointwear validate" in sentence
    design.save(tmp_path, figures=False)
    data = json.loads((tmp_path / "design.json").read_text())
    assert data["baseline_life_interval"] == pytest.approx([low, high])
    assert data["targets"][0]["baseline_life_interval"] == pytest.approx([low, high])
    from result_keys import undocumented_keys

    assert undocumented_keys(tmp_path / "design.json") == []  # docs/results.md lists the new key


def test_a_target_in_cycles_says_nothing_of_it(relative):
    rel, design = relative
    absolute = copy.deepcopy(design)
    absolute.life_factor = None
    assert absolute.relative_target_sentence() == ""
