"""Stages run again in a folder that holds results: what is kept, what is moved aside, and how the lines count calls.

One small study of the slider-crank benchmark (20 learning calls, 4 validation samples, a design with 15
verification calls) is run once into a base folder, its design first on the fresh folder; each test works on a copy.
"""

from __future__ import annotations

import shutil

import pytest

import jointwear
from jointwear.config import load_config, updated
from jointwear.design.results import DesignResult
from jointwear.schema import ConfigError

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

SMALL = {
    "extends": "flores_slider_crank",
    "reliability": {"max_calls": 20, "n_mc": 50_000},
    "sensitivity": {"sobol_base_samples": 256},
    "design": {"refine_max_calls": 5, "verification_max_calls": 15,
               "targets": [{"reliability": 0.9, "life_factor": 1.1}],
               "tolerances": [{"variable": "l2", "grades": ["IT9", "IT10", "IT11"]}],
               "properties": [{"variable": "k_b", "classes": [{"name": "standard", "cost": 0.0},
                                                             {"name": "coated", "mean": 0.8e-4, "std": 0.8e-5,
                                                              "cost": 2.0}]}]},
}
# the files each stage writes here, but for the moved stages': what a folder keeps when those are moved aside
SIMULATE_FILES = {"simulate.json", "simulate.npz", "simulate_joints.csv", "orbit_B.png", "force_B.png"}
WEAR_FILES = {"wear.json", "wear_history.csv", "wear_journal_profile.csv", "wear_profile.csv", "wear_polar.png",
              "wear_history.png", "wear_vs_angle.png"}


@pytest.fixture(scope="module")
def base(tmp_path_factory, figures_unrendered):
    folder = tmp_path_factory.mktemp("study") / "base"
    lines: list[str] = []
    study = jointwear.Study(SMALL, out=folder, workers=1, echo=lines.append)
    design = study.design()
    design_lines = list(lines)
    study.simulate()
    study.wear()
    study.sensitivity()
    study.validate(n_samples=4)
    study.report()
    return folder, design, design_lines


def _small_config():
    return load_config(SMALL)


def _copy(base, tmp_path):
    return shutil.copytree(base[0], tmp_path / "copy")


def _results_files(folder) -> set[str]:
    return {p.name for p in folder.iterdir() if p.suffix in (".json", ".csv", ".png", ".npz", ".html")}


def test_design_on_a_fresh_folder_tells_the_reliability_stage_it_runs_first(base):
    """design() on a fresh folder learned R(N) in silence (no line, no 'stopped before its stopping rule') and then
    said '35 model calls (15 run now)' although all 35 ran in that call; its result's provenance was {}."""
    folder, design, lines = base
    (rel,) = [line for line in lines if line.startswith("reliability: 20 model calls")]
    assert "read back" not in rel  # all run now
    assert any(line.startswith("reliability: the learning stopped before its stopping rule") for line in lines)
    (told,) = [line for line in lines if line.startswith("design: ") and " model calls" in line]
    assert f"; {design.model_calls} model calls -> " in told and "run now" not in told
    assert design.provenance and design.provenance == DesignResult.load(folder).provenance


def test_calls_read_back_from_the_store_are_not_counted_as_new(base, tmp_path):
    """A fresh Study's sensitivity printed '9 extra model calls' although the store held all of them."""
    folder = _copy(base, tmp_path)
    lines: list[str] = []
    study = jointwear.Study(SMALL, out=folder, workers=1, echo=lines.append)
    phases = []
    told_phase = study._progress_phase
    study._progress_phase = lambda *args: (phases.append(args), told_phase(*args))
    sens = study.sensitivity()
    assert sens.extra_model_calls > 0
    # its calls are counted on their own, not on the learning's line ('model calls 23/23 ... budget=14 calls')
    from jointwear.study.sensitivity import far_shift_calls

    assert phases == [("sensitivity shifts", far_shift_calls(study.config))]
    assert any(line.startswith("reliability: 20 model calls (0 new, 20 read back from the store)") for line in lines)
    (told,) = [line for line in lines if line.startswith("sensitivity: ")]
    assert f"; {sens.extra_model_calls} extra model calls (0 new, {sens.extra_model_calls} read back " in told
    # the same stage again on the same Study: the same result ('0 extra model calls' counted this session's reads)
    assert study.sensitivity() == sens
    study.validate(n_samples=4)
    assert any(line.startswith("validate: 4 true-model samples (0 new, 4 read back from the store), ")
               for line in lines)
    # a smaller validation replacing it says so (validate(n_samples=1) replaced 40 samples without a word)
    study.validate(n_samples=2)
    assert f"validate: this validation of 2 samples replaces one of 4 in {folder}; validating again with 4 reads " \
        "its calls back from the store" in lines


