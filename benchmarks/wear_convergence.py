"""`jointwear converge` on the presets: is each preset's nominal wear history converged in its numerical settings?

    python benchmarks/wear_convergence.py [--replicates 8] [--out FILE]

Runs :func:`jointwear.study.convergence.run_convergence` (the engine of `jointwear converge`) on
- the default preset (jin2025_flapping_wing), every refinement 2x, 16 replicates, and its record length and
  settling 8x;
- the six-bar preset (watt_six_bar_two_clearances), every refinement 2x, then `record_cycles` alone refined
  2x, 4x, 8x and 16x (one sampled cycle per block in the preset), with the given replicates;
- the pendulum rig (tests/wear/rigs/pendulum.toml) in profile mode to 10,000 revolutions: a steady load, so the
  replicates agree and the verdicts are decisive;
- the other presets and examples (flores_slider_crank, jin2025_flapping_wing_profile, examples/my_linkage.toml,
  examples/piston_pump.toml), every refinement 2x, with the given replicates.
`--only KEY ...` runs those entries alone and keeps the record's others. Writes
benchmarks/results/wear_convergence.json (docs/wear.md, "Is my history converged?").
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


def entries(replicates: int) -> dict:
    """The record's entries: key -> a function that measures it."""
    default = load_config(None)
    six = load_config("watt_six_bar_two_clearances")
    n6 = nominal_wear_cycles(six)
    out = {
        "default_2x": lambda: one(default, nominal_wear_cycles(default), replicates=16),
        "default_record_settle_8x": lambda: one(default, nominal_wear_cycles(default), replicates=16, factor=8,
                                                only=["record_cycles", "settle_cycles"]),
        "six_bar_2x": lambda: one(six, n6, replicates=replicates),
        "six_bar_record": lambda: {str(f): one(six, n6, replicates=replicates, factor=f, only=["record_cycles"])
                                   for f in (2, 4, 8, 16)},
        "rig_profile_2x": lambda: one(updated(load_config(str(RIG)), {"wear.geometry_mode": "profile"}), 10_000,
                                      replicates=2),
    }
    for key, source in (("slider_crank_2x", "flores_slider_crank"),
                        ("profile_preset_2x", "jin2025_flapping_wing_profile"),
                        ("my_linkage_2x", str(ROOT / "examples" / "my_linkage.toml")),
                        ("piston_pump_2x", str(ROOT / "examples" / "piston_pump.toml"))):
        out[key] = (lambda src: lambda: one(cfg := load_config(src), nominal_wear_cycles(cfg),
                                            replicates=replicates))(source)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument("--only", nargs="+", default=None, help="entries to run (default all)")
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "wear_convergence.json")
    args = ap.parse_args(argv)
    rec: dict = json.loads(args.out.read_text(encoding="utf-8")) if args.only and args.out.is_file() else {}
    rec.update({"benchmark": "jointwear converge on the presets", "date": dt.date.today().isoformat(),
                "machine": provenance()})
    todo = entries(args.replicates)
    for key in args.only or list(todo):
        rec[key] = todo[key]()
        rec[key + "_date"] = dt.date.today().isoformat()
        args.out.write_text(json.dumps(rec, indent=1), encoding="utf-8")
    print(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
