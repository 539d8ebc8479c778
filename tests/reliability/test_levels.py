"""akmcs_multi with a family of thresholds on one response (one shared Kriging)."""

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import akmcs_multi, population_size
from jointwear.reliability.results import mc_cov


def test_levels_match_the_exact_probabilities_and_are_monotone():
    # y = x1 + x2 with standard normals: P(y < t) = Phi(t / sqrt(2)) exactly.
    levels = np.array([-3.0, -2.0, -1.0, 0.0, 1.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels,
                      n_mc=100_000, seed=4, pf_floor=1e-3)
    exact = stats.norm.cdf(levels / np.sqrt(2.0))
    for k, p in enumerate(exact):
        if p < 1e-3:
            continue
        # Acceptance of issue 4: within 3 % of the reference or 2x the reported COV.
        assert abs(res.pf[k] - p) <= max(0.03 * p, 2 * res.cov[k] * res.pf[k]), (levels[k], res.pf[k], p)
    assert np.all(np.diff(res.pf) >= 0)  # one response, increasing thresholds: Pf cannot decrease
    assert res.n_calls < 40  # a linear response needs few points (Echard et al. 2011: ~12-20)
    # the per-level surrogates are the shared one minus the level
    u = np.array([[0.3, -0.2]])
    m0 = res.surrogates[0].predict(u, return_variance=False)[0]
    m3 = res.surrogates[3].predict(u, return_variance=False)[0]
    assert m0 - m3 == pytest.approx(levels[3] - levels[0], abs=1e-12)


def test_result_hooks_continue_from_the_learned_surrogate():
    # y = x1 + x2: the learned response is nearly exact, so a fresh population classified by the hooks
    # agrees with the exact Pf within the Monte Carlo noise of that population
    levels = np.array([-2.0, 0.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels,
                      n_mc=20_000, seed=1, pf_floor=1e-3)
    u = np.random.default_rng(5).standard_normal((1000, 2))
    mu = res.predict(u)
    for k in range(2):  # one shared prediction equals each level's own surrogate
        np.testing.assert_allclose(mu[:, k], res.surrogates[k].predict(u, return_variance=False)[0], atol=1e-12)
        # and the response minus the level (rounding of two subtractions of levels of order 1)
        np.testing.assert_allclose(res.response(u) - levels[k], mu[:, k], atol=1e-12)
    n = population_size(float(res.pf[0]), 0.05, 10**7)
    assert mc_cov(res.pf[0], n) < 0.05 <= mc_cov(res.pf[0], int(n / 1.1) - 1)  # 10 % over the COV formula
    rng = np.random.default_rng(9)
    pf, cov = res.estimate_on(lambda m, start: rng.standard_normal((m, 2)), n, chunk=7_000)
    exact = stats.norm.cdf(levels / np.sqrt(2.0))
    assert np.all(np.abs(pf - exact) <= 3 * cov * exact)  # 3 sigma of the new population's estimate
    assert cov[0] < 0.05 and population_size(0.0, 0.05, 10**6) == 10**6


def test_the_curve_between_the_levels_comes_from_the_same_surrogate_and_population(monkeypatch):
    # y = x1 + x2, levels -2 and 0: Pf at thresholds between them (no call), on the engine's own population
    # (keep_population), equals the engine's own estimate at the levels to the bit and the exact Phi(t / sqrt 2)
    # between them within 3 standard errors; held 40 probabilities per row block, the same sums as one block
    levels = np.array([-2.0, 0.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels,
                      n_mc=20_000, seed=1, pf_floor=1e-3, keep_population=True)
    assert res.population_u.shape == (res.n_mc, 2)
    thresholds = np.linspace(-2.0, 0.0, 9)
    pop = res.population_u
    pf, cov = res.estimate_on(lambda m, start: pop[start:start + m], res.n_mc, thresholds=thresholds)
    np.testing.assert_array_equal(pf[[0, -1]], res.pf)
    exact = stats.norm.cdf(thresholds / np.sqrt(2.0))
    assert np.all(np.abs(pf - exact) <= 3 * cov * exact), (pf, exact)
    assert np.all(np.diff(pf) > 0)
    from jointwear.reliability import results

    monkeypatch.setattr(results, "MAX_PROBABILITIES", 40_000)  # 4,444 rows of 9 thresholds per block
    blocked, _ = res.estimate_on(lambda m, start: pop[start:start + m], res.n_mc, thresholds=thresholds)
    np.testing.assert_allclose(blocked, pf, rtol=1e-12)


def test_levels_must_be_finite():
    with pytest.raises(ValueError, match="levels"):
        akmcs_multi(lambda x: x[:, 0], [stats.norm()], levels=[np.nan])


def test_esc_errors_stay_finite_where_the_relative_bound_is_unbounded():
    from scipy.special import ndtr

    from jointwear.reliability import esc_errors

    z = 1.959963984540054
    # one predicted failure, uncertain (U = 0.1), and 3 uncertain predicted-safe candidates among 1000
    u = np.full(1000, np.inf)
    u[:4] = [0.1, 0.5, 1.0, 2.0]
    fail = np.zeros(1000, dtype=bool)
    fail[0] = True
    p = ndtr(-u[:4])
    n_fs = p[0] + z * np.sqrt(p[0] * (1 - p[0]))  # the ESC counts (Wang & Shafieezadeh 2019), by hand
    n_sf = p[1:].sum() + z * np.sqrt((p[1:] * (1 - p[1:])).sum())
    assert n_fs > 1.0  # so the relative bound n_fs / (n_f - n_fs) is unbounded
    rel, absolute = esc_errors(u, fail)
    assert rel == np.inf
    assert absolute == pytest.approx(max(n_fs, n_sf) / 1000, rel=1e-12)  # the true Pf lies in [n_f -/+ ...] / n
    # every sign certain and no failure predicted: nothing can be misclassified
    assert esc_errors(np.full(10, np.inf), np.zeros(10, dtype=bool)) == (np.inf, 0.0)
    # a bounded relative error: the absolute one is relative x Pf
    fail[:200] = True
    rel, absolute = esc_errors(u, fail)
    assert np.isfinite(rel) and absolute == pytest.approx(rel * 0.2, rel=1e-12)


def test_esc_relative_error_is_the_larger_of_the_two_bounds():
    """The relative ESC error is max(n_fs / (n_f - n_fs), n_sf / (n_f + n_sf)) (Wang & Shafieezadeh 2019), here
    dominated by the predicted-safe term (guards n_sf / (n_f - n_sf), 0.18 instead of 0.13 here). Counts by hand
    from the same formulas: rounding only (rel 1e-12)."""
    from scipy.special import ndtr

    from jointwear.reliability import esc_errors

    z = 1.959963984540054
    u = np.full(1000, np.inf)
    fail = np.zeros(1000, dtype=bool)
    fail[:200] = True
    u[0] = 0.5  # one uncertain predicted failure
    u[200:260] = 0.3  # 60 uncertain predicted-safe candidates
    pf, ps = ndtr(-u[:1]), ndtr(-u[200:260])
    n_f = 200.0
    n_fs = pf.sum() + z * np.sqrt((pf * (1 - pf)).sum())
    n_sf = ps.sum() + z * np.sqrt((ps * (1 - ps)).sum())
    expected = max(n_fs / (n_f - n_fs), n_sf / (n_f + n_sf))
    assert expected == pytest.approx(n_sf / (n_f + n_sf), rel=1e-12)  # the case in point: the safe-side term wins
    rel, absolute = esc_errors(u, fail)
    assert rel == pytest.approx(expected, rel=1e-12)
    assert absolute == pytest.approx(expected * 0.2, rel=1e-12)


def test_a_level_far_in_the_tail_gets_a_finite_absolute_error():
    # y = x1 + x2; at the level -6 (Pf = 1.1e-5) the surrogate predicts a handful of failures at most among
    # 20,000 candidates, where the relative ESC bound is unbounded or large; its absolute error is the
    # misclassified fraction's bound, which cannot exceed the share of uncertain candidates (< 1)
    levels = np.array([-6.0, 0.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels,
                      n_mc=20_000, seed=3, pf_floor=1e-3)
    assert np.all(np.isfinite(res.error_absolute)) and np.all(res.error_absolute < 0.01)
    assert res.error_estimate[0] == np.inf  # the case in point (else this test checks nothing new)
    assert np.isfinite(res.error_estimate[1])
    assert res.error_absolute[1] == pytest.approx(res.error_estimate[1] * res.pf[1], rel=1e-12)


def test_estimate_on_integrates_a_gaussian_noise_of_the_response():
    # y = x1 + x2 learned (nearly exactly), read with a noise e ~ N(0, s^2) added: P(y + e < t) = Phi(t / sqrt(2 + s^2))
    from jointwear.reliability import failure_probability

    levels = np.array([-2.0, 0.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels,
                      n_mc=20_000, seed=1, pf_floor=1e-3)
    s, n = 0.8, 200_000
    rng = np.random.default_rng(2)
    pf, cov = res.estimate_on(lambda m, start: rng.standard_normal((m, 2)), n, chunk=70_000, noise_sd=s)
    exact = stats.norm.cdf(levels / np.sqrt(2.0 + s * s))
    assert np.all(np.abs(pf - exact) <= 3 * cov * exact)  # 3 sigma of the estimate
    # the COV is that of a mean of probabilities: below the crude Monte Carlo one of the same population
    assert np.all(cov < mc_cov(pf, n))
    # without noise, the indicator: the crude estimate and its COV
    pf0, cov0 = res.estimate_on(lambda m, start: np.random.default_rng(3).standard_normal((m, 2)), 10_000)
    np.testing.assert_allclose(cov0, mc_cov(pf0, 10_000), rtol=1e-12)
    np.testing.assert_array_equal(failure_probability(np.array([-1.0, 0.0, 2.0, np.nan])), [1.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(failure_probability(np.array([-1.0, 0.0, np.nan]), 0.5),
                               [stats.norm.cdf(2.0), 0.5, 1.0], rtol=1e-15)


def _exact_spread(mu, sigma, shift, s):
    """Standard deviation of Phi((shift - g) / s) for g ~ N(mu, sigma^2): E[P] = Phi(h), E[P^2] = P(X1 < h, X2 < h)
    with correlation rho = b^2 / (1 + b^2), h = a / sqrt(1 + b^2), a = (shift - mu) / s, b = sigma / s; for equal
    limits P(X1 < h, X2 < h) = Phi(h) - 2 T(h, sqrt((1 - rho) / (1 + rho))) (Owen's T)."""
    from scipy.special import owens_t

    a, b = (shift - mu) / s, sigma / s
    h, rho = a / np.sqrt(1 + b * b), b * b / (1 + b * b)
    second = stats.norm.cdf(h) - 2 * owens_t(h, np.sqrt((1 - rho) / (1 + rho)))
    return np.sqrt(second - stats.norm.cdf(h) ** 2)


@pytest.mark.parametrize("noise_sd", [0.5, 0.0])
def test_posterior_spread_of_pf_keeps_the_correlation_of_the_errors(noise_sd):
    # m points of equal posterior N(mu, sigma^2): fully correlated errors move Pf as one point's, independent ones
    # average out by sqrt(m). Exact standard deviations (_exact_spread; the indicator's sqrt(p (1 - p)) without
    # noise); tolerance 5 %, ~8 standard errors of a standard deviation from 20,000 draws (1 / sqrt(2 x 20,000))
    from jointwear.reliability import posterior_failure_spread

    mu, sigma, m, n = 0.3, 0.4, 40, 20_000
    shifts = np.array([-0.2, 0.3, 0.9])
    mean = np.full(m, mu)
    if noise_sd > 0:
        one = _exact_spread(mu, sigma, shifts, noise_sd)
    else:
        p = stats.norm.cdf((shifts - mu) / sigma)
        one = np.sqrt(p * (1 - p))
    rng = np.random.default_rng(4)
    together = posterior_failure_spread(mean, np.full((m, m), sigma**2), shifts, noise_sd, n, rng)  # rank 1
    np.testing.assert_allclose(together, one, rtol=0.05)
    apart = posterior_failure_spread(mean, sigma**2 * np.eye(m), shifts, noise_sd, n, rng)
    np.testing.assert_allclose(apart, one / np.sqrt(m), rtol=0.05)


def test_quantile_errors_interpolate_the_level_errors_and_divide_by_the_slope():
    from jointwear.reliability.learning import quantile_errors

    levels, pf, err = np.array([0.0, 1.0, 2.0]), np.array([0.1, 0.3, 0.5]), np.array([0.01, 0.02, 0.03])
    # Pf = 0.2 halfway between levels 0 and 1: error 0.015 in Pf over a slope of 0.2 per unit level
    assert quantile_errors(levels, pf, err, [0.2]) == [(0, 1, pytest.approx(0.075))]
    assert quantile_errors(levels[::-1], pf[::-1], err[::-1], [0.4]) == [(1, 0, pytest.approx(0.125))]
    assert quantile_errors(levels, pf, err, [0.05, 0.6]) == []  # outside the levels' Pf: no bracket
    assert quantile_errors(levels, np.array([0.1, 0.1, 0.5]), err, [0.1]) == []  # reached at the first level
    assert quantile_errors(levels, np.array([0.1, 0.3, 0.3]), err, [0.3]) == [(0, 1, pytest.approx(0.1))]


def test_quantile_tol_learns_the_level_where_pf_reaches_a_target():
    # y = exp(0.5 x1) + 0.3 x2 (nonlinear); a loose absolute tolerance stops the learning on its initial design, where
    # the level at Pf = 0.25 (between the levels 0.6 and 0.8) is still uncertain by 0.004: quantile_tol carries on
    from jointwear.reliability.learning import quantile_errors

    def g(x):
        return np.exp(0.5 * x[:, 0]) + 0.3 * x[:, 1]

    levels = np.array([0.4, 0.6, 0.8, 1.0, 1.2])
    common = dict(levels=levels, n_mc=20_000, seed=3, pf_floor=1e-3, error_abs_tol=0.03, error_tol=0.5,
                  hold_iterations=1)
    loose = akmcs_multi(g, [stats.norm(), stats.norm()], **common)
    tight = akmcs_multi(g, [stats.norm(), stats.norm()], quantile_pf=[0.25], quantile_tol=0.001, **common)
    (lo, hi, e_loose), = quantile_errors(levels, loose.pf, loose.error_absolute, [0.25])
    (lo2, hi2, e_tight), = quantile_errors(levels, tight.pf, tight.error_absolute, [0.25])
    assert (lo, hi) == (lo2, hi2) == (1, 2)
    assert e_loose > 0.001 >= e_tight
    assert tight.n_calls > loose.n_calls and tight.converged
    with pytest.raises(ValueError, match="quantile_tol"):
        akmcs_multi(g, [stats.norm(), stats.norm()], quantile_pf=[1.5], quantile_tol=0.01, **common)


def test_quantile_tol_of_a_noisy_response_stops_at_its_fitted_scatter():
    # the same response with a call-to-call scatter, which the Kriging fits (a nugget): its quantile is learnt to that
    # scatter, not to a quantile_tol far below it, so the learning stops where the levels' rules stop it
    def g(x):
        return np.exp(0.5 * x[:, 0]) + 0.3 * x[:, 1] + 0.05 * rng.standard_normal(len(x))

    levels = np.array([0.4, 0.6, 0.8, 1.0, 1.2])
    common = dict(levels=levels, n_mc=20_000, seed=3, pf_floor=1e-3, error_abs_tol=0.03, error_tol=0.5,
                  hold_iterations=1, kriging={"estimate_nugget": True})
    rng = np.random.default_rng(0)
    plain = akmcs_multi(g, [stats.norm(), stats.norm()], **common)
    rng = np.random.default_rng(0)
    tight = akmcs_multi(g, [stats.norm(), stats.norm()], quantile_pf=[0.25], quantile_tol=0.001, **common)
    assert plain.noise_sd > 0.001 and tight.n_calls == plain.n_calls and tight.converged


@pytest.mark.parametrize("noise_sd", [0.3, 0.0])
def test_point_shifts_move_each_points_threshold(noise_sd):
    """posterior_pf_sd(point_shifts=s): a shift equal at every point is the threshold moved by it; shifts that differ
    from point to point move only their own points: with the first half of the points shifted far below every draw
    (never failing) or far above (always failing), each draw's Pf differs by exactly 0.5, so the two spreads are equal.
    The same draws (same points, same seed) throughout: equal to rounding."""
    levels = np.array([-1.0, 0.0])
    res = akmcs_multi(lambda x: x[:, 0] + x[:, 1], [stats.norm(), stats.norm()], levels=levels, n_mc=5_000, seed=2,
                      max_calls=12)
    u = np.random.default_rng(4).standard_normal((400, 2))

    def spread(threshold, shifts=None):
        return res.posterior_pf_sd(u, noise_sd, 200, seed=5, thresholds=[threshold], point_shifts=shifts)[0]

    assert spread(0.0, np.full(400, 0.3)) == pytest.approx(spread(0.3), rel=1e-12)
    first_half = np.arange(400) < 200
    never, always = spread(0.0, np.where(first_half, -1e3, 0.0)), spread(0.0, np.where(first_half, 1e3, 0.0))
    assert never == pytest.approx(always, rel=1e-9, abs=1e-15)
    if noise_sd > 0:  # the Kriging of a plane is exact: without the response's scatter its spread is 0
        assert never > 0 and never != pytest.approx(spread(0.0), rel=1e-3)
    # the points' failure probabilities under each draw (which the sensitivity weighs for a slope's error) average to
    # the Pf whose spread posterior_pf_sd gives: the same draws
    p = res.posterior_failure_draws(u, 0.3, noise_sd, 200, seed=5)
    assert p.shape == (400, 200) and p.mean(axis=0).std(ddof=1) == pytest.approx(spread(0.3), rel=1e-12, abs=1e-15)


def test_posterior_draws_kept_for_the_same_points_give_the_numbers_of_fresh_draws():
    """posterior_pf_sd keeps its last draws (an m x m factorisation each): a second reading on the same points and seed
    equals, bit for bit, the reading of a result that never drew before; other points or another seed draw anew."""
    def fitted():
        return akmcs_multi(lambda x: x[:, 0] + 0.5 * x[:, 1] ** 2, [stats.norm(), stats.norm()],
                           levels=np.array([-1.0, 0.0]), n_mc=5_000, seed=2, max_calls=12)

    res, fresh = fitted(), fitted()
    u = np.random.default_rng(4).standard_normal((300, 2))
    other = np.random.default_rng(5).standard_normal((300, 2))
    res.posterior_pf_sd(u, 0.2, 100, seed=5, thresholds=[0.3])
    res.posterior_pf_sd(other, 0.2, 100, seed=5)
    calls = []
    draws = res.response_surrogate.posterior_draws
    res.response_surrogate.posterior_draws = lambda *a: calls.append(1) or draws(*a)
    kept = res.posterior_pf_sd(u.copy(), 0.2, 100, seed=5, thresholds=[-0.5, 0.1])
    assert calls == []  # read from the kept draws
    assert np.array_equal(kept, fresh.posterior_pf_sd(u, 0.2, 100, seed=5, thresholds=[-0.5, 0.1]))
    res.posterior_pf_sd(u, 0.2, 100, seed=6)
    assert calls == [1]
    res.posterior_pf_sd(u, 0.2, 100, seed=None)
    res.posterior_pf_sd(u, 0.2, 100, seed=None)  # unseeded: drawn afresh each time
    assert calls == [1, 1, 1]
