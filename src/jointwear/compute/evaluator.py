"""The evaluator: a batch of model calls through an executor, with time-outs, failure records and the
evaluation store.

The model is any function ``f(x) -> (outputs, status)`` of one input row ``x`` (a 1-D float64 array):

- ``outputs``: a 1-D array (or a scalar), or a dict of scalars/arrays;
- ``status``: ``"ok"`` for a good call; any other string declares a failure and is kept as its reason
  (``"no assembly at crank angle 1.2 rad"``). A function may also return just ``outputs`` (status ok).

The failure rule (one bad call never ends a batch):

- the model raises, declares a failure, or returns non-finite outputs -> status ``"failed"``;
- the call runs longer than ``timeout`` seconds -> status ``"timeout"``;
- the worker process running the call dies -> the call is run again, alone, on a fresh worker; when it
  has killed its worker ``max_attempts`` times (default 2) it is ``"failed"`` (reason ``"the worker
  process died ..."``); calls that merely shared the pool with it are run again, not failed;
- on Dask, the scheduler re-runs the tasks of a lost worker; a task that keeps killing workers ends as
  ``KilledWorker`` -> status ``"failed"``; a lost scheduler ends the batch with
  :class:`~jointwear.compute.executors.SchedulerLostError` (the calls completed before are stored);

A failed call is stored like a good one (with its reason and wall time) and its outputs are NaN in
:attr:`BatchResult.Y`. What a study does with failed calls is the study's rule; the evaluator only
records them. Calls already in the store (same tag, bit-identical input row) are served from it and
never run again; failed calls too, unless ``retry_failed=True``; a call that timed out in an earlier session is
run again (its time-out measured that machine's load, or a pause of the job, not the model).

The evaluator is the one cache of model calls: it keeps every outcome it has run or read in memory (so a
row asked for again is served without a store look-up and without counting again in the progress), in
front of the persistent store (so a resumed study is served what an earlier process computed).
"""

from __future__ import annotations

import math
import sys
import time
from collections import deque
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, CancelledError, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .call import (
    FAILED,
    OK,
    TIMEOUT,
    describe_error,
    dumps_model,
    now_iso,
    run_call,
    run_pickled,
)
from .executors import SerialExecutor
from .store import CallRecord, EvaluationStore, row_bytes

__all__ = ["BatchResult", "Evaluator", "run_call"]

#: seconds without a completed call after which the executor is asked whether it can run any (a Dask cluster whose
#: workers are all gone waits silently for a new one)
IDLE_CHECK_SECONDS = 60.0


# ----------------------------------------------------------------------------------------------------
# results


@dataclass
class BatchResult:
    """The outcome of :meth:`Evaluator.evaluate`, one entry per input row, in the input order."""

    X: np.ndarray
    records: list[CallRecord]
    #: True where the row was served from the store (or repeated an earlier row of the batch).
    reused: np.ndarray
    #: model calls actually made for this batch
    n_evaluated: int
    wall_s: float
    n_outputs: int | None = None
    output_names: list[str] | None = field(default=None)

    def __len__(self) -> int:
        return len(self.records)

    def __repr__(self) -> str:
        st = self.status
        return (
            f"BatchResult(n={len(self)}, ok={int((st == OK).sum())}, failed={int((st == FAILED).sum())}, "
            f"timeout={int((st == TIMEOUT).sum())}, reused={int(self.reused.sum())}, "
            f"n_evaluated={self.n_evaluated}, wall_s={self.wall_s:.3g})"
        )

    @property
    def status(self) -> np.ndarray:
        return np.array([r.status for r in self.records], dtype=object)

    @property
    def ok(self) -> np.ndarray:
        return np.array([r.status == OK for r in self.records], dtype=bool)

    @property
    def n_failed(self) -> int:
        return int((~self.ok).sum())

    @property
    def failures(self) -> list[tuple[int, str, str | None]]:
        """(row index, status, reason) of every failed row."""
        return [(i, r.status, r.reason) for i, r in enumerate(self.records) if r.status != OK]

    @property
    def outputs(self) -> list[np.ndarray | dict[str, np.ndarray] | None]:
        return [r.outputs for r in self.records]

    @property
    def Y(self) -> np.ndarray:
        """Outputs as an (n, m) float64 array (dict outputs flattened in key order); NaN rows for
        failed calls."""
        flat = []
        for r in self.records:
            o = r.outputs
            if o is None:
                flat.append(None)
            elif isinstance(o, dict):
                flat.append(np.concatenate([np.ravel(v) for v in o.values()]) if o else np.empty(0))
            else:
                flat.append(np.ravel(o))
        m = self.n_outputs
        if m is None:
            m = next((f.size for f in flat if f is not None), 1)
        Y = np.full((len(flat), m), np.nan)
        for i, f in enumerate(flat):
            if f is not None:
                if f.size != m:
                    raise ValueError(
                        f"model outputs have different sizes across calls ({f.size} at row {i}, "
                        f"expected {m})"
                    )
                Y[i] = f
        return Y


