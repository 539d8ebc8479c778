"""What the design says of a candidate and of its verification: exact intervals, the share outside the study's
inputs in the error, the verification's verdict, and which candidates are left undecided."""

import numpy as np
import pytest
from design_fixtures import FixedPopulationSpace
from scipy import stats

from jointwear.design.results import DesignResult
from jointwear.design.search import estimate, monte_carlo_half_width, surviving

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


@pytest.mark.parametrize("k, n", [(10, 10), (0, 10), (9_000, 10_000), (49_000, 50_000)])
def test_the_monte_carlo_half_width_is_the_exact_interval(k, n):
    """Clopper-Pearson: the normal approximation gave 0 for R = 1.0000 of 10 samples (a user's n_population = 10)."""
    ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="exact")
    assert monte_carlo_half_width(k, n) == pytest.approx(max(k / n - ci.low, ci.high - k / n), rel=1e-9)
    if k == n:  # the closed form at the edge: lower bound 0.025^(1/n)
        assert monte_carlo_half_width(k, n) == pytest.approx(1 - 0.025 ** (1 / n), rel=1e-12)


def _space(n):
    """Every candidate's population: ``n`` points, each with a standard-normal life-scatter draw (seed 0)."""
    return FixedPopulationSpace(n, dim=2, scatter=np.random.default_rng(0).standard_normal(n))


class _Surrogate:
    """Every point predicted far above the target with a tiny variance; ``share`` of them outside the design."""

    scatter_sd = 0.0
    per_joint = False

    def __init__(self, share):
        self.share = share

    def predict(self, u):
        return np.full(u.shape[0], 20.0), np.full(u.shape[0], 1e-3)

    def outside(self, u):
        return np.arange(u.shape[0]) < self.share * u.shape[0]


@pytest.mark.parametrize("share", [0.0, 0.05, 1.0])
def test_a_candidate_drawn_outside_the_studys_inputs_carries_that_share_in_its_error(share):
    """A PTFE option 8 standard deviations out read R(N*) = 1.0000 +/- 0.0000; its own study gave a life 1.8x
    the design's: the share outside may be misclassified wholesale."""
    n = 2_000
    est = estimate(_space(n), _Surrogate(share), None, log_target=10.0, reliability_target=0.9)
    assert est.reliability == 1.0 and est.surrogate_error == pytest.approx(0.0, abs=1e-12)
    assert est.outside_fraction == pytest.approx(share)
    assert est.error == pytest.approx(min(monte_carlo_half_width(n, n) + share, 1.0), rel=1e-9)


def _result(verification, refinement=None, r_star=0.9):
    return DesignResult(target_life_cycles=1e6, target_reliability=r_star, chosen={"choices": {"fit": "H7/g6"}},
                        pareto=[], verification=verification, model_calls=10, wall_seconds=1.0,
                        refinement=refinement or {})


@pytest.mark.parametrize("r, err, verdict, words", [
    (0.95, 0.01, "meets", "it meets R* beyond its error"),
    (0.895, 0.006, "within_error", "lies within its error, so the target is not excluded, nor proven"),
    (0.85, 0.01, "misses", "it misses R* = 0.9"),
])
def test_the_verification_says_whether_it_meets_the_target_beyond_its_error(r, err, verdict, words):
    """A verified 0.895 +/- 0.006 read 'confirms R(N*) >= R*'."""
    res = _result({"reliability_at_target_life": r, "error": err, "model_calls": 30, "confirmed": r + err >= 0.9,
                   "converged": False})
    assert res.verdict() == verdict
    sentence = res.verification_sentence()
    assert words in sentence and "stopped on its budget of calls" in sentence
    # a Kriging stopped by its budget may understate its error (0.0034 where a study of the design gave 0.012)
    assert "and may be too small" in sentence


