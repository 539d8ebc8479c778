"""kill -9 a real reliability study at several points, resume it, and get the uninterrupted result.

Runs the CLI as a subprocess on a reduced version of the default preset (coarse wear blocks, a small
Monte Carlo population and budget), its figures made but not rendered (tests/study/unrendered_cli.py): these tests
read results and text.
"""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path

import pytest

from jointwear.compute import EvaluationStore
from jointwear.config import load_config, updated
from jointwear.study.reliability import store_digest

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

QUICK = """
[wear]
block_cycles = 80000
record_cycles = 1

[reliability]
n_mc = 20000
n_initial = 8
max_calls = 14
cycles_start = 320000
cycles_stop = 480000
cycles_step = 40000
histogram_cycles = [360000, 400000, 440000]
"""


def _without_tables(text: str, names: set[str]) -> str:
    """The TOML text without the top-level tables ``names`` (so QUICK can replace them)."""
    out, skip = [], False
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("[") and not stripped.startswith("[["):
            skip = stripped.split("]")[0].strip("[ ") in names
        elif stripped.startswith("[["):
            skip = False
        if not skip:
            out.append(line)
    return "\n".join(out) + "\n"


@pytest.fixture(scope="module")
def quick_config(tmp_path_factory) -> Path:
    text = (resources.files("jointwear.presets") / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")
    path = tmp_path_factory.mktemp("cfg") / "quick.toml"
    path.write_text(_without_tables(text, {"wear", "reliability"}) + QUICK, encoding="utf-8")
    return path


CLI = [sys.executable, str(Path(__file__).with_name("unrendered_cli.py"))]  # `python -m jointwear`, unrendered


def _cmd(config: Path, out: Path, *extra: str) -> list[str]:
    return [*CLI, "reliability", str(config), "--out", str(out), "--workers", "2", *extra]


def _env() -> dict:
    return dict(os.environ, JOINTWEAR_PROGRESS="0")


def _stored_calls(out: Path) -> int:
    db = out / "evaluations.sqlite"
    if not db.exists():
        return 0
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=1) as con:
            return int(con.execute("select count(*) from calls").fetchone()[0])
    except sqlite3.Error:
        return 0


def _run_and_kill(cmd: list[str], out: Path, after_calls: int, limit_s: float = 300) -> bool:
    """Start the study, SIGKILL its whole process group once `after_calls` calls are stored."""
    proc = subprocess.Popen(cmd, env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)
    t0 = time.monotonic()
    while proc.poll() is None and time.monotonic() - t0 < limit_s:
        if _stored_calls(out) >= after_calls:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            return True
        time.sleep(0.05)
    proc.wait()
    return False


