"""Why the flapping-wing cycle costs what it costs: what limits the step count, and the work per cycle.

Writes benchmarks/results/dynamics_limits.json. Run: python benchmarks/dynamics_limits.py (about 1 minute).
The companion of benchmarks/dynamics.py (which times the integrator); docs/dynamics.md "Integrator" reads both.

Sections (one settled cycle of the nominal jin2025_flapping_wing preset, natural-coordinate kernel):
- rhs: cost of one right-hand side evaluation in compiled loops (ns, median of 5 x 300k calls): throughput
  and latency, with and without the crank angle's sin/cos, and with numba's reference counting (as before
  session 3);
- reference: Dormand-Prince at rtol 1e-8, the contact force's pulses per cycle (peaks of prominence >= 10 mN);
- modes: eigenvalues of the Jacobian along the cycle (central differences with increments far below the
  penetration: 1e-12 m, 1e-9 m/s); the stiff pair is the contact's normal mode, the slow pair the journal
  rocking along the bearing wall (its real part > 0 means the friction excites it);
- evaluations: right-hand sides per cycle of Dormand-Prince (the default) and of scipy's Radau and of a
  Rosenbrock-W method (ROS34PW2, Rang & Angermann 2005) whose W is the exact Jacobian of the clearance
  joint's coordinates (the stiff part; a W-method keeps its order with any W) and the exact df/dt,
  with the physics each keeps (mean force, the wear integrand F_N |v_t|, impacts).
The lower bound printed at the end is evaluations x latency of an evaluation, without any loop overhead.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

# ROS34PW2 (Rang & Angermann 2005, BIT 45: 761-787), order 3 (embedded 2), L-stable, stiffly accurate W-method
RW_GAMMA = 0.435866521508459
RW_ALPHA = np.array([[0, 0, 0, 0], [0.87173304301691801, 0, 0, 0],
                     [0.84457060015369423, -0.11299064236484185, 0, 0], [0, 0, 1.0, 0]])
RW_GAMMA_OFF = np.array([[0, 0, 0, 0], [-0.87173304301691801, 0, 0, 0],
                         [-0.90338057013044082, 0.054180672388095326, 0, 0],
                         [0.24212380706095346, -1.2232505839045147, 0.54526025533510214, 0]])
RW_B = np.array([0.24212380706095346, -1.2232505839045147, 1.5452602553351020, 0.435866521508459])
RW_BHAT = np.array([0.37810903145819369, -0.096042292212423178, 0.5, 0.2179332607542295])


def trace_metrics(t, fn, vt, in_contact) -> dict:
    """Time-weighted mean force and F_N |v_t|, impacts (contact starts) over recorded steps."""
    w = np.zeros(len(t))
    d = np.diff(t)
    w[:-1] += d / 2
    w[1:] += d / 2
    return {"mean_force_mN": float(np.sum(w * fn) / w.sum() * 1e3),
            "mean_fn_abs_vt_W": float(np.sum(w * fn * np.abs(vt)) / w.sum()),
            "impacts": int(np.count_nonzero(np.diff(in_contact.astype(int)) == 1))}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "dynamics_limits.json"))
    args = ap.parse_args()

    from numba import njit
    from scipy.integrate import solve_ivp
    from scipy.signal import find_peaks

    from jointwear.config import load_config
    from jointwear.mechanism import build_model, simulate
    from jointwear.mechanism import kernel as K
    from jointwear.mechanism.simulate import Runner

    model = build_model(load_config("jin2025_flapping_wing"))
    st = simulate(model, 0.0, settle_cycles=3).state_end
    run = Runner(model, None, model.settings.rtol, model.settings.atol)
    a = run._args()
    _, _, _, dpar, _, jpar, cint, cpar, prof, ngrid, cstate, baum = a[:12]
    lam, cout = a[18], a[20]
    cstate[:] = st.cstate
    y0 = run.to_internal(st.y)
    period = model.period
    out: dict = {"preset": "jin2025_flapping_wing", "kernel": "natural_fourbar" if run.mode == 1 else "cartesian"}

    # ---- cost of one right-hand side: throughput (independent calls) and latency (each call waits for the
    # previous one, as the stages of a step do), with the crank angle's sin/cos (rhs_fourbar) and without
    # (rhs_fourbar_cs, as in the step loop), and with numba's reference counting as before session 3
    def make_loops(nrt):
        @njit(fastmath=K.FASTMATH, _nrt=nrt)
        def throughput(n, t0, Y, dy, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
            s = 0.0
            for i in range(n):
                Y[0, 0] += 1e-15  # a new state every call
                K.rhs_fourbar(t0 + i * 1e-9, Y, 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam,
                              cout)
                s += dy[0, 5]
            return s

        @njit(fastmath=K.FASTMATH, _nrt=nrt)
        def latency_no_trig(n, t0, Y, dy, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
            for i in range(n):
                K.rhs_fourbar_cs(0.6, 0.8, Y, 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
                Y[0, 0] += 1e-30 * dy[0, 5]  # the next call depends on this one's result
                Y[0, 6] += 1e-30 * dy[0, 4]
            return Y[0, 0]

        @njit(fastmath=K.FASTMATH, _nrt=nrt)
        def throughput_no_trig(n, t0, Y, dy, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
            s = 0.0
            for i in range(n):
                Y[0, 0] += 1e-15
                K.rhs_fourbar_cs(0.6, 0.8, Y, 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
                s += dy[0, 5]
            return s

        return {"throughput": throughput, "throughput_no_trig": throughput_no_trig,
                "latency_no_trig": latency_no_trig}

    dyw = np.zeros((7, run.ny))
    loops = {f"{name}{'' if nrt == K.STEP_LOOP_NRT else '_refcounted'}": fn
             for nrt in (K.STEP_LOOP_NRT, True) for name, fn in make_loops(nrt).items()}
    ns = {name: [] for name in loops}
    for fn in loops.values():
        fn(10, st.t, y0[None, :].copy(), dyw, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
    for _ in range(5):  # alternate the variants (this VM's speed drifts)
        for name, fn in loops.items():
            Y = y0[None, :].copy()
            t0 = time.perf_counter()
            fn(300_000, st.t, Y, dyw, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
            ns[name].append((time.perf_counter() - t0) / 300_000 * 1e9)
    out["rhs_ns_median"] = {name: statistics.median(v) for name, v in ns.items()}
    out["rhs_ns_all"] = ns

    # ---- tight reference and its force pulses
    ref = simulate(model, 1, settle_cycles=0, state0=st, rtol=1e-8, atol=1e-11)
    tr = ref.joints[0]
    tu = np.linspace(ref.t[0], ref.t[-1], 200_000)
    fu = np.interp(tu, ref.t, tr.contact_force)
    peaks, _ = find_peaks(fu, prominence=0.010)
    out["reference_rtol_1e-8"] = {"steps": ref.n_recorded_steps,
                                  **trace_metrics(ref.t, tr.contact_force, tr.slip_speed, tr.in_contact),
                                  "force_pulses_per_cycle_prominence_10mN": int(peaks.size),
                                  "median_pulse_interval_ms": float(np.median(np.diff(tu[peaks])) * 1e3)}

    # ---- modes along the cycle
    dy = np.zeros((1, run.ny))

    def f(t, y):
        K.rhs_fourbar(t, y[None, :], 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)
        return dy[0].copy()

    q, qd = ref.q, ref.qd
    from jointwear.mechanism.fast import to_natural

    stiff, slow = [], []
    for i in np.linspace(0, len(ref.t) - 1, 60).astype(int):
        y = to_natural(model, run.lay, np.concatenate([q[i], qd[i]]))
        jac = np.zeros((8, 8))
        for j in range(8):
            e = 1e-12 if j < 4 else 1e-9
            yp, ym = y.copy(), y.copy()
            yp[j] += e
            ym[j] -= e
            jac[:, j] = (f(ref.t[i], yp) - f(ref.t[i], ym)) / (2 * e)
        ev = np.linalg.eigvals(jac)
        ev = ev[np.argsort(-np.abs(ev))]
        stiff.append(ev[0] if ev[0].imag >= 0 else ev[1])
        slow.append(ev[2] if ev[2].imag >= 0 else ev[3])
    stiff, slow = np.array(stiff), np.array(slow)
    out["modes"] = {
        "stiff_pair_abs_imag_range_per_s": [float(np.abs(stiff.imag).min()), float(np.abs(stiff.imag).max())],
        "stiff_pair_real_range_per_s": [float(stiff.real.min()), float(stiff.real.max())],
        "slow_pair_abs_imag_range_per_s": [float(np.abs(slow.imag).min()), float(np.abs(slow.imag).max())],
        "slow_pair_real_range_per_s": [float(slow.real.min()), float(slow.real.max())],
        "fraction_of_points_with_slow_pair_growing": float(np.mean(slow.real > 0)),
    }

    # ---- evaluations per cycle
    dp = simulate(model, 1, settle_cycles=0, state0=st)
    tdp = dp.joints[0]
    attempted = dp.n_recorded_steps + dp.n_rejected
    out["dopri5_rtol_1e-6"] = {"steps": dp.n_recorded_steps, "rejected": dp.n_rejected,
                               "evaluations": 6 * attempted + 1,
                               **trace_metrics(dp.t, tdp.contact_force, tdp.slip_speed, tdp.in_contact)}

    def f_ivp(t, y):
        return f(t, y)

    for rt in (1e-4, 1e-5):
        cstate[:] = st.cstate  # frozen contact memory (solve_ivp has no per-step hook)
        sol = solve_ivp(f_ivp, (st.t, st.t + period), y0, method="Radau", rtol=rt, atol=run.atolv * rt / 1e-6,
                        max_step=period / 200)
        # scipy's nfev leaves out the finite-difference Jacobians (n + 1 evaluations each)
        out[f"scipy_radau_rtol_{rt:g}"] = {"steps": int(sol.t.size - 1), "evaluations_newton": int(sol.nfev),
                                           "jacobians": int(sol.njev), "lu": int(sol.nlu),
                                           "evaluations": int(sol.nfev + (y0.size + 1) * sol.njev)}

    for rt in (1e-4, 1e-5):
        out[f"rosenbrock_w_stiff_jacobian_rtol_{rt:g}"] = rosenbrock_w(f, st, y0, period, rt, run.atolv * rt / 1e-6,
                                                                       cstate, cpar, cout, K)

    # a step's stages are sequential: its evaluations cost their latency
    lat = out["rhs_ns_median"]["latency_no_trig"]
    ev = out["dopri5_rtol_1e-6"]["evaluations"]
    out["lower_bound_ms_per_cycle_dopri5_evaluations_only"] = ev * lat * 1e-6
    rw = out["rosenbrock_w_stiff_jacobian_rtol_1e-05"]["evaluations_with_analytic_w"]
    out["lower_bound_ms_per_cycle_rosenbrock_w_1e-5_evaluations_only"] = rw * lat * 1e-6
    out["evaluations_per_cycle_for_4_ms"] = 4e-3 / (lat * 1e-9)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))


def rosenbrock_w(f, st, y0, period, rtol, atolv, cstate, cpar, cout, K) -> dict:
    """ROS34PW2 over one cycle; W = exact Jacobian columns of the clearance joint's coordinates (A, Adot), by
    central differences 1e-12 m / 1e-9 m/s, exact df/dt (central, 1e-12 s); contact memory as kernel's step loops."""
    cstate[:] = st.cstate
    y = y0.copy()
    t = st.t
    t_end = t + period
    h = 1e-6
    nf = 0
    steps = rejected = 0
    rec = []
    asum = RW_ALPHA.sum(1)
    gsum = RW_GAMMA_OFF.sum(1) + RW_GAMMA
    while t < t_end:
        h = min(h, t_end - t, period / 200)
        f0 = f(t, y)
        jac = np.zeros((8, 8))
        for j in (0, 1, 4, 5):
            e = 1e-12 if j < 4 else 1e-9
            yp, ym = y.copy(), y.copy()
            yp[j] += e
            ym[j] -= e
            jac[:, j] = (f(t, yp) - f(t, ym)) / (2 * e)
        ft = (f(t + 1e-12, y) - f(t - 1e-12, y)) / 2e-12
        nf += 11
        while True:
            m = np.eye(8) - h * RW_GAMMA * jac
            ks = []
            for i in range(4):
                ys = y + sum(RW_ALPHA[i, j] * ks[j] for j in range(i))
                gs = sum(RW_GAMMA_OFF[i, j] * ks[j] for j in range(i)) if i else np.zeros(8)
                fi = f(t + asum[i] * h, ys) if i else f0
                nf += 1 if i else 0
                ks.append(np.linalg.solve(m, h * fi + h * jac @ gs + gsum[i] * h * h * ft))
            yn = y + sum(RW_B[i] * ks[i] for i in range(4))
            er = sum((RW_B[i] - RW_BHAT[i]) * ks[i] for i in range(4))
            err = np.sqrt(np.mean((er / (atolv + rtol * np.maximum(abs(y), abs(yn)))) ** 2))
            if err <= 1.0:
                break
            rejected += 1
            h *= max(0.2, 0.9 * err ** (-1 / 3))
        t += h
        y = yn
        steps += 1
        h *= min(5.0, max(0.2, 0.9 * max(err, 1e-10) ** (-1 / 3)))
        f(t, y)
        nf += 1
        c = cout[0]
        if c[K.O_DELTA] > 0:
            if cstate[0, K.S_INC] < 0.5:
                cstate[0, K.S_V0] = max(c[K.O_VN], cpar[0, K.C_V0MIN])
                cstate[0, K.S_INC] = 1.0
        else:
            cstate[0, K.S_INC] = 0.0
        rec.append((t, c[K.O_FN], c[K.O_VT], c[K.O_DELTA] > 0))
    r = np.array(rec)
    # with an analytic W and df/dt a step needs 3 new stage evaluations per attempt plus f at the new point
    return {"steps": steps, "rejected": rejected, "evaluations_here": nf,
            "evaluations_with_analytic_w": 3 * (steps + rejected) + steps,
            **trace_metrics(r[:, 0], r[:, 1], r[:, 2], r[:, 3] > 0)}


if __name__ == "__main__":
    main()
