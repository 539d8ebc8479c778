"""The report's remaining findings of audits 61-L (a reliability engineer reading the slider-crank study's report)
and 61-K (a designer's press with two clearance joints): what the life's interval leaves out (the history's
numerics, a call's scatter from few recorded cycles), the sensitivity figures against the resolved ranking, the
captions and labels of the figures, the comparison's differences of R, the calls card, the per-joint allowances and
the joint named in each figure's title."""

from __future__ import annotations

import html
import re

import pytest
from report_fixtures import make_fixture_dir

from jointwear.report import build_report
from jointwear.study.reliability_results import SurrogateFit
from jointwear.study.results import ReliabilityCurve

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read text, not pictures


def _page(folder) -> str:
    return html.unescape(build_report(folder).read_text(encoding="utf-8"))


def _text(page: str) -> str:
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", page)).replace(" :", ":")


def _summary(page: str) -> str:
    return page[page.index("Summary"):page.index("Source of the study's data")]


def test_the_life_says_the_histories_numerics_are_outside_its_interval_until_converge_runs(tmp_path, nominal):
    """The report never mentioned jointwear converge, though docs/study.md lists the wear history's numerical
    settings as outside the life's interval (audit 61-L, D6)."""
    from types import SimpleNamespace

    from jointwear import load_results
    from jointwear.report.read import StudyOutputs
    from jointwear.report.result_sections import numerics_unchecked

    d = make_fixture_dir(tmp_path / "n", nominal, which=("wear", "reliability", "config"))
    page = _text(_page(d))
    record = load_results(d).setting("wear.record_cycles")
    said = "are outside the life's interval and have not been checked on this study"
    assert "The wear history's numerics are not checked: the wear history's numerical settings" in _summary(page)
    assert f"this study records {record:g} cycle" in page and "jointwear converge refines each" in page
    section = page[page.index("How far to trust the life"):]
    assert said in section[:1500]  # beside the life's trust sentence, not only in the summary
    results = load_results(d)
    results.wear_convergence = SimpleNamespace()  # once converge has run, its own verdicts are reported instead
    assert numerics_unchecked(StudyOutputs(d, results)) == ""


def test_the_scatter_card_says_few_recorded_cycles_can_make_part_of_it(tmp_path, nominal):
    """'scatter of a call's life' did not say that part of it can be sampling noise from recording two cycles of a
    chaotic contact per block, which wear.record_cycles lowers (audit 61-L, D6); Q^2 was half-defined (D11)."""
    d = make_fixture_dir(tmp_path / "s", nominal, which=("wear", "reliability", "config"))
    rel = ReliabilityCurve.load(d)
    rel.surrogate_fit = SurrogateFit(n_points=80, q2=0.897, rmse_log_life=0.04, noise_sd_log_life=0.035,
                                     process_sd_log_life=0.2, relative_nugget=0.01, nugget_at_bound=False)
    rel.write(d)
    page = _text(_page(d))
    card = page[page.index("scatter of a call's life"):][:700]
    assert "sampling noise of recording few cycles of chaotic contact dynamics per wear block" in card
    assert "more cycles (wear.record_cycles) lower that part" in card
    assert "leave-one-out predictive R² over the 80 design points" in page


