"""True-model calls: one shared design for the whole R(N) curve against a separate AK-MCS at each N.

The study learns the wear life once (`akmcs_multi(levels=...)`, docs/study.md); the paper's way is one AK-MCS
per cycle count. This runs, on the default preset and with the study's own settings, a separate AK-MCS for a
few cycle counts (each through the same wear model; no call is shared between them) and writes JSON
(default benchmarks/results/study_levels.json) with the calls and R of each, next to the shared-design run
recorded by benchmarks/study.py.

    python benchmarks/study_levels.py [--cycles 360000 400000 520000] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np


def main() -> None:
    from jointwear import compute
    from jointwear.config import load_config
    from jointwear.reliability import akmcs
    from jointwear.study import study_context

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, nargs="+", default=[360_000, 400_000, 520_000])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "study_levels.json")
    args = ap.parse_args()
    cfg = load_config()
    rel = cfg.reliability
    runs = []
    with compute.make_executor(workers=args.workers) as ex:
        for n in args.cycles:
            holder = {}
            ctx = study_context(cfg, lambda call: holder.setdefault(
                "ev", compute.Evaluator(call, ex, None, n_outputs=len(call.cycles))), threads=ex.threads_per_call)
            log_n = float(np.log(n))

            def g(x, ctx=ctx, log_n=log_n):
                return ctx.log_life(x) - log_n

            t0 = time.perf_counter()
            res = akmcs(g, ctx.marginals, n_mc=rel.n_mc, n_mc_max=rel.n_mc_max, n_initial=rel.n_initial,
                        batch_size=rel.batch_size, u_threshold=rel.u_threshold, cov_target=rel.cov_target,
                        stopping=rel.stopping, error_tol=rel.error_tol, max_calls=rel.max_calls, seed=rel.seed,
                        kriging={"estimate_nugget": rel.noise == "estimate"})
            runs.append({"cycles": n, "model_calls": res.n_calls, "reliability": 1.0 - res.pf, "pf_cov": res.cov,
                         "converged": res.converged, "wall_seconds": time.perf_counter() - t0})
            print(json.dumps(runs[-1]))
    shared = None
    study_json = Path(__file__).parent / "results" / "study.json"
    if study_json.exists():
        run = json.loads(study_json.read_text())["runs"][-1]
        shared = {"model_calls": run["model_calls"], "reliability": run["reliability"]}
    result = {"benchmark": "separate AK-MCS per cycle count vs one shared design for the whole curve",
              "settings": {"n_mc": rel.n_mc, "n_initial": rel.n_initial, "stopping": rel.stopping,
                           "error_tol": rel.error_tol, "max_calls": rel.max_calls, "seed": rel.seed},
              "separate": runs, "separate_total_calls": sum(r["model_calls"] for r in runs),
              "shared_design_whole_curve": shared}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({"separate_total_calls": result["separate_total_calls"], "shared": shared}))


if __name__ == "__main__":
    main()
