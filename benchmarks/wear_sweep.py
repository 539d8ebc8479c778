"""Where a recorded step's wear is laid: at its one contact angle, or along the arc the contact sweeps over its time
(results/wear_sweep.json).

    python benchmarks/wear_sweep.py [--replicates 8]
    python benchmarks/wear_sweep.py --only profile_mode   # that part alone (about 2 minutes), the others kept

The flapping-wing preset (uniform mode, the wear stage's rtol 5e-7 / atol 5e-10 m unless stated). Three parts:

- per_cycle: one and two cycles recorded after the preset's settling, at rtol 5e-7, 1e-7, 1e-8, 1e-9 (atol = rtol x
  1e-3 m) and at 5e-7 with a tenth of the default largest step: integrator steps, recorded steps, contact impacts,
  peak contact force, the Archard volume per cycle, and the peak of the cycle's bearing and journal depth profiles
  with each step's wear laid at its recorded angle (the earlier deposit) and along its swept arc (now);
- thinned: the rtol 1e-9 record with every k-th step kept (trapezoid weights of the kept steps), both deposits;
- history: the nominal wear history to 400k cycles, `replicates` runs differing only in the initial settling
  (+0.05 cycle each, as benchmarks/wear.py), each block's record laid both ways (the swept one drives the geometry):
  the max bearing and journal depth at 400k cycles of each, on the same trajectory.

A fourth, profile_mode, in profile mode (distributed deposit) on the profile preset (jin2025_flapping_wing_profile)
and on the pendulum rig (tests/wear/rigs/pendulum.toml): one block's deposit from an unworn and a worn state (the
nominal history to 500k cycles on the wing, 1e4 revolutions on the rig), its record simulated from rest at each
rtol and the 1e-9 record thinned to every k-th step (k = 1, 2, 4, 8); each record's loads gathered by the direction
of the contact normal both ways (kernels.gather_directions): to the cell nearest each step's normal (the earlier
gathering) and along the arc the normal sweeps (now). Per row: the peak of the block's bearing and journal deposit
(lay_distributed: sub-steps, running-in smoothing), the block's Archard volumes, the unsmoothed rate's peak, and
(k/H)-free F ds per cycle (the record's own quadrature). And the profile preset's nominal history to its 1M cycles
gathered each way, `replicates` runs differing only in the initial settling (+0.05 cycle each; the profile feeds
back into the dynamics, so the two ways run their own trajectories): the max bearing and journal depth and the
bearing's volume at 1M cycles.

docs/wear.md ("Along the arc a step sweeps") quotes it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).parent / "results" / "wear_sweep.json"
PRESET = "jin2025_flapping_wing"
RTOLS = (5e-7, 1e-7, 1e-8, 1e-9)
UM_PER_MCYCLE = 1e12  # m / cycle -> um per million cycles


def deposit(trace, settings, mat, growth: float, share):
    """Uniform mode's deposit of a record (wear.cycle.cycle_wear): (bearing, journal) depth over the record and the
    bearing's Archard volume, each step laid at its angle (share None) or along its swept arc (share:
    wear.cycle.sweep_shares)."""
    from jointwear.wear.kernels import accumulate_wear

    F = np.where(np.asarray(trace.in_contact, dtype=bool), np.asarray(trace.force_normal, dtype=float), 0.0)
    n = settings.n_grid
    wb, wj, diag = np.zeros(n), np.zeros(n), np.zeros((4, n))
    vb, _, _, _ = accumulate_wear(
        np.ascontiguousarray(trace.theta_bearing, dtype=float), np.ascontiguousarray(trace.theta_journal, dtype=float),
        F, np.ascontiguousarray(trace.slip_speed, dtype=float), np.ascontiguousarray(trace.dt_weight, dtype=float),
        np.full(F.shape, mat.r_b0 + 0.5 * growth), np.full(F.shape, mat.r_j0 - 0.5 * growth), mat.r_b0, mat.r_j0,
        mat.h_b, mat.h_j, mat.kH_b, mat.kH_j, mat.width, settings.half_width_factor, settings.pressure == "hertz",
        settings.track_journal, wb, wj, diag, 0.0, share)
    return wb, wj, vb


def layouts(trace, settings, n_cycles):
    """Both deposits of one record: peaks of the depth per cycle, the volume per cycle, the kernel's time."""
    from jointwear.wear.cycle import JointMaterials, sweep_shares

    mat = JointMaterials.from_trace(trace)
    out = {}
    for name, share in (("at_angle", None), ("swept", sweep_shares(trace.t, trace.t.size))):
        t0 = time.perf_counter()
        wb, wj, vb = deposit(trace, settings, mat, 0.0, share)
        out[name] = {"bearing_peak_um_per_Mcycle": float(wb.max()) / n_cycles * UM_PER_MCYCLE,
                     "bearing_peak_deg_body": float(np.argmax(wb)) * 360.0 / settings.n_grid,
                     "journal_peak_um_per_Mcycle": float(wj.max()) / n_cycles * UM_PER_MCYCLE,
                     "volume_bearing_m3_per_cycle": vb / n_cycles, "kernel_seconds": time.perf_counter() - t0}
    return out


