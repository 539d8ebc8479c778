"""The evaluator and the executors: the failure rule, time-outs, dying workers, reuse of stored calls,
determinism across executors, order, progress."""

from __future__ import annotations

import io
import os
import threading
import time

import numpy as np
import pytest

from jointwear.compute import (
    EvaluationStore,
    Evaluator,
    LocalExecutor,
    Progress,
    SerialExecutor,
    config_hash,
    make_executor,
    run_call,
)


def smooth_model(x):
    """Deterministic floating-point work (a small linear solve, transcendental functions)."""
    A = np.eye(3) * 4.0 + np.outer(np.sin(x[:3]), np.cos(x[:3]))
    y = np.linalg.solve(A, np.exp(-x[:3] ** 2))
    return np.array([y.sum(), np.prod(np.cos(x)), np.hypot(*x[:2])]), "ok"


def faulty_model(x):
    """x[0] selects the behaviour: the four ways a call can fail, or success."""
    kind = int(x[0])
    if kind == 1:
        raise ValueError("the mechanism cannot assemble")
    if kind == 2:
        return np.array([0.0, 0.0]), "integrator step size underflow"
    if kind == 3:
        return np.array([np.nan, 1.0]), "ok"
    if kind == 4:
        time.sleep(3.0)  # longer than the 0.4 s time-out below
    if kind == 5:
        raise SystemExit(3)  # a model that calls sys.exit must not end the batch either
    return np.array([x[1], 2 * x[1]]), "ok"


def crashing_model(x):
    """Kills its worker process for x[0] == 7 (like a segfault in compiled code)."""
    if x[0] == 7.0:
        os._exit(9)
    time.sleep(0.05)
    return np.array([x[0] ** 2]), "ok"


FAULTY_X = np.array([[0, 1.5], [1, 0], [2, 0], [3, 0], [4, 0], [5, 0], [0, 2.5]], dtype=float)


def _check_faulty(res):
    assert list(res.status) == ["ok", "failed", "failed", "failed", "timeout", "failed", "ok"]
    reasons = {i: reason for i, _, reason in res.failures}
    assert reasons[1].startswith("ValueError: the mechanism cannot assemble")
    assert reasons[2] == "model: integrator step size underflow"
    assert reasons[3] == "model returned non-finite outputs"
    assert reasons[4] == "time-out after 0.4 s"
    assert reasons[5].startswith("SystemExit")
    Y = res.Y
    assert Y.shape == (7, 2)
    assert np.isnan(Y[1:6]).all()
    np.testing.assert_array_equal(Y[[0, 6]], [[1.5, 3.0], [2.5, 5.0]])
    # the timed-out call was stopped near its time-out, not after its 3 s sleep
    # (tolerance: 0.4 s limit + 0.5 s for signal delivery and a loaded 2-core machine)
    assert res.records[4].wall_s < 0.9


@pytest.mark.parametrize("workers", [1, 2])
def test_failure_rule_never_raises(workers):
    with make_executor(workers) as ex:
        res = Evaluator(faulty_model, ex, timeout=0.4).evaluate(FAULTY_X)
    _check_faulty(res)


def test_timeout_off_the_main_thread():
    # Dask runs tasks in worker threads, where SIGALRM cannot be used: a watcher thread applies the limit
    box = {}
    t = threading.Thread(target=lambda: box.update(out=run_call(faulty_model, np.array([4.0, 0.0]), 0.3)))
    t.start()
    t.join()
    assert box["out"]["status"] == "timeout"
    assert box["out"]["wall_s"] < 1.0  # 0.3 s limit + slack for a loaded machine; the call itself is 3 s


def test_dying_worker_fails_only_its_call():
    X = np.array([[float(i)] for i in range(12)])  # row 7 kills its worker process
    with make_executor(2) as ex:
        res = Evaluator(crashing_model, ex, max_attempts=2).evaluate(X)
        assert ex.n_restarts >= 2  # the pool was replaced after each death
    assert list(res.status).count("failed") == 1
    assert res.status[7] == "failed" and "worker process died" in res.records[7].reason
    ok = np.arange(12) != 7
    np.testing.assert_array_equal(res.Y[ok, 0], np.arange(12.0)[ok] ** 2)


def test_same_results_serial_and_local_processes():
    rng = np.random.default_rng(7)
    X = rng.normal(size=(24, 4))
    with make_executor(1) as ex:
        serial = Evaluator(smooth_model, ex).evaluate(X).Y
    with make_executor(2) as ex:
        assert isinstance(ex, LocalExecutor)
        local = Evaluator(smooth_model, ex).evaluate(X).Y
        mapped = list(ex.map(abs, [-3, 1, -2]))  # concurrent.futures map keeps the order
    np.testing.assert_array_equal(serial, local)  # bit for bit: no tolerance
    assert mapped == [3, 1, 2]


