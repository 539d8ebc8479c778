"""Benchmark of the reliability engine (issue 4).

Writes JSON (default ``benchmarks/results/reliability.json``) with, per problem and AK-MCS mode, the median
and 90th percentile over seeds of the number of model calls and of the relative Pf error, against the
AK-MCS+U call counts of Echard, Gayton & Lemaire (2011, Struct. Saf. 33:145-154): four-branch k=6: 126,
k=7: 96, oscillator: 58, modified Rastrigin: 416 (their Monte Carlo populations: 1e6, 1e6, 7e4, 6e4).

Two errors are reported for every run:
* ``rel_err_ref``: |Pf / Pf_ref - 1| with the best reference available (exact quadrature for the four-branch
  system, 1e8-sample MCS for the others) - includes the Monte Carlo error of the population;
* ``rel_err_pop``: |Pf / Pf_MC - 1| with Pf_MC the true g on the *same* candidate population - the error
  of the surrogate classification alone, the accuracy Echard et al. report.

Plus the time to predict Kriging mean and variance on 1e6 points in 13-D with 100 training points (median of
repeats), and (``--kriging-libs``) a fit/predict/accuracy comparison of Kriging libraries.

Usage: python benchmarks/reliability.py [OUT.json] [--quick] [--seeds N] [--jobs J] [--problems ...]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

MODES = {
    # the engine's defaults, nothing overridden (the population is set to Echard's for the same MC accuracy)
    "default": dict(),
    # literally akmcs(g, marginals, seed=s): the engine's own population too (1e5, grown to a 5 % COV)
    "default_own_population": dict(n_mc=None),
    # the paper's algorithm: one point per iteration, stop when min U >= 2
    "paper_u": dict(stopping="u", batch_size=1),
    # ESC-type stop on the estimated relative error of Pf (tolerance 1 %)
    "error_1pct": dict(stopping="error", error_tol=0.01, batch_size=1),
    # same, 4 points per iteration (parallel model calls)
    "error_1pct_batch4": dict(stopping="error", error_tol=0.01, batch_size=4),
}


def _problem(name):
    from jointwear.reliability import problems as P

    return {"four_branch_k6": lambda: P.four_branch(6), "four_branch_k7": lambda: P.four_branch(7),
            "oscillator": P.oscillator, "rastrigin": P.rastrigin}[name]()


def run_one(task):
    name, mode, seed, n_mc = task
    from jointwear.reliability import akmcs
    from jointwear.reliability import IsoTransform

    p = _problem(name)
    t0 = time.perf_counter()
    kw = {"n_mc": n_mc, "max_calls": 1500, **MODES[mode]}
    if kw["n_mc"] is None:
        del kw["n_mc"], kw["max_calls"]
        n_mc = "default"
    r = akmcs(p.g, p.marginals, seed=seed, keep_population=True, **kw)
    wall = time.perf_counter() - t0
    u = r.details["population_u"]
    true_fail = p.g(IsoTransform(p.marginals).to_x(u)) < 0
    pf_pop = float(true_fail.mean())
    return {
        "problem": name, "mode": mode, "seed": seed, "n_calls": r.n_calls, "pf": r.pf, "cov": r.cov,
        "pf_population_mc": pf_pop, "rel_err_ref": abs(r.pf / p.pf_ref - 1.0),
        "rel_err_pop": abs(r.pf / pf_pop - 1.0) if pf_pop > 0 else None,
        "misclassified": int(np.count_nonzero(r.details["population_fail"][:, 0] != true_fail)),
        "n_mc_initial": n_mc, "n_mc": r.n_mc, "converged": r.converged, "iterations": len(r.history), "wall_seconds": wall,
    }


def prediction_speed(repeats=5, n_points=1_000_000, d=13, n_train=100):
    from jointwear.reliability import KrigingSurrogate

    rng = np.random.default_rng(0)
    x = rng.normal(size=(n_train, d)) * 2
    y = np.sin(x[:, 0]) + 0.3 * x[:, 1] ** 2 + 0.1 * x.sum(axis=1)
    k = KrigingSurrogate().fit(x, y)
    u = rng.normal(size=(n_points, d))
    out = {}
    for label, kw in {"default": {}, "one_thread": {"n_threads": 1}}.items():
        for key, val in kw.items():
            setattr(k, key, val)
        times, cpu = [], []
        for _ in range(repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            k.predict(u)
            times.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        # wall time depends on the other processes on the machine; CPU time (all threads) does not
        out[label] = {"median_s": float(np.median(times)), "min_s": float(np.min(times)),
                      "cpu_median_s": float(np.median(cpu)), "repeats": repeats,
                      "load_avg_1min": os.getloadavg()[0]}
    # OpenTURNS' own prediction on 1e4 points, extrapolated (x100) to 1e6
    import openturns as ot

    res = k.to_openturns()
    s = ot.Sample(u[:10_000])
    t0 = time.perf_counter()
    res.getMetaModel()(s)
    ot.GaussianProcessConditionalCovariance(res).getConditionalMarginalVariance(s)
    out["openturns_1e4_points_s"] = time.perf_counter() - t0
    out.update({"n_points": n_points, "dim": d, "n_train": n_train})
    return out


def kriging_libs():
    """Fit time, prediction time (1e5 points) and R^2 on a 13-D smooth function, n = 100 and 200."""
    rng = np.random.default_rng(1)
    d = 13

    def f(x):
        return np.sin(x[:, 0]) + 0.3 * x[:, 1] ** 2 + 0.5 * x[:, 2] * x[:, 3] + 0.1 * x.sum(axis=1)

    xt = rng.normal(size=(2000, d))
    yt = f(xt)
    big = rng.normal(size=(100_000, d))
    out = []
    for n in (100, 200):
        x = rng.normal(size=(n, d)) * 1.5
        y = f(x)
        from jointwear.reliability import KrigingSurrogate

        t0 = time.perf_counter()
        k = KrigingSurrogate(n_starts=3).fit(x, y)
        fit = time.perf_counter() - t0
        r2 = 1 - np.mean((k.predict(xt)[0] - yt) ** 2) / np.var(yt)
        t0 = time.perf_counter()
        k.predict(big)
        pred = time.perf_counter() - t0
        out.append({"library": "openturns fit + numpy predict (jointwear)", "n": n, "fit_s": fit,
                    "r2": float(r2), "predict_1e5_s": pred})
        try:
            from sklearn.gaussian_process import GaussianProcessRegressor
            from sklearn.gaussian_process.kernels import RBF, ConstantKernel

            kern = ConstantKernel(1.0) * RBF(np.ones(d), length_scale_bounds=(1e-2, 1e2))
            gp = GaussianProcessRegressor(kern, alpha=1e-10, normalize_y=True, n_restarts_optimizer=2,
                                          random_state=0)
            t0 = time.perf_counter()
            gp.fit(x, y)
            fit = time.perf_counter() - t0
            r2 = 1 - np.mean((gp.predict(xt) - yt) ** 2) / np.var(yt)
            t0 = time.perf_counter()
            gp.predict(big, return_std=True)
            pred = time.perf_counter() - t0
            out.append({"library": "scikit-learn GaussianProcessRegressor (ARD RBF, 2 restarts)", "n": n,
                        "fit_s": fit, "r2": float(r2), "predict_1e5_s": pred})
        except ImportError:
            out.append({"library": "scikit-learn", "n": n, "skipped": "not installed"})
    return out


def summarise(runs, echard):
    summary = {}
    for key in sorted({(r["problem"], r["mode"]) for r in runs}):
        rs = [r for r in runs if (r["problem"], r["mode"]) == key]
        calls = np.array([r["n_calls"] for r in rs], dtype=float)
        e_ref = np.array([r["rel_err_ref"] for r in rs])
        e_pop = np.array([r["rel_err_pop"] if r["rel_err_pop"] is not None else np.nan for r in rs])
        summary.setdefault(key[0], {})[key[1]] = {
            "seeds": len(rs), "n_mc_initial": sorted({r.get("n_mc_initial") for r in rs}, key=str),
            "n_calls_median": float(np.median(calls)), "n_calls_p90": float(np.percentile(calls, 90)),
            "n_calls_min": float(calls.min()), "n_calls_max": float(calls.max()),
            "rel_err_ref_max": float(np.max(e_ref)), "rel_err_pop_max": float(np.nanmax(e_pop)),
            "rel_err_ref_median": float(np.median(e_ref)), "rel_err_ref_p90": float(np.percentile(e_ref, 90)),
            "rel_err_pop_median": float(np.nanmedian(e_pop)), "rel_err_pop_p90": float(np.nanpercentile(e_pop, 90)),
            "pf_median": float(np.median([r["pf"] for r in rs])),
            "converged": int(sum(r["converged"] for r in rs)),
            "wall_seconds_median": float(np.median([r["wall_seconds"] for r in rs])),
            "echard_2011_ak_mcs_u_calls": echard.get(key[0]),
        }
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", nargs="?", default=os.path.join(os.path.dirname(__file__), "results", "reliability.json"))
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--problems", nargs="*", default=["four_branch_k6", "four_branch_k7", "oscillator", "rastrigin"])
    ap.add_argument("--modes", nargs="*", default=list(MODES))
    ap.add_argument("--quick", action="store_true",
                    help="four-branch population 2e5 instead of Echard's 1e6 (cheaper sweeps; COV 3.3 %%)")
    ap.add_argument("--kriging-libs", action="store_true", help="also compare Kriging libraries")
    ap.add_argument("--no-speed", action="store_true")
    ap.add_argument("--append", action="store_true", help="merge with the runs already in OUT (other problems or modes)")
    args = ap.parse_args(argv)


    n_mc = {"four_branch_k6": 1_000_000, "four_branch_k7": 1_000_000, "oscillator": 70_000, "rastrigin": 60_000}
    if args.quick:
        n_mc["four_branch_k6"] = n_mc["four_branch_k7"] = 200_000
    echard = {"four_branch_k6": 126, "four_branch_k7": 96, "oscillator": 58, "rastrigin": 416}
    refs = {name: {"pf_ref": _problem(name).pf_ref, "source": _problem(name).ref_source} for name in args.problems}
    tasks = [(p, m, s, n_mc[p]) for p in args.problems for m in args.modes for s in range(args.seeds)]
    t0 = time.perf_counter()
    runs = []
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            for r in pool.map(run_one, tasks):
                runs.append(r)
                print(json.dumps(r), flush=True)
    else:
        for t in tasks:
            r = run_one(t)
            runs.append(r)
            print(json.dumps(r), flush=True)
    settings = {"n_mc": {p: n_mc[p] for p in args.problems}, "seeds": {p: args.seeds for p in args.problems},
                "modes": MODES, "quick": {p: args.quick for p in args.problems}}
    old = None
    if args.append and os.path.exists(args.out):
        with open(args.out) as fh:
            old = json.load(fh)
        keep = [r for r in old["runs"] if r["problem"] not in args.problems or r["mode"] not in args.modes]
        runs = keep + runs
        for key in ("n_mc", "seeds", "quick"):
            settings[key] = {**old["settings"].get(key, {}), **settings[key]}
        refs = {**old.get("references", {}), **refs}
    result = {
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "cpus": os.cpu_count(),
                    "load_avg_at_start": os.getloadavg()},
        "settings": settings,
        "references": refs,
        "summary": summarise(runs, echard),
        "runs": runs,
        "wall_seconds": time.perf_counter() - t0,
    }
    if old is not None:
        for key in ("prediction_speed_13d_n100_1e6", "kriging_libraries"):
            if key in old:
                result[key] = old[key]
    if not args.no_speed:
        result["prediction_speed_13d_n100_1e6"] = prediction_speed()
    if args.kriging_libs:
        result["kriging_libraries"] = kriging_libs()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=1, default=float)
    print(json.dumps(result["summary"], indent=1))
    return result


if __name__ == "__main__":
    main()
