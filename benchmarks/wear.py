"""Wear-stage benchmark and convergence study; writes benchmarks/results/wear.json.

    python benchmarks/wear.py                 # everything (timing, literal method, convergence, reproduction)
    python benchmarks/wear.py --only timing   # timing | literal | convergence | reproduction (comma separated)

Sections
- timing: wall time of one whole wear history to 520k cycles (flapping-wing preset, default settings: 2 lanes), median
  of repeats after a warm-up run that compiles everything (goal <= 1.5 s, issue 3), next to one lane (sequential)
  and the `fast` settings, alternating in the same process.
- literal: the paper's method (re-integrate every cycle, update the geometry after every cycle, Section 3 Step 5):
  a few cycles are timed, the time per cycle is extrapolated to 520k cycles, and the ratio to `timing` reported.
- convergence: max bearing wear at 400k cycles, baseline vs (a) every block size halved, (b) the angular grid
  spacing halved (n_grid doubled), (c) rtol and atol halved; acceptance < 2 % each (issue 3); and (d) one lane
  instead of two (the lanes' lag of the geometry update).
- reproduction: both assembly branches x both geometry modes at 400k cycles (paper: 0.0249 mm at 110 deg, second
  peak 0.0087 mm at 310 deg).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from jointwear.config import load_config
from jointwear.mechanism import build_model, simulate
from jointwear.wear import WearSettings, wear_history

OUT = Path(__file__).resolve().parent / "results" / "wear.json"
MM = 1e3


def config_for(branch: int | None = None):
    cfg = load_config(None)
    if branch is not None:
        mech = cfg.mechanism.model_copy(update={"assembly_branch": branch})
        cfg = cfg.model_copy(update={"mechanism": mech})
    return cfg


def base_settings(cfg) -> WearSettings:
    s = getattr(cfg, "wear", None)
    return s if isinstance(s, WearSettings) else WearSettings()


def summary(res, n=400_000) -> dict:
    j = res.joints[0]
    return {
        "max_wear_mm": float(res.max_wear_at(n) * MM),
        "final_max_wear_mm": j.max_bearing_wear * MM,
        "max_wear_angle_deg": j.max_wear_angle_deg,
        "peaks": [{"angle_deg": round(p["angle_deg"], 2), "depth_mm": p["depth"] * MM} for p in j.peaks[:4]],
        "journal_max_wear_mm": float(j.journal_wear.max() * MM),
        "n_blocks": len(res.blocks),
        "n_simulated_cycles": res.n_simulated_cycles,
        "wall_seconds": res.wall_seconds,
        "rate_initial_mm_per_cycle": float(j.first_rate.bearing.max() * MM),
        "rate_final_mm_per_cycle": float(j.diagnostics.bearing.max() * MM),
        "rod_mean_orientation_deg": float(np.degrees(j.mean_orientation)),
    }


FAST = {"block_cycles": 40_000, "record_cycles": 1, "settle_cycles": 0.5}


def _time_histories(model, variants: dict, repeats: int) -> dict:
    """Wall and CPU time of whole histories to 520k cycles; the variants alternate within each repeat."""
    times = {k: [] for k in variants}
    cpu = {k: [] for k in variants}
    last = {}
    for _ in range(repeats):
        for name, v in variants.items():
            t0, c0 = time.perf_counter(), time.process_time()
            last[name] = wear_history(model, v, 520_000)
            times[name].append(time.perf_counter() - t0)
            cpu[name].append(time.process_time() - c0)
    out = {}
    for name in variants:
        r = last[name]
        out[name] = {
            "wall_seconds_median": statistics.median(times[name]),
            "wall_seconds_all": times[name],
            "cpu_seconds_median": statistics.median(cpu[name]),
            "cpu_seconds_all": cpu[name],
            "n_blocks": len(r.blocks),
            "n_simulated_cycles": r.n_simulated_cycles,
            "simulation_seconds_summed_over_blocks": r.sim_seconds,
            "simulation_seconds_per_cycle": r.sim_seconds / r.n_simulated_cycles,
            "max_wear_mm_at_520k": float(r.max_wear_at(520_000) * MM),
        }
    return out, times


def bench_timing(repeats: int = 5, replicates: int = 4) -> dict:
    """Whole history to 520k cycles (branch -1): default settings (2 lanes), one lane, the FAST settings."""
    cfg = config_for(-1)
    model = build_model(cfg)
    s = base_settings(cfg)
    t0 = time.perf_counter()
    wear_history(model, s, 20_000)  # warm-up: compiles the dynamics and the wear kernels
    warm = time.perf_counter() - t0
    out = {"cycles": 520_000, "goal_seconds": 1.5, "warmup_seconds_including_compilation": warm,
           "cpus": os.cpu_count()}
    settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    updates = {"default": {}, "sequential": {"lanes": 1}, "fast": FAST}
    variants = {k: s.model_copy(update=u) for k, u in updates.items()}
    recs, times = _time_histories(model, variants, repeats)
    for name, upd in updates.items():
        rec = recs[name]
        rec["settings_changed"] = upd
        v = variants[name]
        reps = [float(wear_history(model, v.model_copy(update={"settle_cycles_initial": settle0 + 0.05 * (r + 1)}),
                                   400_000).max_wear_at(400_000) * MM) for r in range(replicates)]
        rec["max_wear_mm_400k_replicates"] = reps
        rec["scatter_rel_400k"] = float(np.std(reps, ddof=1) / np.mean(reps))
        out[name] = rec
    # same process, alternating: the lanes' wall-time ratio
    out["wall_ratio_default_to_sequential_median"] = statistics.median(
        [a / b for a, b in zip(times["default"], times["sequential"])])
    out["goal_met_by_default"] = out["default"]["wall_seconds_median"] <= 1.5
    return out


def bench_literal(n_measure: int = 6) -> dict:
    """Paper Section 3 Step 5: one simulated cycle per wear cycle, geometry updated after every cycle."""
    from jointwear.wear.history import JointMaterials, _growth, _update_geometry, cycle_wear

    cfg = config_for(-1)
    model = build_model(cfg)
    s = base_settings(cfg)
    geoms0 = list(model.initial_geometry())
    res = simulate(model, 1, geometry=geoms0, state0=None)  # settle from rest + compile (not timed)
    state = res.state_end
    n = s.n_grid
    wb, wj = np.zeros(n), np.zeros(n)
    mat = JointMaterials.from_trace(res.joints[0], geoms0[0])
    growth = 0.0
    t0, c0 = time.perf_counter(), time.process_time()
    for _ in range(n_measure):
        geoms = [_update_geometry(geoms0[0], s, wb, wj, growth)[0]] + geoms0[1:]
        res = simulate(model, 1, geometry=geoms, settle_cycles=0, state0=state)
        state = res.state_end
        cw = cycle_wear(res.joints[0], s, 1, mat, growth=growth)
        wb += cw.bearing
        wj += cw.journal
        growth = _growth(s, wb, wj)
    per = (time.perf_counter() - t0) / n_measure
    per_cpu = (time.process_time() - c0) / n_measure
    return {"cycles_measured": n_measure, "seconds_per_cycle": per, "extrapolated_seconds_520k": per * 520_000,
            "extrapolated_hours_520k": per * 520_000 / 3600.0, "cpu_seconds_per_cycle": per_cpu,
            "extrapolated_cpu_hours_520k": per_cpu * 520_000 / 3600.0}


def bench_convergence(replicates: int = 8) -> dict:
    """Max wear at 400k cycles: baseline vs each refinement, each as the mean of `replicates` runs.

    The clearance dynamics is chaotic: any change (block size, tolerance, even the grid through the uniform growth)
    gives another sample of the cycle-to-cycle scatter. Replicates differ only in the length of the initial settling
    (3.00, 3.05, 3.10 ... cycles: another start phase); the scatter of the replicates is reported with each mean.
    """
    cfg = config_for(-1)
    model = build_model(cfg)
    s = base_settings(cfg)
    rtol = s.rtol if s.rtol is not None else cfg.simulation.rtol
    atol = s.atol if s.atol is not None else cfg.simulation.atol
    settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    variants = {
        "baseline": {},
        "block_halved": {"block_cycles": max(1, s.block_cycles // 2)},
        "grid_halved": {"n_grid": 2 * s.n_grid},
        "tolerance_halved": {"rtol": rtol / 2, "atol": atol / 2},
        "one_lane": {"lanes": 1},  # the lanes' one-block lag of the geometry update (docs/wear.md "Lanes")
    }
    out = {}
    for name, upd in variants.items():
        runs = []
        for r in range(replicates):
            v = s.model_copy(update={**upd, "settle_cycles_initial": settle0 + 0.05 * r})
            runs.append(summary(wear_history(model, v, 400_000)))
        vals = np.array([x["max_wear_mm"] for x in runs])
        out[name] = {"settings_changed": upd, "max_wear_mm_runs": vals.tolist(), "mean_mm": float(vals.mean()),
                     "std_mm": float(vals.std(ddof=1)) if vals.size > 1 else 0.0,
                     "peak_angle_deg_runs": [x["max_wear_angle_deg"] for x in runs],
                     "wall_seconds_runs": [x["wall_seconds"] for x in runs], "n_blocks": runs[0]["n_blocks"]}
    b = out["baseline"]["mean_mm"]
    for name in variants:
        out[name]["rel_change_of_mean"] = out[name]["mean_mm"] / b - 1.0
        out[name]["rel_change_first_run"] = out[name]["max_wear_mm_runs"][0] / out["baseline"]["max_wear_mm_runs"][0] - 1
    out["run_to_run_scatter_rel"] = out["baseline"]["std_mm"] / b
    for name in variants:
        # standard error of the difference of two means of `replicates` runs each (relative to the baseline mean)
        se = math.sqrt(out[name]["std_mm"] ** 2 / replicates + out["baseline"]["std_mm"] ** 2 / replicates) / b
        out[name]["rel_change_standard_error"] = se
    out["acceptance"] = {"limit": 0.02, "pass": all(abs(out[k]["rel_change_of_mean"]) < 0.02
                                                   for k in ("block_halved", "grid_halved", "tolerance_halved"))}
    out["branch"] = -1
    out["baseline_settings"] = s.model_dump(mode="json")
    out["integrator_baseline"] = {"rtol": rtol, "atol": atol}
    return out


def bench_reproduction(profile_cycles: int = 20_000) -> dict:
    """Both branches, uniform mode to 400k cycles; profile mode only to `profile_cycles` (see docs/wear.md: the
    dynamics' profile contact needs 10^5-10^6 steps per cycle once the profile is non-uniform)."""
    out = {}
    for branch in (1, -1):
        cfg = config_for(branch)
        model = build_model(cfg)
        s = base_settings(cfg)
        out[f"branch{branch:+d}_uniform"] = summary(wear_history(model, s, 400_000))
        u20 = wear_history(model, s, profile_cycles)
        p20 = wear_history(model, s.model_copy(update={"geometry_mode": "profile"}), profile_cycles)
        out[f"branch{branch:+d}_uniform_{profile_cycles}"] = summary(u20, profile_cycles)
        out[f"branch{branch:+d}_profile_{profile_cycles}"] = summary(p20, profile_cycles)
    out["paper"] = {"max_wear_mm": 0.0249, "angle_deg": 110, "second_peak_mm": 0.0087, "second_peak_angle_deg": 310}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="timing,literal,convergence,reproduction")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    out_path = Path(a.out)
    data = json.loads(out_path.read_text()) if out_path.exists() else {}
    data["machine"] = {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
                       "load_average_at_start": os.getloadavg()}
    data["date_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    for sec in a.only.split(","):
        t0 = time.perf_counter()
        if sec == "timing":
            data["timing"] = bench_timing(a.repeats)
        elif sec == "literal":
            data["literal"] = bench_literal()
        elif sec == "convergence":
            data["convergence"] = bench_convergence()
        elif sec == "reproduction":
            data["reproduction"] = bench_reproduction()
        else:
            raise SystemExit(f"unknown section {sec!r}")
        print(f"{sec}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    if "timing" in data and "literal" in data:
        for name in ("default", "fast"):
            data["literal"][f"ratio_literal_to_{name}"] = (data["literal"]["extrapolated_seconds_520k"]
                                                          / data["timing"][name]["wall_seconds_median"])
            data["literal"][f"cpu_ratio_literal_to_{name}"] = (
                data["literal"]["cpu_seconds_per_cycle"] * 520_000 / data["timing"][name]["cpu_seconds_median"])
    out_path.parent.mkdir(parents=True, exist_ok=True)
    out_path.write_text(json.dumps(data, indent=1))
    print(json.dumps({k: data[k] for k in data if k in ("timing", "literal")}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
