"""Benchmark of the whole study: `jointwear run CONFIG` end to end, in a fresh process.

    python benchmarks/study.py [--config PRESET_OR_TOML] [--workers N] [--repeats K]

Writes benchmarks/results/study.json for the default preset, study_<name>.json for any other config: the wall
time of each run (median over repeats), the load average before it, the machine (host CPU as numba compiles
for it), the R(N) curve, the life table, the governing joint, the model calls, the life surrogate's fit
(`surrogate_fit`: Q^2, scatter) and the sensitivity's shifted reliabilities (`sensitivity`). Goal: 10 minutes
on 2 cores for any shipped preset.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from jointwear.config import load_config
from jointwear.study.io import provenance


def one_run(config: str, workdir: Path, workers: int | None, pythonpath: str | None = None) -> dict:
    """`jointwear run CONFIG` in a fresh process (with PYTHONPATH=pythonpath: another source tree)."""
    out = workdir / "run"
    env = dict(os.environ, JOINTWEAR_PROGRESS="0")
    if pythonpath is not None:
        env["PYTHONPATH"] = pythonpath
    load = os.getloadavg()[0]
    cmd = [sys.executable, "-m", "jointwear", "run", config, "--out", str(out)]
    if workers:
        cmd += ["--workers", str(workers)]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"jointwear run failed ({proc.returncode}): {proc.stderr[-2000:]}")
    rel = json.loads((out / "reliability.json").read_text())
    wear = json.loads((out / "wear.json").read_text())
    sens = json.loads((out / "sensitivity.json").read_text())
    return {
        "wall_seconds": wall, "load_average_before": load, "model_calls": rel["model_calls"],
        "sensitivity_extra_model_calls": sens.get("extra_model_calls"),
        "converged": rel.get("converged"), "n_mc": rel["n_mc"],
        "curve": {"cycles": rel["curve"]["cycles"], "reliability": rel["curve"]["reliability"]},
        "life_table": rel.get("life_table"), "governing_joint": rel.get("governing_joint"),
        "life_cycles": rel["life_at_target"]["cycles"], "life_hours": rel["life_at_target"]["hours"],
        "mean_max_wear_mm": rel.get("mean_max_wear_mm"),
        "nominal_max_wear_mm": wear["max_wear_mm"], "nominal_max_wear_angle_deg": wear["max_wear_angle_deg"],
        "surrogate_fit": rel.get("surrogate_fit"),
        "sensitivity": sensitivity_readings(sens),
        "stderr_tail": proc.stderr[-1500:],
    }


SENSITIVITY_VARIABLE_KEYS = ("name", "group", "reliability_low", "reliability_high", "reliability_low_error",
                             "reliability_high_error")


def sensitivity_readings(sens: dict) -> dict:
    """The shifted reliabilities of sensitivity.json that the docs quote: the nominal R at the sensitivity level,
    each variable's R at its low and high factor with their errors, the rule that read each shift, the Archard
    checks (scaling against the surrogate's direct reading), the rankings and the unresolved pairs."""
    return {
        "cycles": sens.get("cycles"), "factors": sens.get("factors"),
        "reliability_nominal": sens.get("reliability_nominal"),
        "reliability_nominal_error": sens.get("reliability_nominal_error"),
        "variables": [{k: v[k] for k in SENSITIVITY_VARIABLE_KEYS if k in v} for v in sens.get("variables", [])],
        "rules": sens.get("rules"), "archard_checks": sens.get("archard_checks"),
        "ranking_by_group": sens.get("ranking_by_group"), "unresolved_pairs": sens.get("unresolved_pairs"),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", "--preset", dest="config", default="jin2025_flapping_wing")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--keep", type=Path, default=None, help="Keep the last run's output folder here.")
    args = ap.parse_args()
    name = load_config(args.config).name
    default = "study.json" if name == "jin2025_flapping_wing" else f"study_{name}.json"
    out_file = args.out or Path(__file__).parent / "results" / default
    runs = []
    for _ in range(args.repeats):
        with tempfile.TemporaryDirectory() as tmp:
            runs.append(one_run(args.config, Path(tmp), args.workers))
            if args.keep is not None:
                shutil.rmtree(args.keep, ignore_errors=True)
                shutil.copytree(Path(tmp) / "run", args.keep)
    result = {
        "benchmark": "jointwear run (whole study, end to end, fresh process)",
        "date": dt.date.today().isoformat(), "config": args.config, "name": name,
        "machine": {"cpus": os.cpu_count(), **provenance()},
        "goal_seconds": 600, "median_wall_seconds": statistics.median(r["wall_seconds"] for r in runs),
        "runs": runs,
    }
    out_file.parent.mkdir(parents=True, exist_ok=True)
    out_file.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({k: result[k] for k in ("name", "median_wall_seconds")}))


if __name__ == "__main__":
    main()
