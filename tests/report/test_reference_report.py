"""The report is about the user's study: a comparison, reference points and bands only when the config
declares a [reference] (the six-bar has none; the flapping-wing preset cites Jin et al. 2025)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import numpy as np
import pytest
from report_fixtures import make_fixture_dir

from jointwear import load_results
from jointwear.config import load_config
from jointwear.report import build_report
from jointwear.report import figures as F
from jointwear.report.compare import comparison_markdown, main
from jointwear.report.reference_checks import FAIL, INFO, NA, PASS, reference_checks

pytestmark = pytest.mark.usefixtures("figures_made_not_rendered")  # conftest.py: these tests read text
STAGES = ("simulate", "wear", "reliability", "sensitivity")


def _text(page: str) -> str:
    """The page without its embedded PNGs (base64 text can spell any short word by chance)."""
    return re.sub(r'src="data:image/png;base64,[^"]*"', 'src=""', page)


class _Spy:
    """Records the keyword arguments of the figure functions the report calls."""

    def __init__(self, monkeypatch):
        self.calls: dict[str, dict] = {}
        for name in ("reliability_curve_figure", "wear_history_figure", "wear_histograms_figure"):
            original = getattr(F, name)

            def spy(*args, _name=name, _original=original, **kw):
                self.calls[_name] = kw
                return _original(*args, **kw)

            monkeypatch.setattr(F, name, spy)


def _study(tmp_path: Path, nominal: Path, preset: str) -> Path:
    """Stage outputs with the settings JSON the `run` command writes for ``preset``."""
    return make_fixture_dir(tmp_path / preset, nominal, preset=preset)


def test_six_bar_report_has_no_reference(tmp_path, monkeypatch, nominal):
    d = _study(tmp_path, nominal, "watt_six_bar_two_clearances")
    settings = json.loads((d / "config.json").read_text())
    assert settings["reference"] is None
    assert settings["allowance_mm"] == pytest.approx(0.02)  # the preset's [reliability] allowance_mm
    spy = _Spy(monkeypatch)
    page = _text(build_report(d).read_text(encoding="utf-8"))
    assert 'id="comparison"' not in page
    assert not re.search(r"\bJin\b", page) and "paper" not in page.lower() and "Drones" not in page
    assert "declares no reference results" in page
    assert spy.calls["reliability_curve_figure"]["reference"] is None
    assert spy.calls["reliability_curve_figure"]["reference_life"] is None
    history = spy.calls["wear_history_figure"]
    assert history["reference_mean"] is None and history["reference_nominal"] is None
    assert history["limit_mm"] == pytest.approx(0.02)  # the configured allowance, not 0.01 D = 0.06 mm
    assert spy.calls["wear_histograms_figure"]["reference_means"] is None
    assert reference_checks(load_results(d)) == []
    assert main([str(d)]) == 1  # nothing to compare
    with pytest.raises(LookupError):
        comparison_markdown(d)


def test_flapping_wing_report_compares_with_its_reference(tmp_path, monkeypatch, nominal):
    d = _study(tmp_path, nominal, "jin2025_flapping_wing")
    ref = load_config("jin2025_flapping_wing").reference
    spy = _Spy(monkeypatch)
    page = build_report(d).read_text(encoding="utf-8")
    assert 'id="comparison"' in page and "Comparison with Jin et al. 2025" in page
    rn = spy.calls["reliability_curve_figure"]
    assert rn["reference"] == {v.cycles: v.value for v in ref.values if v.quantity == "reliability"}
    assert rn["reference_life"] == 371_640 and rn["reference_label"] == "Jin et al. 2025"
    assert spy.calls["wear_history_figure"]["reference_nominal"] == (400_000, pytest.approx(0.0249))
    assert spy.calls["wear_histograms_figure"]["reference_means"] == {
        360_000: pytest.approx(0.0256), 400_000: pytest.approx(0.0285), 440_000: pytest.approx(0.0313)}
    assert spy.calls["wear_history_figure"]["limit_mm"] == pytest.approx(0.03)
    # every row names where its number comes from
    for c in reference_checks(load_results(d)):
        assert c.source and html.escape(c.source) in page


# Statuses of the synthetic flapping-wing fixture under the report's former hard-coded PAPER dict and
# paper_checks (recorded from that code on the same fixture): the preset's [reference] must give the same, except
# R(420k), which the preset now bands as every other level of R(N) (it had no band, and the one level that misses it).
FORMER_STATUSES = [
    ("nominal max bearing wear after 400,000 cycles", PASS), ("angle of the max wear", PASS),
    ("second wear peak, depth", INFO), ("second wear peak, angle", PASS),
    ("mean of the max wear at 360,000 cycles", PASS), ("mean of the max wear at 400,000 cycles", PASS),
    ("mean of the max wear at 440,000 cycles", PASS), ("reliability R(N) at 360,000 cycles", PASS),
    ("reliability R(N) at 400,000 cycles", PASS), ("reliability R(N) at 420,000 cycles", PASS),
    ("reliability R(N) at 520,000 cycles", PASS), ("life at R = 0.9", PASS),
    ("life at R = 0.9, hours at 480 rpm", INFO), ("true-model calls (whole curve)", PASS),
    ("sensitivity ranking, tolerances", PASS), ("sensitivity ranking, journal material", PASS),
    ("sensitivity ranking, bearing material", PASS),
]


def test_flapping_wing_checks_as_before(study_dir):
    checks = reference_checks(load_results(study_dir))
    assert [(c.quantity, c.status) for c in checks] == FORMER_STATUSES
    assert {c.band for c in checks} >= {"0.021-0.029 mm", "within 20 deg", "within 15 %", "\u00b10.15 absolute",
                                        "reported (no band)", "\u2264 80", "same order as the reference"}


def test_a_band_that_says_nothing_is_no_band(study_dir, tmp_path):
    """A tampered config.json whose band has an unknown kind and no limits crashed the report (and would have passed
    every number): it is reported as having no band."""
    import shutil

    d = tmp_path / "tampered"
    shutil.copytree(study_dir, d)
    cfg = json.loads((d / "config.json").read_text(encoding="utf-8"))
    cfg["reference"]["values"][1]["band"]["kind"] = "Absolute"
    (d / "config.json").write_text(json.dumps(cfg), encoding="utf-8")
    checks = {c.quantity: c for c in reference_checks(load_results(d))}
    row = checks["angle of the max wear"]
    assert (row.status, row.band) == (INFO, "reported (no band)")
    assert "angle of the max wear" in build_report(d).read_text(encoding="utf-8")


def test_a_pass_within_an_absolute_band_only_says_so(study_dir):
    """R(520k) = 0.152 against the paper's 0.006 read 'pass' (+/- 0.15 absolute) with nothing beside it."""
    results = load_results(study_dir)
    rel = results.reliability
    rel.reliability = np.where(np.asarray(rel.cycles) == 520_000, 0.152, rel.reliability)  # this study's curve
    checks = {c.quantity: c for c in reference_checks(results)}
    far = checks["reliability R(N) at 520,000 cycles"]
    assert far.status == PASS and "times the reference's R: within the absolute band only" in far.note
    assert "within the absolute band only" not in checks["reliability R(N) at 400,000 cycles"].note  # 0.804 / 0.739
    rel.reliability = np.where(np.asarray(rel.cycles) == 520_000, 0.167, rel.reliability)  # outside the band
    far = {c.quantity: c for c in reference_checks(results)}["reliability R(N) at 520,000 cycles"]
    assert far.status == FAIL and "27.8 times the reference's R" in far.note  # a fail is not 'within the band'
    assert "within the absolute band only" not in far.note


