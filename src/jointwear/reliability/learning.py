"""The active-learning pieces that AK-MCS and AK-IS share: Echard's learning function U, the ESC error
estimate of Pf (Wang & Shafieezadeh 2019), the choice of the next batch of points and when to re-optimise
the Kriging hyperparameters."""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.cluster.vq import kmeans2
from scipy.special import ndtr

from .results import Z95

__all__ = [
    "esc_absolute_error",
    "esc_error",
    "esc_errors",
    "needs_optimisation",
    "quantile_errors",
    "select_batch",
    "u_function",
]

def esc_error(u: np.ndarray, fail: np.ndarray, known: np.ndarray | None = None, z: float = Z95) -> float:
    """Estimated maximum relative error of Pf from the surrogate's sign uncertainty (ESC criterion).

    ``u``: U values of the candidates; ``fail``: predicted failure flags; ``known``: candidates whose sign
    is known exactly (evaluated). Returns +inf when no candidate is predicted to fail.
    """
    return esc_errors(u, fail, known, z)[0]


def esc_errors(u: np.ndarray, fail: np.ndarray, known: np.ndarray | None = None,
               z: float = Z95) -> tuple[float, float]:
    """The ESC estimates of Pf = mean(fail), (relative, absolute). Relative: max(n_fs / (n_f - n_fs),
    n_sf / (n_f + n_sf)) (Wang & Shafieezadeh 2019), +inf when the predicted failures n_f do not exceed the bound
    n_fs on those that are safe. Absolute: relative x n_f / n, and where the relative one is unbounded (a level
    with no or a handful of predicted failures) the bound on the misclassified fraction, max(n_fs, n_sf) / n,
    which stays finite: the true Pf lies within [n_f - n_fs, n_f + n_sf] / n."""
    n_f, n_fs, n_sf = esc_counts(u, fail, known, z)
    n = max(int(np.size(fail)), 1)
    if n_f - n_fs > 0:
        rel = max(n_fs / (n_f - n_fs), n_sf / (n_f + n_sf))
        return rel, rel * n_f / n
    return math.inf, max(n_fs, n_sf) / n


def esc_absolute_error(mu: np.ndarray, sd: np.ndarray, z: float = Z95) -> float:
    """Estimated maximum absolute error of Pf = P[mu <= 0] (and so of R) over a population from the surrogate's
    mean ``mu`` and standard deviation ``sd``: :func:`esc_errors`' absolute estimate, the form of the R(N) curve's
    error estimate."""
    fail = mu <= 0.0
    return esc_errors(u_function(mu, sd), fail, None, z)[1]


def esc_counts(u: np.ndarray, fail: np.ndarray, known: np.ndarray | None, z: float) -> tuple[float, float, float]:
    """(predicted failures, 95 % bound on those that are safe, 95 % bound on predicted-safe that fail): the
    Poisson-binomial counts of the ESC criterion (Wang & Shafieezadeh 2019)."""
    relevant = u < 8.0  # Phi(-8) = 6e-16: candidates beyond contribute nothing
    if known is not None:
        relevant &= ~known
    p = ndtr(-u[relevant])
    f = fail[relevant]
    n_f = float(np.count_nonzero(fail))
    pf_, ps_ = p[f], p[~f]
    n_fs = float(pf_.sum() + z * math.sqrt(float((pf_ * (1 - pf_)).sum())))
    n_sf = float(ps_.sum() + z * math.sqrt(float((ps_ * (1 - ps_)).sum())))
    return n_f, n_fs, n_sf


def quantile_errors(levels: np.ndarray, pf: np.ndarray, err_abs: np.ndarray,
                    pf_targets) -> list[tuple[int, int, float]]:
    """The error of the level where Pf reaches each of ``pf_targets`` (a quantile of the response, read by linear
    interpolation between the two levels that bracket it): the levels' absolute Pf errors ``err_abs`` interpolated
    there, divided by the curve's slope dPf / dlevel between them. Returns (lower column, upper column, error) per
    bracketed target, in the levels' units (for levels ln N: the relative error of the life); a target outside the
    levels' Pf range is left out, and a flat bracket gives an infinite error."""
    order = np.argsort(levels)
    lv, p, e = levels[order], pf[order], err_abs[order]
    out = []
    for t in pf_targets:
        above = np.flatnonzero(p >= t)
        if above.size == 0 or above[0] == 0:
            continue
        i = int(above[0])
        dp, dl = p[i] - p[i - 1], lv[i] - lv[i - 1]
        if not (dp > 0 and dl > 0):
            out.append((int(order[i - 1]), int(order[i]), math.inf))
            continue
        w = (t - p[i - 1]) / dp
        out.append((int(order[i - 1]), int(order[i]), float(((1 - w) * e[i - 1] + w * e[i]) / (dp / dl))))
    return out


def needs_optimisation(forced: bool, n_at_opt: int, n_ok: int, growth: float) -> bool:
    """Re-optimise the Kriging hyperparameters (rather than re-condition with the previous ones) when asked to, on
    the first fit, while the design is small (<= 30 points), or once it has grown by the fraction ``growth``."""
    return bool(forced or n_at_opt == 0 or n_ok <= 30 or n_ok >= (1.0 + growth) * n_at_opt)


def u_function(mu: np.ndarray, sd: np.ndarray) -> np.ndarray:
    """Echard's learning function U = |mu| / sigma; infinite where sigma = 0 (the sign is certain)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.abs(mu) / sd
    u[~np.isfinite(u)] = np.inf
    return u


def select_batch(score: np.ndarray, u_pop: np.ndarray, k: int, threshold: float, rng: np.random.Generator,
                  exclude: np.ndarray) -> np.ndarray:
    """Indices of k candidates to evaluate: lowest score; for k > 1 spread by k-means."""
    score = np.where(exclude, np.inf, score)
    if k == 1:
        return np.array([int(np.argmin(score))])
    pool = np.flatnonzero(score < threshold)
    cap = max(50 * k, 2000)
    if pool.size > cap:  # the most uncertain candidates are enough to find k regions
        pool = pool[np.argpartition(score[pool], cap)[:cap]]
    if pool.size <= k:
        order = np.argsort(score)
        return order[: k][np.isfinite(score[order[:k]])]
    seed = int(rng.integers(2**31 - 1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # empty-cluster warnings: handled below
        _, labels = kmeans2(u_pop[pool], k, minit="++", seed=seed)
    chosen = []
    for c in range(k):
        members = pool[labels == c]
        if members.size:
            chosen.append(int(members[np.argmin(score[members])]))
    if len(chosen) < k:  # empty clusters: fill with the next lowest scores
        rest = pool[np.argsort(score[pool])]
        for i in rest:
            if len(chosen) == k:
                break
            if i not in chosen:
                chosen.append(int(i))
    return np.array(chosen)