def test_a_rerun_with_other_reliability_settings_moves_aside_what_the_old_curve_gave(base, tmp_path):
    """Another allowance re-learns R(N): the sensitivity, validation and design of the old curve were left beside
    it, read as current by load_results (validation.all_agree of the old curve), compare_studies and the report."""
    folder = _copy(base, tmp_path)
    lines: list[str] = []
    changed = updated(load_config(folder), {"reliability.allowance_mm": 0.08})
    jointwear.Study(changed, out=folder, workers=1, resume=True, echo=lines.append).reliability()
    (told,) = [line for line in lines if line.startswith("out: ")]
    assert told.startswith("out: moved the results of reliability, sensitivity, validation, design (with their "
                           "tables and figures, and report.html) to ")
    assert "(changed: reliability.allowance)" in told
    results = jointwear.load_results(folder)
    assert results.stages == ["simulate", "wear", "reliability"]
    assert _results_files(folder) == {"config.json"} | SIMULATE_FILES | WEAR_FILES | {
        "reliability.json", "reliability_curve.csv", "life_table.csv", "design_points.csv", "reliability_curve.png",
        "wear_histograms.png", "convergence.png"}
    (aside,) = (folder / "superseded").iterdir()
    assert {"sensitivity.json", "validation.json", "design.json", "report.html"} <= {p.name for p in aside.iterdir()}
    page = jointwear.Study(changed, out=folder, echo=lines.append).report().read_text()
    assert "Validation against the true model" not in page


def test_a_wear_model_change_moves_aside_every_result_but_the_dynamics(base, tmp_path):
    """Every result built on the wear history goes with its tables and figures (none is left for the report to show
    as current); the dynamics do not depend on the wear settings and stay."""
    folder = _copy(base, tmp_path)
    lines: list[str] = []
    cfg = load_config(folder)
    jointwear.Study(updated(cfg, {"wear.record_cycles": cfg.wear.record_cycles + 1}), out=folder, workers=1,
                    echo=lines.append).wear()
    (told,) = [line for line in lines if line.startswith("out: ")]
    assert "results of wear, reliability, sensitivity, validation, design (" in told
    assert "(changed: wear.record_cycles)" in told
    assert _results_files(folder) == {"config.json"} | SIMULATE_FILES | WEAR_FILES
    assert jointwear.load_results(folder).stages == ["simulate", "wear"]


