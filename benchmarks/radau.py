"""Time per cycle of the Radau IIA loop (simulation.method = "radau5") against another checkout's, in one process.

The reference is another checkout's ``jointwear/mechanism/radau.py`` (--reference-src DIR: its ``src``), loaded as a
second module beside this one on the same kernel module, so both loops run the same right-hand sides in the same
process, alternated: the flapping wing (natural four-bar kernel) and the Watt six-bar (Cartesian kernel under
Radau), each from a settled state at rtol 1e-5; medians over --repeats after one warm-up (both compile first, in a
fresh numba cache). Also checks that both loops give the same steps and mean contact force. Writes
benchmarks/results/radau.json.

    python benchmarks/radau.py --reference-src DIR [--repeats 7] [--out FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime as dt
import importlib.util
import json
import os
import platform
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

CASES = {"flapping_wing": ("jin2025_flapping_wing", 30), "six_bar": ("watt_six_bar_two_clearances", 2)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference-src", type=Path, required=True)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "radau.json")
    args = ap.parse_args()
    # a fresh numba cache: a module loaded from a file path cannot load its own cached machine code back
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="jointwear-radau-bench-")
    from llvmlite import binding as llvm

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, radau, simulate

    path = args.reference_src.resolve() / "jointwear" / "mechanism" / "radau.py"
    spec = importlib.util.spec_from_file_location("radau_reference", path)
    reference = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(reference)
    loops = {"current": radau.RADAU_INTEGRATORS, "reference": reference.RADAU_INTEGRATORS}
    cases = {}
    for name, (preset, cycles) in CASES.items():
        model = build_model(load_config(preset))
        state = simulate(model, 0.0, settle_cycles=1).state_end
        rad = dataclasses.replace(model, settings=model.settings.model_copy(update={"method": "radau5"}))
        walls = {k: [] for k in loops}
        same = {}
        for rep in range(args.repeats + 1):
            for which, integrators in loops.items():
                radau.RADAU_INTEGRATORS = integrators
                t0 = time.perf_counter()
                res = simulate(rad, cycles, settle_cycles=0, state0=state, rtol=1e-5, atol=1e-8)
                if rep:  # the first round compiles (or loads) both loops
                    walls[which].append((time.perf_counter() - t0) / cycles)
                same[which] = (res.n_recorded_steps, res.joints[0].mean_force)
        radau.RADAU_INTEGRATORS = loops["current"]
        med = {k: statistics.median(v) for k, v in walls.items()}
        cases[name] = {"preset": preset, "cycles": cycles, "kernel": res.extra["kernel"],
                       "seconds_per_cycle": walls, "median_seconds_per_cycle": med,
                       "ratio_current_to_reference": med["current"] / med["reference"],
                       "same_steps_and_mean_force": same["current"] == same["reference"],
                       "steps": same["current"][0], "mean_force_N": same["current"][1]}
        print(f"{name}: {med['current'] * 1e3:.2f} ms per cycle against {med['reference'] * 1e3:.2f} ms "
              f"({cases[name]['ratio_current_to_reference']:.3f}x), same results: "
              f"{cases[name]['same_steps_and_mean_force']}", flush=True)
    here = Path(__file__).resolve().parents[1]
    commit = subprocess.run(["git", "-C", str(here), "rev-parse", "HEAD"], capture_output=True, text=True).stdout
    ref_commit = subprocess.run(["git", "-C", str(args.reference_src.resolve().parent), "rev-parse", "HEAD"],
                                capture_output=True, text=True).stdout
    rec = {"date_utc": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
           "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "platform": platform.platform(),
                       "llvm_host_cpu": str(llvm.get_host_cpu_name()), "loadavg_1min_at_start": os.getloadavg()[0]},
           "commit": commit.strip() or None, "reference_commit": ref_commit.strip() or None,
           "note": "one process, the two Radau loops alternated on the same kernels; seconds per recorded cycle from "
                   "a settled state, rtol 1e-5, atol 1e-8",
           "cases": cases}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rec, indent=2) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
