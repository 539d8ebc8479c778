"""Shared pieces of the reliability engine: option validation, the model
evaluator (executor, cache, callbacks, failed calls) and the result dataclasses.

NaN rule (every method): a model call that returns NaN (or raises, when it runs through an executor or
row by row) is a *failed call*. It is counted in ``n_failed_calls``, its reason is kept in
``failure_reasons`` (index into the design), it is **counted as a failure (g < 0)** - conservative - and it
is excluded from any Kriging training set. It is never counted as safe. With ``nan_policy="raise"`` the
first NaN raises ``ValueError`` instead. If *every* point of the first batch fails, the limit state is
considered broken and ``ValueError`` is raised with the first reason.
"""

from __future__ import annotations

import time
from collections.abc import Callable, MutableMapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from scipy.special import ndtri

from .inputs import IsoTransform, check_copula, check_marginals

__all__ = [
    "IsoTransform",
    "Evaluator",
    "IterationRecord",
    "ReliabilityResult",
    "MultiReliabilityResult",
    "check_marginals",
    "check_copula",
]


# ----------------------------------------------------------------------------- validation
def check_positive_int(name: str, value: Any, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def check_positive(name: str, value: Any) -> float:
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite number > 0; got {value!r}")
    return v


# ----------------------------------------------------------------------------- evaluation
class ExecutorLike(Protocol):
    def map(self, fn: Callable, *iterables: Any) -> Any: ...


def _call_rows(g: Callable, x: np.ndarray) -> tuple[np.ndarray | None, str | None]:
    """Run g on a block of rows in a worker; never raises (the reason is returned instead)."""
    try:
        return np.asarray(g(x), dtype=float), None
    except Exception as exc:  # a failing model call is data, not a crash (DESIGN.md)
        return None, f"{type(exc).__name__}: {exc}"


class Evaluator:
    """Calls the limit state, keeps every evaluated point, handles failures.

    Parameters
    ----------
    g:
        Vectorised limit state ``g(X) -> G``, X of shape (n, d); G of shape (n,) or (n, m).
    n_outputs:
        None for a scalar limit state (G of shape (n,) or (n, 1)); m for ``akmcs_multi`` (G of shape (n, m)).
        ``"auto"`` fixes m from the first call.
    executor:
        None (call g directly on the whole batch) or any object with a ``concurrent.futures.Executor``-style
        ``map`` (``ProcessPoolExecutor``, ``dask.distributed.Client.get_executor()``...). With an executor the
        batch is split into blocks of ``rows_per_task`` rows, one task each.
    cache:
        Optional mutable mapping from an input row (``tuple`` of floats, physical space) to its g value(s).
        Rows found there are not recomputed; new rows are stored. A dict makes repeated runs free; a
        persistent mapping makes a study resumable.
    on_evaluate:
        Optional callback ``on_evaluate(X, G, reasons)`` after every batch (for logging/persisting).
    nan_policy:
        ``"failure"`` (default; NaN counts as failure, see module docstring) or ``"raise"``.
    """

    def __init__(
        self,
        g: Callable[[np.ndarray], np.ndarray],
        dim: int,
        *,
        n_outputs: int | None | str = None,
        executor: ExecutorLike | None = None,
        rows_per_task: int = 1,
        cache: MutableMapping | None = None,
        on_evaluate: Callable | None = None,
        nan_policy: str = "failure",
        keep: bool = True,
    ):
        if not callable(g):
            raise ValueError(f"g must be a callable g(X) -> array; got {type(g).__name__}")
        if nan_policy not in ("failure", "raise"):
            raise ValueError(f"nan_policy must be 'failure' or 'raise'; got {nan_policy!r}")
        if executor is not None and not callable(getattr(executor, "map", None)):
            raise ValueError("executor must have a concurrent.futures-style map(fn, *iterables) method, or be None")
        self.g = g
        self.dim = dim
        self.n_outputs = n_outputs
        self.executor = executor
        self.rows_per_task = check_positive_int("rows_per_task", rows_per_task)
        self.cache = cache
        self.on_evaluate = on_evaluate
        self.nan_policy = nan_policy
        self.keep = keep
        self._x: list[np.ndarray] = []
        self._g: list[np.ndarray] = []
        self.n_calls = 0  # points evaluated (cache hits included: they are part of the design)
        self.n_model_calls = 0  # points actually sent to the model
        self.n_failed_calls = 0
        self.failure_reasons: dict[int, str] = {}
        self.wall_seconds = 0.0

    # -- shape handling
    def _shape_output(self, G: np.ndarray, n: int) -> np.ndarray:
        G = np.asarray(G, dtype=float)
        if self.n_outputs is None:
            if G.shape == (n, 1):
                G = G[:, 0]
            if G.shape != (n,):
                raise ValueError(
                    f"g returned an array of shape {G.shape} for X of shape ({n}, {self.dim}); expected shape ({n},)"
                    " - one value per row (failure where g < 0)"
                )
            return G
        if G.ndim == 1 and G.shape == (n,):
            G = G[:, None]
        if self.n_outputs == "auto":
            if G.ndim != 2 or G.shape[0] != n:
                raise ValueError(
                    f"g returned an array of shape {G.shape} for X of shape ({n}, {self.dim}); expected (n, m)"
                )
            self.n_outputs = G.shape[1]
        if G.shape != (n, self.n_outputs):
            raise ValueError(
                f"g returned an array of shape {G.shape} for X of shape ({n}, {self.dim}); "
                f"expected ({n}, {self.n_outputs})"
            )
        return G

    def _run(self, X: np.ndarray) -> tuple[np.ndarray, dict[int, str]]:
        n = X.shape[0]
        reasons: dict[int, str] = {}
        blocks: list[tuple[int, np.ndarray | None, str | None]] = []
        if self.executor is None:
            try:
                G = self.g(X)
            except Exception:
                # isolate the failing rows: retry row by row
                for i in range(n):
                    val, why = _call_rows(self.g, X[i : i + 1])
                    blocks.append((i, val, why))
            else:
                return self._shape_output(G, n), reasons
        else:
            starts = list(range(0, n, self.rows_per_task))
            chunks = [X[s : s + self.rows_per_task] for s in starts]
            outs = list(self.executor.map(_call_rows, [self.g] * len(chunks), chunks))
            for s, (val, why) in zip(starts, outs):
                blocks.append((s, val, why))
        step = self.rows_per_task if self.executor is not None else 1
        shaped: dict[int, np.ndarray] = {}
        for s, val, why in blocks:  # successful blocks first: they fix the output width in "auto" mode
            if val is not None:
                shaped[s] = self._shape_output(val, min(step, n - s))
        width = self.n_outputs
        if width == "auto":
            raise ValueError(f"every model call of the first batch failed: {blocks[0][2]}")
        parts = []
        for s, val, why in blocks:
            k = min(step, n - s)
            if val is None:
                parts.append(np.full((k,) if width is None else (k, width), np.nan))
                for j in range(k):
                    reasons[s + j] = why
            else:
                parts.append(shaped[s])
        return self._shape_output(np.concatenate(parts, axis=0), n), reasons

    def evaluate(self, X: np.ndarray) -> np.ndarray:
        """Evaluate g at the rows of X (physical space); returns G with NaN for failed calls."""
        t0 = time.perf_counter()
        X = np.atleast_2d(np.asarray(X, dtype=float))
        n = X.shape[0]
        if X.shape[1] != self.dim:
            raise ValueError(f"points have {X.shape[1]} columns but there are {self.dim} marginals")
        keys = [tuple(map(float, row)) for row in X] if self.cache is not None else None
        todo = list(range(n))
        cached: dict[int, np.ndarray] = {}
        if self.cache is not None:
            todo = []
            for i, k in enumerate(keys):
                if k in self.cache:
                    cached[i] = np.asarray(self.cache[k], dtype=float)
                else:
                    todo.append(i)
        reasons: dict[int, str] = {}
        if todo:
            Gt, r = self._run(X[todo])
            self.n_model_calls += len(todo)
            for j, why in r.items():
                reasons[todo[j]] = why
        width = self.n_outputs
        rows: list[np.ndarray | None] = [None] * n
        for j, i in enumerate(todo):
            rows[i] = Gt[j]
        for i, v in cached.items():
            rows[i] = np.asarray(v, dtype=float).reshape(() if width is None else (-1,))
        G = self._shape_output(np.stack(rows, axis=0) if n else np.empty((0,)), n)
        if self.cache is not None:
            for j, i in enumerate(todo):
                self.cache[keys[i]] = G[i].tolist() if G.ndim == 2 else float(G[i])
        bad = ~np.isfinite(G) if G.ndim == 1 else ~np.all(np.isfinite(G), axis=1)
        for i in np.flatnonzero(bad):
            reasons.setdefault(int(i), "g returned a non-finite value")
        if bad.any() and self.nan_policy == "raise":
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"g returned NaN/inf at x = {X[i].tolist()} ({reasons[i]}); nan_policy='raise'")
        base = self.n_calls
        self.n_calls += n
        self.n_failed_calls += int(bad.sum())
        for i, why in reasons.items():
            self.failure_reasons[base + i] = why
        if self.keep:
            self._x.append(X.copy())
            self._g.append(G.copy())
        if self.on_evaluate is not None:
            self.on_evaluate(X, G, {base + i: w for i, w in reasons.items()})
        self.wall_seconds += time.perf_counter() - t0
        return G

    @property
    def design_x(self) -> np.ndarray:
        if not self._x:
            return np.empty((0, self.dim))
        return np.concatenate(self._x, axis=0)

    @property
    def design_g(self) -> np.ndarray:
        if not self._g:
            return np.empty((0,))
        return np.concatenate(self._g, axis=0)