def test_a_verification_whose_surrogate_fits_poorly_says_so_with_the_cure():
    """A designer's verification read R(N*) = 0.77 +/- 0.13 where four other readings gave 0.90-0.975: its 16 calls
    held an initial point at a wear coefficient near zero that its constant-trend Kriging could not follow, and the
    verification said nothing of its fit. Its fit is recorded and a poor one told, with the Archard trend as cure."""
    from jointwear.study.reliability_results import SurrogateFit

    poor = SurrogateFit(n_points=16, q2=0.2, rmse_log_life=1.3, noise_sd_log_life=1e-3, process_sd_log_life=1.0,
                        relative_nugget=1e-6, nugget_at_bound=False, worst_share=0.9, worst_life_ratio=60.0,
                        archard_trend_hint=True)
    ver = {"reliability_at_target_life": 0.7715, "error": 0.1332, "model_calls": 16, "confirmed": True,
           "converged": False}
    sentence = _result({**ver, "surrogate_fit": poor.to_json()}).verification_sentence()
    assert "; in that study the life surrogate explains little of its 16 design points" in sentence
    assert "its life is 60 times the points' median" in sentence and "reliability.trend = 'archard'" in sentence
    fine = SurrogateFit(n_points=16, q2=0.99, rmse_log_life=0.01, noise_sd_log_life=1e-3, process_sd_log_life=1.0,
                        relative_nugget=1e-6, nugget_at_bound=False)
    assert "in that study" not in _result({**ver, "surrogate_fit": fine.to_json()}).verification_sentence()
    # the designer's verification itself: Q^2 = 0.81, one point of 35 times the median life with 91 % of the error
    far = SurrogateFit(n_points=16, q2=0.81, rmse_log_life=0.527, noise_sd_log_life=1.4e-4, process_sd_log_life=1.44,
                       relative_nugget=1e-8, nugget_at_bound=False, worst_share=0.91, worst_life_ratio=35.1,
                       archard_trend_hint=True)
    sentence = _result({**ver, "surrogate_fit": far.to_json()}).verification_sentence()
    assert ("; in that study one of the life surrogate's 16 design points carries 91 % of its leave-one-out error "
            "(Q^2 = 0.81") in sentence and "R(N) may be off by more than its error says" in sentence
    assert "reliability.trend = 'archard'" in sentence
    assert "in that study" not in _result(ver).verification_sentence()  # a design.json written before


def test_a_choice_not_verified_says_so():
    res = _result({"reliability_at_target_life": None, "error": None, "model_calls": 0, "confirmed": False,
                   "note": "design.verify = false"})
    assert res.verdict() == "not_verified"
    assert res.verification_sentence().startswith("the choice is not verified on the true model (design.verify = "
                                                  "false)")


def test_only_the_choice_undecided_is_left_to_its_verification():
    """The warning said 'a cheaper one may meet it' when the one undecided candidate was the choice itself, and
    after its verification had confirmed it."""
    met = {"reliability_at_target_life": 0.95, "error": 0.01, "model_calls": 30, "confirmed": True}
    only_choice = {"undecided_left": 1, "undecided_other_than_choice": 0, "budget": 10}
    assert _result(met, only_choice).undecided_sentence() == ""
    near = dict(met, reliability_at_target_life=0.905)
    assert _result(near, only_choice).undecided_sentence().startswith("the choice's R(N*) on the surrogate lies "
                                                                      "within its error")
    unverified = {"reliability_at_target_life": None, "error": None, "model_calls": 0, "confirmed": False}
    assert _result(unverified, only_choice).undecided_sentence().endswith("(it was not verified)")
    cheaper = {"undecided_left": 3, "undecided_other_than_choice": 2, "budget": 0}
    assert _result(met, cheaper).undecided_sentence().startswith("no refinement was allowed (design.refine_max_calls "
                                                                 "= 0) with 2 candidate(s)")


def test_a_population_too_small_to_resolve_the_target_is_refused():
    from jointwear.config import load_config, updated
    from jointwear.schema import ConfigError

    with pytest.raises(ConfigError, match=r"design\.n_population: must be >= 1,000 \(got 10\)"):
        updated(load_config(), {"design.n_population": 10})


@pytest.mark.parametrize("n_star, side", [(533_381, "below"), (2_500_000, "beyond"), (1_000_000, None)])
def test_a_target_outside_the_studys_curve_is_told(n_star, side):
    """N* = 0.5 x today's life fell below cycles_start and was accepted silently."""
    res = _result({"reliability_at_target_life": 0.95, "error": 0.01, "model_calls": 30, "confirmed": True})
    res.target_life_cycles, res.study_curve_cycles = n_star, [800_000.0, 2_000_000.0]
    sentence = res.target_outside_curve_sentence()
    assert (sentence == "") if side is None else sentence.startswith(
        f"the target life {n_star:,.0f} cycles lies {side} the study's R(N) curve (800,000 to 2,000,000 cycles)")


class _ScatteredSurrogate(_Surrogate):
    """Every point's mean life exactly at ln N* + 0.1, the life scattering by s = 0.2 about it."""

    scatter_sd = 0.2

    def __init__(self):
        super().__init__(0.0)

    def predict(self, u):
        return np.full(u.shape[0], 10.1), np.full(u.shape[0], 1e-3)


