"""Does the default study's life interval hold the exact life as often as it says? (results/life_coverage.json)

    python benchmarks/life_coverage.py [--seeds 40] [--only SETTING ...]

The default preset with its true wear model replaced by the analytic Archard-type model of tests/analytic_wear.py
(13 inputs, an exact life per sample), its curve cut to 340k-480k cycles in steps of 40k. Per setting and seed
(``reliability.seed``): the life at R = 0.9 with its 95 % interval, and R at every level with its band, against the
exact values read off 4e6 fresh samples of the exact life (their own error is negligible beside the intervals). The
settings: the defaults, ``reliability.error_abs_tol = 0.002``, ``reliability.life_tol = 0.002``,
``reliability.trend = "archard"``, ``reliability.trend = "linear"`` and the linear trend with ``life_tol = 0.002``.

Per seed, the life's error against the exact life L_true of 2e7 samples splits into four relative parts
(``parts``; research 63-D), which multiply to life / L_true:
population = L_pop / L_true - 1, L_pop the exact life on the study's own curve population;
surrogate = L_mean / L_pop - 1, L_mean the quantile of exp(mu) (the Kriging's mean) on that population;
scatter = L_smooth / L_mean - 1, L_smooth the root of mean Phi((ln N - mu) / s) = 1 - R* with the fitted scatter s;
reading = life / L_smooth - 1, the fine curve's reading. ``parts_summary``: their mean, standard error and spread.
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
from scipy.optimize import brentq
from scipy.special import ndtr

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from analytic_wear import RATE, AnalyticWear  # noqa: E402

from jointwear.reliability.kriging import LINEAR_TREND_POINTS_PER_TERM
from jointwear.study.reliability import life_scatter_sd

OUT = Path(__file__).parent / "results" / "life_coverage.json"
CURVE = {"reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 40_000,
         "reliability.histogram_cycles": [380_000]}
SETTINGS = {"defaults": {}, "error_abs_tol_0.002": {"reliability.error_abs_tol": 0.002},
            "life_tol_0.002": {"reliability.life_tol": 0.002}, "trend_archard": {"reliability.trend": "archard"},
            "trend_linear": {"reliability.trend": "linear"},
            "trend_linear_life_tol_0.002": {"reliability.trend": "linear", "reliability.life_tol": 0.002}}
PARTS = ("population", "surrogate", "scatter", "reading")
#: the parts' exact life: 2e7 samples (SE 0.005 %), drawn 2e6 at a time with seeds 777000 + k (research 63-D)
REFERENCE_SAMPLES, REFERENCE_CHUNK, REFERENCE_SEED = 20_000_000, 2_000_000, 777_000
#: the rows per draw of the study's curve population (``engine.estimate_on``'s chunk, each drawn with seed + start)
CURVE_CHUNK = 200_000
_reference: dict = {}


def exact_log_life(cfg, model, x: np.ndarray) -> np.ndarray:
    """ln of the exact life of each input row ``x``."""
    return np.log(cfg.reliability.allowance / (RATE * model.scale(x)))


def reference_life(ctx, model, p: float) -> float:
    """The exact life at failure probability ``p`` from REFERENCE_SAMPLES fresh samples (computed once)."""
    if p not in _reference:
        lnl = np.concatenate([exact_log_life(ctx.config, model, ctx.sample(REFERENCE_CHUNK, REFERENCE_SEED + k))
                              for k in range(REFERENCE_SAMPLES // REFERENCE_CHUNK)])
        _reference[p] = float(np.exp(np.quantile(lnl, p)))
    return _reference[p]


def curve_population(ctx, res) -> np.ndarray:
    """The input rows the study's curve was estimated on, drawn again as the study drew them."""
    # mirrors the private jointwear.study.reliability._curve_estimate (seeds reliability.seed + 7 + start), which
    # uses the learning's own population instead when the fitted scatter is 0
    eng, n, seed = res.engine, int(res.n_mc), ctx.config.reliability.seed + 7
    if life_scatter_sd(ctx, eng) <= 0 and eng.population_u is not None:
        return ctx.iso().to_x(np.asarray(eng.population_u)[:n])
    return np.vstack([ctx.sample(min(CURVE_CHUNK, n - start), seed + start) for start in range(0, n, CURVE_CHUNK)])


