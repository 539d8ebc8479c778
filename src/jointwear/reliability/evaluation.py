"""How the reliability methods call the limit state: one :class:`Evaluation` context (executor, callbacks,
NaN policy) that every method takes, and the :class:`LimitStateCaller` it builds.

NaN rule (every method): a model call that returns NaN (or raises, when it runs through an executor or
row by row) is a *failed call*. It is counted in ``n_failed_calls``, its reason is kept in
``failure_reasons`` (index into the design), it is **counted as a failure (g < 0)** - conservative - and it
is excluded from any Kriging training set. It is never counted as safe. With ``nan_policy="raise"`` the
first NaN raises ``ValueError`` instead. If *every* point of the first batch fails, the limit state is
considered broken and :class:`AllCallsFailedError` (a ``ValueError``) is raised with the first reason.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from .checks import check_positive_int

__all__ = ["AllCallsFailedError", "Evaluation", "LimitStateCaller"]

NAN_POLICIES = ("failure", "raise")


class AllCallsFailedError(ValueError):
    """Every point of a method's first batch failed (NaN or an error): there is nothing to learn from, so the
    method stops; a caller that knows its model can say why (the message gives the first reason it saw)."""


class ExecutorLike(Protocol):
    def map(self, fn: Callable, *iterables: Any) -> Any: ...


def _call_rows(g: Callable, x: np.ndarray) -> tuple[np.ndarray | None, str | None]:
    """Run g on a block of rows in a worker; never raises (the reason is returned instead)."""
    try:
        return np.asarray(g(x)), None  # its dtype is checked where it is shaped
    except Exception as exc:  # a failing model call is data, not a crash
        return None, f"{type(exc).__name__}: {exc}"


class LimitStateCaller:
    """Calls the vectorised limit state g, keeps every evaluated point, handles failures (the NaN rule).

    Not to be confused with :class:`jointwear.compute.Evaluator`, which runs a one-row model through worker
    processes with an evaluation store; a study hands the reliability methods ``g`` built on one of those.

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
    on_evaluate:
        Optional callback ``on_evaluate(X, G, reasons)`` after every batch (for logging/persisting).
    nan_policy:
        ``"failure"`` (default; NaN counts as failure, see module docstring) or ``"raise"``.
    keep:
        Keep every evaluated point (``design_x``, ``design_g``); crude Monte Carlo turns it off.
    """

    def __init__(
        self,
        g: Callable[[np.ndarray], np.ndarray],
        dim: int,
        *,
        n_outputs: int | None | str = None,
        executor: ExecutorLike | None = None,
        rows_per_task: int = 1,
        on_evaluate: Callable | None = None,
        nan_policy: str = "failure",
        keep: bool = True,
    ):
        if not callable(g):
            raise ValueError(f"g must be a callable g(X) -> array; got {type(g).__name__}")
        if nan_policy not in NAN_POLICIES:
            raise ValueError(f"nan_policy must be 'failure' or 'raise'; got {nan_policy!r}")
        if executor is not None and not callable(getattr(executor, "map", None)):
            raise ValueError("executor must have a concurrent.futures-style map(fn, *iterables) method, or be None")
        self.g = g
        self.dim = dim
        self.n_outputs = n_outputs
        self.executor = executor
        self.rows_per_task = check_positive_int("rows_per_task", rows_per_task)
        self.on_evaluate = on_evaluate
        self.nan_policy = nan_policy
        self.keep = keep
        self._x: list[np.ndarray] = []
        self._g: list[np.ndarray] = []
        self.n_calls = 0  # points evaluated (the design)
        self.n_failed_calls = 0
        self.failure_reasons: dict[int, str] = {}
        self.wall_seconds = 0.0

    # -- shape handling
    def _shape_output(self, G: np.ndarray, n: int) -> np.ndarray:
        if np.asarray(G).dtype == bool:  # an indicator has no margin to learn: a Kriging of 0/1 invents failures
            raise ValueError("g returned booleans (a failure indicator); return the limit-state value itself, "
                             "failure where g < 0 (e.g. 3 - x.sum(axis=1) rather than x.sum(axis=1) > 3)")
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
        for s, val, _ in blocks:  # successful blocks first: they fix the output width in "auto" mode
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
        G, reasons = self._run(X) if n else (self._shape_output(np.empty((0,)), 0), {})
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


@dataclass(frozen=True)
class Evaluation:
    """How a reliability method calls the limit state; every method takes one (``evaluation=``).

    Calls are not cached here: to reuse or persist them (a resumable run), make ``g`` a
    :class:`jointwear.compute.Evaluator` with an evaluation store, the one cache of model calls (its
    ``__call__(X)`` is a vectorised limit state).

    Parameters
    ----------
    executor:
        None (call g on the whole batch in this process) or any object with a ``concurrent.futures``-style
        ``map`` (``ProcessPoolExecutor``, ``dask.distributed.Client.get_executor()``...): the batch is then
        split into blocks of ``rows_per_task`` rows, one task each.
    rows_per_task:
        Rows per executor task.
    on_evaluate:
        Optional callback ``on_evaluate(X, G, reasons)`` after every batch (for logging or persisting).
    progress:
        Optional callback after every iteration of the iterative methods (an :class:`IterationRecord` for
        AK-MCS and AK-IS, a dict for crude Monte Carlo and subset simulation).
    nan_policy:
        ``"failure"`` (a failed call counts as failure, the module's NaN rule) or ``"raise"``; None takes the
        method's default (``"failure"``; ``"raise"`` for FORM and SORM, whose gradients a NaN makes
        meaningless).
    caller:
        An object with ``evaluate(X) -> G`` that replaces the :class:`LimitStateCaller` (``executor``,
        ``rows_per_task``, ``on_evaluate`` and ``nan_policy`` are then its business); e.g. to share one design
        and one call count between methods.
    """

    executor: ExecutorLike | None = None
    rows_per_task: int = 1
    on_evaluate: Callable | None = None
    progress: Callable | None = None
    nan_policy: str | None = None
    caller: Any = None

    def __post_init__(self) -> None:
        if self.nan_policy is not None and self.nan_policy not in NAN_POLICIES:
            raise ValueError(f"nan_policy must be 'failure', 'raise' or None; got {self.nan_policy!r}")
        if self.executor is not None and not callable(getattr(self.executor, "map", None)):
            raise ValueError("executor must have a concurrent.futures-style map(fn, *iterables) method, or be None")
        if self.caller is not None and not callable(getattr(self.caller, "evaluate", None)):
            raise ValueError("caller must have an evaluate(X) -> G method")
        check_positive_int("rows_per_task", self.rows_per_task)

    def caller_for(self, g: Callable[[np.ndarray], np.ndarray], dim: int, *, nan_policy: str = "failure",
                   n_outputs: int | None | str = None, keep: bool = True):
        """The object that evaluates ``g`` for a method: ``caller`` when given, else a new
        :class:`LimitStateCaller`; ``nan_policy`` is the method's default, used when this context has none."""
        if self.caller is not None:
            return self.caller
        return LimitStateCaller(g, dim, n_outputs=n_outputs, executor=self.executor,
                                rows_per_task=self.rows_per_task, on_evaluate=self.on_evaluate,
                                nan_policy=self.nan_policy or nan_policy, keep=keep)


def evaluation_or_default(evaluation: Evaluation | None) -> Evaluation:
    """``evaluation``, or the default context (g called directly, no callbacks)."""
    if evaluation is None:
        return Evaluation()
    if not isinstance(evaluation, Evaluation):
        raise ValueError(f"evaluation must be a jointwear.reliability.Evaluation or None; got "
                         f"{type(evaluation).__name__}")
    return evaluation
