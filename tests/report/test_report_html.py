"""The HTML report: self-contained, tolerant of missing and malformed inputs, escaped, and compared with the
study's cited reference only when the study declares one."""

from __future__ import annotations

import html
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from report_fixtures import make_fixture_dir

from jointwear import load_results
from jointwear.report import build_report
from jointwear.report.markup import format_number
from jointwear.report.reference_checks import FAIL, NA, PASS, reference_checks
from jointwear.report.study_sections import in_random_inputs
from jointwear.study.results import ReliabilityCurve, SensitivityResult, WearSummary

pytestmark = pytest.mark.usefixtures("figures_made_not_rendered")  # conftest.py: these tests read text
SECTIONS = ("summary", "comparison", "study", "dynamics", "wear", "reliability", "sensitivity", "files")


def _imgs(page: str) -> list[str]:
    return re.findall(r"<img\s[^>]*src=\"([^\"]*)\"", page)


def test_full_report_is_self_contained(full_report: Path):
    page = full_report.read_text(encoding="utf-8")
    assert full_report.name == "report.html"
    for sid in SECTIONS:
        assert f'id="{sid}"' in page, sid
    srcs = _imgs(page)
    # mechanism, orbit, force, polar, history, Fig. 17, R(N), convergence, histograms, 3 tornados, Sobol'
    assert len(srcs) == 13
    assert all(s.startswith("data:image/png;base64,") for s in srcs)
    assert min(map(len, srcs)) > 5000  # rendered: figures_made_not_rendered does not reach a module fixture
    assert "<script" not in page.lower()
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page, re.I)
    assert "url(" not in page and "@import" not in page and "<link" not in page.lower()
    assert 'class="missing"' not in page  # full fixture: nothing missing


def test_the_data_figures_tell_their_numbers_to_a_reader_who_cannot_see_them(full_report: Path, study_dir: Path):
    """Every image had its caption as its text alternative, so a screen reader read the caption twice and never the
    numbers; the data figures' alternatives now give them, from the results the figures draw."""
    page = html.unescape(full_report.read_text(encoding="utf-8"))
    figures = re.findall(r'<img\s[^>]*alt="([^"]*)">\s*<figcaption>(.*?)</figcaption>', page, re.S)
    assert len(figures) == 13
    alts = [alt for alt, caption in figures if alt != caption]
    res = load_results(study_dir)
    rel, wear = res.reliability, res.wear
    life = rel.life()
    r, c = rel.reliability, rel.cycles
    assert (f"R goes from {r[0]:.3f} at {c[0]:,.0f} cycles to {r[-1]:.3f} at {c[-1]:,.0f}; it crosses the target "
            f"{rel.target:g} at {life:,.0f} cycles.") in alts[2]
    depth = np.asarray(wear.profile["depth_mm"])
    arc = 360.0 * np.count_nonzero(depth >= 0.5 * depth.max()) / depth.size
    assert f"deepest {depth.max():.4g} mm" in alts[0] and f"; {arc:.0f} deg of the circle worn to half" in alts[0]
    assert f"reaches {wear.history['max_wear_mm'][-1]:.4g} mm at {wear.history['cycles'][-1]:,.0f}" in alts[1]
    tornados = [a for a in alts if a.startswith("Bar chart of R at") and "the largest change of R is" in a]
    assert len(tornados) == 3
    assert len(alts) == 6  # polar, history, R(N) and three tornados; the other figures keep their caption


def test_the_tables_of_numbers_are_printed_though_collapsed_on_screen(full_report: Path):
    # Chromium 156 printing the default study's report: 14 pages without the print rule, and the R(N) and
    # sensitivity tables absent from the PDF's text; 15 pages with it, both tables present
    page = full_report.read_text(encoding="utf-8")
    css = re.search(r"@media print\{(.*?)\}\s*</style>", page, re.S).group(1)
    assert "details.numbers::details-content{content-visibility:visible" in css
    numbers = re.findall(r'<details class="numbers"><summary>([^<]*)</summary>', page)
    assert numbers == ["R(N) as numbers", "Sensitivity as numbers"]
    assert re.search(r"<details( open)?><summary>All \d+ settings", page)  # the long settings table stays out


def test_every_setting_and_paper_open_flag(full_report: Path, study_dir: Path):
    page = full_report.read_text(encoding="utf-8")
    cfg = json.loads((study_dir / "config.json").read_text())
    # a random input's fields that its Random inputs row shows are not listed again (tests/report/test_settings_units)
    shown_above = in_random_inputs(cfg["settings"], cfg["random_variables"])
    for s in cfg["settings"]:
        assert s["name"] in page or s["name"] in shown_above
    n_open = sum(s["paper_open"] for s in cfg["settings"])
    assert page.count('<tr class="open">') == 2 * n_open  # open table + full list


def test_text_is_escaped(full_report: Path):
    page = full_report.read_text(encoding="utf-8")
    assert "&lt;script&gt;alert(&#x27;escaped&#x27;)&lt;/script&gt;" in page


def test_comparison_with_paper_on_fixture(study_dir: Path):
    checks = reference_checks(load_results(study_dir))
    banded = [c for c in checks if c.status in (PASS, FAIL)]
    assert len(banded) >= 12
    assert all(c.status == PASS for c in banded), [(c.quantity, c.ours) for c in banded if c.status != PASS]
    byname = {c.quantity: c for c in checks}
    assert byname["life at R = 0.9"].ours == pytest.approx(381_000, rel=0.01)
    assert byname["reliability R(N) at 400,000 cycles"].reference == 0.739
    assert byname["sensitivity ranking, tolerances"].status == PASS


def test_a_result_moved_aside_is_told_as_such_not_as_never_run(tmp_path: Path, nominal: Path):
    """A stage whose result a settings change moved to superseded/ read "has not been run"; the section now names
    where the last result went (the latest of several moves)."""
    d = make_fixture_dir(tmp_path, nominal, which=("wear", "reliability", "sensitivity", "config"))
    for stamp in ("20261129T080000Z", "20261129T090000Z"):
        (d / "superseded" / stamp).mkdir(parents=True)
        shutil.copy(d / "sensitivity.json", d / "superseded" / stamp / "sensitivity.json")
    (d / "sensitivity.json").unlink()
    page = html.unescape(build_report(d).read_text(encoding="utf-8"))
    assert ("the sensitivity study has not been run with its current settings; its last result, computed with other "
            "settings, was moved to superseded/20261129T090000Z/ (jointwear sensitivity runs it again)") in page
    assert "No reliability.json" not in page and "the reliability study has not been run" not in page


def test_comparison_flags_out_of_band(tmp_path: Path, nominal: Path):
    d = make_fixture_dir(tmp_path, nominal, which=("wear", "reliability", "config"))
    wear = WearSummary.load(d)
    wear.max_wear_mm, wear.max_wear_angle_deg = 0.05, 200.0
    wear.write(d)
    rel = ReliabilityCurve.load(d)
    rel.reliability = np.ones_like(rel.reliability)
    rel.life_table, rel.life_cycles = [], None
    rel.write(d)
    byname = {c.quantity: c for c in reference_checks(load_results(d))}
    assert byname["nominal max bearing wear after 400,000 cycles"].status == FAIL
    assert byname["angle of the max wear"].status == FAIL
    assert byname["reliability R(N) at 520,000 cycles"].status == FAIL
    assert byname["life at R = 0.9"].status == NA  # never reaches 0.9 on the curve
    page = build_report(d).read_text()
    assert "FAIL" in page and "No simulate.json" in page


def test_empty_folder_says_what_is_missing(tmp_path: Path):
    page = build_report(tmp_path).read_text()
    for what in ("No simulate.json", "No wear.json", "No reliability.json", "No sensitivity.json",
                 "No config.json"):
        assert what in page
    assert _imgs(page) == []


