"""How the learnt R(N) varies with the study's seed, against the true model's R(N) sampled directly.

    python benchmarks/noise_fit.py --truth VALIDATION_JSON [--config PRESET_OR_TOML] [--seeds 2025 1 2]
                                   [--tree LABEL=SRC ...] [--out FILE]

For each source tree (default: the installed jointwear, labelled "current"; ``--tree before=/path/to/src`` adds
another, run with PYTHONPATH=/path/to/src) and each seed: `jointwear reliability` in a fresh process on the
config with ``reliability.seed`` set, then the curve's rms and largest difference from the true model's
``reliability_mc`` in the validation record ``--truth`` (a `benchmarks/validate.py` output of the same config,
same host), the life at the first target with its interval and the surrogate's own check (``surrogate_fit``).
Writes benchmarks/results/noise_fit.json by default. Used to judge a change of the Kriging's noise fit
(docs/reliability.md, "A noisy model").
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from jointwear.study.io import provenance


def one_run(config: str, seed: int, pythonpath: str | None, truth: np.ndarray, workdir: Path) -> dict:
    """`jointwear reliability` on ``config`` with reliability.seed = ``seed``; its curve against ``truth``."""
    toml = workdir / f"seed_{seed}.toml"
    base = config if not config.endswith(".toml") else str(Path(config).resolve())
    toml.write_text(f'extends = "{base}"\n\n[reliability]\nseed = {seed}\n', encoding="utf-8")
    out = workdir / f"out_{seed}"
    env = dict(os.environ, JOINTWEAR_PROGRESS="0")
    if pythonpath is not None:
        env["PYTHONPATH"] = pythonpath
    proc = subprocess.run([sys.executable, "-m", "jointwear", "reliability", str(toml), "--out", str(out)],
                          env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"jointwear reliability failed ({proc.returncode}): {proc.stderr[-2000:]}")
    rel = json.loads((out / "reliability.json").read_text())
    r = np.array([np.nan if v is None else v for v in rel["curve"]["reliability"]], dtype=float)
    life = rel["life_at_target"]
    return {"seed": seed, "life_cycles": life["cycles"], "life_interval": [life["cycles_low"], life["cycles_high"]],
            "model_calls": rel["model_calls"], "converged": rel["converged"],
            "rms_difference_from_true_model": float(np.sqrt(np.nanmean((r - truth) ** 2))),
            "largest_difference_from_true_model": float(np.nanmax(np.abs(r - truth))),
            "surrogate_fit": rel.get("surrogate_fit"), "reliability": r.tolist(),
            "jointwear": rel.get("provenance", {}).get("jointwear")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="jin2025_flapping_wing")
    ap.add_argument("--truth", type=Path, required=True, help="validation record of the same config and host")
    ap.add_argument("--seeds", type=int, nargs="+", default=[2025, 1, 2])
    ap.add_argument("--tree", action="append", default=[], help="LABEL=SRC: also run the source tree SRC")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "noise_fit.json")
    args = ap.parse_args()
    record = json.loads(args.truth.read_text())
    # a benchmarks/validate.py record, or one that gives the true curve at top level (reliability_true_model)
    val = record.get("validation") or {"reliability_mc": record["reliability_true_model"], "cycles": record["cycles"],
                                       "n_samples": record.get("n_samples")}
    truth = np.array(val["reliability_mc"], dtype=float)
    trees = {"current": None, **dict(t.split("=", 1) for t in args.tree)}
    result = {"benchmark": "the learnt R(N) over study seeds against the true model sampled directly",
              "date": dt.date.today().isoformat(), "config": args.config, "machine": provenance(),
              "truth": {"file": args.truth.name, "n_samples": val["n_samples"], "cycles": val["cycles"],
                        "reliability_mc": val["reliability_mc"], "life_table": val.get("life_table")},
              "trees": {}}
    for label, src in trees.items():
        runs = []
        for seed in args.seeds:
            with tempfile.TemporaryDirectory() as tmp:
                runs.append(one_run(args.config, seed, src, truth, Path(tmp)))
            print(label, seed, runs[-1]["life_cycles"], runs[-1]["rms_difference_from_true_model"], file=sys.stderr)
        result["trees"][label] = {
            "source": src or "installed", "runs": runs,
            "rms_mean": statistics.fmean(r["rms_difference_from_true_model"] for r in runs),
            "rms_largest": max(r["rms_difference_from_true_model"] for r in runs),
            "life_spread_cycles": (max(r["life_cycles"] for r in runs) - min(r["life_cycles"] for r in runs))}
    args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps({k: {kk: v[kk] for kk in ("rms_mean", "rms_largest", "life_spread_cycles")}
                      for k, v in result["trees"].items()}))


if __name__ == "__main__":
    main()
