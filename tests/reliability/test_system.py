"""A series system learnt one Kriging per component (akmcs_multi(system="series"), SeriesSurrogate)."""

import numpy as np
import pytest
from scipy import stats
from scipy.special import ndtr

from jointwear.reliability import KrigingSurrogate, SeriesSurrogate, akmcs_multi, problems
from jointwear.reliability.system import series_failure_probability


def four_branch_components(x: np.ndarray, k: float = 6.0) -> np.ndarray:
    """The four branches of Echard et al.'s series system (2011, Sec. 5.1); their minimum is problems.four_branch."""
    x1, x2 = x[:, 0], x[:, 1]
    s2 = np.sqrt(2.0)
    return np.column_stack([3 + 0.1 * (x1 - x2) ** 2 - (x1 + x2) / s2, 3 + 0.1 * (x1 - x2) ** 2 + (x1 + x2) / s2,
                            (x1 - x2) + k / s2, (x2 - x1) + k / s2])


def test_components_are_the_four_branch_system():
    x = np.random.default_rng(0).standard_normal((50, 2))
    np.testing.assert_allclose(four_branch_components(x).min(axis=1), problems.four_branch(6.0).g(x), atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1])
def test_series_system_matches_the_exact_pf_with_fewer_calls(seed):
    problem = problems.four_branch(6.0)
    series = akmcs_multi(four_branch_components, problem.marginals, levels=[0.0], system="series", seed=seed,
                         n_mc=200_000, pf_floor=0.0)
    one = akmcs_multi(problem.g, problem.marginals, levels=[0.0], seed=seed, n_mc=200_000, pf_floor=0.0)
    # exact Pf (quadrature) within the Monte Carlo 95 % band plus the surrogate's own error estimate
    band = 1.96 * series.cov[0] * series.pf[0] + series.error_absolute[0]
    assert abs(series.pf[0] - problem.pf_ref) <= band, (series.pf[0], problem.pf_ref, band)
    # each branch is quadratic or linear in u: the components need far fewer calls than the kinked minimum
    # (Echard et al. 2011 report 126 calls for this system with one Kriging)
    assert series.n_calls < one.n_calls, (series.n_calls, one.n_calls)


def test_series_surrogate_takes_the_governing_components_mean_and_variance():
    rng = np.random.default_rng(3)
    x = rng.uniform(-3, 3, (30, 2))
    y = np.column_stack([x[:, 0] + 1.0, 2.0 - x[:, 1] ** 2 / 4])
    sur = SeriesSurrogate(2, seed=0).fit(x, y)
    u = rng.uniform(-2, 2, (200, 2))
    m = np.column_stack([c.predict(u)[0] for c in sur.components])
    v = np.column_stack([c.predict(u)[1] for c in sur.components])
    mean, var = sur.predict(u)
    np.testing.assert_array_equal(mean, m.min(axis=1))
    np.testing.assert_array_equal(var, v[np.arange(200), m.argmin(axis=1)])
    np.testing.assert_array_equal(sur(u), mean)
    np.testing.assert_array_equal(sur.training_outputs, y.min(axis=1))


def test_posterior_draws_of_a_series_system_are_the_minimum_of_independent_components():
    # Clark (1961): for independent N(m1, s1^2), N(m2, s2^2), E[min] = m1 Phi(b) + m2 Phi(-b) - a phi(b), with
    # a = sqrt(s1^2 + s2^2) and b = (m2 - m1) / a. Two Krigings, each unsure at a point far from its design.
    rng = np.random.default_rng(7)
    x = rng.uniform(-1, 1, (12, 1))
    sur = SeriesSurrogate(2, seed=0, scale_bounds=(0.3, 0.6)).fit(x, np.column_stack([x[:, 0], 0.3 - x[:, 0]]))
    u = np.array([[1.6]])
    (m1,), (s1,) = (np.atleast_1d(t) for t in sur.components[0].predict(u))
    (m2,), (s2,) = (np.atleast_1d(t) for t in sur.components[1].predict(u))
    a = np.sqrt(s1 + s2)
    b = (m2 - m1) / a
    exact = m1 * ndtr(b) + m2 * ndtr(-b) - a * stats.norm.pdf(b)
    draws = sur.posterior_draws(u, 40_000, np.random.default_rng(1))[0]
    # 4 standard errors of the draws' mean
    assert draws.mean() == pytest.approx(exact, abs=4 * draws.std() / np.sqrt(draws.size))
    assert draws.mean() < min(m1, m2)  # the minimum of two unsure components sits below both means