def test_malformed_and_odd_inputs_spoil_only_their_section(tmp_path: Path, nominal: Path):
    d = make_fixture_dir(tmp_path, nominal, which=("wear", "reliability", "sensitivity", "config"))
    (d / "simulate.json").write_text("{not json")
    rel = json.loads((d / "reliability.json").read_text())
    rel["curve"]["reliability"] = "oops"  # wrong type
    (d / "reliability.json").write_text(json.dumps(rel))
    (d / "sensitivity.json").write_text(json.dumps([1, 2, 3]))  # not an object
    page = build_report(d).read_text()
    for stage in ("simulate", "reliability", "sensitivity"):
        assert f"{stage}.json could not be read" in page, stage
    assert 'id="wear"' in page and len(_imgs(page)) >= 4


def test_optional_results_absent(tmp_path: Path, nominal: Path):
    d = make_fixture_dir(tmp_path, nominal, optional=False)
    for name in ("simulate.npz", "orbit_A.png", "force_A.png", "convergence.png", "wear_histograms.png"):
        (d / name).unlink(missing_ok=True)
    cfg = json.loads((d / "config.json").read_text())
    cfg.pop("mechanism")
    (d / "config.json").write_text(json.dumps(cfg))
    page = build_report(d).read_text()
    for what in ("Journal orbit: no series file (simulate.npz)", "Contact force: no series file",
                 "Convergence of Pf: not recorded", "Max wear histograms: none requested",
                 "Sobol&#x27; indices: not computed",
                 "Mechanism sketch: drawn for four-bar, slider-crank and general linkages"):
        assert what in page, what
    # no mean max wear: its checks say no data, the rest still compare
    checks = {c.quantity: c for c in reference_checks(load_results(d))}
    assert checks["mean of the max wear at 400,000 cycles"].status == NA
    assert checks["reliability R(N) at 400,000 cycles"].status == PASS


def test_series_from_the_stage_and_png_fallback(tmp_path: Path, nominal: Path):
    d = make_fixture_dir(tmp_path, nominal, which=("simulate", "wear"))
    page = build_report(d).read_text()
    assert "figure file orbit_A.png" not in page  # drawn from simulate.npz, the stage's file superseded
    (d / "simulate.npz").unlink()
    # a stage figure the report cannot draw itself, and a file that is not a PNG
    shutil.copy(Path(__file__).with_name("report_fixtures.py"), d / "not-a-figure.png")
    from jointwear.report.figures import sobol_figure
    from jointwear.report.style import savefig

    savefig(sobol_figure(["a", "b"], [0.2, 0.5], [0.3, 0.6]), d / "sobol_indices.png")
    page = build_report(d).read_text()
    assert "figure file orbit_A.png" in page  # no series: the stage's own figure fills the slot
    assert "figure file sobol_indices.png" not in page  # no sensitivity.json: Sobol' slot not drawn
    assert "sobol_indices.png" in page  # but the stage's own figure is embedded in the appendix
    assert "not-a-figure.png" not in page.split('id="files"')[0]  # not a PNG: never embedded


def test_output_path_and_missing_dir(tmp_path: Path, study_dir: Path):
    out = build_report(study_dir, output=tmp_path / "elsewhere" / "r.html")
    assert out.is_file() and out.parent.name == "elsewhere"
    with pytest.raises(FileNotFoundError):
        build_report(tmp_path / "does-not-exist")


def test_comparison_markdown(study_dir: Path):
    from jointwear.report.compare import comparison_markdown, main

    md = comparison_markdown(study_dir)
    assert md.startswith("| quantity | Jin et al. 2025 | jointwear |")
    assert "| life at R = 0.9 | 371,640 cycles |" in md
    assert md.count("**pass**") >= 12
    assert main(["/does/not/exist"]) == 2


def test_ranking_marks_neighbours_the_surrogate_does_not_separate(tmp_path: Path, nominal: Path):
    """sensitivity.json's unresolved_pairs: the ranking joins them with \u2248 and the comparison says so."""
    d = make_fixture_dir(tmp_path, nominal, which=("sensitivity", "config"))
    sens = SensitivityResult.load(d)
    # fixture bearing group: HB_b (swing 0.568) > k_b (0.168) > E_b > nu_b; declare E_b / nu_b unresolved
    sens.unresolved_pairs = [{"group": "bearing_material", "first": "E_b", "second": "nu_b",
                              "swing_difference": 0.014, "error_sum": 0.02}]
    sens.write(d)
    checks = {c.quantity: c for c in reference_checks(load_results(d))}
    note = checks["sensitivity ranking, bearing material"].note
    assert ("not resolved within the surrogate's error: bearing Young's modulus \u2248 bearing Poisson's ratio"
            in note)
    assert "not resolved" not in checks["sensitivity ranking, tolerances"].note
    page = build_report(d).read_text(encoding="utf-8")
    assert ("bearing Brinell hardness &gt; bearing wear coefficient &gt; bearing Young&#x27;s modulus \u2248 "
            "bearing Poisson&#x27;s ratio") in page


