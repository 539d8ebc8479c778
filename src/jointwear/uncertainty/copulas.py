"""Dependence between random inputs: a normal (Gaussian) copula from a correlation matrix, built by OpenTURNS.

Two readings of the matrix (``measure``):

* ``"pearson"``: the matrix is the normal copula's own correlation, i.e. the Pearson correlation of the
  normal scores Phi^-1(F_i(X_i)). For normal inputs that is the Pearson correlation of the inputs themselves;
  for other marginals the Pearson correlation of X differs slightly (no Nataf adjustment is made).
* ``"spearman"``: the matrix is the rank (Spearman) correlation of the inputs, exact for any marginals;
  OpenTURNS converts it (``NormalCopula.GetCorrelationFromSpearmanCorrelation``: r = 2 sin(pi rho_s / 6)).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["check_correlation", "normal_copula"]

MEASURES = ("pearson", "spearman")


def check_correlation(matrix: Any, field: str = "correlation") -> np.ndarray:
    """The matrix as a float array if it is a correlation matrix (square, symmetric, unit diagonal, entries
    in (-1, 1) off the diagonal, positive definite); ``ValueError`` naming ``field`` otherwise."""
    r = np.asarray(matrix, dtype=float)
    if r.ndim != 2 or r.shape[0] != r.shape[1] or r.shape[0] < 1:
        raise ValueError(f"{field} must be a square matrix; got shape {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ValueError(f"{field} has non-finite entries")
    if not np.allclose(r, r.T, rtol=0.0, atol=1e-12):
        i, j = np.unravel_index(np.argmax(np.abs(r - r.T)), r.shape)
        raise ValueError(f"{field} must be symmetric: entry [{i}][{j}] = {r[i, j]:g} but [{j}][{i}] = {r[j, i]:g}")
    if not np.allclose(np.diag(r), 1.0, rtol=0.0, atol=1e-12):
        raise ValueError(f"{field} must have ones on the diagonal; got {np.diag(r).tolist()}")
    off = r[~np.eye(r.shape[0], dtype=bool)]
    if off.size and np.max(np.abs(off)) >= 1.0:
        i, j = np.argwhere((np.abs(r) >= 1.0) & ~np.eye(r.shape[0], dtype=bool))[0]
        raise ValueError(f"{field}: off-diagonal entries must be in (-1, 1); [{i}][{j}] = {r[i, j]:g}")
    if np.linalg.eigvalsh(0.5 * (r + r.T)).min() <= 0.0:
        raise ValueError(f"{field} is not positive definite (its smallest eigenvalue is "
                         f"{np.linalg.eigvalsh(0.5 * (r + r.T)).min():.3g}): the correlations are inconsistent")
    return 0.5 * (r + r.T)


def normal_copula(matrix: Any, measure: str = "pearson", field: str = "correlation") -> Any:
    """An ``openturns.NormalCopula`` from a correlation matrix read as ``measure`` (module docstring)."""
    import openturns as ot

    if measure not in MEASURES:
        raise ValueError(f"{field}.measure must be one of {', '.join(MEASURES)}; got {measure!r}")
    r = check_correlation(matrix, field)
    d = r.shape[0]
    cm = ot.CorrelationMatrix(d)
    for i in range(d):
        for j in range(i):
            cm[i, j] = float(r[i, j])
    if measure == "spearman":
        cm = ot.NormalCopula.GetCorrelationFromSpearmanCorrelation(cm)
        if not cm.isPositiveDefinite():
            raise ValueError(f"{field}: the normal copula of this Spearman matrix is not positive definite")
    return ot.NormalCopula(cm)