def test_the_tornado_follows_the_resolved_ranking_and_says_its_level_is_not_the_lifes(tmp_path, nominal):
    """The tolerance tornado's alt text said 'the largest change of R is crank length's' where the ranking table
    wrote 'crank length ≈ pin radius ≈ ...'; the level (40,000 cycles) was not said to differ from the life's
    (33,015); the out-of-region table gave R without its error (audit 61-L, D13)."""
    from report_fixtures import SENS_VARS, sensitivity_result

    d = make_fixture_dir(tmp_path / "t", nominal, which=("wear", "reliability", "config"))
    # the fixture's two largest tolerance changes (rod length, then radial clearance) not told apart
    sens = sensitivity_result(unresolved=[{"first": "l2", "second": "c"}])
    label = {name: lab for name, lab, *_ in SENS_VARS}
    sens.rules = [{"variable": "c", "factor": 1.2, "rule": "separable_scaling", "reliability": 0.48,
                   "wear_ratio": 1.14, "error_estimate": 0.196}]
    sens.save(d)
    page = _page(d)
    alts = re.findall(r'alt="(Bar chart of R[^"]*)"', page)
    tolerance = html.unescape(next(a for a in alts if label["l2"] in a))
    assert (f"the largest changes of R are {label['l2']}'s (R at 0.000 and 0.000) and those of {label['c']}, not "
            "told apart within the surrogate's error") in tolerance
    text = _text(page)
    assert ("The ranking below (≈: not told apart within the surrogate's error, so the bars' order between them is "
            f"not resolved): {label['l2']} \u2248 {label['c']} >") in text
    life = ReliabilityCurve.load(d).life()
    assert f"This level (sensitivity.cycles) is not the life at R = 0.9 ({life:,.0f} cycles)" in text
    table = text[text.index("Shifts outside the learned region"):][:900]
    assert f"{label['c']} (c) × 1.2 0.48 0.196 wear × 1.14" in table


def test_the_tornados_nominal_line_is_in_its_legend():
    from jointwear.report.figures import tornado_figure

    fig = tornado_figure(["a", "b"], [0.2, 0.5], [0.9, 0.6], 0.539)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "nominal R = 0.539" in labels


def _two_joint_wear(d):
    """The fixture's wear result with a second joint E (a copy of A), its own allowance half A's; the wear stage's
    files of E written beside A's, as a study with two joints writes them."""
    from jointwear.study.results import WearSummary

    wear = WearSummary.load(d)
    first = wear.joints[0]
    wear.joints = [first, {**first, "name": "E", "allowance_mm": 0.5 * first["allowance_mm"]}]
    wear.write(d)
    rel = ReliabilityCurve.load(d)
    n = len(rel.cycles)  # as test_report_html.two_joint_result: A governs 70 % of the failures, E 30 %
    rel.joints = [{"name": "A", "allowance_mm": first["allowance_mm"], "reliability": list(rel.reliability),
                   "governing_share": [0.7] * n},
                  {"name": "E", "allowance_mm": 0.5 * first["allowance_mm"], "reliability": [1.0] * n,
                   "governing_share": [0.3] * n}]
    rel.write(d)
    for stem in ("wear_history", "wear_vs_angle", "wear_polar"):
        (d / f"{stem}_E.png").write_bytes((d / f"{stem}.png").read_bytes())
    return first["allowance_mm"]


def test_per_joint_allowances_are_shown_per_joint(tmp_path, nominal):
    """With allowances_mm = { K = 0.05, C = 0.02 } the settings table printed allowance_mm 0.05 as if it were the
    study's (audit 61-K, D6)."""
    d = make_fixture_dir(tmp_path / "a", nominal, which=("wear", "reliability", "config"))
    allowance = _two_joint_wear(d)
    text = _text(_page(d))
    assert f"allowance_mm joint A: {allowance:g}, joint E: {0.5 * allowance:g} (per joint)" in text


