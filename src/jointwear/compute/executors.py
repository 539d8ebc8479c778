"""Where model calls run: one ``concurrent.futures``-style interface over three back-ends.

- ``make_executor(1)``: :class:`SerialExecutor`, in this process (debugging, tiny studies);
- ``make_executor()`` / ``make_executor(n)``: :class:`LocalExecutor`, a pool of local processes (the
  default: every usable core);
- ``make_executor(scheduler="tcp://host:8786")``: :class:`DaskExecutor`, a Dask distributed cluster.

Every executor has ``submit(fn, *args)`` and ``map(fn, *iterables)`` with the semantics of
:class:`concurrent.futures.Executor` (``map`` keeps the input order), a ``kind`` and an ``n_workers``,
and is a context manager that releases its processes (or its Dask client) on exit.

Nothing here draws random numbers, so a deterministic function gives the same results on every executor.
"""

from __future__ import annotations

import ast
import concurrent.futures as cf
import ctypes
import multiprocessing
import os
import signal
import sys
from pathlib import Path
from typing import Any, Callable

from .store import code_version

__all__ = [
    "ClusterError",
    "DaskExecutor",
    "LocalExecutor",
    "SchedulerLostError",
    "SerialExecutor",
    "WorkerVersionError",
    "available_cores",
    "make_executor",
    "scheduler_address",
    "scheduler_not_answering",
    "scheduler_url",
    "start_local_cluster",
    "unguarded_main_script",
]


def available_cores() -> int:
    """The number of CPU cores this process may run on (the affinity mask, not the machine's count)."""
    try:
        cores = max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        cores = max(1, os.cpu_count() or 1)
    return min(cores, 61) if sys.platform == "win32" else cores  # Windows' process pools take at most 61


class _ExecutorBase(cf.Executor):
    kind: str = "base"
    #: True when ``submit`` runs the call at once in the calling process.
    in_process: bool = False

    @property
    def n_workers(self) -> int:  # pragma: no cover - overridden
        return 1

    @property
    def threads_per_call(self) -> int | None:
        """Most threads one call may use (None: the cores of the process that runs the call)."""
        return None

    def __exit__(self, exc_type, exc, tb):
        # On an error or Ctrl-C, do not wait for the queued calls.
        self.shutdown(wait=exc_type is None, cancel_futures=exc_type is not None)
        return False

    def restart(self) -> None:
        """Replace broken workers (only local process pools can break)."""

    def check_alive(self) -> None:
        """Raise when the executor can run no more calls and never will again (only a Dask scheduler can be lost)."""

    def __repr__(self) -> str:
        return f"<{type(self).__name__} kind={self.kind} n_workers={self.n_workers}>"


class SerialExecutor(_ExecutorBase):
    """Runs each call at once, in this process, when it is submitted (no pool, no pickling)."""

    kind = "serial"
    in_process = True

    def __init__(self) -> None:
        self._shutdown = False

    @property
    def n_workers(self) -> int:
        return 1

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> cf.Future:
        if self._shutdown:
            raise RuntimeError("cannot schedule new calls after shutdown")
        fut: cf.Future = cf.Future()
        fut.set_running_or_notify_cancel()
        try:
            fut.set_result(fn(*args, **kwargs))
        except Exception as exc:  # KeyboardInterrupt and SystemExit propagate
            fut.set_exception(exc)
        return fut

    def map(self, fn: Callable, *iterables, timeout=None, chunksize: int = 1):
        # lazy, like the builtin: each result is computed when it is asked for
        if self._shutdown:
            raise RuntimeError("cannot schedule new calls after shutdown")
        return map(fn, *iterables)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._shutdown = True


# ----------------------------------------------------------------------------------------------------
# local processes

_PR_SET_PDEATHSIG = 1


def _exit_when_gone(main_pid: int) -> None:
    """Block until process ``main_pid`` has ended, then end this process at once."""
    import multiprocessing
    from multiprocessing.connection import wait

    parent = multiprocessing.parent_process()
    if parent is not None and parent.pid == main_pid:  # spawned by the study (Windows, macOS): its sentinel
        wait([parent.sentinel])  # (os.kill(pid, 0) on Windows sends CTRL_C_EVENT to a console group)
        os._exit(1)
    try:
        import select

        fd = os.pidfd_open(main_pid)  # Linux >= 5.3: readable when the process ends
        select.select([fd], [], [])
    except (AttributeError, OSError):  # older kernels, other systems: poll
        import time

        while True:
            try:
                os.kill(main_pid, 0)
            except ProcessLookupError:
                break
            except PermissionError:
                pass
            time.sleep(0.5)
    os._exit(1)


