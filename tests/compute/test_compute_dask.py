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


@pytest.mark.timeout(60)
def test_workers_with_another_jointwear_are_refused():
    """A worker running another jointwear version, or none, is refused at connection, naming it and both versions."""
    import distributed

    import jointwear
    from jointwear.schema import ConfigError

    def other_version():
        import jointwear

        jointwear.__version__ = "0.0.0-other"

    def no_jointwear():
        import sys

        sys.modules["jointwear"] = None  # `import jointwear` fails from now on

    with start_local_cluster(n_workers=2, threads_per_worker=1, processes=True) as c:
        with distributed.Client(c, set_as_default=False) as client:
            other, missing = sorted(client.scheduler_info()["workers"])
            client.run(other_version, workers=[other])
            client.run(no_jointwear, workers=[missing])
        with pytest.raises(ConfigError) as err:
            DaskExecutor(c)
    message = str(err.value)
    assert "\n" not in message
    assert jointwear.__version__ in message
    assert f"{other} runs jointwear 0.0.0-other" in message
    assert f"{missing} cannot import jointwear" in message


@pytest.mark.timeout(60)
def test_a_worker_loaded_from_another_commit_of_the_same_version_is_refused():
    """The check compared jointwear.__version__ alone: a worker started from an editable checkout before a `git pull`
    passed it and ran the old code. It compares code_version(), the commit the worker loaded."""
    import distributed

    from jointwear.compute.store import code_version
    from jointwear.schema import ConfigError

    def older_commit():
        import jointwear
        import jointwear.compute.store as store

        store.code_version = lambda with_git=True: f"{jointwear.__version__}+g0000000"

    with start_local_cluster(n_workers=1, threads_per_worker=1, processes=True) as c:
        with distributed.Client(c, set_as_default=False) as client:
            (worker,) = client.scheduler_info()["workers"]
            client.run(older_commit, workers=[worker])
        with pytest.raises(ConfigError) as err:
            DaskExecutor(c)
    assert f"{worker} runs jointwear {jointwear_version()}+g0000000" in str(err.value)
    assert code_version() in str(err.value)


def jointwear_version() -> str:
    import jointwear

    return jointwear.__version__


@pytest.mark.timeout(90)
@pytest.mark.parametrize("late", ["other version", "no jointwear"])
def test_a_worker_that_joins_later_with_another_jointwear_ends_the_study(tmp_path, late):
    """A worker that joins after the connection check refuses the study's calls before running them: the batch ends
    with WorkerVersionError naming it, and the store keeps only the calls of the checked worker."""
    import distributed

    import jointwear
    from jointwear.compute.executors import WorkerVersionError

    def other_version():
        import jointwear

        jointwear.__version__ = "0.0.0-other"

    def no_jointwear():
        import sys

        sys.modules["jointwear"] = None

    X = np.arange(12.0)[:, None]
    with start_local_cluster(n_workers=1, threads_per_worker=1, processes=True) as c, \
            EvaluationStore.open(tmp_path, "dask-late") as store, DaskExecutor(c) as ex:
        ev = Evaluator(slept_model, ex, store)
        assert ev.evaluate(X[:2]).ok.all()
        with distributed.Client(c, set_as_default=False) as client:
            (checked,) = client.scheduler_info()["workers"]
            c.scale(2)
            client.wait_for_workers(2)
            (joined,) = set(client.scheduler_info()["workers"]) - {checked}
            client.run(other_version if late == "other version" else no_jointwear, workers=[joined])
            client.retire_workers([checked])  # every later call goes to the late worker
        with pytest.raises(WorkerVersionError) as err:
            ev.evaluate(X[2:])
        assert store.stats().n_calls == 2
    message = str(err.value)
    assert joined in message and jointwear.__version__ in message and "\n" not in message
    assert ("runs jointwear 0.0.0-other" if late == "other version" else "cannot import jointwear") in message


def slept_model(x):
    time.sleep(0.2)
    return x.copy(), "ok"


@pytest.mark.timeout(60)
def test_a_lost_scheduler_ends_the_batch_and_keeps_the_calls_done(tmp_path):
    """Stopping the scheduler mid-batch raises SchedulerLostError at once; the calls completed before are stored."""
    import dask

    from jointwear.compute.executors import SchedulerLostError

    X = np.arange(40.0)[:, None]
    # a short connect time-out: the cluster's own close does not wait half a minute for its stopped scheduler
    with dask.config.set({"distributed.comm.timeouts.connect": "2s"}), \
            start_local_cluster(n_workers=1, threads_per_worker=1, processes=True) as c, \
            EvaluationStore.open(tmp_path, "dask-lost") as store:
        ex = DaskExecutor(c.scheduler_address, timeout=5)
        ev = Evaluator(slept_model, ex, store)
        ev.evaluate(X[:2])  # the worker is up and has run calls
        threading.Timer(0.5, lambda: c.sync(c.scheduler.close)).start()
        t0 = time.monotonic()
        with pytest.raises(SchedulerLostError) as err, ex:  # the executor's shutdown does not raise either
            ev.evaluate(X[2:])
        assert time.monotonic() - t0 < 4  # not after the client's 5 s of reconnection attempts
        assert c.scheduler_address in str(err.value)
        assert 2 <= store.stats().n_calls < len(X)
        assert ex.address == c.scheduler_address and ex.idle_message() is None  # no AttributeError once closed


