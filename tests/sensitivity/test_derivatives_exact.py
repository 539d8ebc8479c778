"""Reliability derivatives against exact ones on a linear limit state g = b - a.X (failure where g < 0).

Tolerances: 4 standard errors of the estimator, the SE each estimate carries (a two-sided 4-SE band misses with
probability 6e-5 per comparison); the exact values are closed forms or Gauss quadrature accurate to ~1e-10.
"""

import math

import numpy as np
import openturns as ot
import pytest
from scipy import stats

from jointwear.sensitivity import reliability_derivatives

N = 400_000
B, A = 6.0, np.array([1.0, 2.0, -0.5])
MU, S = np.array([1.0, 0.5, 2.0]), np.array([0.8, 0.6, 1.0])


def exact_normal(c: np.ndarray):
    """X ~ N(mu, D C D): g ~ N(b - a.mu, sd_g^2), sd_g^2 = a^T D C D a, Pf = Phi(-beta), beta = (b - a.mu) / sd_g.
    dPf/dmu_i = phi(beta) a_i / sd_g; d sd_g / d sigma_i = a_i (C D a)_i / sd_g, so
    dPf/dsigma_i = phi(beta) beta a_i (C D a)_i / sd_g^2 (C held fixed)."""
    cda = c @ (S * A)
    sd_g = math.sqrt((S * A) @ cda)
    beta = (B - A @ MU) / sd_g
    phi = stats.norm.pdf(beta)
    return stats.norm.cdf(-beta), phi * A / sd_g, phi * beta * A * cda / sd_g**2


def check(res, pf, dmean, dstd):
    assert abs(res.pf - pf) < 4 * math.sqrt(pf * (1 - pf) / N)  # 4 binomial SE
    assert np.all(np.abs(res.dpf_dmean - dmean) < 4 * res.dpf_dmean_se), (res.dpf_dmean, dmean, res.dpf_dmean_se)
    assert np.all(np.abs(res.dpf_dstd - dstd) < 4 * res.dpf_dstd_se), (res.dpf_dstd, dstd, res.dpf_dstd_se)


def test_independent_normals_by_the_score():
    marg = [stats.norm(m, s) for m, s in zip(MU, S)]
    x = np.column_stack([m.rvs(size=N, random_state=np.random.default_rng(1 + k)) for k, m in enumerate(marg)])
    res = reliability_derivatives(x, B - x @ A < 0, marg, ["x1", "x2", "x3"])
    check(res, *exact_normal(np.eye(3)))
    assert res.method == ["score"] * 3


@pytest.mark.parametrize("as_copula", [False, True])
def test_correlated_normals_take_the_copula_score(as_copula):
    """rho(x1, x2) = 0.6: the independent score u_i / sigma_i gave dPf/dmu_1 0.0108 against 0.0059 (24 SE off)."""
    c = np.array([[1.0, 0.6, 0.0], [0.6, 1.0, 0.0], [0.0, 0.0, 1.0]])
    marg = [stats.norm(m, s) for m, s in zip(MU, S)]
    x = MU + np.random.default_rng(3).standard_normal((N, 3)) @ np.linalg.cholesky(np.outer(S, S) * c).T
    corr = ot.NormalCopula(ot.CorrelationMatrix(3, c.ravel().tolist())) if as_copula else c
    res = reliability_derivatives(x, B - x @ A < 0, marg, ["x1", "x2", "x3"], correlation=corr)
    check(res, *exact_normal(c))


def test_non_normal_marginals_are_not_given_a_wrong_score():
    marg = [stats.uniform(0.0, 1.0), stats.norm(0.0, 1.0)]
    x = np.column_stack([m.rvs(size=1000, random_state=np.random.default_rng(k)) for k, m in enumerate(marg)])
    res = reliability_derivatives(x, x.sum(axis=1) > 1.5, marg, ["u", "n"])
    assert np.isnan(res.dpf_dmean[0]) and np.isnan(res.dpf_dstd[0]) and np.isnan(res.elasticity_mean[0])
    assert np.isfinite(res.dpf_dmean[1]) and res.method == ["not_computed", "score"]


