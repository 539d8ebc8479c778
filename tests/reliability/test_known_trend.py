"""A Kriging told a known part of its response (KrigingSurrogate(offset=...), akmcs_multi(trend=...))."""

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import KrigingSurrogate, akmcs_multi


def known(u: np.ndarray) -> np.ndarray:
    """A part no Gaussian correlation of a few points would learn: a fold and a ripple."""
    return np.abs(u[:, 0]) + 0.3 * np.sin(5.0 * u[:, 1])


def test_offset_with_a_constant_rest_is_predicted_exactly():
    rng = np.random.default_rng(0)
    u = rng.uniform(-3, 3, (15, 2))
    k = KrigingSurrogate(offset=known).fit(u, known(u) + 2.5)
    new = rng.uniform(-3, 3, (200, 2))
    mean, var = k.predict(new)
    # the rest is the constant 2.5, which ordinary Kriging's trend reproduces: the prediction is exact to rounding
    np.testing.assert_allclose(mean, known(new) + 2.5, rtol=0, atol=1e-9)
    loo, _ = k.leave_one_out()
    np.testing.assert_allclose(loo, known(u) + 2.5, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(k.training_outputs, known(u) + 2.5)  # the outputs as given, not less the offset
    assert np.all(var >= 0)


def test_offset_shifts_the_mean_and_keeps_the_variance():
    rng = np.random.default_rng(1)
    u = rng.uniform(-3, 3, (20, 2))
    rest = np.cos(u[:, 0]) + 0.5 * u[:, 1]
    plain = KrigingSurrogate(seed=0).fit(u, rest)
    # the same hyperparameters (the optimiser's path follows the outputs' last digits)
    told = KrigingSurrogate(offset=known, hyperparameters=plain.hyperparameters).fit(u, rest + known(u),
                                                                                    optimize=False)
    new = rng.uniform(-3, 3, (50, 2))
    (m0, v0), (m1, v1) = plain.predict(new), told.predict(new)
    # the same fit of the same rest: exact up to rounding
    np.testing.assert_allclose(m1, m0 + known(new), rtol=0, atol=1e-9)
    np.testing.assert_allclose(v1, v0, rtol=1e-9, atol=1e-15)
    d0, d1 = plain.posterior_draws(new[:5], 3, np.random.default_rng(2)), told.posterior_draws(
        new[:5], 3, np.random.default_rng(2))
    np.testing.assert_allclose(d1, d0 + known(new[:5])[:, None], rtol=0, atol=1e-8)
    np.testing.assert_allclose(told.predict_openturns(new[:5])[0], m1[:5], rtol=0, atol=1e-6)  # OpenTURNS agrees


def test_trend_in_x_learns_what_the_kriging_alone_cannot():
    # g = known(x) + 0.1 x3 on standard normals: the fold and the ripple are given, a linear rest is learnt
    marginals = [stats.norm(0, 1)] * 3

    def g(x):
        return known(x) + 0.1 * x[:, 2]

    level = 0.25
    exact = float(np.mean(g(np.random.default_rng(0).standard_normal((2_000_000, 3))) < level))  # Pf about 0.2
    kw = dict(levels=[level], seed=3, n_mc=100_000, error_tol=0.01, max_calls=40)
    told = akmcs_multi(g, marginals, trend=known, **kw)
    plain = akmcs_multi(g, marginals, **kw)
    # Tolerance: 4 standard errors of the 1e5-point population (the 2e6-sample reference's are a fifth of it) plus
    # the engine's 1 % error rule
    tol = 4 * np.sqrt(exact * (1 - exact) / 100_000) + 0.01 * exact
    assert told.converged and abs(told.pf[0] - exact) < tol, (told.pf[0], exact, told.n_calls)
    assert not plain.converged and plain.n_calls == 40  # alone, the Kriging spends the budget on the ripple


def test_trend_is_for_one_response():
    with pytest.raises(ValueError, match="trend"):
        akmcs_multi(lambda x: x, [stats.norm()] * 2, levels=[0.0], system="series", trend=lambda x: x[:, 0])
