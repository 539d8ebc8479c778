"""Do the true-model engines' stated COVs hold? (writes benchmarks/results/engine_coverage.json)

    python benchmarks/engine_coverage.py [--seeds 400]

Monte Carlo, subset simulation and importance sampling, each at its defaults, over independent seeds on problems
with exact Pf (jointwear.reliability.problems): linear beta = 2, 3, 4 in 2 and 10 dimensions (Phi(-beta)) and the
four-branch series system (k = 6, several failure regions). Per problem and engine: the relative bias of the mean
estimate, the seed-to-seed spread over the mean stated standard error (COV x Pf; 1 when the COV is honest), and the
coverage of the stated 95 % interval Pf (1 +- 1.96 COV) with its binomial standard error.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

OUT = Path(__file__).parent / "results" / "engine_coverage.json"


def _problems():
    from jointwear.reliability import problems as P

    cases = {f"linear_beta{b}_d{d}": P.linear(float(b), d) for d in (2, 10) for b in (2, 3, 4)}
    cases["four_branch_k6"] = P.four_branch(6.0)
    return cases


def _engines():
    from jointwear.reliability import importance_sampling, monte_carlo, subset_simulation

    return {"monte_carlo": monte_carlo, "subset_simulation": subset_simulation,
            "importance_sampling": importance_sampling}


def _summary(pf_ref: float, pf: np.ndarray, cov: np.ndarray, calls: list[int]) -> dict:
    se = np.where(np.isfinite(cov), cov * pf, np.nan)  # no failure: COV inf, no interval
    finite = np.isfinite(se)
    covered = float(np.mean(np.abs(pf - pf_ref) <= 1.96 * np.where(finite, se, np.inf)))
    n = pf.size
    return {"bias_relative": float(pf.mean() / pf_ref - 1.0), "spread_relative": float(pf.std(ddof=1) / pf_ref),
            "cov_stated_mean": float(cov[np.isfinite(cov)].mean()) if np.isfinite(cov).any() else None,
            "spread_over_stated_se": float(pf.std(ddof=1) / se[finite].mean()) if finite.any() else None,
            "coverage_95": covered, "coverage_se": float(np.sqrt(0.95 * 0.05 / n)),
            "n_calls_median": statistics.median(calls)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=400)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    from jointwear.study.io import provenance

    out = {"machine": provenance(),
           "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "seeds": a.seeds, "problems": {}}
    t_all = time.perf_counter()
    for name, problem in _problems().items():
        rec = {"pf_ref": problem.pf_ref, "ref_source": problem.ref_source, "engines": {}}
        for engine_name, engine in _engines().items():
            t0 = time.perf_counter()
            pf, cov, calls = [], [], []
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                for seed in range(a.seeds):
                    r = engine(problem.g, problem.marginals, seed=seed)
                    pf.append(r.pf)
                    cov.append(r.cov)
                    calls.append(int(r.n_calls))
            rec["engines"][engine_name] = {**_summary(problem.pf_ref, np.array(pf), np.array(cov), calls),
                                           "wall_seconds": time.perf_counter() - t0}
            s = rec["engines"][engine_name]
            print(f"{name:20s} {engine_name:20s} bias {s['bias_relative']:+.3f}  spread/SE "
                  f"{s['spread_over_stated_se']:.2f}  coverage {s['coverage_95']:.3f} +- {s['coverage_se']:.3f}",
                  flush=True)
        out["problems"][name] = rec
    out["wall_seconds"] = time.perf_counter() - t_all
    Path(a.out).write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
