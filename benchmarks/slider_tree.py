"""Linkages with a slider on the tree kernel (joint coordinates) against the Cartesian kernel they ran on before.

Writes benchmarks/results/slider_tree.json. Run: python benchmarks/slider_tree.py [--repeats 5] (about 5 minutes).

- per_cycle: for the Flores slider-crank preset and the two test linkages of tests/dynamics/test_tree_slider.py with a
  slower crank (the piston pump at 1500 rpm, the quick-return slotted lever at 300 rpm): one cycle from a settled state
  on the tree kernel (the default) and on the Cartesian kernel (fast=False), alternated in the same process; medians
  of the whole simulate() call, steps per cycle, and the mean contact force of each (the same physics; the clearance
  dynamics is chaotic, so they agree to the scatter of one cycle, not to rounding);
- wear_call: one wear-history model call of the Flores preset's study (wear_history(build_model(cfg), cfg.wear,
  reliability.cycles_stop)) on each kernel, alternated: median wall seconds and the last call's max bearing wear;
- wear_scatter: that call's max bearing wear, 16 calls per kernel with the journal radius nudged by k x 1e-9 (relative),
  at the preset's integrator tolerance and at 10x and 100x tighter ones: mean and standard error per kernel (the
  impacting joint's wear is chaotic: one call scatters by about 5 %; the means say which kernel converges).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results" / "slider_tree.json"


def _models() -> dict:
    sys.path.insert(0, str(ROOT / "tests" / "dynamics"))
    from test_tree_slider import quick_return, slider_crank

    from jointwear.config import load_config
    from jointwear.mechanism import build_model

    return {"flores_slider_crank": build_model(load_config("flores_slider_crank")), "piston_pump": slider_crank(),
            "quick_return": quick_return()}


def per_cycle(repeats: int) -> dict:
    from jointwear.mechanism import simulate

    out = {}
    for name, model in _models().items():
        state = simulate(model, 0.0, settle_cycles=2).state_end
        runs = {"tree": [], "cartesian": []}
        last = {}
        for _ in range(repeats + 1):  # the first of each compiles or loads the cache: dropped
            for label, fast in (("tree", None), ("cartesian", False)):
                t0 = time.perf_counter()
                r = simulate(model, 1, settle_cycles=0, state0=state, fast=fast)
                runs[label].append(time.perf_counter() - t0)
                last[label] = r
        rec = {}
        for label, r in last.items():
            rec[label] = {"kernel": r.extra["kernel"],
                          "wall_seconds_per_cycle_median": statistics.median(runs[label][1:]),
                          "wall_seconds_all": runs[label][1:], "steps_per_cycle": int(r.n_steps),
                          "contact_force_mean_N": [j.mean_force for j in r.joints]}
        rec["ratio_tree_to_cartesian_per_cycle"] = (rec["tree"]["wall_seconds_per_cycle_median"]
                                                    / rec["cartesian"]["wall_seconds_per_cycle_median"])
        out[name] = rec
        print(name, f"tree/cartesian per cycle {rec['ratio_tree_to_cartesian_per_cycle']:.2f}", file=sys.stderr)
    return out


def wear_call(repeats: int) -> dict:
    import functools

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.wear import wear_history

    cfg = load_config("flores_slider_crank")
    n = int(cfg.reliability.cycles_stop)
    sims = {"tree": simulate, "cartesian": functools.partial(simulate, fast=False)}
    walls = {k: [] for k in sims}
    last = {}
    for sim in sims.values():
        wear_history(build_model(cfg), cfg.wear, n, simulate=sim)  # compile / load from numba's cache, untimed
    for _ in range(repeats):  # alternated
        for label, sim in sims.items():
            t0 = time.perf_counter()
            last[label] = wear_history(build_model(cfg), cfg.wear, n, simulate=sim)
            walls[label].append(time.perf_counter() - t0)
    out = {"cycles": n, "lanes": cfg.wear.lanes}
    for label, res in last.items():
        out[label] = {"wall_seconds_median": statistics.median(walls[label]), "wall_seconds_all": walls[label],
                      "max_bearing_wear_mm": res.joints[0].max_bearing_wear * 1e3, "n_steps": int(res.n_steps)}
    out["ratio_tree_to_cartesian_wall"] = out["tree"]["wall_seconds_median"] / out["cartesian"]["wall_seconds_median"]
    return out


def wear_scatter(n_calls: int = 16) -> dict:
    import functools

    from jointwear.config import load_config, updated
    from jointwear.mechanism import build_model, simulate
    from jointwear.wear import wear_history

    cfg = load_config("flores_slider_crank")
    r0, n = cfg.clearance_joints[0].journal_radius, int(cfg.reliability.cycles_stop)
    out = {"cycles": n, "calls_per_kernel": n_calls}
    for factor in (1.0, 0.1, 0.01):
        rtol, atol = cfg.wear.rtol * factor, cfg.wear.atol * factor
        rec = {"rtol": rtol, "atol_m": atol}
        for label, sim in (("tree", simulate), ("cartesian", functools.partial(simulate, fast=False))):
            vals = []
            for k in range(n_calls):
                c = updated(cfg, {"clearance_joints.0.journal_radius": r0 * (1 + 1e-9 * k), "wear.rtol": rtol,
                                  "wear.atol": atol})
                vals.append(wear_history(build_model(c), c.wear, n, simulate=sim).joints[0].max_bearing_wear * 1e3)
            rec[label] = {"max_bearing_wear_mm_mean": float(np.mean(vals)),
                          "standard_error_mm": float(np.std(vals, ddof=1) / np.sqrt(n_calls)), "values_mm": vals}
        out[f"rtol_{rtol:.0e}"] = rec
        print("wear scatter", rtol, {k: round(rec[k]["max_bearing_wear_mm_mean"], 4) for k in ("tree", "cartesian")},
              file=sys.stderr)
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    import os

    from jointwear.study.io import provenance

    rec = {"date_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
           "machine": {"cpus": os.cpu_count(), **provenance()},
           "per_cycle": per_cycle(args.repeats), "wear_call": wear_call(args.repeats), "wear_scatter": wear_scatter()}
    OUT.write_text(json.dumps(rec, indent=1, default=lambda o: float(o) if isinstance(o, np.floating) else str(o)))
    print(OUT)


if __name__ == "__main__":
    main()
