"""Studies compared side by side (`jointwear compare`, `jointwear.compare_studies`), on straight R(N) curves whose
lives and 95 % intervals are exact: R(N) = 1 - N / scale with a band of +-0.01 crosses R = 0.9 at
N = 0.1 scale, and its band at 0.09 scale and 0.11 scale (linear interpolation is exact on a straight line)."""

from __future__ import annotations

import json
import sys
from html.parser import HTMLParser

import numpy as np
import pytest

import jointwear
from jointwear.cli import main_entry
from jointwear.schema import ConfigError
from jointwear.study import ReliabilityCurve, StudyComparison, ValidationResult, compare_studies
from jointwear.study.comparison import life_verdict


def _study(folder, name, scale, mode="uniform", rpm=480.0):
    """A finished study in ``folder``: a straight R(N) of slope 1 / scale, its band +-0.01 (no Monte Carlo part),
    and a config.json whose settings list the wear mode."""
    cycles = np.linspace(0.0, 4e5, 21)
    rel = 1.0 - cycles / scale
    res = ReliabilityCurve(
        cycles=cycles, reliability=rel, pf=1.0 - rel, pf_cov=np.zeros(21), below_floor=np.zeros(21, dtype=bool),
        pf_error=np.full(21, 0.01), target=0.9, life_cycles=0.1 * scale, life_hours=0.1 * scale / (rpm * 60),
        model_calls=40, failed_calls=0, n_mc=1000, converged=True, wall_seconds=1.0, names=["a"], units=[""],
        histograms={}, mean_max_wear_mm={}, convergence={}, design_x=np.ones((2, 1)), design_wear=np.ones((2, 3)),
        life_table=[{"target": 0.9, "cycles": 0.1 * scale, "hours": 1.0, "status": "in_curve"}],
        joints=[{"name": "A", "allowance_mm": 0.02}], crank_speed_rpm=rpm)
    folder.mkdir()
    res.save(folder, figures=False)
    settings = [{"name": "name", "value": name, "unit": None},
                {"name": "clearance_joints[0].bearing_radius", "value": 1.0, "unit": "mm"},
                {"name": "wear.geometry_mode", "value": mode, "unit": None}]
    (folder / "config.json").write_text(json.dumps({"name": name, "settings": settings}))
    return folder


@pytest.fixture
def three(tmp_path):
    return [_study(tmp_path / "a", "pin", 1e6), _study(tmp_path / "b", "pin profile", 2e6, mode="profile"),
            _study(tmp_path / "c", "pin again", 1.02e6)]


def test_lives_intervals_and_verdicts_are_exact_on_straight_curves(three):
    comp = compare_studies(three)
    a, b, c = comp.studies
    assert comp.target == 0.9 and comp.labels == ["pin", "pin profile", "pin again"]
    for row, scale in ((a, 1e6), (b, 2e6), (c, 1.02e6)):
        assert row["life_cycles"] == pytest.approx(0.1 * scale, rel=1e-12)
        assert row["life_cycles_low"] == pytest.approx(0.09 * scale, rel=1e-12)
        assert row["life_cycles_high"] == pytest.approx(0.11 * scale, rel=1e-12)
        assert row["life_hours"] == pytest.approx(0.1 * scale / (480 * 60), rel=1e-12)
    # 180,000-220,000 lies above 90,000-110,000; 91,800-112,200 overlaps it
    assert (a["verdict"], b["verdict"], c["verdict"]) == ("baseline", "longer", "within the errors")
    assert b["life_ratio"] == pytest.approx(2.0, rel=1e-12) and a["life_ratio"] == 1.0
    # the one setting that differs among those the three share (the name is a label, not a setting)
    assert [d["name"] for d in comp.differences] == ["wear.geometry_mode"]
    assert comp.differences[0]["values"] == ["uniform", "profile", "uniform"]


def test_another_target_is_read_on_each_curve(three):
    comp = compare_studies(three[:2], target=0.8)  # no study has it in its table: read on the curves
    assert [s["life_cycles"] for s in comp.studies] == pytest.approx([2e5, 4e5], rel=1e-12)
    assert comp.studies[1]["life_cycles_high"] is None  # 0.79 never reached on the 2e6 curve's upper band
    assert comp.studies[1]["status"] == "in_curve" and comp.studies[1]["verdict"] == "longer"


