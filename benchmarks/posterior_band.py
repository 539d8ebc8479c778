"""Cost of the surrogate's posterior band of R(N) (docs/reliability.md, "The surrogate's error of R(N)").

    python benchmarks/posterior_band.py [--repeats 7] [--out benchmarks/results/posterior_band.json]

A Kriging of the default study's size (54 noisy points in 13 dimensions, the noise estimated) and the study's
band settings: the posterior covariance at POSTERIOR_POINTS population points, then the spread of Pf at 14 levels
over POSTERIOR_DRAWS conditional simulations (``surrogate_pf_error``'s posterior part, split into its two
parts). Medians of wall and CPU time, and their ratio to a reference in the same process: the Kriging's mean and
variance on 200,000 points (the study's Monte Carlo population). Writes JSON.
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

from jointwear.reliability import KrigingSurrogate, posterior_failure_spread
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
    total = out["posterior_covariance"]["wall_median_s"] + out["spread"]["wall_median_s"]
    out["total_wall_median_s"] = total
    out["ratio_total_to_reference"] = total / out["reference_predict_200k"]["wall_median_s"]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: out[k] for k in ("total_wall_median_s", "ratio_total_to_reference")}))


if __name__ == "__main__":
    main()
