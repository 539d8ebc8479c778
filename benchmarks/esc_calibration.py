"""Is ESC's error estimate calibrated, and does the learning stop where Pf meets its tolerance? The AK-MCS engine
with its defaults on analytic limit states, with the stop held on 1 design (Echard et al.'s and Wang &
Shafieezadeh's rule) and on 3 successive designs (the default, ``hold_iterations``): its reported error against its
actual one, the share of runs whose actual error exceeds ``error_tol`` (1 %), and the leave-one-out variance scale
of its final Kriging.

    python benchmarks/esc_calibration.py [--seeds 30] [--out benchmarks/results/esc_calibration.json]

For each case and seed: ``akmcs(g, marginals, seed=s, keep_population=True)``; the actual relative error of its
Pf against the true g on the same population (the surrogate's own error, no sampling error); the reported
``error_estimate``; and the Kriging's leave-one-out standardized residuals z_i = (y_i - mu_-i) / sigma_-i over its
design, whose mean square is the factor by which the Kriging's variance would have to be scaled to explain its own
data (Bachoc 2013, "Cross validation and maximum likelihood estimations of hyper-parameters of Gaussian processes
with model misspecification"). A scale well above 1 where the estimate is exceeded would support calibrating the
variance by it before ESC and U read it. Writes JSON.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
from pathlib import Path

import numpy as np
from scipy import stats

from jointwear.reliability import IsoTransform, akmcs, problems
from jointwear.study.io import provenance


def archard_case():
    """examples/api_example.py's limit state: DELTA_0 - k / H q N, three inputs, Pf about 0.26."""
    p = problems.archard_wear()
    return list(p.marginals), p.g


def linear_case():
    """g = 3 - (x1 + x2) / sqrt(2), standard normals: Pf = Phi(-3)."""
    return [stats.norm(), stats.norm()], lambda x: 3.0 - x.sum(axis=1) / np.sqrt(2.0)


def four_branch_case():
    """Echard et al.'s four-branch series system, k = 6."""
    def g(x):
        x1, x2 = x[:, 0], x[:, 1]
        return np.min(np.column_stack([3 + 0.1 * (x1 - x2) ** 2 - (x1 + x2) / np.sqrt(2),
                                       3 + 0.1 * (x1 - x2) ** 2 + (x1 + x2) / np.sqrt(2),
                                       (x1 - x2) + 6 / np.sqrt(2), (x2 - x1) + 6 / np.sqrt(2)]), axis=1)
    return [stats.norm(), stats.norm()], g


CASES = {"archard_api_example": archard_case, "linear_beta3": linear_case, "four_branch_k6": four_branch_case}


HOLDS = (1, 3)
ERROR_TOL = 0.01  # akmcs' default


def one_run(case: str, seed: int, hold: int) -> dict:
    marginals, g = CASES[case]()
    res = akmcs(g, marginals, seed=seed, keep_population=True, hold_iterations=hold, error_tol=ERROR_TOL)
    u = res.details["population_u"]
    true_pf = float(np.mean(g(IsoTransform(marginals).to_x(u)) < 0))
    mean, var = res.surrogate.leave_one_out()
    y = res.surrogate.training_outputs
    z = (y - mean) / np.sqrt(np.maximum(var + res.surrogate.noise_variance, 1e-300))
    actual = abs(res.pf / true_pf - 1.0) if true_pf > 0 else float("nan")
    return {"seed": seed, "n_calls": int(res.n_calls), "pf": float(res.pf), "pf_true_on_population": true_pf,
            "error_estimate": float(res.error_estimate), "actual_relative_error": actual,
            "exceeded": bool(actual > res.error_estimate), "over_tolerance": bool(actual > ERROR_TOL),
            "loo_variance_scale": float(np.mean(z * z))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=30)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "esc_calibration.json")
    args = ap.parse_args()
    cases = {}
    for case in CASES:
        cases[case] = {}
        for hold in HOLDS:
            runs = [one_run(case, seed, hold) for seed in range(args.seeds)]
            scale = np.array([r["loo_variance_scale"] for r in runs])
            exceeded = np.array([r["exceeded"] for r in runs])
            actual = np.array([r["actual_relative_error"] for r in runs])
            cases[case][f"hold_{hold}"] = {
                "runs": runs, "exceeded": int(exceeded.sum()),
                "over_tolerance": int(sum(r["over_tolerance"] for r in runs)),
                "median_calls": float(np.median([r["n_calls"] for r in runs])),
                "median_error_estimate": float(np.median([r["error_estimate"] for r in runs])),
                "median_actual_error": float(np.median(actual)), "max_actual_error": float(actual.max()),
                "median_loo_variance_scale": float(np.median(scale)),
                "median_scale_where_exceeded": float(np.median(scale[exceeded])) if exceeded.any() else None,
                "median_scale_where_held": float(np.median(scale[~exceeded])) if (~exceeded).any() else None}
            print(json.dumps({case: {f"hold_{hold}": {k: v for k, v in cases[case][f"hold_{hold}"].items()
                                                      if k != "runs"}}}), flush=True)
    out = {"benchmark": "ESC's reported error against the surrogate's actual error, with the stop held on 1 and on 3 "
                        "successive designs, and the LOO variance scale", "error_tol": ERROR_TOL,
           "date_utc": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "seeds": args.seeds,
           "machine": {"cpus": os.cpu_count(), **provenance()}, "cases": cases}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