def make_evaluator(g, dim, *, evaluator=None, executor=None, cache=None, on_evaluate=None, nan_policy="failure",
                   n_outputs=None, keep=True, rows_per_task=1) -> Evaluator:
    if evaluator is not None:
        if not callable(getattr(evaluator, "evaluate", None)):
            raise ValueError("evaluator must have an evaluate(X) -> G method")
        return evaluator
    return Evaluator(g, dim, n_outputs=n_outputs, executor=executor, cache=cache, on_evaluate=on_evaluate,
                     nan_policy=nan_policy, keep=keep, rows_per_task=rows_per_task)


# ----------------------------------------------------------------------------- results
def pf_to_beta(pf: float | np.ndarray) -> float | np.ndarray:
    """Generalised reliability index beta = -Phi^-1(pf) (+inf for pf = 0)."""
    with np.errstate(divide="ignore"):
        b = -ndtri(np.asarray(pf, dtype=float))
    return float(b) if np.ndim(b) == 0 else b


def mc_cov(pf: float | np.ndarray, n: int) -> float | np.ndarray:
    """Coefficient of variation of a crude Monte Carlo estimate: sqrt((1 - pf) / ((n - 1) pf))."""
    pf = np.asarray(pf, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(pf > 0, np.sqrt((1.0 - pf) / (max(n - 1, 1) * pf)), np.inf)
    return float(c) if c.ndim == 0 else c


@dataclass
class IterationRecord:
    """One AK-MCS iteration (arrays of one value per column in ``akmcs_multi``)."""

    iteration: int
    n_calls: int
    n_mc: int
    pf: Any
    cov: Any
    min_u: Any
    error: Any  # estimated relative error of pf from the surrogate's sign uncertainty (ESC)
    wall_seconds: float


@dataclass
class ReliabilityResult:
    """Result of every reliability method (fields not used by a method are None/NaN).

    ``pf``: failure probability P[g(X) < 0]; ``cov``: its coefficient of variation (sampling methods; NaN for
    FORM/SORM); ``beta``: generalised reliability index -Phi^-1(pf); ``n_calls``: points evaluated (the length
    of ``design_x``); ``n_failed_calls``: calls that returned NaN/raised (counted as failures, see the NaN rule).
    """

    method: str
    pf: float
    cov: float
    beta: float
    n_calls: int
    converged: bool
    design_x: np.ndarray | None = None
    design_g: np.ndarray | None = None
    design_u: np.ndarray | None = None
    n_failed_calls: int = 0
    failure_reasons: dict[int, str] = field(default_factory=dict)
    history: list[IterationRecord] = field(default_factory=list)
    surrogate: Any = None
    n_mc: int = 0
    error_estimate: float = float("nan")
    design_point_u: np.ndarray | None = None
    design_point_x: np.ndarray | None = None
    alpha: np.ndarray | None = None
    curvatures: np.ndarray | None = None
    details: dict[str, Any] = field(default_factory=dict)
    message: str = ""
    wall_seconds: float = 0.0

    def __repr__(self) -> str:  # short: the design can be large
        return (
            f"ReliabilityResult(method={self.method!r}, pf={self.pf:.4g}, cov={self.cov:.3g}, beta={self.beta:.4g}, "
            f"n_calls={self.n_calls}, converged={self.converged}, n_failed_calls={self.n_failed_calls})"
        )


@dataclass
class MultiReliabilityResult:
    """Result of :func:`akmcs_multi`: one pf/cov/beta per column (limit-state level) from one shared design."""

    pf: np.ndarray
    cov: np.ndarray
    beta: np.ndarray
    n_calls: int
    converged: bool
    column_converged: np.ndarray
    below_floor: np.ndarray  # columns with pf < pf_floor: U criterion met, COV criterion waived
    design_x: np.ndarray
    design_g: np.ndarray
    design_u: np.ndarray
    n_failed_calls: int
    failure_reasons: dict[int, str]
    history: list[IterationRecord]
    surrogates: list
    min_u: np.ndarray
    error_estimate: np.ndarray
    n_mc: int
    message: str = ""
    wall_seconds: float = 0.0
    method: str = "akmcs_multi"

    def __repr__(self) -> str:
        return (
            f"MultiReliabilityResult(pf={np.array2string(self.pf, precision=4)}, n_calls={self.n_calls}, "
            f"converged={self.converged}, n_failed_calls={self.n_failed_calls})"
        )