def test_studies_that_differ_only_in_their_seeds_say_so(three):
    """Seed 1 read 'shorter' than seed 2 (0.972) with nothing else changed: the verdict measured the learning's own
    scatter, which the intervals do not hold. Where the calls ran (compute.*) is no difference."""
    for folder, seed, workers in ((three[0], 2, 1), (three[2], 1, 2)):
        path = folder / "config.json"
        data = json.loads(path.read_text())
        data["settings"] = [s for s in data["settings"] if s["name"] not in ("reliability.seed", "compute.workers")]
        data["settings"] += [{"name": "reliability.seed", "value": seed}, {"name": "compute.workers", "value": workers}]
        path.write_text(json.dumps(data))
    comp = compare_studies([three[0], three[2]])
    assert [d["name"] for d in comp.differences] == ["reliability.seed"]
    assert "differ only in their seeds" in comp.seed_note() and comp.seed_note() in comp.markdown()
    assert compare_studies(three[:2]).seed_note() == ""
    # a call's time-out does change a result (a call it stops counts as a failure): 'No setting differs' hid it
    for folder, timeout in ((three[0], 600.0), (three[2], 300.0)):
        path = folder / "config.json"
        data = json.loads(path.read_text())
        data["settings"] += [{"name": "compute.call_timeout", "value": timeout, "unit": "s"}]
        path.write_text(json.dumps(data))
    comp = compare_studies([three[0], three[2]])
    assert [d["name"] for d in comp.differences] == ["reliability.seed", "compute.call_timeout"]


def test_a_life_outside_the_curve_has_no_interval_cell():
    """A life before the curve showed 'before the curve | before the curve \u2013 beyond the curve'."""
    from jointwear.study.reliability_results import interval_cells

    assert interval_cells(None, None) == "wider than the curve"
    assert interval_cells(None, 5.0) == "before the curve \u2013 5"


def test_life_verdict_reads_an_open_end_as_reaching_as_far_as_it_may():
    assert life_verdict(5.0, 6.0, 1.0, 4.0) == "longer"
    assert life_verdict(1.0, 2.0, 3.0, 4.0) == "shorter"
    assert life_verdict(4.0, 6.0, 1.0, 4.0) == "within the errors"  # touching intervals overlap
    assert life_verdict(5.0, 6.0, 1.0, None) == "within the errors"  # the baseline's end beyond its curve
    assert life_verdict(None, 0.5, 1.0, 4.0) == "shorter"


def test_saved_comparison_reads_back_and_writes_its_tables(three, tmp_path):
    comp = compare_studies(three, labels=["A", "B", "C"])
    comp.save(tmp_path / "cmp")
    back = StudyComparison.load(tmp_path / "cmp")
    assert back == comp and back.labels == ["A", "B", "C"]
    rows = (tmp_path / "cmp" / "comparison.csv").read_text().splitlines()
    assert rows[0].startswith("label,geometry_mode,life_cycles,life_cycles_low,life_cycles_high") and len(rows) == 4
    assert (tmp_path / "cmp" / "comparison_settings.csv").read_text().splitlines() == [
        "setting,unit,A,B,C", "wear.geometry_mode,,uniform,profile,uniform"]
    assert (tmp_path / "cmp" / "comparison_reliability.png").stat().st_size > 10_000
    md = (tmp_path / "cmp" / "comparison.md").read_text()
    assert "| B | 200,000 | 180,000 \u2013 220,000 | 2.000 | longer |" in md
    # no wear stage ran: the mode is the config's; not validated: said so, not left blank
    # no wear stage in these folders: whether uniform mode was in its range is not known
    assert md.count("| 40 | uniform (its range not checked: no wear stage) | \u2014 |") == 2
    assert md.count("| 40 | profile | \u2014 |") == 1


class _Cells(HTMLParser):
    """The text of every table cell, row by row, and the images' sources."""

    def __init__(self):
        super().__init__()
        self.rows, self.images, self._cell = [], [], None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = ""
        elif tag == "img":
            self.images.append(dict(attrs)["src"])

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.rows[-1].append(self._cell)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