def _worker_init(main_pid: int) -> None:
    """Runs once in each local worker process.

    A study killed with ``kill -9`` must not leave its workers computing in the background. A worker
    forked by the study itself asks the kernel for SIGKILL when its parent dies (PR_SET_PDEATHSIG); a
    worker started by the forkserver (whose parent is the forkserver, which outlives the study) runs a
    watcher thread that ends it when the study's process ends. Once the workers are gone the
    forkserver and the resource tracker see their pipes close and exit too.
    """
    if sys.platform.startswith("linux") and os.getppid() == main_pid:
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except Exception:  # pragma: no cover - exotic libc
            pass
    else:
        import threading

        threading.Thread(
            target=_exit_when_gone, args=(main_pid,), name="jointwear-parent-watch", daemon=True
        ).start()
    if os.getppid() != main_pid and not _pid_alive(main_pid):  # the study died while we started
        os._exit(1)
    # Ctrl-C goes to the study, which cancels the batch; workers are ended by the pool's shutdown (and a SIGTERM
    # ends a worker, whatever handler the study has for its own).
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def unguarded_main_script() -> str | None:
    """The script run as ``__main__`` when no top-level ``if __name__ == "__main__":`` guards any of it, else None.

    Worker processes import the main script again before they take calls; without the guard each of them would
    run the study once more, and every call would fail with multiprocessing's bootstrapping error."""
    path = getattr(sys.modules.get("__main__"), "__file__", None)
    if not path:  # an interactive session or a notebook: nothing is imported again
        return None
    try:
        tree = ast.parse(Path(path).read_bytes())
    except (OSError, SyntaxError, ValueError):
        return None
    return None if any(_is_main_guard(node) for node in tree.body) else str(path)


def worker_pool_problem(workers: int) -> str | None:
    """Why ``workers`` local worker processes cannot run this process's model calls (they import its main script
    again: one without the ``__main__`` guard, or one that cannot be read again), else None."""
    script = unguarded_main_script()
    if script is not None:
        return (f"{script} runs model calls in {workers} worker processes, which import it again: put the "
                "study under `if __name__ == \"__main__\":` (or use workers=1 to run the calls in this process)")
    main_path = getattr(sys.modules.get("__main__"), "__file__", None)
    if main_path and not Path(main_path).is_file():  # python - < script.py: every worker would die importing '<stdin>'
        return (f"the main script ({main_path}) cannot be read again by the {workers} worker processes, which "
                "import it: save it to a file (with the study under `if __name__ == \"__main__\":`), or use workers=1 "
                "to run the calls in this process")
    return None


def _is_main_guard(node: ast.stmt) -> bool:
    """``if __name__ == "__main__":`` (either order of the comparison)."""
    if not isinstance(node, ast.If) or not isinstance(node.test, ast.Compare) or len(node.test.comparators) != 1:
        return False
    sides = [node.test.left, node.test.comparators[0]]
    names = [s.id for s in sides if isinstance(s, ast.Name)]
    texts = [s.value for s in sides if isinstance(s, ast.Constant)]
    return isinstance(node.test.ops[0], ast.Eq) and names == ["__name__"] and texts == ["__main__"]