def test_report_shows_the_validation_from_its_typed_result(tmp_path, nominal):
    """A validation.json written by the stage's typed result appears as its own section with both figures."""
    from jointwear.study.results import ValidationResult

    d = make_fixture_dir(tmp_path / "v", nominal, which=("reliability",))
    ValidationResult(cycles=[360_000, 400_000], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                     ci_high=[0.96, 0.82], reliability_surrogate=[0.948, 0.812], surrogate_error=[0.005, 0.01],
                     n_samples=2000, model_calls=2000, wall_seconds=1.0, agreement=[True, False],
                     cross_validation={"log_life_true": [12.8, 12.9, 13.0], "log_life_loo": [12.81, 12.9, 12.98],
                                       "log_life_loo_sd": [0.01, 0.01, 0.01], "q2": 0.97, "n_points": 3}).save(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert 'id="validation"' in page and "1 of 2" in page and "0.970" in page
    assert "\u00b10.02" in page  # the widest half-width of the direct estimate, 0.82 - 0.8: what the check can see
    # the table holds the half-width the overlap test adds (no COV given: the error estimate alone) beside the estimate
    assert "its 95 % half-width (error estimate)" in page and "<td>0.01 (0.01)</td>" in page
    val = ValidationResult.load(d)
    val.surrogate_cov = np.array([0.0, 0.05])  # the Monte Carlo part: 1.96 x 0.05 x Pf 0.188 = 0.0184 at 400k
    val.save(d)
    assert f"<td>{format_number(1.96 * 0.05 * 0.188 + 0.01)} (0.01)</td>" in build_report(d).read_text(encoding="utf-8")
    assert page.count("data:image/png;base64") >= 2
    assert "could not be drawn" not in page  # a figure that fails falls back to the stage's PNG, silently
    assert ("from 2,000 samples: their 95 % intervals overlap at 1 of 2 levels; the largest difference in R is "
            "0.012, at 400,000 cycles.") in html.unescape(page)  # the figure's text alternative
    # the summary's caveats name the level that disagrees (the summary spoke only of the learning)
    assert ("<strong>The true model disagrees with the curve</strong></a>: at 1 of 2 levels (400,000 cycles: "
            "true model 0.800 [0.780, 0.820], surrogate 0.812 (its error estimate 0.010)") in page


def test_the_report_warns_about_a_poor_fit(tmp_path, nominal):
    """The life surrogate's Q^2 and scatter are shown; a poor fit (the two-fit six-bar's numbers) warns."""
    from jointwear.study.reliability_results import SurrogateFit

    d = make_fixture_dir(tmp_path / "r", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    rel.surrogate_fit = SurrogateFit(n_points=60, q2=0.002, rmse_log_life=0.33, noise_sd_log_life=0.18,
                                     process_sd_log_life=0.5, relative_nugget=0.1, nugget_at_bound=True)
    rel.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "The surrogate explains little" in page and "0.00" in page
    assert ReliabilityCurve.load(d).surrogate_fit == rel.surrogate_fit
    rel.surrogate_fit = SurrogateFit(n_points=60, q2=0.94, rmse_log_life=0.04, noise_sd_log_life=0.025,
                                     process_sd_log_life=0.45, relative_nugget=0.003, nugget_at_bound=False)
    rel.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "The surrogate explains little" not in page and "0.94" in page


def test_report_warns_when_uniform_mode_is_outside_its_range(tmp_path, nominal):
    d = make_fixture_dir(tmp_path / "w", nominal, which=("wear",))
    wear = WearSummary.load(d)
    wear.geometry_mode, wear.conformity, wear.uniform_mode_valid = "uniform", 2.4, False
    wear.write(d)
    assert "Uniform mode is outside its range" in build_report(d).read_text(encoding="utf-8")
    wear.conformity, wear.uniform_mode_valid = 0.4, True
    wear.write(d)
    assert "Uniform mode is outside its range" not in build_report(d).read_text(encoding="utf-8")


def test_second_peak_only_when_the_far_side_is_a_wear_zone(tmp_path, nominal):
    """The wear card names a second peak only where the far side (> 90 deg from the main peak) wears at least the
    peak-detection floor (peak_prominence x the max); a steady load's single zone leaves rounding there."""
    d = make_fixture_dir(tmp_path / "p", nominal, which=("wear",))
    wear = WearSummary.load(d)
    depth = np.asarray(wear.profile["depth_mm"], dtype=float)
    ang = np.asarray(wear.profile["angle_deg"], dtype=float)
    far = np.abs((ang - wear.max_wear_angle_deg + 180.0) % 360.0 - 180.0) > 90.0
    assert far.any() and depth[far].max() >= 0.05 * wear.max_wear_mm  # the wing's far zone: a real second peak
    page = build_report(d).read_text(encoding="utf-8")
    assert "a single wear zone" not in page
    wear.peaks = wear.peaks[:1]
    wear.profile["depth_mm"] = np.where(far, 1e-18, depth).tolist()
    wear.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "a single wear zone" in page and "1e-18 mm" not in page


def test_wear_card_shows_the_conformity_in_either_mode(tmp_path, nominal):
    """The indicator of docs/wear.md ("When uniform mode is fair") is on the wear card whatever the mode; the warning
    only when uniform mode is outside its range."""
    d = make_fixture_dir(tmp_path / "c", nominal, which=("wear",))
    wear = WearSummary.load(d)
    assert wear.conformity is not None and wear.conformity > 1.0  # the wing's 2 um clearance (docs/wear.md: ~100)
    shown = format_number(wear.conformity, 3)
    page = build_report(d).read_text(encoding="utf-8")
    assert f'<div class="card-value">{shown}</div>' in page and "Uniform mode is outside its range" in page
    wear.geometry_mode = "profile"
    wear.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    card = f'<div class="card-label">conformity</div><div class="card-value">{shown}</div>'
    assert card in page and "Uniform mode is outside its range" not in page


def test_wear_card_shows_the_nominal_life(tmp_path, nominal):
    """When the nominal history reaches the allowance, read off it as the wear stage prints it (limit_state.
    nominal_lives: exact for the history's own points, linear between them and past its end)."""
    from jointwear.study.limit_state import nominal_lives

    d = make_fixture_dir(tmp_path / "n", nominal, which=("wear",))
    wear = WearSummary.load(d)
    joint = wear.joints[0]
    life = nominal_lives([joint], {joint["name"]: joint["allowance_mm"]}, "bearing_max_depth")[joint["name"]]
    page = build_report(d).read_text(encoding="utf-8")
    card = f'<div class="card-label">nominal life</div><div class="card-value">{format_number(life)} cycles</div>'
    assert card in page
    # a history that reaches the allowance inside it: no extrapolation
    h = joint["history"]
    joint["allowance_mm"] = 0.5 * h["max_wear_mm"][-1]
    wear.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "; read off the history</div>" in page and "; extrapolated linearly past the history" not in page


def test_report_has_a_design_section_when_the_folder_has_a_design(tmp_path, nominal):
    import json


    d = make_fixture_dir(tmp_path / "d", nominal, which=("reliability",))
    point = {"choices": {"l2": "IT11", "fit": "IT8/IT7", "k_b": "coated"}, "cost": 4.0,
             "life_at_target_cycles": 482_188.0, "reliability_at_target_life": 0.961}
    (d / "design.json").write_text(json.dumps({
        "target_life_cycles": 452_920.0, "target_reliability": 0.9, "chosen": point, "pareto": [point],
        "verification": {"reliability_at_target_life": 0.958, "error": 0.0035, "model_calls": 80, "confirmed": True},
        "model_calls": 140, "wall_seconds": 223.0, "n_candidates": 243}))
    from jointwear.report import figures as F
    from jointwear.report.style import to_png_bytes

    (d / "design_pareto.png").write_bytes(to_png_bytes(F.reliability_curve_figure([1, 2], [0.9, 0.5])))
    page = build_report(d).read_text(encoding="utf-8")
    assert 'id="design"' in page and "IT8/IT7" in page and "coated" in page
    # the stage's own file of the front is not shown again among the figures no section shows (it was)
    assert "design_pareto.png" not in page and "Candidates left undecided" not in page
    data = json.loads((d / "design.json").read_text())
    data["refinement"] = {"iterations": 20, "model_calls": 40, "undecided_left": 1}
    (d / "design.json").write_text(json.dumps(data))
    page = build_report(d).read_text(encoding="utf-8")
    assert "Candidates left undecided" in page and "ran out with 1 candidate(s)" in page


def test_a_general_linkage_is_sketched_as_drawn(tmp_path):
    """A user's own linkage (examples/my_linkage.toml) gets its sketch from the drawing's global coordinates: the
    config.json summary carries every body's points in mm, and the report draws them instead of saying it cannot."""
    from jointwear.config import load_config
    from jointwear.study.settings_record import settings_dump

    root = Path(__file__).resolve().parents[2]
    toml = root / "examples" / "my_linkage.toml"
    dump = settings_dump(load_config(str(toml)), source=str(toml))  # as a study from a TOML file writes it
    mech = dump["mechanism"]
    assert mech["type"] == "general" and [b["name"] for b in mech["bodies"]] == ["crank", "coupler", "rocker"]
    assert mech["bodies"][1]["points_mm"]["B"] == pytest.approx([18.7805, 39.0244])  # the TOML's points_mm
    assert {j["name"]: j["at_mm"] for j in mech["joints"]}["C"] == pytest.approx([35.0, 20.0])
    assert mech["clearance_joints"] == ["B"] and mech["driven_joints"] == ["O"]
    d = tmp_path / "general"
    d.mkdir()
    (d / "config.json").write_text(json.dumps(dump))
    page = build_report(d).read_text(encoding="utf-8")
    assert "The mechanism as drawn in its config" in page and "Mechanism sketch: drawn for" not in page
    assert "coupler, rocker" in page  # the bodies in the mechanism table, not a dump of dicts
    # the user's study, not a preset: its name and its file head the page
    assert f"study {dump['name']} \u00b7 config {toml}" in page and "preset " + dump["name"] not in page
    assert "Source of the preset" not in page


def test_far_shifts_show_how_they_were_read_and_why_a_shifted_mechanism_failed(tmp_path: Path, nominal: Path):
    """sensitivity.json's separable-scaling rules appear with their wear ratio; a shifted mechanism that could not
    run is warned about, with the reason its model call recorded."""
    d = make_fixture_dir(tmp_path, nominal, which=("sensitivity", "config"))
    sens = SensitivityResult.load(d)
    name = sens.variables[0]["name"]
    sens.rules = [{"variable": name, "factor": 0.8, "rule": "separable_scaling", "reliability": 0.0,
                   "reason": "the shifted mechanism could not run (counted as failure): joint A's points are 2 mm "
                             "apart"},
                  {"variable": name, "factor": 1.2, "rule": "separable_scaling", "reliability": 0.61,
                   "wear_ratio": 1.1734, "error_estimate": 0.01}]
    sens.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "Shifts outside the learned region" in page and "wear \u00d7 1.17" in page
    assert "could not be built or run" in page and "joint A&#x27;s points are 2 mm apart" in page
    # the command line says it too (the result's sentence): only the report did
    assert sens.unbuilt_shifts_sentence().startswith(
        f"the shifted mechanism could not be built or run for {name} x 0.8 (the shifted mechanism could not run")
    sens.rules = [sens.rules[1]]
    sens.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "Shifts outside the learned region" in page and "could not be built or run" not in page
    assert sens.unbuilt_shifts_sentence() == ""
    assert sens.extreme_shifts_sentence() == "" and "moves otherwise" not in page  # x 1.17: a sensitivity
    # a rod at 120 % near the dead point wore 40,668 times the nominal, with no caveat
    sens.rules = [{**sens.rules[0], "wear_ratio": 40668.04}]
    sens.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert sens.extreme_shifts_sentence().startswith(
        f"the shifted mechanism's wear differs from the nominal's more than 10-fold for {name} x 1.2 (wear x 40,668)")
    assert "A shifted mechanism that moves otherwise." in page


def test_the_archard_check_is_shown_and_a_disagreement_warned(tmp_path: Path, nominal: Path):
    """sensitivity.json's archard_checks appear as a table; a disagreement raises a warning with its size, and a
    check not made says why."""
    d = make_fixture_dir(tmp_path, nominal, which=("sensitivity", "config"))
    sens = SensitivityResult.load(d)
    agree = {"variable": "HB_b", "factor": 0.8, "reliability_surrogate": 0.531, "reliability_archard": 0.514,
             "difference": 0.017, "tolerance": 0.042, "consistent": True}
    not_made = {"variable": "k_b", "factor": 0.8, "reliability_surrogate": 0.999, "consistent": None,
                "note": "not checked: the Archard reading needs the life surrogate at 288,000 cycles"}
    sens.archard_checks = [agree, not_made]
    sens.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "Check against Archard" in page and "288,000 cycles" in page
    assert "disagrees with Archard" not in page and "DISAGREE" not in page
    sens.archard_checks = [agree, not_made, {"variable": "k_b", "factor": 1.2, "reliability_surrogate": 0.552,
                                             "reliability_archard": 0.637, "difference": -0.0843, "tolerance": 0.041,
                                             "consistent": False}]
    sens.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "by up to 0.084 in R" in page
    assert 'class="bad"' in page and "DISAGREE" in page


def test_a_curve_that_misses_the_life_says_where_the_nominal_design_reaches_the_allowance(tmp_path, nominal):
    """R(N) = 0 from the first level on: the report warns and gives the nominal history's crossing of the
    allowance, interpolated on the wear history (checked here against the history itself); a curve that holds its
    life has no warning."""
    d = make_fixture_dir(tmp_path / "m", nominal, which=("wear", "reliability"))
    assert "The curve misses the life" not in build_report(d).read_text(encoding="utf-8")
    wear, rel = WearSummary.load(d), ReliabilityCurve.load(d)
    n, h = (np.asarray(wear.history[k], dtype=float) for k in ("cycles", "max_wear_mm"))
    allowance = 0.5 * h[-1]  # reached half-way through the history: the crossing is inside it
    rel.joints = [{"name": wear.joints[0]["name"], "allowance_mm": allowance}]
    rel.cycles = np.asarray(rel.cycles) + 2 * n[-1]  # the whole curve after the history's end: R = 0 everywhere
    rel.reliability, rel.pf = np.zeros(rel.cycles.size), np.ones(rel.cycles.size)
    rel.life_table = [{"target": 0.9, "cycles": None, "hours": None, "status": "before_curve"}]
    rel.save(d)
    page = build_report(d).read_text(encoding="utf-8")
    expected = float(np.interp(allowance, h, n))  # the history grows monotonically
    assert "The curve misses the life" in page and "Lower <code>reliability.cycles_start</code>" in page
    assert f"after about {expected:,.0f} cycles" in page


def test_sensitivity_at_a_level_where_no_shift_moves_r_says_it_ranks_nothing(tmp_path, nominal):
    """R = 0 at the sensitivity's level whatever the shift: the report warns, the CLI's ranking line says none."""
    from jointwear.study.stage_lines import ranking_line

    d = make_fixture_dir(tmp_path / "s", nominal, which=("sensitivity",))
    sens = SensitivityResult.load(d)
    assert sens.shifts_move_reliability and not ranking_line(sens).startswith("none")
    assert "No mean shift changes the reliability here" not in build_report(d).read_text(encoding="utf-8")
    sens.reliability_nominal = 0.0
    for v in sens.variables:
        v["reliability_low"] = v["reliability_high"] = 0.0
    sens.write(d)
    assert not SensitivityResult.load(d).shifts_move_reliability
    assert ranking_line(sens).startswith("none: no mean shift changes R at 360,000 cycles (R = 0.000")
    assert "No mean shift changes the reliability here" in build_report(d).read_text(encoding="utf-8")


def test_force_cards_take_the_prefix_of_the_peak_and_angles_wrap_to_0(tmp_path, nominal):
    """The wing's contact force reads in mN, a 200 N joint's in N (not "2e+05 mN"); a peak 5e-6 deg short of 360
    reads 0."""
    d = make_fixture_dir(tmp_path / "f", nominal, which=("simulate", "wear"))
    page = build_report(d).read_text(encoding="utf-8")
    assert re.search(r'mean contact force</div><div class="card-value">[0-9.]+ mN<', page)
    sim = json.loads((d / "simulate.json").read_text(encoding="utf-8"))
    sim["contact_force_mean_N"], sim["contact_force_max_N"] = 203.0, 256.0
    (d / "simulate.json").write_text(json.dumps(sim), encoding="utf-8")
    wear = WearSummary.load(d)
    wear.max_wear_angle_deg = 359.99999547857817
    wear.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert 'mean contact force</div><div class="card-value">203 N<' in page
    assert 'peak contact force</div><div class="card-value">256 N<' in page
    assert 'at angle</div><div class="card-value">0.0 deg<' in page


def test_a_mechanism_with_several_clearance_joints_shows_each(tmp_path, nominal):
    """Two clearance joints (a series system): the dynamics and wear sections list both, the cards say which joint
    they show, and the second joint's profile gets its own figure; one joint keeps the cards unlabelled."""
    d = make_fixture_dir(tmp_path / "j", nominal, which=("simulate", "wear"))
    page = build_report(d).read_text(encoding="utf-8")
    assert "Every clearance joint" not in page and "(joint A)" not in page and "Wear of the joints" not in page
    sim = json.loads((d / "simulate.json").read_text(encoding="utf-8"))
    sim["joints"] = [sim["joints"][0], {**sim["joints"][0], "name": "E", "contact_force_mean_N": 0.1914}]
    (d / "simulate.json").write_text(json.dumps(sim), encoding="utf-8")
    wear = WearSummary.load(d)
    second = {**wear.joints[0], "name": "E", "max_wear_mm": 0.003286, "max_wear_angle_deg": 277.24}
    wear.joints = [wear.joints[0], second]
    wear.write(d)
    n_figures = page.count("data:image/png;base64")
    page = build_report(d).read_text(encoding="utf-8")
    assert page.count("<h3>Every clearance joint</h3>") == 2 and "Wear of the joints" in page
    assert "mean contact force (joint A)" in page and "max bearing wear (joint A)" in page
    assert "<td>E</td><td>0.003286</td><td>277.2</td>" in page and "<td>0.1914</td>" in page
    # the second joint's polar profile, wear history and wear against the angle, each drawn and named
    assert "Bearing wear profile of joint E" in page and page.count("data:image/png;base64") == n_figures + 3
    assert "Max bearing wear of joint E against cycles" in page and "bearing wear depth of joint E against" in page


def test_failed_model_calls_and_a_worn_away_joint_are_warned(tmp_path, nominal):
    """Failed calls teach the surrogate nothing (the curve can be too high), and a history that stopped because a
    joint wore away extrapolates past that point: both are said where the numbers are, not only in the JSON."""
    d = make_fixture_dir(tmp_path / "x", nominal, which=("wear", "reliability"))
    page = build_report(d).read_text(encoding="utf-8")
    assert "Failed model calls" not in page and "Worn away" not in page
    rel, wear = ReliabilityCurve.load(d), WearSummary.load(d)
    rel.failed_calls = 9
    rel.infeasible = {"failed_calls": 9, "failure_reasons": {"3": "ValueError: boom", "5": "ValueError: boom"},
                      "worn_away_calls": 3}
    rel.save(d)
    wear.stopped_at_cycles, wear.cycles_requested = 100_000, wear.cycles
    wear.stop_reason = "joint A: the journal is worn 2 mm deep"
    wear.write(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert "Failed model calls" in page and f"9 of {rel.model_calls} model calls failed" in page
    assert "most often: ValueError: boom" in page and "unconservative" in page
    assert "Worn away" in page and "stopped at 100,000 of" in page
    assert "Joints worn away" in page and f"3 of {rel.model_calls} model calls wore a joint away" in page


def test_the_share_of_clearances_below_their_minimum_is_said_with_its_rule(tmp_path, nominal):
    """2.5 % of the default study's clearances are rejected at assembly (rule 'truncate'); the report never said so."""
    d = make_fixture_dir(tmp_path / "x", nominal, which=("wear", "reliability"))
    rel = ReliabilityCurve.load(d)
    rel.infeasible = {"clearances": [{"name": "c", "rule": "truncate", "minimum_clearance_m": 1e-7,
                                      "probability_below_minimum": 0.025286}]}
    rel.save(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert ("2.53 % of clearance c&#x27;s normal lies below its minimum (0.1 um): rejected at assembly, so R(N) is "
            "that of the accepted assemblies") in page
    rel.infeasible["clearances"][0].update(rule="fail", probability_below_minimum=0.0)
    assert rel.truncation_sentence() == ""


def test_the_life_table_keeps_a_target_near_1_and_the_numbers_give_the_surrogates_error(tmp_path, nominal):
    """A target of 0.99995 was shown as '1'; the R(N) table had no column for the surrogate's error of R."""
    d = make_fixture_dir(tmp_path / "t", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    rel.life_table = [{"target": 0.9, "cycles": 370_000.0, "hours": 12.8, "status": "in_curve"},
                      {"target": 0.99995, "cycles": 300_000.0, "hours": 10.4, "status": "in_curve"}]
    rel.save(d)
    page = build_report(d).read_text(encoding="utf-8")
    assert ">0.99995<" in page and "surrogate error of R" in page


def test_the_life_is_shown_with_its_interval(tmp_path, nominal):
    """The reliability card, the life table and the summary give the life's 95 % interval, the one the result
    computes (where the band R -/+ half-width crosses the target)."""
    d = make_fixture_dir(tmp_path / "i", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    rel.life_table = [{"target": 0.9, "cycles": rel.life_cycles, "hours": 12.8, "status": "in_curve"},
                      {"target": 0.5, "cycles": 450_000.0, "hours": 15.6, "status": "in_curve"}]
    rel.save(d, figures=False)
    low, high = rel.life_interval()
    assert low < rel.life_cycles < high
    page = build_report(d).read_text(encoding="utf-8")
    assert page.count(f"95 % interval {low:,.0f}-{high:,.0f} cycles") == 2  # the summary's card and the section's
    low5, high5 = rel.life_interval(0.5)
    assert f"{low5:,.0f} \u2013 {high5:,.0f}" in page  # the life table's column


def two_joint_result(folder, nominal):
    """The fixture's reliability result as a series system of joints A and E, which govern 70 and 30 % of the
    failures at every level."""
    d = make_fixture_dir(folder, nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    n = len(rel.cycles)
    rel.joints = [
        {"name": "A", "allowance_mm": 0.03, "reliability": list(rel.reliability), "governing_share": [0.7] * n},
        {"name": "E", "allowance_mm": 0.03, "reliability": [1.0] * n, "governing_share": [0.3] * n}]
    return d, rel


def test_a_series_system_is_told_that_its_interval_may_be_too_narrow(tmp_path, nominal):
    d, rel = two_joint_result(tmp_path / "s", nominal)
    n = len(rel.cycles)
    rel.save(d, figures=False)
    page = build_report(d).read_text(encoding="utf-8")
    assert "Series system of 2 joints" in page and "<b>A</b>" in page
    assert "held the exact life in 9 of 20 runs" in page and "<code>jointwear validate</code>" in page
    assert rel.life_surrogate == "system_life"  # a result written before the choice: one Kriging of the life
    # and the summary says so beside the headline life, naming the shares
    assert ("<strong>A series system</strong></a>: the failures at the life are shared between judged joints "
            "(A 70 %, E 30 %)") in page
    # a second joint that governs under 10 % of the failures leaves the kink in the tail: no caveat
    rel.joints[0]["governing_share"], rel.joints[1]["governing_share"] = [0.95] * n, [0.05] * n
    assert rel.series_sentence() == ""
    assert rel.governing_shares() == {"A": 0.95, "E": 0.05} and rel.governing_joint == "A"


def test_a_series_system_learnt_per_joint_carries_no_kink_caveat(tmp_path, nominal):
    d, rel = two_joint_result(tmp_path / "p", nominal)
    rel.life_surrogate = "per_joint"
    fit = {"n_points": 60, "q2": 0.71, "rmse_log_life": 0.1, "relative_nugget": 0.1, "nugget_at_bound": False,
           "process_sd_log_life": 0.4}
    rel.joints[0]["surrogate_fit"] = {**fit, "noise_sd_log_life": 0.14}
    rel.joints[1]["surrogate_fit"] = {**fit, "noise_sd_log_life": 0.02}
    assert rel.series_sentence() == ""
    rel.save(d, figures=False)
    assert ReliabilityCurve.load(d).life_surrogate == "per_joint"
    page = build_report(d).read_text(encoding="utf-8")
    assert "learnt one Kriging per joint" in page and "held the exact life in 18 of 20 runs at R = 0.9" in page
    assert "are shared between judged joints" not in page
    # each joint's share of the failures, its own life (A's curve is the system's here; E's never falls to 0.9) and
    # its own fit: Q^2 and the scatter of a call's life, exp(0.14) - 1 = 15 %
    life_a = f"{rel.joint_lives()['A'][0]:,.0f}"
    assert f"<td>A</td><td>70 %</td><td>{life_a}</td><td>0.71</td><td>\u00b115 %</td>" in page
    assert "<td>E</td><td>30 %</td><td>beyond the curve</td><td>0.71</td><td>\u00b12 %</td>" in page
    assert rel.joint_lives()["A"][0] == pytest.approx(rel.life(), rel=1e-12)


def test_the_summary_carries_the_caveats_of_the_sections_below(tmp_path, nominal):
    """The headline life stood alone; 'learning converged: NO' and the uniform-mode warning were three sections
    further down."""
    from jointwear.report.read import read_outputs
    from jointwear.report.result_sections import summary_caveats

    d = make_fixture_dir(tmp_path / "c", nominal, which=("wear", "reliability"))
    rel, wear = ReliabilityCurve.load(d), WearSummary.load(d)
    rel.converged, rel.learning_stop = True, ""
    rel.save(d, figures=False)
    wear.geometry_mode, wear.uniform_mode_valid = "profile", True
    wear.joints[0]["journal"]["max_wear_mm"] = 0.5 * wear.joints[0]["allowance_mm"]  # judged or not, within it
    wear.write(d)
    # only the one caveat that holds until jointwear converge has run on the folder
    baseline = summary_caveats(read_outputs(d))
    assert baseline.count("<li>") == 1 and "The wear history's numerics are not checked" in html.unescape(baseline)
    rel.converged, rel.learning_stop, rel.failed_calls = False, "max_calls (60) reached", 2
    rel.infeasible = {"failed_calls": 2, "failure_reasons": {"3": "ValueError: boom"}}
    rel.save(d, figures=False)
    wear.geometry_mode, wear.uniform_mode_valid = "uniform", False
    wear.write(d)
    summary = summary_caveats(read_outputs(d))
    assert "Read these numbers with these caveats" in summary
    assert '<a href="#reliability"><strong>The learning did not converge</strong></a>: its budget of model calls ' \
           "ended" in summary
    assert '<a href="#wear"><strong>Uniform mode is outside its range</strong></a>' in summary
    assert f"2 of {rel.model_calls} model calls failed" in summary
    # and the report puts them in its summary section
    page = build_report(d).read_text(encoding="utf-8")
    start = page.index('<section id="summary">')
    assert summary in page[start:page.index("</section>", start)]


def test_a_budget_spent_while_confirming_the_stop_says_so(tmp_path, nominal):
    """The card said only 'stopped by the budget of model calls' where the rule had held and was being confirmed."""
    d = make_fixture_dir(tmp_path / "h", nominal, which=("wear", "reliability"))
    rel = ReliabilityCurve.load(d)
    rel.converged = False
    rel.learning_stop = ("max_calls=80 reached while confirming the learning stop (it held on 1 of the 3 successive "
                         "designs hold_iterations asks for)")
    rel.save(d, figures=False)
    page = html.unescape(build_report(d).read_text(encoding="utf-8"))
    assert "reached while confirming the learning stop (it held on 1 of the 3" in page


def test_sobol_indices_carry_their_intervals_and_the_nominal_r_says_its_population(tmp_path, nominal):
    """ST read below S1 with no interval shown (0.493 < 0.505 on 256 base samples, within +/- 0.18); the
    sensitivity's nominal R (0.969) differed from the curve's (0.9684) with no word of their two populations."""
    d = make_fixture_dir(tmp_path / "s", nominal, which=("wear", "reliability", "sensitivity"))
    rel, sens = ReliabilityCurve.load(d), SensitivityResult.load(d)
    names = sens.sobol["names"]
    for v in sens.variables:
        k = names.index(v["name"])
        v["S1"], v["ST"] = sens.sobol["S1"][k], sens.sobol["ST"][k]
    sens.sobol["S1_conf"] = [0.1776] * len(names)
    sens.sobol["ST_conf"] = [0.0842] * len(names)
    sens.cycles, sens.n_population = int(rel.cycles[2]), 100_000
    sens.save(d)
    page = build_report(d).read_text(encoding="utf-8")
    hb = names.index("HB_b")
    assert f"{sens.sobol['S1'][hb]:.3g} \u00b1 0.18" in page and f"{sens.sobol['ST'][hb]:.3g} \u00b1 0.084" in page
    assert "on the sensitivity&#x27;s population of 100,000" in page or "on the sensitivity's population of 100,000" \
        in page
    assert f"the R(N) curve, on its own population, reads {rel.reliability[2]:.4g} there" in page


def test_an_elasticity_carries_its_interval_and_says_when_it_is_not_resolved():
    """The crank length's elasticity +2.89 stood beside a mean shift whose R fell, without its error; the journal
    radius's was pure noise (its derivative -12.6 +/- 445) and read like a number."""
    from jointwear.report.result_sections import _elasticity_text

    derivatives = {"names": ["l1", "Rj"], "dpf_dmean": [-454.0, -12.6], "dpf_dmean_se": [131.0, 445.0]}
    resolved = _elasticity_text(derivatives, {"name": "l1", "elasticity_mean": 2.89})
    assert resolved == "2.89 \u00b1 1.6"  # 1.96 x 2.89 x 131 / 454 = 1.63
    assert _elasticity_text(derivatives, {"name": "Rj", "elasticity_mean": 0.0134}).endswith("(not resolved)")
    assert _elasticity_text({}, {"name": "l1", "elasticity_mean": 2.89}) == "2.89"  # a result without errors


def test_the_summary_carries_the_design_and_its_verification(tmp_path, nominal):
    """A design study's summary showed neither the choice nor that its verification had stopped on its budget."""
    from jointwear.design.results import DesignResult

    d = make_fixture_dir(tmp_path / "x", nominal, which=("wear", "reliability"))
    design = DesignResult(target_life_cycles=260_545.0, target_reliability=0.9,
                          chosen={"choices": {"fit": "H7/g6"}, "cost": 4.148, "reliability_at_target_life": 0.95},
                          pareto=[], verification={"reliability_at_target_life": 0.95, "error": 0.0034,
                                                   "model_calls": 20, "converged": False},
                          model_calls=54, wall_seconds=1.0, baseline_choices={"fit": "IT7/IT6"}, baseline_cost=4.083)
    design.save(d)
    page = build_report(d).read_text(encoding="utf-8")
    summary = page[page.index("cards summary"):page.index("cards summary") + 3000]
    assert "design for 260,545 cycles at R = 0.9" in summary and "cost 4.148" in summary
    # with the verification's own R(N*): a designer's card read 'within error' beside a verified 0.77 +- 0.13
    assert "verification: meets (R(N*) = 0.950 \u00b1 0.003); today&#x27;s design 4.083 (+0.065)" in summary
    assert "The choice&#x27;s verification stopped on its budget" in page


def test_a_reliability_result_plots_itself(tmp_path, nominal):
    """A notebook user had to rebuild the report's R(N) figure from six fields (and drew it without its band)."""
    d = make_fixture_dir(tmp_path / "x", nominal, which=("wear", "reliability"))
    rel = ReliabilityCurve.load(d)
    ax = rel.plot().axes[0]
    assert ax.get_title(loc="left").startswith("Reliability") and len(ax.collections) >= 1  # the band
    assert any(ln.get_label() == "this study" for ln in ax.get_lines())


def test_the_wear_sensitivity_and_validation_results_plot_themselves(tmp_path, nominal):
    """A notebook had .plot() on the reliability curve only; the wear, sensitivity and validation results draw the
    figure their stage writes (the same function, so the PNG in the folder is this figure)."""
    from jointwear.study.results import ValidationResult

    d = make_fixture_dir(tmp_path / "p", nominal, which=("wear", "reliability", "sensitivity"))
    res = load_results(d)
    polar = res.wear.plot()
    assert polar.axes[0].name == "polar" and polar.axes[0].get_title(loc="left") == "Worn bearing, joint A"
    with pytest.raises(KeyError, match=r"WearSummary has no joint 'Z'; its joints: A"):
        res.wear.plot("Z")
    tornado = res.sensitivity.plot()
    labels = [t.get_text() for ax in tornado.axes for t in ax.get_yticklabels()]
    assert all(v["label"] in labels for v in res.sensitivity.variables)
    val = ValidationResult(cycles=[360_000, 400_000], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                           ci_high=[0.96, 0.82], reliability_surrogate=[0.948, 0.805], surrogate_error=[0.005, 0.01],
                           n_samples=200, model_calls=200, wall_seconds=1.0, agreement=[True, True])
    assert len(val.plot().axes[0].get_lines()) >= 2  # the two curves


def test_a_simulation_result_plots_its_orbit_and_its_force_in_process_and_read_back(tmp_path, nominal):
    """SimulationSummary had no .plot(): a notebook redrew the stage's orbit from simulate.npz by hand."""
    import numpy as np

    from jointwear.report import figures
    from jointwear.study.results import SimulationSummary

    d = make_fixture_dir(tmp_path / "s", nominal, which=("simulate",))
    loaded = load_results(d).simulate
    orbit, force = loaded.plot(), loaded.plot("A", kind="force")
    assert orbit.axes[0].get_title(loc="left") == "Journal centre orbit, joint A"
    assert force.axes[0].get_title(loc="left") == "Contact force, joint A"
    with np.load(d / "simulate.npz") as data:  # the series drawn are the saved ones
        ecc, fn, ft = (data[f"A_{k}"] for k in ("eccentricity_bearing_frame_m", "force_normal_N", "force_tangential_N"))
        crank_deg = np.degrees(data["crank_angle_rad"])
    drawn = orbit.axes[0].get_lines()[0].get_xydata()
    np.testing.assert_allclose(drawn, ecc * 1e6, rtol=1e-12)  # drawn in um (rounding of the mm -> um scaling)
    mean = loaded.joints[0]["contact_force_mean_N"]
    expected = figures.contact_force_figure(crank_deg, np.hypot(fn, ft), mean_N=mean)
    np.testing.assert_array_equal(force.axes[0].get_lines()[0].get_xydata(),
                                  expected.axes[0].get_lines()[0].get_xydata())
    with pytest.raises(KeyError, match=r"SimulationSummary has no joint 'Z'; its joints: A"):
        loaded.plot("Z")
    with pytest.raises(ValueError, match=r"kind must be 'orbit' or 'force'"):
        loaded.plot(kind="wear")
    bare = SimulationSummary.from_json(loaded.to_json())  # no trace, no folder: said, not a KeyError
    with pytest.raises(ValueError, match=r"loaded from a folder that holds its simulate.npz"):
        bare.plot()


def test_a_validated_life_that_disagrees_is_flagged_beside_the_headline(tmp_path, nominal):
    """The summary showed the life at R = 0.9 without a flag while the validation's own life at that target had a
    95 % interval apart from the curve's (398,667 against 376,184 cycles on a 200-sample validation)."""
    from jointwear.study.results import ValidationResult

    d = make_fixture_dir(tmp_path / "v", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    life = rel.life()

    def validate(agree: bool) -> str:
        ValidationResult(cycles=[360_000, 400_000], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                         ci_high=[0.96, 0.82], reliability_surrogate=[0.948, 0.805], surrogate_error=[0.005, 0.01],
                         n_samples=200, model_calls=200, wall_seconds=1.0, agreement=[True, True],
                         life_table=[{"target": rel.target, "cycles": 1.06 * life, "cycles_low": 1.02 * life,
                                      "cycles_high": 1.09 * life, "surrogate_cycles": life, "agree": agree}]).save(d)
        return html.unescape(build_report(d).read_text(encoding="utf-8"))

    page = validate(False)
    assert "the validation's true model disagrees (caveats below)" in page
    assert (f"The true model's life disagrees with the curve's</strong></a>: at R = {rel.target:g} the true model's "
            f"life is {1.06 * life:,.0f} cycles") in page
    # the reliability section says how far this study's life reads from its own true model's (1 / 1.06 - 1)
    assert ("How far to trust the life: on 200 direct samples of this study's true model (the validation below), "
            f"the life reads 5.7 % below the true model's {1.06 * life:,.0f} cycles") in page
    assert "<b>their 95 % intervals do not overlap</b>: the life's interval is too narrow" in page
    page = validate(True)
    assert "true model disagrees (caveats below)" not in page and "The true model's life disagrees" not in page
    assert "the life reads 5.7 % below the true model's" in page and "their 95 % intervals overlap." in page
    assert "flapping-wing presets' lives" not in page  # the presets' figures only stand in for a study's own


def test_a_validation_on_the_same_samples_is_told_beside_the_life_and_in_its_section(tmp_path, nominal):
    """The surrogate read on the validation's own samples gives its own error of the life (paired_ratio): the
    reliability section's trust sentence says it and whether the life's interval allows it, the validation section
    shows it as a card and the paired differences in R as columns."""
    from jointwear.study.results import ValidationResult

    d = make_fixture_dir(tmp_path / "p", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    life = rel.life()
    low, high = rel.life_interval()

    def validate(ratio: float) -> str:
        ValidationResult(cycles=[360_000, 400_000], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                         ci_high=[0.96, 0.82], reliability_surrogate=[0.948, 0.805], surrogate_error=[0.005, 0.01],
                         n_samples=2000, model_calls=2000, wall_seconds=1.0, agreement=[True, True],
                         paired_reliability_surrogate=[0.946, 0.79], paired_difference_low=[-0.006, -0.014],
                         paired_difference_high=[-0.002, -0.006],
                         life_table=[{"target": rel.target, "cycles": 1.01 * life, "cycles_low": 0.99 * life,
                                      "cycles_high": 1.03 * life, "surrogate_cycles": life, "surrogate_cycles_low": low,
                                      "surrogate_cycles_high": high, "agree": True,
                                      "paired_surrogate_cycles": (1 + ratio) * life, "paired_ratio": ratio,
                                      "paired_ratio_low": ratio - 0.004, "paired_ratio_high": ratio + 0.004}]).save(d)
        return html.unescape(build_report(d).read_text(encoding="utf-8"))

    page = validate(-0.019)
    assert ("How far to trust the life: the validation below ran this study's true model on 2,000 samples; on the "
            f"same samples the surrogate's life at R = 0.9 is {0.981 * life:,.0f} cycles, 1.9 % below the true "
            f"model's {1.01 * life:,.0f} (95 % interval -2.3 % to -1.5 %): the learnt life reads 1.9 % short (95 %: "
            "1.5-2.3 % short), on the safe side: a short life is conservative; <b>beyond what the life's 95 % "
            "interval allows (") in page
    assert "surrogate's life on these samples" in page and "-1.9 %" in page
    assert "-0.004 [-0.014, -0.006]" not in page and "-0.010 [-0.014, -0.006]" in page  # 0.79 - 0.8, its bounds
    assert page.count("same samples: surrogate \u2212 true (95 %)") == 1
    # the summary, read alone, says so too
    assert "the validation finds a larger error (caveats below)" in page
    assert ("The life errs by more than its interval says</strong></a>: against 2,000 direct runs of the true "
            "model, on the same samples the surrogate's life at R = 0.9 is") in page
    assert 'reliability.trend = "linear" (a linear trend under the Kriging' in page  # the cure, named
    page = validate(0.0)
    assert ("(95 % interval -0.4 % to +0.4 %): the learnt life reads true (95 %: 0.4 % short to 0.4 % long); "
            "within what the life's 95 % interval allows (") in page
    assert "larger error" not in page and "The life errs by more" not in page


def test_an_unvalidated_life_is_told_the_presets_validations(tmp_path, nominal):
    """Without its own validation the reliability section gives the presets' measured error and names the command
    that measures this study's."""
    from jointwear.report.result_sections import LIFE_TRUST

    d = make_fixture_dir(tmp_path / "n", nominal, which=("reliability",))
    page = html.unescape(build_report(d).read_text(encoding="utf-8"))
    assert html.unescape(LIFE_TRUST) in page and "jointwear validate" in page


def test_a_wear_history_whose_contact_outgrows_hertz_and_an_unjudged_journal_are_told(tmp_path, nominal):
    """The wear stage said nothing of a soft bushing's contact past the Hertz law's range (only simulate did), and
    the summary left out a journal worn past the allowance that the limit state does not judge."""
    import math

    from jointwear.contact.geometry import HERTZ_HALF_ANGLE_LIMIT

    d = make_fixture_dir(tmp_path / "w", nominal, which=("wear", "config"))
    wear = WearSummary.load(d)
    joint = wear.joints[0]
    radius_um = joint["bearing_radius_mm"] * 1e3
    joint["max_half_width_um"] = 1.5 * HERTZ_HALF_ANGLE_LIMIT * radius_um  # 26 deg each side
    (sentence,) = wear.outside_hertz()
    assert f"is {math.degrees(1.5 * HERTZ_HALF_ANGLE_LIMIT):.3g} deg wide each side" in sentence
    assert "its worn volume stands" in sentence
    joint["journal"]["max_wear_mm"] = 2.0 * joint["allowance_mm"]
    wear.write(d)
    page = html.unescape(build_report(d).read_text(encoding="utf-8"))
    assert "Outside the contact law's range</strong></a>: joint" in page
    assert "Wear the limit state does not judge</strong></a>: joint" in page
    # a half-width factor of one's own (100 for Johnson's 1.128) was left unnamed: the note blamed a soft bushing
    wear.settings["half_width_factor"] = 100.0
    (sentence,) = wear.outside_hertz()
    assert (f"It is read with wear.half_width_factor = 100, {100 / 1.1283791670955126:.3g} times Johnson's 1.128, "
            f"which gives {joint['max_half_width_um'] * 1.1283791670955126 / 100:.4g} um: check that setting first. "
            "A bushing that really is that soft") in sentence
    joint["max_half_width_um"] = 0.5 * HERTZ_HALF_ANGLE_LIMIT * radius_um
    assert wear.outside_hertz() == []


def test_the_validation_figure_draws_the_band_the_agreement_test_reads():
    # the figure drew the error estimate alone (0.01 at 400k) while the test reads the 95 % band, Monte Carlo
    # 1.96 COV Pf plus that estimate: 1.96 x 0.05 x 0.2 + 0.01 = 0.0296
    import numpy as np

    from jointwear.reliability import Z95
    from jointwear.report import figures as F
    from jointwear.study.results import ValidationResult

    val = ValidationResult(cycles=[360_000, 400_000], reliability_mc=[0.95, 0.8], ci_low=[0.94, 0.78],
                           ci_high=[0.96, 0.82], reliability_surrogate=[0.95, 0.8], surrogate_error=[0.005, 0.01],
                           surrogate_cov=np.array([0.1, 0.05]), n_samples=2000, model_calls=2000, wall_seconds=1.0,
                           agreement=[True, True])
    assert val.surrogate_half_width == pytest.approx([Z95 * 0.1 * 0.05 + 0.005, Z95 * 0.05 * 0.2 + 0.01])
    fig = F.validation_figure(val.cycles, val.reliability_mc, val.ci_low, val.ci_high, val.reliability_surrogate,
                              val.surrogate_half_width, n_samples=val.n_samples)
    band = fig.axes[0].collections[0].get_paths()[0].vertices[:, 1]
    assert band.max() == pytest.approx(0.95 + val.surrogate_half_width[0])
    assert band.min() == pytest.approx(0.8 - val.surrogate_half_width[1])


def test_a_long_text_cell_wraps_in_a_table_of_numbers():
    """A shift's reason (the Grashof message) kept its table of numbers on one line: the page grew 4,000 px wide and
    the reason was cut in print. Cells longer than PROSE_CELL wrap; short ones stay on one line."""
    from jointwear.report.markup import PROSE_CELL, table

    html = table(["variable", "R", "reason"], [["l2", "0.0", "x" * (PROSE_CELL + 1)]], cls="num")
    assert '<td>l2</td><td>0.0</td><td class="prose">' in html


@pytest.mark.rendered  # its own two PNG files must differ
def test_a_png_linked_from_outside_the_folder_is_not_embedded(tmp_path: Path):
    import base64

    from jointwear.report.figures import sobol_figure
    from jointwear.report.read import read_outputs
    from jointwear.report.style import savefig

    outside, d = tmp_path / "outside", tmp_path / "results"
    outside.mkdir()
    d.mkdir()
    savefig(sobol_figure(["a", "b"], [0.2, 0.5], [0.3, 0.6]), outside / "secret.png")
    savefig(sobol_figure(["c", "d"], [0.1, 0.4], [0.2, 0.5]), d / "own.png")
    (d / "linked.png").symlink_to(outside / "secret.png")
    (d / "linked.csv").symlink_to(outside / "secret.png")
    (d / "data").symlink_to(outside, target_is_directory=True)  # a linked data folder is outside too
    (d / "inside_link.png").symlink_to(d / "own.png")  # a link that stays inside is fine
    out = read_outputs(d)
    assert sorted(out.pngs) == ["inside_link", "own"] and not out.files
    page = build_report(d).read_text()
    secret = base64.b64encode((outside / "secret.png").read_bytes()).decode()
    assert base64.b64encode((d / "own.png").read_bytes()).decode() in page and secret not in page


def test_the_mechanism_table_names_the_clearance_joint_as_the_results_do():
    """A clearance joint named 'Bpin' at the mechanism's joint B was 'B' in the mechanism table and 'Bpin' everywhere
    else; the presets, whose clearance joints carry their joint's name, show one name."""
    from jointwear.config import load_config, updated
    from jointwear.study.settings_record import settings_dump

    named = settings_dump(updated(load_config("flores_slider_crank"), {"clearance_joints.0.name": "Bpin"}))
    assert (named["mechanism"]["clearance_joint"], named["mechanism"]["clearance_joint_name"]) == ("B", "Bpin")
    assert "clearance_joint_name" not in settings_dump(load_config("flores_slider_crank"))["mechanism"]


def test_the_clearance_joints_geometry_and_materials_stand_beside_the_mechanism(full_report):
    """A designer looked for the bushing's and the pin's materials and found them only in the list of every
    setting; the settings section now tables each clearance joint's bearing and journal."""
    from jointwear.config import load_config
    from jointwear.report.study_sections import clearance_joints_table
    from jointwear.study.settings_record import settings_records

    page = full_report.read_text(encoding="utf-8")
    section = page[page.index("Clearance joints: geometry and materials"):]
    section = section[:section.index("</table>")]
    cells = re.findall(r"<td>([^<]*)</td>", section)
    joint = load_config().clearance_joints[0]
    # the preset's rod eye (titanium, 350 HB) on the crank pin (40Cr, 207 HB), radii 1.002 and 1 mm, 1 mm wide
    assert cells[:10] == ["A", "bearing", joint.bearing_body, joint.bearing_material.name, "120", "0.32", "350",
                          "0.0012", "1.002", "1"], cells
    assert cells[10:19] == ["A", "journal", joint.journal_body, joint.journal_material.name, "211", "0.277", "207",
                            "0.0021", "1"], cells
    assert "Young&#x27;s modulus (GPa)" in section and "hardness (HB)" in section and "width (mm)" in section
    records = settings_records(load_config("watt_six_bar_two_clearances"))
    two = clearance_joints_table(records)
    assert two.count("<tr>") == 5  # the heading and a bearing and a journal row per joint
    by_index = [{**r, "name": r["name"].replace("clearance_joints[A]", "clearance_joints[0]")
                 .replace("clearance_joints[E]", "clearance_joints[1]")}
                for r in records]  # a folder written when list items went by their index
    assert clearance_joints_table(by_index) == two
    assert clearance_joints_table([]) == ""


def test_a_coordinate_variables_name_keeps_its_case_in_the_ranking_text():
    """The six-bar's report wrote 'L_OA and l_AB are coordinates ...': the sentence's capital changed a variable's
    name (l_OA)."""
    from jointwear.report.result_sections import ranking_meaning

    class Sensitivity:
        factors, sobol = (0.8, 1.2), {}

        def variance_ranking(self):
            return []

    text = ranking_meaning(Sensitivity(), {"l_OA": "mechanism.bodies.crank.points.A.x"})
    assert "Here l_OA is a coordinate of the drawing" in text and "L_OA" not in text


def test_the_tornados_text_alternative_names_the_variable_the_ranking_puts_first():
    """The alt text named the rocker (R from 0 to 1: the widest span) while the ranking, which compares each
    variable's larger change from the nominal R, put the rod first (R = 0 at both shifts)."""
    from jointwear.report.alt_text import tornado_alt

    text = tornado_alt(["rod length", "rocker length", "crank length"], [0.0, 0.0, 0.99], [0.0, 1.0, 0.5], 0.94,
                       360_000)
    assert "the largest change of R is rod length's, R at 0.000 and 0.000" in text