def test_the_comparison_page_holds_the_same_rows_and_the_curves(three, tmp_path):
    comp = compare_studies(three, labels=["A", "B", "C"])
    comp.save(tmp_path / "cmp")
    page = _Cells()
    page.feed((tmp_path / "cmp" / "comparison.html").read_text(encoding="utf-8"))
    assert list(StudyComparison.COLUMNS) in page.rows
    for row in comp.rows():  # the rows of comparison.md, cell for cell
        assert list(row) in page.rows
    assert ["B", "200,000", "180,000 \u2013 220,000", "2.000", "longer"] == page.rows[page.rows.index(
        list(comp.rows()[1]))][:5]
    assert ["wear.geometry_mode", "uniform", "profile", "uniform"] in page.rows
    assert len(page.images) == 1 and page.images[0].startswith("data:image/png;base64,")
    # written without figures: the page says so instead of showing an empty frame
    comp.save(tmp_path / "nofig", figures=False)
    text = (tmp_path / "nofig" / "comparison.html").read_text(encoding="utf-8")
    assert "<img" not in text and "No figure of the curves" in text


def test_labels_default_to_folders_where_names_repeat(tmp_path):
    a = _study(tmp_path / "x", "same", 1e6)
    b = _study(tmp_path / "y", "same", 1e6)
    comp = jointwear.compare_studies([a, b])
    assert comp.labels == ["x", "y"] and comp.differences == []
    assert comp.studies[1]["verdict"] == "within the errors"


def test_bad_inputs_name_what_is_wrong(three, tmp_path):
    with pytest.raises(ConfigError, match="two or more"):
        compare_studies(three[:1])
    for single in (str(three[0]), three[0]):  # a str was read letter by letter: "no study folder 'b'"
        with pytest.raises(ConfigError, match=r"compare: studies: a list of two or more .*single folder '.*a'"):
            compare_studies(single)
    (tmp_path / "empty").mkdir()
    with pytest.raises(ConfigError, match="compare: '.*empty' holds no study results"):
        compare_studies([three[0], tmp_path / "empty"])
    (tmp_path / "empty" / "config.json").write_text("{}")  # a study whose learning has not run
    with pytest.raises(ConfigError, match="'.*empty' has no reliability result"):
        compare_studies([three[0], tmp_path / "empty"])
    with pytest.raises(ConfigError, match="no study folder"):
        compare_studies([three[0], tmp_path / "missing"])
    with pytest.raises(ConfigError, match="target"):
        compare_studies(three, target=1.5)
    with pytest.raises(ConfigError, match="labels"):
        compare_studies(three, labels=["a", "a", "b"])


def test_the_command_prints_the_table_and_writes_with_out(three, tmp_path, capsys):
    assert main_entry(["compare", *map(str, three[:2]), "--label", "U", "--label", "P",
                       "--out", str(tmp_path / "cmp")]) == 0
    out = capsys.readouterr()
    assert "| P | 200,000 | 180,000 \u2013 220,000 | 2.000 | longer |" in out.out
    assert "| wear.geometry_mode | uniform | profile |" in out.out
    assert (tmp_path / "cmp" / "comparison.json").is_file() and "comparison.json" in out.err
    assert main_entry(["compare", str(three[0])]) == 2
    assert "two or more" in capsys.readouterr().err


