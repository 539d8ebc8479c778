"""Forward dynamics: settle, then record whole crank cycles; typed results for the wear stage."""

from __future__ import annotations

import math
import sys
import threading
import time

import numpy as np
from numba import njit

from jointwear.contact.geometry import ClearanceGeometry
from jointwear.mechanism import kernel as K
from jointwear.mechanism.fast import fast_layout, natural_angles, to_cartesian_point, to_natural
from jointwear.mechanism.fast import to_cartesian as natural_to_cartesian
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.model import MechanismModel
from jointwear.mechanism.results import (
    ContactTrace,
    SimulationCancelled,
    SimulationError,
    SimulationResult,
    SimulationState,
)

TWO_PI = 2.0 * math.pi


def _atol_vector(model: MechanismModel, atol: float) -> np.ndarray:
    nb = len(model.free_bodies)
    per = model.period
    wref = TWO_PI / per if per else 1.0
    lref = model.length_ref
    pos = np.tile([atol, atol, atol / lref], nb)
    vel = np.tile([atol * wref, atol * wref, atol * wref / lref], nb)
    return np.concatenate([pos, vel])


# Record buffers are reused between calls once nothing refers to them any more. A fresh buffer costs its first
# touch: the allocator maps new zeroed pages for every large array, ~1 ms per simulated cycle against ~0.1 ms to
# rewrite warm memory, a sixth of a flapping-wing cycle. A pooled set is free when only the pool refers to its dict
# and arrays: results keep views of them (numpy views refer to their base array), so a kept result is never
# overwritten. The lock makes the check-and-take atomic for the wear stage's lane threads.
_POOL_MIN_CAP = 1000  # rows; smaller sets are cheap to allocate
_POOL_MAX_CAP = 100_000  # rows (~25 MB per set for the flapping wing): longer records are not kept
_POOL_MAX_SETS = 8
_record_pool: list[dict[str, np.ndarray]] = []
_record_pool_lock = threading.Lock()


def _free_array(a: np.ndarray, shape) -> bool:
    return a.shape == shape and sys.getrefcount(a) == 3  # the dict, the parameter `a`, getrefcount's argument


def _record_buffers(shapes) -> dict[str, np.ndarray]:
    if not _POOL_MIN_CAP <= shapes[0][1][0] <= _POOL_MAX_CAP:
        return {name: np.empty(shape) for name, shape in shapes}
    with _record_pool_lock:
        for i in range(len(_record_pool)):
            buf = _record_pool[i]
            # references to the dict: the pool, `buf` and getrefcount's argument (3); to an array: the dict and the
            # argument (2). Any other holder or view adds one.
            if sys.getrefcount(buf) == 3 and all(_free_array(buf[name], shape) for name, shape in shapes):
                return buf
        buf = {name: np.empty(shape) for name, shape in shapes}
        if len(_record_pool) >= _POOL_MAX_SETS:
            _record_pool.pop(0)
        _record_pool.append(buf)
        return buf


