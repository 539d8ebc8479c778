"""A series system learnt one Kriging per component (akmcs_multi(system="series"), SeriesSurrogate)."""

import numpy as np
import pytest
from scipy import stats
from scipy.special import ndtr

from jointwear.reliability import KrigingSurrogate, akmcs_multi, problems
from jointwear.reliability.system import SeriesSurrogate


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
