"""Implicit alternative to the Dormand-Prince loop: Radau IIA of order 5 (3 stages, L-stable), compiled.

Why: in near-continuous contact the Dormand-Prince step is set by the contact modes' stability, not by the
tolerance (docs/dynamics.md, "Integrator"); an L-stable collocation method damps those modes and follows the
accuracy alone, with far fewer steps per cycle (each one dearer: benchmarks/results/dynamics.json, six_bar_l_stable).

Algorithm: Hairer & Wanner, Solving ODEs II, Section IV.8 (RADAU5), as implemented by
``scipy.integrate.Radau`` (whose constants are copied below): simplified Newton iterations on the transformed
collocation system with one real and one complex LU of the iteration matrices, a finite-difference Jacobian
refreshed when the Newton iterations converge slowly (rate > 1e-3 after more than 2 iterations), up to 10 Newton
iterations given up only when the contraction rate exceeds 0.9 (scipy's predictive give-up after at most 6 turned
most rejections of the contact problem into Newton failures), the embedded error estimate
(I - h gamma0 J)^-1 (f0 + Z^T E / h) (re-estimated once after a rejection), Gustafsson's predictive step control,
and the step size kept (LU reused) when it would grow by less than 20 %.

Same arguments as the loops of ``kernel.INTEGRATORS`` plus the work arrays of ``work_arrays``; selected by
``simulation.method = "radau5"``. The step start (``kernel.next_step``), the step limit (``kernel.step_limit``) and the
accepted-step bookkeeping (impact speed, record; ``kernel.accept_point``) are shared with the Dormand-Prince loop.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from jointwear.mechanism.kernel import (
    MODES,
    STEP_LOOP_NRT,
    accept_point,
    compile_for_mode,
    next_step,
    rhs,
    rhs_fourbar,
    step_limit,
)

# Radau IIA (order 5) constants, copied from scipy/integrate/_ivp/radau.py (scipy 1.17.1, BSD-3-Clause;
# Hairer & Wanner's RADAU5): collocation nodes C, error-estimate weights E, the eigenvalues of A^-1
# (MU_REAL, MU_COMPLEX) and its eigenvector matrices T, TI, and the dense-output coefficients P.
_S6 = 6 ** 0.5
_C = np.array([(4 - _S6) / 10, (4 + _S6) / 10, 1])
_E = np.array([-13 - 7 * _S6, -13 + 7 * _S6, -1]) / 3
_MU_REAL = 3 + 3 ** (2 / 3) - 3 ** (1 / 3)
_MU_COMPLEX = (3 + 0.5 * (3 ** (1 / 3) - 3 ** (2 / 3))
               - 0.5j * (3 ** (5 / 6) + 3 ** (7 / 6)))
_T = np.array([
    [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
    [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
    [1, 1, 0]])
_TI = np.array([
    [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
    [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
    [0.50287263494578682, -2.57192694985560522, 0.59603920482822492]])
_P = np.array([
    [13 / 3 + 7 * _S6 / 3, -23 / 3 - 22 * _S6 / 3, 10 / 3 + 5 * _S6],
    [13 / 3 - 7 * _S6 / 3, -23 / 3 + 22 * _S6 / 3, 10 / 3 - 5 * _S6],
    [1 / 3, -8 / 3, 10 / 3]])

RC = np.array(_C, dtype=float)
RE = np.array(_E, dtype=float)
RT = np.array(_T, dtype=float)
RTI = np.array(_TI, dtype=float)
RP = np.array(_P, dtype=float)
MU_R = float(_MU_REAL)
MU_C = complex(_MU_COMPLEX)
NEWTON_MAXITER = 10  # scipy: 6 with a predictive give-up; the contact needs more iterations (docs/dynamics.md)
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0


@njit(cache=True, error_model="numpy", _nrt=STEP_LOOP_NRT)
def rhs_cartesian_row(t, Y, dy, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                      kin, phi_, phid, rest, jac, smat, lam, f, cout):
    """dy[0] = f(t, Y[0]) of the Cartesian kernel (kernel.rhs), for the loop's evaluations outside the Newton stages
    (the Jacobian's columns, the error re-estimate, the accepted point). Called there, not inlined: every inlined copy
    of a right-hand side is compiled again (benchmarks/results/compile.json), and the stages, inlined, take most
    evaluations (three per Newton iteration against one per accepted step). The call weighs on the four-bar's cheap
    evaluation per cycle, not on the six-bar's (benchmarks/results/radau.json)."""
    rhs(t, Y[0], dy, 0, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
        kin, phi_, phid, rest, jac, smat, lam, f, cout)


@njit(cache=True, error_model="numpy", _nrt=STEP_LOOP_NRT)
def rhs_natural_fourbar_row(t, Y, dy, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                            kin, phi_, phid, rest, jac, smat, lam, f, cout):
    """dy[0] = f(t, Y[0]) of the natural-coordinate four-bar (kernel.rhs_fourbar); as rhs_cartesian_row."""
    rhs_fourbar(t, Y, 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)


def work_arrays(ny: int) -> tuple:
    """(J, LU_real, piv_real, LU_complex, piv_complex, Z, W, F, ytmp, f0, vec, cvec, Zold) for integrate_radau."""
    return (np.zeros((ny, ny)), np.zeros((ny, ny)), np.zeros(ny, dtype=np.int64), np.zeros((ny, ny), dtype=np.complex128),
            np.zeros(ny, dtype=np.int64), np.zeros((3, ny)), np.zeros((3, ny)), np.zeros((3, ny)), np.zeros((3, ny)),
            np.zeros(ny), np.zeros(ny), np.zeros(ny, dtype=np.complex128), np.zeros((3, ny)))


@njit(cache=True, error_model="numpy", _nrt=STEP_LOOP_NRT)
def _lu_factor(a, piv):
    """In-place LU with partial pivoting (real or complex); False if singular."""
    n = a.shape[0]
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            v = abs(a[i, k])
            if v > big:
                big = v
                p = i
        piv[k] = p
        if big == 0.0:
            return False
        if p != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = tmp
        inv = 1.0 / a[k, k]
        for i in range(k + 1, n):
            m = a[i, k] * inv
            a[i, k] = m
            for j in range(k + 1, n):
                a[i, j] -= m * a[k, j]
    return True


@njit(cache=True, error_model="numpy", _nrt=STEP_LOOP_NRT)
def _lu_solve(a, piv, b):
    """Solve in place with the factors of _lu_factor."""
    n = a.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= a[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= a[i, j] * b[j]
        b[i] = s / a[i, i]


@njit(cache=True, error_model="numpy", _nrt=STEP_LOOP_NRT)
def _rms(v, scale):
    s = 0.0
    for i in range(v.shape[0]):
        r = v[i] / scale[i]
        s += r * r
    return math.sqrt(s / v.shape[0])


def _radau(mode: int):
    """The Radau loop for one right-hand side (kernel.MODES; `mode` is a closure constant, as in
    kernel._dormand_prince, so that each mode compiles alone)."""
    def integrate_radau(t, y, t_end, h, rtol, atolv, hmax, clear_frac, max_steps, t_record,
                        nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                        kin, phi_, phid, rest, jac, smat, lam, f, cout, ks, ytmp6,
                        rec_t, rec_h, rec_y, rec_acc, rec_lam, rec_c, counters,
                        J, LUr, pivr, LUc, pivc, Z, W, F, ytmp, f0, vec, cvec, Zold):
        """Radau IIA (order 5) with error control from t to t_end (in place on y); contract of kernel.INTEGRATORS.

        ks[0] must hold f(t, y) on entry and holds f at the final point on exit (ytmp6 is unused here)."""
        if mode == 0:  # folded: only the chosen one is compiled into the loop
            rhs_row = rhs_cartesian_row
        else:
            rhs_row = rhs_natural_fourbar_row
        ny = y.shape[0]
        cap = rec_t.shape[0]
        nrec = counters[0]
        nsteps = 0
        counters[3] = 0
        hmin = 1e-15 * max(abs(t), abs(t_end), 1.0)
        newton_tol = max(10.0 * 2.220446049250313e-16 / rtol, min(0.03, math.sqrt(rtol)))
        hlim = step_limit(cout, clear_frac, hmax)
        for i in range(ny):
            f0[i] = ks[0, i]
        need_jac = True
        current_jac = False
        lu_ok = False
        h_lu = -1.0
        h_old = -1.0
        err_old = -1.0
        rejected = False
        h_acc = -1.0  # length of the last accepted step (for the extrapolated Newton start)
        while t < t_end:
            h, tn, stop = next_step(t, h, hlim, t_end, hmin, nrec, cap, nsteps, max_steps)
            if stop:
                counters[3] = stop
                break
            nsteps += 1
            if need_jac:  # forward differences around (t, y); f0 = f(t, y)
                for i in range(ny):
                    ytmp[0, i] = y[i]
                for i in range(ny):
                    e = 1e-8 * abs(y[i])
                    e2 = 1e-3 * atolv[i]
                    if e2 > e:
                        e = e2
                    ytmp[0, i] = y[i] + e
                    e = ytmp[0, i] - y[i]
                    rhs_row(t, ytmp[0:1], F[0:1], nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                            baum, kin, phi_, phid, rest, jac, smat, lam, f, cout)
                    for r in range(ny):
                        J[r, i] = (F[0, r] - f0[r]) / e
                    ytmp[0, i] = y[i]
                need_jac = False
                current_jac = True
                lu_ok = False
            if not lu_ok or h != h_lu:
                mr = MU_R / h
                mc = MU_C / h
                for r in range(ny):
                    for c in range(ny):
                        LUr[r, c] = -J[r, c]
                        LUc[r, c] = -J[r, c]
                    LUr[r, r] += mr
                    LUc[r, r] += mc
                ok_r = _lu_factor(LUr, pivr)
                ok_c = _lu_factor(LUc, pivc)
                lu_ok = ok_r and ok_c
                h_lu = h
                if not lu_ok:
                    h *= 0.5
                    counters[2] += 1
                    continue
            # ---- simplified Newton on the transformed collocation system, started from the previous step's
            # collocation polynomial extrapolated to the new stages (zero on the first step)
            if h_acc > 0.0:
                for s in range(3):
                    x = 1.0 + RC[s] * h / h_acc
                    for i in range(ny):
                        q = 0.0
                        xp = x
                        for j in range(3):
                            q += (Zold[0, i] * RP[0, j] + Zold[1, i] * RP[1, j] + Zold[2, i] * RP[2, j]) * xp
                            xp *= x
                        Z[s, i] = q - Zold[2, i]
            else:
                for s in range(3):
                    for i in range(ny):
                        Z[s, i] = 0.0
            for s in range(3):
                for i in range(ny):
                    W[s, i] = RTI[s, 0] * Z[0, i] + RTI[s, 1] * Z[1, i] + RTI[s, 2] * Z[2, i]
            mr = MU_R / h
            mc = MU_C / h
            converged = False
            n_iter = 0
            rate = -1.0
            dw_old = -1.0
            for it in range(NEWTON_MAXITER):
                n_iter = it + 1
                for s in range(3):
                    for i in range(ny):
                        ytmp[s, i] = y[i] + Z[s, i]
                    if mode == 0:  # inlined here, where the loop spends its evaluations; called elsewhere
                        rhs(t + RC[s] * h, ytmp[s], F, s, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid,
                            cstate, baum, kin, phi_, phid, rest, jac, smat, lam, f, cout)
                    else:
                        rhs_fourbar(t + RC[s] * h, ytmp, s, F, s, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum,
                                    lam, cout)
                finite = True
                for s in range(3):
                    for i in range(ny):
                        if not math.isfinite(F[s, i]):
                            finite = False
                if not finite:
                    break
                dw = 0.0
                for i in range(ny):
                    fr = RTI[0, 0] * F[0, i] + RTI[0, 1] * F[1, i] + RTI[0, 2] * F[2, i] - mr * W[0, i]
                    fre = RTI[1, 0] * F[0, i] + RTI[1, 1] * F[1, i] + RTI[1, 2] * F[2, i]
                    fim = RTI[2, 0] * F[0, i] + RTI[2, 1] * F[1, i] + RTI[2, 2] * F[2, i]
                    vec[i] = fr
                    cvec[i] = complex(fre, fim) - mc * complex(W[1, i], W[2, i])
                _lu_solve(LUr, pivr, vec)
                _lu_solve(LUc, pivc, cvec)
                for i in range(ny):
                    sc = atolv[i] + abs(y[i]) * rtol
                    d0 = vec[i] / sc
                    d1 = cvec[i].real / sc
                    d2 = cvec[i].imag / sc
                    dw += d0 * d0 + d1 * d1 + d2 * d2
                dw = math.sqrt(dw / (3 * ny))
                if dw_old >= 0.0:
                    rate = dw / dw_old
                if rate >= 0.9:  # diverging or stalled (scipy also gives up when the predicted error misses newton_tol)
                    break
                for i in range(ny):
                    W[0, i] += vec[i]
                    W[1, i] += cvec[i].real
                    W[2, i] += cvec[i].imag
                for s in range(3):
                    for i in range(ny):
                        Z[s, i] = RT[s, 0] * W[0, i] + RT[s, 1] * W[1, i] + RT[s, 2] * W[2, i]
                if dw == 0.0 or (rate >= 0.0 and rate / (1.0 - rate) * dw < newton_tol):
                    converged = True
                    break
                dw_old = dw
            if not converged:
                counters[2] += 1
                if not current_jac:
                    need_jac = True
                else:
                    h *= 0.5
                    lu_ok = False
                continue
            # ---- error estimate
            for i in range(ny):
                vec[i] = f0[i] + (RE[0] * Z[0, i] + RE[1] * Z[1, i] + RE[2] * Z[2, i]) / h
            _lu_solve(LUr, pivr, vec)
            for i in range(ny):
                ytmp[2, i] = y[i] + Z[2, i]  # y_new
            # scale from max(|y|, |y_new|) (reuse F[0] as the scale vector)
            for i in range(ny):
                a0 = abs(y[i])
                a1 = abs(ytmp[2, i])
                F[0, i] = atolv[i] + rtol * (a0 if a0 > a1 else a1)
            err = _rms(vec, F[0])
            if rejected and err > 1.0:
                for i in range(ny):
                    ytmp[1, i] = y[i] + vec[i]
                rhs_row(t, ytmp[1:2], F[1:2], nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                        kin, phi_, phid, rest, jac, smat, lam, f, cout)
                for i in range(ny):
                    vec[i] = F[1, i] + (RE[0] * Z[0, i] + RE[1] * Z[1, i] + RE[2] * Z[2, i]) / h
                _lu_solve(LUr, pivr, vec)
                err = _rms(vec, F[0])
            safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
            if err != err or err > 1.0:  # rejected (NaN included)
                counters[2] += 1
                if err != err:
                    fac = 0.1
                else:
                    mult = 1.0
                    if h_old > 0.0 and err_old > 0.0:
                        mult = h / h_old * (err_old / err) ** 0.25
                    fac = min(1.0, mult) * err ** -0.25
                    fac = max(MIN_FACTOR, safety * fac)
                h *= fac
                lu_ok = False
                rejected = True
                continue
            # ---- accepted
            rejected = False
            t = tn
            h_acc = h
            for s in range(3):
                for i in range(ny):
                    Zold[s, i] = Z[s, i]
            for i in range(ny):
                y[i] = ytmp[2, i]
            rhs_row(t, ytmp[2:3], ks[0:1], nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                    kin, phi_, phid, rest, jac, smat, lam, f, cout)
            for i in range(ny):
                f0[i] = ks[0, i]
            counters[1] += 1
            nrec = accept_point(t, h, y, ks, lam, cout, cstate, cpar, t_record, nrec, rec_t, rec_h, rec_y, rec_acc,
                                rec_lam, rec_c)
            hlim = step_limit(cout, clear_frac, hmax)
            recompute = n_iter > 2 and rate > 1e-3
            mult = 1.0
            if h_old > 0.0 and err_old > 0.0 and err > 0.0:
                mult = h / h_old * (err_old / err) ** 0.25
            fac = min(1.0, mult) * (err if err > 1e-10 else 1e-10) ** -0.25
            fac = min(MAX_FACTOR, safety * fac)
            h_old = h
            err_old = err
            if not recompute and fac < 1.2:
                fac = 1.0  # keep h: the factorisations stay valid (as scipy's Radau)
            h *= fac
            if recompute:
                need_jac = True
            else:
                current_jac = False
        counters[0] = nrec
        return t, h

    return compile_for_mode(integrate_radau, mode, nogil=True, error_model="numpy", _nrt=STEP_LOOP_NRT)


# the tree kernel does not run under Radau (simulate.Runner): no tree entry
RADAU_INTEGRATORS = (_radau(MODES.index("cartesian")), _radau(MODES.index("natural_fourbar")))