def test_a_candidate_integrates_the_life_scatter():
    # each sample survives N* with probability Phi(0.1 / 0.2) exactly; the mean alone would read R = 1
    n = 20_000
    est = estimate(_space(n), _ScatteredSurrogate(), None, log_target=10.0, reliability_target=0.6)
    assert est.reliability == pytest.approx(stats.norm.cdf(0.5), rel=1e-12)
    # the life at R* = 0.6: the 40 % quantile of ln N = 10.1 + 0.2 z over the space's draws of z (exactly, on them)
    assert est.life_cycles == pytest.approx(np.exp(np.quantile(10.1 + 0.2 * _space(n).scatter, 0.4)), rel=1e-12)
    # and close to the closed form exp(10.1 + 0.2 Phi^-1(0.4)) within ~3 standard errors of the quantile
    # (sqrt(p (1 - p) / n) / phi(Phi^-1(p)) x 0.2 = 1.8e-3)
    assert est.life_cycles == pytest.approx(np.exp(10.1 + 0.2 * stats.norm.ppf(0.4)), rel=5e-3)


def test_todays_design_and_the_candidates_count_survivors_alike():
    """Today's design was read from the Kriging mean alone (R = 1 here: every mean outlives N*), the candidates with
    the life's scatter (Phi(0.5) each): the report put 0.8832 beside a candidate of today's options at 0.8719. Both
    now count the survivors by ``surviving``."""
    n = 20_000
    u = np.zeros((n, 2))
    sur = _ScatteredSurrogate()
    mu, _ = sur.predict(u)
    assert surviving(sur, u, mu, 10.0) / n == pytest.approx(stats.norm.cdf(0.5), rel=1e-12)
    assert surviving(_Surrogate(0.0), u, mu, 10.0) == n  # without scatter: a count
    est = estimate(_space(n), sur, None, log_target=10.0, reliability_target=0.6)
    assert est.reliability == pytest.approx(surviving(sur, u, mu, 10.0) / n, rel=1e-15)


def test_an_extrapolated_life_puts_no_candidate_off_the_pareto_front():
    """A front of fits whose lives were extrapolations (69 % of their population outside the study's inputs, R
    +/- 0.70) hid the one well-estimated alternative, which they 'dominated'. Such a life may still dominate
    another extrapolated one, and a well-estimated life dominates anything."""
    from jointwear.design.search import pareto_front

    def row(name, cost, life, outside):
        return {"choices": {"fit": name}, "cost": cost, "life_at_target_cycles": life,
                "outside_design_fraction": outside}

    far = [row("H7/g6 a", 0.3, 500_000.0, 0.69), row("H7/g6 b", 1.3, 510_000.0, 0.69)]
    near = [row("IT7/IT6", 0.0, 400_000.0, 0.0), row("hardened", 2.0, 450_000.0, 0.0),
            row("dominated", 2.5, 420_000.0, 0.0), row("far, dominated", 3.0, 505_000.0, 0.69)]
    front = [r["choices"]["fit"] for r in pareto_front(far + near)]
    assert front == ["IT7/IT6", "H7/g6 a", "H7/g6 b", "hardened"]
    # without extrapolation, the front is the usual one
    assert [r["choices"]["fit"] for r in pareto_front(near[:3])] == ["IT7/IT6", "hardened"]


def test_a_life_longer_within_the_studys_own_interval_does_not_enter_the_front():
    """22 front rows, many only tightening grades for 25-150 cycles more (0.05 %), where the study's life interval is
    +/- 1.2 %: a dearer design enters the front only beyond that resolution."""
    from jointwear.design.search import pareto_front

    rows = [{"choices": {"g": name}, "cost": cost, "life_at_target_cycles": life, "outside_design_fraction": 0.0}
            for name, cost, life in (("IT11", 1.0, 400_000.0), ("IT10", 1.5, 400_150.0), ("IT9", 2.0, 404_000.0),
                                     ("IT8", 3.0, 406_000.0))]
    assert [r["choices"]["g"] for r in pareto_front(rows)] == ["IT11", "IT10", "IT9", "IT8"]
    # at 1.2 %: IT10 (+0.04 %) and IT9 (+1.0 %) are not resolved from IT11; IT8 (+1.5 %) is, and no cheaper design
    # lives as long
    assert [r["choices"]["g"] for r in pareto_front(rows, resolution=0.012)] == ["IT11", "IT8"]
    # the choice is on the front whatever the resolution: a designer's front listed a dearer design beside the
    # headline choice it had left out (6.2 % longer than the previous point, under a 7.1 % resolution)
    # (the dearer points are then resolved against it: IT8 is 1.46 % beyond IT10 and 0.5 % beyond IT9)
    assert [r["choices"]["g"] for r in pareto_front(rows, resolution=0.012, keep=1)] == ["IT11", "IT10", "IT8"]
    assert [r["choices"]["g"] for r in pareto_front(rows, resolution=0.012, keep=2)] == ["IT11", "IT9"]


