"""One model call on a worker: run it with its time-out, turn whatever happens into an outcome record (the
failure rule of :mod:`jointwear.compute.evaluator`), and ship the model to worker processes as bytes."""

from __future__ import annotations

import datetime as _dt
import functools
import os
import pickle
import signal
import socket
import threading
import time
import traceback
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

__all__ = ["FAILED", "OK", "TIMEOUT", "describe_error", "dumps_model", "now_iso", "run_call", "run_pickled"]

OK, FAILED, TIMEOUT = "ok", "failed", "timeout"


def now_iso() -> str:
    """The current UTC time, ISO 8601 with microseconds (the store's time stamps)."""
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="microseconds")



class CallTimeout(BaseException):
    """Raised inside a model call that ran past its time-out (a BaseException, so that a model's own
    ``except Exception`` does not swallow it)."""


def _call_with_alarm(model: Callable, x: np.ndarray, timeout: float):
    def _on_alarm(signum, frame):
        raise CallTimeout()

    old = signal.signal(signal.SIGALRM, _on_alarm)
    pending, interval = signal.setitimer(signal.ITIMER_REAL, timeout)
    if 0.0 < pending <= timeout:  # the caller's own alarm comes first: it is theirs to handle, as without a limit
        signal.signal(signal.SIGALRM, old)
        signal.setitimer(signal.ITIMER_REAL, pending, interval)
        return model(x)
    start = time.monotonic()
    try:
        return model(x)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)
        if pending > 0.0:  # the caller's alarm, re-armed for what is left of it
            signal.setitimer(signal.ITIMER_REAL, max(pending - (time.monotonic() - start), 1e-6), interval)


def _call_in_thread(model: Callable, x: np.ndarray, timeout: float):
    box: dict[str, Any] = {}

    def target():
        try:
            box["value"] = model(x)
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller
            box["error"] = exc

    t = threading.Thread(target=target, name="jointwear-model-call", daemon=True)
    t.start()
    t.join(timeout)
    if t.is_alive():  # cannot be stopped: it finishes in the background and its result is dropped
        raise CallTimeout()
    if "error" in box:
        raise box["error"]
    return box["value"]


def _split_result(res: Any) -> tuple[Any, str]:
    if isinstance(res, tuple) and len(res) == 2 and isinstance(res[1], str):
        return res[0], res[1]
    return res, OK


def _as_outputs(outputs: Any) -> np.ndarray | dict[str, np.ndarray]:
    if isinstance(outputs, Mapping):
        return {str(k): np.array(v, dtype=np.float64) for k, v in outputs.items()}
    return np.atleast_1d(np.array(outputs, dtype=np.float64))


def _all_finite(outputs) -> bool:
    if isinstance(outputs, dict):
        return all(np.all(np.isfinite(v)) for v in outputs.values())
    return bool(np.all(np.isfinite(outputs)))


def describe_error(exc: BaseException) -> str:
    """One line naming an exception, its message and where it was raised."""
    tb = traceback.extract_tb(exc.__traceback__)
    where = f" (at {os.path.basename(tb[-1].filename)}:{tb[-1].lineno} in {tb[-1].name})" if tb else ""
    msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}: {msg}{where}" if msg else f"{type(exc).__name__}{where}"


def run_call(model: Callable, x: np.ndarray, timeout: float | None = None) -> dict:
    """Run ``model(x)`` once and return its outcome as a plain dict (``status``, ``reason``,
    ``outputs``, ``wall_s``, ``started_at``, ``finished_at``, ``worker``). Never raises for a model
    error. The time-out uses SIGALRM when the call runs on a process's main thread (it interrupts
    Python code; compiled code is interrupted when it returns to Python), otherwise a watcher thread
    (the call is abandoned, not stopped)."""
    x = np.array(x, dtype=np.float64)  # a private copy: the model may not change the caller's row
    started = now_iso()
    t0 = time.perf_counter()
    status, reason, outputs = OK, None, None
    try:
        if timeout is None:
            res = model(x)
        elif hasattr(signal, "SIGALRM") and threading.current_thread() is threading.main_thread():
            res = _call_with_alarm(model, x, timeout)
        else:
            res = _call_in_thread(model, x, timeout)
        out, st = _split_result(res)
        if st != OK:
            status, reason = FAILED, f"model: {st}"
        else:
            outputs = _as_outputs(out)
            if not _all_finite(outputs):
                status, reason, outputs = FAILED, "model returned non-finite outputs", None
    except CallTimeout:
        status, reason, outputs = TIMEOUT, f"time-out after {timeout:g} s", None
    except (Exception, SystemExit) as exc:
        status, reason, outputs = FAILED, describe_error(exc), None
    wall = time.perf_counter() - t0
    return {
        "status": status,
        "reason": reason,
        "outputs": outputs,
        "wall_s": wall,
        "started_at": started,
        "finished_at": now_iso(),
        "worker": f"{socket.gethostname()}:{os.getpid()}",
    }


@functools.lru_cache(maxsize=8)
def _load_model(blob: bytes) -> Callable:
    return pickle.loads(blob)


def run_pickled(blob: bytes, x: np.ndarray, timeout: float | None) -> dict:
    """Worker entry point: the model travels as cloudpickle bytes (unpickled once per worker)."""
    return run_call(_load_model(blob), x, timeout)


def dumps_model(model: Callable) -> bytes:
    """The model as bytes for the workers: cloudpickle, so that closures, lambdas and ``__main__`` functions go too."""
    import cloudpickle

    return cloudpickle.dumps(model)
