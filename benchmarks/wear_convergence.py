"""`jointwear converge` on the presets: is each preset's nominal wear history converged in its numerical settings?

    python benchmarks/wear_convergence.py [--replicates 8] [--out FILE]

Runs :func:`jointwear.study.convergence.run_convergence` (the engine of `jointwear converge`) on
- the default preset (jin2025_flapping_wing), every refinement 2x, 16 replicates;
- the six-bar preset (watt_six_bar_two_clearances), every refinement 2x, then `record_cycles` alone refined
  2x, 4x, 8x and 16x (one sampled cycle per block in the preset), with the given replicates;
- the pendulum rig (tests/wear/rigs/pendulum.toml) in profile mode to 10,000 revolutions: a steady load, so the
  replicates agree and the verdicts are decisive.
Writes benchmarks/results/wear_convergence.json (docs/wear.md, "Is my history converged?").
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import sys
import time
from pathlib import Path

from jointwear.config import load_config, updated
from jointwear.study.checks import nominal_wear_cycles
from jointwear.study.convergence import run_convergence
from jointwear.study.io import provenance

ROOT = Path(__file__).resolve().parents[1]
RIG = ROOT / "tests" / "wear" / "rigs" / "pendulum.toml"


def one(config, cycles: int, **kw) -> dict:
    t0 = time.perf_counter()
    res = run_convergence(config, cycles, **kw)
    out = res.to_json()
    out.pop("provenance", None)
    out["seconds"] = time.perf_counter() - t0
    print(config.name, kw.get("factor"), kw.get("only"), round(res.baseline["mean"]),
          {r["name"]: (round(100 * r["change"], 1), round(196 * r["change_se"], 1), r["verdict"])
           for r in res.refinements}, file=sys.stderr, flush=True)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "wear_convergence.json")
    args = ap.parse_args(argv)
    rec: dict = {"benchmark": "jointwear converge on the presets", "date": dt.date.today().isoformat(),
                 "machine": provenance()}
    default = load_config(None)
    rec["default_2x"] = one(default, nominal_wear_cycles(default), replicates=16)
    six = load_config("watt_six_bar_two_clearances")
    n6 = nominal_wear_cycles(six)
    rec["six_bar_2x"] = one(six, n6, replicates=args.replicates)
    rec["six_bar_record"] = {str(f): one(six, n6, replicates=args.replicates, factor=f, only=["record_cycles"])
                             for f in (2, 4, 8, 16)}
    rig = updated(load_config(str(RIG)), {"wear.geometry_mode": "profile"})
    rec["rig_profile_2x"] = one(rig, 10_000, replicates=2)
    args.out.write_text(json.dumps(rec, indent=1), encoding="utf-8")
    print(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
