"""Audit 61-L's findings on the report (the slider-crank study with a 400-sample validation): one verdict on the
life after a validation, the validation of every target, the convergence figure's estimator, the paired verdict in
validation.csv, the provenance, the correlations, the non-convergence remedy and the minor captions."""

from __future__ import annotations

import html
import re

import pytest
from report_fixtures import make_fixture_dir

from jointwear.report import build_report
from jointwear.study.results import ReliabilityCurve

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read text, not pictures


def _page(folder) -> str:
    return html.unescape(build_report(folder).read_text(encoding="utf-8"))


def _text(page: str) -> str:
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", page)).replace(" :", ":")


def _validation(rel, *, ratio=-0.019, ratio_low=-0.036, ratio_high=-0.006, agree=False, targets=None, **kw):
    """A paired validation in the audit's shape: the surrogate's life 1.9 % short on the same samples (95 %:
    -3.6 % to -0.6 %), the unpaired intervals apart, one level whose intervals do not overlap."""
    from jointwear.study.results import ValidationResult

    life = rel.life()
    low, high = rel.life_interval()
    rows = []
    for target in targets or (rel.target,):
        t_life = rel.life(target) if target != rel.target else life
        t_low, t_high = rel.life_interval(target)
        true = t_life / (1 + ratio)
        rows.append({"target": target, "cycles": 1.045 * t_life, "cycles_low": 1.03 * t_life,
                     "cycles_high": 1.065 * t_life, "surrogate_cycles": t_life, "surrogate_cycles_low": t_low,
                     "surrogate_cycles_high": t_high, "agree": agree, "paired_surrogate_cycles": true * (1 + ratio),
                     "paired_ratio": ratio, "paired_ratio_low": ratio_low, "paired_ratio_high": ratio_high})
    assert (low, high) == rel.life_interval()
    args = dict(cycles=[360_000, 400_000], reliability_mc=[0.995, 0.8], ci_low=[0.982, 0.78], ci_high=[0.999, 0.82],
                reliability_surrogate=[0.968, 0.805], surrogate_error=[0.012, 0.01], n_samples=400, model_calls=400,
                wall_seconds=1.0, agreement=[False, True], paired_reliability_surrogate=[0.9834, 0.79],
                paired_difference_low=[-0.025, -0.014], paired_difference_high=[-0.001, -0.006], seed=3025,
                life_table=rows)
    args.update(kw)
    return ValidationResult(**args)