def record_row(res, settings, n_cycles) -> dict:
    tr = res.joints[0]
    contact = np.asarray(tr.in_contact, dtype=bool)
    F = np.where(contact, tr.force_normal, 0.0)
    step = np.abs((np.diff(tr.theta_bearing) + math.pi) % (2 * math.pi) - math.pi)
    near = contact[1:] | contact[:-1]
    return {"steps": int(res.n_steps), "rejected": int(res.n_rejected), "recorded_steps": int(res.n_recorded_steps),
            "impacts": int(np.sum(contact[1:] & ~contact[:-1])), "peak_contact_force_N": float(F.max()),
            "largest_step_s": float(np.diff(tr.t).max()),
            "contact_angle_step_deg_p99": float(np.degrees(np.quantile(step[near], 0.99))),
            **layouts(tr, settings, n_cycles)}


def per_cycle(cfg) -> list[dict]:
    from jointwear.config import updated
    from jointwear.mechanism import build_model, simulate

    ws = cfg.wear
    model = build_model(cfg)
    period = model.period
    rows = []
    for n_cycles in (1, 2):
        cases = [(rtol, None) for rtol in RTOLS] + [(5e-7, period / 2000.0)]
        for rtol, max_step in cases:
            m = model if max_step is None else build_model(updated(cfg, {"simulation.max_step": max_step}))
            res = simulate(m, n_cycles, rtol=rtol, atol=rtol * 1e-3)
            rows.append({"cycles": n_cycles, "rtol": rtol, "atol_m": rtol * 1e-3,
                         "max_step_s": max_step if max_step is not None else period / 200.0,
                         **record_row(res, ws, n_cycles)})
            r = rows[-1]
            print(f"{n_cycles} cycle(s) rtol {rtol:g} max_step {r['max_step_s']:.3g}: peak "
                  f"{r['at_angle']['bearing_peak_um_per_Mcycle']:.3f} at the angles, "
                  f"{r['swept']['bearing_peak_um_per_Mcycle']:.3f} swept (um/Mcycle)", file=sys.stderr)
    return rows


def thinned(cfg) -> list[dict]:
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism.simulate import trapezoid_weights

    res = simulate(build_model(cfg), 1, rtol=1e-9, atol=1e-9 * 1e-3)  # as per_cycle
    tr = res.joints[0]
    rows = []
    for k in (1, 2, 3, 4, 6, 8):
        idx = np.r_[np.arange(0, tr.t.size - 1, k), tr.t.size - 1]
        sub = type(tr)(**{f: (getattr(tr, f)[idx] if isinstance(getattr(tr, f), np.ndarray)
                              and getattr(tr, f).shape[:1] == tr.t.shape else getattr(tr, f))
                          for f in tr.__dataclass_fields__})
        sub.dt_weight = trapezoid_weights(sub.t)
        rows.append({"keep_every": k, "recorded_steps": int(idx.size - 1),
                     "largest_step_s": float(np.diff(sub.t).max()), **layouts(sub, cfg.wear, 1)})
    return rows


