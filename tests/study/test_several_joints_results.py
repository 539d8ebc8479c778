"""A mechanism with several clearance joints gets every joint's own result and message: its allowance, its nominal
life kept in wear.json, and its conformity named in profile mode (a designer's toggle press with joints K and C,
allowances 0.05 and 0.02 mm, read one allowance and one conformity without a joint's name, and the nominal lives the
wear stage printed were stored nowhere)."""

import json
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "wear"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from result_keys import undocumented_keys  # noqa: E402
from wear_synthetic import FakeModel, fake_simulate  # noqa: E402

from jointwear.config import load_config, updated  # noqa: E402
from jointwear.study import WearSummary, load_results  # noqa: E402
from jointwear.study.limit_state import nominal_lives  # noqa: E402
from jointwear.study.stage_lines import profile_mode_line  # noqa: E402
from jointwear.wear import WearSettings, wear_history  # noqa: E402

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def test_profile_mode_names_each_joints_conformity():
    """The verdict is every joint's: the first joint within 1 and the second past it is profile mode's case."""
    def line(**conformity):
        joints = [{"name": name, "conformity": c} for name, c in conformity.items()]
        return profile_mode_line(SimpleNamespace(geometry_mode="profile", joints=joints,
                                                 conformity=joints[0]["conformity"]))

    assert line(K=7.36, C=6.21) == (
        "profile mode follows the worn shape here (conformity 7.36 at joint K, 6.21 at joint C > 1: the journal fits "
        "into its own wear, which uniform mode ignores): this is the answer to trust")
    # only the joints past 1 are named, as uniform mode's warning names them
    assert line(K=0.6, C=7.36).startswith("profile mode follows the worn shape here (conformity 7.36 at joint C > 1")
    assert line(K=0.6, C=0.4).startswith(
        "uniform mode would be fair here too (conformity 0.6 at joint K, 0.4 at joint C <= 1")
    assert line(K=float("nan"), C=0.4).startswith("uniform mode would be fair here too (conformity 0.4 at joint C <=")
    assert line(K=float("nan"), C=float("nan")) == ""


def test_wear_json_keeps_each_joints_allowance_and_nominal_life(tmp_path):
    res = wear_history(FakeModel(n_joints=2), WearSettings(n_grid=360), 40_000, simulate=fake_simulate)
    probe = WearSummary.from_history(res)
    # joint0's allowance is reached within the history, joint1's (twice its final depth) is not
    reached = 0.5 * probe.joints[0]["max_wear_mm"]
    beyond = 2.0 * probe.joints[1]["max_wear_mm"]
    s = WearSummary.from_history(res, allowances_m={"joint0": reached * 1e-3, "joint1": beyond * 1e-3})
    s.save(tmp_path, figures=False)
    d = json.loads((tmp_path / "wear.json").read_text())
    assert [j["allowance_mm"] for j in d["joints"]] == pytest.approx([reached, beyond])
    assert d["limit_mm"] == pytest.approx(reached)  # the first joint's, as documented
    # the life the wear stage prints (nominal_lives reads it), the same arithmetic: equal
    printed = nominal_lives(d["joints"], {"joint0": reached}, "bearing_max_depth")["joint0"]
    assert 0 < d["joints"][0]["nominal_life_cycles"] == printed < d["cycles"]
    assert d["joints"][1]["nominal_life_cycles"] is None  # not extrapolated past the history
    assert d["quantity"] == "bearing_max_depth"
    assert undocumented_keys(tmp_path / "wear.json") == []
    back = load_results(tmp_path).wear
    assert [j["nominal_life_cycles"] for j in back.joints] == [printed, None]
    # a joint without an allowance has no nominal life
    assert [j["nominal_life_cycles"] for j in probe.joints] == [None, None]


def test_the_nominal_life_is_read_in_the_limit_states_quantity():
    """Under 'journal_max_depth' the journal's history reaches the allowance, not the bearing's."""
    config = updated(load_config(), {"reliability.quantity": "journal_max_depth"})
    res = wear_history(FakeModel(), WearSettings(n_grid=360), 40_000, simulate=fake_simulate)
    name = config.clearance_joints[0].name
    journal = WearSummary.from_history(res).joints[0]["history"]["max_journal_wear_mm"][-1]
    s = WearSummary.from_history(res, config, {name: 0.5 * journal * 1e-3})
    row = s.joints[0]
    assert s.quantity == "journal_max_depth"
    assert row["nominal_life_cycles"] == nominal_lives(s.joints, {name: 0.5 * journal}, "journal_max_depth")[name]
    assert row["nominal_life_cycles"] != nominal_lives(s.joints, {name: 0.5 * journal}, "bearing_max_depth")[name]


def test_the_wear_stages_own_figures_name_their_joint(tmp_path, monkeypatch):
    """wear_history_<J>.png and wear_vs_angle_<J>.png of a mechanism with several joints: each figure's title names
    its joint (the designer's two files read alike); a single joint's figures stay unnamed."""
    from jointwear.report import figures as F

    seen: dict[str, list] = {"history": [], "panels": []}
    monkeypatch.setattr(F, "wear_history_figure", lambda *a, joint=None, **k: seen["history"].append(joint))
    monkeypatch.setattr(F, "wear_panels_figure", lambda *a, joint=None, **k: seen["panels"].append(joint))
    monkeypatch.setattr("jointwear.study.results.save_figure", lambda fig, path: None)
    monkeypatch.setattr(WearSummary, "plot", lambda self, name=None: None)
    two = WearSummary.from_history(wear_history(FakeModel(n_joints=2), WearSettings(n_grid=360), 20_000,
                                                simulate=fake_simulate))
    two.save(tmp_path / "two")
    assert seen["history"] == ["joint0", "joint1"]
    assert seen["panels"] == ["joint0", "joint1"]
    seen["history"].clear()
    one = WearSummary.from_history(wear_history(FakeModel(n_joints=1), WearSettings(n_grid=360), 20_000,
                                                simulate=fake_simulate))
    one.save(tmp_path / "one")
    assert seen["history"] == [None]