def test_the_choice_is_told_against_todays_design():
    res = DesignResult(target_life_cycles=1e6, target_reliability=0.9, chosen={
        "choices": {"l1": "IT10", "fit": "H7/g6", "HB_b": "standard"}, "cost": 4.15}, pareto=[], verification=None,
        model_calls=10, wall_seconds=1.0, baseline_choices={"l1": "IT9", "fit": "IT7/IT6", "HB_b": "standard"},
        baseline_cost=4.083)
    assert res.change_sentence() == ("against today's design (l1 IT9, fit IT7/IT6, HB_b standard, cost 4.083): cost "
                                     "+0.067; changes l1 IT9 -> IT10, fit IT7/IT6 -> H7/g6")
    res.baseline_reliability_at_target_life = 0.3892  # today's R(N*), on the surrogate the candidates are read on
    assert "HB_b standard, cost 4.083, R(N*) 0.3892): cost +0.067" in res.change_sentence()
    res.chosen["choices"] = dict(res.baseline_choices)
    assert res.change_sentence().endswith("is the choice: it meets the target as it is")
    res.baseline_choices, res.baseline_unmatched = None, ["l2"]
    assert res.change_sentence().startswith("today's design is not among the candidates (l2: ")
    # no choice: the candidate nearest the target is named
    res.chosen = None
    res.candidates = [{"choices": {"l1": "IT8"}, "cost": 9.0, "reliability_at_target_life": 0.877,
                       "reliability_error": 0.1}, {"choices": {"l1": "IT9"}, "cost": 5.0,
                                                   "reliability_at_target_life": 0.8, "reliability_error": 0.1}]
    assert res.nearest_sentence() == ("the nearest is l1 IT9 (cost 5): R = 0.8000 +/- 0.1000 at 1,000,000 cycles, "
                                      "as near as the highest, l1 IT8 (cost 9, R = 0.8770 +/- 0.1000), within their "
                                      "errors")  # the strictly highest R cost 2.4 more for 0.003 against +-0.04
    for row in res.candidates:
        row["reliability_error"] = 0.01  # now the highest R is resolved from the cheaper one
    assert res.nearest_sentence() == "the nearest is l1 IT8 (cost 9): R = 0.8770 +/- 0.0100 at 1,000,000 cycles"


def test_an_undecided_candidate_closer_to_the_target_than_its_population_resolves_is_told():
    """Raising refine_max_calls and resuming left the same 7 candidates undecided: the cheapest read R = 0.8998
    against R* = 0.9, 0.0002 away where 20,000 samples resolve +/- 0.0042 (Clopper-Pearson at 18,000 of 20,000)."""
    near = {"choices": {"k_b": "screened"}, "cost": 4.35, "reliability_at_target_life": 0.8998,
            "reliability_error": 0.0157, "surrogate_error": 0.005, "outside_design_fraction": 0.0}
    chosen = {"choices": {"k_b": "PTFE"}, "cost": 5.75, "reliability_at_target_life": 0.997}
    res = DesignResult(target_life_cycles=1e6, target_reliability=0.9, chosen=chosen, pareto=[], verification=None,
                       model_calls=10, wall_seconds=1.0, candidates=[near, chosen], n_population=20_000,
                       refinement={"undecided_left": 2, "undecided_other_than_choice": 1, "budget": 30})
    assert res.undecided_sentence().endswith(
        "; but the cheapest of them (k_b screened, cost 4.35, R(N*) 0.8998) lies 0.0002 from R*, closer than its "
        "population of 20,000 resolves (+/- 0.0042): more calls cannot settle it; judge it by a reliability study of "
        "that design")
    near["reliability_at_target_life"] = 0.895  # 0.005 away: beyond the resolution, the refinement may settle it
    assert res.undecided_sentence().endswith("run again with --resume (resume=True in Python)")


