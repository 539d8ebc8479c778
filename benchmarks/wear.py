"""Wear-stage benchmark and convergence study; writes benchmarks/results/wear.json.

    python benchmarks/wear.py                 # everything (timing, literal method, convergence, reproduction)
    python benchmarks/wear.py --only timing   # timing | literal | convergence | reproduction (comma separated)
    python benchmarks/wear.py --only profile_convergence   # profile mode's own study (~10 min; not in the default)

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
- profile_cost (only with --only; issue 14): uniform vs profile mode, --repeats model calls each in the same process:
  the pendulum rig (tests/wear/rigs/pendulum.toml) to 100k revolutions and the flapping wing to 520k cycles; cost per
  simulated cycle and its two factors (steps per cycle, cost per step), peak memory, the conformity indicator.
- profile_rig_convergence / profile_wing_convergence (only with --only): profile mode's max depth with each setting
  halved (grid spacing, smoothing, block, corner rounding), on the rig at 1e4/1e5 revolutions (beside the closed
  form of docs/verification.md) and on the flapping wing at 520k cycles.
- profile_rig_mirrored (only with --only, about a minute): the same on the rig mirrored (the load fixed on the pin,
  only the pin wearing), the pin's flat beside the same closed form.
- profile_wing_blocks (only with --only, a few minutes): profile mode on the flapping wing to 1.5M cycles, the
  profile preset's settings against the block halved, the deposit's sub-step halved and quartered, and the former
  16 sub-steps per block (two runs each): how they move the max depth over the profile preset's curve.
- profile_study (only with --only, about 5-10 minutes; issue 14 item 5): `jointwear run` end to end in fresh
  processes for the uniform preset (jin2025_flapping_wing) and the profile one (jin2025_flapping_wing_profile),
  one after the other in the same benchmark run: wall times, their ratio (goal <= 2), model calls, R(N), the life
  at the target, the nominal wear, the host CPU and the date.
- profile_deposit (only with --only, about a minute): the profile preset's model call, replicated: its max depth
  over the curve, its wall time, the deposit's own wall time, and how much its sub-step iteration amplifies rounding.
- profile_rig_rocking (only with --only, about a minute): what sets the integrator's steps on the pendulum rig: the
  eye's rocking on the pin (docs/verification.md, case 7) on each mode's geometry after 0, 1e4 and 1e5 revolutions.
- profile_rig_rounding (only with --only, about 30 s): profile mode on the rig to 1e5 revolutions with the admissible
  set's corners rounded 0.2 (the default), 0.4 and 0.8 c0: steps per simulated cycle and max depth (issue 14 item 1:
  is the rounding, which sets the pocket's rocking frequency, a lever on the cost?).
- profile_rig_step_drivers (only with --only, about 20 s): what the rig's steps do not depend on: the unworn bore and
  profile mode's pocket after 2e4 revolutions with the Young's moduli x4 and /4 (the contact's normal mode) and
  without friction (which sustains the rocking), and with the implicit Radau IIA integrator: steps and rejected
  steps per cycle.
- profile_rig_start_phase (only with --only, about 3 minutes): the pendulum rig, whose swing nothing damps, with
  mu_d 0.1 (the rig's) and 0.2: the max depth after 1e4 revolutions in each geometry mode from 8 start phases (the
  first block's settling lengthened by k/8 cycle, one lane): how much a single history's answer depends on the start.
- profile_rig_soft_liner (only with --only, about 2 minutes): the pendulum rig with a filled-PTFE bore (E 1 GPa,
  k/H 1e-15 m^2/N), whose contact patch is 36 deg each side, to 1e5 revolutions: uniform mode with flat and Hertz
  pressure and profile mode, beside the unworn patch's closed-form deposit with each pressure shape.
- profile_jammed_shift (only with --only, about a minute): the profile preset's rod length x 1.2 in both geometry modes
  until the step budget stops it: why the step size collapses there (docs/dynamics.md).
- profile_convergence (only with --only, long: about 10 minutes on 2 cores): profile mode (geometry_mode = "profile")
  at 400k cycles, baseline vs n_grid doubled, block halved, rtol/atol halved, profile_smoothing_deg 6 and 1.5; each
  the mean of a few replicates. Besides the max it reports the worn area (the Archard volume / width, smooth), the
  max of the profile smoothed at 5 deg, and the L2 distance of the mean profiles from the baseline's.
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
from jointwear.wear.angles import report_angle_deg
from jointwear.wear.kernels import smooth_periodic, worn_area
from jointwear.wear.results import find_peaks_periodic

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
    from jointwear.wear.cycle import JointMaterials, cycle_wear
    from jointwear.wear.history import growth_depth, update_geometry

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
        geoms = [update_geometry(geoms0[0], s, wb, wj, growth)[0]] + geoms0[1:]
        res = simulate(model, 1, geometry=geoms, settle_cycles=0, state0=state)
        state = res.state_end
        cw = cycle_wear(res.joints[0], s, 1, mat, growth=growth)
        wb += cw.bearing
        wj += cw.journal
        growth = growth_depth(s, wb, wj)
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
        first = out["baseline"]["max_wear_mm_runs"][0]
        out[name]["rel_change_first_run"] = out[name]["max_wear_mm_runs"][0] / first - 1
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


def _to_grid(profile: np.ndarray, n: int) -> np.ndarray:
    """Cell averages of a cell-average profile on a grid of n cells (cells centred at 2 pi k / n), for a profile on
    a grid of 2n cells: cell m of n covers half of fine cell 2m and a quarter of 2m - 1 and 2m + 1 (exact)."""
    p = np.asarray(profile, dtype=float)
    if p.size == n:
        return p
    if p.size != 2 * n:
        raise ValueError(f"cannot map a grid of {p.size} cells onto {n}")
    return 0.5 * p[0::2] + 0.25 * p[1::2] + 0.25 * np.roll(p[1::2], 1)


def _rel_change(v: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """Relative change of the mean of v against the mean of b, and its standard error (both relative to mean b)."""
    mb = float(b.mean())
    se = math.sqrt(v.var(ddof=1) / v.size + b.var(ddof=1) / b.size) / mb if min(v.size, b.size) > 1 else float("nan")
    return float(v.mean()) / mb - 1.0, se


def _smoothed_shape(section: dict, smooth_deg: float = 5.0) -> dict:
    """Shape of the mean bearing profiles at the scale of the crescent: every variant's stored 2-deg mean profile
    ("mean_bearing_profile_mm_2deg_body_frame") smoothed by a periodic Gaussian of `smooth_deg`; its max, the report
    angle of the max, the width (deg) over which it exceeds half its max, and its L2 distance from the baseline's
    smoothed mean profile relative to the latter's norm. Derived from the stored profiles only (no per-run noise
    floor: compare with the replicate scatter of smoothed_max_wear_mm)."""
    psi = math.radians(section["reported_angles_at_rod_mean_orientation_deg"])
    names = [k for k, v in section.items() if isinstance(v, dict) and "mean_bearing_profile_mm_2deg_body_frame" in v]
    sm = {k: smooth_periodic(np.array(section[k]["mean_bearing_profile_mm_2deg_body_frame"]), smooth_deg)
          for k in names}
    n = len(sm["baseline"])
    cell = 360.0 / section["baseline_settings"]["n_grid"]
    ang = report_angle_deg(np.radians(np.arange(n) * 360.0 / n + 0.5 * (360.0 / n - cell)), psi)
    b = sm["baseline"]
    return {k: {"smoothed_mean_profile_max_mm": float(v.max()), "angle_deg": float(ang[int(np.argmax(v))]),
                "width_above_half_max_deg": float(np.sum(v > 0.5 * v.max()) * 360.0 / n),
                "rel_l2_distance_from_baseline": float(np.linalg.norm(v - b) / np.linalg.norm(b))}
            for k, v in sm.items()} | {"sigma_deg": smooth_deg}


def bench_profile_convergence(replicates: int = 3, n_cycles: int = 400_000, smooth_deg: float = 5.0) -> dict:
    """Profile mode (geometry_mode = "profile") at 400k cycles: baseline vs each refinement / smoothing length.

    As `bench_convergence`, each variant is the mean of `replicates` runs that differ only in the length of the initial
    settling (+0.05 cycle each); the runs are interleaved (replicate outer, variant inner) so that a change of the
    machine's load hits every variant alike. Per run: max bearing wear and its angle, journal max, the worn area of
    bearing and journal (integral of the profile, = Archard volume / width: the smooth measure), the max of the
    profile smoothed by a Gaussian of `smooth_deg` (the depth of the crescent without its grid-scale waviness), wall
    time and integrator steps. Per variant: mean, std, relative change of the mean with its standard error, and the
    L2 distance between the variant's and the baseline's mean bearing profiles (body frame; the 1440-cell grid is
    averaged onto 720 cells exactly) relative to the baseline's L2 norm, next to the distance that the replicate
    scatter alone gives (noise floor: sqrt(sum_k var_v,k / n_v + var_b,k / n_b) / |mean_b|); the same distance and
    the max, angle and width of the mean profiles after smoothing by `smooth_deg` ("mean_profile_shape_smoothed").
    """
    cfg = config_for(-1)
    model = build_model(cfg)
    s = base_settings(cfg).model_copy(update={"geometry_mode": "profile"})
    rtol = s.rtol if s.rtol is not None else cfg.simulation.rtol
    atol = s.atol if s.atol is not None else cfg.simulation.atol
    settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    variants = {
        "baseline": {},
        "grid_halved": {"n_grid": 2 * s.n_grid},
        "block_halved": {"block_cycles": max(1, s.block_cycles // 2)},
        "tolerance_halved": {"rtol": rtol / 2, "atol": atol / 2},
        "smoothing_6deg": {"profile_smoothing_deg": 2.0 * s.profile_smoothing_deg},
        "smoothing_1.5deg": {"profile_smoothing_deg": 0.5 * s.profile_smoothing_deg},
    }
    n0 = s.n_grid
    load0 = os.getloadavg()
    t_start = time.perf_counter()
    wear_history(model, s, 2 * s.block_cycles)  # warm-up: compiles the dynamics and the wear kernels
    runs = {k: [] for k in variants}
    prof_b = {k: [] for k in variants}
    prof_j = {k: [] for k in variants}
    for r in range(replicates):
        for name, upd in variants.items():
            v = s.model_copy(update={**upd, "settle_cycles_initial": settle0 + 0.05 * r})
            res = wear_history(model, v, n_cycles)
            j = res.joints[0]
            rec = summary(res, n_cycles)
            rec["bearing_worn_area_mm2"] = worn_area(j.bearing_wear, j.bearing_radius) * MM**2
            rec["journal_worn_area_mm2"] = worn_area(j.journal_wear, j.journal_radius) * MM**2
            rec["smoothed_max_wear_mm"] = float(smooth_periodic(j.bearing_wear, smooth_deg).max() * MM)
            rec["n_steps"] = res.n_steps
            runs[name].append(rec)
            prof_b[name].append(_to_grid(j.bearing_wear, n0) * MM)
            prof_j[name].append(_to_grid(j.journal_wear, n0) * MM)
            print(f"profile_convergence {name} replicate {r}: max {rec['max_wear_mm']:.5f} mm at "
                  f"{rec['max_wear_angle_deg']:.1f} deg, area {rec['bearing_worn_area_mm2']:.4e} mm2, "
                  f"{rec['wall_seconds']:.1f} s, load {os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
    theta = 2.0 * math.pi * np.arange(n0) / n0
    psi = float(np.mean([math.radians(x["rod_mean_orientation_deg"]) for x in runs["baseline"]]))
    ang = report_angle_deg(theta, psi)
    metrics = ("max_wear_mm", "smoothed_max_wear_mm", "bearing_worn_area_mm2", "journal_max_wear_mm",
               "journal_worn_area_mm2")
    base = {m: np.array([x[m] for x in runs["baseline"]]) for m in metrics}
    Pb = {"bearing": np.array(prof_b["baseline"]), "journal": np.array(prof_j["baseline"])}
    out = {}
    for name, upd in variants.items():
        rs = runs[name]
        rec = {"settings_changed": upd}
        for m in metrics:
            vals = np.array([x[m] for x in rs])
            chg, se = _rel_change(vals, base[m])
            rec[m] = {"runs": vals.tolist(), "mean": float(vals.mean()),
                      "std": float(vals.std(ddof=1)) if vals.size > 1 else 0.0,
                      "scatter_rel": float(vals.std(ddof=1) / vals.mean()) if vals.size > 1 else 0.0,
                      "rel_change_of_mean": chg, "rel_change_standard_error": se}
        rec["max_wear_angle_deg_runs"] = [x["max_wear_angle_deg"] for x in rs]
        rec["peaks_runs"] = [x["peaks"][:3] for x in rs]
        for body, profs in (("bearing", prof_b), ("journal", prof_j)):
            P = np.array(profs[name])
            mean_v, mean_b = P.mean(axis=0), Pb[body].mean(axis=0)
            nb = float(np.linalg.norm(mean_b))
            floor2 = float(np.sum(P.var(axis=0, ddof=1) / P.shape[0]
                                  + Pb[body].var(axis=0, ddof=1) / Pb[body].shape[0]))
            d = float(np.linalg.norm(mean_v - mean_b))
            rec[f"{body}_profile_l2"] = {
                "rel_distance_of_means": d / nb,
                "rel_noise_floor": math.sqrt(floor2) / nb,
                # d^2 - floor^2 estimates the squared systematic distance (0 when the noise explains it all)
                "rel_systematic_estimate": math.sqrt(max(0.0, d * d - floor2)) / nb,
                "single_run_rel_scatter": float(np.mean([np.linalg.norm(p - mean_v) for p in P]) / nb),
            }
        mean_v = np.array(prof_b[name]).mean(axis=0)
        pk = find_peaks_periodic(mean_v, s.peak_prominence, s.peak_separation_deg)
        rec["mean_profile_peaks"] = [{"angle_deg": round(float(ang[k]), 2), "depth_mm": float(mean_v[k])}
                                     for k in pk[:4]]
        rec["mean_profile_max_mm"] = float(mean_v.max())
        rec["mean_profile_max_angle_deg"] = float(ang[int(np.argmax(mean_v))])
        rec["mean_profile_min_mm"] = float(mean_v.min())
        # the mean bearing profile (mm) averaged over groups of cells 2 deg long, body frame (first group: the
        # cells centred at 0 .. 2 deg - one cell), for plots
        if n0 % 180 == 0:
            rec["mean_bearing_profile_mm_2deg_body_frame"] = [round(float(x), 7)
                                                              for x in mean_v.reshape(180, -1).mean(axis=1)]
        rec["wall_seconds_runs"] = [x["wall_seconds"] for x in rs]
        rec["wall_seconds_mean"] = float(np.mean(rec["wall_seconds_runs"]))
        rec["n_steps_runs"] = [x["n_steps"] for x in rs]
        rec["n_blocks"] = rs[0]["n_blocks"]
        out[name] = rec
    out["replicates"] = replicates
    out["cycles"] = n_cycles
    out["smoothed_max_sigma_deg"] = smooth_deg
    out["branch"] = -1
    out["baseline_settings"] = s.model_dump(mode="json")
    out["integrator_baseline"] = {"rtol": rtol, "atol": atol}
    out["reported_angles_at_rod_mean_orientation_deg"] = math.degrees(psi)
    out["machine"] = {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
                      "load_average_at_start": load0, "load_average_at_end": os.getloadavg()}
    out["date_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    out["section_wall_seconds"] = time.perf_counter() - t_start
    out["mean_profile_shape_smoothed"] = _smoothed_shape(out, smooth_deg)
    return out


def bench_reproduction(profile_cycles: int = 20_000) -> dict:
    """Both branches, uniform mode to 400k cycles; profile mode to `profile_cycles` (a short check of the two modes
    side by side; profile mode's own convergence study is bench_profile_convergence)."""
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


RIG = Path(__file__).resolve().parents[1] / "tests" / "wear" / "rigs" / "pendulum.toml"


def _host_cpu() -> str:
    """The CPU numba compiles for (as benchmarks/dynamics.py records it)."""
    import llvmlite.binding as llvm

    return str(llvm.get_host_cpu_name())


def _peak_rss_gb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6  # Linux: kB


def _mode_run(model, settings, n_cycles: int, repeats: int) -> dict:
    """One model call per repeat; wall/CPU medians, integrator steps and the growth of the peak RSS."""
    walls, cpus, rss = [], [], []
    res = None
    for _ in range(repeats):
        r0 = _peak_rss_gb()
        t0, c0 = time.perf_counter(), time.process_time()
        res = wear_history(model, settings, n_cycles)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
        rss.append(_peak_rss_gb() - r0)
    j = res.joints[0]
    return {
        "wall_seconds_median": statistics.median(walls), "wall_seconds_all": walls,
        "cpu_seconds_median": statistics.median(cpus),
        "simulation_seconds": res.sim_seconds, "n_simulated_cycles": res.n_simulated_cycles, "n_steps": res.n_steps,
        "steps_per_simulated_cycle": res.n_steps / res.n_simulated_cycles,
        "simulation_seconds_per_step": res.sim_seconds / res.n_steps,
        # the deposit and bookkeeping between blocks (with lanes > 1 the dynamics overlaps them: not separable)
        "other_seconds_per_block": ((statistics.median(walls) - res.sim_seconds) / len(res.blocks)
                                    if settings.lanes == 1 else None),
        "wall_seconds_per_simulated_cycle": statistics.median(walls) / res.n_simulated_cycles,
        "peak_rss_growth_gb": max(rss), "peak_rss_gb": _peak_rss_gb(),
        "max_wear_mm": j.max_bearing_wear * MM, "conformity": j.conformity,
        "uniform_mode_valid": j.uniform_mode_valid,
        "history": {"cycles": j.history_cycles[:: max(1, len(j.history_cycles) // 20)].tolist(),
                    "max_wear_mm": (j.history_max_bearing[:: max(1, len(j.history_cycles) // 20)] * MM).tolist()},
    }


def _per_step_at_equal_geometry(model, both_sides: bool, repeats: int = 7) -> dict:
    """The dynamics' cost per step of the profiled contact against the round one at equal geometry: 3 cycles from the
    same settled state, once round and once with a profile of 1e-13 m (0.1 pm: the same motion; both sides, or the
    bearing alone as on the rig, whose journal does not wear), alternated, medians."""
    import dataclasses

    g0 = model.initial_geometry()
    n = g0[0].bearing_wear.size
    bump = 1e-13 * (1.0 + np.cos(2.0 * np.pi * np.arange(n) / n))
    worn = [dataclasses.replace(g, use_profile=True, bearing_wear=bump,
                                journal_wear=bump if both_sides else np.zeros(n)) for g in g0]
    state = simulate(model, 1, geometry=g0, settle_cycles=1).state_end
    walls = {"round": [], "profile": []}
    steps = {}
    for _ in range(repeats):
        for label, geom in (("round", g0), ("profile", worn)):
            t0 = time.perf_counter()
            r = simulate(model, 3, geometry=geom, settle_cycles=0, state0=state)
            walls[label].append(time.perf_counter() - t0)
            steps[label] = r.n_steps
    out = {label: {"steps": steps[label], "seconds_per_step_median": statistics.median(w) / steps[label]}
           for label, w in walls.items()}
    out["profiled_sides"] = "bearing and journal" if both_sides else "bearing"
    out["ratio_seconds_per_step_profile_to_round"] = (out["profile"]["seconds_per_step_median"]
                                                      / out["round"]["seconds_per_step_median"])
    return out


def bench_profile_cost(repeats: int = 1) -> dict:
    """Issue 14: profile mode against uniform mode, same process, same settings otherwise: the pendulum rig
    (tests/wear/rigs/pendulum.toml, blocks of 250, one lane) to 100,000 revolutions and the flapping wing
    (default settings) to 520,000 cycles. Cost per simulated cycle, integrator steps, peak memory; the ratio's two
    factors (steps per cycle, each mode on its own geometry, and the dynamics' cost per step)."""
    out = {}
    for name, path, n in (("pendulum_rig", str(RIG), 100_000), ("flapping_wing", None, 520_000)):
        cfg = load_config(path)
        model = build_model(cfg)
        s = base_settings(cfg)
        wear_history(model, s.model_copy(update={"geometry_mode": "profile"}), 2 * s.block_cycles)  # compile
        rec = {"cycles": n}
        for mode in ("uniform", "profile"):
            rec[mode] = _mode_run(model, s.model_copy(update={"geometry_mode": mode}), n, repeats)
        rec["ratio_wall_per_simulated_cycle_profile_to_uniform"] = (
            rec["profile"]["wall_seconds_per_simulated_cycle"] / rec["uniform"]["wall_seconds_per_simulated_cycle"])
        rec["ratio_wall_profile_to_uniform"] = (rec["profile"]["wall_seconds_median"]
                                                / rec["uniform"]["wall_seconds_median"])
        # the ratio's factors: integrator steps per cycle (each mode's own geometry) and the cost of a step
        for key in ("steps_per_simulated_cycle", "simulation_seconds_per_step"):
            rec[f"ratio_{key}_profile_to_uniform"] = rec["profile"][key] / rec["uniform"][key]
        rec["per_step_at_equal_geometry"] = _per_step_at_equal_geometry(model, both_sides=path is None)
        out[name] = rec
        print(name, {m: rec[m]["wall_seconds_median"] for m in ("uniform", "profile")}, file=sys.stderr)
    return out


def bench_profile_rig_convergence(n_values=(10_000, 100_000), mirrored: bool = False) -> dict:
    """Issue 14 item 3 on the pendulum rig: profile mode's max depth, baseline vs each setting halved (angular grid
    spacing, running-in smoothing, block size, the corner rounding of the admissible set), at 1e4 and 1e5
    revolutions, beside the closed-form conformal wear (docs/verification.md). The rig's load is steady, so one
    run per variant (no chaotic scatter to average). mirrored: the rig with the load fixed on the pin, whose flat is
    judged (closed_form.mirrored_config)."""
    import jointwear.wear.history as hist

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from verification.closed_form import Rig, conformal_wear, friction_circle, mirrored_config

    cfg = load_config(str(RIG))
    rig = Rig.from_config(cfg)
    if mirrored:
        cfg = mirrored_config(cfg)
    model = build_model(cfg)
    side, radius = ("journal_wear", rig.r_j) if mirrored else ("bearing_wear", rig.r_b)
    s = base_settings(cfg).model_copy(update={"geometry_mode": "profile"})
    out = {"settings": {"n_grid": s.n_grid, "profile_smoothing_deg": s.profile_smoothing_deg,
                        "block_cycles": s.block_cycles, "profile_rounding": hist.PROFILE_ROUNDING}}
    for n in n_values:
        cf = conformal_wear(rig, friction_circle(rig)[1], n)
        rec = {"closed_form": {"depth_mm": cf["depth"] * MM, "arc_deg": math.degrees(cf["arc"]),
                               "area_mm2": cf["area"] * 1e6}}

        def record(res):
            h = getattr(res.joints[0], side)
            return {"max_depth_mm": float(h.max() * MM), "worn_area_mm2": worn_area(h, radius) * 1e6,
                    "arc_deg_above_1pct": np.count_nonzero(h > 0.01 * h.max()) * 360.0 / h.size,
                    "wall_seconds": res.wall_seconds}

        rec.update(halved_settings_runs(model, s, n, record))
        rec["baseline"]["error_vs_closed_form"] = rec["baseline"]["max_depth_mm"] / rec["closed_form"]["depth_mm"] - 1
        rec["all_changes_below_2pct"] = all(abs(v["change_of_max_depth"]) < 0.02 for k, v in rec.items()
                                            if k in HALVED and k != "baseline")
        out[str(n)] = rec
        print(n, {k: rec[k].get("change_of_max_depth") for k in HALVED}, file=sys.stderr)
    return out


HALVED = ("baseline", "grid_halved", "smoothing_halved", "block_halved", "rounding_halved", "substep_halved")


def halved_settings_runs(model, s, n_cycles: int, record) -> dict:
    """Profile mode's convergence study: the wear history at settings ``s`` and with each of the angular grid
    spacing, the running-in smoothing, the block size, the admissible set's corner rounding and the deposit's
    sub-step (both its bounds: LEVELLING_STEP and profile_substep_cycles) halved;
    ``record(result) -> dict`` of each run, with the change of the max depth against the baseline."""
    import jointwear.wear.history as hist

    updates = {"baseline": {}, "grid_halved": {"n_grid": 2 * s.n_grid},
               "smoothing_halved": {"profile_smoothing_deg": s.profile_smoothing_deg / 2},
               "block_halved": {"block_cycles": s.block_cycles // 2}, "rounding_halved": {},
               "substep_halved": {"profile_substep_cycles": s.profile_substep_cycles / 2}}
    rounding0 = hist.PROFILE_ROUNDING
    step0 = hist.LEVELLING_STEP
    out = {}
    for name in HALVED:
        try:
            if name == "rounding_halved":
                hist.PROFILE_ROUNDING = rounding0 / 2
            if name == "substep_halved":
                hist.LEVELLING_STEP = step0 / 2
            out[name] = record(wear_history(model, s.model_copy(update=updates[name]), n_cycles))
        finally:
            hist.PROFILE_ROUNDING = rounding0
            hist.LEVELLING_STEP = step0
    for name in HALVED[1:]:
        out[name]["change_of_max_depth"] = out[name]["max_depth_mm"] / out["baseline"]["max_depth_mm"] - 1
    return out


def bench_profile_wing_convergence(n_cycles: int = 520_000) -> dict:
    """Issue 14 item 3 on the flapping wing: profile mode's max depth at 520k cycles, baseline vs each setting
    halved, one run each (single runs scatter by a few % on this chaotic mechanism: see "Sampling scatter")."""
    cfg = config_for(-1)
    model = build_model(cfg)
    s = base_settings(cfg).model_copy(update={"geometry_mode": "profile"})
    out = {"cycles": n_cycles}

    def record(res):
        h = res.joints[0].bearing_wear
        return {"max_depth_mm": float(h.max() * MM), "smoothed_max_mm": float(smooth_periodic(h, 5.0).max() * MM),
                "worn_area_mm2": worn_area(h, res.joints[0].bearing_radius) * 1e6, "wall_seconds": res.wall_seconds}

    out.update(halved_settings_runs(model, s, n_cycles, record))
    return out


def bench_profile_wing_blocks(levels=(520_000, 900_000, 1_000_000, 1_300_000, 1_500_000), replicates: int = 2) -> dict:
    """Profile mode on the flapping wing to 1.5M cycles (the range of preset jin2025_flapping_wing_profile),
    `replicates` runs each (start phase +0.05 cycle): the preset's settings (20k blocks, sub-steps of at most
    `profile_substep_cycles`), the block halved, the sub-step halved and quartered, the default sub-step, the former
    cap of 16 sub-steps per block (1,250-cycle sub-steps) and a reference with a sixteenth of the sub-step (one
    run): the max depth at
    `levels` and the wall time; how the block and the deposit's sub-step move the life."""
    cfg = load_config("jin2025_flapping_wing_profile")
    model = build_model(cfg)
    s = base_settings(cfg)
    settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    sub = s.profile_substep_cycles
    variants = {
        "baseline": {},
        "block_halved": {"block_cycles": s.block_cycles // 2},
        "substep_halved": {"profile_substep_cycles": sub / 2},
        "substep_quartered": {"profile_substep_cycles": sub / 4},
        "default_substep": {"profile_substep_cycles": WearSettings().profile_substep_cycles},
        "former_16_per_block": {"profile_substep_cycles": s.block_cycles / 16},
        "substep_reference": {"profile_substep_cycles": sub / 16},  # resolved: an eighth changes it by < 0.3 %
    }
    out = {"levels": list(levels), "block_cycles": s.block_cycles, "profile_substep_cycles": sub}
    for name, upd in variants.items():
        runs, walls = [], []
        for r in range(1 if name == "substep_reference" else replicates):
            v = s.model_copy(update={**upd, "settle_cycles_initial": settle0 + 0.05 * r})
            res = wear_history(model, v, max(levels))
            runs.append([float(res.max_wear_at(n) * MM) for n in levels])
            walls.append(res.wall_seconds)
        mean = np.mean(runs, axis=0)
        out[name] = {"settings": upd, "max_depth_mm_runs": runs, "max_depth_mm_mean": mean.tolist(),
                     "wall_seconds_runs": walls}
        print(name, mean.round(5).tolist(), file=sys.stderr)
    base = np.array(out["baseline"]["max_depth_mm_mean"])
    for name in variants:
        out[name]["change_vs_baseline"] = (np.array(out[name]["max_depth_mm_mean"]) / base - 1).tolist()
    out["halved_changes_below_2pct"] = all(abs(x) < 0.02 for name in ("block_halved", "substep_halved")
                                           for x in out[name]["change_vs_baseline"])
    return out


def bench_profile_rig_rocking(n_values=(0, 10_000, 100_000)) -> dict:
    """Issue 14 item 1: what sets the integrator's steps on the pendulum rig. The pendulum's eye rocks on the pin along
    the bore at omega^2 = N / (e m_eff) (docs/verification.md, case 7; e the radius of the path of its centre),
    and the step follows that frequency. Each mode's geometry after n revolutions; 3 cycles after 3 settling
    cycles on it from rest (and the history's last blocks' steps): steps, rejections, the rocking frequency (the
    spectral peak of the eye's angle on the pin), the closed form with e = the mean eccentricity (a round bore:
    exact for uniform mode), and with e = the corner rounding of the admissible set (profile mode's pocket, an
    estimate: the eye's centre rides that arc). Then the unworn rig without friction (the rocking is free, not
    self-excited)."""
    from jointwear.config import updated
    from jointwear.wear.history import PROFILE_ROUNDING, update_geometry

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from verification.closed_form import Rig, rocking_hz, spectral_peak

    cfg = load_config(str(RIG))
    rig = Rig.from_config(cfg)
    s = base_settings(cfg)  # the wear runs' tolerances, so that the steps are the history's
    m_eff = rig.mass_at_pin

    def rocking(model, geometry) -> dict:
        res = simulate(model, 3, geometry=geometry, settle_cycles=3, rtol=s.rtol, atol=s.atol)
        tr = res.joints[0]
        e = tr.eccentricity_global
        f = spectral_peak(tr.t, np.unwrap(np.arctan2(e[:, 1], e[:, 0])), above=10.0)
        n_force = float(np.sum(tr.dt_weight * tr.force_normal) / np.sum(tr.dt_weight))
        e_mean = float(np.mean(np.hypot(e[:, 0], e[:, 1])))
        steps = res.n_steps / (res.n_cycles + res.settle_cycles)
        return {"steps_per_cycle": steps, "rejected_per_cycle": res.n_rejected / (res.n_cycles + res.settle_cycles),
                "rocking_hz": f, "steps_per_rocking_period": steps / f, "mean_normal_force_n": n_force,
                "mean_eccentricity_um": e_mean * 1e6, "normal_force_std_n": float(np.std(tr.force_normal)),
                "closed_form_round_bore_hz": rocking_hz(n_force, e_mean, m_eff)}

    model = build_model(cfg)
    g0 = model.initial_geometry()
    out = {"m_eff_kg": m_eff, "profile_rounding_um": PROFILE_ROUNDING * rig.clearance * 1e6}
    for mode in ("uniform", "profile"):
        sm = s.model_copy(update={"geometry_mode": mode})
        rows = {}
        for n in n_values:
            geometry = g0
            if n > 0:
                hist = wear_history(model, sm, n)
                j = hist.joints[0]
                geometry = [update_geometry(g0[0], sm, j.bearing_wear, j.journal_wear,
                                            j.history_clearance_growth[-1])[0]]
            rows[str(n)] = rec = rocking(model, geometry)
            if n > 0:  # the history's own blocks there: they continue from the previous block's state
                per_block = sm.settle_cycles + sm.record_cycles
                rec["history_steps_per_cycle_last_5_blocks"] = statistics.median(
                    b.n_steps / per_block for b in hist.blocks[-5:])
            if mode == "profile" and n > 0:
                rec["closed_form_pocket_corner_hz"] = rocking_hz(rec["mean_normal_force_n"],
                                                                 PROFILE_ROUNDING * rig.clearance, m_eff)
            print(mode, n, {k: round(v, 1) for k, v in rec.items()}, file=sys.stderr)
        out[mode] = rows
    free = build_model(updated(cfg, {"clearance_joints.0.friction.law": "none"}))
    out["unworn_without_friction"] = rocking(free, free.initial_geometry())
    return out


def bench_profile_rig_rounding(roundings=(0.2, 0.4, 0.8), n_cycles: int = 100_000) -> dict:
    """Profile mode on the rig with the corner rounding of the admissible set (fraction of c0) varied: wall time,
    steps per simulated cycle and max depth at ``n_cycles`` revolutions, one process."""
    import jointwear.wear.history as history

    cfg = load_config(str(RIG))
    model = build_model(cfg)
    s = base_settings(cfg).model_copy(update={"geometry_mode": "profile"})
    wear_history(model, s, 2 * s.block_cycles)  # compile
    default, out = history.PROFILE_ROUNDING, {}
    try:
        for rho in roundings:
            history.PROFILE_ROUNDING = rho
            t0 = time.perf_counter()
            res = wear_history(model, s, n_cycles)
            out[str(rho)] = {"wall_seconds": time.perf_counter() - t0,
                             "steps_per_simulated_cycle": sum(b.n_steps for b in res.blocks) / res.n_simulated_cycles,
                             "max_depth_um": float(res.joints[0].bearing_wear.max() * 1e6)}
            print(rho, out[str(rho)], file=sys.stderr)
    finally:
        history.PROFILE_ROUNDING = default
    return {"cycles": n_cycles, "roundings_of_c0": out}


def bench_profile_rig_step_drivers(n_cycles: int = 20_000) -> dict:
    """What sets the rig's steps, by elimination: 3 cycles after 3 settling cycles on the unworn bore and on profile
    mode's geometry after ``n_cycles`` revolutions, with the Young's moduli x4 and /4 (the contact's normal mode
    1.6x faster or slower; the rocking unchanged), without friction (the rocking no longer sustained) and with the
    implicit Radau IIA integrator. Steps and rejected steps per cycle, wall time per cycle, the mean penetration and
    the normal force's standard deviation."""
    from jointwear.config import updated
    from jointwear.wear.history import update_geometry

    cfg = load_config(str(RIG))
    s = base_settings(cfg).model_copy(update={"geometry_mode": "profile"})
    model = build_model(cfg)
    g0 = model.initial_geometry()
    j = wear_history(model, s, n_cycles).joints[0]
    worn = [update_geometry(g0[0], s, j.bearing_wear, j.journal_wear, j.history_clearance_growth[-1])[0]]
    moduli = ("clearance_joints.0.bearing_material.youngs_modulus_GPa",
              "clearance_joints.0.journal_material.youngs_modulus_GPa")
    variants = {"as_is": {}, "youngs_moduli_x4": dict.fromkeys(moduli, 4 * 207.0),
                "youngs_moduli_div4": dict.fromkeys(moduli, 207.0 / 4), "no_friction": {
                    "clearance_joints.0.friction.law": "none"}, "radau5": {"simulation.method": "radau5"}}
    out = {"cycles_worn": n_cycles}
    for name, changes in variants.items():
        m = build_model(updated(cfg, changes)) if changes else model
        for label, geometry in (("unworn", None), ("profile_worn", worn)):
            t0 = time.perf_counter()
            r = simulate(m, 3, geometry=geometry, settle_cycles=3, rtol=s.rtol, atol=s.atol)
            wall = time.perf_counter() - t0
            tr = r.joints[0]
            per = r.n_cycles + r.settle_cycles
            out.setdefault(name, {})[label] = {
                "steps_per_cycle": r.n_steps / per, "rejected_per_cycle": r.n_rejected / per,
                "wall_seconds_per_cycle": wall / per,
                "mean_penetration_um": float(np.mean(tr.penetration) * 1e6),
                "normal_force_std_n": float(np.std(tr.force_normal))}
            print(name, label, {k: round(v, 2) for k, v in out[name][label].items()}, file=sys.stderr)
    return out


def bench_profile_rig_start_phase(mus=(0.1, 0.2), n_cycles: int = 10_000, phases: int = 8) -> dict:
    """The pendulum rig's free swing (docs/verification.md) is undamped in the model, so where a history starts may
    set where its contact wears: the max depth after ``n_cycles`` revolutions from ``phases`` start phases, each
    geometry mode, for each mu_d; the scatter (std / mean) and the range."""
    out = {"cycles": n_cycles, "phases": phases}
    for mu in mus:
        data = load_config(str(RIG)).model_dump(mode="python")
        data["clearance_joints"][0]["friction"]["mu_d"] = mu
        data["clearance_joints"][0]["friction"]["mu_s"] = max(mu, 0.15)
        cfg = type(load_config(str(RIG))).model_validate(data)
        model = build_model(cfg)
        rec = {}
        for mode in ("uniform", "profile"):
            s0 = base_settings(cfg)
            depths = []
            for k in range(phases):
                s = s0.model_copy(update={"geometry_mode": mode, "lanes": 1,
                                          "settle_cycles_initial": cfg.simulation.settle_cycles + 2 + k / phases})
                depths.append(wear_history(model, s, n_cycles).joints[0].max_bearing_wear * MM)
            d = np.array(depths)
            rec[mode] = {"max_depth_mm": depths, "mean_mm": float(d.mean()), "scatter": float(d.std(ddof=1) / d.mean()),
                         "min_mm": float(d.min()), "max_mm": float(d.max())}
            print(mu, mode, rec[mode]["scatter"], file=sys.stderr)
        out[f"mu_d_{mu:g}"] = rec
    return out


SOFT_LINER = {"name": "filled PTFE", "youngs_modulus": 1.0e9, "poissons_ratio": 0.46, "hardness": 35.0e6,
              "wear_coefficient": 3.5e-8}  # k/H = 1e-15 m^2/N


def bench_profile_rig_soft_liner(levels=(1_000, 10_000, 100_000)) -> dict:
    """Where uniform mode is fair by its indicator, the two modes still lay the patch's deposit with different
    pressure shapes (uniform mode: `wear.pressure`, flat by default; profile mode: the elastic foundation's parabola). A soft
    liner's wide patch shows it: the rig with a PTFE bore, max depth at ``levels`` revolutions in each mode, beside
    the unworn patch's closed-form deposit (docs/verification.md, case 2) for flat, Hertz and parabolic pressure."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from verification.closed_form import Rig, deposit_per_rev, friction_circle, half_width

    data = load_config(str(RIG)).model_dump(mode="python")
    data["clearance_joints"][0]["bearing_material"] = dict(SOFT_LINER)
    cfg = type(load_config(str(RIG))).model_validate(data)
    rig = Rig.from_config(cfg)
    force = friction_circle(rig)[1]
    b = half_width(force, rig.r_b, rig.r_j, rig.hsum, rig.width)
    flat = deposit_per_rev(rig.kH_b, force, rig.slide_per_rev, b, rig.width, "uniform")
    per_rev = {"flat": flat, "hertz": deposit_per_rev(rig.kH_b, force, rig.slide_per_rev, b, rig.width, "hertz"),
               "parabola": 1.5 * flat}  # a parabola's peak is 3/2 of its mean
    out = {"contact_half_angle_deg": math.degrees(b / rig.r_b), "normal_force_N": force,
           "closed_form_unworn_per_revolution_nm": {k: v * 1e9 for k, v in per_rev.items()}}
    model = build_model(cfg)
    s0 = base_settings(cfg)
    for name, update in (("uniform_flat", {"geometry_mode": "uniform", "pressure": "uniform"}),
                         ("uniform_hertz", {"geometry_mode": "uniform", "pressure": "hertz"}),
                         ("profile", {"geometry_mode": "profile"})):
        res = wear_history(model, s0.model_copy(update=update), max(levels))
        out[name] = {"max_depth_um": {str(n): float(res.max_wear_at(n) * 1e6) for n in levels},
                     "conformity": res.conformity, "uniform_mode_valid": res.uniform_mode_valid,
                     "wall_seconds": res.wall_seconds}
        print(name, out[name]["max_depth_um"], file=sys.stderr)
    return out


def bench_profile_jammed_shift(factor: float = 1.2, n_cycles: int = 400_000) -> dict:
    """The profile preset's most extreme sensitivity shift, rod length x 1.2 (hundreds of sigma), in each geometry
    mode until the step budget stops its history: the linkage's Grashof slack, the steps of every call, the stop's
    message, and for the last call that completed, where along the crank cycle its steps went and the joint's force
    and slip speed there (docs/dynamics.md, 'When the step size collapses')."""
    from jointwear.mechanism import SimulationError

    cfg = load_config("jin2025_flapping_wing_profile")
    m = cfg.mechanism
    mech = m.model_copy(update={"rod": m.rod.model_copy(update={"length": m.rod.length * factor})})
    cfg = cfg.model_copy(update={"mechanism": mech})
    ground = math.hypot(mech.rocker_pivot[0] - mech.crank_pivot[0], mech.rocker_pivot[1] - mech.crank_pivot[1])
    lengths = sorted([mech.crank.length, mech.rod.length, mech.rocker.length, ground])
    out = {"rod_factor": factor, "grashof_slack_mm": (lengths[1] + lengths[2] - lengths[0] - lengths[3]) * MM,
           "max_steps": cfg.simulation.max_steps}
    model = build_model(cfg)
    for mode in ("profile", "uniform"):
        s = cfg.wear.model_copy(update={"lanes": 1, "geometry_mode": mode})
        calls, last = [], {}

        def spy(model, n, geometry=None, **kw):
            g = geometry[0]
            r = simulate(model, n, geometry=geometry, **kw)
            calls.append({"steps": r.n_steps, "rejected": r.n_rejected, "clearance_um": g.clearance * 1e6,
                          "bearing_profile_max_um": float(g.bearing_wear.max()) * 1e6 if g.use_profile else 0.0})
            last["res"] = r
            return r

        rec = {"calls": calls}
        try:
            wear_history(model, s, n_cycles, simulate=spy)
            rec["stopped"] = None
        except SimulationError as exc:
            rec["stopped"] = str(exc)
        rec["cycles_before_the_stop"] = (len(calls)) * s.block_cycles if rec["stopped"] else n_cycles
        r = last["res"]
        j = r.joints[0]
        deg = np.degrees(r.crank_angle)
        steps, edges = np.histogram(deg, bins=36, range=(0.0, 360.0))
        k = int(np.argmax(steps))
        window = (deg >= edges[max(k - 2, 0)]) & (deg < edges[min(k + 3, 36)])
        rec["last_completed_call"] = {
            "steps_per_10_deg": steps.tolist(),
            "crank_deg_of_most_steps": [float(edges[max(k - 2, 0)]), float(edges[min(k + 3, 36)])],
            "share_of_steps_there": float(window.mean()),
            "median_step_there_s": float(np.median(np.diff(r.t)[window[1:]])),
            "median_normal_force_there_N": float(np.median(j.force_normal[window])),
            "median_slip_speed_there_m_s": float(np.median(np.abs(j.slip_speed[window]))),
            "median_normal_force_elsewhere_N": float(np.median(j.force_normal[~window])),
        }
        out[mode] = rec
    return out


def bench_profile_deposit(levels=(700_000, 900_000, 1_100_000, 1_300_000), replicates: int = 8,
                          blocks=(1, 10, 40), perturbations: int = 3) -> dict:
    """Issue 14 items 1 and 5: the profile preset's model call (its nominal history to 1.3M cycles) and its
    deposit. `replicates` histories (start phase +0.05 cycle each): the max depth at `levels`, the wall and
    simulation seconds of each; the wall of laying the deposit alone (history.lay_distributed over one history's
    blocks, both sides, re-run on their recorded loads); and how the deposit's sub-step iteration amplifies
    rounding: bearing blocks `blocks`
    laid again from their input profile perturbed by 1e-13 (relative, `perturbations` draws), the change of the
    block's increment (largest cell, relative to the increment's max) and of its max."""
    import jointwear.wear.history as history

    cfg = load_config("jin2025_flapping_wing_profile")
    model = build_model(cfg)
    s = base_settings(cfg)
    settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    n_cycles = max(levels)
    wear_history(model, s, 40_000)  # compiles
    runs = []
    for r in range(replicates):
        res = wear_history(model, s.model_copy(update={"settle_cycles_initial": settle0 + 0.05 * r}), n_cycles)
        runs.append({"max_depth_mm": [float(res.max_wear_at(n) * MM) for n in levels],
                     "wall_seconds": res.wall_seconds, "simulation_seconds": res.sim_seconds})
        print("replicate", r, round(res.wall_seconds, 2), file=sys.stderr)
    depth = np.array([x["max_depth_mm"] for x in runs])
    out = {"levels": list(levels), "replicates": runs, "max_depth_mm_mean": depth.mean(axis=0).tolist(),
           "max_depth_mm_std": depth.std(axis=0, ddof=1).tolist(),
           "wall_seconds_median": statistics.median(x["wall_seconds"] for x in runs),
           "simulation_seconds_median": statistics.median(x["simulation_seconds"] for x in runs)}
    captured = []
    lay = history.lay_distributed

    def spy(share, rate, volume, levelling_rate, w, dn, settings):
        captured.append((share, rate, volume, levelling_rate, w.copy(), dn))
        return lay(share, rate, volume, levelling_rate, w, dn, settings)

    history.lay_distributed = spy
    try:
        wear_history(model, s.model_copy(update={"lanes": 1}), n_cycles)
    finally:
        history.lay_distributed = lay
    t0 = time.perf_counter()
    for share, rate, volume, g, w, dn in captured:
        lay(share, rate, volume, g, w, dn, s)
    out["deposit_wall_seconds_one_history"] = time.perf_counter() - t0
    bearing = [c for c in captured if c[0].r_b0 == max(x[0].r_b0 for x in captured)]  # the journal's is smaller
    out["deposit_blocks"] = len(bearing)
    out["deposit_calls"] = len(captured)  # both sides' (the journal's too when it is shared)
    rng = np.random.default_rng(0)
    cond = []
    for i in blocks:
        share, rate, volume, g, wb, dn = bearing[i]
        inc = lay(share, rate, volume, g, wb, dn, s)[0] - wb
        for _ in range(perturbations):
            pert = wb * (1.0 + 1e-13 * rng.standard_normal(wb.shape))
            inc_p = lay(share, rate, volume, g, pert, dn, s)[0] - pert
            cond.append({"block": i, "increment_change": float(np.abs(inc_p - inc).max() / inc.max()),
                         "increment_max_change": float(inc_p.max() / inc.max() - 1.0)})
    out["rounding_amplification"] = cond
    return out


def bench_profile_study(repeats: int = 1) -> dict:
    """Issue 14 item 5: the whole study (`jointwear run`, fresh process, benchmarks/study.py's runner) with the
    uniform preset and with the profile preset, alternating when repeated; the ratio of the median wall times."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import tempfile

    from study import one_run

    from jointwear.study.io import provenance

    names = {"uniform": "jin2025_flapping_wing", "profile": "jin2025_flapping_wing_profile"}
    runs = {k: [] for k in names}
    for _ in range(repeats):
        for mode, preset in names.items():
            with tempfile.TemporaryDirectory() as tmp:
                runs[mode].append(one_run(preset, Path(tmp), None))
            print(mode, f"{runs[mode][-1]['wall_seconds']:.1f} s", file=sys.stderr)
    out = {"presets": names, "provenance": provenance()}  # versions and the host CPU numba compiles for
    for mode in names:
        r = runs[mode]
        out[mode] = {"median_wall_seconds": statistics.median(x["wall_seconds"] for x in r), "runs": r}
    out["ratio_wall_profile_to_uniform"] = out["profile"]["median_wall_seconds"] / out["uniform"]["median_wall_seconds"]
    out["goal_ratio"] = 2.0
    out["goal_met"] = out["ratio_wall_profile_to_uniform"] <= 2.0
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="timing,literal,convergence,reproduction")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    out_path = Path(a.out)
    data = json.loads(out_path.read_text()) if out_path.exists() else {}
    sections = a.only.split(",")
    if any(not sec.startswith("profile_") for sec in sections):  # the profile sections record their own machine/date
        data["machine"] = {"python": sys.version.split()[0], "platform": platform.platform(),
                           "cpus": os.cpu_count(), "load_average_at_start": os.getloadavg()}
        data["date_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    for sec in sections:
        t0 = time.perf_counter()
        if sec == "timing":
            data["timing"] = bench_timing(a.repeats)
        elif sec == "literal":
            data["literal"] = bench_literal()
        elif sec == "convergence":
            data["convergence"] = bench_convergence()
        elif sec == "reproduction":
            data["reproduction"] = bench_reproduction()
        elif sec == "profile_convergence":
            data["profile_convergence"] = bench_profile_convergence()
        elif sec == "profile_cost":
            data["profile_cost"] = bench_profile_cost(a.repeats)
        elif sec == "profile_rig_convergence":
            data["profile_rig_convergence"] = bench_profile_rig_convergence()
        elif sec == "profile_rig_mirrored":
            data["profile_rig_mirrored"] = bench_profile_rig_convergence(mirrored=True)
        elif sec == "profile_wing_blocks":
            data["profile_wing_blocks"] = bench_profile_wing_blocks()
        elif sec == "profile_deposit":
            data["profile_deposit"] = bench_profile_deposit()
        elif sec == "profile_study":
            data["profile_study"] = bench_profile_study()
        elif sec == "profile_rig_rocking":
            data["profile_rig_rocking"] = bench_profile_rig_rocking()
        elif sec == "profile_rig_rounding":
            data["profile_rig_rounding"] = bench_profile_rig_rounding()
        elif sec == "profile_rig_step_drivers":
            data["profile_rig_step_drivers"] = bench_profile_rig_step_drivers()
        elif sec == "profile_rig_start_phase":
            data["profile_rig_start_phase"] = bench_profile_rig_start_phase()
        elif sec == "profile_rig_soft_liner":
            data["profile_rig_soft_liner"] = bench_profile_rig_soft_liner()
        elif sec == "profile_jammed_shift":
            data["profile_jammed_shift"] = bench_profile_jammed_shift()
        elif sec == "profile_wing_convergence":
            data["profile_wing_convergence"] = bench_profile_wing_convergence()
        else:
            raise SystemExit(f"unknown section {sec!r}")
        if sec.startswith("profile_") and sec != "profile_convergence":
            data[sec]["machine"] = {"python": sys.version.split()[0], "platform": platform.platform(),
                                    "cpus": os.cpu_count(), "llvm_host_cpu": _host_cpu(),
                                    "load_average_at_start": os.getloadavg()}
            data[sec]["date_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        print(f"{sec}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
        out_path.parent.mkdir(parents=True, exist_ok=True)
        out_path.write_text(json.dumps(data, indent=1))  # after every section: a later failure loses nothing
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
