"""Direct validation of the R(N) curve: the true model sampled directly against the surrogate.

The wear model is the analytic Archard-like law of tests/analytic_wear.py (exact R(N) by brute force), so the
validation must agree at every level, and the leave-one-out cross-validation of a smooth 3-variable product
must be nearly exact.
"""

import json

import numpy as np
import pytest
from analytic_wear import AnalyticWear
from result_keys import undocumented_keys

from jointwear import compute
from jointwear.config import load_config, updated
from jointwear.study import ReliabilityCurve, ValidationResult, run_reliability, study_context
from jointwear.study.io import strict
from jointwear.study.limit_state import interval_reach, life_at
from jointwear.study.validation import clopper_pearson, life_check, run_validation

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def test_clopper_pearson_exact_values():
    # k = 0: the upper bound solves (1 - p)^n = alpha / 2 exactly
    lo, hi = clopper_pearson(0, 100)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 100), rel=1e-9)
    lo, hi = clopper_pearson(100, 100)
    assert hi == 1.0 and lo == pytest.approx(0.025 ** (1 / 100), rel=1e-9)


def analytic_context():
    """The analytic wear model's study context: exact model, tight error tolerance (error_abs_tol 0.002)."""
    cfg = updated(load_config(), {
        "reliability.cycles_start": 320_000, "reliability.cycles_stop": 440_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [400_000], "reliability.n_mc": 20_000, "reliability.max_calls": 40,
        "reliability.noise": "none", "reliability.error_abs_tol": 0.002})
    return study_context(cfg, lambda call: compute.Evaluator(
        AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles), None, None,
        n_outputs=call.n_outputs))


def test_validation_agrees_with_an_exact_model():
    ctx = analytic_context()
    rel = run_reliability(ctx)
    val = run_validation(ctx, rel, 3000)
    assert val.n_samples == 3000 and val.model_calls == 3000 and val.failed_calls == 0
    again = run_validation(ctx, rel, 3000)  # the same samples, known: no new call (it said 3000 new calls)
    # a level without an error estimate stays without one (it was written as an error of 0)
    rel.pf_error = np.where(np.arange(len(rel.pf_error)) == 0, np.nan, rel.pf_error)
    unestimated = run_validation(ctx, rel, 3000)
    assert np.isnan(unestimated.surrogate_error[0]) and np.isfinite(unestimated.surrogate_error[1:]).all()
    assert again.model_calls == 0 and np.array_equal(again.reliability_mc, val.reliability_mc)
    # typed as the reliability's curves: arrays, also when read back from validation.json
    back = ValidationResult.from_json(json.loads(json.dumps(strict(val.to_json()))))
    assert back == val and back.reliability_mc.dtype == float and back.agreement.dtype == bool
    assert np.all(val.ci_high - val.ci_low >= 0)
    assert val.all_agree, list(zip(val.cycles, val.reliability_mc, val.reliability_surrogate))
    for lo, r, hi in zip(val.ci_low, val.reliability_mc, val.ci_high):
        assert lo <= r <= hi
    # the life on the true model's curve, with its interval, overlaps the surrogate's
    (row,) = val.life_table
    assert row["target"] == 0.9 and row["cycles_low"] <= row["cycles"] <= row["cycles_high"]
    assert row["surrogate_cycles"] == rel.life_cycles and row["agree"]
    cv = val.cross_validation
    # the analytic log life is smooth (a sum of logs): its leave-one-out Q^2 is near 1
    assert cv["q2"] > 0.95 and cv["n_points"] == len(rel.design_x)
    # it scores the surrogate behind R(N), not a Kriging fitted anew (the report showed two Q^2 for the same points)
    assert cv["q2"] == rel.surrogate_fit.q2
    np.testing.assert_allclose(cv["log_life_true"], np.log(ctx.life(np.asarray(rel.design_x))), rtol=1e-12)
    assert np.isfinite(cv["log_life_loo"]).all()


