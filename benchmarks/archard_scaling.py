"""Does the true wear model follow Archard's scaling in the bearing's wear coefficient? (the sensitivity's Archard rule)

    python benchmarks/archard_scaling.py [--samples 6] [--factor 1.2] [--no-study]

Writes benchmarks/results/archard_scaling.json:
- true_model: for random samples of the default preset's inputs, the judged max depth at each curve level of the
  true model (one wear history each) with k_b and with k_b x factor, and their ratio. Archard's law alone gives
  `factor` exactly; the wear's feedback on the dynamics (the clearance grows) and the chaotic contact move it;
- study (a few minutes): the default study's sensitivity (`Study.sensitivity()` in a temporary folder): the bearing
  variables' shifted reliabilities, how each was read, and the Archard checks.
docs/study.md ("Sensitivity") and docs/paper-comparison.md quote them.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import llvmlite.binding as llvm
import numpy as np

from jointwear.config import load_config
from jointwear.study import study_context

OUT = Path(__file__).resolve().parent / "results" / "archard_scaling.json"


def study_sensitivity() -> dict:
    """The default study's sensitivity: the bearing rows, their reading rules and the Archard checks."""
    import jointwear

    with tempfile.TemporaryDirectory() as tmp:
        sens = jointwear.Study(None, out=tmp).sensitivity()
    bearing = [v for v in sens.variables if v["group"] == "bearing_material"]
    return {
        "cycles": sens.cycles, "reliability_nominal": sens.reliability_nominal,
        "bearing_variables": [{k: v.get(k) for k in ("name", "reliability_low", "reliability_high",
                                                     "reliability_low_error", "reliability_high_error")}
                              for v in bearing],
        "ranking_bearing_material": sens.ranking_by_group.get("bearing_material"),
        "unresolved_pairs": sens.unresolved_pairs,
        "rules": [r for r in sens.rules if r["variable"] in {v["name"] for v in bearing}],
        "archard_checks": sens.archard_checks,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=6)
    ap.add_argument("--factor", type=float, default=1.2)
    ap.add_argument("--seed", type=int, default=77)
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--no-study", action="store_true", help="skip the default study's sensitivity")
    a = ap.parse_args(argv)
    calls = {}
    ctx = study_context(load_config(None), lambda call: calls.setdefault("call", call))
    call = calls["call"]
    i = ctx.names.index("k_b")
    load = os.getloadavg()
    t0 = time.perf_counter()
    rows = []
    for x in ctx.sample(a.samples, a.seed):
        w0, _ = call(x)
        x1 = x.copy()
        x1[i] *= a.factor
        w1, _ = call(x1)
        rows.append((w1 / w0).tolist())
        print(f"sample {len(rows)}: ratio {np.mean(rows[-1]):.4f} over the levels", file=sys.stderr)
    ratios = np.array(rows)
    per_sample = ratios.mean(axis=1)
    out = {
        "factor": a.factor, "samples": a.samples, "seed": a.seed, "cycles": list(call.cycles),
        "ratio_per_sample_and_level": rows,
        "mean_ratio": float(ratios.mean()),
        "standard_error_of_mean_ratio": float(per_sample.std(ddof=1) / np.sqrt(len(per_sample))),
        "wall_seconds": time.perf_counter() - t0,
        "study": None if a.no_study else study_sensitivity(),
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
                    "llvm_host_cpu": str(llvm.get_host_cpu_name()), "load_average_at_start": load},
        "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(out, indent=1))
    print(json.dumps({k: out[k] for k in ("factor", "samples", "mean_ratio", "standard_error_of_mean_ratio")}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
