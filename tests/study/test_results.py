"""The stage results: JSON keys of DESIGN.md, CSV tables beside the JSON, figures, strict JSON, and the typed
results read back by load_results."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "wear"))
from wear_synthetic import FakeModel, fake_simulate  # noqa: E402

from jointwear.config import config_from_dict, load_config  # noqa: E402
from jointwear.reliability import Z95  # noqa: E402
from jointwear.study import ReliabilityCurve, ValidationResult, WearSummary, load_results  # noqa: E402
from jointwear.study.io import file_labels, strict, write_csv, write_json  # noqa: E402
from jointwear.study.reliability import study_context  # noqa: E402
from jointwear.wear import WearSettings, wear_history  # noqa: E402

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def test_wear_summary_save_and_load(tmp_path):
    r = wear_history(FakeModel(), WearSettings(n_grid=360), 50_000, simulate=fake_simulate)
    s = WearSummary.from_history(r, allowances_m={"joint0": 3e-5})
    s.save(tmp_path)
    d = json.loads((tmp_path / "wear.json").read_text())
    for k in ("cycles", "max_wear_mm", "max_wear_angle_deg", "peaks", "profile", "history", "wall_seconds",
              "provenance"):
        assert k in d
    assert d["cycles"] == 50_000
    assert set(d["profile"]) == {"angle_deg", "depth_mm", "contact_force_mean_N", "sliding_mm_per_deg_per_cycle",
                                 "contact_area_mean_mm2", "body_angle_deg", "contact_time_s_per_cycle",
                                 "depth_rate_mm_per_cycle", "depth_growth_mm_per_cycle"}
    assert all(len(v) == 360 for v in d["profile"].values())
    assert set(d["history"]) == {"cycles", "max_wear_mm"} and d["history"]["cycles"][-1] == 50_000
    assert d["peaks"][0]["depth_mm"] == pytest.approx(d["max_wear_mm"])
    assert d["max_wear_mm"] == pytest.approx(r.joints[0].max_bearing_wear * 1e3)
    assert d["limit_mm"] == pytest.approx(0.03)
    # the deepest point's growth over the last block, as the tutorial reads the nominal life from it (the peak of a
    # block's rate profile, which moves round a conformal pocket, read 50x the growth in profile mode)
    h = d["joints"][0]["history"]
    growth = (h["max_wear_mm"][-1] - h["max_wear_mm"][-2]) / (h["cycles"][-1] - h["cycles"][-2])
    assert d["joints"][0]["max_depth_growth_mm_per_cycle"] == pytest.approx(growth, rel=1e-12)
    # the bearing body's mean orientation (the rod's on the flapping wing), under a name that fits any body
    psi = math.degrees(r.joints[0].mean_orientation)
    assert d["joints"][0]["bearing_mean_orientation_deg"] == d["joints"][0]["rod_mean_orientation_deg"] == psi
    assert {"jointwear", "numpy", "scipy", "numba", "openturns", "machine"} <= set(d["provenance"])
    # the code that wrote it, as the evaluation store records it: the git commit too when run from a checkout
    from jointwear.compute.store import code_version

    assert d["provenance"]["jointwear"] == code_version()
    for f in ("wear_profile.csv", "wear_history.csv", "wear_journal_profile.csv", "wear_polar.png",
              "wear_vs_angle.png", "wear_history.png"):
        assert (tmp_path / f).stat().st_size > 0
    back = load_results(tmp_path).wear
    assert isinstance(back, WearSummary) and back.max_wear_mm == s.max_wear_mm and back.history_result is None
    # cells never in contact hold NaN (a mean over no contact); JSON's null comes back as NaN, not None, so numpy
    # reads the loaded profile as it read the one in memory
    force = np.asarray(s.profile["contact_force_mean_N"], dtype=float)
    assert np.isnan(force).any()
    np.testing.assert_array_equal(np.asarray(back.profile["contact_force_mean_N"]), force)
    # a folder read back gives every column of its CSV (the last three were computed from the history in memory)
    csv = pd.read_csv(tmp_path / "wear_profile.csv")
    frame = back.frame("wear_profile")
    assert list(frame.columns) == list(csv.columns) == list(s.frame("wear_profile").columns)
    # the CSV writes 10 significant digits (study.io.write_csv)
    np.testing.assert_allclose(frame.to_numpy(dtype=float), csv.to_numpy(dtype=float), rtol=1e-9, atol=0,
                               equal_nan=True)


def test_several_joints_write_their_files_under_their_names(tmp_path):
    """wear_profile_<joint>.csv and the rest, as orbit_<joint>.png: a name made safe for a file name, and one
    label two names would share told apart by position."""
    r = wear_history(FakeModel(n_joints=2), WearSettings(n_grid=360), 20_000, simulate=fake_simulate)
    s = WearSummary.from_history(r, allowances_m={"joint0": 3e-5, "joint1": 3e-5})
    first = s.joints[0]["name"]
    s.joints[1]["name"] = "crank pin/rod"
    s.save(tmp_path, figures=False)
    names = {p.name for p in tmp_path.glob("*.csv")}
    for stem in ("wear_profile", "wear_history", "wear_journal_profile"):
        assert {f"{stem}_{first}.csv", f"{stem}_crank_pin_rod.csv"} <= names and f"{stem}.csv" not in names
    assert file_labels(["A", "A B", "A/B", ""]) == ["A", "A_B_1", "A_B_2", "_"]


def test_json_is_strict(tmp_path):
    path = write_json(tmp_path / "x.json", {"a": math.inf, "b": [1.0, math.nan], "c": np.float64(2.5)})
    text = path.read_text()
    assert "Infinity" not in text and "NaN" not in text
    assert json.loads(text) == {"a": None, "b": [1.0, None], "c": 2.5}
    assert strict({"n": np.arange(2)}) == {"n": [0, 1]}


@pytest.mark.skipif(sys.platform == "win32", reason="symlinks need privileges on Windows")
def test_a_symlink_planted_in_a_results_folder_is_never_written_through(tmp_path):
    """A received folder whose result file, or the old fixed temporary name beside it, is a link to a file outside:
    writing the result replaces the link and leaves the outside file as it was."""
    from jointwear.report.markup import write_page
    from jointwear.report.style import figure, savefig
    from jointwear.study.io import write_csv

    outside = tmp_path / "outside.txt"
    outside.write_text("keep", encoding="utf-8")
    folder = tmp_path / "results"
    folder.mkdir()
    for name in ("x.json", "report.html.tmp", "x.csv", "fig.png"):
        (folder / name).symlink_to(outside)
    write_json(folder / "x.json", {"a": 1})
    savefig(figure()[0], folder / "fig.png")
    write_page(folder / "report.html", "<p>page</p>")
    write_csv(folder / "x.csv", {"a": [1.0, 2.0]})
    assert outside.read_text(encoding="utf-8") == "keep"
    assert not (folder / "x.json").is_symlink() and json.loads((folder / "x.json").read_text()) == {"a": 1}
    assert (folder / "report.html").read_text(encoding="utf-8") == "<p>page</p>"
    assert (folder / "x.csv").read_text(encoding="utf-8").splitlines() == ["a", "1", "2"]
    assert not (folder / "fig.png").is_symlink() and (folder / "fig.png").read_bytes().startswith(b"\x89PNG")
    assert [f.name for f in folder.glob("*.tmp")] == ["report.html.tmp"]  # the planted link; no temporary file left


def test_a_number_too_large_for_its_field_spoils_only_its_stage(tmp_path):
    # load_results turns an unreadable stage into None with its reason; 10**400 raised OverflowError past it
    from jointwear.study.io import strict

    rel = small_reliability_curve()
    rel.save(tmp_path)
    data = json.loads((tmp_path / rel.FILE).read_text())
    data["curve"]["cycles"][0] = 10**400
    (tmp_path / rel.FILE).write_text(json.dumps(strict(data)))
    loaded = load_results(tmp_path)
    assert loaded.reliability is None and "could not be read" in loaded.errors["reliability"]


def small_reliability_curve():
    cycles = np.array([1e5, 2e5, 3e5])
    rel = np.array([0.99, 0.8, 0.3])
    return ReliabilityCurve(
        cycles=cycles, reliability=rel, pf=1 - rel, pf_cov=np.array([np.inf, 0.02, 0.01]),
        below_floor=np.array([False, False, False]), pf_error=np.array([0.001, 0.01, 0.01]), target=0.9,
        life_cycles=1.45e5, life_hours=1.0, model_calls=20, failed_calls=0, n_mc=1000, converged=True,
        wall_seconds=1.0, names=["a", "b"], units=["Pa", ""], histograms={}, mean_max_wear_mm={}, convergence={},
        design_x=np.ones((3, 2)), design_wear=np.ones((3, 3)), design_life=np.array([1e5, 2e5, np.inf]),
        life_table=[{"target": 0.9, "cycles": 1.45e5, "hours": 1.0}, {"target": 0.99, "cycles": None,
                                                                       "hours": None}],
        joints=[{"name": "A", "allowance_mm": 0.03, "reliability": rel.tolist(), "governing_share": [1.0] * 3}])


def test_reliability_result_round_trip_and_tables(tmp_path):
    res = small_reliability_curve()
    res.save(tmp_path, figures=False)
    back = load_results(tmp_path).reliability
    np.testing.assert_array_equal(back.reliability, res.reliability)
    assert back.pf_cov[0] != back.pf_cov[0]  # infinity is written as null (strict JSON) and read back as NaN
    assert back.life_table == res.life_table and back.governing_joint == "A"
    curve = (tmp_path / "reliability_curve.csv").read_text().splitlines()
    assert curve[0].split(",")[:3] == ["cycles", "reliability", "pf"] and len(curve) == 4
    life_rows = (tmp_path / "life_table.csv").read_text().splitlines()
    assert life_rows[0] == "target_reliability,life_cycles,life_hours,status,life_cycles_low,life_cycles_high"
    # the band R -/+ (1.96 COV Pf + error) is 0.99 -/+ 0.001 at 1e5 (the infinite COV counts as 0) and
    # 0.8 -/+ (1.96 x 0.02 x 0.2 + 0.01) = 0.8 -/+ 0.01784 at 2e5: it crosses 0.9 where linear interpolation puts it
    low, high = res.life_interval()
    half = Z95 * 0.02 * 0.2 + 0.01
    assert low == pytest.approx(1e5 + (0.989 - 0.9) / (0.989 - (0.8 - half)) * 1e5, rel=1e-12)
    assert high == pytest.approx(1e5 + (0.991 - 0.9) / (0.991 - (0.8 + half)) * 1e5, rel=1e-12)
    assert back.to_json()["life_at_target"]["cycles_low"] == pytest.approx(low, rel=1e-15)
    # each input column named as a config key with its SI unit, a plain number bare
    assert (tmp_path / "design_points.csv").read_text().splitlines()[0] == "a_Pa,b,life_cycles"
    assert back.units == ["Pa", ""]
    assert back.pf_error_esc is None  # a result without ESC's part (written before it) reads back without it
    res.pf_error_esc = np.array([0.001, 0.004, 0.01])
    res.save(tmp_path, figures=False)
    np.testing.assert_array_equal(load_results(tmp_path).reliability.pf_error_esc, res.pf_error_esc)
    assert "pf_error_esc" in (tmp_path / "reliability_curve.csv").read_text().splitlines()[0].split(",")


def test_a_result_whose_arrays_disagree_in_length_saves_nothing_and_names_them(tmp_path):
    """A curve cut short by hand wrote its CSV cut at the shortest column, without a word (zip stops there)."""
    res = small_reliability_curve()
    res.pf_error = res.pf_error[:2]
    with pytest.raises(ValueError, match=r"ReliabilityCurve: cycles, .* run along one axis but their lengths differ "
                                         r"\(cycles 3, reliability 3, .*pf_error 2"):
        res.save(tmp_path, figures=False)
    res = small_reliability_curve()
    res.joints[0]["reliability"] = res.joints[0]["reliability"][:2]  # one joint's column of the curve's table
    res.joints.append({**res.joints[0], "name": "B"})
    with pytest.raises(ValueError, match=r"ReliabilityCurve table 'reliability_curve': columns of different lengths "
                                         r"\(cycles 3, .*reliability_A 2"):
        res.save(tmp_path, figures=False)
    val = ValidationResult(cycles=[1e5, 2e5], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78], ci_high=[0.96, 0.82],
                           reliability_surrogate=[0.948], surrogate_error=[0.005, 0.01], n_samples=200,
                           model_calls=200, wall_seconds=1.0, agreement=[True, True])
    with pytest.raises(ValueError, match=r"ValidationResult: .*\(cycles 2, .*reliability_surrogate 1,"):
        val.save(tmp_path, figures=False)
    assert not any(tmp_path.iterdir())  # everything is checked before the first file is written
    with pytest.raises(ValueError, match=r"t.csv: columns of different lengths \(a 2, b 1\)"):
        write_csv(tmp_path / "t.csv", {"a": [1, 2], "b": [3]})


def test_the_study_inputs_carry_their_si_units():
    """The units that name design_points.csv's columns and sensitivity.csv's `unit`: each variable's target's SI
    unit (the clearance's and the wear allowance's: m), "" for a plain number."""
    cfg = load_config("jin2025_flapping_wing")
    ctx = study_context(cfg, lambda call: None)
    units = dict(zip(ctx.names, ctx.units))
    assert units["Rj"] == units["c"] == units["l2"] == "m"
    assert units["E_b"] == units["HB_j"] == "Pa" and units["nu_b"] == units["k_j"] == ""
    data = cfg.model_dump(mode="json")
    data["reliability"]["allowance_std"] = 1e-6  # a random allowance: one more input
    ctx = study_context(config_from_dict(data), lambda call: None)
    assert ctx.names[-1] == "delta_0" and ctx.units[-1] == "m" and len(ctx.units) == len(ctx.names)


def test_every_table_as_its_csv_file_and_as_a_data_frame(tmp_path):
    """A stage's tables are what its CSV files hold, and each is a pandas DataFrame with the same columns and rows
    (a notebook reads the result without the folder)."""
    import pandas as pd

    res = small_reliability_curve()
    res.save(tmp_path, figures=False)
    tables = res.tables()
    assert list(tables) == ["reliability_curve", "life_table", "design_points"]
    for stem in tables:
        frame, csv = res.frame(stem), pd.read_csv(tmp_path / f"{stem}.csv")
        assert list(frame.columns) == list(csv.columns) and len(frame) == len(csv)
    assert res.frame().equals(res.frame("reliability_curve"))
    np.testing.assert_allclose(res.frame("design_points")["a_Pa"], pd.read_csv(tmp_path / "design_points.csv")["a_Pa"])
    with pytest.raises(KeyError, match="reliability_curve, life_table, design_points"):
        res.frame("curve")
    r = wear_history(FakeModel(n_joints=2), WearSettings(n_grid=360), 20_000, simulate=fake_simulate)
    wear = WearSummary.from_history(r, allowances_m={"joint0": 3e-5, "joint1": 3e-5})
    names = [j["name"] for j in wear.joints]
    assert set(wear.tables()) == {f"{stem}_{n}" for stem in ("wear_history", "wear_journal_profile", "wear_profile")
                                  for n in names}
    assert len(wear.frame(f"wear_profile_{names[1]}")) == 360


def test_load_results_of_an_empty_or_damaged_folder(tmp_path):
    """An existing folder with nothing of a study in it (a typo in the last part of the path, the folder above a
    study's) read as a study with every stage None, and failed later on a None."""
    (tmp_path / "runs" / "study_a").mkdir(parents=True)
    (tmp_path / "runs" / "study_a" / "config.json").write_text("{}")
    with pytest.raises(FileNotFoundError, match=r"runs' holds no study results .*these folders in it do: study_a$"):
        load_results(tmp_path / "runs")
    with pytest.raises(FileNotFoundError, match=r"holds no study results \(none of config.json, simulate.json"):
        load_results(tmp_path)
    assert load_results(tmp_path / "runs" / "study_a").stages == []  # a study with no stage run yet
    (tmp_path / "reliability.json").write_text("{not json")
    res = load_results(tmp_path)
    assert res.reliability is None and "reliability" in res.errors


def test_a_result_prints_short_with_every_field(tmp_path):
    """A notebook prints a result whole: one line per field, a 360-cell profile as its keys, a short array whole (the
    repr used to run to 126 kB for one wear result)."""
    from dataclasses import fields

    r = wear_history(FakeModel(), WearSettings(n_grid=360), 50_000, simulate=fake_simulate)
    s = WearSummary.from_history(r, allowances_m={"joint0": 3e-5})
    s.save(tmp_path)
    rel = small_reliability_curve()
    rel.save(tmp_path, figures=False)
    for res in (s, rel):
        text = repr(res)
        assert len(text) < 3000 and text.startswith(type(res).__name__ + "(")
        assert all(f"\n    {f.name}=" in text for f in fields(res) if f.repr)
    assert "profile=<dict of 9: angle_deg, depth_mm" in repr(s)
    assert f"reliability={np.array2string(rel.reliability, precision=4, separator=', ')}" in repr(rel)
    expected = f"StudyResults(folder={str(tmp_path)!r}, name=None, stages=['wear', 'reliability'])"
    assert repr(load_results(tmp_path)) == expected


def test_a_study_prints_its_config_and_folder(tmp_path):
    import jointwear

    study = jointwear.Study("jin2025_flapping_wing", out=tmp_path / "o", workers=1)
    out = str(tmp_path / "o")
    assert repr(study) == f"Study('jin2025_flapping_wing', source='jin2025_flapping_wing', out={out!r}, workers=1)"
    assert not (tmp_path / "o").exists()  # building a study writes nothing


def test_profile_mode_writes_the_limit_states_clearance_growth(tmp_path):
    """In profile mode the dynamics grow no clearance, so the column read all zeros while the bearing wore 0.024 mm;
    it now holds the limit state's clearance_growth: the maximum bearing plus the maximum journal depth."""
    r = wear_history(FakeModel(), WearSettings(n_grid=360, geometry_mode="profile"), 50_000, simulate=fake_simulate)
    s = WearSummary.from_history(r)
    h = s.joints[0]["history"]
    np.testing.assert_allclose(h["clearance_growth_mm"],
                               np.add(h["max_wear_mm"], h["max_journal_wear_mm"]), rtol=1e-12)
    assert h["clearance_growth_mm"][-1] > 0


def test_results_compare_by_value():
    """`rel_a == rel_b` raised 'the truth value of an array is ambiguous' (the dataclass comparison)."""
    a, b = small_reliability_curve(), small_reliability_curve()
    a.pf_error[0] = b.pf_error[0] = np.nan  # NaN holes, as a loaded result has them, compare equal
    assert a == b and not (a != b)
    b.reliability = b.reliability.copy()
    b.reliability[1] = 0.81
    assert a != b
    assert a != "a string" and a != small_reliability_curve().__dict__


def test_equality_ignores_the_runs_metadata():
    """The same curve computed twice compared unequal: the wall time and the provenance's time of writing differ."""
    a, b = small_reliability_curve(), small_reliability_curve()
    b.wall_seconds = a.wall_seconds + 7.0
    b.provenance = {**a.provenance, "written_at": "2030-01-01T00:00:00+00:00", "machine": "another"}
    assert a == b
    b.life_table = [dict(row, cycles=1.0) for row in b.life_table]
    assert a != b  # what the run found still counts


def test_a_resumed_validation_equals_an_uninterrupted_one():
    """A validation resumed after an interrupt read most of its samples back: its model_calls (the calls that run
    made, 21 of 80) made it unequal to the uninterrupted one though every number it found was the same."""
    def validation(calls: int) -> ValidationResult:
        return ValidationResult(cycles=[1e5, 2e5], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                                ci_high=[0.96, 0.82], reliability_surrogate=[0.948, 0.81],
                                surrogate_error=[0.005, 0.01], n_samples=80, model_calls=calls,
                                wall_seconds=float(calls), agreement=[True, True])

    assert validation(80) == validation(21)
    other = validation(80)
    other.n_samples = 81
    assert other != validation(80)  # how many samples it rests on is a finding


def test_a_life_target_outside_0_1_or_not_a_number_is_refused_by_name():
    """life_interval(1.5) returned (None, None) and life_interval("0.9") raised numpy's UFuncTypeError."""
    from jointwear.schema import ConfigError

    res = small_reliability_curve()
    for bad in (1.5, 0.0, 1.0, -0.1, "0.9", True, float("nan")):
        with pytest.raises(ConfigError, match=r"life_interval: target: a reliability in \(0, 1\)"):
            res.life_interval(bad)
        with pytest.raises(ConfigError, match=r"life: target: a reliability in \(0, 1\)"):
            res.life(bad)
    assert res.life(np.float64(0.9)) == res.life() and res.life_interval(0.9) == res.life_interval()


def test_profile_mode_says_whether_uniform_mode_would_have_been_fair():
    """In profile mode the command line said nothing of the conformity (only wear.json and the report did)."""
    from types import SimpleNamespace

    from jointwear.study.stage_lines import profile_mode_line

    assert profile_mode_line(SimpleNamespace(geometry_mode="profile", joints=[], conformity=6.57)) == (
        "profile mode follows the worn shape here (conformity 6.57 > 1: the journal fits into its own wear, which "
        "uniform mode ignores): this is the answer to trust")
    assert profile_mode_line(SimpleNamespace(geometry_mode="profile", joints=[], conformity=0.4)).startswith(
        "uniform mode would be fair here too (conformity 0.4 <= 1")
    assert profile_mode_line(SimpleNamespace(geometry_mode="uniform", joints=[], conformity=6.57)) == ""
    assert profile_mode_line(SimpleNamespace(geometry_mode="profile", joints=[], conformity=float("nan"))) == ""


def test_every_stage_result_saves_with_the_same_signature():
    import inspect

    from jointwear.study.stage_result import StageResult

    def subclasses(cls):
        for sub in cls.__subclasses__():
            yield sub
            yield from subclasses(sub)

    import jointwear.study  # noqa: F401  (registers every stage result)

    savers = [c for c in subclasses(StageResult) if "save" in vars(c)]
    assert len(savers) >= 6
    for cls in savers:
        params = inspect.signature(cls.save).parameters
        assert list(params)[:2] == ["self", "folder"], cls.__name__
        assert params.get("figures") is not None and params["figures"].kind is inspect.Parameter.KEYWORD_ONLY, \
            cls.__name__


def test_a_stage_killed_while_drawing_leaves_no_json_that_reads_as_whole(tmp_path, monkeypatch):
    """A crash after reliability.json but before its figures left the figures missing for good: a resume takes the
    JSON as a finished stage. The JSON is written last."""
    import jointwear.study.reliability_results as rr

    def killed(fig, path):
        raise KeyboardInterrupt

    monkeypatch.setattr(rr, "save_figure", killed)
    with pytest.raises(KeyboardInterrupt):
        small_reliability_curve().save(tmp_path)
    assert (tmp_path / "reliability_curve.csv").is_file() and not (tmp_path / "reliability.json").exists()


def test_file_labels_differ_on_a_case_insensitive_file_system():
    from jointwear.study.io import file_labels

    assert file_labels(["A", "a", "B"]) == ["A_0", "a_1", "B"]  # orbit_A.png and orbit_a.png: one file on macOS


def test_an_interval_outside_the_curve_says_on_which_side():
    """The life table read 'wider than the curve' for an interval wholly before the curve's first level (R = 0.9999
    on the default curve)."""
    from jointwear.study.reliability_results import interval_cells

    assert interval_cells(None, None, reach=(-math.inf, 2e5)) == "before the curve"
    assert interval_cells(None, None, reach=(5.6e5, math.inf)) == "beyond the curve"
    assert interval_cells(None, None, reach=(-math.inf, math.inf)) == "wider than the curve"


def test_the_command_line_gives_every_targets_life():
    """Only the headline target's life was printed; a second target (R = 0.9999) appeared in the table alone."""
    from jointwear.study.stage_lines import other_lives_line

    res = small_reliability_curve()
    res.life_table[1]["status"] = "beyond_curve"
    assert other_lives_line(res) == "R = 0.99: beyond the curve's last level (extend cycles_stop)"
    res.life_table = res.life_table[:1]
    assert other_lives_line(res) == ""


def test_a_target_in_the_posterior_points_thin_tail_is_told():
    """R = 0.999 leaves about 3 failures among the 3,000 points where the Kriging's posterior spread of Pf is drawn:
    that part of the life's interval rested on about nothing, and nothing said so."""
    from jointwear.study.stage_lines import POSTERIOR_TAIL_POINTS, posterior_tail_line

    res = small_reliability_curve()  # targets 0.9 and 0.99: 300 and 30 expected failures among 3,000
    assert 0.01 * 3000 >= POSTERIOR_TAIL_POINTS and posterior_tail_line(res, 3000) == ""
    res.life_table = [*res.life_table, {"target": 0.999, "cycles": None, "hours": None}]
    line = posterior_tail_line(res, 3000)
    assert line.startswith("at R = 0.999 the Kriging's posterior spread of Pf") and "about 3 fail" in line


def test_a_life_read_in_the_populations_thin_tail_warns_in_python():
    """life(0.99999) on a curve learnt with 1,000 samples read a Pf that about 0.01 failures estimate, in silence (the
    stage's check warns only of the configured targets). Threshold: THIN_TAIL_FAILURES expected failures, n Pf."""
    import warnings

    res = small_reliability_curve()  # n_mc = 1000
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res.life(0.9)  # 100 expected failures
        res.life(1.0 - (res.THIN_TAIL_FAILURES + 1) / res.n_mc)
    with pytest.warns(UserWarning, match=r"life at R = 0.99: the 1,000 Monte Carlo samples expect about 10 failures "
                                         r"at Pf = 0.01 \(Monte Carlo COV 0.31\).*n_mc_max >= 2,000"):
        res.life(0.99)
    res.n_mc = 100_000
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res.life(0.99)


def test_the_lazy_public_names_are_the_ones_type_checkers_see():
    """jointwear and jointwear.design load their names on first use through __getattr__, which type checkers read as
    returning Any (every `jointwear.Study(...)` was untyped): each lazy name must also be imported under
    TYPE_CHECKING, and jointwear.design's __all__ must be a literal list that holds every lazy name."""
    import ast
    import inspect

    import jointwear
    import jointwear.design as design

    for module, lazy in ((jointwear, {"Study", "load_results", "compare_studies", "load_config", "ConfigError"}),
                         (design, set(design._LAZY))):
        tree = ast.parse(inspect.getsource(module))
        guarded = {alias.asname or alias.name for node in ast.walk(tree) if isinstance(node, ast.If)
                   and getattr(node.test, "id", "") == "TYPE_CHECKING" for imp in node.body
                   if isinstance(imp, ast.ImportFrom) for alias in imp.names}
        assert lazy <= guarded, (module.__name__, lazy - guarded)
        assert lazy <= set(module.__all__) and lazy <= set(dir(module))
        for name in lazy:
            assert getattr(module, name).__name__ == name


def test_a_hertz_half_width_past_half_the_bore_is_not_told_as_an_angle():
    """A 1 MPa bushing's contact read '304 deg wide each side': Hertz's formula past its range, not a contact."""
    from jointwear.study.results import half_angle_text

    assert half_angle_text(12.34) == "12.3 deg wide each side"
    assert half_angle_text(304.0) == "wider than the whole bore (Hertz's half-width reads 304 deg each side)"


def test_a_life_of_minutes_keeps_three_figures_in_hours():
    """The slider-crank's R = 0.99 life, 0.0957 h, was printed as 0.10 h (4 % off by its rounding)."""
    from jointwear.study.stage_lines import life_text

    assert life_text({"cycles": 28_713, "hours": 0.0957}) == "28,713 cycles = 0.0957 h"
    assert life_text({"cycles": 376_184, "hours": 13.0619}) == "376,184 cycles = 13.06 h"


def test_csv_text_cells_that_a_spreadsheet_would_run_are_neutralised_numbers_are_not(tmp_path):
    import csv

    from jointwear.study.io import write_csv

    write_csv(tmp_path / "x.csv", {
        "=1+2 name": ["=HYPERLINK(\"http://x\",\"l\")", "+cmd", "-2+3", "@SUM(A1)", "\tx", "ok", "-1.5", "plain"],
        "value": [-1.5, -2, np.float64(-3.25), np.int64(-4), None, 0.5, 1.0, True],
    })
    with open(tmp_path / "x.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["'=1+2 name", "value"]
    assert [r[0] for r in rows[1:]] == ["'=HYPERLINK(\"http://x\",\"l\")", "'+cmd", "'-2+3", "'@SUM(A1)", "'\tx", "ok",
                                        "-1.5", "plain"]
    assert [r[1] for r in rows[1:]] == ["-1.5", "-2", "-3.25", "-4", "", "0.5", "1", "True"]


def test_a_long_reliability_budget_is_told_after_the_wear_stage():
    """A designer's mechanism under a realistic load took 8.9 s a cycle, and nothing said what 12 calls of a 350,000-
    cycle curve would cost before the reliability stage began. At the nominal history's pace (seconds per cycle of
    the history times the calls' cycles) beyond half an hour in all the wear stage says so; the default study's
    budget (0.7 s for 400,000 cycles, 80 calls to 520,000) says nothing."""
    from jointwear.study.stage_lines import LONG_BUDGET_SECONDS, budget_line

    assert budget_line(0.7, 400_000, 520_000, 80) == ""
    line = budget_line(890.0, 10_000, 350_000, 12)  # 31,150 s a call, 373,800 s in all
    assert line.startswith("each model call of the reliability stage runs such a history to 350,000 cycles, about "
                           "8.7 h at this history's pace: its budget of 12 calls may take up to 4.3 days in all")
    per_call = LONG_BUDGET_SECONDS / 10
    assert budget_line(per_call, 1000, 1000, 10) == "" and budget_line(per_call * 1.01, 1000, 1000, 10) != ""
    # the sensitivity stage's runs of far-shifted means count too, and are named
    assert budget_line(per_call, 1000, 1000, 8) == "" and "sensitivity" not in line
    with_sensitivity = budget_line(per_call, 1000, 1000, 8, 3)
    assert "its budget of 8 calls may take up to 24 min in all, and the sensitivity stage's 3 runs of means shifted " \
           "beyond the learned region up to 9 min more" in with_sensitivity, with_sensitivity


def test_simulate_tells_a_model_calls_cost_and_names_the_stick_branch_of_a_stiff_cycle():
    """A designer's loaded press took 1.6 million steps and 3.7 s a cycle, and simulate said neither what a model call
    would cost nor why (audit 61-K, D5). The line multiplies the pace by the history's simulated cycles (blocks times
    settled and recorded cycles) and the budget's calls; past MANY_STEPS_PER_CYCLE it names the friction law's stick
    branch. A history of adaptive blocks (no simulated count) and a light cycle say nothing."""
    from jointwear.study.stage_lines import MANY_STEPS_PER_CYCLE, simulation_cost_line

    assert simulation_cost_line(5_000, 0.004, None, 520_000, 80) == ""
    line = simulation_cost_line(1_589_723, 3.7, 90, 300_000, 26)  # 333 s a call, 8,658 s for 26
    assert line.startswith("a wear history of 300,000 cycles (each model call) simulates 90 cycles of dynamics: about "
                           "6 min at this pace; the reliability budget of 26 calls about 2.4 h of computing"), line
    assert "1,589,723 steps a cycle is many" in line and "larger friction v_s and v_d" in line
    assert "steps a cycle" not in simulation_cost_line(MANY_STEPS_PER_CYCLE, 1.0, 90, 300_000, None)
    assert "budget" not in simulation_cost_line(MANY_STEPS_PER_CYCLE, 1.0, 90, 300_000, None)


def test_the_sensitivity_stages_true_model_calls_are_counted_from_the_config():
    """The default study's sensitivity made 9 true-model calls beyond the curve's design (the four lengths' and the
    journal radius' 20 % shifts, hundreds of standard deviations, and the nominal means: benchmarks/results/
    study.json's sensitivity_extra_model_calls); its materials' shifts (2 standard deviations) need none."""
    import json
    from pathlib import Path

    from jointwear.config import load_config, updated
    from jointwear.study.sensitivity import far_shift_calls

    record = json.loads((Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "study.json").read_text())
    cfg = load_config()
    assert far_shift_calls(cfg) == record["runs"][0]["sensitivity_extra_model_calls"] == 9
    assert far_shift_calls(updated(cfg, {"sensitivity.surrogate_shift_limit": 1e9})) == 0