def test_life_check_reads_both_curves_and_says_when_their_intervals_miss():
    class Surrogate:  # R(N) = 1 - N / 1e6 with a band of +-0.01: life 1e5, interval 9e4-1.1e5
        cycles = np.linspace(0.0, 2e5, 11)
        reliability = 1.0 - cycles / 1e6

        def life(self, target):
            return life_at(self.cycles, self.reliability, target)

        def life_interval(self, target):
            return life_at(self.cycles, self.reliability - 0.01, target), life_at(
                self.cycles, self.reliability + 0.01, target)

        def life_reach(self, target):
            return interval_reach(self.cycles, self.reliability, np.full(self.cycles.size, 0.01), target)

    sur = Surrogate()
    # the true curve 0.02 lower (life 8e4) with exact bounds +-0.005: 7.5e4-8.5e4, no overlap with 9e4-1.1e5
    r = sur.reliability - 0.02
    row = life_check(sur.cycles, r, r - 0.005, r + 0.005, sur, 0.9)
    assert row["cycles"] == pytest.approx(8e4, rel=1e-12) and row["cycles_low"] == pytest.approx(7.5e4, rel=1e-12)
    assert row["cycles_high"] == pytest.approx(8.5e4, rel=1e-12) and row["surrogate_cycles"] == pytest.approx(1e5)
    assert not row["agree"]
    # bounds +-0.012 reach 9.2e4: the intervals overlap
    assert life_check(sur.cycles, r, r - 0.012, r + 0.012, sur, 0.9)["agree"]


def test_the_validate_line_names_the_levels_that_disagree():
    """'agreement at 10 of 11 levels' did not say which level missed, nor by how much."""
    res = ValidationResult(cycles=np.array([10_000, 20_000, 30_000, 40_000]),
                           reliability_mc=np.array([1.0, 0.683, 0.5, 0.2]), ci_low=np.array([0.9, 0.55, 0.4, 0.1]),
                           ci_high=np.array([1.0, 0.797, 0.6, 0.3]),
                           reliability_surrogate=np.array([1.0, 0.4985, 0.5, 0.45]),
                           surrogate_error=np.array([0.0, 0.031, 0.01, np.nan]), n_samples=60, model_calls=60,
                           wall_seconds=1.0, agreement=np.array([True, False, True, False]))
    assert res.disagreement() == ("not at 20,000 cycles: true model 0.683 [0.550, 0.797], surrogate 0.498 (its error "
                                  "estimate 0.031), 40,000 cycles: true model 0.200 [0.100, 0.300], surrogate 0.450")
    assert res.disagreement(shown=1).endswith("(its error estimate 0.031) and 1 more")
    res.agreement[:] = True
    assert res.disagreement() == ""


def test_the_95_percent_test_of_the_difference_is_stricter_than_overlapping_intervals():
    """Overlapping 95 % intervals were told as agreement at 95 %; a difference of 0.03 with a half-width of 0.02 on
    each side overlaps (0.03 < 0.04) but fails the test of the difference, sqrt(0.02^2 + 0.02^2) = 0.028."""
    res = ValidationResult(cycles=np.array([10_000, 20_000, 30_000]), reliability_mc=np.array([0.9, 0.9, 0.5]),
                           ci_low=np.array([0.88, 0.88, 0.45]), ci_high=np.array([0.92, 0.92, 0.52]),
                           reliability_surrogate=np.array([0.87, 0.88, 0.535]),
                           surrogate_error=np.array([0.02, 0.02, 0.0]), surrogate_cov=np.array([0.0, 0.0, 0.0]),
                           n_samples=1000, model_calls=1000, wall_seconds=1.0,
                           agreement=np.array([True, True, True]))
    # level 3: the true model's interval on the surrogate's side (0.02, not 0.05) is what the difference meets
    assert res.differs_at_95().tolist() == [True, False, True]
    assert res.differences_at_95() == "a 95 % test of the difference rejects 10,000 and 30,000 cycles"
    # the curve's Monte Carlo half-width 1.96 COV Pf counts too: COV 0.1 at Pf 0.13 adds 0.025 (sqrt -> 0.037)
    res.surrogate_cov = np.array([0.1, 0.0, 0.0])
    assert res.differs_at_95().tolist() == [False, False, True]



