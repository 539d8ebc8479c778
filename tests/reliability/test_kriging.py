"""Kriging surrogate: numpy prediction equals OpenTURNS' own prediction; robustness."""

import numpy as np
import pytest

from jointwear.reliability import KrigingSurrogate


def _data(d, n, seed=0):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-3, 3, (n, d))
    y = np.sin(x[:, 0]) + 0.3 * x[:, 1] ** 2 + 0.1 * x.sum(axis=1)
    return x, y


@pytest.mark.parametrize("linear_trend", [False, True])
@pytest.mark.parametrize("d,n", [(2, 25), (6, 40)])
def test_prediction_matches_openturns(d, n, linear_trend):
    x, y = _data(d, n)
    k = KrigingSurrogate(nugget=1e-8, n_starts=1, linear_trend=linear_trend).fit(x, y)
    xt = np.random.default_rng(1).uniform(-3, 3, (7, d))
    mean, var = k.predict(xt)
    mean_ot, var_ot = k.predict_openturns(xt)
    # means: identical formulas, differences are round-off of a conditioned solve (cond(R) ~ 1e8 here)
    np.testing.assert_allclose(mean, mean_ot, rtol=1e-6, atol=1e-8 * np.ptp(y))
    # variances: same DACE/universal-Kriging formula; absolute round-off ~ sigma^2 * cond(R) * eps
    np.testing.assert_allclose(var, var_ot, rtol=1e-4, atol=1e-6 * np.var(y))


@pytest.mark.parametrize("linear_trend", [False, True])
@pytest.mark.parametrize("estimate_nugget", [False, True])
def test_posterior_covariance_matches_openturns(estimate_nugget, linear_trend):
    x, y = _data(3, 30)
    if estimate_nugget:  # a noisy response: the fit finds a nugget of order 0.2^2 / var(y)
        y = y + 0.2 * np.random.default_rng(3).standard_normal(y.size)
    k = KrigingSurrogate(nugget=1e-8, n_starts=1, estimate_nugget=estimate_nugget, linear_trend=linear_trend).fit(x, y)
    xt = np.random.default_rng(1).uniform(-3, 3, (6, 3))
    cov = k.posterior_covariance(xt)
    np.testing.assert_allclose(np.diag(cov), k.predict(xt)[1], rtol=1e-9, atol=1e-12 * np.var(y))
    # OpenTURNS' conditional covariance is that of a noisy observation: the latent one plus the noise variance
    import openturns as ot

    cov_ot = np.array(ot.GaussianProcessConditionalCovariance(k.to_openturns()).getConditionalCovariance(
        ot.Sample(xt))) * np.var(y) - k.noise_variance * np.eye(6)  # OpenTURNS works on y / std(y)
    if estimate_nugget:
        assert k.noise_variance > 1e-3 * np.var(y)  # the case tests the nugget's part
    # off the diagonal the two agree to ~1e-12: the round-off bound of the variances of
    # test_prediction_matches_openturns covers that with room
    np.testing.assert_allclose(cov, cov_ot, rtol=1e-4, atol=1e-6 * np.var(y))


def test_prediction_interpolates_and_chunks():
    x, y = _data(3, 30)
    k = KrigingSurrogate(n_starts=1, chunk_size=7, n_threads=2).fit(x, y)
    mean, var = k.predict(x)
    # interpolation up to the 1e-10 nugget (relative to the output spread)
    np.testing.assert_allclose(mean, y, atol=1e-5 * np.ptp(y))
    assert np.all(var <= 1e-6 * np.var(y))
    # chunked + threaded prediction equals one-chunk prediction up to BLAS summation order (~1e-10 relative)
    xt = np.random.default_rng(2).normal(size=(100, 3))
    m1, v1 = k.predict(xt)
    k.chunk_size, k.n_threads = 10_000, 1
    m2, v2 = k.predict(xt)
    np.testing.assert_allclose(m1, m2, rtol=1e-8, atol=1e-10 * np.ptp(y))
    np.testing.assert_allclose(v1, v2, rtol=1e-6, atol=1e-12 * np.var(y))