def gauss_expectation(h):
    """E[h(X1, X2)] for X1 ~ U(0, 1) (Gauss-Legendre) and X2 = exp(m + s Z) (Gauss-Hermite), on a tensor grid."""
    t, wt = np.polynomial.legendre.leggauss(200)
    z, wz = np.polynomial.hermite_e.hermegauss(120)
    x1, x2 = np.meshgrid(0.5 * (t + 1.0), np.exp(LOGM + LOGS * z), indexing="ij")
    return float(np.sum(np.outer(0.5 * wt, wz / math.sqrt(2 * math.pi)) * h(x1, x2)))


LOGM, LOGS = math.log(0.5), 0.5


def test_uniform_and_lognormal_by_finite_differences():
    """X1 ~ U(0, 1), X2 lognormal, X3 ~ N(2, 1): conditional on X1, X2, Pf = Phi(-t),
    t = (b - a1 X1 - a2 X2 - a3 mu3) / (|a3| s3). The mean of X1 moves by location (dt/dh = -a1 / |a3| s3); that of
    the lognormal by scaling X2 (1 + h / mu2) (dt/dh = -a2 X2 / mu2 / |a3| s3); a std moves X_i - mu_i by (1 + h / s_i)
    (dt/dh = -a_i (X_i - mu_i) / s_i / |a3| s3). dPf/dh = E[phi(t) (-dt/dh)] by quadrature."""
    from jointwear.sensitivity.derivatives import fill_by_finite_differences

    marg = [stats.uniform(0.0, 1.0), stats.lognorm(LOGS, scale=math.exp(LOGM)), stats.norm(MU[2], S[2])]
    mu = np.array([m.mean() for m in marg])
    sd = np.array([m.std() for m in marg])
    g_sd = abs(A[2]) * S[2]

    def t(x1, x2):
        return (B - 3.0 - A[0] * x1 - A[1] * x2 - A[2] * MU[2]) / g_sd  # b - 3: Pf ~ 0.1

    pf = gauss_expectation(lambda x1, x2: stats.norm.cdf(-t(x1, x2)))
    dens = lambda x1, x2: stats.norm.pdf(t(x1, x2)) / g_sd  # noqa: E731
    d_mean = [gauss_expectation(lambda x1, x2: dens(x1, x2) * A[0]),
              gauss_expectation(lambda x1, x2: dens(x1, x2) * A[1] * x2 / mu[1])]
    d_std = [gauss_expectation(lambda x1, x2: dens(x1, x2) * A[0] * (x1 - mu[0]) / sd[0]),
             gauss_expectation(lambda x1, x2: dens(x1, x2) * A[1] * (x2 - mu[1]) / sd[1])]
    x = np.column_stack([m.rvs(size=N, random_state=np.random.default_rng(10 + k)) for k, m in enumerate(marg)])

    def failure_of(xs, i):
        return (B - 3.0 - xs @ A < 0).astype(float)

    score = reliability_derivatives(x, failure_of(x, -1), marg, ["u", "ln", "n"])
    res = fill_by_finite_differences(score, x, failure_of, marg)
    assert res.method == ["finite_difference", "finite_difference", "score"]
    assert abs(res.pf - pf) < 4 * math.sqrt(pf * (1 - pf) / N)
    for i in range(2):
        assert abs(res.dpf_dmean[i] - d_mean[i]) < 4 * res.dpf_dmean_se[i], (i, res.dpf_dmean[i], d_mean[i])
        assert abs(res.dpf_dstd[i] - d_std[i]) < 4 * res.dpf_dstd_se[i], (i, res.dpf_dstd[i], d_std[i])
        assert res.elasticity_mean[i] == pytest.approx(mu[i] * res.dpf_dmean[i] / res.pf, rel=1e-12)  # algebra
    assert res.dpf_dmean[2] == score.dpf_dmean[2]  # the normal input keeps its score