def history(cfg, replicates: int) -> list[dict]:
    import jointwear.wear.history as H
    from jointwear.mechanism import build_model
    from jointwear.wear.cycle import cycle_wear

    ws = cfg.wear
    settle0 = ws.settle_cycles_initial if ws.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    model = build_model(cfg)
    n_total = 400_000
    rows = []
    for r in range(replicates):
        acc = {"b": np.zeros(ws.n_grid), "j": np.zeros(ws.n_grid), "done": 0, "ratio": []}

        def both(trace, settings, n_cycles, materials, growth=0.0, **kw):
            cw = cycle_wear(trace, settings, n_cycles, materials, growth=growth, **kw)
            wb, wj, _ = deposit(trace, settings, materials, growth, None)  # the same record at the recorded angles
            dn = min(settings.block_cycles, n_total - acc["done"])
            acc["done"] += dn
            acc["b"] += wb / n_cycles * dn
            acc["j"] += wj / n_cycles * dn
            acc["ratio"].append(float(wb.max()) / n_cycles / float(cw.bearing.max()))
            return cw

        H.cycle_wear = both
        try:
            res = H.wear_history(model, ws.model_copy(update={"settle_cycles_initial": settle0 + 0.05 * r}), n_total)
        finally:
            H.cycle_wear = cycle_wear
        j = res.joints[0]
        ratio = np.asarray(acc["ratio"])
        rows.append({"replicate": r, "settle_cycles_initial": settle0 + 0.05 * r,
                     "swept_max_bearing_mm": float(j.bearing_wear.max()) * 1e3,
                     "at_angle_max_bearing_mm": float(acc["b"].max()) * 1e3,
                     "swept_max_journal_mm": float(j.journal_wear.max()) * 1e3,
                     "at_angle_max_journal_mm": float(acc["j"].max()) * 1e3,
                     "block_peak_ratio_at_angle_over_swept": {"mean": float(ratio.mean()), "min": float(ratio.min()),
                                                             "max": float(ratio.max())},
                     "blocks": int(ratio.size)})
        q = rows[-1]
        print(f"history {r}: max bearing {q['swept_max_bearing_mm']:.5f} mm swept, "
              f"{q['at_angle_max_bearing_mm']:.5f} mm at the angles", file=sys.stderr)
    return rows


PROFILE_CASES = (("jin2025_flapping_wing_profile", 500_000),
                 (str(Path(__file__).parents[1] / "tests" / "wear" / "rigs" / "pendulum.toml"), 10_000))
THIN = (1, 2, 4, 8)


def thin_trace(tr, k: int):
    """The record with every k-th step kept (and the last), trapezoid weights of the kept steps."""
    from jointwear.mechanism.simulate import trapezoid_weights

    idx = np.r_[np.arange(0, tr.t.size - 1, k), tr.t.size - 1]
    sub = type(tr)(**{f: (getattr(tr, f)[idx] if isinstance(getattr(tr, f), np.ndarray)
                          and getattr(tr, f).shape[:1] == tr.t.shape else getattr(tr, f))
                      for f in tr.__dataclass_fields__})
    sub.dt_weight = trapezoid_weights(sub.t)
    return sub


def profile_block(tr, ws, mat, upd, wb, wj, swept: bool) -> dict:
    """One block's deposit of a record in profile mode (history.wear_history's own steps), the loads gathered along
    the normal's swept arcs or to each step's nearest direction cell."""
    import jointwear.wear.cycle as C
    from jointwear.wear.history import lay_distributed

    geom = upd.geometry
    gather = C.gather_directions
    if not swept:  # the earlier gathering: no left shares
        C.gather_directions = lambda *a: gather(*a[:10])
    try:
        cw = C.cycle_wear(tr, ws, ws.record_cycles, mat, bearing_profile=geom.bearing_wear,
                          journal_profile=geom.journal_wear, bearing_bore=upd.bearing_bore,
                          journal_surface=upd.journal_surface)
    finally:
        C.gather_directions = gather
    dn = ws.block_cycles
    out = {"rate_bearing_peak_nm_per_cycle": float(cw.bearing.max()) * 1e9,
           "rate_journal_peak_nm_per_cycle": float(cw.journal.max()) * 1e9}
    for side, w, share, rate, vol, g in (("bearing", wb, cw.share, cw.bearing, cw.volume_bearing, cw.levelling_rate),
                                         ("journal", wj, cw.journal_share, cw.journal, cw.volume_journal,
                                          cw.journal_levelling_rate)):
        if share is not None:
            new, v = lay_distributed(share, rate, vol, g, w, dn, ws)
        else:
            new, v = w + rate * dn, vol * dn
        d = new - w
        out[f"block_{side}_peak_um"] = float(d.max()) * 1e6
        out[f"block_{side}_peak_deg"] = float(np.argmax(d)) * 360.0 / d.size
        out[f"block_volume_{side}_m3"] = v
    return out