def test_the_summary_and_the_reliability_section_give_one_verdict_on_the_life(tmp_path, nominal):
    """The summary said 'the 95 % intervals do not overlap, so the life above carries more error than its interval
    says' (the unpaired check) while the reliability section said the paired check could not tell; the summary
    also read 'at 1 of 11 levels, not at 30,000 cycles' for 'at 30,000 cycles'."""
    d = make_fixture_dir(tmp_path / "v", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    low, high = rel.life_interval()
    allowed = (rel.life() / high - 1, rel.life() / low - 1)
    _validation(rel, ratio_low=min(-0.036, allowed[0] - 0.01), ratio_high=max(-0.006, allowed[0] + 0.001)).save(d)
    page = _text(_page(d))
    verdict = re.search(r"How far to trust the life: the validation below ran this study's true model on 400 "
                        r"samples; (.*?)\. ", page).group(1)
    assert "the learnt life reads 1.9 % short (95 %: " in verdict and "on the safe side" in verdict
    assert "across the edge of what the life's 95 % interval allows" in verdict
    # the summary gives the same verdict, not the unpaired one
    assert f"The life's error reaches the edge of its interval: against 400 direct runs of the true model, {verdict}" \
        in page
    assert "so the life above carries more error than its interval says" not in page
    assert "The unpaired 95 % intervals" in page and "partly from these samples' own draw" in page
    assert "the validation's error reaches the interval's edge (caveats below)" in page
    # the level that disagrees, said as where it disagrees, with the paired check's word on it
    assert "at 1 of 2 levels (360,000 cycles: true model 0.995" in page and "not at 360,000" not in page
    assert "on the same samples the surrogate's difference reaches its error estimate" in page


def test_a_long_life_is_said_to_be_on_the_unsafe_side(tmp_path, nominal):
    d = make_fixture_dir(tmp_path / "l", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    _validation(rel, ratio=0.05, ratio_low=0.04, ratio_high=0.06).save(d)
    page = _text(_page(d))
    assert "the learnt life reads 5.0 % long (95 %: 4.0-6.0 % long), on the unsafe side" in page
    assert "The life errs by more than its interval says: against 400 direct runs" in page


def test_the_unpaired_non_overlap_is_the_verdict_only_without_a_paired_check(tmp_path, nominal):
    d = make_fixture_dir(tmp_path / "u", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    val = _validation(rel, paired_reliability_surrogate=None, paired_difference_low=None, paired_difference_high=None)
    for row in val.life_table:
        for key in ("paired_surrogate_cycles", "paired_ratio", "paired_ratio_low", "paired_ratio_high"):
            row.pop(key)
    val.save(d)
    page = _text(_page(d))
    assert "The true model's life disagrees with the curve's: at R = " in page
    assert "at 1 of 2 levels (360,000 cycles: true model 0.995" in page


def test_the_unvalidated_trust_sentence_reads_plainly():
    from jointwear.report.result_sections import LIFE_TRUST

    assert "read so" not in LIFE_TRUST and "On the flapping-wing presets the learnt lives are 1.8 %" in LIFE_TRUST


def test_validation_csv_has_the_reports_paired_verdict(tmp_path, nominal):
    """validation.csv's paired_within_error is True where the report says 'reaches it': paired_verdict gives the
    report's own classification."""
    d = make_fixture_dir(tmp_path / "c", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    val = _validation(rel, paired_difference_low=[-0.025, -0.009], paired_difference_high=[-0.001, -0.006],
                      paired_reliability_surrogate=[0.9834, 0.7925])
    table = val.tables()["validation"]
    assert list(table["paired_within_error"]) == [True, True]
    assert list(table["paired_verdict"]) == ["reaches", "inside"]
    val.save(d)
    csv = (d / "validation.csv").read_text(encoding="utf-8").splitlines()
    col = csv[0].split(",").index("paired_verdict")
    assert [line.split(",")[col] for line in csv[1:]] == ["reaches", "inside"]
    page = _text(_page(d))
    assert "(reaches it)" in page and "(inside)" in page
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from result_keys import undocumented_keys

    for name in ("validation.csv", "validation_life.csv", "validation.json"):
        assert undocumented_keys(d / name) == [], name  # docs/results.md


def test_every_targets_validated_life_is_shown(tmp_path, nominal):
    """validation_life.csv held the R = 0.99 life (true 30,962; paired -5.8 %) but the report showed R = 0.9's only."""
    d = make_fixture_dir(tmp_path / "t", nominal, which=("reliability",))
    rel = ReliabilityCurve.load(d)
    targets = [rel.target, 0.95]  # the study's second target (its life table's rows are not needed here)
    _validation(rel, targets=targets).save(d)
    page = _text(_page(d))
    section = page[page.index("Validation against the true model"):]
    for target in targets:
        life = rel.life(target)
        assert f"{target:g} {1.045 * life:,.0f} (" in section, target
    assert "surrogate / true \u2212 1 on the same samples (95 %)" in section


def _with_scatter(d):
    """The fixture's reliability with a fitted call-to-call scatter of the life (3.6 %), as the slider-crank's."""
    from jointwear.study.reliability_results import SurrogateFit

    rel = ReliabilityCurve.load(d)
    rel.surrogate_fit = SurrogateFit.from_json({"n_points": 38, "q2": 0.9, "rmse_log_life": 0.05,
                                                "noise_sd_log_life": 0.0354, "process_sd_log_life": 0.2,
                                                "relative_nugget": 0.03, "nugget_at_bound": False})
    rel.write(d)
    return rel


def test_the_convergence_figure_says_its_estimator_and_gives_the_curves_pf(tmp_path, nominal):
    """The convergence figure read 'final Pf = 0.7592' beside the R(N) table's 0.7521 at the same level: the
    learning's estimator (the surrogate mean's sign) without the life's call-to-call scatter that R(N) counts."""
    d = make_fixture_dir(tmp_path / "k", nominal, which=("reliability",))
    rel = _with_scatter(d)
    level = float(rel.convergence["cycles"])
    curve_pf = float(rel.pf[[float(c) for c in rel.cycles].index(level)])
    assert f"{rel.convergence['pf'][-1]:.4g}" != f"{curve_pf:.4g}"
    page = _text(_page(d))
    assert ("it is the learning's own estimator, the share of its Monte Carlo population whose surrogate mean fails, "
            "without the life's call-to-call scatter that R(N) counts") in page
    assert f"the curve's Pf there ({curve_pf:.4g}, dashed)" in page


def test_the_convergence_figure_draws_the_curves_pf_beside_the_learnings():
    import numpy as np

    from jointwear.report import figures as F

    fig = F.convergence_figure(np.arange(12, 20), np.linspace(0.8, 0.76, 8), curve_pf=0.7521)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "R(N) curve's Pf = 0.7521 (with the scatter)" in labels
    assert "the learning's Pf (surrogate mean, no call-to-call scatter)" in labels
    assert "learning's last Pf = 0.76" in [t.get_text() for t in fig.axes[0].texts]


def test_the_report_shows_the_provenance_and_the_seeds(tmp_path, nominal):
    """The report said 'jointwear 0.1.0' only; the results record the commit, the host CPU, the versions and the
    seeds."""
    d = make_fixture_dir(tmp_path / "p", nominal, which=("reliability", "config"))
    rel = ReliabilityCurve.load(d)
    rel.provenance = {"jointwear": "0.1.0+gf75291d", "python": "3.11.7", "numpy": "2.4.6", "scipy": "1.17.1",
                      "numba": "0.68.1", "openturns": "1.27.post1", "written_at": "2026-11-29T18:04:00+00:00",
                      "machine": {"llvm_host_cpu": "znver3", "cpus": 2}}
    rel.write(d)
    _validation(rel).save(d)
    page = _text(_page(d))
    assert "results by jointwear 0.1.0+gf75291d on znver3 (2 CPUs)" in page  # the footer
    prov = page[page.index("Provenance"):]
    assert "reliability 0.1.0+gf75291d znver3, 2 CPUs python 3.11.7, numpy 2.4.6, scipy 1.17.1, numba 0.68.1, " \
        "openturns 1.27.post1" in prov
    assert "the validation's seed 3025 and its 400 samples" in prov


def test_the_random_inputs_show_their_correlations():
    from jointwear.report.study_sections import correlation_part

    cfg = {"study_config": {"uncertainty": {"correlation": {"pairs": [["Rj", "c", -0.537]], "measure": "pearson"}}}}
    assert "Rj and c: -0.537" in correlation_part(cfg) and "pearson" in correlation_part(cfg)
    cfg = {"study_config": {"uncertainty": {"correlation": {"variables": ["a", "b"], "matrix": [[1, 0.3], [0.3, 1]]}}}}
    assert "a and b: +0.3" in correlation_part(cfg)
    assert "independent" in correlation_part({})


def test_a_learning_out_of_budget_names_the_remedy_and_why_its_stop_held(tmp_path, nominal):
    """The non-convergence caveat gave no remedy, and a card said the stop 'held' beside an error three times its
    tolerance: the stop tests ESC's count only, the error shown adds the Kriging's posterior spread."""
    import numpy as np

    from jointwear import load_results

    d = make_fixture_dir(tmp_path / "b", nominal, which=("reliability", "config"))
    results = load_results(d)
    assert results.setting("reliability.stopping") == "error", "the fixture's rule"
    tol = results.setting("reliability.error_abs_tol")
    rel = ReliabilityCurve.load(d)
    rel.converged = False
    rel.learning_stop = ("max_calls=38 reached while confirming the learning stop (it held on 1 of the 3 successive "
                         "designs hold_iterations asks for)")
    rel.pf_error = np.full(rel.cycles.size, 3.0 * tol)
    rel.pf_error_esc = np.full(rel.cycles.size, 0.5 * tol)
    rel.write(d)
    raw = build_report(d).read_text(encoding="utf-8")
    assert "&lt;code&gt;" not in raw  # the caveat is text: its markup was shown as written
    page = _text(html.unescape(raw))
    assert "Raise reliability.max_calls" in page and "run again with --resume" in page
    assert "the stop tests ESC's count of misclassified samples only" in page
    assert "the error shown adds the Kriging's posterior spread" in page
    rel.pf_error_esc = np.full(rel.cycles.size, 2.0 * tol)  # ESC's part over the tolerance: the stop did not hold so
    rel.write(d)
    page = _text(_page(d))
    assert "Raise reliability.max_calls" in page and "the stop tests ESC's count" not in page


def test_minor_captions_times_and_probabilities_read_right(tmp_path, nominal):
    """The histogram caption called its own 100,000 samples the curve's population (200,000); the wear history's
    caption kept '(if computed; ...'; a 5.5-minute life read '0.09 h'; the R(N) table printed R = 1 beside
    Pf = 3.9e-06."""
    from jointwear.report.result_sections import probability_pair, running_time

    assert running_time(0.0917) == "5.5 min" and running_time(0.11) == "6.6 min" and running_time(13.04) == "13 h"
    assert probability_pair(1 - 3.943e-06, 3.943e-06) == ("1 \u2212 3.9e-06", "3.943e-06")
    assert probability_pair(4.752e-05, 1 - 4.752e-05) == ("4.752e-05", "1 \u2212 4.8e-05")
    d = make_fixture_dir(tmp_path / "m", nominal)
    rel = ReliabilityCurve.load(d)
    rel.histograms.update({"n_samples_shown": 2000, "n_population": 100_000})
    rel.write(d)
    page = _text(_page(d))
    assert ("2,000 of the 100,000 samples drawn for these histograms, the wear read from the life surrogate (the "
            f"curve and the tables read the study's own population of {rel.n_mc:,}") in page
    assert "if computed" not in page
    assert f"{rel.target:g} {rel.life():,.0f}" in page and running_time(rel.life_hours) in page


def test_a_call_count_goal_is_not_passed_by_a_learning_its_budget_ended(tmp_path, nominal):
    """The default report passed 'at most 80 true-model calls ..., its learning stop confirmed' on a learning the
    budget of 80 calls ended; its summary's life card also dropped the 95 % interval beside the reference's."""
    from jointwear import load_results
    from jointwear.report.reference_checks import FAIL, PASS, reference_checks

    d = make_fixture_dir(tmp_path / "r", nominal, which=("wear", "reliability", "config"))
    results = load_results(d)

    def check():
        return next(c for c in reference_checks(results) if c.quantity.startswith("true-model calls"))

    results.reliability.model_calls = 80
    assert check().status == PASS
    results.reliability.converged = False
    assert check().status == FAIL and "the learning did not converge" in check().note
    page = _text(_page(d))
    summary = page[page.index("life at R = 0.9"):][:300]  # the summary's card, the first on the page
    low, high = ReliabilityCurve.load(d).life_interval()
    assert f"95 % interval {low:,.0f}-{high:,.0f} cycles;" in summary  # beside the reference's value


def test_the_life_card_says_what_it_judges_and_an_unjudged_wear_says_when(tmp_path, nominal):
    """The summary's life card did not name the quantity, joint, allowance or wear mode; the unjudged journal's
    caveat never said when it reaches the allowance (30,300 cycles, before the life of 33,015)."""
    from jointwear.study.results import WearSummary

    d = make_fixture_dir(tmp_path / "j", nominal, which=("wear", "reliability", "config"))
    rel = ReliabilityCurve.load(d)
    wear = WearSummary.load(d)
    joint = wear.joints[0]
    joint["allowance_mm"] = 0.03
    joint["journal"]["max_wear_mm"] = 0.06
    life = rel.life()
    joint["history"] = {"cycles": [0.0, 0.5 * life, life], "max_wear_mm": [0.0, 0.01, 0.02],
                        "max_journal_wear_mm": [0.0, 0.02, 0.04], "clearance_growth_mm": [0.0, 0.03, 0.06]}
    wear.write(d)
    page = _text(_page(d))
    card = page[page.index("life at R = 0.9"):][:400]
    assert "the max wear depth of joint A's bearing reaching 0.03 mm" in card
    assert f"the nominal journal reaches the allowance at about {0.75 * life:,.0f} cycles, before the life at " \
        f"R = 0.9 ({life:,.0f} cycles)" in page
