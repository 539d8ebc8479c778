"""Sobol' indices of a vectorised function of independent inputs, with SALib.

Samples are drawn by SALib's Saltelli scheme on the unit hypercube and mapped to each input through its
inverse CDF, so any marginal the reliability engine accepts works (frozen ``scipy.stats``, scipy's new
distributions, OpenTURNS; :func:`jointwear.reliability.as_marginal`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from jointwear.reliability.inputs import as_marginal


@dataclass
class SobolResult:
    """First-order (S1) and total (ST) indices with their 95 % bootstrap half-widths."""

    names: list[str]
    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray
    n_evaluations: int

    def as_dict(self) -> dict:
        return {"names": list(self.names), "S1": self.S1.tolist(), "S1_conf": self.S1_conf.tolist(),
                "ST": self.ST.tolist(), "ST_conf": self.ST_conf.tolist(), "n_evaluations": self.n_evaluations}


def sobol_indices(f: Callable[[np.ndarray], np.ndarray], marginals: Sequence, names: Sequence[str],
                  n_base: int = 1024, seed: int = 0) -> SobolResult:
    """Sobol' indices of ``f(X) -> (n,)`` for independent ``marginals`` (frozen scipy.stats).

    ``n_base`` is Saltelli's base sample size (a power of two); f is called once on
    ``n_base * (d + 2)`` rows. Indices are estimated by SALib (Saltelli 2010 / Jansen 1999).
    """
    d = len(marginals)
    if len(names) != d:
        raise ValueError(f"{len(names)} names for {d} marginals")
    if n_base < 2 or n_base & (n_base - 1):
        raise ValueError(f"n_base must be a power of two >= 2 (got {n_base})")
    problem = {"num_vars": d, "names": list(names), "bounds": [[0.0, 1.0]] * d}
    unit = sobol_sample.sample(problem, n_base, calc_second_order=False, seed=seed)
    # Keep the unit-hypercube samples strictly inside (0, 1) so the inverse CDFs stay finite.
    unit = np.clip(unit, 1e-12, 1.0 - 1e-12)
    x = np.column_stack([as_marginal(m).ppf(unit[:, j]) for j, m in enumerate(marginals)])
    y = np.asarray(f(x), dtype=float).reshape(-1)
    if y.shape[0] != x.shape[0] or not np.all(np.isfinite(y)):
        raise ValueError("the function must return one finite value per row")
    res = sobol_analyze.analyze(problem, y, calc_second_order=False, seed=seed)
    return SobolResult(names=list(names), S1=np.asarray(res["S1"]), S1_conf=np.asarray(res["S1_conf"]),
                       ST=np.asarray(res["ST"]), ST_conf=np.asarray(res["ST_conf"]), n_evaluations=len(y))