def test_a_reference_between_levels_is_read_on_the_curve_between_them(study_dir):
    """R at 420,000 cycles, between two levels of a curve, was read on a straight line between them (0.704) where the
    study's own curve (life_curve, the surrogate's R at 256 or more points) read 0.7068."""
    from jointwear.study.limit_state import curve_cycles

    results = load_results(study_dir)
    rel = results.reliability
    cycles = curve_cycles(np.asarray(rel.cycles, dtype=float), 4)  # the levels and 3 points between each two
    r = np.interp(cycles, np.asarray(rel.cycles, dtype=float), rel.reliability)
    inner = float(cycles[1 + 4])  # between the second and third levels
    bent = np.where(cycles == inner, r - 0.05, r)  # a curve that bends away from the straight line there
    rel.life_curve = {"cycles": cycles.tolist(), "reliability": bent.tolist(), "half_width_95": [0.0] * cycles.size}
    from jointwear.report import reference_checks as rc

    def ours_at(n):
        results.config["reference"]["values"] = [{"quantity": "reliability", "cycles": n, "value": 0.5,
                                                  "source": "test", "band": {"absolute": 1.0, "justification": "t"}}]
        return next(c for c in rc.reference_checks(results) if c.quantity.startswith("reliability R(N)")).ours

    assert ours_at(inner) == pytest.approx(float(bent[list(cycles).index(inner)]), abs=1e-12)
    level = float(rel.cycles[1])
    assert ours_at(level) == pytest.approx(float(rel.reliability[1]), abs=1e-12)  # a level reads its own R


