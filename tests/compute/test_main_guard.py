"""A script without `if __name__ == "__main__":` that starts worker processes is told so at once.

Without the guard every worker imports the script again and runs the study once more; a user's study took two
minutes and ended with 'g returned NaN for every one of the 8 initial design points'."""

import subprocess
import sys
import textwrap


def _run(tmp_path, body: str) -> subprocess.CompletedProcess:
    script = tmp_path / "sweep.py"
    script.write_text(textwrap.dedent(body), encoding="utf-8")
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)


def test_a_script_without_the_main_guard_is_refused_before_any_worker_starts(tmp_path):
    done = _run(tmp_path, """
        # a comment that names `if __name__ == "__main__":` is no guard
        from jointwear.compute import make_executor
        print("script body ran")
        make_executor(2)
    """)
    assert done.returncode != 0
    assert done.stdout.count("script body ran") == 1  # no worker imported it again
    assert "sweep.py runs model calls in 2 worker processes" in done.stderr
    assert 'put the study under `if __name__ == "__main__":`' in done.stderr


def test_a_guarded_script_runs_its_calls_in_workers(tmp_path):
    done = _run(tmp_path, """
        from jointwear.compute import make_executor

        if "__main__" == __name__:
            with make_executor(2) as pool:
                print(list(pool.map(abs, [-1, -2, -3])))
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[1, 2, 3]"


def test_serial_calls_need_no_guard(tmp_path):
    done = _run(tmp_path, """
        from jointwear.compute import make_executor
        with make_executor(1) as pool:
            print(list(pool.map(abs, [-4])))
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[4]"


def test_a_script_read_from_stdin_is_refused_before_any_worker_starts():
    """`python - < sweep.py` with workers: every worker died importing '<stdin>', and the study blamed the worker
    processes only after all its initial calls had failed."""
    body = 'from jointwear.compute import make_executor\n\nif __name__ == "__main__":\n    make_executor(2)\n'
    done = subprocess.run([sys.executable, "-"], input=body, capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert "the main script (<stdin>) cannot be read again by the 2 worker processes" in done.stderr


def test_a_study_without_the_guard_is_refused_before_it_writes_its_folder(tmp_path):
    """Study(..., workers=2).reliability() in such a script was refused by the executor after config.json and an
    empty evaluation store were written (a designer's audit)."""
    done = _run(tmp_path, f"""
        import jointwear
        try:
            jointwear.Study("jin2025_flapping_wing", out={str(tmp_path / "out")!r}, workers=2).reliability()
        except jointwear.ConfigError as exc:
            print(exc)
    """)
    assert done.returncode == 0, done.stderr
    assert "compute: cannot start the executor: " in done.stdout and "runs model calls in 2 worker" in done.stdout
    assert not (tmp_path / "out").exists()
