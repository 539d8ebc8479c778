"""Does the default study's life interval hold the exact life as often as it says? (results/life_coverage.json)

    python benchmarks/life_coverage.py [--seeds 40] [--only SETTING ...]

The default preset with its true wear model replaced by the analytic Archard-type model of tests/analytic_wear.py
(13 inputs, an exact life per sample), its curve cut to 340k-480k cycles in steps of 40k. Per setting and seed
(``reliability.seed``): the life at R = 0.9 with its 95 % interval, and R at every level with its band, against the
exact values read off 4e6 fresh samples of the exact life (their own error is negligible beside the intervals). The
settings: the defaults, ``reliability.error_abs_tol = 0.002``, ``reliability.life_tol = 0.002``,
``reliability.trend = "archard"`` and ``reliability.trend = "linear"``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from analytic_wear import RATE, AnalyticWear  # noqa: E402

OUT = Path(__file__).parent / "results" / "life_coverage.json"
CURVE = {"reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 40_000,
         "reliability.histogram_cycles": [380_000]}
SETTINGS = {"defaults": {}, "error_abs_tol_0.002": {"reliability.error_abs_tol": 0.002},
            "life_tol_0.002": {"reliability.life_tol": 0.002}, "trend_archard": {"reliability.trend": "archard"},
            "trend_linear": {"reliability.trend": "linear"}}


def one_study(changes: dict, seed: int) -> dict:
    from jointwear import compute
    from jointwear.config import load_config, updated
    from jointwear.study import population, run_reliability, study_context

    cfg = updated(load_config(), {**CURVE, **changes, "reliability.seed": seed})
    holder = {}

    def factory(call):
        holder["model"] = AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
        return compute.Evaluator(holder["model"], None, None, n_outputs=len(call.cycles))

    t0 = time.perf_counter()
    ctx = study_context(cfg, factory)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_reliability(ctx)
    wall = time.perf_counter() - t0
    x = population(ctx.marginals, 4_000_000, seed=10_000 + seed)
    life = np.sort(cfg.reliability.allowance / (RATE * holder["model"].scale(x)))
    target = cfg.reliability.target_reliability
    exact = float(np.quantile(life, 1.0 - target))
    lo, hi = res.life_interval()
    levels = np.asarray(res.cycles, float)
    r_exact = 1.0 - np.searchsorted(life, levels, side="left") / life.size
    half = 0.5 * (hi - lo) if lo is not None and hi is not None else None
    return {"seed": seed, "wall_seconds": wall, "calls": int(res.model_calls), "life": res.life(), "lower": lo,
            "upper": hi, "life_exact": exact, "held": bool(lo is not None and lo <= exact <= hi),
            "miss_over_half_width": (res.life() - exact) / half if half else None,
            "levels": levels.tolist(), "r": list(map(float, res.reliability)), "r_exact": r_exact.tolist(),
            "level_held": (np.abs(np.asarray(res.reliability) - r_exact) <= np.asarray(res.half_width)).tolist()}


def summary(runs: list[dict]) -> dict:
    from scipy.stats import binomtest

    held = sum(r["held"] for r in runs)
    ci = binomtest(held, len(runs)).proportion_ci(0.95)
    err = np.array([r["life"] / r["life_exact"] - 1.0 for r in runs])
    width = np.array([(r["upper"] - r["lower"]) / (2 * r["life_exact"]) for r in runs])
    return {"life_held": held, "runs": len(runs), "coverage_95_interval": [ci.low, ci.high],
            "life_error_mean_relative": float(err.mean()), "life_error_se_relative": float(err.std(ddof=1) /
                                                                                            np.sqrt(err.size)),
            "life_error_spread_relative": float(err.std(ddof=1)),
            "half_width_median_relative": float(np.median(width)),
            "misses_low": int(sum(1 for r in runs if not r["held"] and r["life"] < r["life_exact"])),
            "levels_held": np.sum([r["level_held"] for r in runs], axis=0).tolist(),
            "calls_median": statistics.median(r["calls"] for r in runs)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--only", nargs="+", choices=list(SETTINGS), default=None,
                    help="run these settings alone and keep the record's others")
    a = ap.parse_args(argv)
    from jointwear.study.io import provenance

    out = {"machine": provenance(),
           "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "curve": CURVE, "settings": {}}
    if a.only and Path(a.out).is_file():
        kept = json.loads(Path(a.out).read_text(encoding="utf-8"))
        out = {**kept, "settings": kept["settings"]}
    for name, changes in SETTINGS.items():
        if a.only and name not in a.only:
            continue
        runs = [one_study(changes, seed) for seed in range(1, a.seeds + 1)]
        out["settings"][name] = {"changes": changes, **summary(runs), "per_seed": runs, "machine": provenance(),
                                 "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
        s = out["settings"][name]
        print(f"{name}: life held {s['life_held']}/{s['runs']} (95 % {s['coverage_95_interval'][0]:.2f}-"
              f"{s['coverage_95_interval'][1]:.2f}), mean error {s['life_error_mean_relative']:+.4f} +- "
              f"{s['life_error_se_relative']:.4f}, median half-width {s['half_width_median_relative']:.4f}, "
              f"levels held {s['levels_held']}, median calls {s['calls_median']}", flush=True)
    Path(a.out).write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