class LocalExecutor(_ExecutorBase):
    """A pool of ``workers`` local processes (:class:`concurrent.futures.ProcessPoolExecutor`).

    ``mp_context`` defaults to ``"forkserver"``: workers start from a clean single-threaded server
    process, so a study may hold threads (progress display, a Dask client) without the risk of a
    ``fork`` deadlock. Functions sent to the workers must be picklable by reference (importable)
    unless they go through :class:`~jointwear.compute.Evaluator`, which ships the model with
    cloudpickle (so models defined in ``__main__`` or a notebook work too).
    """

    kind = "local"

    def __init__(self, workers: int | None = None, mp_context: str | None = None) -> None:
        self._workers = int(workers) if workers is not None else available_cores()
        if self._workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        problem = worker_pool_problem(self._workers)
        if problem is not None:
            raise RuntimeError(problem)
        if mp_context is None:
            methods = multiprocessing.get_all_start_methods()
            mp_context = "forkserver" if "forkserver" in methods else "spawn"
        self._mp_context = mp_context
        self._pool = self._new_pool()
        self.n_restarts = 0

    def _new_pool(self) -> cf.ProcessPoolExecutor:
        ctx = multiprocessing.get_context(self._mp_context)
        if self._mp_context == "forkserver":
            # workers fork from a server that has already imported numpy and the worker code
            ctx.set_forkserver_preload(["__main__", "numpy", "jointwear.compute.evaluator"])
        return cf.ProcessPoolExecutor(
            max_workers=self._workers,
            mp_context=ctx,
            initializer=_worker_init,
            initargs=(os.getpid(),),
        )

    @property
    def n_workers(self) -> int:
        return self._workers

    @property
    def threads_per_call(self) -> int:
        """Every core: a call alone (the sensitivity's one-at-a-time calls, the last of a batch) uses the idle ones,
        and busy workers share them; a wear history runs at most `wear.lanes` threads, the same numbers whatever it
        gets (benchmarks/results/executor_threads.json)."""
        return available_cores()

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> cf.Future:
        return self._pool.submit(fn, *args, **kwargs)

    def map(self, fn: Callable, *iterables, timeout=None, chunksize: int = 1):
        return self._pool.map(fn, *iterables, timeout=timeout, chunksize=chunksize)

    def restart(self) -> None:
        """Replace a pool broken by a worker that died (segfault, out of memory, ``os._exit``)."""
        try:
            self._pool.shutdown(wait=False, cancel_futures=True)
        except Exception:  # pragma: no cover
            pass
        self._pool = self._new_pool()
        self.n_restarts += 1

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Release the workers. With ``cancel_futures`` (the context manager does it on an error or
        Ctrl-C) the calls still running are stopped too: their results are not wanted."""
        if cancel_futures:
            self._terminate_workers()
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)

    def _terminate_workers(self) -> None:
        pool = self._pool
        if hasattr(pool, "terminate_workers"):  # Python >= 3.14
            pool.terminate_workers()
            return
        for proc in list((getattr(pool, "_processes", None) or {}).values()):
            try:
                proc.terminate()
            except Exception:  # pragma: no cover - already gone
                pass


# ----------------------------------------------------------------------------------------------------
# Dask distributed


#: seconds a Dask scheduler address has to answer Dask's handshake (distributed's own connect timeout does not bound
#: a port that accepts connections and says nothing, such as the dashboard's)
SCHEDULER_ANSWER_SECONDS = 5.0


class ClusterError(BaseException):
    """A fault of the cluster, not of a model call, that ends the study (the calls completed before are stored).

    A BaseException, as Ctrl-C is: code that records an ``Exception`` from a limit state as a failed sample (the
    reliability engine's) must not turn every later call into a failure; the study ends instead."""


class SchedulerLostError(ClusterError):
    """The Dask scheduler went away during a batch (it stopped, or the network to it failed)."""

    def __init__(self, address: str) -> None:
        super().__init__(f"the Dask scheduler at {address} was lost: it stopped, or the network to it failed")
        self.address = address


class WorkerVersionError(ClusterError):
    """A Dask worker that joined after the study connected runs another jointwear, or none: its call is refused
    before it runs, so no result of another version joins the store."""

    def __init__(self, worker: str, theirs: str | None, mine: str) -> None:
        runs = f"runs jointwear {theirs}" if theirs is not None else "cannot import jointwear"
        super().__init__(f"the Dask worker {worker}, which joined after the study connected, {runs}; this study runs "
                         f"jointwear {mine} (install jointwear {mine} on that worker, or stop it)")
        self.worker, self.theirs, self.mine = worker, theirs, mine


def scheduler_url(address: str) -> str:
    """A scheduler address with its scheme: a bare ``host:port`` is ``tcp://host:port``, as Dask reads it."""
    address = address.strip()
    return address if "://" in address else f"tcp://{address}"


def scheduler_not_answering(address: str, timeout: float = SCHEDULER_ANSWER_SECONDS) -> str | None:
    """Why ``address`` does not answer as a Dask scheduler within ``timeout`` seconds (None when it does)."""
    import asyncio
    import threading

    from distributed.comm import connect

    async def identity():
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    outcome: dict[str, Any] = {}

    def ask() -> None:
        try:
            outcome["reply"] = asyncio.run(asyncio.wait_for(identity(), timeout))
        except BaseException as exc:  # noqa: BLE001 - reported below
            outcome["error"] = exc

    # a thread of its own: the caller may be inside a running event loop (a notebook)
    thread = threading.Thread(target=ask, name="jointwear-scheduler-probe", daemon=True)
    thread.start()
    thread.join(timeout + 2.0)
    error, reply = outcome.get("error"), outcome.get("reply")
    if isinstance(error, (TimeoutError, asyncio.TimeoutError)) or not outcome:
        return (f"nothing at {address} answered as a Dask scheduler within {timeout:g} s (a stopped scheduler, or "
                "another service's port such as the dashboard's; `dask scheduler` listens on 8786 by default)")
    if error is not None and not isinstance(error, OSError):  # bytes came back that Dask's protocol cannot read
        return (f"{address} answered, but not as a Dask scheduler (its reply is not Dask's protocol: "
                f"{type(error).__name__}); is the address another service's, such as SSH or the dashboard's?")
    if error is not None:
        return f"cannot reach the Dask scheduler at {address}: {' '.join(str(error).split()) or type(error).__name__}"
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind != "Scheduler":
        return f"{address} is not a Dask scheduler (it answered as {kind or 'something else'})"
    return None


def _jointwear_version() -> str | None:
    """The jointwear of the process it runs in, with the commit of a checkout it runs from
    (``jointwear.compute.store.code_version``; None: jointwear cannot be imported there)."""
    try:
        from jointwear.compute.store import code_version
    except Exception:  # noqa: BLE001 - any failure to import means the same to the study
        return None
    return code_version()


# sent to the workers by value (as functions of __main__ are), so a worker without jointwear answers None instead of
# failing to load the function
_jointwear_version.__module__ = "__main__"


#: first argument of the error a worker raises instead of running a call under another jointwear
_OTHER_JOINTWEAR = "jointwear-version-mismatch"


def _call_if_same_jointwear(mine: str, payload: bytes) -> Any:
    """Run the call ``payload`` (cloudpickled ``(fn, args, kwargs)``) if this process imports jointwear ``mine``.

    Unpickled only after the check: a worker without jointwear could not even load ``fn``."""
    theirs = _jointwear_version()  # sent by value with this function
    if theirs != mine:
        try:
            from distributed import get_worker

            where = get_worker().address
        except Exception:  # noqa: BLE001 - the address only names the worker in the message
            where = "(address unknown)"
        raise RuntimeError(_OTHER_JOINTWEAR, where, theirs)
    import cloudpickle

    fn, args, kwargs = cloudpickle.loads(payload)
    return fn(*args, **kwargs)


_call_if_same_jointwear.__module__ = "__main__"  # sent by value, as _jointwear_version


def _relay(inner: cf.Future, mine: str) -> cf.Future:
    """A future that follows ``inner`` (cancelling it when cancelled), with a worker's refusal to run under another
    jointwear raised as :class:`WorkerVersionError`."""
    outer: cf.Future = cf.Future()

    def follow(done: cf.Future) -> None:
        try:
            if done.cancelled():
                outer.cancel()
                outer.set_running_or_notify_cancel()  # wakes concurrent.futures.wait (cancel() alone does not)
                return
            exc = done.exception()
            if isinstance(exc, RuntimeError) and exc.args[:1] == (_OTHER_JOINTWEAR,) and len(exc.args) == 3:
                exc = WorkerVersionError(exc.args[1], exc.args[2], mine)
            if exc is None:
                outer.set_result(done.result())
            else:
                outer.set_exception(exc)
        except cf.InvalidStateError:  # the caller cancelled ``outer`` meanwhile
            pass

    outer.add_done_callback(lambda f: inner.cancel() if f.cancelled() else None)
    inner.add_done_callback(follow)
    return outer


def _version_problem(workers: dict[str, Any], mine: str) -> str | None:
    """Which workers (address -> version, None or an error) do not run jointwear ``mine``, in one line."""
    bad = []
    for address, theirs in sorted(workers.items()):
        if isinstance(theirs, BaseException):
            bad.append(f"{address} did not answer ({' '.join(str(theirs).split()) or type(theirs).__name__})")
        elif theirs is None:
            bad.append(f"{address} cannot import jointwear")
        elif theirs != mine:
            bad.append(f"{address} runs jointwear {theirs}")
    if not bad:
        return None
    return (f"Dask workers must run this study's jointwear {mine}: {'; '.join(bad)} (install jointwear {mine} on "
            "the workers, from the same commit where it runs from a git checkout, and restart them; or stop those "
            "workers)")


def scheduler_argument_accepted(scheduler: Any) -> bool:
    """Whether ``scheduler`` is of a kind :class:`DaskExecutor` takes: an address string, a ``distributed.Client`` or
    a cluster object (anything with a ``scheduler_address``)."""
    return (isinstance(scheduler, str) or hasattr(scheduler, "scheduler_address")
            or type(scheduler).__module__.split(".")[0] == "distributed")


def scheduler_address(scheduler: Any) -> str | None:
    """The address of a scheduler argument (an address string, a ``distributed.Client`` or a cluster object); None
    for None or an object that does not say."""
    if scheduler is None or isinstance(scheduler, str):
        return scheduler
    address = getattr(scheduler, "scheduler_address", None)  # a cluster object
    if not isinstance(address, str):  # a Client
        address = getattr(getattr(scheduler, "scheduler", None), "address", None)
    return address if isinstance(address, str) else None


class DaskExecutor(_ExecutorBase):
    """Calls run on a Dask distributed cluster, through ``Client.get_executor()``.

    ``scheduler`` is an address (``"tcp://10.0.0.5:8786"``; a bare ``host:port`` means tcp), a
    ``distributed.Client`` (not closed on exit) or a cluster object (``LocalCluster``; a client is made and
    closed on exit). Every connected worker must run this process's jointwear version (a
    :class:`~jointwear.schema.ConfigError` otherwise); a worker that joins later checks its version before each call
    and refuses it (:class:`WorkerVersionError`, which ends the study). Tasks are submitted with ``pure=False``.
    When a worker dies mid-task, the scheduler re-runs its tasks on the remaining workers (up to
    ``distributed.scheduler.allowed-failures`` times per task, default 3); when the scheduler is lost,
    :class:`SchedulerLostError`.
    """

    kind = "dask"

    def __init__(self, scheduler: Any, timeout: float = 30.0) -> None:
        try:
            import distributed
        except ImportError as exc:
            raise ImportError(
                'a Dask scheduler was given but Dask is not installed: python -m pip install -e ".[cluster]" in '
                "jointwear's source folder"
            ) from exc
        if isinstance(scheduler, distributed.Client):
            self.client = scheduler
            self._owns_client = False
        else:
            if isinstance(scheduler, str):
                scheduler = scheduler_url(scheduler)
                problem = scheduler_not_answering(scheduler, min(timeout, SCHEDULER_ANSWER_SECONDS))
                if problem:
                    raise ConnectionError(f"{problem}; start it with `dask scheduler` and give its tcp:// address")
            try:
                self.client = distributed.Client(scheduler, timeout=timeout, set_as_default=False)
            except OSError as exc:
                raise ConnectionError(
                    f"cannot reach the Dask scheduler at {scheduler!r}: {exc}; start it with "
                    "`dask scheduler` and give its tcp:// address"
                ) from exc
            self._owns_client = True
        self._address = self.client.scheduler.address
        try:
            self._check_workers()
        except BaseException:
            if self._owns_client:
                self.client.close()
            raise
        self._executor = self.client.get_executor(pure=False)
        self._shutdown = False

    def _check_workers(self) -> None:
        """Refuse workers that run another jointwear (their results would join the store) or none (they die on the
        first call, and the study would wait for a worker forever)."""
        from jointwear.schema import ConfigError

        problem = _version_problem(self.client.run(_jointwear_version, on_error="return"), code_version())
        if problem:
            raise ConfigError(problem)

    @property
    def address(self) -> str:
        """The scheduler's address (kept: a closed client no longer has it)."""
        return self._address

    @property
    def lost(self) -> bool:
        """True once the connection to the scheduler has gone (its tasks are cancelled then), unless shut down."""
        return not self._shutdown and self.client.status != "running"

    def check_alive(self) -> None:
        """Raise :class:`SchedulerLostError` when the scheduler is gone."""
        if self.lost:
            raise SchedulerLostError(self.address)

    @property
    def n_workers(self) -> int:
        try:
            return max(1, len(self.client.scheduler_info().get("workers", {})))
        except Exception:  # pragma: no cover - scheduler gone
            return 1

    def idle_message(self) -> str | None:
        """Why no call completes, when the cluster can say: no worker connected (the study waits for one)."""
        try:
            workers = len(self.client.scheduler_info().get("workers", {}))
        except Exception:  # noqa: BLE001 - a scheduler that does not answer says nothing either
            return None
        if workers:
            return None
        return (f"no Dask worker is connected to {self.address}: the study waits for one (start `dask worker "
                f"{self.address}`; the calls made so far are in the evaluation store)")

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> cf.Future:
        """Submit ``fn(*args, **kwargs)``, run only by a worker that imports this process's jointwear (``map`` is
        concurrent.futures', through this method)."""
        import cloudpickle

        self.check_alive()
        payload = cloudpickle.dumps((fn, args, kwargs))
        mine = code_version()
        return _relay(self._executor.submit(_call_if_same_jointwear, mine, payload), mine)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        if self._shutdown:
            return
        lost = self.lost
        self._shutdown = True
        try:
            if not lost:  # a lost client's tasks are cancelled already, and it can send nothing
                self._executor.shutdown(wait=wait and not cancel_futures)
        finally:
            if self._owns_client:
                self._close_client(quiet=lost)

    def _close_client(self, quiet: bool) -> None:
        if not quiet:
            self.client.close()
            return
        import logging

        # closing a client that is still trying to reconnect logs the attempts it cuts short, tracebacks included;
        # the study has already said that the scheduler was lost
        log = logging.getLogger("distributed.client")
        level = log.level
        log.setLevel(logging.CRITICAL)
        try:
            self.client.close()
        finally:
            log.setLevel(level)


def make_executor(
    workers: int | None = None,
    scheduler: Any | None = None,
    *,
    mp_context: str | None = None,
) -> SerialExecutor | LocalExecutor | DaskExecutor:
    """The executor for model calls.

    - ``scheduler`` given (a ``tcp://host:port`` address of a running ``dask scheduler``, a
      ``distributed.Client`` or a ``LocalCluster``): calls run on that Dask cluster; ``workers`` must
      then be None (the cluster decides).
    - otherwise ``workers`` local processes; None means every usable core, 1 means in this process,
      serially, without a pool.
    """
    if scheduler is not None and scheduler != "":
        if workers is not None:
            raise ValueError(
                "give either workers (local processes) or scheduler (a Dask cluster), not both"
            )
        return DaskExecutor(scheduler)
    if workers is not None:
        if isinstance(workers, bool) or not isinstance(workers, int):
            raise TypeError(f"workers must be an integer >= 1 or None, got {workers!r}")
        if workers < 1:
            raise ValueError(f"workers must be >= 1 (or None for all cores), got {workers}")
    n = workers if workers is not None else available_cores()
    if n == 1:
        return SerialExecutor()
    return LocalExecutor(n, mp_context=mp_context)


def start_local_cluster(
    n_workers: int = 2,
    threads_per_worker: int = 1,
    processes: bool = True,
    **kwargs: Any,
):
    """Start a ``distributed.LocalCluster`` (dashboard on a free port, quiet logs) for tests and benchmarks.

    Use it as a context manager and pass it (or its ``scheduler_address``) as ``scheduler``. In a
    script, call it under ``if __name__ == "__main__":`` (worker processes re-import the main module).
    """
    import logging

    from distributed import LocalCluster

    kwargs.setdefault("dashboard_address", ":0")  # a free port: no clash with a running cluster
    kwargs.setdefault("silence_logs", logging.ERROR)
    return LocalCluster(
        n_workers=n_workers, threads_per_worker=threads_per_worker, processes=processes, **kwargs
    )