def smoothed_quantile(mu: np.ndarray, s: float, p: float) -> float:
    """N with mean Phi((ln N - mu) / s) = p over the population (s = 0: the plain p-quantile of exp(mu))."""
    q0 = float(np.quantile(mu, p))
    if s <= 0:
        return float(np.exp(q0))
    return float(np.exp(brentq(lambda t: ndtr((t - mu) / s).mean() - p, q0 - 0.3, q0 + 0.3, xtol=1e-12)))


def life_parts(ctx, res, model) -> dict:
    """The life's relative error split into the population's, the surrogate's, the scatter's and the reading's."""
    p = 1.0 - ctx.config.reliability.target_reliability
    x = curve_population(ctx, res)
    l_pop = float(np.exp(np.quantile(exact_log_life(ctx.config, model, x), p)))
    mu = res.engine.response(ctx.iso().to_u(x))
    l_mean = smoothed_quantile(mu, 0.0, p)
    l_smooth = smoothed_quantile(mu, life_scatter_sd(ctx, res.engine), p)
    l_true = reference_life(ctx, model, p)
    return {"population": l_pop / l_true - 1.0, "surrogate": l_mean / l_pop - 1.0,
            "scatter": l_smooth / l_mean - 1.0, "reading": res.life() / l_smooth - 1.0}


def linear_trend_active(ctx, res) -> bool:
    """Whether the final Kriging fitted the linear trend (the design holds enough points per coefficient)."""
    n_points, d = len(res.engine.design_x), len(ctx.marginals)
    return ctx.config.reliability.trend == "linear" and n_points >= LINEAR_TREND_POINTS_PER_TERM * (d + 1)


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
    return {"seed": seed, "wall_seconds": wall, "calls": int(res.model_calls),
            "design_points": len(res.engine.design_x), "linear_trend_active": linear_trend_active(ctx, res),
            "parts": life_parts(ctx, res, holder["model"]), "life": res.life(), "lower": lo,
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
            "calls_median": statistics.median(r["calls"] for r in runs),
            "design_points_median": statistics.median(r["design_points"] for r in runs),
            "linear_trend_active_runs": sum(r["linear_trend_active"] for r in runs),
            "parts_summary": {k: spread_summary([r["parts"][k] for r in runs]) for k in PARTS}}


def spread_summary(values) -> dict:
    """Mean, standard error of the mean and seed-to-seed spread (sd) of per-seed values."""
    v = np.asarray(values, float)
    return {"mean": float(v.mean()), "se": float(v.std(ddof=1) / np.sqrt(v.size)), "spread": float(v.std(ddof=1))}


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
    for name in a.only or list(SETTINGS):
        changes = SETTINGS[name]
        runs = [one_study(changes, seed) for seed in range(1, a.seeds + 1)]
        out["parts_reference"] = {"life": next(iter(_reference.values())), "samples": REFERENCE_SAMPLES,
                                  "seeds": f"{REFERENCE_SEED} + k, {REFERENCE_CHUNK} each"}
        out["settings"][name] = {"changes": changes, **summary(runs), "per_seed": runs, "machine": provenance(),
                                 "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
        s = out["settings"][name]
        print(f"{name}: life held {s['life_held']}/{s['runs']} (95 % {s['coverage_95_interval'][0]:.2f}-"
              f"{s['coverage_95_interval'][1]:.2f}), mean error {s['life_error_mean_relative']:+.4f} +- "
              f"{s['life_error_se_relative']:.4f}, median half-width {s['half_width_median_relative']:.4f}, "
              f"levels held {s['levels_held']}, median calls {s['calls_median']}, parts " + ", ".join(
                  f"{k} {v['mean']:+.5f} +- {v['se']:.5f} (sd {v['spread']:.5f})"
                  for k, v in s["parts_summary"].items()), flush=True)
        # written after every setting, so that a stopped run keeps the settings it finished
        Path(a.out).write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
        print(f"wrote {a.out}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