def test_each_joints_wear_figures_are_drawn_and_named(tmp_path, nominal):
    """wear_history_<J>.png and wear_vs_angle_<J>.png did not name their joint; the report showed the second joint's
    only as those files in the appendix (audit 61-K, D7)."""
    import matplotlib.pyplot as plt

    from jointwear.report.figures import wear_history_figure, wear_panels_figure

    fig = wear_history_figure([0, 1e5], [0, 0.01], joint="C")
    assert fig.axes[0].get_title(loc="left") == "Max wear of joint C against cycles"  # the house style's place
    fig2 = wear_panels_figure([0, 180], [0.0, 0.01], joint="C")
    assert fig2.get_suptitle().startswith("Wear data of joint C against the angle")
    plt.close("all")
    d = make_fixture_dir(tmp_path / "w", nominal, which=("wear", "reliability", "config"))
    _two_joint_wear(d)
    page = _page(d)
    text = _text(page)
    for joint in ("A", "E"):
        assert f"Max bearing wear of joint {joint} against cycles" in text
        assert f"bearing wear depth of joint {joint} against the angle on the bearing" in text
    head = "PNG files found in the output folder that the sections above do not show."
    appendix = text.split(head, 1)[1] if head in text else ""
    assert "wear_history_E.png" not in appendix and "wear_vs_angle_E.png" not in appendix
    assert "wear_polar_E.png" not in appendix  # drawn in the section, not repeated


def test_r_is_compared_in_absolute_terms_and_the_calls_card_keeps_the_reference_apart(tmp_path, nominal):
    """'+2642.8 %' for R(520k) = 0.165 against 0.006, whose band is absolute; 'true-model calls 80 / Jin et al.
    2025: 20; 9 more for the sensitivity' read as the paper's 9; the card left out the validation's calls
    (audit 61-L, D15 and D14)."""
    from jointwear import load_results
    from jointwear.report.compare import comparison_markdown
    from jointwear.report.reference_checks import reference_checks

    d = make_fixture_dir(tmp_path / "r", nominal)
    checks = reference_checks(load_results(d))
    reliability = [c for c in checks if c.quantity.startswith("reliability R(N)")]
    assert reliability and all(c.rel_diff is None for c in reliability)
    first = reliability[0]
    assert first.difference_text == f"{first.ours - first.reference:+.3f} absolute"
    wear = next(c for c in checks if c.quantity.startswith("nominal max bearing wear"))
    assert wear.difference_text.endswith(" %")
    assert f"| {first.difference_text} |" in comparison_markdown(d)
    sens = load_results(d).sensitivity
    sens.extra_model_calls = 9
    sens.save(d)
    text = _text(_page(d))
    card = text[text.index("true-model calls"):][:200]
    assert "for the whole R(N) curve; beyond them this study ran 9 for the sensitivity; Jin et al. 2025: 20" in card
    assert f"{first.difference_text} ±0.15 absolute" in text


def test_the_calls_card_counts_the_validations_samples(tmp_path, nominal):
    from test_audit61l_report import _validation

    d = make_fixture_dir(tmp_path / "v", nominal, which=("wear", "reliability", "config"))
    _validation(ReliabilityCurve.load(d)).save(d)
    text = _text(_page(d))
    assert "for the whole R(N) curve; beyond them this study ran 400 for the validation" in text


def test_the_simulated_cycles_say_what_a_fraction_is():
    """'84.5 of them simulated': a half cycle needs a word (audit 61-L, D14)."""
    from types import SimpleNamespace

    from jointwear.report.study_sections import simulated_note

    wear = SimpleNamespace(cycles=70_000, n_simulated_cycles=84.5, n_blocks=28,
                           settings={"settle_cycles": 1.0, "record_cycles": 2})
    note = simulated_note(wear)
    assert note.startswith("84.5 of them simulated as dynamics: each of the 28 wear blocks settles 1 and records 2")
    assert "the fraction is a second chain of blocks started part of a cycle later" in note
    wear.n_simulated_cycles = 84.0
    assert "fraction" not in simulated_note(wear)
    wear.n_simulated_cycles = 70_000
    assert simulated_note(wear) is None


