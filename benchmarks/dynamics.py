"""Benchmark of the dynamics stage: wall time per crank cycle of the flapping-wing preset.

Writes benchmarks/results/dynamics.json. Run: python benchmarks/dynamics.py [--repeats 5] [--no-scipy]

- compiled: jointwear.mechanism.simulate (numba Dormand-Prince 5(4)), after compilation, from a
  settled state, median over repeats of one recorded cycle;
- scipy: the same cycle (same state, tolerances and equations) by scipy.integrate.solve_ivp(RK45)
  with (a) the compiled right-hand side called from Python, (b) a pure-Python right-hand side
  (the kernel's Python source, numba bypassed).  The contact memory (impact speed v0) is frozen at
  its settled value in the scipy runs (no per-step bookkeeping hook in solve_ivp);
- cartesian_kernel (skip with --no-cartesian): the general kernels on the six-bar preset watt_six_bar_two_clearances
  (one cycle from a settled state): the tree kernel specialised to the six-bar's shape (jointwear.mechanism.
  tree_codegen, the default for it), the general tree kernel (kernel.integrate_tree with kernel.rhs_tree) and the
  Cartesian kernel (kernel.rhs, fast=False), and the flapping wing forced onto the Cartesian kernel; medians over the
  repeats, alternated with the fast path in the same process. Per step: the whole simulate() call and the
  integration loop alone, against the fast path's loop (goal: six-bar <= 2.5x per step);
- rhs_ns_per_evaluation: ns per right-hand side, each evaluation waiting for the previous one, for the fast path,
  the six-bar's specialised and general tree kernels and its Cartesian kernel, alternated in the same process;
- six_bar_specialised: two cycles from a settled state on the specialised and the general tree kernel, and the
  specialised one after a 1-ulp nudge of an angle: mean and peak force and one cycle's wear per joint;
- six_bar_l_stable: the steps an L-stable method needs for the same accuracy (Radau IIA, simulation.method =
  "radau5"; a tree linkage now runs it on the Cartesian kernel) and what a cycle costs with it, against the default;
- six_bar_steps: what sets the six-bar's steps per cycle: steps against rtol, the clearance step limiter, the
  stiffest eigenvalues of the Jacobian along the cycle times the step size (Dormand-Prince is stable for
  |h lambda| up to ~3.3 on the negative real axis);
- six_bar_accuracy: cycle statistics per joint at the default tolerance, after a 1-ulp nudge of an angle of the start
  state, and at rtol 1e-9 on both kernels;
- six_bar_wear_call (skip with --no-wear): one wear-history model call of the six-bar study, wear_history(
  build_model(cfg), cfg.wear, 300_000) with the preset's wear settings: wall and CPU seconds, on the tree kernel and
  (--wear-cartesian) on the Cartesian kernel; 60 such calls on 2 workers extrapolated from the CPU seconds.
"""

from __future__ import annotations

import argparse
import math
import contextlib
import datetime
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
    ap.add_argument("--no-cartesian", action="store_true", help="skip the general-kernel (six-bar) measurements")
    ap.add_argument("--no-wear", action="store_true", help="skip the six-bar wear-history call")
    ap.add_argument("--wear-cartesian", action="store_true", help="also time the wear call on the Cartesian kernel")
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "dynamics.json"))
    args = ap.parse_args()

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import Runner

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

    fast_loops = K.INTEGRATORS
    refcounted = tuple(njit(nogil=True, error_model="numpy", fastmath=K.FASTMATH)(f.py_func) for f in fast_loops)
    K.INTEGRATORS = refcounted
    simulate(model, 0.01, settle_cycles=0, state0=state)  # compile
    K.INTEGRATORS = fast_loops
    ref_walls = []
    walls, cpus, steps, rejected, before_packaging = [], [], [], [], []
    for _ in range(args.repeats):
        K.INTEGRATORS = refcounted
        w0 = time.perf_counter()
        simulate(model, 1, settle_cycles=0, state0=state)
        ref_walls.append(time.perf_counter() - w0)
        K.INTEGRATORS = fast_loops
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
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
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
        out["rhs_ns_per_evaluation"] = _rhs_ns(model, state, args.repeats)
        out["six_bar_steps"] = _six_bar_steps()
        out["six_bar_accuracy"] = _six_bar_accuracy()
        out["six_bar_specialised"] = _six_bar_specialised()
        out["six_bar_l_stable"] = _six_bar_l_stable()
    if not args.no_wear:
        out["six_bar_wear_call"] = _six_bar_wear_call(args.wear_cartesian)
    # the experimental implicit option (simulation.method = "radau5") on the same cycle, rtol 1e-5
    import dataclasses

    rad = dataclasses.replace(model, settings=model.settings.model_copy(update={"method": "radau5"}))
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

        run = Runner(model, None, model.settings.rtol, model.settings.atol)
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


