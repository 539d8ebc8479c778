"""Sensitivity tools against problems with exact answers."""

import math

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import esc_absolute_error, esc_error
from jointwear.sensitivity import (
    mean_shift_table,
    reliability_derivatives,
    shifted_marginal,
    sobol_indices,
    unresolved_pairs,
)


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def test_sobol_ishigami_matches_analytic_indices():
    # Exact indices of the Ishigami function (a = 7, b = 0.1): Saltelli et al. (2008), Sec. 4.
    a, b = 7.0, 0.1
    v = a**2 / 8 + b * math.pi**4 / 5 + b**2 * math.pi**8 / 18 + 0.5
    v1 = 0.5 * (1 + b * math.pi**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * math.pi**8 * (1 / 18 - 1 / 50)
    s1 = np.array([v1, v2, 0.0]) / v
    st = np.array([(v1 + v13) / v, v2 / v, v13 / v])
    marg = [stats.uniform(-math.pi, 2 * math.pi)] * 3
    res = sobol_indices(ishigami, marg, ["x1", "x2", "x3"], n_base=4096, seed=3)
    # Tolerance: twice SALib's bootstrap 95 % half-width (about 4 standard errors), floored at 0.01
    # for indices whose bootstrap interval is itself tiny.
    assert np.all(np.abs(res.S1 - s1) < np.maximum(2 * res.S1_conf, 0.01))
    assert np.all(np.abs(res.ST - st) < np.maximum(2 * res.ST_conf, 0.01))
    assert res.n_evaluations == 4096 * 5


def test_sobol_rejects_bad_input():
    with pytest.raises(ValueError, match="power of two"):
        sobol_indices(ishigami, [stats.norm()] * 3, ["a", "b", "c"], n_base=1000)
    with pytest.raises(ValueError, match="names"):
        sobol_indices(ishigami, [stats.norm()] * 3, ["a", "b"])


def test_reliability_derivatives_linear_limit_state():
    # g = a0 - b.x with X_i ~ N(mu_i, s_i): Pf = Phi(-beta), beta = (a0 - b.mu) / sqrt(sum b_i^2 s_i^2).
    a0, b = 6.0, np.array([1.0, 2.0])
    mu, s = np.array([1.0, 0.5]), np.array([0.8, 0.6])
    marg = [stats.norm(m, sd) for m, sd in zip(mu, s)]
    sig = math.sqrt(np.sum(b**2 * s**2))
    beta = (a0 - b @ mu) / sig
    phi = stats.norm.pdf(beta)
    exact_dmean = phi * b / sig                     # dPf/dmu_i = phi(beta) b_i / sigma_g
    exact_dstd = phi * beta * b**2 * s / sig**2     # dPf/ds_i = phi(beta) beta b_i^2 s_i / sigma_g^2
    rng = np.random.default_rng(7)
    x = np.column_stack([m.rvs(size=400_000, random_state=rng) for m in marg])
    failed = a0 - x @ b < 0
    res = reliability_derivatives(x, failed, marg, ["x1", "x2"])
    assert abs(res.pf - stats.norm.cdf(-beta)) < 4 * math.sqrt(res.pf / len(x))  # 4 binomial std errors
    assert np.all(np.abs(res.dpf_dmean - exact_dmean) < 4 * res.dpf_dmean_se)   # 4 standard errors
    assert np.all(np.abs(res.dpf_dstd - exact_dstd) < 4 * res.dpf_dstd_se)


def test_shifted_marginal_moves_the_mean_and_keeps_the_spread():
    for m in [stats.norm(10.0, 1.0), stats.truncnorm(-2.0, np.inf, loc=2.0, scale=1.0),
              stats.lognorm(0.3, scale=5.0), stats.uniform(1.0, 2.0)]:
        for f in (0.8, 1.2):
            s = shifted_marginal(m, f)
            assert s.mean() == pytest.approx(f * m.mean(), rel=1e-12)  # exact algebra
            if m.dist.name == "lognorm":
                assert s.std() / s.mean() == pytest.approx(m.std() / m.mean(), rel=1e-12)
            else:
                assert s.std() == pytest.approx(m.std(), rel=1e-12)


def test_mean_shift_table_ranks_the_variable_that_matters():
    # R = P(x1 + 0.01 x2 < 3) with x_i ~ N(1, 0.5): shifting x1 matters, x2 hardly.
    marg = [stats.norm(1.0, 0.5), stats.norm(1.0, 0.5)]

    def reliability_of(ms):
        mean = ms[0].mean() + 0.01 * ms[1].mean()
        sd = math.hypot(ms[0].std(), 0.01 * ms[1].std())
        return stats.norm.cdf((3.0 - mean) / sd), 0

    res = mean_shift_table(reliability_of, marg, ["x1", "x2"], factors=(0.8, 1.2))
    assert res.ranking() == ["x1", "x2"]
    assert res.reliability_high[0] < res.reliability_nominal < res.reliability_low[0]


def test_unresolved_pairs_are_neighbours_within_the_summed_errors():
    swing = {"a": 0.41, "b": 0.39, "c": 0.10, "d": 0.05, "e": 0.30}
    groups = {"g1": ["a", "b", "c"], "g2": ["d", "e"]}
    ranking = ["a", "b", "e", "c", "d"]
    loose = {"a": 0.015, "b": 0.01, "c": 0.01, "d": 0.01, "e": 0.01}
    out = unresolved_pairs(ranking, swing, loose, groups)
    assert [(p["group"], p["first"], p["second"]) for p in out] == [("g1", "a", "b")]  # 0.02 < 0.025
    assert out[0]["swing_difference"] == pytest.approx(0.02) and out[0]["error_sum"] == pytest.approx(0.025)
    tight = dict.fromkeys(swing, 0.005)
    assert unresolved_pairs(ranking, swing, tight, groups) == []  # 0.02 > 0.01: resolved
    # equal swings are no order, even with exact reliabilities (a level where every shift leaves R = 0)
    zero = dict.fromkeys("abc", 0.0)
    flat = unresolved_pairs(["a", "b", "c"], zero, zero, {"g": ["a", "b", "c"]})
    assert [(p["first"], p["second"]) for p in flat] == [("a", "b"), ("b", "c")]


def test_esc_absolute_error_bounds_the_misclassification_of_a_known_gaussian_surrogate():
    """A surrogate whose error is exactly N(0, sd) at each point: the true Pf is drawn by sampling the true values.
    The bound is the larger of two one-sided 95 % bounds on the misclassified counts, so |Pf_true - Pf_hat| stays
    under it in >= 95 % of the replicates (the binomial 95 % band of 400 replicates is >= 93 %). It is
    conservative (misclassifications both ways partly cancel in Pf: measured 100 %, and 97.5 % for half the
    bound), so this only catches a bound far too small; its value is pinned by the exact forms: esc_error x
    Pf_hat (the R(N) curve's estimate) with predicted failures, 0 without surrogate variance, and the
    predicted-safe bound over n when nothing is predicted to fail."""
    rng = np.random.default_rng(3)
    n = 20_000
    mu = rng.normal(1.5, 1.0, n)
    sd = np.full(n, 0.2)
    pf_hat = np.mean(mu <= 0)
    bound = esc_absolute_error(mu, sd)
    u = np.abs(mu) / sd
    assert bound == pytest.approx(esc_error(u, mu <= 0) * pf_hat, rel=1e-12)
    inside = [abs(np.mean(mu + sd * rng.standard_normal(n) <= 0) - pf_hat) <= bound for _ in range(400)]
    assert np.mean(inside) >= 0.93
    assert esc_absolute_error(mu, np.zeros(n)) == 0.0
    # nothing predicted to fail: the one-sided 95 % bound on the predicted-safe points that fail, over n
    safe = np.abs(mu) + 0.1
    p = stats.norm.cdf(-safe / sd)
    expected = (p.sum() + 1.959963984540054 * math.sqrt(float((p * (1 - p)).sum()))) / n
    assert esc_absolute_error(safe, sd) == pytest.approx(expected, rel=1e-9)


def test_command_line_ranking_shows_groups_and_unresolved_neighbours():
    from types import SimpleNamespace

    from jointwear.study.stage_lines import ranking_line

    sens = SimpleNamespace(
        shifts_move_reliability=True, reliability_nominal=0.944, cycles=360_000,
        ranking_by_group={"tolerance": ["l2", "lBC", "l1"], "bearing_material": ["k_b", "HB_b", "E_b"]},
        unresolved_pairs=[{"group": "bearing_material", "first": "k_b", "second": "HB_b"}])
    assert ranking_line(sens) == ("tolerance: l2 > lBC > l1 | bearing_material: k_b ~ HB_b > E_b (~: not told apart "
                                  "within the surrogate's error)")  # a legend for '~' where one is shown
    assert ranking_line(SimpleNamespace(shifts_move_reliability=True, ranking_by_group={"tolerance": ["c"]},
                                        unresolved_pairs=[], reliability_nominal=0.5, cycles=1)) == "tolerance: c"
    # R = 0 at the sensitivity's level (a uniform-mode pump whose curve missed its life): the largest shift moved R
    # by 4.7e-6, and the line ranked variables on that without a word
    edge = SimpleNamespace(shifts_move_reliability=True, reliability_nominal=0.0, cycles=1_200_000,
                           ranking_by_group={"tolerance": ["c"]}, unresolved_pairs=[],
                           variables=[{"reliability_low": 0.0, "reliability_high": 4.7e-6}])
    assert ranking_line(edge) == ("tolerance: c | (read with care: R = 0.000 at 1,200,000 cycles, where the largest "
                                  "shift moves it by 4.7e-06; set sensitivity.cycles where R passes the target)")


def test_the_variance_ranking_is_told_beside_the_mean_shifts():
    """The command line said 'ranking tolerance: l_crank > c' from the +-20 % mean shifts (a change of the nominal
    design by hundreds of the length's standard deviations) while the Sobol' indices gave the clearance 200 times the
    crank's share of the wear's variance: the line and the report now say what each ranking measures."""
    from types import SimpleNamespace

    from jointwear.report.result_sections import ranking_meaning
    from jointwear.study import SensitivityResult
    from jointwear.study.stage_lines import variance_line

    sens = SimpleNamespace(sobol={"names": ["l_crank", "c", "E_b"], "ST": [2.6e-4, 0.05, 0.012],
                                  "output": "max bearing wear depth of joint B at 150,000 cycles"},
                           factors=[0.8, 1.2])
    sens.variance_ranking = lambda floor=0.01: SensitivityResult.variance_ranking(sens, floor)
    assert sens.variance_ranking() == [("c", 0.05), ("E_b", 0.012)]
    assert variance_line(sens) == "c 0.05 > E_b 0.012 (the others < 0.01)"
    text = ranking_meaning(sens)
    assert "moves to 80 % and 120 % of its value: a change of the nominal design" in text
    assert "so the indices add up to 1 or more): c 0.05, E_b 0.012." in text
    sens.sobol = {}
    assert sens.variance_ranking() == [] and variance_line(sens) == ""
    assert "Sobol' ST" not in ranking_meaning(sens).replace("&#x27;", "'")
