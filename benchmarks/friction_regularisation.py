"""What the friction law's regularisation speeds cost and change on a heavily loaded joint
(results/friction_regularisation.json).

    python benchmarks/friction_regularisation.py [--config benchmarks/configs/toggle_press.toml] [--factors 1 10]

Per factor f: every clearance joint's friction ``v_s`` and ``v_d`` times f (the defaults 1e-4 and 1e-3 m/s at f = 1),
then the ``simulate`` stage over 2 cycles after 1 settling (steps and wall time per cycle, the mean contact forces)
and the ``wear`` stage's nominal history (the max bearing wear of every joint, the stage's wall time). The stick
branch of the law has slope about 1.5 mu_s F_N / v_s: under 800 N on links of 0.3 kg it sets the step
(docs/dynamics.md, "When the step size collapses").
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import tempfile
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"


def one_factor(base, factor: float, folder: Path) -> dict:
    import jointwear
    from jointwear.config import updated

    changes = {}
    for cj in base.clearance_joints:
        changes[f"clearance_joints.{cj.name}.friction.v_s"] = cj.friction.v_s * factor
        changes[f"clearance_joints.{cj.name}.friction.v_d"] = cj.friction.v_d * factor
    study = jointwear.Study(updated(base, changes), out=folder / f"factor_{factor:g}", echo=lambda line: None)
    sim = study.simulate(cycles=2, settle=1)
    t0 = time.perf_counter()
    wear = study.wear()
    return {"factor": factor, "v_s_m_s": changes[f"clearance_joints.{base.clearance_joints[0].name}.friction.v_s"],
            "steps_per_cycle": sim.steps_per_cycle, "simulate_wall_seconds_per_cycle": sim.wall_seconds_per_cycle,
            "kernel": sim.kernel, "contact_force_mean_N": {j["name"]: j["contact_force_mean_N"] for j in sim.joints},
            "wear_cycles": wear.cycles, "wear_stage_wall_seconds": time.perf_counter() - t0,
            "max_bearing_wear_mm": {j["name"]: j["max_wear_mm"] for j in wear.joints}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(Path(__file__).parent / "configs" / "toggle_press.toml"))
    ap.add_argument("--factors", type=float, nargs="+", default=[1.0, 10.0])
    ap.add_argument("--out", type=Path, default=RESULTS / "friction_regularisation.json")
    a = ap.parse_args(argv)
    from jointwear.config import load_config
    from jointwear.study.io import provenance

    base = load_config(a.config)
    runs = []
    with tempfile.TemporaryDirectory() as folder:
        for f in a.factors:
            runs.append(one_factor(base, f, Path(folder)))
            print(json.dumps(runs[-1]), flush=True)
    record = {"benchmark": __doc__.splitlines()[0], "machine": provenance(),
              "date_utc": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"), "config": a.config,
              "runs": runs}
    a.out.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