def test_one_component_draws_as_its_kriging():
    rng = np.random.default_rng(2)
    x = rng.uniform(-2, 2, (15, 2))
    y = np.sin(x[:, 0]) + x[:, 1]
    sur = SeriesSurrogate(1, seed=0).fit(x, y[:, None])
    alone = KrigingSurrogate(seed=0).fit(x, y)
    u = rng.uniform(-2, 2, (40, 2))
    np.testing.assert_allclose(sur.posterior_draws(u, 30, np.random.default_rng(4)),
                               alone.posterior_draws(u, 30, np.random.default_rng(4)), atol=1e-9)


def test_a_failed_call_is_a_system_failure_and_each_component_fits_its_finite_rows():
    def g(x):
        y = np.column_stack([x[:, 0] + 3.0, x[:, 1] + 3.0])
        y[x[:, 0] > 4.0, 1] = np.nan  # the second component's response is lost there, the first's is not
        return y

    res = akmcs_multi(g, [stats.norm(), stats.norm()], levels=[0.0], system="series", seed=0, n_mc=20_000,
                      pf_floor=0.0)
    lost = np.isnan(res.design_g[:, 0])
    assert lost.any()  # the initial design reaches x1 > 4 (+-5 sigma box)
    sur = res.response_surrogate
    assert sur.components[0].n_train == res.n_calls
    assert sur.components[1].n_train == res.n_calls - lost.sum()


def test_system_needs_levels_and_a_known_rule():
    with pytest.raises(ValueError, match="needs levels"):
        akmcs_multi(four_branch_components, [stats.norm(), stats.norm()], system="series")
    with pytest.raises(ValueError, match="system must be"):
        akmcs_multi(four_branch_components, [stats.norm(), stats.norm()], levels=[0.0], system="parallel")


def test_leave_one_out_is_the_minimum_of_each_joints_refit_without_the_point():
    # the system's leave-one-out prediction of a design point: each component refitted without it (hyperparameters
    # kept; Dubrule's identity, test_kriging.py), then the smallest; the first component's row 4 is lost (NaN), so
    # that row is left out of the system's rows and of that component's fit
    rng = np.random.default_rng(5)
    x = rng.uniform(-2, 2, (20, 2))
    y = np.column_stack([x[:, 0] + 0.5 * x[:, 1] ** 2, 1.0 - x[:, 1]])
    y[4, 0] = np.nan
    sur = SeriesSurrogate(2, seed=0).fit(x, y)
    loo, _ = sur.leave_one_out()
    complete = np.flatnonzero(np.isfinite(y).all(axis=1))
    assert loo.size == complete.size == 19
    np.testing.assert_array_equal(sur.training_outputs, y[complete].min(axis=1))
    for k, i in enumerate(complete):
        refits = []
        for j, c in enumerate(sur.components):
            keep = np.isfinite(y[:, j]) & (np.arange(20) != i)
            refit = KrigingSurrogate(seed=0, nugget=c.hyperparameters.nugget, hyperparameters=c.hyperparameters)
            refit.fit(x[keep], y[keep, j], optimize=False)
            refits.append(refit.predict(x[i:i + 1], return_variance=False)[0][0])
        assert loo[k] == pytest.approx(min(refits), abs=1e-9 * np.nanmax(np.abs(y)))


