"""How often the life's 95 % interval holds the exact life: the reliability stage on analytic wear models whose
R(N) is known by brute force, repeated over seeds.

    python benchmarks/life_interval.py [--seeds 20] [--out benchmarks/results/life_interval.json]

Cases, each with the exact life read at the same 256 points of the curve as the study's own life
(``jointwear.study.limit_state.curve_cycles``); the life a straight line between the levels would read is recorded
beside it (``straight_line_life``, ``straight_line_held``), the reading before the curve was estimated between
its levels:
- ``smooth``: the flapping-wing preset's 13 inputs, wear = RATE N (k_b / k0) (H0 / H_b) (1 + 0.05 (c - c0) / 1 um)
  (Archard's structure; one joint, a smooth log life);
- ``series``: the Watt six-bar's two clearance joints A and E, each wearing RATE_j N k_j / k0 with its own random
  wear coefficient: a series system, whose life min(N_A, N_E) has a kink where the two joints' lives cross; learnt
  one Kriging per joint (``reliability.surrogate = "per_joint"``, the default);
- ``series_coarse``: the same with levels 100,000 cycles apart (100,000-400,000) instead of 50,000;
- ``series_system_life``: the same learnt with one Kriging of the system's log life (``"system_life"``);
- ``series_system_life_u_rule``: that with the paper's learning rule (``stopping = "u"``), which spends the call
  budget.

For each seed of the study: the life and interval at each target, the brute-force life (1e6 samples), whether
the interval holds it and by how many half-widths the life misses it. Writes JSON.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import sys
import time
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from jointwear import compute
from jointwear.config import config_from_dict, load_config, updated
from jointwear.study import life_at, population, run_reliability, study_context
from jointwear.study.io import provenance
from jointwear.study.limit_state import curve_cycles, life_interval

# the tests' analytic wear model (Archard's structure; its exact R(N) by brute force)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from analytic_wear import RATE, AnalyticWear  # noqa: E402

RATES_SERIES = {"A": 1.2e-10, "E": 1.0e-10}


def smooth_pf(model: AnalyticWear, x, levels, allowance):
    """Exact Pf at each level over the population x: wear = RATE N scale(x) above the allowance."""
    return np.mean(RATE * model.scale(x)[:, None] * levels[None, :] > allowance, axis=0)


class SeriesWear:
    """Joints A and E of the six-bar: q_j = RATE_j N k_j / 1e-4 (outputs joint after joint)."""

    def __init__(self, cycles):
        self.cycles = np.asarray(cycles, dtype=float)

    def __call__(self, x):
        x = np.atleast_1d(x)
        return np.concatenate([RATES_SERIES["A"] * self.cycles * x[0] / 1e-4,
                               RATES_SERIES["E"] * self.cycles * x[1] / 1e-4]), "ok"

    @staticmethod
    def pf(x, levels, allowance):
        n = levels[None, :]
        return np.mean((RATES_SERIES["A"] * n * x[:, :1] / 1e-4 > allowance)
                       | (RATES_SERIES["E"] * n * x[:, 1:] / 1e-4 > allowance), axis=0)


def smooth_config(seed: int):
    return updated(load_config(), {
        "reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [380_000, 420_000], "reliability.n_mc": 50_000, "reliability.noise": "none",
        "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002, "reliability.max_calls": 120,
        "reliability.seed": seed})


def series_config(seed: int, stopping: str = "error", surrogate: str = "per_joint", step: int = 50_000):
    name = "watt_six_bar_two_clearances"
    data = tomllib.loads((resources.files("jointwear.presets") / f"{name}.toml").read_text(encoding="utf-8"))
    data["uncertainty"] = {"variables": [
        {"name": "k_A", "target": "clearance_joints.A.bearing_material.wear_coefficient", "mean": 1e-4,
         "std": 1e-5, "group": "bearing_material"},
        {"name": "k_E", "target": "clearance_joints.E.bearing_material.wear_coefficient", "mean": 1e-4,
         "std": 1.5e-5, "group": "bearing_material"}]}
    data["reliability"] = {"allowance_mm": 0.03, "cycles_start": 100_000, "cycles_stop": 300_000 if step < 100_000
                           else 400_000, "cycles_step": step, "n_mc": 50_000, "noise": "none", "error_abs_tol": 0.002,
                           "max_calls": 60, "target_reliability": [0.9, 0.5], "seed": seed, "stopping": stopping,
                           "surrogate": surrogate}
    data.pop("sensitivity", None)
    return config_from_dict(data)


def one_run(case: str, seed: int, n_truth: int) -> dict:
    cfg = (smooth_config(seed) if case == "smooth" else
           series_config(seed, "u" if case.endswith("u_rule") else "error",
                         "system_life" if "system_life" in case else "per_joint",
                         100_000 if case.endswith("coarse") else 50_000))
    holder = {}

    def factory(call):
        holder["model"] = (AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
                           if case == "smooth" else SeriesWear(call.cycles))
        return compute.Evaluator(holder["model"], None, None, n_outputs=call.n_outputs)

    ctx = study_context(cfg, factory)
    t0 = time.perf_counter()
    res = run_reliability(ctx)
    wall = time.perf_counter() - t0
    x = population(ctx.marginals, n_truth, seed=10_000 + seed)
    fine = curve_cycles(np.asarray(res.cycles, dtype=float))
    pf_true = (smooth_pf(holder["model"], x, fine, cfg.reliability.allowance) if case == "smooth"
               else SeriesWear.pf(x, fine, cfg.reliability.allowance))
    rows = []
    for row in res.life_table:
        t = float(row["target"])
        truth = life_at(fine, 1.0 - pf_true, t)
        low, high = res.life_interval(t)
        life = row["cycles"]
        half = None if None in (low, high, life) else (high - low) / 2
        held = None if None in (low, high, truth) else bool(low <= truth <= high)
        miss = None if half is None or truth is None or not half else abs(truth - life) / half
        # the reading on straight lines between the levels (life and interval), for comparison
        s_low, s_high = life_interval(res.cycles, res.reliability, res.half_width, t)
        rows.append({"target": t, "life": life, "low": low, "high": high, "truth": truth, "held": held,
                     "miss_in_half_widths": miss, "straight_line_life": life_at(res.cycles, res.reliability, t),
                     "straight_line_low": s_low, "straight_line_high": s_high,
                     "straight_line_held": None if None in (s_low, s_high, truth) else bool(s_low <= truth <= s_high)})
    return {"seed": seed, "model_calls": int(res.model_calls), "converged": bool(res.converged),
            "wall_seconds": wall, "lives": rows}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--truth-samples", type=int, default=1_000_000)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "life_interval.json")
    args = ap.parse_args()
    load_before = os.getloadavg()[0]
    cases = {}
    for case in ("smooth", "series", "series_coarse", "series_system_life", "series_system_life_u_rule"):
        runs = [one_run(case, seed, args.truth_samples) for seed in range(args.seeds)]
        summary = {}
        for t in sorted({r["target"] for run in runs for r in run["lives"]}):
            rows = [r for run in runs for r in run["lives"] if r["target"] == t and r["held"] is not None]
            misses = [r["miss_in_half_widths"] for r in rows if r["miss_in_half_widths"] is not None]
            straight = [r["straight_line_held"] for r in rows if r.get("straight_line_held") is not None]
            summary[str(t)] = {"runs": len(rows), "held": sum(r["held"] for r in rows),
                               "straight_line_held": sum(straight),
                               "coverage": sum(r["held"] for r in rows) / len(rows) if rows else None,
                               "median_miss_in_half_widths": float(np.median(misses)) if misses else None,
                               "largest_miss_in_half_widths": float(np.max(misses)) if misses else None}
        cases[case] = {"summary": summary, "median_model_calls": float(np.median([r["model_calls"] for r in runs])),
                       "runs": runs}
        print(json.dumps({case: summary}))
    out = {"benchmark": "coverage of the life's 95 % interval on analytic wear models (exact R(N) by brute force)",
           "date_utc": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "seeds": args.seeds,
           "truth_samples": args.truth_samples, "machine": {"cpus": os.cpu_count(), **provenance()},
           "load_average_before": load_before, "cases": cases}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