def test_the_files_hold_the_95_percent_test_the_report_shows(tmp_path):
    """The report's "95 % test" column was in neither validation.json nor validation.csv."""
    import csv
    import json

    res = ValidationResult(cycles=np.array([10_000, 20_000]), reliability_mc=np.array([0.9, 0.9]),
                           ci_low=np.array([0.88, 0.88]), ci_high=np.array([0.92, 0.92]),
                           reliability_surrogate=np.array([0.87, 0.88]), surrogate_error=np.array([0.02, 0.02]),
                           surrogate_cov=np.array([0.0, 0.0]), n_samples=1000, model_calls=1000, wall_seconds=1.0,
                           agreement=np.array([True, True]))
    res.save(tmp_path, figures=False)
    data = json.loads((tmp_path / "validation.json").read_text(encoding="utf-8"))
    assert data["differs_at_95"] == [True, False]
    np.testing.assert_allclose(data["surrogate_half_width_95"], [0.02, 0.02])  # its error estimate, no MC part
    with open(tmp_path / "validation.csv", encoding="utf-8", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [row["differs_at_95"] for row in rows] == ["True", "False"]
    assert ValidationResult.load(tmp_path) == res  # derived keys are not read back as data


def test_a_true_life_before_the_curve_does_not_agree_with_a_life_inside_it():
    """The true model's R below the target already at the first level (its life before 800,000 cycles) against a
    surrogate life of 1,000,000 (900,000-1,100,000): the missing ends counted as unbounded made them 'agree'."""
    from types import SimpleNamespace

    levels = np.linspace(8e5, 1.2e6, 5)
    r_mc = np.full(5, 0.5)
    sur = SimpleNamespace(life=lambda t: 1e6, life_interval=lambda t: (9e5, 1.1e6), life_reach=lambda t: (9e5, 1.1e6))
    check = life_check(levels, r_mc, r_mc - 0.05, r_mc + 0.05, sur, 0.9)
    assert (check["cycles"], check["cycles_low"], check["cycles_high"]) == (None, None, None)
    assert check["agree"] is False
    # a true life beyond the curve (R above the target to 1.2 M) does not agree with 0.9-1.1 M either
    high = np.full(5, 0.97)
    assert life_check(levels, high, high - 0.02, high + 0.02, sur, 0.9)["agree"] is False
    # and one whose band reaches the surrogate's interval does
    straight = 1.0 - levels / 1e7
    assert life_check(levels, straight, straight - 0.01, straight + 0.01, sur, 0.9)["agree"] is True


def test_a_target_beyond_what_the_samples_resolve_is_not_tested():
    """800 samples read R = 1 [0.9954, 1] at every early level; the life at R = 0.999 was still given (an
    interpolation between R = 1 and the first failure) and called in agreement."""
    from types import SimpleNamespace

    levels = np.linspace(2e5, 4e5, 11)
    r_mc = np.where(levels < 3.2e5, 1.0, 0.99)
    sur = SimpleNamespace(life=lambda t: 2.9e5, life_interval=lambda t: (2.85e5, 3.0e5),
                          life_reach=lambda t: (2.85e5, 3.0e5))
    resolved = 0.025 ** (1 / 800)  # Clopper-Pearson's lower bound of R with no failure in 800
    check = life_check(levels, r_mc, r_mc - 0.005, r_mc, sur, 0.999, n_samples=800)
    assert check["cycles"] is None and check["agree"] is None
    assert check["note"] == f"not testable: 800 samples resolve R up to {resolved:.4g}" and resolved < 0.999
    assert check["surrogate_cycles"] == 2.9e5
    assert life_check(levels, r_mc, r_mc - 0.005, r_mc, sur, 0.99, n_samples=800)["agree"] is not None


@pytest.fixture(scope="module")
def analytic_study():
    """The analytic study's context and its learnt curve (not to be changed by a test: the module shares it)."""
    ctx = analytic_context()
    return ctx, run_reliability(ctx)


class _TrueModelAsSurrogate:
    """The learnt engine with its failure probabilities replaced by the true model's, every life scaled by ``factor``,
    at the validation's own samples (whose true lives it holds, in order); the rest (the cross-validation's Kriging)
    is the engine's."""

    def __init__(self, engine, life: np.ndarray, factor: float):
        self.engine, self.life, self.factor = engine, life, factor

    def __getattr__(self, name):
        return getattr(self.engine, name)

    def failure_probabilities(self, u, noise_sd=0.0, thresholds=None):
        assert u.shape[0] == self.life.size and noise_sd == 0.0
        return (self.factor * self.life[:, None] <= np.exp(thresholds)[None, :]).astype(float)


def test_the_surrogate_read_on_the_validations_own_samples_measures_its_own_error(analytic_study):
    """The surrogate against the true model on the same samples: exactly no difference for a surrogate that is the
    true model, exactly the samples' share between the two lives for one that reads every life 3 % long, and that
    life's ratio within the curve's interpolation (one grid interval of :func:`curve_cycles` on each life)."""
    from dataclasses import replace

    from jointwear.study.limit_state import curve_cycles
    from jointwear.study.validation import SEED_OFFSET

    ctx, rel = analytic_study
    n = 1000
    life = ctx.life(ctx.sample(n, ctx.config.reliability.seed + SEED_OFFSET))
    exact = run_validation(ctx, replace(rel, engine=_TrueModelAsSurrogate(rel.engine, life, 1.0)), n)
    assert exact.paired and exact.n_samples == n
    np.testing.assert_array_equal(exact.paired_reliability_surrogate, exact.reliability_mc)
    assert not exact.paired_difference_low.any() and not exact.paired_difference_high.any()
    row = exact.life_table[0]
    assert row["paired_ratio"] == row["paired_ratio_low"] == row["paired_ratio_high"] == 0.0
    assert row["paired_surrogate_cycles"] == row["cycles"]

    long = run_validation(ctx, replace(rel, engine=_TrueModelAsSurrogate(rel.engine, life, 1.03)), n)
    levels = exact.cycles.astype(float)
    share = ((life[:, None] <= levels) & (1.03 * life[:, None] > levels)).mean(axis=0)  # safe only on the surrogate
    np.testing.assert_allclose(long.paired_difference(), share, rtol=0, atol=1e-12)
    assert np.all(long.paired_difference_low <= share) and np.all(share <= long.paired_difference_high)
    row = long.life_table[0]
    grid = np.diff(curve_cycles(levels)).max()
    assert abs(row["paired_surrogate_cycles"] - 1.03 * row["cycles"]) <= 2 * grid
    assert row["paired_ratio_low"] <= row["paired_ratio"] <= row["paired_ratio_high"]
    assert 0.0 < row["paired_ratio_low"]  # 3 % long is seen: the interval excludes no error
    assert long.paired_life_sentence().startswith(
        f"on the same samples the surrogate's life at R = 0.9 is {row['paired_surrogate_cycles']:,.0f} cycles, 3.0 % "
        f"above the true model's {row['cycles']:,.0f} (95 % interval +")


def test_the_learnt_surrogate_on_the_same_samples_is_within_its_error_estimate(analytic_study):
    """On the exact analytic model the learnt surrogate's error, measured on the validation's samples, lies within its
    own error estimate at every level, and the paired interval is narrower than the true model's own (the noise the
    two share cancels)."""
    ctx, rel = analytic_study
    val = run_validation(ctx, rel, 3000)
    assert val.paired and val.paired_within_error().all(), (val.paired_difference(), val.surrogate_error)
    assert np.all(val.paired_difference_high - val.paired_difference_low < val.ci_high - val.ci_low)
    row = val.life_table[0]
    assert row["paired_ratio_low"] <= 0.0025 and row["paired_ratio_high"] >= -0.0025  # error_abs_tol's reach
    back = ValidationResult.from_json(json.loads(json.dumps(strict(val.to_json()))))
    assert back == val and back.paired_reliability_surrogate.dtype == float


def test_the_paired_check_tells_inside_reaching_and_exceeding_the_error_estimate(analytic_study):
    """'within its error estimate at 11 of 11 levels' was printed where the surrogate erred by up to 1.3 times its
    estimate: an interval that merely reaches +- e is not refuted, not shown. Three degrees, and the largest ratio,
    on made-up differences of known place (e = 0.01, the paired interval +- 0.005)."""
    from dataclasses import replace

    ctx, rel = analytic_study
    val = run_validation(ctx, rel, 200)
    n = len(val.cycles)
    d = np.zeros(n)
    d[0], d[1] = 0.012, -0.03  # reaches +-e (0.007 <= 0.01), exceeds it (-0.025 < -0.01)
    made = replace(val, reliability_mc=np.full(n, 0.5), paired_reliability_surrogate=0.5 + d,
                   paired_difference_low=d - 0.005, paired_difference_high=d + 0.005, surrogate_error=np.full(n, 0.01))
    np.testing.assert_array_equal(made.paired_inside_error(), np.r_[False, False, np.ones(n - 2, bool)])
    np.testing.assert_array_equal(made.paired_within_error(), np.r_[True, False, np.ones(n - 2, bool)])
    np.testing.assert_allclose(made.paired_error_ratio(), np.abs(d) / 0.01)
    assert made.paired_error_sentence() == (
        f"on the same samples the curve's difference from the true model lies inside its error estimate at {n - 2} of "
        f"{n} levels (its 95 % interval within +- the estimate), reaches it at 1 more, and exceeds it at 1; the "
        f"largest is 3 times the estimate (at {val.cycles[1]:,.0f} cycles)")


def test_a_validation_too_small_for_the_target_still_reads_the_levels_paired(analytic_study):
    """10 samples resolve R up to 0.69: the life at R = 0.9 is not tested (nor paired), the levels are."""
    ctx, rel = analytic_study
    val = run_validation(ctx, rel, 10)
    assert val.life_table[0]["cycles"] is None and "paired_ratio" not in val.life_table[0]
    assert val.paired and val.paired_difference_low.shape == val.cycles.shape
    assert val.paired_life_sentence() == "" and val.paired_life_allowed() is None
    assert val.unpaired_life_sentence() == ""  # not tried (too few samples): nothing to explain


def test_a_paired_life_outside_the_curve_is_told_why_it_is_missing(analytic_study):
    """100 samples of a designer's compressor read the surrogate's R at the first level below the target: the paired
    life was missing from the validate line without a word."""
    import dataclasses

    ctx, rel = analytic_study
    val = run_validation(ctx, rel, 200)
    row = {**val.life_table[0], "paired_ratio": None, "paired_surrogate_cycles": None}
    before = dataclasses.replace(val, life_table=[row],
                                 paired_reliability_surrogate=np.full_like(val.paired_reliability_surrogate, 0.5))
    assert before.unpaired_life_sentence() == (
        f"on the same samples the surrogate's life lies before the curve's first level at R = {row['target']:g}, so "
        "the two lives are not compared (a curve that starts or ends further would compare them)")
    assert before.paired_life_sentence() == "" and val.unpaired_life_sentence() == ""


def test_a_curve_read_back_from_disk_is_validated_unpaired(analytic_study, tmp_path):
    """A result loaded from its folder holds no surrogate: the validation runs as before, without the paired check."""
    ctx, rel = analytic_study
    rel.save(tmp_path, figures=False)
    val = run_validation(ctx, ReliabilityCurve.load(tmp_path), 200)
    assert not val.paired and val.paired_difference() is None and val.paired_life_sentence() == ""
    assert "paired_ratio" not in val.life_table[0]


def test_the_validations_samples_are_kept_and_recount_its_curve(analytic_study, tmp_path):
    """The direct Monte Carlo is handed over: the samples the true model ran on (in SI, as config keys with their
    units) and the life each gave; counting them again gives the validation's R at every level exactly, also from
    the CSV it writes (a reliability engineer's own estimator needs them; they were not exposed)."""
    import pandas as pd

    from jointwear.study.validation import SEED_OFFSET

    ctx, rel = analytic_study
    val = run_validation(ctx, rel, 300)
    x = ctx.sample(300, ctx.config.reliability.seed + SEED_OFFSET)
    np.testing.assert_array_equal(val.sample_x, x)
    np.testing.assert_array_equal(val.sample_life, ctx.life(x))
    assert val.names == ctx.names and val.units == ctx.units
    p_inf = ctx.config.uncertainty.infeasible_probability()
    recount = [1.0 - (p_inf + (1.0 - p_inf) * np.mean(val.sample_life <= n)) for n in val.cycles]
    np.testing.assert_allclose(recount, val.reliability_mc, rtol=0, atol=1e-15)
    val.save(tmp_path, figures=False)
    table = pd.read_csv(tmp_path / "validation_samples.csv")
    assert list(table.columns) == [*rel.frame("design_points").columns[:len(ctx.names)], "life_cycles"]
    # the CSV's 10 significant digits (jointwear.study.io.csv_cell): half a unit of the last
    np.testing.assert_allclose(table.to_numpy()[:, :-1], x, rtol=5e-10)
    np.testing.assert_allclose(table["life_cycles"], val.sample_life, rtol=5e-10)
    back = ValidationResult.load(tmp_path)
    assert back == val and back.sample_x.shape == (300, len(ctx.names))
    assert undocumented_keys(tmp_path / "validation.json") == []  # docs/results.md (tests/result_keys.py)
    # a validation.json written before the samples were kept still reads, without them
    old = {k: v for k, v in json.loads(json.dumps(strict(val.to_json()))).items()
           if k not in ("sample_x", "sample_life", "names", "units")}
    older = ValidationResult.from_json(old)
    assert older.sample_x is None and "validation_samples" not in older.tables()


def test_a_paired_error_beyond_the_lifes_interval_is_told_from_the_interval_it_allows():
    """The life 373,680 (368,297-378,809) allows a learnt life from 373,680 / 378,809 - 1 = -1.35 % to
    373,680 / 368,297 - 1 = +1.46 % of the true one; a paired error of -2.3 % to -1.4 % lies beyond it, one of
    -2.3 % to -1.3 % across its edge, one of -1.3 % to +1.0 % within it. A point estimate outside with an interval
    across the edge was called within (the reviewer's +5.2 % (+1.2 % to +9.4 %) against -3.5 % to +3.8 %)."""
    row = {"target": 0.9, "cycles": 381_429.0, "surrogate_cycles": 373_680.0, "surrogate_cycles_low": 368_297.0,
           "surrogate_cycles_high": 378_809.0, "paired_ratio": -0.018, "paired_ratio_low": -0.023,
           "paired_ratio_high": -0.014}
    val = ValidationResult(cycles=[1], reliability_mc=[0.9], ci_low=[0.88], ci_high=[0.92],
                           reliability_surrogate=[0.9], surrogate_error=[0.01], n_samples=2000, model_calls=0,
                           wall_seconds=1.0, agreement=[True], life_table=[row])
    low, high, verdict = val.paired_life_allowed()
    assert low == pytest.approx(373_680 / 378_809 - 1) and high == pytest.approx(373_680 / 368_297 - 1)
    assert verdict == "beyond"
    row["paired_ratio_high"] = -0.013  # across the edge: these samples cannot tell
    assert val.paired_life_allowed(0.9)[2] == "unresolved"
    row["paired_ratio_low"], row["paired_ratio_high"] = -0.013, 0.01
    assert val.paired_life_allowed(0.9)[2] == "within"
    assert val.paired_life_allowed(0.5) is None  # no such target
    del row["paired_ratio_low"]
    assert val.paired_life_allowed() is None  # a validation without the paired check


def test_agreement_is_overlap_on_the_side_that_faces_the_surrogate():
    """90 of 100 samples survive: exact interval [0.8238, 0.9510]. A surrogate of 0.99 +- 0.02 (from 0.97) does not
    overlap it; the larger side (0.9 - 0.8238 = 0.076) let it agree. One of 0.96 +- 0.02 overlaps."""
    from jointwear.study.validation import agreement

    lo, hi = clopper_pearson(90, 100)
    assert agreement([0.9], [lo], [hi], [0.99], [0.02]).tolist() == [False]
    assert agreement([0.9], [lo], [hi], [0.96], [0.02]).tolist() == [True]
    assert agreement([0.9], [lo], [hi], [0.82], [0.02]).tolist() == [True]  # below: the long side faces it