def test_noise_of_the_system_weights_each_joints_by_the_points_it_governs():
    rng = np.random.default_rng(8)
    x = rng.uniform(-3, 3, (120, 1))
    # component 0 governs where x < 0 (noise 0.1), component 1 where x > 0 (noise 0.3)
    y = np.column_stack([x[:, 0] + 0.1 * rng.standard_normal(120), -x[:, 0] + 0.3 * rng.standard_normal(120)])
    sur = SeriesSurrogate(2, seed=0, estimate_nugget=True).fit(x, y)
    w = sur.governing_shares()
    assert w.sum() == pytest.approx(1.0)
    assert w[0] == pytest.approx(np.mean(y[:, 0] < y[:, 1]))
    expected = w[0] * sur.components[0].noise_variance + w[1] * sur.components[1].noise_variance
    assert sur.noise_variance == pytest.approx(expected, rel=1e-12)
    # each component's estimate is its own noise (4 standard errors of an SD from 120 residuals: 0.26 relative)
    assert sur.components[0].noise_sd == pytest.approx(0.1, rel=0.26)
    assert sur.components[1].noise_sd == pytest.approx(0.3, rel=0.26)


def test_a_system_governed_everywhere_by_one_component_learns_as_that_component_alone():
    # the second component exceeds the first by far over the whole +-5 sigma design box: the series system is its
    # first component, and its Kriging (same seed as akmcs_multi's single one) makes the same choices to the bit
    def g(x):  # a rough first component (a noise-like term, its nugget estimated): the multistart's seed matters
        first = x[:, 0] + 0.5 * np.sin(3 * x[:, 1]) + 2.5 + 0.1 * np.sin(37 * x[:, 0] * x[:, 1])
        return np.column_stack([first, 100.0 + x[:, 0]])

    marginals = [stats.norm(), stats.norm()]
    kwargs = dict(levels=[-0.5, 0.0, 0.5], seed=3, n_mc=20_000, pf_floor=0.0, max_calls=40,
                  kriging={"estimate_nugget": True})
    series = akmcs_multi(g, marginals, system="series", **kwargs)
    alone = akmcs_multi(lambda x: g(x)[:, 0], marginals, **kwargs)
    assert series.n_calls == alone.n_calls
    np.testing.assert_array_equal(series.design_u, alone.design_u)
    np.testing.assert_array_equal(series.pf, alone.pf)
    np.testing.assert_array_equal(series.error_absolute, alone.error_absolute)


def test_series_failure_probability_is_that_of_independent_scatters():
    # margins g_j with independent scatters: the product formula against the minimum sampled directly (1e6 draws,
    # 4 standard errors); a component without scatter fails exactly where its margin is negative
    g = np.array([0.1, 0.2, 0.05])
    tau = np.array([0.3, 0.05, 0.0])
    p = float(series_failure_probability([g[0], g[1], g[2]], tau))
    assert p == pytest.approx(1.0 - ndtr(0.1 / 0.3) * ndtr(0.2 / 0.05))
    e = np.random.default_rng(0).standard_normal((1_000_000, 3)) * tau
    sampled = np.mean((g + e).min(axis=1) < 0)
    assert p == pytest.approx(sampled, abs=4 * np.sqrt(p * (1 - p) / 1e6))
    assert float(series_failure_probability([np.array(-0.01), np.array(5.0)], [0.0, 0.3])) == 1.0
    assert float(series_failure_probability([np.array(np.nan), np.array(5.0)], [0.1, 0.1])) == 1.0


