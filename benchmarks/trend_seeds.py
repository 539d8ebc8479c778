"""The learnt life over seeds with each Kriging trend, against the true model on shared samples
(results/trend_seeds_<config>.json).

    python benchmarks/trend_seeds.py [--config flores_slider_crank] [--samples 3000] [--seeds 12]
                                     [--trends constant linear] [--workers 2] [--keep DIR]

One set of true-model samples (``--samples``, the seed ``VALIDATION_SEED``, reused from the evaluation store of
``--keep``) gives the true life at the first target with its exact 95 % interval. Then, per trend and per
``reliability.seed``: the reliability stage's life and its 95 % interval, and the paired check of the validation
(``jointwear.study.validation.paired_check``: the learnt surrogate read on the same samples, so their sampling noise
cancels) with its 95 % bootstrap bounds. Per trend: the mean error of the life against the true one over seeds, its
spread, how often the interval holds the true life, and how often the paired error lies within the interval's
half-width (the check that does not carry the true samples' own error).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
#: seed of the shared true-model samples: far from the studies' seeds (seed + 0..7) and their validations' (+1000)
VALIDATION_SEED = 77_000


def true_life(life: np.ndarray, ctx, target: float) -> dict:
    """The true model's life at ``target`` read on the study's fine curve, with its exact 95 % interval."""
    from jointwear.study.limit_state import curve_cycles, life_at
    from jointwear.study.validation import true_reliability

    fine = curve_cycles(np.asarray(ctx.cycles, dtype=float))
    r, low, high = true_reliability(life, fine, ctx.config.uncertainty.infeasible_probability())
    # the band's low side crosses the target first: the life's lower bound
    return {"cycles": life_at(fine, r, target), "low": life_at(fine, low, target),
            "high": life_at(fine, high, target)}


def one_run(base, changes: dict, make_context, x: np.ndarray, life: np.ndarray, truth: dict) -> dict:
    from jointwear.config import updated
    from jointwear.study import run_reliability
    from jointwear.study.limit_state import curve_cycles
    from jointwear.study.reliability import life_scatter_sd
    from jointwear.study.validation import paired_check

    cfg = updated(base, changes)
    ctx = make_context(cfg)
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_reliability(ctx)
    wall = time.perf_counter() - t0
    target = res.target
    lo, hi = res.life_interval()
    fine = curve_cycles(np.asarray(ctx.cycles, dtype=float))
    paired = paired_check(ctx, res, x, life, fine, cfg.uncertainty.infeasible_probability(), [target],
                          seed=cfg.reliability.seed).lives[target]
    value = res.life()
    half = None if lo is None or hi is None or value is None else 0.5 * (hi - lo) / value
    return {"seed": cfg.reliability.seed, "calls": int(res.model_calls), "wall_seconds": wall, "life": value,
            "lower": lo, "upper": hi, "half_width_relative": half,
            "error_relative": None if value is None else value / truth["cycles"] - 1.0,
            "held": bool(lo is not None and hi is not None and lo <= truth["cycles"] <= hi),
            "paired_ratio": paired["paired_ratio"], "paired_ratio_low": paired["paired_ratio_low"],
            "paired_ratio_high": paired["paired_ratio_high"],
            "paired_within_half_width": bool(half is not None and paired["paired_ratio"] is not None
                                             and abs(paired["paired_ratio"]) <= half),
            "fitted_scatter_sd_log_life": float(life_scatter_sd(ctx, res.engine))}


def summary(runs: list[dict]) -> dict:
    from scipy.stats import binomtest

    err = np.array([r["error_relative"] for r in runs if r["error_relative"] is not None])
    paired = np.array([r["paired_ratio"] for r in runs if r["paired_ratio"] is not None])
    held = sum(r["held"] for r in runs)
    within = sum(r["paired_within_half_width"] for r in runs)
    return {"runs": len(runs), "life_held": held,
            "life_held_95_interval": list(binomtest(held, len(runs)).proportion_ci(0.95)),
            "paired_within_half_width": within,
            "paired_within_95_interval": list(binomtest(within, len(runs)).proportion_ci(0.95)),
            "error_mean_relative": float(err.mean()), "error_se_relative": float(err.std(ddof=1) / np.sqrt(err.size)),
            "error_spread_relative": float(err.std(ddof=1)),
            "paired_mean": float(paired.mean()), "paired_se": float(paired.std(ddof=1) / np.sqrt(paired.size)),
            "paired_spread": float(paired.std(ddof=1)),
            "half_width_median_relative": statistics.median(r["half_width_relative"] for r in runs
                                                            if r["half_width_relative"] is not None),
            "fitted_scatter_sd_median": statistics.median(r["fitted_scatter_sd_log_life"] for r in runs),
            "calls_median": statistics.median(r["calls"] for r in runs)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="flores_slider_crank")
    ap.add_argument("--samples", type=int, default=3000)
    ap.add_argument("--seeds", type=int, default=12)
    ap.add_argument("--trends", nargs="+", default=["constant", "linear"], choices=["constant", "archard", "linear"])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--keep", type=Path, default=Path("trend_seeds_store"),
                    help="folder of the evaluation store (true-model calls are read back from it)")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)

    from jointwear import compute
    from jointwear.config import load_config
    from jointwear.study import study_context
    from jointwear.study.facade import WEAR_MODEL_TAG
    from jointwear.study.io import provenance
    from jointwear.study.reliability import store_digest

    base = load_config(a.config)
    a.keep.mkdir(parents=True, exist_ok=True)
    store = compute.EvaluationStore.open(a.keep, store_digest(base, a.keep), resume=True)
    executor = compute.make_executor(workers=a.workers)
    out_file = a.out or RESULTS / f"trend_seeds_{base.name}.json"
    with executor:
        def make_context(cfg):
            return study_context(cfg, lambda call: compute.Evaluator(
                call, executor, store, timeout=cfg.compute.call_timeout, tag=WEAR_MODEL_TAG,
                n_outputs=call.n_outputs), threads=executor.threads_per_call)

        ctx = make_context(base)
        t0 = time.perf_counter()
        x = ctx.sample(a.samples, VALIDATION_SEED)
        life = ctx.life(x)
        target = base.reliability.targets[0]
        truth = true_life(life, ctx, target)
        print(f"true model: {a.samples} samples in {time.perf_counter() - t0:.0f} s, life at R = {target}: "
              f"{truth['cycles']:,.0f} ({truth['low']:,.0f}-{truth['high']:,.0f})", flush=True)
        record = {"machine": provenance(), "date_utc": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
                  "config": a.config, "samples": a.samples, "validation_seed": VALIDATION_SEED, "target": target,
                  "true_life": truth, "true_failed_calls": int(np.isnan(life).sum()), "trends": {}}
        if out_file.is_file():  # keep the trends not run from a record read against the same true samples
            kept = json.loads(out_file.read_text(encoding="utf-8"))
            if all(kept.get(k) == record[k] for k in ("config", "samples", "validation_seed", "true_life")):
                record["trends"] = {k: {"machine": kept["machine"], "date_utc": kept["date_utc"], **v}
                                    for k, v in kept["trends"].items() if k not in a.trends}
        for trend in a.trends:
            runs = []
            for seed in range(1, a.seeds + 1):
                runs.append(one_run(base, {"reliability.trend": trend, "reliability.seed": seed}, make_context,
                                    x, life, truth))
                r = runs[-1]
                print(f"{trend} seed {seed}: {r['calls']} calls, life {r['life']:,.0f} ({r['lower']:,.0f}-"
                      f"{r['upper']:,.0f}), error {r['error_relative']:+.4f}, paired {r['paired_ratio']:+.4f} "
                      f"({r['paired_ratio_low']:+.4f} to {r['paired_ratio_high']:+.4f}), "
                      f"scatter sd {r['fitted_scatter_sd_log_life']:.4f}", flush=True)
            record["trends"][trend] = {**summary(runs), "per_seed": runs, "machine": provenance(),
                                       "date_utc": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")}
            s = record["trends"][trend]
            print(f"{trend}: error {s['error_mean_relative']:+.4f} +- {s['error_se_relative']:.4f} (spread "
                  f"{s['error_spread_relative']:.4f}), paired {s['paired_mean']:+.4f} +- {s['paired_se']:.4f}, "
                  f"interval held {s['life_held']}/{s['runs']}, paired within half-width "
                  f"{s['paired_within_half_width']}/{s['runs']}, median half-width "
                  f"{s['half_width_median_relative']:.4f}", flush=True)
            out_file.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    store.close()
    print(f"wrote {out_file}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