def test_bands_decide_the_status(tmp_path, nominal):
    """Each kind of band, at and beyond its edge (the edges are the preset's: 0.021-0.029 mm, 20 deg, 15 %)."""
    d = make_fixture_dir(tmp_path, nominal, which=("wear", "reliability", "config"))
    results = load_results(d)

    def status(quantity_prefix: str, **wear_or_rel) -> str:
        for key, value in wear_or_rel.items():
            stage, field = key.split("__")
            setattr(getattr(results, stage), field, value)
        return next(c.status for c in reference_checks(results) if c.quantity.startswith(quantity_prefix))

    assert status("nominal max", wear__max_wear_mm=0.029) == PASS
    assert status("nominal max", wear__max_wear_mm=0.0291) == FAIL
    assert status("angle of the max wear", wear__max_wear_angle_deg=90.0) == PASS  # 20 deg exactly
    assert status("angle of the max wear", wear__max_wear_angle_deg=89.0) == FAIL
    assert status("angle of the max wear", wear__max_wear_angle_deg=-250.0) == PASS  # = 110 deg round the circle
    assert status("true-model calls", reliability__model_calls=80) == PASS
    assert status("true-model calls", reliability__model_calls=81) == FAIL
    results.reliability = None
    assert status("true-model calls") == NA


def test_the_tally_counts_rankings_apart_and_names_what_has_no_data(study_dir):
    """The card read 'checks 11 / 12; 1 outside the band; 4 more without a band': its passes held rankings, which can
    match but never fail, and rows without data went unsaid. Numbers and rankings are now counted apart."""
    from jointwear.report.read import StudyOutputs
    from jointwear.report.reference_checks import checks_summary, tally
    from jointwear.report.result_sections import summary_cards

    results = load_results(study_dir)
    results.reliability.reliability = np.where(np.asarray(results.reliability.cycles) == 520_000, 0.167,
                                               results.reliability.reliability)  # one number outside its band
    checks = reference_checks(results)
    t = tally(checks)
    assert (t.passed, t.failed, t.unbanded, t.no_data, t.rankings, t.rankings_same) == (11, 1, 2, 0, 3, 3)
    assert checks_summary(checks) == ("11 of 12 numbers within their band; 1 outside the band; 2 reported without "
                                      "a band; rankings: 3 of 3 in the reference's order")
    results.sensitivity = None  # the rankings have no data: said, not counted as rankings
    t = tally(reference_checks(results))
    assert (t.passed, t.judged, t.no_data, t.rankings) == (11, 12, 3, 0)
    assert "3 without data" in t.details() and "rankings" not in t.details()
    card = summary_cards(StudyOutputs(out_dir=study_dir, results=results), reference_checks(results),
                         results.config["reference"])
    assert "11 / 12" in card and "3 without data" in card


