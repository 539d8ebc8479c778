"""Benchmark of the threads a local worker gives one model call: two source trees, alternating, each study in a
fresh process.

    python benchmarks/executor_threads.py --before SRC --after SRC [--presets A,B] [--repeats 2]

Runs `jointwear run PRESET` with PYTHONPATH=SRC for each tree, the trees alternating within each repeat, and
writes benchmarks/results/executor_threads.json: the wall times, their medians and ratio (after / before) per
preset, the lives (the threads must not change them), the machine. Written for the change of
`LocalExecutor.threads_per_call` from cores // workers to every core (before: a clone of the commit before it).
Each tree compiles its kernels into its own cache: run once beforehand so that the first timed run does not
compile.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

from study import one_run

from jointwear.study.io import provenance


def timed_run(src: str, preset: str) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        r = one_run(preset, Path(tmp), None, pythonpath=src)
    return {k: r[k] for k in ("wall_seconds", "load_average_before", "life_cycles", "model_calls")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", required=True, help="src folder of the tree before the change")
    ap.add_argument("--after", required=True, help="src folder of the tree after the change")
    ap.add_argument("--presets", default="jin2025_flapping_wing,jin2025_flapping_wing_profile")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "executor_threads.json")
    a = ap.parse_args()
    trees = {"before": a.before, "after": a.after}
    result = {"benchmark": __doc__.splitlines()[0], "date": dt.date.today().isoformat(),
              "machine": {"cpus": os.cpu_count(), **provenance()}, "trees": trees, "presets": {}}
    for preset in a.presets.split(","):
        runs = {name: [] for name in trees}
        for _ in range(a.repeats):
            for name, src in trees.items():
                runs[name].append(timed_run(src, preset))
                print(preset, name, f"{runs[name][-1]['wall_seconds']:.1f} s", file=sys.stderr)
        med = {name: statistics.median(r["wall_seconds"] for r in runs[name]) for name in trees}
        result["presets"][preset] = {
            "runs": runs, "median_wall_seconds": med, "ratio_after_to_before": med["after"] / med["before"],
            "same_lives": len({r["life_cycles"] for rs in runs.values() for r in rs}) == 1,
        }
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({p: {k: v for k, v in r.items() if k != "runs"} for p, r in result["presets"].items()}, indent=1))


if __name__ == "__main__":
    main()