def test_the_cli_says_the_scheduler_was_lost_and_how_to_resume(monkeypatch, capsys, tmp_path):
    from jointwear.cli import main_entry
    from jointwear.compute.executors import SchedulerLostError
    from jointwear.study import Study

    def lost(self):
        raise SchedulerLostError("tcp://10.0.0.5:8786")

    monkeypatch.setattr(Study, "reliability", lost)
    code = main_entry(["reliability", "flores_slider_crank", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert err == ("error: the Dask scheduler at tcp://10.0.0.5:8786 was lost: it stopped, or the network to it "
                   "failed (the model calls made so far are kept in the output folder's evaluation store: run the "
                   "same command again with --resume to continue it)")


def test_the_cli_names_a_late_worker_of_another_version(monkeypatch, capsys, tmp_path):
    from jointwear.cli import main_entry
    from jointwear.compute.executors import WorkerVersionError
    from jointwear.study import Study

    def refused(self):
        raise WorkerVersionError("tcp://10.0.0.7:40123", None, "1.2.3")

    monkeypatch.setattr(Study, "reliability", refused)
    code = main_entry(["reliability", "flores_slider_crank", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert err.startswith("error: the Dask worker tcp://10.0.0.7:40123, which joined after the study connected, cannot "
                          "import jointwear; this study runs jointwear 1.2.3 (install jointwear 1.2.3 on that worker, "
                          "or stop it) (the model calls made so far are kept")


class _Silent(threading.Thread):
    """A TCP server that accepts connections and never says anything."""

    def __init__(self):
        import socket

        super().__init__(daemon=True)
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.conns = []

    def run(self):
        while True:
            try:
                self.conns.append(self.sock.accept()[0])
            except OSError:
                return


class _Banner(_Silent):
    """A TCP server that speaks first, as SSH does, and keeps the connection open."""

    def run(self):
        while True:
            try:
                conn = self.sock.accept()[0]
            except OSError:
                return
            conn.sendall(b"SSH-2.0-OpenSSH_8.9p1 Ubuntu-3ubuntu0.6\r\n")
            self.conns.append(conn)


@pytest.mark.timeout(60)
def test_a_service_that_speaks_another_protocol_is_named_as_not_a_scheduler():
    """An SSH banner read as a Dask frame length gave 'cannot reach the Dask scheduler ...: Unable to allocate 2.82
    EiB for an array' (a user's audit): the message says the address answered, not as a Dask scheduler."""
    from jointwear.compute.executors import scheduler_not_answering

    banner = _Banner()
    banner.start()
    try:
        address = f"tcp://127.0.0.1:{banner.port}"
        problem = scheduler_not_answering(address, timeout=5.0)
        assert problem is not None and problem.startswith(f"{address} answered, but not as a Dask scheduler"), problem
        assert "allocate" not in problem
    finally:
        banner.sock.close()


@pytest.mark.timeout(60)
def test_a_port_that_is_not_a_scheduler_fails_in_seconds(monkeypatch):
    """A port that accepts TCP but is no Dask scheduler (a silent server, an HTTP server like the dashboard) is
    refused within the probe's time-out, naming the address, by the executor and by the study's check."""
    import http.server

    from jointwear.compute import executors
    from jointwear.study import checks

    monkeypatch.setattr(executors, "SCHEDULER_ANSWER_SECONDS", 1.0, raising=False)
    monkeypatch.setattr(checks, "SCHEDULER_CONNECT_SECONDS", 1.0)
    silent = _Silent()
    silent.start()
    web = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
    threading.Thread(target=web.serve_forever, daemon=True).start()
    try:
        for port in (silent.port, web.server_address[1]):
            address = f"tcp://127.0.0.1:{port}"
            t0 = time.monotonic()
            with pytest.raises(ConnectionError, match=f"nothing at {address} answered as a Dask scheduler"):
                DaskExecutor(address)
            assert checks.scheduler_unreachable(f"127.0.0.1:{port}").startswith(f"nothing at {address} answered")
            assert time.monotonic() - t0 < 8
    finally:
        web.shutdown()
        silent.sock.close()


@pytest.mark.timeout(60)
def test_a_bare_host_port_is_a_tcp_address(cluster):
    from jointwear.schema import ConfigError
    from jointwear.study import Study
    from jointwear.study.checks import scheduler_problem, scheduler_unreachable

    bare = cluster.scheduler_address.removeprefix("tcp://")
    assert scheduler_problem(bare) is None and scheduler_unreachable(bare) is None
    with make_executor(scheduler=bare) as ex:
        assert ex.address == cluster.scheduler_address
    assert "is not a Dask scheduler address" in scheduler_problem("http://127.0.0.1:8786")
    # a bad address given as the argument is the argument's fault, not the config's
    with pytest.raises(ConfigError) as err:
        Study("flores_slider_crank", out="unused", scheduler="http://127.0.0.1:8786").check()
    assert str(err.value).startswith("scheduler: 'http://127.0.0.1:8786' is not a Dask scheduler address")