def profile_mode(replicates: int) -> dict:
    from jointwear.config import load_config, updated
    from jointwear.mechanism import build_model, simulate
    from jointwear.wear.cycle import JointMaterials
    from jointwear.wear.history import update_geometry, wear_history

    out = {}
    for preset, n_worn in PROFILE_CASES:
        cfg = updated(load_config(preset), {"wear.geometry_mode": "profile"})
        ws = cfg.wear
        model = build_model(cfg)
        g0 = model.initial_geometry()[0]
        settle0 = ws.settle_cycles_initial if ws.settle_cycles_initial is not None else model.settings.settle_cycles
        n = ws.n_grid
        hist = wear_history(model, ws, n_worn, threads=1)
        states = {"unworn": (np.zeros(n), np.zeros(n)),
                  f"worn_{n_worn}": (hist.joints[0].bearing_wear.copy(), hist.joints[0].journal_wear.copy())}
        case = {"block_cycles": ws.block_cycles, "record_cycles": ws.record_cycles,
                "profile_smoothing_deg": ws.profile_smoothing_deg, "profile_substep_cycles":
                ws.profile_substep_cycles, "n_grid": n, "states": {}}
        for sname, (wb, wj) in states.items():
            upd = update_geometry(g0, ws, wb, wj, 0.0)
            per_rtol, thinned, tr9 = [], [], None
            for rtol in RTOLS:
                res = simulate(model, ws.record_cycles, geometry=[upd.geometry], settle_cycles=settle0, rtol=rtol,
                               atol=rtol * 1e-3)
                tr = res.joints[0]
                mat = JointMaterials.from_trace(tr, g0)
                F = np.where(tr.in_contact, tr.force_normal, 0.0)
                mu = np.unwrap(np.asarray(tr.theta_bearing) + np.asarray(tr.normal_tilt))
                near = (F[1:] > 0) | (F[:-1] > 0)
                per_rtol.append({"rtol": rtol, "atol_m": rtol * 1e-3, "recorded_steps": int(res.n_recorded_steps),
                                 "normal_step_deg_p99": float(np.degrees(np.quantile(np.abs(np.diff(mu))[near], 0.99))),
                                 "F_ds_J_per_cycle": float(np.sum(F * np.abs(tr.slip_speed) * tr.dt_weight))
                                 / ws.record_cycles,
                                 **{lay: profile_block(tr, ws, mat, upd, wb, wj, lay == "swept")
                                    for lay in ("nearest_cell", "swept")}})
                if rtol == 1e-9:
                    tr9 = tr
            for k in THIN:
                sub = thin_trace(tr9, k)
                F = np.where(sub.in_contact, sub.force_normal, 0.0)
                thinned.append({"keep_every": k, "recorded_steps": int(sub.t.size - 1),
                                "F_ds_J_per_cycle": float(np.sum(F * np.abs(sub.slip_speed) * sub.dt_weight))
                                / ws.record_cycles,
                                **{lay: profile_block(sub, ws, mat, upd, wb, wj, lay == "swept")
                                   for lay in ("nearest_cell", "swept")}})
            case["states"][sname] = {"max_bearing_um_at_start": float(wb.max()) * 1e6,
                                     "max_journal_um_at_start": float(wj.max()) * 1e6,
                                     "per_rtol": per_rtol, "thinned": thinned}
            for r in per_rtol + thinned:
                tag = f"rtol {r['rtol']:g}" if "rtol" in r else f"every {r['keep_every']}"
                print(f"{Path(preset).stem} {sname} {tag}: block bearing peak "
                      f"{r['nearest_cell']['block_bearing_peak_um']:.5f} nearest cell, "
                      f"{r['swept']['block_bearing_peak_um']:.5f} swept (um)", file=sys.stderr)
        out[Path(preset).stem] = case
    out["history"] = profile_history(replicates)
    return out


