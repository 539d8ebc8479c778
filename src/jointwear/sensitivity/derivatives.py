"""Reliability derivatives dPf/dmu_i and dPf/dsigma_i from one Monte Carlo population.

Pf = E[I_F(X)]; differentiating the density f under the integral (Wu 1994; Rubinstein's likelihood-ratio method)
gives dPf/dtheta = E[I_F d log f / dtheta], with no extra model call (the *score* estimator).

Normal marginals in a Gaussian copula of correlation C (C = I for independent inputs). With the normal scores
z_j = Phi^-1(F_j(x_j)) the density is f(x) = c(z) prod_j f_j(x_j), log c(z) = -z^T (C^-1 - I) z / 2 - log det C / 2.
For a normal X_i ~ N(mu_i, sigma_i^2), z_i = (x_i - mu_i) / sigma_i, dz_i/dmu_i = -1/sigma_i,
dz_i/dsigma_i = -z_i/sigma_i and d log f_i / dmu_i = z_i / sigma_i, d log f_i / dsigma_i = (z_i^2 - 1) / sigma_i, so
(C held fixed, the other marginals of any kind)

    d log f / d mu_i    = (C^-1 z)_i / sigma_i
    d log f / d sigma_i = (z_i (C^-1 z)_i - 1) / sigma_i

and dPf/dtheta is the mean of I_F x score, its standard error the sample's. All normal and Sigma = D C D, this is
the multivariate-normal score Sigma^-1 (x - mu). The score of a non-normal marginal's mean and standard deviation
depends on how its law moves with them, so :func:`reliability_derivatives` leaves it NaN; :func:`fill_by_finite_
differences` computes it by central differences with common random numbers on a failure function of the population.

The elasticities (mu_i / Pf) dPf/dmu_i and (sigma_i / Pf) dPf/dsigma_i are dimensionless: Pf's relative change per
relative change of the mean (or standard deviation). They compare variables only where a relative change of the
mean means the same thing: not for a coordinate measured from an arbitrary origin, and 1 % of the mean is many
standard deviations of a tight tolerance but a fraction of one of a material property. dR = -dPf.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from jointwear.reliability.inputs import as_marginal
from jointwear.sensitivity.mean_shift import scales_with_mean

#: the finite-difference step, in standard deviations of the variable. On the linear limit states of
#: tests/sensitivity/test_derivatives_exact.py, 0.05, 0.1 and 0.2 sigma agree within 2 SE with the exact
#: derivative (the central difference's bias is O(h^2)); the SE grows as h^-1/2 for an indicator, so 0.1 is kept.
FD_STEP = 0.1

#: scipy's new-style families whose mean shift keeps the COV, as :func:`~jointwear.sensitivity.mean_shift.
#: scales_with_mean` reads a frozen distribution's support
SCALE_FAMILIES = {"LogNormal", "Gamma", "WeibullMin"}


@dataclass
class ReliabilityDerivatives:
    """dPf/dmu and dPf/dsigma per variable with their Monte Carlo standard errors and Pf's elasticities;
    ``method`` per variable: "score", "finite_difference", or "not_computed" (NaN values)."""

    names: list[str]
    pf: float
    dpf_dmean: np.ndarray
    dpf_dstd: np.ndarray
    dpf_dmean_se: np.ndarray
    dpf_dstd_se: np.ndarray
    elasticity_mean: np.ndarray
    elasticity_std: np.ndarray
    method: list[str] = field(default_factory=list)
    fd_step_sigma: float = FD_STEP

    def as_dict(self) -> dict:
        return {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.__dict__.items()}


class NotGaussianCopula(ValueError):
    """A copula other than the Gaussian: its score is not (C^-1 z)."""


def copula_correlation(correlation: Any, dim: int) -> np.ndarray | None:
    """The Gaussian copula's correlation matrix from a matrix or an OpenTURNS copula (None: independent); raises
    :class:`NotGaussianCopula` for another copula."""
    if correlation is None:
        return None
    import openturns as ot

    if isinstance(correlation, (ot.Distribution, ot.DistributionImplementation)):
        impl = correlation.getImplementation() if hasattr(correlation, "getImplementation") else correlation
        if impl.hasIndependentCopula():
            return None
        if impl.getClassName() != "NormalCopula":
            raise NotGaussianCopula(f"correlation: a {impl.getClassName()} is not a Gaussian copula")
        c = np.array(impl.getShapeMatrix(), dtype=float)
    else:
        from jointwear.uncertainty.copulas import check_correlation

        c = check_correlation(correlation, "correlation")
    if c.shape != (dim, dim):
        raise ValueError(f"correlation has shape {c.shape} but there are {dim} marginals")
    return c


def _elasticities(pf: float, mu: np.ndarray, sd: np.ndarray, d_mean: np.ndarray, d_std: np.ndarray):
    if pf > 0:
        return mu * d_mean / pf, sd * d_std / pf
    return np.where(np.isnan(d_mean), np.nan, 0.0), np.where(np.isnan(d_std), np.nan, 0.0)


def reliability_derivatives(x: np.ndarray, failed: np.ndarray, marginals: Sequence, names: Sequence[str],
                            correlation: Any = None) -> ReliabilityDerivatives:
    """Score estimates of dPf/dmu_i and dPf/dsigma_i from samples ``x`` (n, d) of the inputs and each row's failure
    indicator (or failure probability) ``failed``, with Pf's elasticities (module docstring).

    ``correlation``: None (independent inputs), the Gaussian copula's correlation matrix, or an OpenTURNS
    NormalCopula; ``x`` must be drawn from that joint law. Exact for normal marginals; NaN (method "not_computed")
    for every other marginal, and for all when the copula is not Gaussian: fill them with
    :func:`fill_by_finite_differences`.
    """
    x = np.asarray(x, dtype=float)
    ind = np.asarray(failed, dtype=float).reshape(-1)
    if x.ndim != 2 or x.shape[0] != ind.shape[0] or x.shape[1] != len(marginals):
        raise ValueError("x must be (n, d) with one failure flag per row and d marginals")
    n, d = x.shape
    ms = [as_marginal(m) for m in marginals]
    mu = np.array([m.mean() for m in ms])
    sd = np.array([m.std() for m in ms])
    normal = np.array([m.affine is not None for m in ms])
    try:
        c = copula_correlation(correlation, d)
    except NotGaussianCopula:  # no score here: every derivative is left to the finite differences
        normal[:] = False
        c = None
    pf = float(ind.mean())
    d_mean, d_std = np.full(d, np.nan), np.full(d, np.nan)
    se_mean, se_std = np.full(d, np.nan), np.full(d, np.nan)
    if normal.any():
        z, w = _scores(x, ms, c)
        k = np.flatnonzero(normal)
        t_mean = ind[:, None] * w[:, k] / sd[k]
        t_std = ind[:, None] * (z[:, k] * w[:, k] - 1.0) / sd[k]
        d_mean[k], d_std[k] = t_mean.mean(axis=0), t_std.mean(axis=0)
        se_mean[k] = t_mean.std(axis=0, ddof=1) / np.sqrt(n)
        se_std[k] = t_std.std(axis=0, ddof=1) / np.sqrt(n)
    el_mean, el_std = _elasticities(pf, mu, sd, d_mean, d_std)
    method = ["score" if f else "not_computed" for f in normal]
    return ReliabilityDerivatives(list(names), pf, d_mean, d_std, se_mean, se_std, el_mean, el_std, method)


def mean_scores(x: np.ndarray, marginals: Sequence, correlation: Any = None) -> np.ndarray:
    """d log f / d mu_i = (C^-1 z)_i / sigma_i at each row of ``x`` (n, d) (module docstring): the weights of the
    score estimator dPf/dmu_i = E[I_F x score_i]; NaN columns where the score is not known (a non-normal marginal,
    a copula other than the Gaussian)."""
    x = np.asarray(x, dtype=float)
    ms = [as_marginal(m) for m in marginals]
    out = np.full(x.shape, np.nan)
    try:
        c = copula_correlation(correlation, len(ms))
    except NotGaussianCopula:
        return out
    normal = np.array([m.affine is not None for m in ms])
    if normal.any():
        k = np.flatnonzero(normal)
        out[:, k] = _scores(x, ms, c)[1][:, k] / np.array([ms[j].std() for j in k])
    return out


def _scores(x: np.ndarray, ms: Sequence, c: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The normal scores z of the rows of ``x`` and C^-1 z (rows (C^-1 z)^T, C^-1 symmetric; z without a copula)."""
    z = np.column_stack([m.to_normal(x[:, j]) for j, m in enumerate(ms)])
    return z, (z if c is None else z @ np.linalg.inv(c))