@pytest.fixture(scope="module")
def reference_dir(quick_config, tmp_path_factory) -> Path:
    """The uninterrupted study (2 local workers): the reference of every interrupted run below."""
    reference = tmp_path_factory.mktemp("reference")
    done = subprocess.run(_cmd(quick_config, reference), env=_env(), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return reference


@pytest.fixture(scope="module")
def expected(reference_dir) -> dict:
    return json.loads((reference_dir / "reliability.json").read_text())


def test_validate_reuses_the_study_and_adds_only_its_samples(quick_config, reference_dir, expected, tmp_path):
    import shutil

    from jointwear.report.html import build_report

    out = tmp_path / "validate"
    shutil.copytree(reference_dir, out)
    assert "true-model samples" not in build_report(out).read_text(encoding="utf-8")
    cmd = [*CLI, "validate", str(quick_config), "--samples", "4", "--out", str(out), "--workers", "2"]
    done = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    val = json.loads((out / "validation.json").read_text())
    for key in ("cycles", "reliability_mc", "ci_low", "ci_high", "reliability_surrogate", "surrogate_error",
                "n_samples", "model_calls", "wall_seconds", "cross_validation"):
        assert key in val
    assert val["n_samples"] == 4 and val["model_calls"] == 4
    assert val["reliability_surrogate"] == expected["curve"]["reliability"]  # read back, not re-learned
    # the learnt surrogate, replayed from the store, is read on the validation's samples too, and the line says so
    assert len(val["paired_reliability_surrogate"]) == len(val["cycles"])
    assert "on the same samples the curve's difference from the true model lies inside its error estimate at " in (
        done.stdout + done.stderr)
    # the replay keeps the study's own wall time in reliability.json (the report's card read the replay's 1.6 s)
    assert json.loads((out / "reliability.json").read_text())["wall_seconds"] == expected["wall_seconds"]
    assert (out / "validation.csv").is_file() and (out / "cross_validation.csv").is_file()
    assert "true-model samples" in (out / "report.html").read_text(encoding="utf-8")  # the report there is rebuilt


def test_killed_and_resumed_study_equals_uninterrupted(quick_config, expected, tmp_path):

    out = tmp_path / "interrupted"
    killed = [_run_and_kill(_cmd(quick_config, out), out, after_calls=3)]
    killed.append(_run_and_kill(_cmd(quick_config, out, "--resume"), out, after_calls=9))
    assert any(killed), "the study finished before it could be killed"
    final = subprocess.run(_cmd(quick_config, out, "--resume"), env=_env(), capture_output=True, text=True,
                           timeout=600)
    assert final.returncode == 0, final.stderr[-2000:]
    got = json.loads((out / "reliability.json").read_text())

    assert got["curve"]["reliability"] == expected["curve"]["reliability"]  # bit-identical: same seed, same calls
    assert got["model_calls"] == expected["model_calls"]
    assert got["life_at_target"] == expected["life_at_target"]
    digest = store_digest(load_config(quick_config))  # as the CLI computes it
    with EvaluationStore.open(out, digest, resume=True) as store:
        stats = store.stats()
    assert stats.n_repeated == 0
    assert stats.n_calls == expected["model_calls"]


def test_cli_study_resumed_from_python(quick_config, expected, tmp_path):
    """A study started with `jointwear reliability --out D` and continued with
    `jointwear.Study(..., out=D, resume=True).reliability()` repeats no call and gives the same R(N)."""
    import jointwear

    out = tmp_path / "shared"
    assert _run_and_kill(_cmd(quick_config, out), out, after_calls=4), "the study finished before it was killed"
    res = jointwear.Study(quick_config, out=out, workers=2, resume=True).reliability()
    assert res.reliability.tolist() == expected["curve"]["reliability"]
    assert res.model_calls == expected["model_calls"]
    digest = store_digest(load_config(quick_config))
    with EvaluationStore.open(out, digest, resume=True) as store:
        stats = store.stats()
    assert stats.n_repeated == 0 and stats.n_calls == expected["model_calls"]


def test_resume_with_a_changed_model_is_refused(quick_config, reference_dir, tmp_path, capsys):
    import shutil

    from jointwear.cli import main_entry

    out = tmp_path / "study"
    shutil.copytree(reference_dir, out)  # a folder whose store holds the calls of the quick study
    changed = quick_config.with_name("changed.toml")
    changed.write_text(quick_config.read_text().replace("block_cycles = 80000", "block_cycles = 40000"),
                       encoding="utf-8")
    before = (out / "config.json").read_bytes()
    capsys.readouterr()
    assert main_entry(["reliability", str(changed), "--out", str(out), "--workers", "2", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "holds calls of another wear model (changed: wear.block_cycles)" in err
    assert len([ln for ln in err.splitlines() if ln.strip()]) == 1
    assert (out / "config.json").read_bytes() == before  # refused before it wrote anything


def test_a_run_on_a_folder_with_a_store_is_refused_before_it_writes(quick_config, reference_dir, tmp_path, capsys):
    """`jointwear run` into a folder that holds another study's store: refused up front, not after simulate and
    wear have overwritten that study's results."""
    import shutil

    from jointwear.cli import main_entry

    out = tmp_path / "taken"
    shutil.copytree(reference_dir, out)
    def results():  # SQLite's -wal/-shm side files come and go with any reader
        return {p.name: p.read_bytes() for p in out.iterdir() if p.is_file() and not p.name.endswith(("-wal", "-shm"))}

    files = results()
    capsys.readouterr()
    assert main_entry(["run", str(quick_config), "--out", str(out), "--workers", "2"]) == 2
    assert "an evaluation store already exists" in capsys.readouterr().err
    assert results() == files


def test_a_study_resumed_with_a_larger_budget_reads_back_every_call(quick_config, reference_dir, expected, tmp_path):
    """The learning stopped on its budget: raising max_calls and resuming replays the stored calls and only adds
    the new ones (the learning settings are not part of what a call's outputs depend on)."""
    import shutil

    import jointwear

    out = tmp_path / "larger"
    shutil.copytree(reference_dir, out)
    larger = updated(load_config(quick_config), {"reliability.max_calls": expected["model_calls"] + 1})
    lines: list[str] = []
    res = jointwear.Study(larger, out=out, workers=2, resume=True, echo=lines.append).reliability()
    assert res.model_calls == expected["model_calls"] + 1
    # the summary says which calls were made now (it said only the total)
    n = expected["model_calls"]
    assert any(ln.startswith(f"reliability: {n + 1} model calls (1 new, {n} read back from the store)")
               for ln in lines), lines
    with EvaluationStore.open(out, store_digest(larger), resume=True) as store:
        stats = store.stats()
    assert stats.n_repeated == 0 and stats.n_calls == expected["model_calls"] + 1  # one new call, none repeated


@pytest.mark.timeout(600)
def test_study_on_dask_survives_a_killed_worker(quick_config, expected, tmp_path):
    """The whole study on a Dask cluster; a worker process busy with a wear history is killed with SIGKILL.
    Its nanny restarts it, Dask re-runs the lost call elsewhere, and the study ends with the uninterrupted result:
    no call lost, none stored twice."""
    pytest.importorskip("distributed")
    from distributed import Client

    from jointwear.compute import start_local_cluster

    out = tmp_path / "dask"
    killed = {}
    with start_local_cluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, \
            Client(cluster) as client:
        cmd = _cmd(quick_config, out, "--scheduler", cluster.scheduler_address)
        cmd.remove("--workers")
        cmd.remove("2")
        proc = subprocess.Popen(cmd, env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        t0 = time.monotonic()
        while proc.poll() is None and time.monotonic() - t0 < 300 and not killed:
            if _stored_calls(out) >= 3:
                busy = [w for w, tasks in client.processing().items() if tasks]
                if busy:
                    pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
                    os.kill(pid, signal.SIGKILL)
                    killed.update(pid=pid, calls=_stored_calls(out))
            time.sleep(0.05)
        _, err = proc.communicate(timeout=600)
    assert killed, "the study finished before a worker could be killed"
    assert proc.returncode == 0, err[-2000:]
    got = json.loads((out / "reliability.json").read_text())
    assert got["curve"]["reliability"] == expected["curve"]["reliability"]  # same calls, same numbers
    assert got["model_calls"] == expected["model_calls"]
    digest = store_digest(load_config(quick_config))
    with EvaluationStore.open(out, digest, resume=True) as store:
        stats = store.stats()
    assert stats.n_repeated == 0 and stats.n_failed == 0
    assert stats.n_calls == expected["model_calls"]


def test_a_learning_stopped_by_its_budget_is_told_with_its_error(quick_config, reference_dir, expected):
    """The quick study stops on its 14-call budget: the result keeps why, and the terminal's line gives the
    surrogate's largest error estimate of R over the levels whose COV counts, where it is, and what to do."""
    import numpy as np

    from jointwear.study.stage_lines import learning_stop_line
    from jointwear.study.results import ReliabilityCurve

    assert not expected["converged"] and expected["learning_stop"].startswith("max_calls=14 reached")
    res = ReliabilityCurve.load(reference_dir)
    err = np.asarray(res.pf_error, dtype=float)
    counted = np.isfinite(err) & ~np.asarray(res.below_floor)
    k = np.flatnonzero(counted)[np.argmax(err[counted])]
    line = learning_stop_line(res, load_config(quick_config).reliability)
    assert f"reaches {err[k]:.3f} at {res.cycles[k]:,.0f} cycles (tolerance 0.01 in R or 2 % of Pf)" in line
    assert "raise reliability.max_calls and run again with --resume (resume=True in Python)" in line
    # a COV above its target is named too: a line whose error estimate met its tolerance named nothing unmet
    settings = load_config(quick_config).reliability
    assert ("COV of Pf reaches" in line) == (res.largest_cov() >= settings.cov_target)
    res.pf_cov = np.where(counted, 0.0505, res.pf_cov)
    assert "the COV of Pf reaches 0.0505 (target 0.05)" in learning_stop_line(res, settings)
    # under the paper's U rule the line names that rule, not the error tolerance it does not use
    u_rule = learning_stop_line(res, settings.model_copy(update={"stopping": "u"}))
    assert "(the learning's rule is min U >= 2 at every level, stopping = 'u')" in u_rule
    assert "tolerance" not in u_rule
    # a budget spent while the rule was being confirmed on successive designs (hold_iterations) says that
    res.learning_stop = ("max_calls=14 reached while confirming the learning stop (it held on 2 of the 3 successive "
                         "designs hold_iterations asks for)")
    confirming = learning_stop_line(res, settings)
    assert confirming.startswith("the learning's stopping rule held but was not yet confirmed when it stopped "
                                 "(max_calls=14 reached while confirming")
    assert "raise reliability.max_calls and run again with --resume" in confirming


def test_a_converged_learning_whose_whole_error_estimate_exceeds_its_tolerance_says_so(quick_config, reference_dir):
    """'converged' was printed while the error estimate with the Kriging's posterior was 2.7 times the tolerance
    (the rule reads ESC's part alone): told with where, how far, and what checks it; not where it is met."""
    import numpy as np

    from jointwear.study.results import ReliabilityCurve
    from jointwear.study.stage_lines import posterior_error_line

    settings = load_config(quick_config).reliability
    res = ReliabilityCurve.load(reference_dir)
    res.converged = True
    counted = ~np.asarray(res.below_floor)
    k = int(np.flatnonzero(counted)[0])
    tolerance = max(settings.error_abs_tol, settings.error_tol * float(res.pf[k]))
    res.pf_error_esc = np.full(len(res.cycles), 0.5 * settings.error_abs_tol)
    res.pf_error = np.where(np.arange(len(res.cycles)) == k, 2.7 * tolerance, 0.5 * tolerance)
    line = posterior_error_line(res, settings)
    assert f"reaches {2.7 * tolerance:.3f} at {res.cycles[k]:,.0f} cycles, 2.7 times the tolerance there" in line
    assert "`jointwear validate` checks against the true model" in line
    res.pf_error = np.full(len(res.cycles), 0.9 * settings.error_abs_tol)  # met: nothing to tell
    assert posterior_error_line(res, settings) == ""
    res.converged = False  # the unconverged line tells the error instead
    res.pf_error = np.full(len(res.cycles), 2.7 * tolerance)
    assert posterior_error_line(res, settings) == ""


def test_a_population_that_hit_n_mc_max_says_how_large_it_must_be(quick_config, reference_dir):
    """The line said 'the learning stopped before its tolerance' and advised subset_simulation, which no study
    setting offers; the shortfall was the Monte Carlo population (Pf = 0.00103 needs about 388,000 samples)."""
    import numpy as np

    from jointwear.study.stage_lines import learning_stop_line
    from jointwear.study.results import ReliabilityCurve

    res = ReliabilityCurve.load(reference_dir)
    settings = load_config(quick_config).reliability
    res.learning_stop = "COV target 0.05 not met with the maximum population n_mc_max=200000 (pf=0.00103)"
    res.pf = np.full(len(res.cycles), 0.5)
    res.pf_cov = np.full(len(res.cycles), 0.01)
    res.pf[1], res.pf_cov[1] = 0.00103, 0.0685
    line = learning_stop_line(res, settings)
    n = (1 - 0.00103) / (0.00103 * settings.cov_target ** 2)  # COV^2 = (1 - Pf) / (n Pf)
    assert line.startswith("the Monte Carlo population reached its maximum before the COV of Pf met its target")
    assert f"at Pf = 0.00103 needs about {n:,.0f} samples" in line and "subset" not in line
    assert "raise reliability.n_mc_max" in line and "reliability.pf_floor" in line
    # a level below pf_floor, whose COV is waived, is not the one named (it asked for 2.2e17 samples at 1.8e-15)
    res.pf[0], res.pf_cov[0] = 1.8e-15, 1.0
    res.below_floor = np.arange(len(res.cycles)) == 0
    assert f"at Pf = 0.00103 needs about {n:,.0f} samples" in learning_stop_line(res, settings)


def test_a_second_study_in_a_folder_in_use_is_refused(quick_config, tmp_path):
    """Two studies started in one folder both ran, mixing their files and their calls in one store."""
    from filelock import FileLock

    import jointwear
    from jointwear.schema import ConfigError

    out = tmp_path / "busy"
    # a budget the first study cannot spend before the checks: 14 calls ended within seconds of the first one
    longer = quick_config.with_name("longer.toml")
    longer.write_text(quick_config.read_text().replace("max_calls = 14", "max_calls = 60"), encoding="utf-8")
    proc = subprocess.Popen(_cmd(longer, out), env=_env(), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, start_new_session=True)
    try:
        t0 = time.monotonic()
        while _stored_calls(out) < 1 and proc.poll() is None and time.monotonic() - t0 < 300:
            time.sleep(0.05)
        assert proc.poll() is None, "the first study ended before the second could start"
        with pytest.raises(ConfigError, match="another jointwear study is working in"):
            jointwear.Study(quick_config, out=out, workers=1, resume=True).reliability()
        # a run without --resume was told of 'a store from an earlier run', and to resume or overwrite it
        with pytest.raises(ConfigError, match="another jointwear study is working in"):
            jointwear.Study(quick_config, out=out, workers=1).run()
        assert proc.poll() is None  # the first study goes on
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    with FileLock(out / ".jointwear.lock", timeout=0):  # a killed study leaves the folder free (else: Timeout)
        pass


def test_a_curve_that_misses_the_life_is_told_in_the_terminal(quick_config, reference_dir, tmp_path, monkeypatch):
    """A curve ending long before the nominal design reaches its allowance 'converged' at R = 1 everywhere; only
    the report said that the curve misses the life."""
    import numpy as np

    import jointwear
    from jointwear.study import reliability
    from jointwear.study.results import ReliabilityCurve

    res = ReliabilityCurve.load(reference_dir)
    res.life_table = [dict(res.life_table[0], cycles=None, hours=None, status="beyond_curve")]
    res.reliability = np.ones_like(res.reliability)
    monkeypatch.setattr(reliability, "run_reliability", lambda ctx, progress=None: res)
    lines: list[str] = []
    jointwear.Study(quick_config, out=tmp_path / "short", echo=lines.append).reliability()
    (told,) = [ln for ln in lines if "lies beyond this curve" in ln]
    assert told.startswith("reliability: The life at R = 0.9 lies beyond this curve") and "<code>" not in told
    assert "Raise reliability.cycles_stop" in told


def test_an_unreachable_scheduler_is_refused_at_once_before_the_nominal_stages(quick_config, tmp_path):
    """`run --scheduler tcp://...` at an address where nothing listens ran simulate and wear, then waited 30 s for
    distributed's connect time-out (docs/compute.md promised it fails at once)."""
    import socket

    import jointwear
    from jointwear.schema import ConfigError

    with socket.socket() as s:  # a port nothing listens on once closed
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    out = tmp_path / "unreachable"
    t0 = time.monotonic()
    with pytest.raises(ConfigError, match=rf"^compute: cannot start the executor: cannot reach the Dask scheduler at "
                                          rf"'tcp://127\.0\.0\.1:{port}'"):
        jointwear.Study(quick_config, out=out, scheduler=f"tcp://127.0.0.1:{port}").run()
    assert time.monotonic() - t0 < 10.0 and not out.exists()
    # and a single stage that makes model calls writes nothing either (reliability rewrote config.json, converge
    # made its folder, lock and store)
    for stage in ("reliability", "converge"):
        with pytest.raises(ConfigError, match=r"^compute: cannot start the executor"):
            getattr(jointwear.Study(quick_config, out=out, scheduler=f"tcp://127.0.0.1:{port}"), stage)()
        assert not out.exists(), stage


def test_a_study_ended_by_sigterm_says_how_to_resume(quick_config, tmp_path):
    """A batch scheduler's SIGTERM at a time limit ended a study with no message but leaked-semaphore warnings (exit
    143); it now ends as a Ctrl-C does: the calls made kept, the resume hint told, exit status 143 still."""
    out = tmp_path / "term"
    proc = subprocess.Popen(_cmd(quick_config, out), env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True, text=True)
    try:
        t0 = time.monotonic()
        while _stored_calls(out) < 1 and proc.poll() is None and time.monotonic() - t0 < 300:
            time.sleep(0.05)
        assert proc.poll() is None, "the study ended before it could be terminated"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 143, err
    assert "error: aborted" in err and "--resume" in err and "leaked semaphore" not in err, err
    assert _stored_calls(out) >= 1
