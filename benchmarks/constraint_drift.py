"""How far the ideal joints drift over a long run, against the Baumgarte gains (results/constraint_drift.json).

    python benchmarks/constraint_drift.py [--cycles 50]

Per preset, kernel (the preset's own and the general Cartesian one) and gains (alpha = beta, 1/s): the largest
position violation of the ideal joints' constraints over the first cycle and over all cycles (sampled at 4,000
recorded steps), the velocity violation, and the clearance joint's mean contact force, from rest with no settling, at
the dynamics' default tolerances. docs/dynamics.md quotes it.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).parent / "results" / "constraint_drift.json"
PRESETS = ("flores_slider_crank", "jin2025_flapping_wing")
GAINS = (0.0, 100.0, 1.0e4)


def drift(preset: str, gain: float, cycles: float, general: bool) -> dict:
    from jointwear.config import load_config, updated
    from jointwear.mechanism import build_model, simulate

    cfg = updated(load_config(preset), {"simulation.baumgarte_alpha": gain, "simulation.baumgarte_beta": gain})
    model = build_model(cfg)
    arrays = model.kernel_arrays()
    t0 = time.perf_counter()
    res = simulate(model, cycles, settle_cycles=0, fast=False if general else None)
    wall = time.perf_counter() - t0
    idx = np.unique(np.linspace(0, len(res.t) - 1, 4000).astype(int))
    pos, vel = [], []
    for i in idx:
        p, v = model.constraint_eval(res.t[i], res.q[i], res.qd[i], arrays)[:2]
        pos.append(np.max(np.abs(p)))
        vel.append(np.max(np.abs(v)))
    pos, vel = np.asarray(pos), np.asarray(vel)
    first = res.t[idx] <= res.t[0] + (res.t[-1] - res.t[0]) / cycles
    clearance = float(cfg.clearance_joints[0].bearing_radius - cfg.clearance_joints[0].journal_radius)
    return {"preset": preset, "alpha_beta_per_s": gain, "cycles": cycles, "kernel": res.extra.get("kernel"),
            "max_position_violation_m_first_cycle": float(pos[first].max()),
            "max_position_violation_m": float(pos.max()), "max_velocity_violation_m_s": float(vel.max()),
            "radial_clearance_m": clearance, "mean_contact_force_N": float(res.joints[0].mean_force),
            "wall_seconds": wall}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=float, default=50.0)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    from jointwear.study.io import provenance

    load = os.getloadavg()
    rows = []
    for preset in PRESETS:
        for general in (False, True):
            for gain in GAINS:
                rows.append(drift(preset, gain, a.cycles, general))
                r = rows[-1]
                print(f"{preset} {r['kernel']} alpha=beta={gain:g}: first cycle "
                      f"{r['max_position_violation_m_first_cycle']:.2e} m, "
                      f"all {r['max_position_violation_m']:.2e} m, force {r['mean_contact_force_N']:.5g} N",
                      file=sys.stderr)
    out = {"date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "machine": provenance(),
           "load_average_at_start": load, "rows": rows}
    Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