def _loop_timer(model, state, fast, general_tree: bool = False):
    """A function timing one cycle of the integration loop alone (nothing recorded) from `state` on the kernel that
    simulate(fast=fast) picks (general_tree: the general tree loop kernel.integrate_tree instead of the one specialised to
    the shape): returns (seconds, accepted steps, rejected steps)."""
    import math

    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import Runner

    run = Runner(model, None, model.settings.rtol, model.settings.atol, fast)
    if general_tree:
        run.integrate = K.integrate_tree
    y0 = run.to_internal(state.y)
    hmax = model.settings.max_step or model.period / 200.0
    buf = run.buffers(1)

    def once():
        run.a["cstate"][:] = state.cstate
        y = y0.copy()
        run.eval(state.t, y)
        counters = np.zeros(4, dtype=np.int64)
        w0 = time.perf_counter()
        run.run(state.t, y, state.t + model.period, state.h, hmax, math.inf, buf, 10**9, counters)
        return time.perf_counter() - w0, int(counters[1]), int(counters[2])

    return once


def _cartesian_kernel(fw_model, fw_state, fw_fast_wall: float, repeats: int) -> dict:
    """The general kernels on the six-bar preset (two clearance joints, 4 free bodies) from a settled state: the tree
    kernel (its default) and the Cartesian kernel (fast=False), and the flapping wing forced onto the Cartesian kernel
    from the fast path's settled state; the whole simulate() call and the integration loop alone, alternated with the
    fast path's loop in the same process; medians over the repeats."""
    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate

    six = build_model(load_config("watt_six_bar_two_clearances"))
    six_state = simulate(six, 0.0, settle_cycles=six.settings.settle_cycles).state_end
    cases = {"six_bar_tree": (six, six_state, None), "six_bar": (six, six_state, False),
             "flapping_wing_fast_false": (fw_model, fw_state, False)}
    presets = {"six_bar_tree": "watt_six_bar_two_clearances", "six_bar": "watt_six_bar_two_clearances",
               "flapping_wing_fast_false": "jin2025_flapping_wing"}
    loops = {name: _loop_timer(m, st, fast) for name, (m, st, fast) in cases.items()}
    loops["six_bar_tree_general"] = _loop_timer(six, six_state, None, general_tree=True)
    loops["fast_path"] = _loop_timer(fw_model, fw_state, None)
    for m, st, fast in cases.values():  # compile / load from numba's cache and fill the record pool, untimed
        simulate(m, 1, settle_cycles=0, state0=st, fast=fast)
    for f in loops.values():
        f()
    walls = {k: [] for k in cases}
    loop_runs = {k: [] for k in loops}
    last = {}
    for _ in range(repeats):
        for name, (m, st, fast) in cases.items():
            w0 = time.perf_counter()
            last[name] = simulate(m, 1, settle_cycles=0, state0=st, fast=fast)
            walls[name].append(time.perf_counter() - w0)
        for name, f in loops.items():
            loop_runs[name].append(f())
    loop_ns = {k: statistics.median(w / n for w, n, _ in v) * 1e9 for k, v in loop_runs.items()}
    out = {"fast_path_loop_ns_per_step": loop_ns["fast_path"],
           "fast_path_loop_steps_per_cycle": loop_runs["fast_path"][0][1]}
    for name in cases:
        r = last[name]
        med = statistics.median(walls[name])
        out[name] = {"preset": presets[name], "kernel": r.extra["kernel"],
                     "wall_seconds_per_cycle_median": med, "wall_seconds_per_cycle_all": walls[name],
                     "steps_per_cycle": r.n_recorded_steps, "rejected_steps_per_cycle": r.n_rejected,
                     "microseconds_per_step": med / r.n_recorded_steps * 1e6,
                     "loop_ns_per_step": loop_ns[name],
                     "loop_seconds_per_cycle_median": statistics.median(w for w, _, _ in loop_runs[name]),
                     "loop_ratio_per_step_to_fast_path": loop_ns[name] / loop_ns["fast_path"],
                     "contact_force_mean_N": [tr.mean_force for tr in r.joints],
                     "impacts_per_cycle": [tr.n_impacts for tr in r.joints],
                     "max_penetration_m": [float(tr.penetration.max()) for tr in r.joints]}
    out["flapping_wing_fast_false"]["ratio_to_fast_kernel"] = (
        out["flapping_wing_fast_false"]["wall_seconds_per_cycle_median"] / fw_fast_wall)
    out["six_bar_tree"]["ratio_per_cycle_to_cartesian"] = (
        out["six_bar_tree"]["wall_seconds_per_cycle_median"] / out["six_bar"]["wall_seconds_per_cycle_median"])
    out["six_bar_tree_general"] = {
        "kernel": "tree, general loop (kernel.integrate_tree, kernel.rhs_tree)",
        "steps_per_cycle": loop_runs["six_bar_tree_general"][0][1],
        "loop_ns_per_step": loop_ns["six_bar_tree_general"],
        "loop_ratio_per_step_to_fast_path": loop_ns["six_bar_tree_general"] / loop_ns["fast_path"],
        "loop_ratio_specialised_to_general": loop_ns["six_bar_tree"] / loop_ns["six_bar_tree_general"]}
    out["goal"] = "six-bar loop ns per step <= 2.5 x the fast path's (six_bar_tree.loop_ratio_per_step_to_fast_path)"
    return out