def test_a_glossary_explains_the_terms_the_page_uses(tmp_path, nominal):
    """ESC, nugget, surrogate, Q^2, hold_iterations and the paired verdicts were used without definition for a
    reader who did not run the study (audit 61-L, D11): a glossary at the foot explains those the page uses."""
    from test_audit61l_report import _validation

    from jointwear.report.glossary import TERMS

    d = make_fixture_dir(tmp_path / "g", nominal, which=("wear", "reliability", "config"))
    rel = ReliabilityCurve.load(d)
    rel.converged = False
    rel.learning_stop = ("max_calls=80 reached while confirming the learning stop (it held on 1 of the 3 successive "
                         "designs hold_iterations asks for)")
    rel.write(d)
    text = _text(_page(d))
    glossary = text[text.rindex("Glossary The terms of the trade"):]
    assert 'explained in the Glossary at its foot' in text
    for term in ("surrogate, Kriging", "hold_iterations, max_calls", "conformity"):
        assert term in glossary
    assert "inside, reaches it, exceeds it" not in glossary  # no validation: its verdicts are not on the page
    _validation(rel).save(d)
    glossary = _text(_page(d)).split("Glossary The terms of the trade")[-1]
    paired = next(meaning for term, _t, meaning in TERMS if term == "inside, reaches it, exceeds it")
    assert paired in glossary and "leave-one-out predictive R²" in glossary


def test_figure_captions_say_what_they_overlay_and_label_the_perfect_prediction(tmp_path, nominal):
    """The contact-force figure overlaid the recorded cycles without saying so; the cross-validation plot labelled
    its 1:1 line 'exact' and gave ln N_f no unit (audit 61-L, D14)."""
    import matplotlib.pyplot as plt

    from jointwear import load_results
    from jointwear.report.figures import cross_validation_figure

    fig = cross_validation_figure([10.0, 11.0], [10.1, 10.9], q2=0.9)
    ax = fig.axes[0]
    assert "1:1, a perfect prediction" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert "wear life in cycles" in ax.get_xlabel()
    plt.close(fig)
    d = make_fixture_dir(tmp_path / "f", nominal, which=("simulate",))
    sim = load_results(d).simulate
    sim.cycles, sim.settle_cycles = 2, 1  # the flores preset's two recorded cycles (the fixture records one)
    sim.write(d)
    text = _text(_page(d))
    assert "the 2 recorded cycles overlaid (after 1 settling cycle)" in text


def test_the_r_n_figure_draws_each_life_with_a_capped_interval():
    """The life's interval bar hid under its marker (32,399-33,638 cycles on a 20,000-70,000 axis) and the life at
    the second target (R = 0.99) was not drawn (audit 61-L, D14)."""
    import matplotlib.pyplot as plt

    from jointwear.report.figures import reliability_curve_figure

    cyc, rel = [2e4, 3e4, 4e4, 5e4], [0.999, 0.968, 0.539, 0.075]
    fig = reliability_curve_figure(cyc, rel, target=0.9, life_cycles=33_015, life_interval=(32_399, 33_638),
                                   other_lives=[(0.99, 27_673, 26_570, 29_052)])
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "life at R = 0.9: 33,015 cycles, 95 % interval 32,399-33,638 cycles" in labels
    assert "life at R = 0.99: 27,673 cycles, 95 % interval 26,570-29,052 cycles" in labels
    caps = [line for line in ax.lines if line.get_marker() == "|"]  # errorbar's end caps, two per life
    assert sorted(round(x, 3) for c in caps for x in c.get_xdata()) == [26.57, 29.052, 32.399, 33.638]
    plt.close(fig)


def test_the_mean_wear_is_drawn_on_its_own_joints_history(tmp_path, nominal):
    """The mean over the random inputs is the first judged joint's (the histograms name it); with joints A and E
    and E judged first it was drawn on A's history figure."""
    d = make_fixture_dir(tmp_path / "m", nominal, which=("wear", "reliability", "config"))
    _two_joint_wear(d)
    rel = ReliabilityCurve.load(d)
    rel.histograms["joint"] = "E"
    rel.write(d)
    text = _text(_page(d))
    mean = "the mean over the random inputs"
    a = text[text.index("Max bearing wear of joint A against cycles"):][:200]
    e = text[text.index("Max bearing wear of joint E against cycles"):][:200]
    assert mean not in a and mean in e
