"""`jointwear converge`: the nominal history with each numerical wear setting refined, judged with its replicates'
scatter. A steady load (the pendulum rig in profile mode, whose depth the closed form pins, docs/verification.md)
must come out converged; a history of two blocks under a growing clearance must not."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from jointwear.cli import main_entry
from jointwear.config import load_config, updated
from jointwear.schema import ConfigError
from jointwear.study.convergence import (
    STORE_FILE,
    STORE_TAG,
    Z95,
    WearConvergence,
    change_verdict,
    chosen_refinements,
    refinements,
    replicates_to_resolve,
    run_convergence,
)

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

RIG = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"


@pytest.fixture(scope="module")
def rig():
    return load_config(str(RIG))


@pytest.mark.parametrize("change, se, verdict", [
    (0.005, 0.005, "converged"),        # 95 %: -0.5 % .. +1.5 %, inside +-2 %
    (-0.05, 0.01, "not converged"),     # -7 % .. -3 %
    (0.0, 0.02, "no change detected"),  # -3.9 % .. +3.9 %: holds 0, reaches past 2 %
    (0.03, 0.01, "undecided"),          # +1 % .. +5 %: a change, straddling 2 %
    (0.0, 0.0, "converged"),            # a deterministic history that did not move
])
def test_verdict_from_the_95_interval(change, se, verdict):
    assert change_verdict(change, se, 0.02) == verdict


def test_replicates_that_resolve_the_tolerance():
    # the least n with t_0.975(2n - 2) s sqrt(2 / n) <= tol: at that n the interval of a change between two such
    # settings is +-tol; the normal quantile's 2 (1.96 s / tol)^2 = 49 falls short (t_0.975(96) = 1.985)
    from scipy import stats

    n = replicates_to_resolve(0.05, 0.02)
    half = [stats.t.ppf(0.975, 2 * m - 2) * 0.05 * math.sqrt(2 / m) for m in (n, n - 1)]
    assert half[0] <= 0.02 < half[1]
    assert n == 50 > math.ceil(2 * (Z95 * 0.05 / 0.02) ** 2)
    assert replicates_to_resolve(0.0, 0.02) == 2


def test_a_change_from_few_replicates_takes_students_quantile():
    # two replicates each with equal scatter: Welch's degrees of freedom are 2, the 95 % half-width t_0.975(2) =
    # 4.303 standard errors (1.96 would cover about 81 % of such intervals, not 95 %)
    from jointwear.study.convergence import welch_dof

    assert welch_dof(1.0, 2, 1.0, 2) == pytest.approx(2.0)
    assert welch_dof(1.0, 8, 0.0, 8) == pytest.approx(7.0)  # only one side scatters: its n - 1
    assert welch_dof(0.0, 2, 0.0, 2) == math.inf
    base = {"values": [99.0, 101.0], "mean": 100.0, "std": math.sqrt(2.0)}
    conv = run_convergence(load_config(str(RIG)), 500, replicates=2, only=["n_grid"],
                           evaluator_factory=lambda _call: lambda X: np.where(X[:, :1] < 0, 100 + (2 * X[:, 2:3] - 1),
                                                                              102 + (2 * X[:, 2:3] - 1)))
    row = conv.refinements[0]
    assert conv.baseline["mean"] == base["mean"] and row["change"] == pytest.approx(0.02)
    assert row["change_95"] == pytest.approx(4.302653 * row["change_se"], rel=1e-6)
    assert row["verdict"] == "no change detected"  # +2 % +- 5.4 %: with 1.96 SE (+-2.5 %) it read 'undecided'


def test_each_setting_is_refined_by_the_factor(rig):
    s = rig.wear
    by = {r.name: r.update for r in refinements(rig, 2.0)}
    assert set(by) == {"record_cycles", "settle_cycles", "block", "n_grid", "tolerance"}  # uniform mode
    assert by["record_cycles"] == {"record_cycles": 2 * s.record_cycles}
    assert by["settle_cycles"] == {"settle_cycles": 2 * s.settle_cycles}
    assert by["block"] == {"block_cycles": s.block_cycles // 2}
    assert by["n_grid"] == {"n_grid": 2 * s.n_grid}
    rtol = s.rtol if s.rtol is not None else rig.simulation.rtol
    assert by["tolerance"]["rtol"] == pytest.approx(rtol / 2)
    profile = {r.name: r.update for r in refinements(updated(rig, {"wear.geometry_mode": "profile"}), 4.0)}
    assert profile["profile_smoothing_deg"] == {"profile_smoothing_deg": s.profile_smoothing_deg / 4}
    assert profile["profile_substep_cycles"] == {"profile_substep_cycles": s.profile_substep_cycles / 4}
    # one recorded cycle refined 1.5x still records one more; no settling refined becomes one cycle
    low = {r.name: r.update for r in refinements(updated(rig, {"wear.record_cycles": 1, "wear.settle_cycles": 0}),
                                                 1.5)}
    assert low["record_cycles"] == {"record_cycles": 2} and low["settle_cycles"] == {"settle_cycles": 1.0}
    adaptive = {r.name: r.update for r in refinements(updated(rig, {"wear.block_rule": "adaptive"}), 2.0)}
    assert adaptive["block"]["rate_tolerance"] == pytest.approx(rig.wear.rate_tolerance / 2)


@pytest.mark.parametrize("kwargs, needle", [
    ({"replicates": 1}, "replicates"), ({"replicates": 2.5}, "replicates"), ({"factor": 1.0}, "factor"),
    ({"tolerance": 0.0}, "tolerance"), ({"only": ["profile_smoothing_deg"]}, "only"),  # uniform mode: no such
])
def test_bad_requests_name_the_argument(rig, kwargs, needle):
    args = {"replicates": 2, "factor": 2.0, "tolerance": 0.02, "only": None, **kwargs}
    with pytest.raises(ConfigError, match=f"^{needle}:"):
        chosen_refinements(rig, **args)


def test_a_steady_conformal_load_is_converged(rig):
    # the rig in profile mode, 2,000 revolutions in blocks of 250: every refinement halved moves the closed-form
    # matched depth by < 0.1 % at 1e4 revolutions (docs/wear.md); the start phase changes nothing on a steady load
    res = run_convergence(updated(rig, {"wear.geometry_mode": "profile"}), 2000, replicates=2,
                          only=["record_cycles", "block", "n_grid"])
    assert res.measure == "life" and res.scatter < 1e-3
    assert res.verdicts() == {"record_cycles": "converged", "block": "converged", "n_grid": "converged"}
    # the life lies past the 2,000 revolutions (the rig's 0.05 mm allowance takes ~1e5): said, as an extrapolation
    (extrapolated,) = res.sentences()
    assert extrapolated.startswith("the nominal life ") and "beyond the histories' end (2,000 cycles)" in extrapolated
    assert res.converged


@pytest.fixture(scope="module")
def two_blocks(rig):
    # uniform mode grows the rig's clearance 48x over 1e5 revolutions (docs/wear.md). One block of 10,000 revolutions
    # never updates the geometry; two nearly triple the life (+170 to +200 %, 95 % half-width 0.3-0.75 on numpy 1.26 /
    # numba 0.59 and on the newest). Finer blocks change it by ~30 % only, inside the chaotic replicates' scatter.
    return run_convergence(updated(rig, {"wear.block_cycles": 10_000}), 10_000, replicates=3, only=["block"])


def test_two_blocks_of_a_growing_clearance_are_not_converged(two_blocks):
    row = two_blocks.refinements[0]
    assert row["verdict"] == "not converged", row
    assert row["changed"] == {"block_cycles": [10_000, 5000]}
    sentence, extrapolated = two_blocks.sentences()
    assert "beyond the histories' end (10,000 cycles)" in extrapolated
    assert "not converged within 2 %" in sentence and "wear.block_cycles 10,000 -> 5,000" in sentence
    assert WearConvergence.from_json(json.loads(json.dumps(two_blocks.to_json()))) == two_blocks


def test_the_report_shows_the_check_and_its_warning(two_blocks, tmp_path):
    from jointwear import load_results
    from jointwear.report.html import build_report

    two_blocks.save(tmp_path)
    assert load_results(tmp_path).wear_convergence == two_blocks
    page = build_report(tmp_path).read_text(encoding="utf-8")
    assert 'id="wear-convergence"' in page and "not converged within 2 %" in page
    assert "The wear history is not converged" in page  # a caveat beside the summary's numbers
    assert "block_cycles 10,000 \u2192 5,000" in page


def test_the_command_writes_its_result(rig, tmp_path, capsys):
    toml = tmp_path / "rig.toml"
    toml.write_text(f'extends = "{RIG.as_posix()}"\n\n[wear]\ngeometry_mode = "profile"\ncycles = 1000\n',
                    encoding="utf-8")
    out = tmp_path / "out"
    status = main_entry(["converge", str(toml), "--replicates", "2", "--only", "n_grid", "--out", str(out)])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    text = captured.out + captured.err
    assert "n_grid" in text and "converged" in text
    res = WearConvergence.load(out)
    assert [r["name"] for r in res.refinements] == ["n_grid"] and res.cycles == 1000
    assert (out / "wear_convergence.csv").read_text(encoding="utf-8").splitlines()[0].startswith("setting,changed,")


def test_histories_run_on_workers_and_resume_from_the_store(rig, tmp_path):
    """The Study runs the histories on worker processes, the same to the last bit as one after the other in this
    process, and keeps them in the study's evaluation store: a second check reads them back."""
    import sqlite3

    from jointwear import Study

    profile = updated(rig, {"wear.geometry_mode": "profile", "wear.cycles": 1000})
    serial = run_convergence(profile, 1000, replicates=2, only=["n_grid"])
    study = Study(profile, out=tmp_path, workers=2)
    first = study.converge(replicates=2, only=["n_grid"])
    assert first.baseline["values"] == serial.baseline["values"]
    assert first.refinements[0]["values"] == serial.refinements[0]["values"]

    def stored() -> int:
        with sqlite3.connect(tmp_path / STORE_FILE) as db:
            return db.execute("SELECT COUNT(*) FROM calls WHERE tag = ?", (STORE_TAG,)).fetchone()[0]

    assert stored() == 4
    assert not (tmp_path / "evaluations.sqlite").exists()  # the study's own store is left alone
    again = Study(profile, out=tmp_path, workers=2).converge(replicates=2, only=["n_grid"])
    assert stored() == 4 and again.baseline == first.baseline and again.refinements == first.refinements
    # another factor runs only the refinement again: the baseline is read back
    Study(profile, out=tmp_path, workers=2).converge(replicates=2, only=["n_grid"], factor=4.0)
    assert stored() == 6
    # another history length is another row, not the stored one
    longer = Study(profile, out=tmp_path, workers=2).converge(replicates=2, only=["n_grid"], cycles=1500)
    assert stored() == 10 and longer.cycles == 1500 and longer.baseline["values"] != first.baseline["values"]
    # another wear model is refused with what to do; --overwrite starts afresh
    other = updated(profile, {"wear.n_grid": 360})
    with pytest.raises(ConfigError, match="overwrite"):
        Study(other, out=tmp_path, workers=2).converge(replicates=2, only=["n_grid"])
    Study(other, out=tmp_path, workers=2, overwrite=True).converge(replicates=2, only=["n_grid"])
    assert stored() == 4