def test_duplicated_points_and_wild_scales_fit():
    # nearly duplicated design points + output of order 1e-6 (metres of wear): the nugget escalation and the
    # output standardisation must keep the fit usable
    x, y = _data(2, 20)
    x = np.vstack([x, x[:5] + 1e-12])
    y = np.concatenate([y, y[:5]]) * 1e-6
    k = KrigingSurrogate().fit(x, y)
    mean, var = k.predict(x[:5])
    np.testing.assert_allclose(mean, y[:5], atol=1e-3 * np.ptp(y))
    assert np.all(np.isfinite(var))


def test_reconditioning_keeps_hyperparameters():
    x, y = _data(2, 30)
    k = KrigingSurrogate(n_starts=1).fit(x[:20], y[:20])
    scale = k.hyperparameters.scale.copy()
    k.fit(x, y, optimize=False)
    np.testing.assert_array_equal(k.hyperparameters.scale, scale)
    # with larger correlation lengths R is worse conditioned and the nugget may escalate (up to 1e-4):
    # interpolation then holds to ~nugget x output spread
    np.testing.assert_allclose(k.predict(x)[0], y, atol=1e-3 * np.ptp(y))


def test_estimated_nugget_smooths_a_noisy_response():
    # y = sin(2 u) + N(0, 0.1^2): with the nugget estimated, the mean should track sin(2 u) more closely than
    # the interpolant does, and the chosen relative nugget should be far above the interpolation default.
    from jointwear.reliability import KrigingSurrogate

    rng = np.random.default_rng(0)
    u = rng.uniform(-3, 3, size=(60, 1))
    y = np.sin(2 * u[:, 0]) + 0.1 * rng.standard_normal(60)
    grid = np.linspace(-2.5, 2.5, 201)[:, None]
    truth = np.sin(2 * grid[:, 0])
    noisy = KrigingSurrogate(estimate_nugget=True, seed=1).fit(u, y)
    plain = KrigingSurrogate(seed=1).fit(u, y)
    err_noisy = np.sqrt(np.mean((noisy.predict(grid, return_variance=False)[0] - truth) ** 2))
    err_plain = np.sqrt(np.mean((plain.predict(grid, return_variance=False)[0] - truth) ** 2))
    assert noisy.hyperparameters.nugget >= 1e-3  # noise variance / process variance ~ 0.01 / 0.5
    assert err_noisy < err_plain
    assert err_noisy < 0.1  # below the noise level: the smoother averages several noisy points


@pytest.mark.parametrize("linear_trend", [False, True])
@pytest.mark.parametrize("estimate_nugget", [False, True])
def test_leave_one_out_is_the_refit_without_each_point(estimate_nugget, linear_trend):
    # Dubrule's closed form is an identity: it must equal n refits on n - 1 points with the hyperparameters kept,
    # to rounding (the variances once each refit's re-estimated sigma^2 is divided out).
    rng = np.random.default_rng(3)
    x, y = _data(3, 30)
    y = y + 0.05 * rng.standard_normal(y.size)
    full = KrigingSurrogate(seed=0, estimate_nugget=estimate_nugget, linear_trend=linear_trend).fit(x, y)
    mean, var = full.leave_one_out()
    for i in range(y.size):
        keep = np.arange(y.size) != i
        refit = KrigingSurrogate(seed=0, nugget=full.hyperparameters.nugget, hyperparameters=full.hyperparameters,
                                 linear_trend=linear_trend)
        refit.fit(x[keep], y[keep], optimize=False)
        m, v = refit.predict(x[i:i + 1])
        assert m[0] == pytest.approx(mean[i], abs=1e-9 * np.ptp(y))
        assert v[0] / refit.process_variance == pytest.approx(var[i] / full.process_variance, rel=1e-8, abs=1e-12)