def test_a_candidate_undecided_by_its_share_outside_the_design_is_refined_outside_it():
    """A loose grade's spread reached beyond the study's +-5 sigma: its candidates stayed undecided by the share of
    their population outside the design's box, and the refinement's lowest-U points, all inside the box, never
    shrank it (3 undecided after 14 calls; a designer's audit). Such a candidate's point is the least certain of
    those outside the box, which widens it; otherwise the least certain of all."""
    from types import SimpleNamespace

    from jointwear.design.search import _refine_point

    u = np.array([[0.0, 0.1], [0.0, 6.0], [0.0, 7.0], [0.0, -0.2]])
    mu, sd = np.array([1.0, 3.0, 2.0, 1.05]), np.ones(4)  # U = |mu - ln N*| / sd with ln N* = 1: rows 0, 3, 2, 1
    space = SimpleNamespace(population=lambda cand: (u * 10.0, u))
    sur = SimpleNamespace(predict=lambda uu: (mu, sd), outside=lambda uu: np.abs(uu[:, 1]) > 5.0)
    np.testing.assert_array_equal(_refine_point(space, sur, None, 1.0), u[0] * 10.0)
    np.testing.assert_array_equal(_refine_point(space, sur, None, 1.0, widen=True), u[2] * 10.0)
    inside = SimpleNamespace(predict=sur.predict, outside=lambda uu: np.zeros(len(uu), dtype=bool))
    np.testing.assert_array_equal(_refine_point(space, inside, None, 1.0, widen=True), u[0] * 10.0)


def test_no_choice_writes_its_reason_and_the_nearest_candidate_to_design_json(tmp_path):
    """With no choice, design.json held chosen: null and nothing else: the reason and the nearest candidate were a
    console sentence and computed properties only."""
    import json

    from result_keys import undocumented_keys

    from jointwear import load_results

    rows = [{"choices": {"l1": "IT8"}, "cost": 9.0, "life_at_target_cycles": 5e5, "reliability_at_target_life": 0.877,
             "reliability_error": 0.01, "outside_design_fraction": 0.0},
            {"choices": {"l1": "IT9"}, "cost": 5.0, "life_at_target_cycles": 4e5, "reliability_at_target_life": 0.8,
             "reliability_error": 0.01, "outside_design_fraction": 0.0}]
    res = DesignResult(target_life_cycles=1e6, target_reliability=0.9, chosen=None, pareto=rows[::-1],
                       verification=None, model_calls=10, wall_seconds=1.0, candidates=rows)
    res.save(tmp_path, figures=False)
    data = json.loads((tmp_path / "design.json").read_text())
    assert data["no_choice_reason"] == "unreached"
    assert data["nearest"] == {"choices": {"l1": "IT8"}, "cost": 9.0, "reliability_at_target_life": 0.877,
                               "reliability_error": 0.01}
    assert undocumented_keys(tmp_path / "design.json") == []
    back = load_results(tmp_path).design
    assert back.no_choice_reason == "unreached" and back.nearest == data["nearest"]
    assert back.to_json()["nearest"] == data["nearest"]  # and written back as read


@pytest.mark.parametrize("verdicts, overall", [(["meets", "meets"], "meets"),
                                               (["meets", "within_error"], "within_error"),
                                               (["within_error", "misses"], "misses")])
def test_a_verification_at_every_target_is_told_with_its_worst_verdict(verdicts, overall):
    """With several targets the headline choice's own verification checks the first only; its verification at every
    target is one record whose verdict is the worst of the targets', and the sentence gives each target's."""
    from jointwear.design.search import every_target_verification

    per = [{"reliability_at_target_life": 0.95 - 0.01 * k, "error": 0.004, "verdict": v, "model_calls": 30,
            "new_model_calls": 12, "run_now": 12, "n_mc": 10_000, "converged": True, "failed_calls": 0,
            "surrogate_fit": {}} for k, v in enumerate(verdicts)]
    checked = every_target_verification(per)
    assert checked["verdict"] == overall and checked["confirmed"] == (overall != "misses")
    assert checked["verdicts"] == verdicts and checked["new_model_calls"] == 12
    res = _result({"verdict": "meets"})
    res.targets = [{"target_reliability": 0.9}, {"target_reliability": 0.95}]
    res.chosen_every_target = {"choices": {"fit": "H7/g6"}, "cost": 1.0, "reliability_at_target_life": [0.95, 0.96],
                               "reliability_error": [0.01, 0.01], "verification": checked}
    assert res.every_target_sentence() == ""  # the headline choice meets every target on the surrogate
    sentence = res.every_target_check_sentence()
    assert "0.9500 +- 0.0040 (" + verdicts[0] + "), 0.9400 +- 0.0040 (" + verdicts[1] + ")" in sentence
    assert sentence.endswith({"meets": "meets every target", "within_error": "not proven at every target",
                              "misses": "refuted: misses a target"}[overall])