@pytest.mark.parametrize("damage", ["missing", "cut short"])
def test_results_whose_record_of_settings_is_lost_are_moved_aside(base, tmp_path, damage):
    """A study killed while it rewrote config.json, resumed with another target, kept its old life at R = 0.9 as
    current under the new record that says 0.5: without a readable record every result counts as stale."""
    folder = _copy(base, tmp_path)
    record = folder / "config.json"
    if damage == "missing":
        record.unlink()
    else:
        record.write_text(record.read_text()[: len(record.read_text()) // 3])
    lines: list[str] = []
    changed = updated(_small_config(), {"reliability.target_reliability": 0.5})
    jointwear.Study(changed, out=folder, workers=1, resume=True, echo=lines.append).reliability()
    (told,) = [line for line in lines if line.startswith("out: ")]
    assert told.startswith("out: moved the results of simulate, wear, reliability, sensitivity, validation, design")
    assert "config.json, the record of their settings, is missing or cannot be read" in told
    assert jointwear.load_results(folder).reliability.target == 0.5


def test_a_resumed_run_keeps_the_results_it_finds_current(base, tmp_path):
    """run --resume recomputed simulate and the nominal wear history (a long one in profile mode) every time, and
    replayed the whole learning from the store to write the same curve and sensitivity again."""
    folder = _copy(base, tmp_path)
    kept = {name: (folder / name).read_bytes() for name in ("wear.json", "reliability.json", "sensitivity.json")}
    (folder / "simulate.json").unlink()
    lines: list[str] = []
    jointwear.Study(SMALL, out=folder, workers=1, resume=True, echo=lines.append).run()
    assert any(line.startswith("simulate: 2 cycles, ") for line in lines)  # its result was gone: run
    for name, content in kept.items():
        stage = name.removesuffix(".json")
        assert f"{stage}: the result for this config is already in {folder / name} (resume): not run again" in lines
        assert (folder / name).read_bytes() == content
    # a kept result's warnings are told as when it was computed (this slider-crank's uniform wear conforms)
    assert any(line.startswith("wear: uniform mode is outside its range here") for line in lines)
    assert not [line for line in lines if line.startswith("out: ")]


def test_a_resumed_run_replays_the_learning_for_a_missing_sensitivity(base, tmp_path):
    """Without its sensitivity the curve is learnt again from the stored calls (the sensitivity needs the
    surrogate): no call is made, and the curve comes out as it was."""
    folder = _copy(base, tmp_path)
    curve = jointwear.load_results(folder).reliability.reliability
    (folder / "sensitivity.json").unlink()
    lines: list[str] = []
    jointwear.Study(SMALL, out=folder, workers=1, resume=True, echo=lines.append).run()
    assert not [line for line in lines if line.startswith(("reliability: the result", "sensitivity: the result"))]
    assert any(line.startswith("reliability: ") and "(0 new, " in line for line in lines)
    assert any(line.startswith("sensitivity: ranking ") for line in lines)
    assert (folder / "sensitivity.json").is_file()
    assert list(jointwear.load_results(folder).reliability.reliability) == list(curve)


def test_arguments_are_named_as_the_caller_gave_them(tmp_path, capsys):
    with pytest.raises(ConfigError, match=r"^out: must be the output folder, a str or pathlib.Path \(got None\)"):
        jointwear.Study(SMALL, out=None)
    with pytest.raises(ConfigError, match=r"^n_samples: must be a whole number >= 1 \(got -3\)"):
        jointwear.Study(SMALL, out=tmp_path).validate(n_samples=-3)
    from jointwear.cli import main_entry

    assert main_entry(["validate", "flores_slider_crank", "--samples", "-3", "--out", str(tmp_path)]) == 2
    assert "'--samples'" in capsys.readouterr().err


def test_a_report_moved_aside_with_stale_results_is_built_again(tmp_path, monkeypatch):
    """A changed [design] moved report.html aside with the stale design, and the design stage then left the folder
    without a report, where docs/design.md says it rewrites it."""
    from jointwear.study import Study

    study = Study("jin2025_flapping_wing", out=tmp_path)
    built = []
    monkeypatch.setattr(Study, "report", lambda self: built.append(self.out))
    study._refresh_report()
    assert built == []  # no report in the folder: none is made
    study._report_moved = True  # as _supersede leaves it when report.html was among what it moved
    study._refresh_report()
    study._refresh_report()
    assert built == [tmp_path]  # built once; from then on it is in the folder


def test_a_wear_property_changed_leaves_the_dynamics_in_place(tmp_path):
    """A changed wear coefficient moved the simulate results aside although the dynamics reads no wear property
    (docs/user-guide.md says a wear change leaves them in place)."""
    from jointwear.study.superseded import stale_stages

    for name in ("simulate.json", "wear.json"):
        (tmp_path / name).write_text("{}", encoding="utf-8")
    assert stale_stages(tmp_path, ["clearance_joints[0].bearing_material.wear_coefficient",
                                   "clearance_joints[1].journal_material.hardness"]) == ["wear"]
    assert stale_stages(tmp_path, ["clearance_joints[0].bearing_material.youngs_modulus"]) == ["simulate", "wear"]


def test_a_design_without_a_choice_rebuilds_the_report(base, tmp_path):
    """When no candidate reached the target, design.json was written but report.html kept the old design (or none):
    the branch returned before the report was rebuilt, as docs/design.md says design does."""
    folder = _copy(base, tmp_path)
    far = {**SMALL, "design": {**SMALL["design"], "targets": [{"reliability": 0.9, "life_factor": 20.0}]}}
    lines: list[str] = []
    result = jointwear.Study(far, out=folder, workers=1, echo=lines.append).design()
    assert result.chosen is None
    assert any(line.startswith("design: no candidate reaches") for line in lines)
    # the target (20x today's life) lies past the curve: said on this path too, as the report says it
    assert any("lies beyond the study's R(N) curve" in line for line in lines), lines
    page = (folder / "report.html").read_text(encoding="utf-8")
    assert "No candidate reaches the target on the surrogate" in page


def test_a_label_changed_moves_no_result_aside_but_the_one_that_records_it(tmp_path):
    """A random input's label or a material's name changes what the report shows, not what any stage computes:
    every result moved aside for it (to be read back from the store). The sensitivity, which records the labels it
    drew its tornado with, goes; a value beside them still supersedes what depends on it."""
    from jointwear.study.superseded import stale_stages

    for name in ("simulate.json", "wear.json", "reliability.json", "sensitivity.json", "validation.json"):
        (tmp_path / name).write_text("{}")
    shown = ["uncertainty.variables[HB_b].label", "uncertainty.clearance.label",
             "clearance_joints[A].bearing_material.name"]
    assert stale_stages(tmp_path, shown) == ["sensitivity"]
    assert stale_stages(tmp_path, shown + ["uncertainty.variables[HB_b].std"]) == [
        "reliability", "sensitivity", "validation"]
    assert stale_stages(tmp_path, ["clearance_joints[A].bearing_material.youngs_modulus"]) == [
        "simulate", "wear", "reliability", "sensitivity", "validation"]