def test_store_serves_completed_calls_and_duplicates(tmp_path):
    calls = []

    def counted(x):
        calls.append(x.copy())
        if x[0] < 0:
            raise RuntimeError("boom")
        return {"g": x.sum(), "profile": np.array([x[0], x[0] / 3.0])}, "ok"

    X = np.array([[1.0, 2.0], [-1.0, 0.0], [1.0, 2.0], [0.1, 0.2]])
    with EvaluationStore.open(tmp_path, config_hash({"case": 1})) as store:
        ev = Evaluator(counted, store=store)
        first = ev.evaluate(X)
        assert first.n_evaluated == 3 and len(calls) == 3  # the repeated row ran once
        assert list(first.reused) == [False, False, True, False]
        again = ev.evaluate(X[::-1])
        assert again.n_evaluated == 0 and len(calls) == 3 and again.reused.all()
        np.testing.assert_array_equal(again.Y, first.Y[::-1])
        assert first.output_names == ["g", "profile"]
        assert store.stats().n_calls == 3 and store.stats().n_failed == 1

    with EvaluationStore.open(tmp_path, config_hash({"case": 1}), resume=True) as store:
        res = Evaluator(counted, store=store).evaluate(X)
        assert res.n_evaluated == 0  # failed calls are reused too, by default
        np.testing.assert_array_equal(res.Y, first.Y)  # exact float64 round trip through SQLite
        assert res.outputs[3]["profile"][1] == 0.1 / 3.0
        res = Evaluator(counted, store=store, retry_failed=True).evaluate(X)
        assert res.n_evaluated == 1 and len(calls) == 4
        stats = store.stats()
        # the retried failure is a second row for the same input: the repeat counter sees it
        assert stats.n_calls == 4 and stats.n_repeated == 1


def test_outcomes_held_in_memory_without_a_store():
    # the evaluator is the one cache of model calls: a row asked for again is neither run nor counted again
    calls = []

    def counted(x):
        calls.append(x.copy())
        return (np.array([np.nan]), "ok") if x[0] < 0 else (np.array([x.sum()]), "ok")

    X = np.array([[1.0, 2.0], [-1.0, 0.0], [0.5, 0.5]])
    with Progress(description="calls") as progress:
        ev = Evaluator(counted, progress=progress)
        first = ev.evaluate(X)
        again = ev.evaluate(np.vstack([X[::-1], [[3.0, 3.0]]]))
    assert len(calls) == 4 and again.n_evaluated == 1 and list(again.reused) == [True, True, True, False]
    np.testing.assert_array_equal(again.Y[:3], first.Y[::-1])
    assert ev.n_known == 4 and (progress.completed, progress.total) == (4, 4)
    later = Evaluator(counted)
    later.adopt(ev)  # a later session of the same study
    assert later.evaluate(X).n_evaluated == 0 and later.n_known == 4 and len(calls) == 4
    retry = Evaluator(counted, retry_failed=True)
    retry.adopt(ev)
    assert retry.evaluate(X).n_evaluated == 1 and len(calls) == 5  # only the failed row runs again
    with pytest.raises(ValueError, match="adopt"):
        Evaluator(counted, tag="other").adopt(ev)


def test_store_lookup_is_bit_exact(tmp_path):
    x = np.array([0.1, 0.2])
    with EvaluationStore.open(tmp_path / "s.sqlite", "h") as store:
        ev = Evaluator(lambda v: (v * 2, "ok"), store=store)
        ev.evaluate(x)
        res = ev.evaluate(np.vstack([x, np.nextafter(x, 1.0)]))
        assert list(res.reused) == [True, False]