def test_without_an_allowance_the_measure_is_the_final_wear(rig):
    # no allowance anywhere (no [reliability] allowance, no bushing wall for the 0.01 D rule): the first judged
    # joint's max bearing depth at the history's end, as the history itself reports it
    from jointwear.mechanism import build_model
    from jointwear.study.convergence import nominal_measure
    from jointwear.wear import wear_history

    bare = updated(rig, {"clearance_joints.0.bearing_outer_radius": None})
    measure, value_of, _ = nominal_measure(bare)
    assert measure == "wear"
    res = wear_history(build_model(bare), bare.wear, 500)
    assert value_of(res) == pytest.approx(res.joints[0].bearing_wear.max(), rel=1e-12)
    conv = run_convergence(bare, 500, replicates=2, only=["n_grid"])
    assert conv.measure == "wear" and conv.unit == "m"
    assert "mean_wear_mm" in conv.tables()["wear_convergence"]


def test_each_judged_joint_is_judged_on_its_own():
    """A setting that moves only the joint that does not govern the nominal life (E, twice A's life) leaves the
    nominal life where it was, but E's own R(N), and so the system's, moves: the setting is not converged."""
    from jointwear.study.convergence import REFINEMENT_NAMES

    six_bar = load_config("watt_six_bar_two_clearances")
    block = REFINEMENT_NAMES.index("block")

    def fake(_call):
        def evaluate(X):
            k = X[:, 2]
            life_a = 1e5 * (1 + 1e-3 * k)
            life_e = 2e5 * (1 + 1e-3 * k) * np.where(X[:, 0] == block, 1.10, 1.0)  # +10 % with the block halved
            return np.column_stack([np.minimum(life_a, life_e), life_a, life_e])
        return evaluate

    res = run_convergence(six_bar, 2000, replicates=3, only=["n_grid", "block"], evaluator_factory=fake)
    assert res.joints == ["A", "E"] and set(res.baseline["joints"]) == {"A", "E"}
    rows = {r["name"]: r for r in res.refinements}
    assert rows["n_grid"]["verdict"] == "converged"
    assert rows["block"]["system_verdict"] == "converged"  # A governs and did not move
    assert rows["block"]["joints"]["E"]["change"] == pytest.approx(0.10)
    assert rows["block"]["joints"]["E"]["verdict"] == "not converged"
    assert rows["block"]["verdict"] == "not converged" and res.not_converged() == ["block"]
    sentence, extrapolated = res.sentences()
    assert "joint E's own nominal life moves by +10.0 %" in sentence
    # the lives (1e5 and 2e5 x (1 + 1e-3 k), k = 0, 1, 2: means 100,100 and 200,200) lie past the 2,000 cycles: A
    # governs, so its own is not repeated
    assert extrapolated.startswith("the nominal life 100,100, joint E's own nominal life 200,200 cycles lie beyond")
    table = res.tables()["wear_convergence"]
    by_setting = dict(zip(table["setting"], zip(table["E_verdict"], table["E_change_pct"])))
    assert by_setting["baseline"] == ("", 0.0) and by_setting["n_grid"][0] == "converged"
    assert by_setting["block"][0] == "not converged" and by_setting["block"][1] == pytest.approx(10.0)
    assert WearConvergence.from_json(json.loads(json.dumps(res.to_json()))) == res