def test_a_noisy_series_systems_pf_takes_each_components_own_scatter():
    # y_A = 3 + u1 + N(0, 0.3^2), y_B = 3 - 0.8 u2 + 0.4 u1 + N(0, 0.03^2): the exact Pf of min(y_A, y_B) < t by
    # brute force (1e6 draws of u and of both scatters) within the curve's 95 % band (Monte Carlo plus the
    # surrogate's error, the larger of ESC's and its posterior spread's). Each component's noise estimate is its
    # own scatter. With the scatter left out (the indicator of the mean), Pf reads low, far beyond that error.
    tau = np.array([0.3, 0.03])
    rng = np.random.default_rng(0)

    def g(x):
        return (np.column_stack([3.0 + x[:, 0], 3.0 - 0.8 * x[:, 1] + 0.4 * x[:, 0]])
                + rng.standard_normal((x.shape[0], 2)) * tau)

    levels = np.array([0.5, 1.0, 1.5])
    z = np.random.default_rng(99).standard_normal((1_000_000, 4))
    y = np.column_stack([3.0 + z[:, 0], 3.0 - 0.8 * z[:, 1] + 0.4 * z[:, 0]]) + z[:, 2:] * tau
    exact = np.array([np.mean(y.min(axis=1) < t) for t in levels])
    res = akmcs_multi(g, [stats.norm(), stats.norm()], levels=levels, system="series", seed=0, n_mc=50_000,
                      pf_floor=0.0, max_calls=60, kriging={"estimate_nugget": True})
    sur = res.response_surrogate
    # 60 noisy points: the noise SD within ~30 % (4 standard errors of an SD from ~60 residuals is 37 %)
    np.testing.assert_allclose(sur.scatter_sds, tau, rtol=0.37)

    def draw(m, start):
        return np.random.default_rng(1000 + start).standard_normal((m, 2))

    pf, cov = res.estimate_on(draw, 200_000, noise_sd=res.noise_sd)
    spread = res.posterior_pf_sd(draw(3000, 5), res.noise_sd, 400, 3)
    band = 1.96 * cov * pf + np.fmax(res.error_absolute, 1.96 * spread)
    assert np.all(np.abs(pf - exact) <= band), (pf, exact, band)
    # the scatter left out (the indicator of the mean) reads Pf low at the two upper levels, by 2-5x the error of the
    # estimate that integrates it (by just about one band at t = 1.5: 0.98-1.10 of it across numpy / numba versions,
    # too thin to assert)
    mean_only = res.failure_probabilities(draw(200_000, 0), 0.0).mean(axis=0)
    assert np.all(mean_only[1:] < exact[1:]), (mean_only, exact)
    assert np.all(np.abs(mean_only - exact)[1:] > 1.5 * np.abs(pf - exact)[1:]), (mean_only, pf, exact)
    # the noisy response drawn point by point fails as often as the product formula says
    u = draw(200_000, 0)
    drawn = sur.response_draws(u, np.random.default_rng(4).standard_normal((u.shape[0], 2)))
    formula = sur.failure_probability(u, [1.0])[:, 0].mean()
    assert np.mean(drawn < 1.0) == pytest.approx(formula, abs=4 * np.sqrt(formula * (1 - formula) / u.shape[0]))


def test_a_component_that_never_fails_is_not_fitted_and_predicts_infinity():
    # the second component's response is +inf everywhere but at one point (fewer than 2 finite): not fitted; the
    # system is the first component alone, its draws and leave-one-out included
    rng = np.random.default_rng(6)
    x = rng.uniform(-2, 2, (15, 2))
    y = np.column_stack([x[:, 0] + 1.0, np.full(15, np.inf)])
    y[3, 1] = 0.5
    sur = SeriesSurrogate(2, seed=0).fit(x, y)
    alone = KrigingSurrogate(seed=0).fit(x, y[:, 0])
    assert list(sur.fitted) == [True, False] and sur.fitted_components == [sur.components[0]]
    u = rng.uniform(-2, 2, (30, 2))
    for got, want in zip(sur.predict(u), alone.predict(u)):
        np.testing.assert_array_equal(got, want)
    assert np.all(np.isposinf(sur.component_predictions(u)[0][:, 1]))
    np.testing.assert_array_equal(sur.posterior_draws(u, 5, np.random.default_rng(1)),
                                  alone.posterior_draws(u, 5, np.random.default_rng(1)))
    np.testing.assert_array_equal(sur.leave_one_out()[0], alone.leave_one_out()[0])
    assert list(sur.scatter_sds) == [alone.noise_sd, 0.0]
    # the one design point where the unfitted component's response is the smaller counts as governed by it
    assert sur.governing_shares()[1] == pytest.approx(np.mean(y[:, 1] < y[:, 0]))
    assert sur.noise_variance == pytest.approx(sur.governing_shares()[0] * alone.noise_variance, rel=1e-12)
    with pytest.raises(ValueError, match="no component has 2 finite responses"):
        SeriesSurrogate(1).fit(x, np.full((15, 1), np.inf))