def test_reference_declared_in_a_users_config(tmp_path, nominal):
    """A user's own [reference]: its label heads the comparison, its values and bands decide."""
    from jointwear.reference import ReferenceData

    ref = ReferenceData.model_validate({
        "citation": "A. Author, Some Journal 2030, Table 3", "label": "Author 2030",
        "values": [{"quantity": "reliability", "cycles": 400_000, "value": 0.5, "source": "Table 3",
                    "band": {"relative": 0.1, "justification": "test"}},
                   {"quantity": "nominal_max_wear", "cycles": 400_000, "value_um": 25.0, "source": "Fig. 2"}]})
    d = make_fixture_dir(tmp_path, nominal, which=STAGES)
    cfg = json.loads(json.dumps({"preset": None, "reference": ref.report_dict()}))
    (d / "config.json").write_text(json.dumps(cfg))
    checks = reference_checks(load_results(d))
    assert [c.quantity for c in checks] == ["reliability R(N) at 400,000 cycles",
                                            "nominal max bearing wear after 400,000 cycles"]
    assert checks[0].status == FAIL  # the fixture's R(400k) is 0.742, 48 % above 0.5
    assert checks[1].reference == pytest.approx(0.025) and checks[1].status == INFO  # um -> mm, no band
    md = comparison_markdown(d)
    assert md.startswith("| quantity | Author 2030 | jointwear |") and "| Table 3 |" in md
    page = _text(build_report(d).read_text(encoding="utf-8"))
    assert "Comparison with Author 2030" in page and "Jin" not in page


def test_an_angle_has_no_relative_difference(study_dir):
    """'+17.0 %' for 128.7 deg against 110 deg: an angle's origin is a convention; its note gives the degrees."""
    checks = {c.quantity: c for c in reference_checks(load_results(study_dir))}
    angle = checks["angle of the max wear"]
    assert angle.rel_diff is None and "deg from the reference's" in angle.note
    assert checks["nominal max bearing wear after 400,000 cycles"].rel_diff is not None


def test_a_ranking_that_differs_only_within_the_surrogates_error_is_told_so(study_dir):
    """The bearing group read '(differs)' and counted as out of the reference's order where it differed only by two
    neighbours the study's surrogate error does not separate. Swapping the two least influential bearing variables:
    told as the same order within the surrogate's error when the pair is unresolved, as another order when it is not."""
    from jointwear.report.reference_checks import ranking_rows, reference_checks, tally

    results = load_results(study_dir)
    sens = results.sensitivity
    bearing = [n for n, _label in ranking_rows(sens)["bearing_material"]]
    last, before = bearing[-1], bearing[-2]
    by_name = {v["name"]: v for v in sens.variables}
    a, b = by_name[before], by_name[last]
    for key in ("reliability_low", "reliability_high"):
        a[key], b[key] = b[key], a[key]  # the two swap places in the study's ranking
    assert [n for n, _label in ranking_rows(sens)["bearing_material"]][-2:] == [last, before]

    def bearing_check():
        (check,) = [c for c in reference_checks(results) if c.quantity == "sensitivity ranking, bearing material"]
        return check

    resolved = bearing_check()
    assert resolved.status != PASS and not resolved.within_error and "(same most influential)" in resolved.note
    sens.unresolved_pairs = [*sens.unresolved_pairs, {"group": "bearing_material", "first": last, "second": before,
                                                      "swing_difference": 0.0, "error_sum": 0.01}]
    tied = bearing_check()
    assert tied.status != PASS and tied.within_error, tied
    assert "(the same order within the surrogate's error)" in tied.note and "most influential" not in tied.note
    t = tally(reference_checks(results))
    assert (t.rankings, t.rankings_same, t.rankings_within_error) == (3, 2, 1)
    assert t.details().endswith("rankings: 2 of 3 in the reference's order, 1 more within the surrogate's error")
