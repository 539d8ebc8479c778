"""Detection, tables and coordinate maps of the tree kernel (kernel.rhs_tree).

A model qualifies when its ideal joints, with the clearance joints cut, form a forest: every free body hangs by one
ideal joint from the ground, a driven body or another free body, or by none (then it moves freely between its
clearance joints). Its coordinates are then one absolute angle per body hung by a revolute joint, one slide s per
body hung by a prismatic joint (its angle is its parent's plus a constant) and (x, y, phi) per free one. Mechanisms
with a closed loop of ideal joints, or a slider on a driven body, run on the Cartesian kernel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from jointwear.mechanism import kernel as K
from jointwear.mechanism.assembly import rotate


@dataclass
class TreeLayout:
    """Tables of the tree kernel and the positions of its coordinates in the Cartesian q (3 per free body)."""

    jint: np.ndarray  # (nb, K.T_PATH + n): kind, body, parent code, first coordinate, path length, path
    jpar: np.ndarray  # (nb, kernel.NTPAR): joint point in the parent's frame (global for the ground), in the
                      # body's frame; a slider's line direction and angle offset
    mass: np.ndarray  # (3 nb,): m, m, I per free body
    cart_index: np.ndarray  # (n,): index in q of each coordinate

    @property
    def n(self) -> int:
        return int(self.cart_index.size)

    @property
    def has_slider(self) -> bool:
        """Whether a body hangs by a prismatic joint."""
        return bool(np.any(self.jint[:, K.T_KIND] == K.TREE_PRISMATIC))


def tree_layout(arrays: dict) -> TreeLayout | None:
    """The tree layout of a model from its kernel tables (MechanismModel.kernel_arrays), or None if its ideal joints
    do not form a forest, or a prismatic joint hangs a body from a driven one."""
    nb = int(arrays["nb"])
    jint, jpar, bpar = arrays["jint"], arrays["jpar"], arrays["bpar"]
    if nb == 0:
        return None
    placed = {-1, *range(nb, nb + arrays["dpar"].shape[0])}  # ground and driven bodies are roots
    used = np.zeros(jint.shape[0], dtype=bool)
    rows = []  # (kind, body, parent, its jpar row: kernel.NTPAR numbers)
    while len(rows) < nb:
        progress = False
        for k in range(jint.shape[0]):
            if used[k]:
                continue
            bi, bj = int(jint[k, 1]), int(jint[k, 2])
            if bi in placed and bj in placed:
                return None  # a closed loop of ideal joints
            if bi in placed or bj in placed:
                parent_is_i = bi in placed
                parent, body = (bi, bj) if parent_is_i else (bj, bi)
                if jint[k, 0] == K.PRISMATIC:
                    if parent >= nb:
                        return None  # a slider on a driven body: its line moves with time, not with a coordinate
                    rows.append((K.TREE_PRISMATIC, body, parent, _prismatic_table(jpar[k], parent_is_i)))
                else:
                    pp, bp = (jpar[k, 0:2], jpar[k, 2:4]) if parent_is_i else (jpar[k, 2:4], jpar[k, 0:2])
                    rows.append((K.TREE_REVOLUTE, body, parent, np.concatenate([pp, bp, np.zeros(K.NTPAR - 4)])))
                placed.add(body)
                used[k] = True
                progress = True
        if not progress:  # the rest hangs from no root: the first unplaced body moves freely
            b = next(b for b in range(nb) if b not in placed)
            rows.append((K.TREE_FLOATING, b, -1, np.zeros(K.NTPAR)))
            placed.add(b)
    if not used.all():
        return None
    n = sum(3 if row[0] == K.TREE_FLOATING else 1 for row in rows)
    tint = np.zeros((nb, K.T_PATH + n), dtype=np.int64)
    tpar = np.zeros((nb, K.NTPAR))
    path = {}  # body -> the coordinates its velocity depends on (ancestors' first, its own last)
    cart = []
    for r, (kind, b, p, table) in enumerate(rows):
        d = len(cart)
        if kind == K.TREE_FLOATING:
            cart += [3 * b, 3 * b + 1, 3 * b + 2]
            path[b] = [d, d + 1, d + 2]
        else:
            cart.append(3 * b + 2 if kind == K.TREE_REVOLUTE else -1)  # a slide is no Cartesian coordinate
            path[b] = path.get(p, []) + [d]  # ground and driven parents add nothing
        tint[r, :K.T_PATH] = (kind, b, p, d, len(path[b]))
        tint[r, K.T_PATH:K.T_PATH + len(path[b])] = path[b]
        tpar[r] = table
    mass = np.empty(3 * nb)
    mass[0::3] = bpar[:, 0]
    mass[1::3] = bpar[:, 0]
    mass[2::3] = bpar[:, 1]
    return TreeLayout(tint, tpar, mass, np.array(cart, dtype=np.int64))


def _prismatic_table(jp: np.ndarray, parent_is_i: bool) -> np.ndarray:
    """A prismatic joint's tree row (kernel.NTPAR numbers) from its Cartesian one (kernel.eval_constraints: points
    a_i, a_j, the normal n_i of the sliding line in body i's frame, angle0 = phi_i - phi_j). The line through the
    parent's point with direction u carries the body's point at s u. Either body may own the line: the relative angle
    is fixed, so the owner's direction k x n_i is carried into the parent's frame."""
    u_i = (-jp[5], jp[4])
    if parent_is_i:
        parent_point, body_point, beta, u = jp[0:2], jp[2:4], -jp[6], u_i
    else:
        parent_point, body_point, beta = jp[2:4], jp[0:2], jp[6]
        u = rotate(beta, u_i)
    return np.concatenate([parent_point, body_point, u, [beta, np.cos(beta), np.sin(beta)]])


def angle_scales(lay: TreeLayout) -> np.ndarray:
    """True for the coordinates that are angles (the others are positions of freely moving or sliding bodies)."""
    return (lay.cart_index >= 0) & (lay.cart_index % 3 == 2)


def to_tree(lay: TreeLayout, y_cart: np.ndarray) -> np.ndarray:
    """Cartesian state (q, qd) -> tree state: the selected coordinates and their rates (the rest follows from the
    ideal joints, which the Cartesian state satisfies); a slide s = (p_body - p_line) . u, its rate from the points'
    velocities (the offset is along u, so the line's turning adds nothing)."""
    nq = y_cart.size // 2
    q, qd = y_cart[:nq], y_cart[nq:]
    idx = np.maximum(lay.cart_index, 0)
    out = np.concatenate([q[idx], qd[idx]])
    for r in range(lay.jint.shape[0]):
        if lay.jint[r, K.T_KIND] != K.TREE_PRISMATIC:
            continue
        b, p, d = (int(v) for v in lay.jint[r, [K.T_BODY, K.T_PARENT, K.T_DOF]])
        tp = lay.jpar[r]
        parent = np.zeros(3) if p < 0 else q[3 * p:3 * p + 3]  # the ground's pose and rates are zero
        parent_rate = np.zeros(3) if p < 0 else qd[3 * p:3 * p + 3]
        ap, u = np.array(rotate(parent[2], tp[0:2])), np.array(rotate(parent[2], tp[4:6]))
        ab = np.array(rotate(q[3 * b + 2], tp[2:4]))
        gap = q[3 * b:3 * b + 2] + ab - parent[:2] - ap
        rate = (qd[3 * b:3 * b + 2] + qd[3 * b + 2] * np.array([-ab[1], ab[0]])
                - parent_rate[:2] - parent_rate[2] * np.array([-ap[1], ap[0]]))
        out[d] = gap @ u
        out[lay.n + d] = rate @ u
    return out


def body_angles(lay: TreeLayout, Y: np.ndarray) -> np.ndarray:
    """(steps, nb) angle of every free body from tree states (steps, 2 n): a coordinate, or a sliding body's
    parent's angle + beta (prismatic parents are the ground or free bodies)."""
    Y = np.atleast_2d(Y)
    out = np.zeros((Y.shape[0], lay.jint.shape[0]))
    for r in range(lay.jint.shape[0]):  # rows come parents first
        kind, b, p, d = (int(v) for v in lay.jint[r, [K.T_KIND, K.T_BODY, K.T_PARENT, K.T_DOF]])
        if kind == K.TREE_PRISMATIC:
            out[:, b] = (0.0 if p < 0 else out[:, p]) + lay.jpar[r, 6]
        else:
            out[:, b] = Y[:, d + 2 if kind == K.TREE_FLOATING else d]
    return out


def to_cartesian(lay: TreeLayout, dpar: np.ndarray, t: np.ndarray, Y: np.ndarray, Ydd: np.ndarray | None = None):
    """(steps, 2 n) tree states at times t (and accelerations (steps, n)) -> q, qd, qdd (steps, 3 nb)."""
    Y = np.ascontiguousarray(np.atleast_2d(Y))
    t = np.ascontiguousarray(np.atleast_1d(t), dtype=float)
    nb = lay.jint.shape[0]
    q = np.empty((Y.shape[0], 3 * nb))
    qd = np.empty_like(q)
    qdd = np.empty_like(q)
    acc = np.zeros((Y.shape[0], lay.n)) if Ydd is None else np.ascontiguousarray(Ydd)
    _tree_to_cartesian(t, Y, acc, nb, dpar, lay.jint, lay.jpar, q, qd, qdd)
    return q, qd, (None if Ydd is None else qdd)


@njit(cache=True, nogil=True)
def _tree_to_cartesian(t, Y, Ydd, nb, dpar, jint, jpar, q, qd, qdd):
    n = Y.shape[1] // 2
    nd = dpar.shape[0]
    kin = np.zeros((nb + nd + 1, K.NKIN))
    cacc = np.zeros(3 * nb)
    jt = np.zeros((3 * nb, n))  # by path (kernel.T_PATH)
    cb = np.zeros(n + nd)
    sb = np.zeros(n + nd)
    for i in range(Y.shape[0]):
        y = Y[i]
        K.tree_base(t[i], y, jint, dpar, kin, cb, sb)
        K.tree_kinematics(t[i], 0.0, y, y, cb, sb, nb, dpar, jint, jpar, kin, cacc, jt)
        for b in range(nb):
            q[i, 3 * b] = kin[b, K.K_X]
            q[i, 3 * b + 1] = kin[b, K.K_Y]
            q[i, 3 * b + 2] = kin[b, K.K_PHI]
            qd[i, 3 * b] = kin[b, K.K_VX]
            qd[i, 3 * b + 1] = kin[b, K.K_VY]
            qd[i, 3 * b + 2] = kin[b, K.K_W]
        for r in range(jint.shape[0]):
            b = jint[r, K.T_BODY]
            for c in range(3 * b, 3 * b + 3):
                a = cacc[c]
                for k in range(jint[r, K.T_LEN]):
                    a += jt[c, k] * Ydd[i, jint[r, K.T_PATH + k]]
                qdd[i, c] = a


def work_arrays(lay: TreeLayout, nd: int, ncj: int) -> dict[str, np.ndarray]:
    """Work arrays of the tree kernel in the slots of the Cartesian kernel's (kernel.empty_work): phi_, phid hold the
    base cos/sin (coordinates, then drivers), rest the accelerations at qdd = 0, jac the velocity Jacobian, smat the
    mass matrix, lam the generalized forces."""
    nb = lay.jint.shape[0]
    n = lay.n
    return {
        "kin": np.zeros((nb + nd + 1, K.NKIN)),
        "phi_": np.zeros(n + nd),
        "phid": np.zeros(n + nd),
        "rest": np.zeros(3 * nb),
        "jac": np.zeros((3 * nb, n)),
        "smat": np.zeros((n, n)),
        "lam": np.zeros(n),
        "f": np.zeros(3 * nb),
        "cout": np.zeros((ncj, K.NCOUT)),
    }


def atol_vector(lay: TreeLayout, atol: float, length_ref: float, omega_ref: float) -> np.ndarray:
    """Absolute tolerances per coordinate and rate, as the Cartesian kernel's for the same components (positions
    atol, angles atol / L_ref; rates times the driver speed)."""
    pos = np.where(angle_scales(lay), atol / length_ref, atol)
    return np.concatenate([pos, pos * omega_ref])

