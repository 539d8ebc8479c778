"""Detection and coordinate maps of the natural-coordinate fast path (kernel.rhs_fourbar).

A model qualifies when it is a four-bar whose crank is driven and whose only clearance joint sits
between the crank and the rod: one driven body, two free bodies (rod, rocker), ideal revolutes
rod-rocker (B) and ground-rocker (C), all joint points of rod and rocker on their body x axes.
Everything else goes through the general Cartesian kernel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from jointwear.mechanism import kernel as K
from jointwear.mechanism.model import GROUND, MechanismModel


@dataclass
class FastLayout:
    rod: str
    rocker: str
    crank: str
    s_rod_a: tuple[float, float]  # rod point at the clearance joint (body frame)
    s_rod_b: tuple[float, float]
    s_rock_c: tuple[float, float]
    s_rock_b: tuple[float, float]
    c_point: tuple[float, float]  # global rocker pivot
    fp: np.ndarray  # (1, NFP)


def fast_layout(model: MechanismModel) -> FastLayout | None:
    free = model.free_bodies
    driven = model.driven_bodies
    if len(free) != 2 or len(driven) != 1 or len(model.clearance_joints) != 1 or len(model.joints) != 2:
        return None
    crank = driven[0]
    cj = model.clearance_joints[0]
    if crank.name not in (cj.bearing_body, cj.journal_body):
        return None
    rod_name = cj.journal_body if cj.bearing_body == crank.name else cj.bearing_body
    if rod_name not in [b.name for b in free]:
        return None
    rocker = next(b for b in free if b.name != rod_name)
    rod = model.body(rod_name)
    jb = jc = None
    for j in model.joints:
        if j.kind != "revolute":
            return None
        if {j.body_i, j.body_j} == {rod.name, rocker.name}:
            jb = j
        elif {j.body_i, j.body_j} == {GROUND, rocker.name}:
            jc = j
    if jb is None or jc is None:
        return None
    s_rod_a = rod.points[cj.bearing_point if cj.bearing_body == rod.name else cj.journal_point]
    s_rod_b = rod.points[jb.point_i if jb.body_i == rod.name else jb.point_j]
    s_rock_b = rocker.points[jb.point_i if jb.body_i == rocker.name else jb.point_j]
    s_rock_c = rocker.points[jc.point_i if jc.body_i == rocker.name else jc.point_j]
    c_point = model.ground_points[jc.point_i if jc.body_i == GROUND else jc.point_j]
    if any(abs(p[1]) > 0.0 for p in (s_rod_a, s_rod_b, s_rock_b, s_rock_c)):
        return None
    l2 = s_rod_b[0] - s_rod_a[0]
    l3 = s_rock_b[0] - s_rock_c[0]
    if not (l2 > 0 and l3 > 0):
        return None
    xi2 = -s_rod_a[0] / l2
    xi3 = -s_rock_c[0] / l3
    m2, i2, m3, i3 = rod.mass, rod.inertia, rocker.mass, rocker.inertia
    maa = m2 * (1 - xi2) ** 2 + i2 / l2**2
    mab = m2 * xi2 * (1 - xi2) - i2 / l2**2
    mbb = m2 * xi2**2 + i2 / l2**2 + m3 * xi3**2 + i3 / l3**2
    det = maa * mbb - mab**2
    g = np.array(model.gravity, dtype=float)
    f2 = m2 * g + np.array(rod.force)
    f3 = m3 * g + np.array(rocker.force)
    qa = (1 - xi2) * f2
    qb = xi2 * f2 + xi3 * f3
    s_pin = crank.points[cj.bearing_point if cj.bearing_body == crank.name else cj.journal_point]
    s_o = crank.points[crank.driver.point]
    fp = np.zeros((1, K.NFP))
    fp[0, K.FP_L2], fp[0, K.FP_L3] = l2, l3
    fp[0, K.FP_CX], fp[0, K.FP_CY] = c_point
    fp[0, K.FP_P], fp[0, K.FP_R], fp[0, K.FP_S] = mbb / det, -mab / det, maa / det
    fp[0, K.FP_QAX], fp[0, K.FP_QAY] = qa
    fp[0, K.FP_QBX], fp[0, K.FP_QBY] = qb
    fp[0, K.FP_T3] = rocker.torque
    fp[0, K.FP_T2] = rod.torque
    fp[0, K.FP_SIG] = 1.0 if cj.bearing_body == rod.name else -1.0
    fp[0, K.FP_PX], fp[0, K.FP_PY] = s_pin[0] - s_o[0], s_pin[1] - s_o[1]
    return FastLayout(rod.name, rocker.name, crank.name, s_rod_a, s_rod_b, s_rock_c, s_rock_b, tuple(c_point), fp)


def _rot(phi, v):
    c, s = np.cos(phi), np.sin(phi)
    return c * v[0] - s * v[1], s * v[0] + c * v[1]


def to_natural(model: MechanismModel, lay: FastLayout, y: np.ndarray) -> np.ndarray:
    """Cartesian free-body state (x, y, phi per body; velocities) -> (A, B, Adot, Bdot)."""
    names = [b.name for b in model.free_bodies]
    nq = 3 * len(names)
    i = 3 * names.index(lay.rod)
    x, yy, ph = y[i: i + 3]
    vx, vy, w = y[nq + i: nq + i + 3]
    ax_, ay_ = _rot(ph, lay.s_rod_a)
    bx_, by_ = _rot(ph, lay.s_rod_b)
    return np.array([x + ax_, yy + ay_, x + bx_, yy + by_, vx - w * ay_, vy + w * ax_, vx - w * by_, vy + w * bx_])


def to_cartesian(model: MechanismModel, lay: FastLayout, Y: np.ndarray, Ydd: np.ndarray | None = None,
                 phi_ref: dict[str, float] | None = None):
    """(steps, 8) natural states (+ accelerations (steps, 4)) -> q, qd, qdd (steps, 6) in model order."""
    Y = np.atleast_2d(Y)
    A, B, Ad, Bd = Y[:, 0:2], Y[:, 2:4], Y[:, 4:6], Y[:, 6:8]
    C = np.asarray(lay.c_point)
    out = {}
    for name, P, Pd, s_p, Q, Qd in (
        (lay.rod, A, Ad, lay.s_rod_a, B, Bd),
        (lay.rocker, np.broadcast_to(C, B.shape), np.zeros_like(B), lay.s_rock_c, B, Bd),
    ):
        d = Q - P
        dd = Qd - Pd
        d2 = np.sum(d * d, axis=1)
        phi = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        if phi_ref is not None and name in phi_ref:  # continue the Cartesian angle branch
            phi += 2 * np.pi * np.round((phi_ref[name] - phi[0]) / (2 * np.pi))
        w = (d[:, 0] * dd[:, 1] - d[:, 1] * dd[:, 0]) / d2
        rx, ry = _rot(phi, s_p)  # COM -> point P
        gx, gy = P[:, 0] - rx, P[:, 1] - ry
        vx, vy = Pd[:, 0] + w * ry, Pd[:, 1] - w * rx
        q = np.column_stack([gx, gy, phi])
        qd = np.column_stack([vx, vy, w])
        qdd = None
        if Ydd is not None:
            Pdd = Ydd[:, 0:2] if name == lay.rod else np.zeros_like(B)
            Qdd = Ydd[:, 2:4]
            ddd = Qdd - Pdd
            al = (d[:, 0] * ddd[:, 1] - d[:, 1] * ddd[:, 0]) / d2
            # G = P - r, r = R(phi) s_p:  Gdd = Pdd - (al k x r - w^2 r)
            gax = Pdd[:, 0] - (-al * ry - w * w * rx)
            gay = Pdd[:, 1] - (al * rx - w * w * ry)
            qdd = np.column_stack([gax, gay, al])
        out[name] = (q, qd, qdd)
    names = [b.name for b in model.free_bodies]
    q = np.hstack([out[n][0] for n in names])
    qd = np.hstack([out[n][1] for n in names])
    qdd = np.hstack([out[n][2] for n in names]) if Ydd is not None else None
    return q, qd, qdd


def to_cartesian_point(model: MechanismModel, lay: FastLayout, y: np.ndarray, phi_ref: dict[str, float]
                       ) -> tuple[np.ndarray, np.ndarray]:
    """One natural state (A, B, Adot, Bdot) -> q, qd (model order), angles on the branch of phi_ref; the scalar
    form of to_cartesian (which costs ~0.3 ms of numpy calls for a single row, a tenth of a simulated cycle)."""
    ax, ay, bx, by, avx, avy, bvx, bvy = (float(v) for v in y)
    cx, cy = lay.c_point
    out = {}
    for name, px, py, pvx, pvy, s_p in ((lay.rod, ax, ay, avx, avy, lay.s_rod_a),
                                        (lay.rocker, cx, cy, 0.0, 0.0, lay.s_rock_c)):
        dx, dy, ddx, ddy = bx - px, by - py, bvx - pvx, bvy - pvy
        phi = math.atan2(dy, dx)
        if name in phi_ref:
            phi += 2 * math.pi * round((phi_ref[name] - phi) / (2 * math.pi))
        w = (dx * ddy - dy * ddx) / (dx * dx + dy * dy)
        c, s = math.cos(phi), math.sin(phi)
        rx, ry = c * s_p[0] - s * s_p[1], s * s_p[0] + c * s_p[1]  # COM -> point P
        out[name] = ((px - rx, py - ry, phi), (pvx + w * ry, pvy - w * rx, w))
    names = [b.name for b in model.free_bodies]
    q = np.array([v for n in names for v in out[n][0]])
    qd = np.array([v for n in names for v in out[n][1]])
    return q, qd


@njit(cache=True, nogil=True)
def _unwrapped_direction(Y, from_a, cx, cy, out):
    """Angle of B - P over the steps (P = A = Y[:, 0:2], or the fixed point (cx, cy)), unwrapped as np.unwrap
    (jumps larger than pi in magnitude are taken modulo 2 pi) in one pass."""
    two_pi = 2.0 * math.pi
    off = 0.0
    prev = 0.0
    for i in range(Y.shape[0]):
        px = Y[i, 0] if from_a else cx
        py = Y[i, 1] if from_a else cy
        a = math.atan2(Y[i, 3] - py, Y[i, 2] - px) + off
        if i > 0:
            while a - prev > math.pi:
                a -= two_pi
                off -= two_pi
            while a - prev < -math.pi:
                a += two_pi
                off += two_pi
        out[i] = a
        prev = a


def natural_angles(lay: FastLayout, Y: np.ndarray, phi_ref: dict[str, float] | None = None) -> dict[str, np.ndarray]:
    """Unwrapped angles of rod and rocker from (steps, 8) natural states (cheap; no velocities)."""
    Y = np.ascontiguousarray(np.atleast_2d(Y), dtype=float)
    out = {}
    for name, from_a in ((lay.rod, True), (lay.rocker, False)):
        phi = np.empty(Y.shape[0])
        _unwrapped_direction(Y, from_a, float(lay.c_point[0]), float(lay.c_point[1]), phi)
        if phi_ref is not None and name in phi_ref:
            phi += 2 * np.pi * np.round((phi_ref[name] - phi[0]) / (2 * np.pi))
        out[name] = phi
    return out
