"""A series system learnt one Kriging per component against one Kriging of the system's response.

    python benchmarks/series_system.py [--seeds 10] [--out benchmarks/results/series_system.json]

Echard et al.'s four-branch system (2011, Sec. 5.1; k = 6, exact Pf 4.457e-3 by quadrature): ``akmcs_multi`` on
the system's response min_j g_j (one Kriging, as AK-MCS) and on its four branches (``system="series"``, AK-SYS),
the same seeds and population (200,000 points). Per seed: calls, Pf, its Monte Carlo COV, the surrogate's error
estimate, and whether the exact Pf lies within 1.96 COV Pf + that estimate. Writes JSON.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import statistics
from pathlib import Path

import numpy as np

from jointwear.reliability import akmcs_multi, problems
from jointwear.study.io import provenance


def branches(x: np.ndarray, k: float = 6.0) -> np.ndarray:
    """The four branches of the four-branch system; their minimum is problems.four_branch(k).g."""
    x1, x2 = x[:, 0], x[:, 1]
    s2 = np.sqrt(2.0)
    return np.column_stack([3 + 0.1 * (x1 - x2) ** 2 - (x1 + x2) / s2, 3 + 0.1 * (x1 - x2) ** 2 + (x1 + x2) / s2,
                            (x1 - x2) + k / s2, (x2 - x1) + k / s2])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "series_system.json")
    args = ap.parse_args()
    problem = problems.four_branch(6.0)
    cases = {}
    for name, g, system in (("system_response", problem.g, None), ("per_component", branches, "series")):
        runs = []
        for seed in range(args.seeds):
            res = akmcs_multi(g, problem.marginals, levels=[0.0], system=system, seed=seed, n_mc=200_000,
                              pf_floor=0.0)
            band = 1.96 * res.cov[0] * res.pf[0] + res.error_absolute[0]
            runs.append({"seed": seed, "calls": int(res.n_calls), "pf": float(res.pf[0]), "cov": float(res.cov[0]),
                         "error_absolute": float(res.error_absolute[0]), "wall_seconds": res.wall_seconds,
                         "exact_in_band": bool(abs(res.pf[0] - problem.pf_ref) <= band)})
        cases[name] = {"median_calls": statistics.median(r["calls"] for r in runs),
                       "exact_in_band": sum(r["exact_in_band"] for r in runs), "runs": runs}
        print(name, cases[name]["median_calls"], cases[name]["exact_in_band"], "of", args.seeds)
    out = {"benchmark": "four-branch series system: one Kriging of the system against one per branch (AK-SYS)",
           "date_utc": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "pf_exact": problem.pf_ref,
           "echard_2011_calls": problem.echard_calls, "machine": {"cpus": os.cpu_count(), **provenance()},
           "cases": cases}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