def test_progress_counts_calls_and_is_silent_off_a_terminal(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("JOINTWEAR_PROGRESS", raising=False)  # the shell's setting would decide instead of the terminal
    X = np.arange(10.0).reshape(5, 2)
    with Progress(description="calls") as progress:  # stderr is captured: not a terminal
        Evaluator(smooth_model, progress=progress).evaluate(np.vstack([X, X[:2]]))
        progress.update(pf=1.234e-3, cov="0.05")
    assert not progress.enabled
    assert (progress.completed, progress.total) == (7, 7)
    assert capsys.readouterr().err == ""

    from rich.console import Console

    buf = io.StringIO()
    console = Console(file=buf, force_terminal=True, width=120)
    with Progress(total=5, console=console) as progress:
        progress.update(pf=1.234e-3, cov=0.05)
        Evaluator(smooth_model, progress=progress).evaluate(X)
    assert progress.enabled and progress.total == 5
    text = buf.getvalue()
    assert "5/5" in text and "pf=0.001234" in text and "cov=0.05" in text


def test_progress_shows_in_a_notebook_whose_stderr_is_no_terminal(monkeypatch):
    """In Jupyter stderr is no terminal, and the progress line was never shown there."""
    import rich.console

    monkeypatch.delenv("JOINTWEAR_PROGRESS", raising=False)
    assert not Progress(total=3).enabled  # pytest's captured stderr, no notebook
    monkeypatch.setattr(rich.console, "_is_jupyter", lambda: True)  # what rich sees in a Jupyter kernel
    assert Progress(total=3).enabled
    monkeypatch.setenv("JOINTWEAR_PROGRESS", "0")
    assert not Progress(total=3).enabled


def test_progress_off_a_terminal_writes_a_plain_line_at_its_interval(monkeypatch, capsys):
    """Under nohup, in CI or into a file the reliability stage printed nothing until it ended, while the tutorial
    promised a progress line: a plain line now, at most every PLAIN_INTERVAL seconds, and one at the end."""
    monkeypatch.delenv("JOINTWEAR_PROGRESS", raising=False)
    X = np.arange(10.0).reshape(5, 2)
    with Progress(description="reliability", plain_interval=0.0) as progress:  # captured stderr: not a terminal
        progress.update(pf=1.234e-3)
        Evaluator(smooth_model, progress=progress).evaluate(X)
    assert progress.plain and not progress.enabled
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].startswith("reliability 0  pf=0.001234  elapsed 0:00:0")
    assert lines[-1].startswith("reliability 5/5  pf=0.001234  elapsed 0:00:0") and len(lines) >= 3
    with Progress(description="reliability") as progress:  # work shorter than the interval: nothing
        Evaluator(smooth_model, progress=progress).evaluate(X)
    assert Progress.PLAIN_INTERVAL >= 10 and capsys.readouterr().err == ""
    for silent in ({"enabled": False}, {}):
        if not silent:
            monkeypatch.setenv("JOINTWEAR_PROGRESS", "0")
        with Progress(plain_interval=0.0, **silent) as progress:
            Evaluator(smooth_model, progress=progress).evaluate(X + 100.0)
        assert not progress.plain and capsys.readouterr().err == ""


def test_make_executor_arguments():
    assert isinstance(make_executor(1), SerialExecutor)
    with pytest.raises(ValueError, match="workers must be >= 1"):
        make_executor(0)
    with pytest.raises(ValueError, match="not both"):
        make_executor(2, scheduler="tcp://127.0.0.1:1")
    with pytest.raises(TypeError):
        make_executor(2.5)
    with pytest.raises(ValueError, match="timeout"):
        Evaluator(smooth_model, timeout=-1)


def test_config_hash():
    assert config_hash({"a": 1, "b": [1.0, 2.0]}) == config_hash({"b": [1.0, 2.0], "a": 1})
    assert config_hash({"a": 0.1}) != config_hash({"a": np.nextafter(0.1, 1.0)})
    assert config_hash({"a": np.array([1.0, 2.0])}) != config_hash({"a": np.array([1.0, 2.5])})


def test_compute_imports_no_other_stage_and_no_dask():
    import json
    import subprocess
    import sys
    from pathlib import Path

    import jointwear

    code = (
        "import sys, json, numpy as np; import jointwear.compute as c;"
        "c.Evaluator(lambda x: (x, 'ok'), c.make_executor(1)).evaluate(np.ones((2, 2)));"
        "print(json.dumps(sorted(m for m in sys.modules if m.startswith(('jointwear.', 'distributed')))))"
    )
    env = dict(__import__("os").environ)
    env["PYTHONPATH"] = str(Path(jointwear.__file__).resolve().parents[1])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    modules = json.loads(out.stdout)
    assert all(m.startswith("jointwear.compute") for m in modules), modules  # a service: no stage imported
    assert not any(m.startswith("distributed") for m in modules)  # Dask is imported only when asked for


class _StalledCluster:
    """An executor whose calls complete only after ``delay`` seconds (a cluster whose workers are all gone, until a
    new one connects), and that says why while it waits."""

    kind = "dask"
    n_workers = 1

    def __init__(self, delay):
        self.delay = delay
        self.asked = 0

    def submit(self, fn, *args):
        import threading
        from concurrent.futures import Future

        fut = Future()
        threading.Timer(self.delay, lambda: fut.set_result(fn(*args))).start()
        return fut

    def idle_message(self):
        self.asked += 1
        return "no Dask worker is connected to tcp://x:8786: the study waits for one"


