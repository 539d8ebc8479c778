"""The surrogate's own error of each reliability derivative against the number of posterior points (docs/study.md,
"Sensitivity": ``dR_dmean_surrogate_sd``).

    python benchmarks/slope_error.py FOLDER [--points 500 1000 2000 4000] [--out benchmarks/results/slope_error.json]

FOLDER is a finished study (the default study's `jointwear run --out FOLDER`); each count runs its sensitivity stage
on a copy of it (every true-model call read back from the store) with ``SHIFT_POSTERIOR_POINTS`` set to the count,
and records each variable's dR/dmu, its Monte Carlo standard error and the spread of the same estimator over the
Kriging's posterior. Points too few to stand for the population would add each point's own posterior variance to
the spread (it would then fall as 1 / sqrt(points)); a spread that holds as the points grow is the surrogate's
error of the population's slope. Writes JSON.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import shutil
import tempfile
import time
from pathlib import Path

import jointwear
import jointwear.study.sensitivity as stage
from jointwear.study.io import provenance

OUT = Path(__file__).resolve().parent / "results" / "slope_error.json"


def run(folder: Path, points: int) -> dict:
    """The sensitivity stage on a copy of ``folder`` with ``points`` posterior points."""
    stage.SHIFT_POSTERIOR_POINTS = points
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / "study"
        shutil.copytree(folder, copy)
        t0 = time.perf_counter()
        sens = jointwear.Study(out=copy, resume=True, workers=1, echo=lambda line: None).sensitivity()
        wall = time.perf_counter() - t0
    se = dict(zip(sens.derivatives["names"], sens.derivatives["dpf_dmean_se"]))
    return {"stage_wall_s": wall, "extra_model_calls_read_back": sens.extra_model_calls,
            "variables": {v["name"]: {"method": v["derivative_method"], "dR_dmean": v["dR_dmean"],
                                      "monte_carlo_se": se[v["name"]],
                                      "surrogate_sd": v["dR_dmean_surrogate_sd"],
                                      "error_95": v["dR_dmean_error"],
                                      "resolved": abs(v["dR_dmean"]) > v["dR_dmean_error"]}
                          for v in sens.variables}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--points", type=int, nargs="+", default=[500, 1000, 2000, 4000])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    runs = {str(m): run(args.folder, m) for m in args.points}
    names = list(next(iter(runs.values()))["variables"])
    ratio = {name: {m: r["variables"][name]["surrogate_sd"] / abs(r["variables"][name]["dR_dmean"])
                    for m, r in runs.items() if r["variables"][name]["dR_dmean"]} for name in names}
    record = {"benchmark": "slope_error", "date": dt.date.today().isoformat(), "folder": str(args.folder),
              "machine": provenance(), "runs": runs, "surrogate_sd_over_slope": ratio}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(record, indent=1) + "\n")
    for name in names:
        print(name, "  ".join(f"{m}: {v:.3g}" for m, v in ratio[name].items()))


if __name__ == "__main__":
    main()