def test_a_linear_trend_is_estimated_with_the_process_once_the_design_can_hold_it():
    """linear_trend: universal Kriging with the basis [1, u]. Exact on a linear response: the prediction is the
    response itself far outside the design (where a constant trend reverts to its mean); below 2 points per
    coefficient no trend is fitted and the constant phase keeps the default bounds (the constant Kriging's answer,
    bit for bit)."""
    from jointwear.reliability.kriging import LINEAR_TREND_POINTS_PER_TERM

    rng = np.random.default_rng(5)
    d = 3
    coef = np.array([2.0, 0.5, -0.3, 0.0])

    def linear(u):
        return coef[0] + u @ coef[1:]

    x = rng.uniform(-1.0, 1.0, (20, d))
    k = KrigingSurrogate(seed=0, linear_trend=True).fit(x, linear(x))
    far = np.array([[4.0, -4.0, 3.0], [-5.0, 2.0, 0.0]])
    np.testing.assert_allclose(k.predict(far, return_variance=False)[0], linear(far), rtol=0, atol=1e-9)
    constant = KrigingSurrogate(seed=0).fit(x, linear(x))
    assert np.max(np.abs(constant.predict(far, return_variance=False)[0] - linear(far))) > 1e-3  # only approaches it
    few = LINEAR_TREND_POINTS_PER_TERM * (d + 1) - 1
    small = KrigingSurrogate(seed=0, linear_trend=True, trend_scale_bounds=(1.0, 100.0)).fit(x[:few], linear(x[:few]))
    plain = KrigingSurrogate(seed=0).fit(x[:few], linear(x[:few]))
    np.testing.assert_array_equal(small.predict(far)[0], plain.predict(far)[0])
    np.testing.assert_array_equal(small.predict(far)[1], plain.predict(far)[1])
    # the leave-one-out reads the same trend; the trend's fits keep their own bounds
    noisy = linear(x) + 0.05 * rng.standard_normal(x.shape[0])
    fit = KrigingSurrogate(seed=0, linear_trend=True, estimate_nugget=True, trend_scale_bounds=(1.0, 100.0)).fit(
        x, noisy)
    loo, _ = fit.leave_one_out()
    assert np.sqrt(np.mean((loo - noisy) ** 2)) < 0.1  # the noise, not the trend's 1.1 spread
    assert np.all(fit.hyperparameters.scale >= 1.0 - 1e-9)


def _restricted_loglik(x, ys, scale, nugget):
    """REML log-likelihood of the linear trend from the contrasts z = K^T y, K an orthonormal basis of the null space
    of F^T (Patterson and Thompson 1971): z ~ N(0, sigma^2 K^T C K), sigma^2 profiled out; and that sigma^2."""
    from scipy.linalg import null_space

    n, p = x.shape[0], x.shape[1] + 1
    a = x / scale
    c = np.exp(-0.5 * np.sum((a[:, None, :] - a[None, :, :]) ** 2, axis=-1)) + nugget * np.eye(n)
    k = null_space(np.column_stack([np.ones(n), x]).T)
    z, kck = k.T @ ys, k.T @ c @ k
    sigma2 = z @ np.linalg.solve(kck, z) / (n - p)
    return -0.5 * (n - p) * np.log(sigma2) - 0.5 * np.linalg.slogdet(kck)[1], sigma2


def test_the_linear_trend_chooses_its_nugget_by_the_restricted_likelihood():
    """With 6 coefficients on 14 points, maximum likelihood takes the response for a plane plus white noise (the
    grid's largest relative nugget, 10) at 9 of these 10 designs (REML at 3), where the noise is 2 % of the
    response's spread.
    The nugget profiled at fixed lengths must be the argmax of the REML likelihood computed independently from the
    contrasts (an identity: Harville 1974), and the process variance its sigma^2 (to rounding)."""
    from jointwear.reliability.kriging import KrigingHyperparameters

    grid = KrigingSurrogate().nugget_grid
    d, n, scale = 5, 14, np.full(5, 2.0)
    plane_noise = 0
    for seed in range(10):
        rng = np.random.default_rng(seed)
        x = rng.normal(size=(n, d))
        y = x @ rng.normal(size=d) + 0.3 * np.sin(2 * x[:, 0]) + 0.05 * rng.normal(size=n)
        ys = (y - y.mean()) / y.std()
        reml = [_restricted_loglik(x, ys, scale, g)[0] for g in grid]
        k = KrigingSurrogate(linear_trend=True, estimate_nugget=True, nugget=grid[0],
                             hyperparameters=KrigingHyperparameters(scale, grid[0])).fit(x, y, optimize=False)
        chosen = grid[int(np.argmax(reml))]
        assert k.hyperparameters.nugget == chosen
        assert k.process_variance / y.var() == pytest.approx(_restricted_loglik(x, ys, scale, chosen)[1], rel=1e-9)
        plane_noise += chosen == grid[-1]
    assert plane_noise <= 3