def profile_history(replicates: int) -> dict:
    import jointwear.wear.cycle as C
    from jointwear.config import load_config
    from jointwear.mechanism import build_model
    from jointwear.wear.history import wear_history

    cfg = load_config(PROFILE_CASES[0][0])
    ws = cfg.wear
    model = build_model(cfg)
    settle0 = ws.settle_cycles_initial if ws.settle_cycles_initial is not None else cfg.simulation.settle_cycles
    gather = C.gather_directions
    rows = []
    for r in range(replicates):
        row = {"replicate": r, "settle_cycles_initial": settle0 + 0.05 * r}
        for lay in ("nearest_cell", "swept"):
            if lay == "nearest_cell":
                C.gather_directions = lambda *a: gather(*a[:10])
            try:
                t0 = time.perf_counter()
                res = wear_history(model, ws.model_copy(update={"settle_cycles_initial": settle0 + 0.05 * r}),
                                   ws.cycles, threads=1)
            finally:
                C.gather_directions = gather
            j = res.joints[0]
            row[lay] = {"max_bearing_mm": float(j.bearing_wear.max()) * 1e3,
                        "max_journal_mm": float(j.journal_wear.max()) * 1e3,
                        "volume_bearing_mm3": j.volume_bearing * 1e9, "seconds": time.perf_counter() - t0}
        rows.append(row)
    out = {"cycles": ws.cycles, "runs": rows}
    for key in ("max_bearing_mm", "max_journal_mm", "volume_bearing_mm3"):
        d = np.array([x["swept"][key] / x["nearest_cell"][key] - 1.0 for x in rows])
        out[f"{key}_swept_over_nearest_minus_1"] = {"mean": float(d.mean()),
                                                   "std": float(d.std(ddof=1)) if d.size > 1 else 0.0}
        for lay in ("nearest_cell", "swept"):
            out[f"{key}_mean_{lay}"] = float(np.mean([x[lay][key] for x in rows]))
    print(f"profile history at {ws.cycles}: max bearing {out['max_bearing_mm_mean_nearest_cell']:.5f} mm nearest "
          f"cell, {out['max_bearing_mm_mean_swept']:.5f} mm swept ({replicates} runs each)", file=sys.stderr)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--only", choices=("profile_mode",), help="run this part alone and update its key in --out")
    a = ap.parse_args(argv)
    from jointwear.config import load_config
    from jointwear.study.io import provenance

    load = os.getloadavg()
    if a.only == "profile_mode":
        path = Path(a.out)
        out = json.loads(path.read_text()) if path.exists() else {}
        out["profile_mode"] = {"date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                               "machine": provenance(), "load_average_at_start": load, **profile_mode(a.replicates)}
        path.write_text(json.dumps(out, indent=1) + "\n")
        return 0
    cfg = load_config(PRESET)
    out = {"date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "machine": provenance(),
           "load_average_at_start": load, "preset": PRESET, "n_grid": cfg.wear.n_grid,
           "per_cycle": per_cycle(cfg), "thinned": thinned(cfg), "history": history(cfg, a.replicates)}
    h = out["history"]
    for key in ("bearing", "journal"):
        d = np.array([r[f"at_angle_max_{key}_mm"] / r[f"swept_max_{key}_mm"] - 1.0 for r in h])
        out[f"history_{key}_at_angle_over_swept_minus_1"] = {"mean": float(d.mean()), "std": float(d.std(ddof=1))
                                                             if d.size > 1 else 0.0}
    Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
