"""The nominal life against the cycles recorded per block, over replicates that differ in the inputs by 1e-12 m.

    python benchmarks/record_length.py [--config watt_six_bar_two_clearances] [--records 1 2 4 8 16 64]
                                       [--replicates 20 20 20 12 12 10] [--out FILE]

Each replicate is one true-model call (`jointwear.study.reliability.model_call`, one thread) at the inputs' means
with the first input moved by k x 1e-12 (its unit: m for a length): a chaotic contact turns that into another
history, as the reliability stage's calls see it. For each `wear.record_cycles` the lives' mean, their standard
deviation in ln N and the seconds per call. Writes benchmarks/results/record_length.json (docs/wear.md, "Is my
history converged?").
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from jointwear.config import load_config, updated
from jointwear.study.io import provenance
from jointwear.study.reliability import limit_state_from_config, model_call


def lives(config, record: int, replicates: int) -> dict:
    cfg = updated(config, {"wear.record_cycles": record})
    call = model_call(cfg, threads=1)
    limit = limit_state_from_config(cfg)
    x0 = np.array([float(m.mean()) for m in cfg.uncertainty.marginals(feasible=True)])
    out, t0 = [], time.perf_counter()
    for k in range(replicates):
        x = x0.copy()
        x[0] += k * 1e-12
        y = np.asarray(call(x)[0], dtype=float)
        out.append(float(limit.life(call.cycles, y[None, :])[0]))
    ln = np.log(out)
    return {"record_cycles": record, "replicates": replicates, "lives": out, "mean": statistics.fmean(out),
            "standard_error_of_mean": statistics.stdev(out) / len(out) ** 0.5, "sd_log_life": float(np.std(ln, ddof=1)),
            "seconds_per_call": (time.perf_counter() - t0) / replicates}


def fixed_geometry_peaks(config, n: int = 128) -> dict:
    """The wear coefficients / 1e8 (the geometry stays as drawn), blocks of one recorded cycle after half a cycle of
    settling: the spread of one cycle's peak depth rate, and its mean against the peak of the n-cycle mean map."""
    from jointwear.mechanism import build_model
    from jointwear.wear import wear_history

    j0 = config.clearance_joints[0].name
    cfg = updated(config, {f"clearance_joints.{j0}.bearing_material.wear_coefficient": 1e-12,
                           f"clearance_joints.{j0}.journal_material.wear_coefficient": 1e-13,
                           "wear.record_cycles": 1, "wear.block_cycles": 1, "wear.settle_cycles": 0.5})
    res = wear_history(build_model(cfg), cfg.wear, n, threads=1)
    peaks = np.array([b.peak_rate for b in res.blocks])
    mean_map_peak = res.joints[0].bearing_wear.max() / n
    return {"cycles": n, "peak_rate_cv": float(peaks.std() / peaks.mean()),
            "mean_single_cycle_peak_over_mean_map_peak": float(peaks.mean() / mean_map_peak)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="watt_six_bar_two_clearances")
    ap.add_argument("--records", type=int, nargs="+", default=[1, 2, 4, 8, 16, 64])
    ap.add_argument("--replicates", type=int, nargs="+", default=[20, 20, 20, 12, 12, 10])
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results" / "record_length.json")
    args = ap.parse_args(argv)
    config = load_config(args.config)
    rows = []
    for record, n in zip(args.records, args.replicates):
        rows.append(lives(config, record, n))
        print(record, round(rows[-1]["mean"]), round(rows[-1]["sd_log_life"], 3), file=sys.stderr, flush=True)
    rec = {"benchmark": "nominal life against wear.record_cycles", "config": args.config,
           "date": dt.date.today().isoformat(), "machine": provenance(), "rows": rows,
           "fixed_geometry": fixed_geometry_peaks(config)}
    args.out.write_text(json.dumps(rec, indent=1), encoding="utf-8")
    print(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
