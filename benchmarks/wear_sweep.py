"""Where a recorded step's wear is laid: at its one contact angle, or along the arc the contact sweeps over its time
(results/wear_sweep.json).

    python benchmarks/wear_sweep.py [--replicates 8]

The flapping-wing preset (uniform mode, the wear stage's rtol 5e-7 / atol 5e-10 m unless stated). Three parts:

- per_cycle: one and two cycles recorded after the preset's settling, at rtol 5e-7, 1e-7, 1e-8, 1e-9 (atol = rtol x
  1e-3 m) and at 5e-7 with a tenth of the default largest step: integrator steps, recorded steps, contact impacts,
  peak contact force, the Archard volume per cycle, and the peak of the cycle's bearing and journal depth profiles
  with each step's wear laid at its recorded angle (the earlier deposit) and along its swept arc (now);
- thinned: the rtol 1e-9 record with every k-th step kept (trapezoid weights of the kept steps), both deposits;
- history: the nominal wear history to 400k cycles, `replicates` runs differing only in the initial settling
  (+0.05 cycle each, as benchmarks/wear.py), each block's record laid both ways (the swept one drives the geometry):
  the max bearing and journal depth at 400k cycles of each, on the same trajectory.

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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    from jointwear.config import load_config
    from jointwear.study.io import provenance

    load = os.getloadavg()
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
