"""The friction-driven whirl of the flapping-wing crank pin: where it appears, what it takes, what it does to wear.

Writes benchmarks/results/whirl.json. Run: python benchmarks/whirl.py (about 5 minutes on 2 cores).
docs/dynamics.md, "Friction-driven whirl", reads it.

Sections (preset jin2025_flapping_wing, only the named settings changed):
- speeds: one simulate from the assembled rest state (the simulate stage's start) per crank speed: contact-point
  revolutions per cycle, the whirl flag (jointwear.mechanism.whirl_measure), mean contact force, steps per cycle;
- needs: at 360 rpm, the same with friction off, with mu_d = 0.05 and 0.2, with clearances of 1, 4, 8 and
  20 um (what the whirl needs), with rtol 1e-4 and 1e-8, with radau5 and with the other contact laws (what it
  does not depend on);
- centripetal: the mass m that the whirl's mean contact force would keep orbiting at radius c at the whirl's
  angular speed Omega (F = m c Omega^2), beside the rod's mass (the eye's effective mass adds the rocker's);
- other_configs: every clearance joint of the other presets, the examples and benchmarks/configs from rest (the
  calm side of the whirl threshold);
- wear: the wear stage's history (default settings, `--wear-cycles`) per speed: max bearing wear and the blocks
  that whirled.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

SPEEDS_RPM = (240, 300, 330, 360, 390, 420, 450, 480, 600, 720)
WEAR_SPEEDS_RPM = (240, 300, 360, 420, 480, 600)


def one_run(config) -> dict:
    from jointwear.mechanism import build_model, simulate, whirl_measure

    res = simulate(build_model(config), 2)
    tr = res.joints[0]
    revolutions, whirl = whirl_measure(tr, res.n_cycles)
    return {"contact_revolutions_per_cycle": revolutions, "whirl": whirl, "mean_contact_force_N": tr.mean_force,
            "impacts_per_cycle": tr.n_impacts / res.n_cycles, "contact_fraction": tr.contact_fraction,
            "steps_per_cycle": res.steps_per_cycle}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "whirl.json"))
    ap.add_argument("--wear-cycles", type=int, default=400_000)
    args = ap.parse_args()

    import jointwear
    from jointwear.config import load_config, updated

    base = load_config("jin2025_flapping_wing")
    out: dict = {"preset": "jin2025_flapping_wing", "machine": {
        "python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
        "load_average_at_start": os.getloadavg()}, "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    one_run(base)  # compile

    out["speeds"] = {}
    for rpm in SPEEDS_RPM:
        out["speeds"][str(rpm)] = one_run(updated(base, {"mechanism.crank_speed_rpm": rpm}))
        print(f"speed {rpm} rpm: {out['speeds'][str(rpm)]}", file=sys.stderr, flush=True)

    at360 = {"mechanism.crank_speed_rpm": 360}
    variants = {"friction_off": {"clearance_joints.A.friction.law": "none"},
                "mu_d_0.05": {"clearance_joints.A.friction.mu_d": 0.05, "clearance_joints.A.friction.mu_s": 0.075},
                "mu_d_0.2": {"clearance_joints.A.friction.mu_d": 0.2, "clearance_joints.A.friction.mu_s": 0.3},
                **{f"clearance_{c}_um": {"clearance_joints.A.clearance_um": float(c)} for c in (1, 4, 8, 20)},
                # numerics and contact law: the whirl is a solution of the equations, not of the integrator
                "rtol_1e-4": {"simulation.rtol": 1e-4}, "rtol_1e-8": {"simulation.rtol": 1e-8},
                "radau5": {"simulation.method": "radau5"},
                "flores_law": {"clearance_joints.A.contact_law": "flores"},
                "hunt_crossley_law": {"clearance_joints.A.contact_law": "hunt_crossley"}}
    out["needs_at_360_rpm"] = {}
    for name, change in variants.items():
        out["needs_at_360_rpm"][name] = one_run(updated(base, {**at360, **change}))
        print(f"360 rpm, {name}: {out['needs_at_360_rpm'][name]}", file=sys.stderr, flush=True)

    # the calm side of the threshold: every clearance joint of the other presets, the examples and the benchmark
    # configs, from rest (the whirl threshold is max(5, 3 (|n_rel| + 1)))
    from jointwear.config import available_presets
    from jointwear.mechanism import build_model, simulate, whirl_measure

    root = Path(__file__).resolve().parents[1]
    sources = [p for p in available_presets() if p != "jin2025_flapping_wing"]
    sources += [str(p.relative_to(root)) for p in sorted((root / "examples").glob("*.toml"))]
    sources += [str(p.relative_to(root)) for p in sorted((root / "benchmarks" / "configs").glob("*.toml"))]
    out["other_configs"] = {}
    for source in sources:
        cfg = load_config(source if source in available_presets() else root / source)
        res = simulate(build_model(cfg), 2)
        rows = {}
        for tr in res.joints:
            revolutions, whirl = whirl_measure(tr, res.n_cycles)
            rows[tr.name] = {"contact_revolutions_per_cycle": revolutions, "whirl": whirl,
                             "relative_revolutions_per_cycle": tr.relative_revolutions / res.n_cycles}
        out["other_configs"][source] = rows
        print(f"{source}: {out['other_configs'][source]}", file=sys.stderr, flush=True)

    cj = base.clearance_joints[0]
    c = cj.bearing_radius - cj.journal_radius
    rec = out["speeds"]["360"]
    omega = abs(rec["contact_revolutions_per_cycle"]) * 2 * math.pi * 360 / 60  # whirl's angular speed, rad/s
    out["centripetal_at_360_rpm"] = {"whirl_rad_per_s": omega, "clearance_m": c,
                                     "force_per_kg_N": c * omega**2,
                                     "mean_contact_force_N": rec["mean_contact_force_N"],
                                     "implied_effective_mass_kg": rec["mean_contact_force_N"] / (c * omega**2),
                                     "rod_mass_kg": base.mechanism.rod.mass}

    out["wear"] = {"cycles": args.wear_cycles}
    for rpm in WEAR_SPEEDS_RPM:
        cfg = updated(base, {"mechanism.crank_speed_rpm": rpm})
        t0 = time.perf_counter()
        w = jointwear.Study(cfg, out=Path("/tmp") / f"jointwear_whirl_{rpm}", echo=lambda s: None).wear(
            cycles=args.wear_cycles)
        spun = [b for b in w.blocks if b["whirl"]]
        out["wear"][str(rpm)] = {"max_wear_mm": w.max_wear_mm, "blocks": len(w.blocks), "whirl_blocks": len(spun),
                                 "whirl_cycles": sum(b["size"] for b in spun),
                                 "contact_revolutions_per_cycle": [b["contact_revolutions_per_cycle"][0]
                                                                   for b in w.blocks],
                                 "wall_seconds": time.perf_counter() - t0}
        print(f"wear {rpm} rpm: {w.max_wear_mm:.4g} mm, {len(spun)} of {len(w.blocks)} blocks whirl",
              file=sys.stderr, flush=True)
    out["machine"]["load_average_at_end"] = os.getloadavg()
    Path(args.out).write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
