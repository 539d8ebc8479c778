"""A real Dask distributed cluster: same results as serial, a worker killed mid-batch, time-outs."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

pytest.importorskip("distributed")

from jointwear.compute import (  # noqa: E402
    DaskExecutor,
    EvaluationStore,
    Evaluator,
    make_executor,
    row_key,
    start_local_cluster,
)


def det_model(x):
    """Deterministic floating-point work."""
    A = np.eye(3) * 4.0 + np.outer(np.sin(x), np.cos(x))
    return np.linalg.solve(A, np.exp(-(x**2))), "ok"


def logged_model(x, log):
    """Sleeps 0.25 s; logs its start and end (with the worker's pid) to an append-only file."""
    key = row_key(x)
    with open(log, "a") as fh:
        fh.write(f"start {os.getpid()} {key}\n")
    time.sleep(0.25)
    y = det_model(x)[0]
    with open(log, "a") as fh:
        fh.write(f"end {os.getpid()} {key}\n")
    return y, "ok"


class Logged:
    """A picklable model object that carries its log path."""

    def __init__(self, log):
        self.log = str(log)

    def __call__(self, x):
        return logged_model(x, self.log)


def slow_model(x):
    if x[0] > 0:
        time.sleep(2.0)
    return x.copy(), "ok"


@pytest.fixture(scope="module")
def cluster():
    with start_local_cluster(n_workers=2, threads_per_worker=1, processes=True) as c:
        yield c


@pytest.mark.timeout(120)
def test_same_results_serial_local_and_dask(cluster):
    X = np.random.default_rng(3).normal(size=(16, 3))
    with make_executor(1) as ex:
        serial = Evaluator(det_model, ex).evaluate(X).Y
    with make_executor(2) as ex:
        local = Evaluator(det_model, ex).evaluate(X).Y
    with make_executor(scheduler=cluster.scheduler_address) as ex:
        assert isinstance(ex, DaskExecutor) and ex.n_workers == 2
        dask = Evaluator(det_model, ex).evaluate(X).Y
        assert list(ex.map(abs, [-3, 1, -2])) == [3, 1, 2]  # order kept
    # bit for bit, no tolerance: no randomness in the workers, the same arithmetic everywhere
    np.testing.assert_array_equal(serial, local)
    np.testing.assert_array_equal(serial, dask)


@pytest.mark.timeout(120)
def test_timeout_on_dask_worker_thread(cluster):
    with make_executor(scheduler=cluster) as ex:
        res = Evaluator(slow_model, ex, timeout=0.3).evaluate(np.array([[0.0], [1.0]]))
    assert list(res.status) == ["ok", "timeout"]
    assert res.records[1].wall_s < 1.5  # 0.3 s limit + slack on a loaded 2-core machine; the call is 2 s


@pytest.mark.timeout(180)
def test_worker_killed_mid_batch(tmp_path):
    X = np.random.default_rng(11).normal(size=(16, 3))
    expected = np.array([det_model(x)[0] for x in X])
    log = tmp_path / "calls.log"
    model = Logged(log)
    killed = {}

    def lines():
        return [ln.split() for ln in log.read_text().splitlines()] if log.exists() else []

    def killer():
        # once 3 calls have finished, SIGKILL a worker process that is in the middle of a call
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            ls = lines()
            if sum(1 for ln in ls if ln[0] == "end") >= 3:
                ended = {(pid, key) for kind, pid, key in ls if kind == "end"}
                # the latest started call has the most of its 0.25 s left: the kill lands inside it
                running = [(pid, key) for kind, pid, key in ls if kind == "start" and (pid, key) not in ended]
                if running:
                    pid, key = running[-1]
                    os.kill(int(pid), signal.SIGKILL)
                    killed.update(pid=pid, key=key)
                    return
            time.sleep(0.01)

    with start_local_cluster(n_workers=2, threads_per_worker=1, processes=True) as cluster:
        with EvaluationStore.open(tmp_path, "dask-kill") as store, make_executor(scheduler=cluster) as ex:
            t = threading.Thread(target=killer)
            t.start()
            res = Evaluator(model, ex, store).evaluate(X)
            t.join()
            stats = store.stats()

    assert killed, "no worker was killed"
    assert list(res.status) == ["ok"] * len(X)
    np.testing.assert_array_equal(res.Y, expected)  # the same results as serial, bit for bit
    assert stats.n_calls == len(X) and stats.n_repeated == 0 and stats.n_failed == 0
    # the call that was running on the killed worker was run again on another worker process (the killed one may
    # have logged its end just before the signal landed, and died before it reported the result)
    reruns = [pid for kind, pid, key in lines() if kind == "end" and key == killed["key"]]
    assert any(pid != killed["pid"] for pid in reruns)


@pytest.mark.timeout(120)
def test_a_cluster_without_workers_says_so():
    """What the study prints while a cluster has no worker (the evaluator asks after a minute without a call)."""
    with start_local_cluster(n_workers=0, processes=False) as c, DaskExecutor(c) as ex:
        assert ex.idle_message() == (f"no Dask worker is connected to {ex.address}: the study waits for one (start "
                                     f"`dask worker {ex.address}`; the calls made so far are in the evaluation store)")
    with start_local_cluster(n_workers=1, threads_per_worker=1, processes=False) as c, DaskExecutor(c) as ex:
        assert ex.idle_message() is None