def test_a_local_slope_against_a_consistent_mean_shift_trend_is_flagged():
    """R rises from 0.1 at mean 0.8 to 0.9 at mean 1.2 (each beyond its 0.01 error): a resolved dR/dmu < 0 contradicts
    it (the slider-crank's l2: dR/dmu = -1002 +- 102 while R goes 0.0035 -> 0.885)."""
    from jointwear.study.sensitivity import slope_contradicts_shifts

    base = dict(r_nominal=0.5, r_shifted=(0.1, 0.9), errors=(0.01, 0.01), shifted_means=(0.8, 1.2))
    assert slope_contradicts_shifts(-1000.0, 100.0, **base)
    assert not slope_contradicts_shifts(+1000.0, 100.0, **base)  # the slope agrees
    assert not slope_contradicts_shifts(-1000.0, 1200.0, **base)  # the slope is not resolved (its error > |slope|)
    # one side beyond its error tells the trend (a designer's crank read -43.6 +- 6.6 while R at x 1.2 rose by 0.048,
    # 2.3 times its error, and R at x 0.8 stayed within its own)
    assert slope_contradicts_shifts(-1000.0, 100.0, **(base | {"r_shifted": (0.495, 0.9)}))
    assert not slope_contradicts_shifts(-1000.0, 100.0, **(base | {"r_shifted": (0.495, 0.505)}))  # both within
    assert not slope_contradicts_shifts(-1000.0, 100.0, **(base | {"r_shifted": (0.9, 0.95)}))  # no monotone trend
    # a negative mean: x 0.8 -> -0.8, x 1.2 -> -1.2, so R rising from the first to the second falls with the mean
    assert not slope_contradicts_shifts(-1000.0, 100.0, **(base | {"shifted_means": (-0.8, -1.2)}))
    from jointwear.report.result_sections import _elasticity_text

    text = _elasticity_text({"names": ["l2"], "dpf_dmean": [1002.0], "dpf_dmean_se": [102.0]},
                            {"name": "l2", "elasticity_mean": -5.0, "slope_contradicts_shifts": True})
    assert text.endswith("(local slope contradicts the mean shifts)") and text.startswith("-5")
    # the half-width is the slope's recorded 95 % error where the study gives one (the surrogate's own included):
    # 5 x 2000 / 1002 = 9.98 > 5; a folder without it, 1.96 SE: 5 x 200 / 1002 = 0.998
    both = {"name": "l2", "elasticity_mean": -5.0, "dR_dmean_error": 2000.0}
    assert _elasticity_text({"names": ["l2"], "dpf_dmean": [1002.0], "dpf_dmean_se": [102.0]}, both) \
        == "-5 \u00b1 10 (not resolved)"
    assert _elasticity_text({"names": ["l2"], "dpf_dmean": [1002.0], "dpf_dmean_se": [102.0]},
                            {"name": "l2", "elasticity_mean": -5.0}) == "-5 \u00b1 1"


def test_a_copula_other_than_the_gaussian_leaves_every_derivative_to_the_finite_differences():
    """The score (C^-1 z) holds for the Gaussian copula only: with a Clayton copula no variable gets it."""
    x = np.random.default_rng(0).standard_normal((1000, 2))
    failed = (x.sum(axis=1) > 2.0).astype(float)
    marginals = [stats.norm(), stats.norm()]
    res = reliability_derivatives(x, failed, marginals, ["a", "b"], correlation=ot.ClaytonCopula(2.0))
    assert res.method == ["not_computed", "not_computed"] and np.isnan(res.dpf_dmean).all()
    assert reliability_derivatives(x, failed, marginals, ["a", "b"], correlation=ot.NormalCopula(2)).method == [
        "score", "score"]