def test_a_warning_of_the_comparison_is_said_as_a_compare_line(three, capsys):
    """A target beyond what the studies' populations resolve printed Python's UserWarning with a source path and line
    (a user's audit); it is a 'compare: warning:' line, once."""
    assert main_entry(["compare", *map(str, three[:2]), "--target", "0.999999"]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    start = "compare: warning: life at R = 0.999999: the 1,000 Monte Carlo"
    assert lines and all(line.startswith(start) for line in lines), err
    assert len(lines) == len(set(lines)) and "UserWarning" not in err and ".py:" not in err


def test_a_validated_study_shows_how_many_levels_agree(three):
    r = np.linspace(1.0, 0.6, 5)
    # level 3 off by 0.015 (> 0.01 + 0: the intervals miss), level 4 by 0.012 with an error of 0.005 (the intervals
    # overlap, 0.012 < 0.015, but the 95 % test's sqrt(0.01^2 + 0.005^2) = 0.0112 is smaller)
    ValidationResult(cycles=np.linspace(0, 4e5, 5), reliability_mc=r, ci_low=r - 0.01, ci_high=r + 0.01,
                     reliability_surrogate=r + [0, 0, 0.015, 0.012, 0], surrogate_error=[0, 0, 0, 0.005, 0],
                     n_samples=100, model_calls=100, wall_seconds=1.0,
                     agreement=[True, True, False, True, True]).save(three[1], figures=False)
    comp = compare_studies(three[:2])
    assert [(s["validation_levels_agreeing"], s["validation_levels"]) for s in comp.studies] == [(None, None), (4, 5)]
    # and how finely its samples see R: the widest 95 % half-width of the direct estimate (0.01 here)
    assert "| 4 of 5 levels agree (3 by the 95 % test; 100 samples resolve R to \u00b10.01) |" in comp.markdown()


def _with_variables(folder, variables):
    """Add the settings of random variables [(name, std)] to the study's config.json, in that order."""
    data = json.loads((folder / "config.json").read_text())
    for i, (name, std) in enumerate(variables):
        data["settings"] += [{"name": f"uncertainty.variables[{i}].name", "value": name, "unit": None},
                             {"name": f"uncertainty.variables[{i}].std", "value": std, "unit": "HB"}]
    (folder / "config.json").write_text(json.dumps(data))
    return folder


def test_settings_name_a_variable_by_its_name_and_match_by_it(tmp_path):
    """The table said `uncertainty.variables[3].std (HB)`; two studies that list their variables in another order
    compared them by position."""
    a = _with_variables(_study(tmp_path / "a", "a", 1e6), [("HB_b", 10.0), ("HB_j", 20.0)])
    b = _with_variables(_study(tmp_path / "b", "b", 1e6), [("HB_j", 20.0), ("HB_b", 12.0)])
    comp = compare_studies([a, b])
    assert [(d["name"], d["values"]) for d in comp.differences] == [("uncertainty.variables[HB_b].std", [10.0, 12.0])]
    assert comp.setting_rows() == [("uncertainty.variables[HB_b].std (HB)", "10", "12")]


def test_a_comparison_shows_its_table_in_a_shell_and_a_notebook(three):
    comp = compare_studies(three[:2])
    text = repr(comp)
    assert text.startswith("StudyComparison of 2 studies") and comp.markdown() in text
    assert "<list of" not in text
    cells = _Cells()
    cells.feed(comp._repr_html_())
    assert list(StudyComparison.COLUMNS) in cells.rows and all(list(row) in cells.rows for row in comp.rows())
    assert ["wear.geometry_mode", "uniform", "profile"] in cells.rows


def test_an_unconverged_study_says_so_in_the_table(three):
    """The frame had `converged` but comparison.md and its page did not: a study whose learning stopped on its
    budget looked as settled as the others."""
    rel = json.loads((three[1] / "reliability.json").read_text())
    rel["converged"] = False
    (three[1] / "reliability.json").write_text(json.dumps(rel))
    comp = compare_studies(three[:2])
    calls = StudyComparison.COLUMNS.index("model calls")
    assert [row[calls] for row in comp.rows()] == ["40", "40 (not converged)"]
    assert "| 40 (not converged) |" in comp.markdown()


def _on_curve(folder, reliability):
    """The study in ``folder`` with its R(N) curve replaced by ``reliability`` at 21 levels from 800,000 to 1,200,000
    cycles (its band stays +-0.01)."""
    rel = json.loads((folder / "reliability.json").read_text())
    cycles = np.linspace(8e5, 1.2e6, 21)
    r = reliability(cycles)
    rel["curve"].update(cycles=cycles.tolist(), reliability=r.tolist(), pf=(1.0 - r).tolist())
    rel.pop("life_curve", None)
    (folder / "reliability.json").write_text(json.dumps(rel))
    return folder


def test_a_life_before_one_curve_is_shorter_than_a_life_inside_another(tmp_path):
    """A uniform-mode study whose R was already below the target at its curve's first level (800,000 cycles) beside
    a profile-mode life of 1,146,710 (1,141,693-1,152,113) read 'within the errors': both missing ends of the first
    interval counted as unbounded. Before the curve, its high end is at most the first level."""
    early = _on_curve(_study(tmp_path / "early", "pin", 1e6), lambda n: np.full(n.size, 0.5))
    later = _on_curve(_study(tmp_path / "later", "pin profile", 1e6, mode="profile"), lambda n: 1.0 - n / 1e7)
    comp = compare_studies([early, later])
    assert comp.studies[0]["status"] == "before_curve"
    assert (comp.studies[0]["life_cycles_low"], comp.studies[0]["life_cycles_high"]) == (None, None)
    assert comp.studies[1]["life_cycles"] == pytest.approx(1e6, rel=1e-9)  # 1 - N / 1e7 = 0.9, band 0.9-1.1 M
    assert comp.studies[1]["verdict"] == "longer"
    assert compare_studies([later, early]).studies[1]["verdict"] == "shorter"
    # beyond its curve (R above the target to 1.2 M), a life is at least the last level: longer than 0.9-1.1 M
    beyond = _on_curve(_study(tmp_path / "beyond", "pin beyond", 1e6), lambda n: np.full(n.size, 0.95))
    assert compare_studies([later, beyond]).studies[1]["verdict"] == "longer"
    # from Python, a life of None says on which side it is (a notebook had to work it out from the curve)
    for folder, place in ((early, "before_curve"), (later, "in_curve"), (beyond, "beyond_curve")):
        rel = jointwear.load_results(folder).reliability
        assert rel.life_place(0.9) == place and (rel.life(0.9) is None) == (place != "in_curve")
    # and R at any cycle count on the curve, with its band (exact on a straight line): 1 - 1e6 / 1e7 = 0.9 +- 0.01
    rel = jointwear.load_results(later).reliability
    assert rel.reliability_at(1e6) == pytest.approx((0.9, 0.01), rel=1e-12)
    with pytest.raises(ConfigError, match="reliability_at: cycles: a cycle count on the curve"):
        rel.reliability_at(5e7)


def test_the_nominal_wear_names_each_joint_with_several(three):
    # two joints: the column gave the first joint's depth, unnamed
    comp = compare_studies(three[:2])
    comp.studies[0].update(max_wear_mm=0.02524, wear_cycles=450_000, max_wear_mm_by_joint={"A": 0.02524})
    comp.studies[1].update(max_wear_mm=0.008318, wear_cycles=450_000,
                           max_wear_mm_by_joint={"A": 0.008318, "E": 0.001954})
    wear = [row[comp.COLUMNS.index("max wear (mm)")] for row in comp.rows()]
    assert wear == ["0.02524 at 450,000", "0.008318 (A), 0.001954 (E) at 450,000"]
    # comparison.csv holds each study's depths by joint as JSON (it held a Python dict's repr, which a script
    # reading the CSV could only eval)
    column = comp.tables()["comparison"]["max_wear_mm_by_joint"]
    assert [json.loads(c) for c in column] == [{"A": 0.02524}, {"A": 0.008318, "E": 0.001954}]


def test_a_setting_shown_in_other_units_by_each_study_is_compared_in_one(three):
    # config.json shows a modulus in the unit that suits its magnitude: 3 GPa in one study, 700 MPa in another; the
    # table put both under the first's unit ('3 | 700 (GPa)') and read 1 GPa against 1000 MPa as a difference
    def modulus(folder, value, unit):
        data = json.loads((folder / "config.json").read_text())
        data["settings"].append({"name": "clearance_joints[0].bearing_material.youngs_modulus", "value": value,
                                 "unit": unit})
        (folder / "config.json").write_text(json.dumps(data))

    modulus(three[0], 3.0, "GPa")
    modulus(three[1], 700.0, "MPa")
    modulus(three[2], 3000.0, "MPa")
    comp = compare_studies(three)
    (row,) = [d for d in comp.differences if d["name"].endswith("youngs_modulus")]
    assert row["unit"] == "GPa" and row["values"] == pytest.approx([3.0, 0.7, 3.0])
    same = compare_studies([three[0], three[2]])
    assert not [d for d in same.differences if d["name"].endswith("youngs_modulus")]


def test_names_reach_comparison_md_escaped(tmp_path):
    import re

    evil = "pin<img src=x onerror=alert(1)>&\x1b[31mRED\x1b]0;PWNED\x07|x\\"
    a = _study(tmp_path / "a", evil, 1e6)
    b = _study(tmp_path / "b", "pin|b", 2e6, mode="profile")
    comp = compare_studies([a, b])
    comp.save(tmp_path / "out", figures=False)
    text = (tmp_path / "out" / "comparison.md").read_text(encoding="utf-8")
    assert not any(ord(c) < 32 and c != "\n" or 0x7f <= ord(c) <= 0x9f for c in text)
    assert "<img" not in text and "pin&lt;img src=x onerror=alert(1)&gt;&amp;[31mRED]0;PWNED\\|x\\\\ |" in text
    assert "| setting | pin&lt;img" in text and "| pin\\|b |" in text
    # every row of the studies' table has as many cells as the header: no pipe in a name splits one
    rows = [line for line in text.splitlines() if line.startswith("| ")]
    cells = {len(re.split(r"(?<!\\)\|", line)) for line in rows[:3]}
    assert len(cells) == 1, rows[:3]


@pytest.mark.skipif(sys.platform == "win32", reason="symlinks need privileges on Windows")
def test_a_symlink_planted_at_comparison_md_is_never_written_through(three, tmp_path):
    # comparison.md goes through the same atomic writer as the other results (study.io.write_text_atomic)
    outside = tmp_path / "outside.txt"
    outside.write_text("keep", encoding="utf-8")
    out = tmp_path / "cmp"
    out.mkdir()
    (out / "comparison.md").symlink_to(outside)
    compare_studies(three).save(out, figures=False)
    assert outside.read_text(encoding="utf-8") == "keep"
    assert not (out / "comparison.md").is_symlink() and "Life at R" in (out / "comparison.md").read_text()


def test_a_table_of_numbers_is_shown_rounded_in_a_settings_row():
    """A comparison row read {'E': 0.015000000000000001} (an allowance converted to mm and back)."""
    from jointwear.study.comparison import _shown

    assert _shown({"E": 0.015000000000000001, "A": None}) == "{'E': 0.015, 'A': \u2014}"
    assert _shown([0.1 + 0.2, 1]) == "[0.3, 1]"


def test_a_folder_without_its_settings_is_compared_by_its_life_only(three):
    """A result saved on its own (and every superseded/ folder before it kept a copy of config.json) records no
    settings: every setting was listed as differing, shown as a dash, and the one real difference was lost."""
    (three[2] / "config.json").unlink()
    comp = compare_studies(three)
    assert [d["name"] for d in comp.differences] == ["wear.geometry_mode"]  # a against b only
    assert [s["settings_recorded"] for s in comp.studies] == [True, True, False]
    assert f"{comp.labels[2]} records no settings (no config.json in the folder" in comp.markdown()
    assert compare_studies(three[:2]).unrecorded_note() == ""


def test_results_moved_aside_keep_the_settings_they_ran_with(three):
    from jointwear.study.superseded import move_aside

    recorded = (three[0] / "config.json").read_text()
    dest = move_aside(three[0], ["reliability"])
    assert (dest / "config.json").read_text() == recorded and (three[0] / "config.json").is_file()
    assert compare_studies([three[1], dest]).unrecorded_note() == ""


def test_a_uniform_study_outside_its_range_beside_a_profile_one_says_which_to_trust(three, tmp_path):
    """The wear stage says 'this is the answer to trust' of profile mode where uniform mode is outside its range; the
    comparison of the two showed only '(outside its range)' in a cell, and a designer read the ratio alone."""
    comp = compare_studies(three)
    assert comp.wear_mode_note() == ""  # no wear stage: uniform mode's range not judged
    comp.studies[0]["uniform_out_of_range"] = True
    note = comp.wear_mode_note()
    assert note == ("Uniform mode is outside its range in pin (the worn surface conforms to the journal, "
                    "docs/wear.md): of these studies, pin profile, in profile mode, is the answer to trust.")
    assert note in comp.markdown()
    comp.save(tmp_path / "cmp", figures=False)
    assert note.replace("'", "&#x27;") in (tmp_path / "cmp" / "comparison.html").read_text(encoding="utf-8")
    comp.studies[1]["geometry_mode"] = "uniform"  # nothing in profile mode to trust instead
    assert comp.wear_mode_note() == ""