def perturbed_column(marginal, column: np.ndarray, what: str, step: float) -> np.ndarray:
    """Column i of the population with its marginal's mean (``what`` = "mean") or standard deviation ("std")
    moved by ``step`` (SI, signed), each sample kept at its rank so a copula is kept.

    Mean: a location shift x + step, but x (1 + step / mu) for the families whose mean shift keeps the COV
    (lognormal, gamma, Weibull: ``shifted_marginal`` scales them). Std: mu + (1 + step / sigma)(x - mu).
    """
    m = as_marginal(marginal)
    mu, sd = m.mean(), m.std()
    if what == "std":
        return mu + (1.0 + step / sd) * (column - mu)
    scales = scales_with_mean(marginal) if hasattr(marginal, "dist") else m.name in SCALE_FAMILIES
    if scales:
        return column * (1.0 + step / mu)
    return column + step


def fill_by_finite_differences(deriv: ReliabilityDerivatives, x: np.ndarray,
                               failure_of: Callable[[np.ndarray, int], np.ndarray], marginals: Sequence,
                               step: float = FD_STEP) -> ReliabilityDerivatives:
    """``deriv`` with its "not_computed" entries replaced by central finite differences with common random numbers.

    ``failure_of(x', i)``: each row's failure indicator (or probability) for the population ``x'``, which differs
    from ``x`` in column i only. With h = ``step`` sigma_i and D_r = I_F(x_r^+) - I_F(x_r^-) per row
    (:func:`perturbed_column` moving the mean or the std by +-h), dPf/dtheta = mean(D) / 2h and its SE is
    std(D) / (sqrt(n) 2h): the same samples on both sides, so the noise is that of the rows the step moves across
    the limit state only. Bias O(h^2).
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    out = ReliabilityDerivatives(deriv.names, deriv.pf, deriv.dpf_dmean.copy(), deriv.dpf_dstd.copy(),
                                 deriv.dpf_dmean_se.copy(), deriv.dpf_dstd_se.copy(), deriv.elasticity_mean.copy(),
                                 deriv.elasticity_std.copy(), list(deriv.method), step)
    mus = np.array([as_marginal(m).mean() for m in marginals])
    sds = np.array([as_marginal(m).std() for m in marginals])
    for i, how in enumerate(deriv.method):
        if how != "not_computed":
            continue
        h = step * sds[i]
        for what, value, se in (("mean", out.dpf_dmean, out.dpf_dmean_se), ("std", out.dpf_dstd, out.dpf_dstd_se)):
            sides = []
            for sign in (1.0, -1.0):
                xs = x.copy()
                xs[:, i] = perturbed_column(marginals[i], x[:, i], what, sign * h)
                sides.append(np.asarray(failure_of(xs, i), dtype=float).reshape(-1))
            diff = sides[0] - sides[1]
            value[i] = diff.mean() / (2.0 * h)
            se[i] = diff.std(ddof=1) / np.sqrt(n) / (2.0 * h)
        out.method[i] = "finite_difference"
    out.elasticity_mean, out.elasticity_std = _elasticities(out.pf, mus, sds, out.dpf_dmean, out.dpf_dstd)
    return out
