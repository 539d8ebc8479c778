"""Benchmark of the direct validation: `jointwear reliability` then `jointwear validate --samples N` on a config,
each in a fresh process.

    python benchmarks/validate.py [--config PRESET_OR_TOML] [--samples 2000] [--workers N] [--keep DIR]

Writes benchmarks/results/validate.json (validate_<name>.json for another config): the wall time of the
validation (bar: 2,000 calls within 30 minutes on 2 cores), the calls, the load average, the machine, and the
validation itself (true-model R(N) with its exact 95 % interval against the surrogate's, agreement per level,
the life at each target on both curves with their intervals, the surrogate's leave-one-out Q^2).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from jointwear.config import load_config
from jointwear.study.io import provenance


def run(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=dict(os.environ, JOINTWEAR_PROGRESS="0"), capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd[2:4])} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="jin2025_flapping_wing")
    ap.add_argument("--samples", type=int, default=2000)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--keep", type=Path, default=None, help="Run in (and keep) this folder; resumes a stopped run.")
    args = ap.parse_args()
    name = load_config(args.config).name
    out_file = args.out or Path(__file__).parent / "results" / (
        "validate.json" if name == "jin2025_flapping_wing" else f"validate_{name}.json")
    tmp = None
    if args.keep is None:
        tmp = tempfile.TemporaryDirectory()
        folder = Path(tmp.name) / "run"
    else:
        folder = args.keep
    extra = ["--workers", str(args.workers)] if args.workers else []
    resume = ["--resume"] if (folder / "evaluations.sqlite").exists() else []
    load_before = os.getloadavg()[0]
    wall_rel = run([sys.executable, "-m", "jointwear", "reliability", args.config, "--out", str(folder),
                    *extra, *resume])
    wall_val = run([sys.executable, "-m", "jointwear", "validate", args.config, "--samples", str(args.samples),
                    "--out", str(folder), *extra])
    val = json.loads((folder / "validation.json").read_text())
    result = {
        "benchmark": "jointwear validate (direct Monte Carlo of the true wear model against the R(N) surrogate)",
        "date": dt.date.today().isoformat(), "config": args.config, "name": name,
        "machine": {"cpus": os.cpu_count(), **provenance()}, "load_average_before": load_before,
        "load_average_after": os.getloadavg()[0],
        "bar_seconds_for_2000_calls": 1800, "reliability_wall_seconds": wall_rel,
        "validate_wall_seconds": wall_val, "validate_seconds_per_call": wall_val / max(val["model_calls"], 1),
        "validation": {k: v for k, v in val.items() if k != "provenance"},
    }
    out_file.parent.mkdir(parents=True, exist_ok=True)
    out_file.write_text(json.dumps(result, indent=1) + "\n")
    if args.keep is not None:
        shutil.copy(out_file, folder / "validate_benchmark.json")
    print(json.dumps({"name": name, "validate_wall_seconds": wall_val, "calls": val["model_calls"],
                      "agreement": f"{sum(val['agreement'])}/{len(val['agreement'])}",
                      "life": val.get("life_table", [])}))


if __name__ == "__main__":
    main()