def test_estimated_noise_is_the_noise_added():
    # y = smooth + N(0, 0.2^2) at 200 points: the fit's noise SD must match 0.2 within 4 standard errors of an SD
    # estimated from 200 residuals (0.2 * 4 / sqrt(2 * 200) = 0.04); an interpolating fit would say ~0.
    rng = np.random.default_rng(5)
    x = rng.uniform(-3, 3, (200, 2))
    y = np.sin(x[:, 0]) + 0.3 * x[:, 1] + 0.2 * rng.standard_normal(200)
    fit = KrigingSurrogate(seed=0, estimate_nugget=True).fit(x, y)
    assert np.sqrt(fit.noise_variance) == pytest.approx(0.2, abs=0.04)


def test_gaussian_draws_of_a_low_rank_covariance_left_indefinite_by_round_off():
    """A Kriging's posterior covariance over a population: of low rank, and slightly indefinite after round-off. The
    draws reproduce it (4 standard errors of a sample covariance of 20,000 draws, sqrt(2 / 20,000) of the largest
    variance) and stay in its 4 directions up to round-off: no jitter noise is added to them. A covariance indefinite
    by 2 % of its diagonal (past any round-off) gives draws whose covariance is off by no more than that, plus the
    same 4 errors."""
    from jointwear.reliability.kriging import gaussian_draws

    rng = np.random.default_rng(0)
    basis = rng.standard_normal((300, 4))
    noise = rng.standard_normal((300, 300)) * 1e-13
    cov = basis @ basis.T + (noise + noise.T)
    assert np.linalg.eigvalsh(cov).min() < 0  # indefinite, as round-off leaves it
    draws = gaussian_draws(np.ones(300), cov, 20_000, np.random.default_rng(1))
    big = np.diag(cov).max()
    np.testing.assert_allclose(np.cov(draws), cov, atol=4 * np.sqrt(2 / 20_000) * big)
    q = np.linalg.qr(basis)[0]
    outside = (draws - 1.0) - q @ (q.T @ (draws - 1.0))  # a jitter of 1e-10 of the diagonal would put ~4e-10 here
    assert np.mean(outside**2, axis=1).max() <= 1e-11 * big

    cov = np.array([[1.0, 1.02], [1.02, 1.0]])  # eigenvalues 2.02 and -0.02
    draws = gaussian_draws(np.zeros(2), cov, 20_000, np.random.default_rng(0))
    assert np.abs(np.cov(draws) - cov).max() <= 2 * 0.02 * 1.02 + 4 * np.sqrt(2 / 20_000) * 2.02


def test_posterior_draws_do_not_depend_on_the_blas_threads():
    """The posterior spread of Pf moved by one unit in the last place between 1 and 2 BLAS threads (the threaded
    product of the factor and the normal draws); docs/compute.md promises numbers independent of the threads."""
    from threadpoolctl import threadpool_limits

    from jointwear.reliability.kriging import gaussian_draws

    a = np.random.default_rng(0).standard_normal((3000, 1500))  # a rank of 1500: threaded products split it
    cov = a @ a.T / 1500
    draws = []
    for threads in (1, 2):
        with threadpool_limits(limits=threads, user_api="blas"):
            draws.append(gaussian_draws(np.zeros(3000), cov, 400, np.random.default_rng(1)))
    np.testing.assert_array_equal(draws[0], draws[1])


def test_an_openturns_without_the_fitter_is_an_error_not_a_bad_design(monkeypatch):
    """openturns 1.23-1.26 have no top-level GaussianProcessFitter: every fit 'failed' with a RuntimeWarning and
    the Kriging ran on a guessed length scale for the whole study. A missing API is raised, not absorbed."""
    import openturns as ot

    monkeypatch.delattr(ot, "GaussianProcessFitter")
    x = np.linspace(0.0, 1.0, 8)[:, None]
    with pytest.raises(AttributeError, match="GaussianProcessFitter"):
        KrigingSurrogate(n_starts=1).fit(x, np.sin(3.0 * x[:, 0]))