def test_a_two_joint_history_gives_the_system_and_each_joint():
    # the values are the nominal life (the first joint to reach its allowance) and each joint's own, as the
    # reliability stage's limit state reads them from the same history
    from jointwear.mechanism import build_model
    from jointwear.study.convergence import ConvergenceCall, nominal_measure
    from jointwear.study.limit_state import life_from_history
    from jointwear.study.model_call import quantity_history
    from jointwear.wear import wear_history

    six_bar = updated(load_config("watt_six_bar_two_clearances"), {"wear.block_cycles": 500})
    measure, value_of, limit = nominal_measure(six_bar)
    res = wear_history(build_model(six_bar), six_bar.wear, 2000)
    values = value_of(res)
    cycles = res.joints[0].history_cycles
    cycles = cycles[cycles > 0]
    lives = [float(life_from_history(cycles, quantity_history(res.joints[j], limit.quantity, cycles)[None, :], a)[0])
             for j, a in zip(limit.joints, limit.allowances)]
    assert measure == "life" and len(values) == 3
    assert values[1:] == pytest.approx(lives, rel=1e-12) and values[0] == min(lives)
    # a store of the system's measure alone is another store
    assert "outputs" in ConvergenceCall(six_bar.model_dump()).identity()
    assert "outputs" not in ConvergenceCall(load_config(str(RIG)).model_dump()).identity()
