"""Where does the R(N) surrogate err? Its life prediction against the true model's on a kept validation's samples.

    python benchmarks/validate.py --config CONFIG --samples N --keep FOLDER   # first: the true model on N samples
    python benchmarks/surrogate_bias.py --config CONFIG --folder FOLDER [--key KEY]

Replays the study's learning from FOLDER's evaluation store (no new model call: it refuses to make one), predicts
ln N_f with the learnt Kriging at the validation's samples and compares it with the true model's ln N_f there:
- the spread of the two (standard deviations; the slope of true on predicted, 1 for an unbiased spread);
- the residual (true - predicted) by eighths of the prediction, with the Kriging's own standard deviation there, and
  the mean squared standardised residual, on the samples and leave-one-out over the design points;
- a few quantiles of the two lives, and the life at R = 0.9 read from the learnt mean with its fitted scatter;
- the same read from Krigings fitted afresh to the same design points (other local optima of the likelihood);
- the validation's paired check (``run_validation``: the surrogate's R(N) and life on the same samples as the true
  model's, with bootstrap 95 % intervals, and where that difference lies within the surrogate's error estimate).
Writes KEY (default: the config's name) of benchmarks/results/surrogate_bias.json (docs/reliability.md, "The learnt
life's spread").
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.stats import norm

OUT = Path(__file__).parent / "results" / "surrogate_bias.json"
TARGET = 0.9


def life_at(log_life: np.ndarray, scatter_sd: float, target: float = TARGET) -> float:
    """N at which the mean over samples of P(ln N_f > ln N) is ``target`` (ln N_f normal about each mean)."""
    lo, hi = np.quantile(log_life, 1.0 - target) - 0.2, np.quantile(log_life, 1.0 - target) + 0.2
    grid = np.linspace(lo, hi, 801)
    if scatter_sd > 0:
        r = np.array([norm.sf((g - log_life) / scatter_sd).mean() for g in grid])
    else:
        r = np.array([(log_life > g).mean() for g in grid])
    return float(np.exp(np.interp(-target, -r, grid)))


def spread(true: np.ndarray, pred: np.ndarray, pred_sd: np.ndarray, scatter_sd: float) -> dict:
    resid = true - pred
    order = np.argsort(pred)
    eighths = np.array_split(order, 8)
    q = [0.02, 0.05, 0.1, 0.2, 0.5, 0.8, 0.9, 0.95]
    return {"sd_true": float(true.std()), "sd_predicted": float(pred.std()),
            "slope_true_on_predicted": float(np.polyfit(pred, true, 1)[0]),
            "residual_mean": float(resid.mean()), "residual_sd": float(resid.std()),
            "standardised_residual_mean_square": float(np.mean(resid**2 / (pred_sd**2 + scatter_sd**2))),
            "eighths": [{"predicted_mean": float(pred[i].mean()), "residual_mean": float(resid[i].mean()),
                         "residual_sd": float(resid[i].std()), "kriging_sd": float(pred_sd[i].mean())}
                        for i in eighths],
            "quantiles": q, "life_true": np.exp(np.quantile(true, q)).tolist(),
            "life_predicted": np.exp(np.quantile(pred, q)).tolist()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", required=True)
    ap.add_argument("--folder", type=Path, required=True, help="a validation's --keep folder")
    ap.add_argument("--key", default=None)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from jointwear import compute
    from jointwear.config import load_config
    from jointwear.reliability import KrigingSurrogate
    from jointwear.study import WEAR_MODEL_TAG, run_reliability, study_context
    from jointwear.study.io import provenance
    from jointwear.study.reliability import life_offset, store_digest
    from jointwear.study.validation import SEED_OFFSET, run_validation

    validation = json.loads((args.folder / "validation.json").read_text(encoding="utf-8"))
    config = load_config(args.config)
    store = compute.EvaluationStore.open(args.folder, store_digest(config), resume=True)
    try:
        ctx = study_context(config, lambda call: compute.Evaluator(call, None, store, tag=WEAR_MODEL_TAG,
                                                                   n_outputs=call.n_outputs))
        learnt = run_reliability(ctx)  # the learning replayed: every call is read back
        made = ctx.n_model_calls
        x = ctx.sample(int(validation["n_samples"]), config.reliability.seed + SEED_OFFSET)
        true = np.log(ctx.life(x))
        design_x = np.asarray(learnt.design_x, dtype=float)
        design_y = np.log(ctx.life(design_x))
        validation_now = run_validation(ctx, learnt, int(validation["n_samples"]))  # the product's paired check
    finally:
        store.close()
    if ctx.n_model_calls != made:
        sys.exit("the store lacks some of the validation's calls: run benchmarks/validate.py --keep first")
    engine = learnt.engine
    iso = ctx.iso()
    u, design_u = iso.to_u(x), iso.to_u(design_x)
    shift = float(engine.levels[0])
    mean, var = engine.response_surrogate.predict(u)
    scatter = float(engine.noise_sd) if config.reliability.noise == "estimate" else 0.0
    options = {"estimate_nugget": config.reliability.noise == "estimate",  # as the study's Kriging
               "offset": life_offset(ctx, iso)}
    loo_mean, loo_var = engine.response_surrogate.leave_one_out()
    loo_y = engine.response_surrogate.training_outputs
    loo_z2 = float(np.mean((loo_y - loo_mean) ** 2 / (loo_var + engine.response_surrogate.noise_variance)))
    ok = np.isfinite(true)
    fitted = {"loo_standardised_residual_mean_square": loo_z2, "life_at_target": life_at(mean[ok] + shift, scatter),
              "noise_sd": scatter,
              "hyperparameters": {"scale": engine.response_surrogate.hyperparameters.scale.tolist(),
                                  "relative_nugget": engine.response_surrogate.hyperparameters.nugget},
              **spread(true[ok], mean[ok] + shift, np.sqrt(var[ok]), scatter)}
    fresh = []
    keep = np.isfinite(design_y)
    for n_starts in (2, 6):
        k = KrigingSurrogate(seed=0, n_starts=n_starts, **options).fit(design_u[keep], design_y[keep])
        m, v = k.predict(u[ok])
        s = k.noise_sd if options["estimate_nugget"] else 0.0
        fresh.append({"n_starts": n_starts, "life_at_target": life_at(m, s), "noise_sd": s,
                      "slope_true_on_predicted": float(np.polyfit(m, true[ok], 1)[0])})
    life_true = float(np.exp(np.quantile(true[ok], 1.0 - TARGET)))
    entry = {"config": args.config, "machine": provenance(), "n_samples": int(ok.sum()),
             "n_design_points": int(keep.sum()), "target": TARGET, "life_true": life_true,
             "study_life": learnt.life_cycles, "learnt": fitted, "refitted": fresh,
             "paired": {"cycles": validation_now.cycles.tolist(),
                        "difference": validation_now.paired_difference().tolist(),
                        "difference_low": validation_now.paired_difference_low.tolist(),
                        "difference_high": validation_now.paired_difference_high.tolist(),
                        "surrogate_error": validation_now.surrogate_error.tolist(),
                        "within_error": validation_now.paired_within_error().tolist(),
                        "life": {k: validation_now.life_table[0].get(k) for k in (
                            "target", "cycles", "surrogate_cycles", "paired_surrogate_cycles", "paired_ratio",
                            "paired_ratio_low", "paired_ratio_high")}}}
    record = json.loads(args.out.read_text(encoding="utf-8")) if args.out.is_file() else {}
    record[args.key or config.name] = entry
    args.out.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    print(json.dumps({"life_true": life_true, "learnt_life": fitted["life_at_target"],
                      "paired_life": entry["paired"]["life"],
                      "levels_within_error": sum(entry["paired"]["within_error"]),
                      "slope": fitted["slope_true_on_predicted"],
                      "lowest_eighth_residual": fitted["eighths"][0]["residual_mean"],
                      "refitted": [(f["n_starts"], round(f["life_at_target"])) for f in fresh]}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
