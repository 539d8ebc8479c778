"""Benchmark of the dynamics stage: wall time per crank cycle of the flapping-wing preset.

Writes benchmarks/results/dynamics.json. Run: python benchmarks/dynamics.py [--repeats 5] [--no-scipy]

- compiled: jointwear.mechanism.simulate (numba Dormand-Prince 5(4)), after compilation, from a
  settled state, median over repeats of one recorded cycle;
- scipy: the same cycle (same state, tolerances and equations) by scipy.integrate.solve_ivp(RK45)
  with (a) the compiled right-hand side called from Python, (b) a pure-Python right-hand side
  (the kernel's Python source, numba bypassed).  The contact memory (impact speed v0) is frozen at
  its settled value in the scipy runs (no per-step bookkeeping hook in solve_ivp);
- cartesian_kernel (skip with --no-cartesian): the general Cartesian kernel (kernel.rhs), which runs every
  mechanism but the flapping wing: the six-bar preset watt_six_bar_two_clearances (one cycle from a settled
  state) and the flapping wing forced onto it (fast=False), medians over the repeats.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np


@contextlib.contextmanager
def numba_bypassed():
    """Within the block every compiled function of the kernel and of the contact laws is its Python source
    (``py_func``): the pure-Python right-hand side of the scipy comparison. Restored on exit."""
    import jointwear.contact.laws as L
    from jointwear.mechanism import kernel as K

    saved = [(mod, name, obj) for mod in (K, L) for name, obj in vars(mod).items() if hasattr(obj, "py_func")]
    try:
        for mod, name, obj in saved:
            setattr(mod, name, obj.py_func)
        yield
    finally:
        for mod, name, obj in saved:
            setattr(mod, name, obj)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--no-scipy", action="store_true")
    ap.add_argument("--no-cartesian", action="store_true", help="skip the Cartesian-kernel timings")
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "dynamics.json"))
    args = ap.parse_args()

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import _Runner

    cfg = load_config("jin2025_flapping_wing")
    model = build_model(cfg)
    t0 = time.perf_counter()
    simulate(model, 0.01, settle_cycles=0)
    first_call = time.perf_counter() - t0
    settled = simulate(model, 0.0, settle_cycles=model.settings.settle_cycles)
    state = settled.state_end
    # reference in the same process (this VM's speed drifts by ~1.4x between runs): the same step loop compiled
    # with numba's reference counting, as before session 3 (kernel.STEP_LOOP_NRT)
    from numba import njit

    refcounted = njit(nogil=True, error_model="numpy", fastmath=K.FASTMATH)(K.integrate.py_func)
    fast_loop = K.integrate
    K.integrate = refcounted
    simulate(model, 0.01, settle_cycles=0, state0=state)  # compile
    K.integrate = fast_loop
    ref_walls = []
    walls, cpus, steps, rejected, before_packaging = [], [], [], [], []
    for _ in range(args.repeats):
        K.integrate = refcounted
        w0 = time.perf_counter()
        simulate(model, 1, settle_cycles=0, state0=state)
        ref_walls.append(time.perf_counter() - w0)
        K.integrate = fast_loop
        c0 = time.process_time()
        w0 = time.perf_counter()
        r = simulate(model, 1, settle_cycles=0, state0=state)
        walls.append(time.perf_counter() - w0)  # the whole call, result object included
        cpus.append(time.process_time() - c0)
        before_packaging.append(r.wall_seconds)  # simulate's own clock stops before the result is packaged
        steps.append(r.n_recorded_steps)
        rejected.append(r.n_rejected)
    tr = r.joints[0]
    out = {
        "preset": "jin2025_flapping_wing",
        "machine": {"cpus": os.cpu_count(), "python": sys.version.split()[0], "platform": platform.platform(),
                    "llvm_host_cpu": _host_cpu(),
                    "loadavg_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None},
        "rtol": model.settings.rtol, "atol_m": model.settings.atol,
        "first_call_seconds_incl_compile_or_cache_load": first_call,
        "wall_seconds_per_cycle_median": statistics.median(walls),
        "wall_seconds_per_cycle_all": walls,
        "wall_seconds_per_cycle_before_packaging_median": statistics.median(before_packaging),
        "cpu_seconds_per_cycle_median": statistics.median(cpus),
        "note": "wall time of the whole simulate() call; inflated when other work loads the machine (see "
                "loadavg_1min; this VM's speed also drifts by ~1.4x between runs); CPU time is the process's own",
        "reference_refcounted_loop_wall_seconds_per_cycle_median": statistics.median(ref_walls),
        "ratio_to_refcounted_loop_same_process": statistics.median(walls) / statistics.median(ref_walls),
        "steps_per_cycle": statistics.median(steps),
        "rejected_steps_per_cycle": statistics.median(rejected),
        "microseconds_per_step": statistics.median(walls) / statistics.median(steps) * 1e6,
        "contact_force_mean_N": tr.mean_force,
        "contact_force_max_N": float(tr.contact_force.max()),
        "contact_fraction": tr.contact_fraction,
        "impacts_per_cycle": tr.n_impacts,
    }
    if not args.no_cartesian:
        out["cartesian_kernel"] = _cartesian_kernel(model, state, statistics.median(walls), args.repeats)
    # the experimental implicit option (simulation.method = "radau5") on the same cycle, rtol 1e-5
    import dataclasses

    rad = dataclasses.replace(model, settings=dataclasses.replace(model.settings, method="radau5"))
    simulate(rad, 0.05, settle_cycles=0, state0=state, rtol=1e-5, atol=1e-8)  # compile
    rwalls, rsteps = [], []
    for _ in range(max(1, args.repeats // 2)):
        w0 = time.perf_counter()
        rr = simulate(rad, 1, settle_cycles=0, state0=state, rtol=1e-5, atol=1e-8)
        rwalls.append(time.perf_counter() - w0)
        rsteps.append(rr.n_recorded_steps)
    rtr = rr.joints[0]
    out["radau5_rtol_1e-5"] = {"wall_seconds_per_cycle_median": statistics.median(rwalls),
                               "steps_per_cycle": statistics.median(rsteps), "rejected_steps": rr.n_rejected,
                               "contact_force_mean_N": rtr.mean_force, "impacts_per_cycle": rtr.n_impacts,
                               "ratio_to_dopri5": statistics.median(rwalls) / statistics.median(walls)}
    if not args.no_scipy:
        from scipy.integrate import solve_ivp

        run = _Runner(model, None, model.settings.rtol, model.settings.atol)
        run.a["cstate"][:] = state.cstate
        a = run._args()
        y0 = run.to_internal(state.y)
        dy = np.zeros((7, run.ny))
        period = model.period
        atolv = run.atolv
        mode = run.mode
        _, _, _, dpar, _, jpar, cint, cpar, prof, ngrid, cstate, baum = a[:12]
        lam, cout = a[18], a[20]

        def make_f(rhs_func, fourbar):
            if fourbar:
                def f(t, y):
                    rhs_func(t, y[None, :], 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
                    return dy[0].copy()
            else:
                def f(t, y):
                    rhs_func(t, y, dy, 0, *a)
                    return dy[0].copy()
            return f

        rhs_name = "rhs_fourbar" if mode == 1 else "rhs"
        make_f(getattr(K, rhs_name), mode == 1)(state.t, y0)  # compile / load the standalone entry, untimed
        tt, cc = time.perf_counter(), time.process_time()
        sol = solve_ivp(make_f(getattr(K, rhs_name), mode == 1), (state.t, state.t + period), y0, method="RK45",
                        rtol=model.settings.rtol, atol=atolv, max_step=period / 200)
        w_c, c_c = time.perf_counter() - tt, time.process_time() - cc
        out["kernel"] = "natural_fourbar" if mode == 1 else "cartesian"
        out["scipy_rk45_compiled_rhs"] = {"wall_seconds_per_cycle": w_c, "cpu_seconds_per_cycle": c_c,
                                          "steps": int(sol.t.size - 1),
                                          "nfev": int(sol.nfev), "status": int(sol.status)}
        # pure Python right-hand side: the kernel's own Python source with numba bypassed
        with numba_bypassed():
            tt, cc = time.perf_counter(), time.process_time()
            sol = solve_ivp(make_f(getattr(K, rhs_name), mode == 1), (state.t, state.t + period), y0,
                            method="RK45", rtol=model.settings.rtol, atol=atolv, max_step=period / 200)
            w_p, c_p = time.perf_counter() - tt, time.process_time() - cc
        out["scipy_rk45_python_rhs"] = {"wall_seconds_per_cycle": w_p, "cpu_seconds_per_cycle": c_p,
                                        "steps": int(sol.t.size - 1),
                                        "nfev": int(sol.nfev), "status": int(sol.status)}
        out["speedup_vs_scipy_python_rhs"] = w_p / out["wall_seconds_per_cycle_median"]
        out["speedup_vs_scipy_compiled_rhs"] = w_c / out["wall_seconds_per_cycle_median"]
        out["cpu_speedup_vs_scipy_python_rhs"] = c_p / out["cpu_seconds_per_cycle_median"]
        out["cpu_speedup_vs_scipy_compiled_rhs"] = c_c / out["cpu_seconds_per_cycle_median"]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))


def _host_cpu() -> str:
    """The CPU numba compiles for (the kernels' instructions, hence their speed and rounding, depend on it)."""
    import llvmlite.binding as llvm

    return str(llvm.get_host_cpu_name())


def _cartesian_kernel(fw_model, fw_state, fw_fast_wall: float, repeats: int) -> dict:
    """The general Cartesian kernel (kernel.rhs, mode 0 of kernel.integrate): wall time per crank cycle of the
    six-bar preset (two clearance joints, 4 free bodies) from a settled state, and of the flapping wing forced onto
    it (fast=False) from the fast path's settled state; medians over the repeats, the two alternated."""
    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate

    six = build_model(load_config("watt_six_bar_two_clearances"))
    six_state = simulate(six, 0.0, settle_cycles=six.settings.settle_cycles).state_end
    cases = {"six_bar": (six, six_state, None), "flapping_wing_fast_false": (fw_model, fw_state, False)}
    presets = {"six_bar": "watt_six_bar_two_clearances", "flapping_wing_fast_false": "jin2025_flapping_wing"}
    for m, st, fast in cases.values():  # compile / load from numba's cache and fill the record pool, untimed
        simulate(m, 1, settle_cycles=0, state0=st, fast=fast)
    walls = {k: [] for k in cases}
    last = {}
    for _ in range(repeats):
        for name, (m, st, fast) in cases.items():
            w0 = time.perf_counter()
            last[name] = simulate(m, 1, settle_cycles=0, state0=st, fast=fast)
            walls[name].append(time.perf_counter() - w0)
    out = {}
    for name in cases:
        r = last[name]
        med = statistics.median(walls[name])
        out[name] = {"preset": presets[name],
                     "wall_seconds_per_cycle_median": med, "wall_seconds_per_cycle_all": walls[name],
                     "steps_per_cycle": r.n_recorded_steps, "rejected_steps_per_cycle": r.n_rejected,
                     "microseconds_per_step": med / r.n_recorded_steps * 1e6,
                     "contact_force_mean_N": [tr.mean_force for tr in r.joints],
                     "impacts_per_cycle": [tr.n_impacts for tr in r.joints]}
    out["flapping_wing_fast_false"]["ratio_to_fast_kernel"] = (
        out["flapping_wing_fast_false"]["wall_seconds_per_cycle_median"] / fw_fast_wall)
    return out


if __name__ == "__main__":
    main()
