"""Cold compilation of the dynamics kernels: what the first simulation after installing (or upgrading) costs.

Each case runs in a fresh process with empty numba and generated-kernel caches (NUMBA_CACHE_DIR and
JOINTWEAR_KERNEL_CACHE in a temporary directory): the wall seconds of its first short simulation (compilation and
0.01 cycle), then of the same call in a second fresh process on the now warm caches (the load); in each process then
the wall seconds of one cycle from there (median of 3; the record keeps both processes'). Cases: the
flapping wing (natural four-bar kernel), the Flores slider-crank and the Watt six-bar (tree kernel, each shape's
generated module), the flapping wing forced onto the Cartesian kernel (fast=False) and under Radau IIA
(simulation.method = "radau5"), and the six-bar under Radau IIA (its Cartesian kernel). The first pass is repeated
--repeats times (median). --reference-src DIR measures the same cases on another checkout's ``src`` directory (e.g. a
worktree of an earlier commit), alternated with the current one, and records the ratios.

    python benchmarks/compile.py [--repeats 1] [--cases NAME ...] [--reference-src DIR] [--out FILE]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

CASES = {
    "flapping_wing_fourbar": ("jin2025_flapping_wing", "dopri5", None),
    "flores_tree": ("flores_slider_crank", "dopri5", None),
    "six_bar_tree": ("watt_six_bar_two_clearances", "dopri5", None),
    "flapping_wing_cartesian": ("jin2025_flapping_wing", "dopri5", False),
    "flapping_wing_radau5": ("jin2025_flapping_wing", "radau5", None),
    "six_bar_radau5": ("watt_six_bar_two_clearances", "radau5", None),
}

CHILD = """
import dataclasses, json, sys, time
t0 = time.perf_counter()
from jointwear.config import load_config
from jointwear.mechanism import build_model, simulate
t_import = time.perf_counter() - t0
preset, method, fast = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
model = build_model(load_config(preset))
if method != "dopri5":
    model = dataclasses.replace(model, settings=model.settings.model_copy(update={"method": method}))
t0 = time.perf_counter()
res = simulate(model, 0.01, settle_cycles=0, fast=fast)
first = time.perf_counter() - t0
runs = []
for _ in range(3):
    t0 = time.perf_counter()
    simulate(model, 1, settle_cycles=0, state0=res.state_end, fast=fast)
    runs.append(time.perf_counter() - t0)
import jointwear
print(json.dumps({"import_seconds": t_import, "first_simulation_seconds": first,
                  "seconds_per_cycle": sorted(runs)[1], "kernel": res.extra["kernel"], "package": jointwear.__file__}))
"""


def run_child(preset: str, method: str, fast, cache: Path, src: Path | None) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache / "numba"), "JOINTWEAR_KERNEL_CACHE": str(cache / "kernels")}
    if src is not None:
        env["PYTHONPATH"] = str(src)
    out = subprocess.run([sys.executable, "-c", CHILD, preset, method, json.dumps(fast)], env=env, check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def one_case(preset: str, method: str, fast, repeats: int, src: Path | None = None) -> dict:
    cold, warm, per_cycle, kernel = [], [], [], None
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as d:
            first = run_child(preset, method, fast, Path(d), src)
            second = run_child(preset, method, fast, Path(d), src)
        cold.append(first["first_simulation_seconds"])
        warm.append(second["first_simulation_seconds"])
        per_cycle += [first["seconds_per_cycle"], second["seconds_per_cycle"]]
        kernel, package = first["kernel"], first["package"]
    return {"preset": preset, "method": method, "fast": fast, "kernel": kernel, "package": package,
            "cold_seconds": cold, "warm_seconds": warm, "median_cold_seconds": statistics.median(cold),
            "median_warm_seconds": statistics.median(warm), "seconds_per_cycle": per_cycle,
            "median_seconds_per_cycle": statistics.median(per_cycle)}


def _commit(repo: Path) -> str | None:
    """The checked-out commit of a git work tree, None if it is not one."""
    out = subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], capture_output=True, text=True)
    return out.stdout.strip() or None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES), help="the cases to run")
    ap.add_argument("--reference-src", type=Path, default=None,
                    help="another checkout's src directory, measured alongside as the reference")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "compile.json")
    args = ap.parse_args()
    here = Path(__file__).resolve().parents[1] / "src"
    from numba import __version__ as numba_version
    from numba.core import config as numba_config

    load = os.getloadavg()[0]
    cases = {}
    for name in args.cases:
        preset, method, fast = CASES[name]
        rec = one_case(preset, method, fast, args.repeats, here)
        line = f"{name}: {rec['median_cold_seconds']:.1f} s cold, {rec['median_warm_seconds']:.2f} s warm"
        if args.reference_src is not None:
            ref = one_case(preset, method, fast, args.repeats, args.reference_src.resolve())
            rec["reference"] = ref
            rec["cold_ratio_to_reference"] = rec["median_cold_seconds"] / ref["median_cold_seconds"]
            rec["per_cycle_ratio_to_reference"] = rec["median_seconds_per_cycle"] / ref["median_seconds_per_cycle"]
            line += (f" (reference {ref['median_cold_seconds']:.1f} s cold: {rec['cold_ratio_to_reference']:.2f}x;"
                     f" per cycle {rec['per_cycle_ratio_to_reference']:.2f}x)")
        cases[name] = rec
        print(line, flush=True)
    from llvmlite import binding as llvm

    rec = {
        "date_utc": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "platform": platform.platform(),
                    "llvm_host_cpu": str(llvm.get_host_cpu_name()), "numba": numba_version,
                    "numba_threads": numba_config.NUMBA_NUM_THREADS, "loadavg_1min_at_start": load},
        "note": "each case in fresh processes with empty caches; cold = the first simulate() call of 0.01 cycle "
                "(compilation included), warm = the same call in a second process loading the caches; "
                "seconds_per_cycle = one cycle after it (median of 3 in each process)",
        "commit": _commit(here.parent),
        "reference_src": str(args.reference_src) if args.reference_src else None,
        "reference_commit": _commit(args.reference_src.resolve().parent) if args.reference_src else None,
        "cases": cases,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rec, indent=2) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