def test_a_cluster_without_workers_is_told_once_while_the_study_waits(monkeypatch, capsys):
    """A Dask study whose workers were all killed waited with no line at all until a new worker connected."""
    import jointwear.compute.evaluator as ev

    monkeypatch.setattr(ev, "IDLE_CHECK_SECONDS", 0.1)
    stalled = _StalledCluster(delay=0.8)
    res = ev.Evaluator(smooth_model, stalled).evaluate(np.zeros((1, 2)))
    assert res.Y.shape[0] == 1 and stalled.asked >= 3  # asked at every idle check
    err = capsys.readouterr().err
    assert err.count("compute: no Dask worker is connected to tcp://x:8786") == 1, err


def test_a_callers_own_alarm_survives_the_call_time_out():
    """The per-call limit is a SIGALRM timer in the main thread: it replaced a script's own alarm and then cancelled
    it, so a study bounded by signal.alarm ran to its end."""
    import signal
    import time

    class Mine(BaseException):  # as KeyboardInterrupt: not a model error, so not turned into a failed call
        pass

    def mine(signum, frame):
        raise Mine()

    old = signal.signal(signal.SIGALRM, mine)
    try:
        # the caller's alarm falls after the call: it is still pending afterwards, less the call's time
        signal.setitimer(signal.ITIMER_REAL, 5.0)
        assert run_call(lambda x: x, np.array([1.0]), timeout=30.0)["status"] == "ok"
        left = signal.getitimer(signal.ITIMER_REAL)[0]
        assert 4.0 < left <= 5.0 and signal.getsignal(signal.SIGALRM) is mine
        # the caller's alarm falls within the call: theirs fires, not the call's time-out
        signal.setitimer(signal.ITIMER_REAL, 0.2)
        with pytest.raises(Mine):
            run_call(lambda x: (time.sleep(2.0), x)[1], np.array([1.0]), timeout=30.0)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)


def test_a_call_that_timed_out_in_an_earlier_session_runs_again(tmp_path):
    """A job suspended (Ctrl-Z, a laptop asleep) past the time-out stored a 'timeout' that every resume reused: the
    sensitivity's shift read as a failed mechanism, R 0.908 -> 0, and the ranking changed."""
    delay = {"s": 0.6}
    calls = []

    def paused(x):
        calls.append(1)
        time.sleep(delay["s"])
        return np.array([x.sum()]), "ok"

    X = np.array([[1.0, 2.0]])
    with EvaluationStore.open(tmp_path, config_hash({"case": "pause"})) as store:
        ev = Evaluator(paused, store=store, timeout=0.3)
        assert list(ev.evaluate(X).status) == ["timeout"]
        assert list(ev.evaluate(X).status) == ["timeout"] and len(calls) == 1  # this session's outcome is kept
    delay["s"] = 0.0
    with EvaluationStore.open(tmp_path, config_hash({"case": "pause"}), resume=True) as store:
        res = Evaluator(paused, store=store, timeout=0.3).evaluate(X)
        assert list(res.status) == ["ok"] and res.n_evaluated == 1 and res.Y[0, 0] == 3.0
    with EvaluationStore.open(tmp_path, config_hash({"case": "pause"}), resume=True) as store:
        assert Evaluator(paused, store=store, timeout=0.3).evaluate(X).n_evaluated == 0  # the latest outcome, ok


def test_an_installed_package_inside_a_users_repository_records_no_commit_of_it(tmp_path, monkeypatch):
    """A wheel installed into a venv inside the user's own git project recorded that project's commit as
    jointwear's version ('0.1.0+g<their commit>'): git describe ran in the installed package's folder."""
    import importlib.util
    import shutil
    import subprocess

    import jointwear
    from jointwear.compute import store

    repo = tmp_path / "user_project"
    installed = repo / "venv" / "lib" / "python3" / "site-packages" / "jointwear" / "compute"
    installed.mkdir(parents=True)
    shutil.copy(store.__file__, installed / "store.py")
    git = ["git", "-c", "user.name=u", "-c", "user.email=u@example.org"]
    subprocess.run([*git, "init", "-q", str(repo)], check=True)
    subprocess.run([*git, "-C", str(repo), "commit", "-q", "--allow-empty", "-m", "theirs"], check=True)
    spec = importlib.util.spec_from_file_location("installed_store", installed / "store.py")
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(__import__("sys").modules, spec.name, module)  # its dataclasses look their module up
    spec.loader.exec_module(module)
    assert module.code_version() == jointwear.__version__