class Runner:
    """Kernel arrays, work arrays and the coordinate set (mode 0: Cartesian, 1: natural four-bar)."""

    def __init__(self, model: MechanismModel, geometry, rtol, atol, fast: bool | None = None):
        from jointwear.mechanism.tree import atol_vector as tree_atol_vector
        from jointwear.mechanism.tree import tree_layout
        from jointwear.mechanism.tree import work_arrays as tree_work_arrays

        self.model = model
        self.a = model.kernel_arrays(geometry)
        a = self.a
        nb = a["nb"]
        self.lay = fast_layout(model) if fast in (None, True) else None
        if fast is True and self.lay is None:
            raise ValueError("fast=True but the model does not qualify for the natural-coordinate kernel")
        # the tree kernel (joint coordinates) for a linkage whose ideal joints form a forest
        # (not under Radau: its Newton loop inlining the tree right-hand side costs minutes of compilation)
        self.tree = (tree_layout(a) if fast is None and self.lay is None and model.settings.method == "dopri5"
                     else None)
        self.mode = 1 if self.lay is not None else 2 if self.tree is not None else 0
        self.integrate, self.evaluate = K.INTEGRATORS[self.mode], K.EVALUATORS[self.mode]
        if self.mode == 2:
            from jointwear.mechanism.tree_codegen import specialised_module

            # the Dormand-Prince loop compiled for this linkage shape (generated, cached per shape)
            self.integrate = specialised_module(self.tree, a["dpar"].shape[0], a["cint"]).integrate
            a["jint"], a["jpar"], a["winv"] = self.tree.jint, self.tree.jpar, self.tree.mass
            self.w = tree_work_arrays(self.tree, a["dpar"].shape[0], a["cint"].shape[0])
            self.ny = 2 * self.tree.n
            per = model.period
            self.atolv = tree_atol_vector(self.tree, atol, model.length_ref, TWO_PI / per if per else 1.0)
        elif self.mode == 1:
            a["jpar"] = self.lay.fp
            self.w = K.empty_work(nb, a["dpar"].shape[0], 1, a["cint"].shape[0])
            self.ny = 8
            per = model.period
            wref = TWO_PI / per if per else 1.0
            self.atolv = np.concatenate([np.full(4, atol), np.full(4, atol * wref)])
        else:
            self.w = K.empty_work(nb, a["dpar"].shape[0], a["jint"].shape[0], a["cint"].shape[0])
            self.ny = 6 * nb
            self.atolv = _atol_vector(model, atol)
        self.rtol = rtol
        self.ks = np.zeros((7, self.ny))
        self.ytmp = np.zeros((6, self.ny))
        self._radau_work = None

    def to_internal(self, y_cart: np.ndarray) -> np.ndarray:
        if self.mode == 0:
            return np.array(y_cart, dtype=float)
        if self.mode == 2:
            from jointwear.mechanism.tree import to_tree

            return to_tree(self.tree, np.asarray(y_cart, dtype=float))

        return to_natural(self.model, self.lay, y_cart)

    def to_cartesian(self, Y: np.ndarray, Ydd: np.ndarray | None, phi_ref=None, t: np.ndarray | None = None):
        """Recorded internal states (at times t: needed by the tree kernel's driven parents) -> Cartesian q, qd, qdd."""
        if self.mode == 0:
            nq = Y.shape[1] // 2
            return Y[:, :nq], Y[:, nq:], Ydd
        if self.mode == 2:
            from jointwear.mechanism.tree import to_cartesian as tree_to_cartesian

            return tree_to_cartesian(self.tree, self.a["dpar"], t, Y, Ydd)

        return natural_to_cartesian(self.model, self.lay, Y, Ydd, phi_ref)

    def to_cartesian_state(self, t: float, y: np.ndarray, phi_ref: dict[str, float]) -> np.ndarray:
        """One internal state at t -> the Cartesian (q, qd), angles on the branch of phi_ref."""
        if self.mode == 0:
            return np.array(y, dtype=float)
        if self.mode == 2:
            from jointwear.mechanism.tree import to_cartesian as tree_to_cartesian

            q, qd, _ = tree_to_cartesian(self.tree, self.a["dpar"], np.array([t]), y[None, :])
            return np.concatenate([q[0], qd[0]])

        return np.concatenate(to_cartesian_point(self.model, self.lay, y, phi_ref))

    def _args(self):
        a, w = self.a, self.w
        return (a["nb"], a["winv"], a["fext"].ravel(), a["dpar"], a["jint"], a["jpar"], a["cint"], a["cpar"],
                a["prof"], a["ngrid"], a["cstate"], a["baum"], w["kin"], w["phi_"], w["phid"], w["rest"], w["jac"],
                w["smat"], w["lam"], w["f"], w["cout"])

    def eval(self, t, y):
        """Evaluate the equations of motion at (t, y) into ks[0] (also fills lam and cout)."""
        self.evaluate(t, y, self.ks, *self._args())

    def buffers(self, cap: int) -> dict[str, np.ndarray]:
        ncj = self.a["cint"].shape[0]
        nc = self.w["lam"].shape[0]
        shapes = (("rec_t", (cap,)), ("rec_h", (cap,)), ("rec_y", (cap, self.ny)), ("rec_acc", (cap, self.ny // 2)),
                  ("rec_lam", (cap, nc)), ("rec_c", (ncj, K.NCOUT, cap)))  # rec_c: outputs x steps, series contiguous
        return _record_buffers(shapes)

    def run(self, t, y, t_end, h, hmax, t_record, rec, max_steps, counters):
        s = self.model.settings
        args = (t, y, t_end, h, self.rtol, self.atolv, hmax, s.clearance_step_fraction, max_steps,
                t_record, *self._args(), self.ks, self.ytmp, rec["rec_t"], rec["rec_h"], rec["rec_y"],
                rec["rec_acc"], rec["rec_lam"], rec["rec_c"], counters)
        if s.method == "radau5":
            from jointwear.mechanism import radau

            if self._radau_work is None:
                self._radau_work = radau.work_arrays(self.ny)
            return radau.RADAU_INTEGRATORS[self.mode](*args, *self._radau_work)
        return self.integrate(*args)


def simulate(model: MechanismModel, n_cycles: float, geometry: list[ClearanceGeometry] | None = None,
             settle_cycles: float | None = None, rtol: float | None = None, atol: float | None = None,
             state0: SimulationState | None = None, *, record: bool = True,
             fast: bool | None = None, cancel: threading.Event | None = None) -> SimulationResult:
    """Integrate the mechanism: settle_cycles crank cycles (discarded), then n_cycles recorded.

    geometry: one ClearanceGeometry per clearance joint (default: unworn). state0: continue from a
    previous result's ``state_end`` (default: ideal kinematics at t = 0, journals preloaded).
    The cycle length is the driver's period (or model.period_override).
    fast: None (default) uses the natural-coordinate four-bar kernel when the model qualifies
    (jointwear.mechanism.fast), else the joint-coordinate tree kernel when the ideal joints form a forest
    (jointwear.mechanism.tree), else the general Cartesian kernel; True requires the
    four-bar kernel, False forces the Cartesian kernel.
    cancel: an event another thread may set; the simulation then stops at its next record chunk and raises
    SimulationCancelled (a wear history's look-ahead block after the joint is worn away).
    """
    wall0 = time.perf_counter()
    if not (np.isfinite(n_cycles) and n_cycles >= 0):
        raise ValueError(f"n_cycles must be a finite number >= 0 (got {n_cycles!r})")
    if settle_cycles is not None and not (np.isfinite(settle_cycles) and settle_cycles >= 0):
        raise ValueError(f"settle_cycles must be a finite number >= 0 (got {settle_cycles!r})")
    for name, val in (("rtol", rtol), ("atol", atol)):
        if val is not None and not (np.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a finite number > 0 (got {val!r})")
    period = model.period
    if period is None:
        raise ValueError("model has no driver: set model.period_override to define a cycle length")
    s = model.settings
    settle = s.settle_cycles if settle_cycles is None else settle_cycles
    rtol = s.rtol if rtol is None else rtol
    atol = s.atol if atol is None else atol
    if geometry is None:
        geometry = model.initial_geometry()
    run = Runner(model, geometry, rtol, atol, fast)
    st = initial_state(model, geometry=geometry) if state0 is None else state0
    y = run.to_internal(st.y)
    free_names = [b.name for b in model.free_bodies]
    phi_ref = {n: float(st.y[3 * i + 2]) for i, n in enumerate(free_names)}
    run.a["cstate"][:] = st.cstate
    t = float(st.t)
    hmax = s.max_step if s.max_step is not None else period / 200.0
    h = st.h if st.h > 0 else min(hmax, 1e-7)
    k1 = run.ks[0]
    run.eval(t, y)
    counters = np.zeros(4, dtype=np.int64)
    max_steps = int(s.max_steps)
    # settling (not recorded)
    t_settle = t + settle * period
    settle_buf = run.buffers(1)
    while t < t_settle:
        counters[0] = 0
        t, h = run.run(t, y, t_settle, h, hmax, math.inf, settle_buf, max_steps, counters)
        if counters[3] in (2, 3):
            raise SimulationError(_status_text(counters[3], t, h, run))
    # recording: the first sample is the state at the start of the recorded window
    t_end = t + n_cycles * period
    run.eval(t, y)
    est = int(max(1000, 20000 * n_cycles)) if record else 1
    chunks = []
    first = True
    while True:
        if cancel is not None and cancel.is_set():
            raise SimulationCancelled(f"cancelled at t = {t:.6g} s")
        counters[0] = 0
        rec = run.buffers(est + 1 if first else est)
        if first:  # the first sample is the state at the start of the recorded window
            rec["rec_t"][0], rec["rec_h"][0] = t, 0.0
            rec["rec_y"][0] = y
            rec["rec_acc"][0] = k1[run.ny // 2:]
            rec["rec_lam"][0] = run.w["lam"]
            rec["rec_c"][:, :, 0] = run.w["cout"]
            counters[0] = 1
            first = False
        if t < t_end:
            # the step budget is per call, not per record chunk (each chunk's loop counts from zero): a collapsing
            # step size stops at max_steps instead of growing the record without bound
            budget = max(1, max_steps - int(counters[1] + counters[2]))
            t, h = run.run(t, y, t_end, h, hmax, -math.inf if record else math.inf, rec, budget, counters)
            if counters[3] in (2, 3):
                raise SimulationError(_status_text(counters[3], t, h, run))
        n = int(counters[0])
        chunks.append({k: (v[..., :n] if k == "rec_c" else v[:n]) for k, v in rec.items()})
        if t >= t_end:
            break
    # joined one series at a time, each chunk's part dropped as it is joined: the record is held once, not twice;
    # the fast kernels' multipliers are not recorded (filled with NaN below), so not joined
    unrecorded = ("rec_lam",) if run.mode in (1, 2) else ()
    cat = chunks[0] if len(chunks) == 1 else {
        k: np.concatenate([c.pop(k) for c in chunks], axis=-1 if k == "rec_c" else 0)
        for k in list(chunks[0]) if k not in unrecorded}
    del chunks, rec
    ref = phi_ref if settle == 0 else None
    Y, Ydd = cat["rec_y"], cat["rec_acc"]
    if run.mode == 2:
        from jointwear.mechanism.tree import body_angles

        tree_angles = body_angles(run.tree, Y)
        free_phi = {n: tree_angles[:, i] for i, n in enumerate(free_names)}
        joint_angles = {}
        cat["rec_lam"] = np.broadcast_to(np.nan, (Y.shape[0], 2 * len(model.joints)))  # read-only, no memory
        rec_t = cat["rec_t"]

        def cart():
            return run.to_cartesian(Y, Ydd, t=rec_t)
    elif run.mode == 1:
        angles = natural_angles(run.lay, Y, ref)
        joint_angles = {0: _fast_joint_angles(model, run, cat["rec_t"], angles[run.lay.rod])}
        cat["rec_lam"] = np.broadcast_to(np.nan, (Y.shape[0], 2 * len(model.joints)))  # read-only, no memory
        free_phi = {n: angles[n] for n in free_names}

        def cart():
            return run.to_cartesian(Y, Ydd, ref)
    else:
        nq = Y.shape[1] // 2
        free_phi = {n: Y[:, 3 * i + 2] for i, n in enumerate(free_names)}
        joint_angles = {}

        def cart():
            return Y[:, :nq], Y[:, nq:], Ydd
    y_end = run.to_cartesian_state(t, y, {n: float(free_phi[n][-1]) for n in free_names})
    state_end = SimulationState(t, y_end, run.a["cstate"].copy(), h)
    res = _package(model, geometry, cat, free_phi, joint_angles, cart, state_end, counters, n_cycles, settle, period,
                   time.perf_counter() - wall0)
    res.extra["kernel"] = K.MODES[run.mode]
    return res


def _fast_joint_angles(model, run, t, phi_rod) -> tuple[np.ndarray, np.ndarray]:
    """(bearing, journal) body angles of the fast kernel's joint, which its contact outputs leave out."""
    lay = run.lay
    crank = model.body(lay.crank)
    phi_crank = crank.driver.angle0 + crank.driver.speed * t
    if model.clearance_joints[0].bearing_body == lay.rod:
        return phi_rod, phi_crank
    return phi_crank, phi_rod


def _status_text(code: int, t: float, h: float, run) -> str:
    """Why the integrator stopped, with each clearance joint's state at the last accepted point: a collapsing step
    is a contact's doing (a jammed linkage, a stuck pin, a deep penetration), and these numbers say which."""
    what = {2: "step budget exhausted", 3: "step size underflow"}[int(code)]
    cout, cpar, cint = run.w["cout"], run.a["cpar"], run.a["cint"]
    joints = []
    for k, cj in enumerate(run.model.clearance_joints):
        fn, vt, pen = cout[k, K.O_FN], abs(cout[k, K.O_VT]), cout[k, K.O_DELTA]
        text = f"joint {cj.name}: normal force {fn:.3g} N, penetration {pen * 1e6:.3g} um, slip speed {vt:.2g} m/s"
        v_s = cpar[k, K.C_VS]
        if cint[k, K.CI_FRIC] != 0 and fn > 0.0 and vt < v_s:
            text += f" (below the friction law's v_s = {v_s:.2g} m/s: sticking)"
        joints.append(text)
    return (f"{what} at t = {t:.6g} s, last step {h:.2g} s; " + "; ".join(joints)
            + " (docs/dynamics.md, 'When the step size collapses')")


def wrap_2pi(x: np.ndarray) -> np.ndarray:
    """x modulo 2 pi in [0, 2 pi) by floor division: 5-8x faster than np.mod (fmod-based), equal to it within
    rounding (an ulp of x). Returns a new array."""
    out = np.empty(np.shape(x))
    _wrap_2pi(np.ascontiguousarray(x, dtype=float).ravel(), out.ravel())
    return out


@njit(cache=True, nogil=True)
def _wrap_2pi(x, out):
    for i in range(x.shape[0]):
        r = x[i] - TWO_PI * math.floor(x[i] / TWO_PI)
        if r < 0.0:  # rounding next to a multiple of 2 pi: back into [0, 2 pi)
            r += TWO_PI
        if r >= TWO_PI:
            r -= TWO_PI
        out[i] = r


def trapezoid_weights(t: np.ndarray) -> np.ndarray:
    """Trapezoid-rule weights of the samples at times t (they sum to t[-1] - t[0])."""
    w = np.zeros_like(t)
    if t.size > 1:
        d = np.diff(t)
        w[:-1] += 0.5 * d
        w[1:] += 0.5 * d
    return w


def _package(model, geometry, cat, free_phi, joint_angles, cart, state_end, counters, n_cycles, settle, period,
             wall) -> SimulationResult:
    t = cat["rec_t"]
    crank = model.crank
    names = model.body_names
    angles = np.empty((t.size, len(names)))
    free = [b.name for b in model.free_bodies]
    for i, b in enumerate(model.bodies):
        if b.driver is None:
            angles[:, i] = free_phi[b.name]
        else:
            angles[:, i] = b.driver.angle0 + b.driver.speed * t
    crank_angle = wrap_2pi(crank.driver.angle0 + crank.driver.speed * t) if crank else np.zeros_like(t)
    w = trapezoid_weights(t)
    traces = []
    for k, (cj, g) in enumerate(zip(model.clearance_joints, geometry)):
        c = cat["rec_c"][k]  # (NCOUT, steps): the trace's series are its rows (views, each contiguous)
        ang = np.arctan2(c[K.O_NY], c[K.O_NX])
        phib, phij = joint_angles.get(k, (c[K.O_PHIB], c[K.O_PHIJ]))
        traces.append(ContactTrace(
            name=cj.name, bearing_body=cj.bearing_body, journal_body=cj.journal_body, t=t, dt_weight=w,
            theta_bearing=wrap_2pi(ang - phib), theta_journal=wrap_2pi(ang - phij),
            force_normal=c[K.O_FN], force_tangential=c[K.O_FT], slip_speed=c[K.O_VT],
            penetration=c[K.O_DELTA], penetration_rate=c[K.O_VN],
            in_contact=c[K.O_DELTA] > 0.0, eccentricity_global=c[K.O_EX:K.O_EY + 1].T,
            bearing_body_angle=phib, journal_body_angle=phij, stiffness=c[K.O_K], normal_tilt=np.arctan(c[K.O_TAN_TILT]),
            bearing_radius=g.bearing_radius, journal_radius=g.journal_radius, clearance_used=g.clearance,
            joint=cj.spec,
        ))
    return SimulationResult(
        t=t, crank_angle=crank_angle, body_angles=angles, body_names=names, free_body_names=free,
        _cart_fn=cart, multipliers=cat["rec_lam"], joint_names=[j.name for j in model.joints],
        prismatic=[j.name for j in model.joints if j.kind == "prismatic"], joints=traces,
        state_end=state_end, n_steps=int(counters[1]), n_rejected=int(counters[2]), n_recorded_steps=t.size - 1,
        n_cycles=n_cycles, settle_cycles=settle, period=period, wall_seconds=wall, drive=_drive_data(model),
    )


def _drive_data(model) -> dict:
    """What SimulationResult.driver_torque reads of the model (plain numbers: the result pickles)."""
    driven = []
    for b in model.driven_bodies:
        cx, cy = b.points[b.driver.point]
        driven.append((b.mass, *b.force, b.torque, *b.driver.pivot, cx, cy, b.driver.angle0, b.driver.speed))
    return {"gravity": tuple(model.gravity), "driven": driven,
            "free": [(b.mass, b.inertia, *b.force, b.torque) for b in model.free_bodies]}