# ----------------------------------------------------------------------------------------------------
# the evaluator


class Evaluator:
    """Evaluate a model over batches of input rows through an executor, with a store.

    Parameters
    ----------
    model : ``f(x: 1-D float64 array) -> (outputs, status)``; see the module docstring.
    executor : from :func:`make_executor`; None runs in this process, serially. Not closed by the
        evaluator.
    store : an open :class:`EvaluationStore`, or None (no persistence: outcomes are reused within this
        evaluator only).
    timeout : seconds per call, or None.
    tag : name of this model inside the store (a study with several models uses several tags).
    retry_failed : run stored failed/timed-out calls again instead of reusing their outcome.
    max_attempts : how many times a call may kill its local worker process (running alone, see
        ``_run_pool``) before it is recorded as failed (on Dask the scheduler re-runs lost tasks
        itself, ``distributed.scheduler.allowed-failures``).
    max_in_flight : calls submitted ahead of completions (default 2 per worker; all at once on Dask).
    n_outputs : output length, for the NaN rows of :attr:`BatchResult.Y` when every call failed.
    progress : a :class:`~jointwear.compute.Progress`, advanced by one per completed call.
    """

    def __init__(
        self,
        model: Callable,
        executor=None,
        store: EvaluationStore | None = None,
        *,
        timeout: float | None = None,
        tag: str = "model",
        retry_failed: bool = False,
        max_attempts: int = 2,
        max_in_flight: int | None = None,
        n_outputs: int | None = None,
        progress=None,
    ) -> None:
        if not callable(model):
            raise TypeError(f"model must be callable, got {type(model).__name__}")
        if timeout is not None and not (isinstance(timeout, (int, float)) and timeout > 0):
            raise ValueError(f"timeout must be a positive number of seconds or None, got {timeout!r}")
        if max_attempts < 1:
            raise ValueError(f"max_attempts must be >= 1, got {max_attempts}")
        self.model = model
        self.executor = executor if executor is not None else SerialExecutor()
        self.store = store
        self.timeout = float(timeout) if timeout is not None else None
        self.tag = str(tag)
        self.retry_failed = retry_failed
        self.max_attempts = int(max_attempts)
        self.max_in_flight = max_in_flight
        self.n_outputs = n_outputs
        self.progress = progress
        self._blob: bytes | None = None
        #: model calls made by this evaluator / served from the store, over all batches
        self.n_model_calls = 0
        self.n_reused = 0
        self._known: dict[bytes, CallRecord] = {}  # outcomes run or read by this evaluator, by row bytes

    @property
    def n_known(self) -> int:
        """Distinct input rows whose outcome this evaluator holds (run, or read back from the store)."""
        return len(self._known)

    def adopt(self, other: Evaluator) -> None:
        """Take over the outcomes another evaluator of the same model holds (a later session of one study):
        rows it knows are served from memory and do not count again."""
        if other.tag != self.tag:
            raise ValueError(f"cannot adopt the outcomes of model {other.tag!r} for model {self.tag!r}")
        for key, rec in other._known.items():
            self._known.setdefault(key, rec)

    def _reusable(self, rec: CallRecord | None) -> bool:
        return rec is not None and (rec.status == OK or not self.retry_failed)

    # -- helpers ------------------------------------------------------------------------------------
    def _model_blob(self) -> bytes:
        if self._blob is None:
            try:
                self._blob = dumps_model(self.model)
            except Exception as exc:
                raise TypeError(
                    f"the model cannot be sent to worker processes ({describe_error(exc)}); make it a "
                    "module-level function or an object without open files/locks, or use workers=1"
                ) from exc
        return self._blob

    def _window(self) -> int:
        if self.max_in_flight is not None:
            return max(1, int(self.max_in_flight))
        if getattr(self.executor, "kind", None) == "dask":
            return 1 << 30
        return 2 * max(1, int(getattr(self.executor, "n_workers", 1)))

    def _record(self, x: np.ndarray, out: dict) -> CallRecord:
        return CallRecord(
            x=x,
            status=out["status"],
            reason=out["reason"],
            outputs=out["outputs"],
            wall_s=out["wall_s"],
            started_at=out["started_at"],
            finished_at=out["finished_at"],
            worker=out["worker"],
        )

    def _completed(self, x: np.ndarray, rec: CallRecord) -> CallRecord:
        if self.store is not None:
            self.store.put(self.tag, rec)  # committed before the call counts as done
        self.n_model_calls += 1
        if self.progress is not None:
            self.progress.advance(1)
        return rec

    # -- the batch ------------------------------------------------------------------------------------
    def __call__(self, X) -> np.ndarray:
        """``evaluate(X).Y``: outputs as an (n, m) array, NaN rows for failed calls."""
        return self.evaluate(X).Y

    def evaluate(self, X) -> BatchResult:
        """Evaluate every row of ``X`` (shape (n, d); a 1-D array is one row). Never raises for a
        failed model call; raises only for a broken setup (unpicklable model, closed store, lost Dask scheduler)."""
        t0 = time.perf_counter()
        X = np.array(X, dtype=np.float64)
        if X.ndim == 1:
            X = X[None, :]
        if X.ndim != 2:
            raise ValueError(f"X must have shape (n, d), got {X.shape}")
        n = X.shape[0]

        # unique rows, by exact bytes; rows this evaluator already holds are served from memory
        first_of: dict[bytes, int] = {}
        keys = [row_bytes(X[i]) for i in range(n)]
        owner = np.empty(n, dtype=np.int64)
        for i in range(n):
            owner[i] = first_of.setdefault(keys[i], i)
        records: dict[int, CallRecord] = {}
        for i in first_of.values():
            if self._reusable(self._known.get(keys[i])):
                records[i] = self._known[keys[i]]
        held = set(records)
        uniq = [i for i in range(n) if owner[i] == i and i not in held]

        if self.store is not None and uniq:
            for i, rec in zip(uniq, self.store.get_many(self.tag, [X[i] for i in uniq])):
                # an earlier session's time-out is run again: it measured that machine's load and pauses (a
                # suspended job's clock runs on), not the model
                if self._reusable(rec) and rec.status != TIMEOUT:
                    records[i] = rec
        todo = [i for i in uniq if i not in records]
        reused = np.array([owner[i] != i or i in records for i in range(n)], dtype=bool)
        n_cached = int(reused.sum())
        self.n_reused += n_cached
        # rows held from an earlier batch were counted then; the rest count now
        n_new = n - sum(1 for i in range(n) if owner[i] in held)
        if self.progress is not None and n_new:
            self.progress.expect(n_new)
            if n_cached - (n - n_new):
                self.progress.advance(n_cached - (n - n_new))

        if todo:
            if getattr(self.executor, "in_process", False):
                for i in todo:
                    records[i] = self._completed(
                        X[i], self._record(X[i], run_call(self.model, X[i], self.timeout))
                    )
            else:
                self._run_pool(X, todo, records)

        for i in first_of.values():
            if i not in held:
                self._known[keys[i]] = records[i]
        out = [records[owner[i]] for i in range(n)]
        names = None
        for r in out:
            if isinstance(r.outputs, dict):
                names = list(r.outputs)
                break
        return BatchResult(
            X=X,
            records=out,
            reused=reused,
            n_evaluated=len(todo),
            wall_s=time.perf_counter() - t0,
            n_outputs=self.n_outputs,
            output_names=names,
        )

    def _run_pool(self, X: np.ndarray, todo: list[int], records: dict[int, CallRecord]) -> None:
        """Run the calls ``todo`` through the executor, at most ``window`` at a time.

        When a local worker process dies, every call in flight fails with ``BrokenProcessPool`` and
        nobody knows which one killed it. Those calls become *suspects* and run again one at a time,
        alone in a fresh pool: a suspect that completes is innocent; one that kills its worker while
        running alone is the culprit, and after ``max_attempts`` such deaths it is recorded as failed.
        A crashing call therefore never fails the calls that happened to share the pool with it.
        """
        blob = self._model_blob()
        window = self._window()
        queue: deque[int] = deque(todo)
        suspects: deque[int] = deque()
        deaths: dict[int, int] = {}
        in_flight: dict[Any, tuple[int, bool]] = {}  # future -> (row, ran alone)
        check_alive = getattr(self.executor, "check_alive", lambda: None)

        def submit(i: int) -> Any:
            while True:
                try:
                    return self.executor.submit(run_pickled, blob, X[i], self.timeout)
                except BrokenProcessPool:
                    self.executor.restart()

        def submit_next() -> None:
            if suspects:
                if not in_flight:
                    i = suspects.popleft()
                    in_flight[submit(i)] = (i, True)
                return
            while queue and len(in_flight) < window:
                i = queue.popleft()
                in_flight[submit(i)] = (i, False)

        try:
            submit_next()
            told = False
            while in_flight:
                done, _ = wait(list(in_flight), timeout=IDLE_CHECK_SECONDS, return_when=FIRST_COMPLETED)
                if not done:  # a cluster left without workers waits for one: say so, once per stretch
                    check_alive()
                    message = getattr(self.executor, "idle_message", lambda: None)()
                    if message and not told:
                        print(f"compute: {message}", file=sys.stderr, flush=True)
                    told = told or bool(message)
                    continue
                told = False
                for fut in done:
                    i, alone = in_flight.pop(fut)
                    try:
                        rec = self._record(X[i], fut.result())
                    except (BrokenProcessPool, CancelledError) as exc:
                        # a lost Dask scheduler cancels every task: the batch ends (the calls done are stored)
                        check_alive()
                        # a worker process died (segfault, out of memory, os._exit) under this call
                        # or under another one in the same pool
                        if not alone:
                            suspects.append(i)
                            continue
                        deaths[i] = deaths.get(i, 0) + 1
                        if deaths[i] < self.max_attempts:
                            suspects.appendleft(i)
                            continue
                        rec = self._infra_failure(
                            X[i], f"the worker process died running this call ({deaths[i]} times): {describe_error(exc)}"
                        )
                    except Exception as exc:  # noqa: BLE001
                        # e.g. distributed's KilledWorker: the scheduler already re-ran the task
                        rec = self._infra_failure(X[i], f"worker error: {describe_error(exc)}")
                    records[i] = self._completed(X[i], rec)
                submit_next()
        except BaseException:
            if not getattr(self.executor, "lost", False):  # a lost scheduler's tasks are cancelled already
                for fut in in_flight:
                    fut.cancel()
            raise

    def _infra_failure(self, x: np.ndarray, reason: str) -> CallRecord:
        now = now_iso()
        return CallRecord(
            x=x, status=FAILED, reason=reason, outputs=None, wall_s=math.nan, started_at=now, finished_at=now, worker=None
        )