def _rhs_ns(fw_model, fw_state, repeats: int) -> dict:
    """ns per right-hand-side evaluation, each waiting for the previous one (as the stages of a step do): the fast
    path's rhs_fourbar_cs on the flapping wing, the six-bar's tree kernel (rhs_tree) and Cartesian kernel (rhs), at
    settled states, alternated in the same process; medians over the repeats."""
    from numba import njit

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import Runner

    @njit(error_model="numpy", fastmath=K.FASTMATH, _nrt=False)
    def chain_fast(n, t, Y, dy, dpar, fp, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
        acc = 0.0
        y0 = Y[0, 0]
        th = dpar[0, 4] + dpar[0, 5] * t
        c, sn = math.cos(th), math.sin(th)
        for _ in range(n):
            Y[0, 0] = y0 + 1e-30 * acc  # the next input depends on this output
            K.rhs_fourbar_cs(c, sn, Y, 0, dy, 0, dpar, fp, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
            acc = dy[0, 4]
        Y[0, 0] = y0
        return acc

    @njit(error_model="numpy", fastmath=K.FASTMATH, _nrt=False)
    def chain_tree(n, t, y, yb, dy, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                   kin, cb, sb, cacc, jt, mm, gq, f, cout):
        acc = 0.0
        y0 = y[0]
        K.tree_base(t, yb, jint, dpar, kin, cb, sb)
        for _ in range(n):
            y[0] = y0 + 1e-30 * acc
            K.rhs_tree(t, 0.0, y, yb, dy, 0, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                       kin, cb, sb, cacc, jt, mm, gq, f, cout)
            acc = dy[0, y.shape[0] // 2]
        y[0] = y0
        return acc

    @njit(error_model="numpy", _nrt=False)
    def chain_cart(n, t, y, dy, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                   kin, phi_, phid, rest, jac, smat, lam, f, cout):
        acc = 0.0
        y0 = y[0]
        for _ in range(n):
            y[0] = y0 + 1e-30 * acc
            K.rhs(t, y, dy, 0, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                  kin, phi_, phid, rest, jac, smat, lam, f, cout)
            acc = dy[0, y.shape[0] // 2]
        y[0] = y0
        return acc

    @njit(error_model="numpy", fastmath=K.FASTMATH, _nrt=False)
    def chain_spec(n, rhs_spec, t, y, yb, dy, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                   kin, cb, sb, cacc, jt, mm, gq, f, cout):
        acc = 0.0
        y0 = y[0]
        K.tree_base(t, yb, jint, dpar, kin, cb, sb)
        for _ in range(n):
            y[0] = y0 + 1e-30 * acc
            rhs_spec(t, 0.0, y, yb, dy, 0, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                     kin, cb, sb, cacc, jt, mm, gq, f, cout)
            acc = dy[0, y.shape[0] // 2]
        y[0] = y0
        return acc

    from jointwear.mechanism.tree_codegen import specialised_module

    six = build_model(load_config("watt_six_bar_two_clearances"))
    st = simulate(six, 0.0).state_end
    fw = Runner(fw_model, None, 1e-6, 1e-9)
    fw.a["cstate"][:] = fw_state.cstate
    af = fw._args()
    yf = fw.to_internal(fw_state.y)[None, :].copy()
    tr = Runner(six, None, 1e-6, 1e-9)
    tr.a["cstate"][:] = st.cstate
    yt = tr.to_internal(st.y)
    ca = Runner(six, None, 1e-6, 1e-9, fast=False)
    ca.a["cstate"][:] = st.cstate
    yc = np.array(st.y)
    at, ac = tr._args(), ca._args()
    spec = specialised_module(tr.tree, tr.a["dpar"].shape[0], tr.a["cint"]).rhs_spec
    cases = {
        "fast_path": lambda n: chain_fast(n, fw_state.t, yf, np.zeros((1, 8)), af[3], af[5], *af[6:12], af[18], af[20]),
        "six_bar_tree": lambda n: chain_spec(n, spec, st.t, yt.copy(), yt, np.zeros((1, yt.size)), *at[0:11],
                                             *at[12:21]),
        "six_bar_tree_general": lambda n: chain_tree(n, st.t, yt.copy(), yt, np.zeros((1, yt.size)), *at[0:11],
                                                     *at[12:21]),
        "six_bar_cartesian": lambda n: chain_cart(n, st.t, yc.copy(), np.zeros((1, yc.size)), *ac),
    }
    for f in cases.values():
        f(10)  # compile
    n = 100_000
    ns = {k: [] for k in cases}
    for _ in range(repeats):
        for k, f in cases.items():
            w0 = time.perf_counter()
            f(n)
            ns[k].append((time.perf_counter() - w0) / n * 1e9)
    out = {k: statistics.median(v) for k, v in ns.items()}
    out["six_bar_tree_ratio_to_fast_path"] = out["six_bar_tree"] / out["fast_path"]
    out["six_bar_tree_general_ratio_to_fast_path"] = out["six_bar_tree_general"] / out["fast_path"]
    out["six_bar_cartesian_ratio_to_fast_path"] = out["six_bar_cartesian"] / out["fast_path"]
    return out


def _six_bar_steps() -> dict:
    """What sets the six-bar's steps per cycle (tree kernel, one cycle from a settled state)."""
    import dataclasses

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism.simulate import Runner

    six = build_model(load_config("watt_six_bar_two_clearances"))
    st = simulate(six, 0.0).state_end
    s = six.settings
    out: dict = {"steps_vs_rtol": []}
    for rtol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8):
        r = simulate(six, 1, settle_cycles=0, state0=st, rtol=rtol, atol=s.atol * rtol / s.rtol)
        out["steps_vs_rtol"].append({"rtol": rtol, "steps": r.n_recorded_steps, "rejected": r.n_rejected,
                                     "contact_force_mean_N": [tr.mean_force for tr in r.joints]})
    base = simulate(six, 1, settle_cycles=0, state0=st)
    out["clearance_step_fraction"] = []
    for cf in (0.05, s.clearance_step_fraction, 1.0):
        m = dataclasses.replace(six, settings=s.model_copy(update={"clearance_step_fraction": cf}))
        r = simulate(m, 1, settle_cycles=0, state0=st)
        out["clearance_step_fraction"].append({"value": cf, "steps": r.n_recorded_steps})
    # stiffest eigenvalues of the Jacobian of the Cartesian right-hand side (central differences) along the cycle
    run = Runner(six, None, s.rtol, s.atol, fast=False)
    run.a["cstate"][:] = base.state_end.cstate
    Y = np.column_stack([base.q, base.qd])
    h = np.diff(base.t)
    modes = []
    for i in np.linspace(0, base.t.size - 2, 9).astype(int)[1:-1]:
        y0, t0 = Y[i], base.t[i]
        n = y0.size
        jm = np.zeros((n, n))
        for j in range(n):
            d = 1e-7 * max(abs(y0[j]), 1e-3 if j < n // 2 else 1e-2)
            yp, ym = y0.copy(), y0.copy()
            yp[j] += d
            ym[j] -= d
            run.eval(t0, yp)
            fp = run.ks[0].copy()
            run.eval(t0, ym)
            jm[:, j] = (fp - run.ks[0]) / (2 * d)
        ev = np.linalg.eigvals(jm)
        ev = ev[np.argsort(-np.abs(ev))][:4]
        hloc = float(np.median(h[max(i - 50, 0): i + 50]))
        modes.append({"t": float(t0), "h_median_local": hloc, "eigenvalues_re_im": [[z.real, z.imag] for z in ev],
                      "h_times_abs_lambda_max": hloc * float(np.abs(ev[0]))})
    out["stiffest_modes"] = modes
    out["note"] = ("Dormand-Prince's stability boundary is |h lambda| ~ 3.3 on the negative real axis and less along "
                   "the lightly damped directions: the step follows the contact modes (h |lambda| 1.5-3.4), not the "
                   "tolerance (100x looser rtol: 1.4x fewer steps); the clearance step limiter never binds")
    return out


def _six_bar_accuracy() -> dict:
    """Cycle statistics per joint, two cycles from a settled state: the tree kernel at the default tolerance, after a
    1-ulp nudge of the first tree coordinate (an angle), and the tree and Cartesian kernels at rtol 1e-9."""
    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism.simulate import SimulationState

    six = build_model(load_config("watt_six_bar_two_clearances"))
    st = simulate(six, 0.0).state_end
    y = st.y.copy()
    y[2] = np.nextafter(y[2], np.inf)  # the coupler's angle
    nudged = SimulationState(st.t, y, st.cstate.copy(), st.h)
    runs = {"tree_default": dict(state0=st), "tree_default_nudged_1ulp": dict(state0=nudged),
            "cartesian_default": dict(state0=st, fast=False),
            "cartesian_default_nudged_1ulp": dict(state0=nudged, fast=False),
            "tree_rtol_1e-9": dict(state0=st, rtol=1e-9, atol=1e-12),
            "cartesian_rtol_1e-9": dict(state0=st, rtol=1e-9, atol=1e-12, fast=False)}
    out = {}
    for name, kw in runs.items():
        r = simulate(six, 2, settle_cycles=0, **kw)
        out[name] = {"kernel": r.extra["kernel"], "steps_per_cycle": r.steps_per_cycle,
                     "contact_force_mean_N": [tr.mean_force for tr in r.joints],
                     "impacts": [tr.n_impacts for tr in r.joints],
                     "max_penetration_m": [float(tr.penetration.max()) for tr in r.joints]}
    ref = out["cartesian_rtol_1e-9"]
    for name in runs:
        out[name]["mean_force_rel_to_cartesian_rtol_1e-9"] = [
            a / b - 1 for a, b in zip(out[name]["contact_force_mean_N"], ref["contact_force_mean_N"])]
        out[name]["max_penetration_rel_to_cartesian_rtol_1e-9"] = [
            a / b - 1 for a, b in zip(out[name]["max_penetration_m"], ref["max_penetration_m"])]
    return out


def _six_bar_specialised() -> dict:
    """Two cycles from a settled state on the specialised tree kernel (simulate's default), on the general tree loop
    (kernel.integrate_tree, kernel.rhs_tree), and on the specialised one after a 1-ulp nudge of the coupler's angle: mean
    and peak normal force and one cycle's wear (the preset's wear settings, uniform mode) per joint, relative to the
    general loop."""
    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import Runner, SimulationState
    from jointwear.wear.history import cycle_wear

    cfg = load_config("watt_six_bar_two_clearances")
    six = build_model(cfg)
    st = simulate(six, 0.0).state_end
    y = st.y.copy()
    y[2] = np.nextafter(y[2], np.inf)
    nudged = SimulationState(st.t, y, st.cstate.copy(), st.h)
    orig = Runner.__init__

    def general_init(self, *a, **kw):
        orig(self, *a, **kw)
        self.integrate = K.integrate_tree

    runs = {}
    for name, state0, general in (("general", st, True), ("specialised", st, False),
                                  ("specialised_nudged_1ulp", nudged, False)):
        Runner.__init__ = general_init if general else orig
        try:
            r = simulate(six, 2, settle_cycles=0, state0=state0)
        finally:
            Runner.__init__ = orig
        cws = [cycle_wear(tr, cfg.wear, r.n_cycles) for tr in r.joints]
        runs[name] = {"steps_per_cycle": r.steps_per_cycle,
                      "contact_force_mean_N": [tr.mean_force for tr in r.joints],
                      "contact_force_max_N": [float(tr.force_normal.max()) for tr in r.joints],
                      "bearing_wear_depth_max_m_per_cycle": [float(cw.bearing.max()) for cw in cws],
                      "bearing_wear_volume_m3_per_cycle": [cw.volume_bearing for cw in cws]}
    ref = runs["general"]
    for name in ("specialised", "specialised_nudged_1ulp"):
        runs[name]["rel_to_general"] = {k: [a / b - 1 for a, b in zip(runs[name][k], ref[k])]
                                        for k in ref if k != "steps_per_cycle"}
    runs["note"] = ("the specialised kernel changes results at the level of rounding (another order of the mass "
                    "matrix's factorisation and of sums), which the step control amplifies as a 1-ulp change of the "
                    "start state does")
    return runs


def _six_bar_l_stable() -> dict:
    """How many steps the six-bar's accuracy needs: Radau IIA (L-stable, no stability limit on the contact modes;
    simulation.method = "radau5"; recorded on the tree kernel, which now runs Dormand-Prince only, so a rerun measures
    Radau on the Cartesian kernel) at rtol 1e-4 .. 1e-6 against the default
    (Dormand-Prince on the specialised tree kernel, rtol 1e-6): steps per cycle, wall seconds per cycle (alternated,
    medians of 3), mean and peak force per joint."""
    import dataclasses

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate

    six = build_model(load_config("watt_six_bar_two_clearances"))
    st = simulate(six, 0.0).state_end
    rad = dataclasses.replace(six, settings=six.settings.model_copy(update={"method": "radau5"}))
    s = six.settings
    cases = {"dopri5_rtol_1e-06": (six, s.rtol)}
    cases |= {f"radau5_rtol_{r:.0e}": (rad, r) for r in (1e-4, 1e-5, 1e-6)}
    walls: dict = {k: [] for k in cases}
    last = {}
    for m, r in cases.values():
        simulate(m, 0.01, settle_cycles=0, state0=st, rtol=r, atol=s.atol * r / s.rtol)  # compile
    for _ in range(3):
        for k, (m, r) in cases.items():
            w0 = time.perf_counter()
            last[k] = simulate(m, 1, settle_cycles=0, state0=st, rtol=r, atol=s.atol * r / s.rtol)
            walls[k].append(time.perf_counter() - w0)
    out = {}
    ref = last["dopri5_rtol_1e-06"]
    for k, r in last.items():
        out[k] = {"kernel": r.extra["kernel"], "steps_per_cycle": r.n_recorded_steps,
                  "rejected_steps_per_cycle": r.n_rejected,
                  "wall_seconds_per_cycle_median": statistics.median(walls[k]),
                  "wall_ratio_to_default": statistics.median(walls[k]) / statistics.median(walls["dopri5_rtol_1e-06"]),
                  "contact_force_mean_N": [tr.mean_force for tr in r.joints],
                  "contact_force_max_N": [float(tr.force_normal.max()) for tr in r.joints],
                  "mean_force_rel_to_default": [a.mean_force / b.mean_force - 1 for a, b in zip(r.joints, ref.joints)],
                  "max_force_rel_to_default": [float(a.force_normal.max() / b.force_normal.max() - 1)
                                               for a, b in zip(r.joints, ref.joints)]}
    out["note"] = ("an L-stable method follows the accuracy, not the contact modes' stability, and needs a tenth to a "
                   "third of the default's steps; each of its steps (Newton iterations on three stages, "
                   "finite-difference Jacobians, a real and a complex LU) costs more than the Dormand-Prince steps "
                   "it saves: see wall_ratio_to_default")
    return out


def _six_bar_wear_call(cartesian: bool) -> dict:
    """One model call of the six-bar wear study: the wear history to 300,000 cycles with the preset's wear settings
    (its lanes run as threads, so CPU seconds can exceed wall seconds on an idle machine)."""
    import functools

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.wear import wear_history

    cfg = load_config("watt_six_bar_two_clearances")
    kernels = {"tree": simulate} | ({"cartesian": functools.partial(simulate, fast=False)} if cartesian else {})
    out: dict = {"cycles": 300_000, "wear_settings": {"lanes": cfg.wear.lanes, "block_cycles": cfg.wear.block_cycles,
                                                       "rtol": cfg.wear.rtol, "atol": cfg.wear.atol}}
    for name, sim in kernels.items():
        sim(build_model(cfg), 0.01, settle_cycles=0)  # compile / load from numba's cache, untimed
        load0 = os.getloadavg()[0]
        w0, c0 = time.perf_counter(), time.process_time()
        res = wear_history(build_model(cfg), cfg.wear, 300_000, simulate=sim)
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        out[name] = {"wall_seconds": wall, "cpu_seconds": cpu, "simulated_cycles": res.n_simulated_cycles,
                     "steps": res.n_steps, "loadavg_1min_before": load0, "loadavg_1min_after": os.getloadavg()[0],
                     "sixty_calls_on_2_workers_minutes_from_cpu": 60 * cpu / 2 / 60}
    out["goal"] = "60 calls within 8 minutes on 2 cores: one call <= 16 CPU seconds"
    return out


if __name__ == "__main__":
    main()
