"""The own-mechanism examples (examples/my_linkage.toml, study_from_toml.sh, study_from_python.py) run as a
user runs them, on a small version of the config (short curve, few model calls) so the test stays short."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from result_keys import undocumented_keys

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

SMALL = {
    # one recorded cycle a block (2 by default): a third less dynamics in every history, converge's 48 included
    "[wear]": "[wear]\ncycles = 300000\nblock_cycles = 150000\nrecord_cycles = 1\n",
    "[reliability]": ("[reliability]\nallowance_mm = 0.003\ncycles_start = 100000\ncycles_stop = 300000\n"
                      "cycles_step = 100000\ntarget_reliability = [0.9, 0.99]\nn_mc = 20000\nn_initial = 6\n"
                      "max_calls = 8\n"),
    "[sensitivity]": "[sensitivity]\nsobol_base_samples = 64\n",
}


def _small_config(tmp_path: Path) -> Path:
    """examples/my_linkage.toml with its [wear], [reliability] and [sensitivity] tables replaced by SMALL."""
    lines, skip = [], False
    for line in (EXAMPLES / "my_linkage.toml").read_text(encoding="utf-8").splitlines():
        head = line.strip().split("#")[0].strip()
        if head.startswith("[") and not head.startswith("[["):
            skip = head in SMALL
        elif head.startswith("[["):
            skip = False
        if not skip:
            lines.append(line)
    path = tmp_path / "small_linkage.toml"
    path.write_text("\n".join(lines) + "\n" + "\n".join(SMALL.values()), encoding="utf-8")
    return path


def _env() -> dict:
    env = dict(os.environ, JOINTWEAR_PROGRESS="0", MPLBACKEND="Agg")
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    return env


@pytest.mark.timeout(900)
def test_toml_example_runs_the_whole_study(tmp_path):
    if shutil.which("jointwear", path=_env()["PATH"]) is None:
        pytest.skip("the jointwear console script is not installed")
    out = tmp_path / "out"
    proc = subprocess.run(["bash", str(EXAMPLES / "study_from_toml.sh"), str(_small_config(tmp_path)), str(out)],
                          capture_output=True, text=True, timeout=900, env=_env(), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    for name in ("wear_convergence.json", "simulate.json", "wear.json", "reliability.json", "sensitivity.json",
                 "report.html",
                 "reliability_curve.csv", "life_table.csv", "design_points.csv", "sensitivity.csv"):
        assert (out / name).is_file(), name
    rel = json.loads((out / "reliability.json").read_text())
    assert [row["target"] for row in rel["life_table"]] == [0.9, 0.99]
    assert rel["curve"]["cycles"] == [100000, 200000, 300000]  # the user's bounds, nothing from the paper
    html = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "", (out / "report.html").read_text())
    assert 'id="wear-convergence"' in html  # the check run before the study is in its report
    assert not re.search(r"\bJin\b|Drones", html)  # a report about the user's study, not the reference paper
    # every key of every result file is in docs/results.md (tests/result_keys.py)
    for name in ("simulate.json", "simulate.npz", "simulate_joints.csv", "wear.json", "reliability.json",
                 "sensitivity.json", "config.json"):
        assert undocumented_keys(out / name) == [], name


@pytest.mark.timeout(900)
def test_python_example_runs_and_scripts_a_variation(tmp_path):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, str(EXAMPLES / "study_from_python.py"), str(_small_config(tmp_path)),
                           str(out)], capture_output=True, text=True, timeout=900, env=_env(), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "life at R = 0.9" in proc.stdout and "tight hardness" in proc.stdout
    assert (out / "baseline" / "report.html").is_file() and (out / "tight_hardness" / "reliability.json").is_file()
    # a quiet terminal: numerical warnings are handled where they arise, none reaches the screen or the log
    assert "Warning" not in proc.stderr, proc.stderr[-3000:]
    for folder in ("baseline", "tight_hardness"):
        log = out / folder / "jointwear.log"
        assert not log.exists() or "RuntimeWarning" not in log.read_text(), log.read_text()


def test_the_slider_example_checks_and_runs_on_the_tree_kernel(capsys):
    """examples/piston_pump.toml (a slider-crank drawn as a general linkage): valid for every stage, and its dynamics
    runs on the joint-coordinate kernel with the journal pressed by the 200 N fluid load. Mean contact force within
    5 % of it: the piston's inertia averages out over a cycle (its acceleration has zero mean, and 0.15 kg x 15 mm x
    (157 rad/s)^2 x 1.25 ~ 70 N < 200 N keeps the force's sign), and the rod's obliquity (up to 14.5 deg) adds about
    phi^2 / 4 ~ 1.6 % (measured +1.5 %)."""
    from jointwear.cli import main_entry
    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate

    assert main_entry(["check", str(EXAMPLES / "piston_pump.toml")]) == 0
    assert "valid study config for the stages simulate, wear, reliability, sensitivity" in capsys.readouterr().err
    res = simulate(build_model(load_config(EXAMPLES / "piston_pump.toml")), 1, settle_cycles=1)
    assert res.extra["kernel"] == "tree"
    assert res.joints[0].mean_force == pytest.approx(200.0, rel=0.05)
