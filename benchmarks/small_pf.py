"""Small failure probabilities: AK-IS against the true-model methods (writes benchmarks/results/small_pf.json).

    python benchmarks/small_pf.py [--seeds 8]

Problems with exact or high-accuracy references (jointwear.reliability.problems): linear beta = 5 (Pf = Phi(-5)),
parabolic beta = 5, kappa = 0.1 (exact quadrature), cubic-parabolic (Echard et al. 2013, AK-IS example 1;
1e8-sample IS reference), linear beta = 4 in 6-D. Per problem and method, over seeds: median and range of the
model calls and of |Pf / Pf_ref - 1|, and the median reported COV. Methods: AK-IS (Kriging on the IS population),
importance sampling with the true model at the FORM design point (same COV target, 5 %), subset simulation
(true model), FORM and SORM (deterministic).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

OUT = Path(__file__).parent / "results" / "small_pf.json"


def _problems():
    from jointwear.reliability import problems as P

    return {"linear_beta5_d2": P.linear(5.0, 2), "parabolic_beta5_kappa0.1": P.parabolic(5.0, 0.1),
            "cubic_parabolic": P.cubic_parabolic(), "linear_beta4_d6": P.linear(4.0, 6)}


def _summary(rows):
    calls = [r["n_calls"] for r in rows]
    err = [r["rel_err"] for r in rows]
    return {"n_calls_median": statistics.median(calls), "n_calls_range": [min(calls), max(calls)],
            "rel_err_median": statistics.median(err), "rel_err_max": max(err),
            "cov_median": statistics.median([r["cov"] for r in rows]) if rows[0]["cov"] is not None else None,
            "pf_median": statistics.median([r["pf"] for r in rows])}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    from jointwear.reliability import (
        akis,
        form,
        importance_sampling,
        sorm,
        subset_simulation,
    )

    out = {"machine": {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count()},
           "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "seeds": a.seeds, "problems": {}}
    t_all = time.perf_counter()
    for name, p in _problems().items():
        rec = {"pf_ref": p.pf_ref, "ref_source": p.ref_source, "methods": {}}
        f = form(p.g, p.marginals)
        s = sorm(p.g, p.marginals, form_result=f)
        for m, r in (("form", f), ("sorm", s)):
            rec["methods"][m] = {"pf": r.pf, "n_calls": r.n_calls, "rel_err": abs(r.pf / p.pf_ref - 1)}
        rows = {"akis": [], "importance_sampling": [], "subset_simulation": []}
        for seed in range(a.seeds):
            t0 = time.perf_counter()
            r = akis(p.g, p.marginals, seed=seed)
            rows["akis"].append({"n_calls": r.n_calls, "pf": r.pf, "cov": r.cov, "rel_err": abs(r.pf / p.pf_ref - 1),
                                 "n_is": r.n_mc, "converged": r.converged, "wall_seconds": time.perf_counter() - t0})
            # true-model IS at the same design point, sized for the same 5 % COV as AK-IS's population
            ri = importance_sampling(p.g, p.marginals, n=max(r.n_mc, 100), form_result=f, seed=seed)
            rows["importance_sampling"].append({"n_calls": ri.n_calls, "pf": ri.pf, "cov": ri.cov,
                                                "rel_err": abs(ri.pf / p.pf_ref - 1)})
            rs = subset_simulation(p.g, p.marginals, n_per_level=2000, seed=seed)
            rows["subset_simulation"].append({"n_calls": rs.n_calls, "pf": rs.pf, "cov": rs.cov,
                                              "rel_err": abs(rs.pf / p.pf_ref - 1)})
        for m, rr in rows.items():
            rec["methods"][m] = {**_summary(rr), "runs": rr}
        rec["crude_mc_calls_for_cov_5pct"] = (1 - p.pf_ref) / (0.05**2 * p.pf_ref)
        out["problems"][name] = rec
        am = rec["methods"]["akis"]
        print(f"{name}: ref {p.pf_ref:.4g}; AK-IS {am['n_calls_median']} calls (range {am['n_calls_range']}), "
              f"median error {am['rel_err_median']:.3%}, max {am['rel_err_max']:.3%}; IS "
              f"{rec['methods']['importance_sampling']['n_calls_median']} calls; subset "
              f"{rec['methods']['subset_simulation']['n_calls_median']} calls", flush=True)
    out["wall_seconds"] = time.perf_counter() - t_all
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(out, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
