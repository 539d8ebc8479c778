"""Reliability derivatives from one Monte Carlo population (score-function estimator).

For independent normal inputs X_i ~ N(mu_i, sigma_i^2) and failure indicator I_F(x),
Pf = E[I_F], and differentiating the density under the integral (Wu 1994; Rubinstein's likelihood-ratio
method) gives, with u_i = (x_i - mu_i) / sigma_i,

    dPf/dmu_i    = E[I_F u_i] / sigma_i
    dPf/dsigma_i = E[I_F (u_i^2 - 1)] / sigma_i

with no extra model call. dR = -dPf. The elasticities (mu_i / Pf) dPf/dmu_i and
(sigma_i / Pf) dPf/dsigma_i are comparable across variables. For a non-normal marginal the formula
is applied to the standard score of the marginal's mean and standard deviation (documented
approximation; exact for normal inputs).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from jointwear.reliability.inputs import as_marginal


@dataclass
class ReliabilityDerivatives:
    names: list[str]
    pf: float
    dpf_dmean: np.ndarray
    dpf_dstd: np.ndarray
    dpf_dmean_se: np.ndarray
    dpf_dstd_se: np.ndarray
    elasticity_mean: np.ndarray
    elasticity_std: np.ndarray

    def as_dict(self) -> dict:
        return {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.__dict__.items()}


def reliability_derivatives(x: np.ndarray, failed: np.ndarray, marginals: Sequence,
                            names: Sequence[str]) -> ReliabilityDerivatives:
    """Derivatives of Pf w.r.t. each mean and standard deviation from samples ``x`` (n, d), and the elasticities of
    Pf, (mu / Pf) dPf/dmu and (sigma / Pf) dPf/dsigma."""
    x = np.asarray(x, dtype=float)
    ind = np.asarray(failed, dtype=float).reshape(-1)
    if x.ndim != 2 or x.shape[0] != ind.shape[0] or x.shape[1] != len(marginals):
        raise ValueError("x must be (n, d) with one failure flag per row and d marginals")
    n = x.shape[0]
    mu = np.array([as_marginal(m).mean() for m in marginals])
    sd = np.array([as_marginal(m).std() for m in marginals])
    u = (x - mu) / sd
    pf = float(ind.mean())
    t_mean = ind[:, None] * u / sd
    t_std = ind[:, None] * (u * u - 1.0) / sd
    d_mean, d_std = t_mean.mean(axis=0), t_std.mean(axis=0)
    se_mean = t_mean.std(axis=0, ddof=1) / np.sqrt(n)
    se_std = t_std.std(axis=0, ddof=1) / np.sqrt(n)
    with np.errstate(divide="ignore", invalid="ignore"):
        el_mean = np.where(pf > 0, mu * d_mean / pf, 0.0)
        el_std = np.where(pf > 0, sd * d_std / pf, 0.0)
    return ReliabilityDerivatives(list(names), pf, d_mean, d_std, se_mean, se_std, el_mean, el_std)
