"""Cost of one true-model call of each preset: a whole wear history to the end of its R(N) curve.

A reliability study makes up to ``reliability.max_calls`` such calls (plus a few for the sensitivity), run by
one worker process per core, so (calls / workers) x the CPU time of one call estimates the study's wall time on
an idle machine. Writes JSON (default benchmarks/results/preset_calls.json): per preset the wall and CPU
seconds of each repeat, their medians, the ratio of the median CPU time to the flapping-wing preset's in the same
process, and that estimate for 2 workers.

    python benchmarks/preset_calls.py [--repeats 3] [--out benchmarks/results/preset_calls.json]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import statistics
import time
from pathlib import Path

from jointwear.config import available_presets, load_config
from jointwear.mechanism import build_model
from jointwear.wear import wear_history

REFERENCE = "jin2025_flapping_wing"
SENSITIVITY_CALLS = 14  # upper end of the extra calls of the sensitivity stage (2 per separable-scaling rule)


def one_preset(name: str, repeats: int) -> dict:
    cfg = load_config(name)
    model = build_model(cfg)
    n = max(cfg.reliability.curve_cycles())
    wear_history(model, cfg.wear, min(n, 2 * cfg.wear.block_cycles))  # compile / load the kernels once
    walls, cpus, sims = [], [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        res = wear_history(model, cfg.wear, n)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)  # every lane's thread
        sims.append(res.n_simulated_cycles)
    cpu = statistics.median(cpus)
    calls = cfg.reliability.max_calls + SENSITIVITY_CALLS
    return {"cycles": n, "block_cycles": cfg.wear.block_cycles, "lanes": cfg.wear.lanes,
            "simulated_cycles": sims[0], "wall_seconds": walls, "cpu_seconds": cpus,
            "median_wall_seconds": statistics.median(walls), "median_cpu_seconds": cpu,
            "max_calls": cfg.reliability.max_calls,
            "study_estimate_seconds_2_workers": calls / 2 * cpu}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "preset_calls.json")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    presets = {name: one_preset(name, args.repeats) for name in available_presets()}
    ref = presets[REFERENCE]["median_cpu_seconds"]
    for rec in presets.values():
        rec["cpu_ratio_to_" + REFERENCE] = rec["median_cpu_seconds"] / ref
    out = {"date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
           "host": {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
                    "python": platform.python_version(), "load_average_before": load,
                    "load_average_after": os.getloadavg()[0]},
           "sensitivity_calls_assumed": SENSITIVITY_CALLS, "presets": presets}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1))
    for name, rec in presets.items():
        print(f"{name}: one call to {rec['cycles']:,} cycles: {rec['median_cpu_seconds']:.2f} s CPU "
              f"({rec['median_wall_seconds']:.2f} s wall), x{rec['cpu_ratio_to_' + REFERENCE]:.2f} the "
              f"flapping-wing call; study estimate {rec['study_estimate_seconds_2_workers']:.0f} s on 2 workers")


if __name__ == "__main__":
    main()
