"""Cost of the surrogate's posterior band of R(N) (docs/reliability.md, "The surrogate's error of R(N)").

    python benchmarks/posterior_band.py [--repeats 7] [--out benchmarks/results/posterior_band.json]

A Kriging of the default study's size (54 noisy points in 13 dimensions, the noise estimated) and the study's
band settings: the posterior covariance at POSTERIOR_POINTS population points, then the spread of Pf at 14 levels
over POSTERIOR_DRAWS conditional simulations (``surrogate_pf_error``'s posterior part, split into its two
parts). Medians of wall and CPU time, and their ratio to a reference in the same process: the Kriging's mean and
variance on 200,000 points (the study's Monte Carlo population).

``draws``: the conditional simulations alone (``gaussian_draws``, a pivoted Cholesky factor stopped at the
covariance's numerical rank) against the jittered full Cholesky factor it replaced, in the same process, on that
Kriging (13 inputs: a covariance of full rank) and on an interpolating one of a study with 3 random inputs (20
points), whose posterior covariance over the population has a low numerical rank. Writes JSON.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import statistics
import time
from pathlib import Path

import numpy as np
from scipy.linalg import lapack

from jointwear.reliability import KrigingSurrogate, posterior_failure_spread
from jointwear.reliability.kriging import gaussian_draws
from jointwear.study.io import provenance
from jointwear.study.reliability import POSTERIOR_DRAWS, POSTERIOR_POINTS

OUT = Path(__file__).resolve().parent / "results" / "posterior_band.json"


def timed(fn, repeats: int) -> dict:
    walls, cpus = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return {"wall_median_s": statistics.median(walls), "cpu_median_s": statistics.median(cpus),
            "wall_all_s": walls}


def jittered_cholesky_draws(mean, cov, n_draws, rng):
    """The draws as made before the pivoted factor: a full Cholesky factor of cov, its diagonal raised by a jitter
    of 1e-10 of its mean (up to 1e-4) until it factors, else an eigen-decomposition (the reference of ``draws``)."""
    scale = max(float(np.mean(np.diag(cov))), np.finfo(float).tiny)
    for jitter in (1e-10, 1e-8, 1e-6, 1e-4):
        work = cov.copy()
        work[np.diag_indices(mean.size)] += jitter * scale
        try:
            chol = np.linalg.cholesky(work)
            break
        except np.linalg.LinAlgError:
            continue
    else:
        eigenvalues, vectors = np.linalg.eigh(cov)
        chol = vectors * np.sqrt(np.clip(eigenvalues, 0.0, None))[None, :]
    return mean[:, None] + chol @ rng.standard_normal((mean.size, n_draws))


def draws_case(k, u, repeats: int) -> dict:
    """Time of the conditional simulations on the Kriging k's posterior at u, pivoted and jittered."""
    mean, cov = k.predict(u, return_variance=False)[0], k.posterior_covariance(u)
    pivoted = timed(lambda: gaussian_draws(mean, cov, POSTERIOR_DRAWS, np.random.default_rng(1)), repeats)
    jittered = timed(lambda: jittered_cholesky_draws(mean, cov, POSTERIOR_DRAWS, np.random.default_rng(1)), repeats)
    return {"numerical_rank": int(lapack.dpstrf(cov, lower=1)[2]), "points": len(u), "pivoted": pivoted,
            "jittered_reference": jittered,
            "ratio_pivoted_to_jittered": pivoted["wall_median_s"] / jittered["wall_median_s"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    d, n_train, levels = 13, 54, 14
    x = rng.standard_normal((n_train, d))
    y = 13.0 + 0.1 * x[:, 0] + 0.05 * np.sin(x[:, 1]) + 0.02 * rng.standard_normal(n_train)
    k = KrigingSurrogate(estimate_nugget=True).fit(x, y)
    u = rng.standard_normal((POSTERIOR_POINTS, d))
    shifts = np.linspace(-0.3, 0.3, levels)
    mean = k.predict(u, return_variance=False)[0] - 13.0
    noise_sd = k.noise_sd
    cov = k.posterior_covariance(u)
    population = rng.standard_normal((200_000, d))
    out = {
        "benchmark": "posterior band of R(N): covariance at the population sample and the spread of Pf",
        "date": dt.date.today().isoformat(), "machine": {"cpus": os.cpu_count(), **provenance()},
        "load_average_before": os.getloadavg()[0],
        "points": POSTERIOR_POINTS, "draws": POSTERIOR_DRAWS, "levels": levels, "dim": d, "n_train": n_train,
        "noise_sd": noise_sd,
        "reference_predict_200k": timed(lambda: k.predict(population), args.repeats),
        "posterior_covariance": timed(lambda: k.posterior_covariance(u), args.repeats),
        "spread": timed(lambda: posterior_failure_spread(mean, cov, shifts, noise_sd, POSTERIOR_DRAWS,
                                                          np.random.default_rng(1)), args.repeats),
    }
    x3 = rng.standard_normal((20, 3))
    three = KrigingSurrogate().fit(x3, 13.0 + 0.3 * x3[:, 0] - 0.2 * x3[:, 1] ** 2 + 0.1 * x3[:, 2])
    out["draws"] = {"thirteen_inputs": draws_case(k, u, args.repeats),
                    "three_inputs": draws_case(three, rng.standard_normal((POSTERIOR_POINTS, 3)), args.repeats)}
    total = out["posterior_covariance"]["wall_median_s"] + out["spread"]["wall_median_s"]
    out["total_wall_median_s"] = total
    out["ratio_total_to_reference"] = total / out["reference_predict_200k"]["wall_median_s"]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({**{k: out[k] for k in ("total_wall_median_s", "ratio_total_to_reference")},
                      **{name: (case["numerical_rank"], case["ratio_pivoted_to_jittered"])
                         for name, case in out["draws"].items()}}))


if __name__ == "__main__":
    main()
