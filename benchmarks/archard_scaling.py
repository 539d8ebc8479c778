"""Does the true wear model follow Archard's scaling in the bearing's wear coefficient? (the sensitivity's Archard rule)

    python benchmarks/archard_scaling.py [--samples 6] [--factor 1.2]

Writes benchmarks/results/archard_scaling.json: for random samples of the default preset's inputs, the judged max
depth at each curve level of the true model (one wear history each) with k_b and with k_b x factor, and their
ratio. Archard's law alone gives `factor` exactly; the wear's feedback on the dynamics (the clearance grows) and the
chaotic contact move it. docs/study.md ("Sensitivity") quotes the mean ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from jointwear.config import load_config
from jointwear.study import study_context

OUT = Path(__file__).resolve().parent / "results" / "archard_scaling.json"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=6)
    ap.add_argument("--factor", type=float, default=1.2)
    ap.add_argument("--seed", type=int, default=77)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    calls = {}
    ctx = study_context(load_config(None), lambda call: calls.setdefault("call", call))
    call = calls["call"]
    i = ctx.names.index("k_b")
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
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
                    "load_average_at_start": os.getloadavg()},
        "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(out, indent=1))
    print(json.dumps({k: out[k] for k in ("factor", "samples", "mean_ratio", "standard_error_of_mean_ratio")}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
