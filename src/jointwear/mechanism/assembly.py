"""Assembly of a general planar linkage (``mechanism.type = "general"``) over one cycle.

The drawing is the assembly configuration at t = 0: the linkage is assembled around it (so the branch is the one
drawn) and tracked by continuation over one revolution of the first driver; the poses are tabulated as the
assembly guess of the dynamics. A linkage that cannot be assembled raises :class:`AssemblyError` naming the links;
:func:`check_assembly` is the config-level check (a ConfigError naming the field) that runs after the schema.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np

from jointwear.mechanism.model import GROUND, Body, Driver, Joint, MechanismModel
from jointwear.schema import ConfigError, item_key


def rotate(phi: float, v: tuple[float, float]) -> tuple[float, float]:
    """The vector v turned by phi (rad, CCW)."""
    c, s = math.cos(phi), math.sin(phi)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


@dataclass
class TableGuess:
    """Assembly guess of a general linkage: free-body poses tabulated over one cycle by continuation
    from the drawn configuration, interpolated linearly (periodic in t); picklable."""

    period: float
    names: list[str]
    table: np.ndarray  # (n + 1, 3 n_free): q at t_k = k period / n; row n closes the cycle (angles unwrapped)

    def __call__(self, t: float) -> dict[str, tuple[float, float, float]]:
        n = self.table.shape[0] - 1
        u = (t / self.period) % 1.0 * n
        i = min(int(u), n - 1)
        fr = u - i
        q = self.table[i] * (1.0 - fr) + self.table[i + 1] * fr
        return {name: (float(q[3 * k]), float(q[3 * k + 1]), float(q[3 * k + 2])) for k, name in enumerate(self.names)}


@dataclass(frozen=True)
class DeadPointMargin:
    """How close the one-cycle assembly sweep of a general linkage comes to a dead point: the smallest ratio of the
    smallest to the largest singular value of the constraint Jacobian (angle columns scaled by the reference length,
    so dimensionless; 0 at a dead point, where the assembly refuses below 1e-6) over the ``assembly_steps`` positions,
    where it occurs and the links involved (the bodies carrying the near-singular self-stress and motion)."""

    ratio: float
    turn_deg: float  # the first driver's turn from the drawing where the ratio is smallest, deg (signed as its speed)
    driver_angle_deg: float  # the first driver's axis angle there in the drawing's frame, deg in [0, 360)
    links: tuple[str, ...]


@dataclass
class GeneralParts:
    """A general linkage ready to be a MechanismModel: bodies, ideal joints, ground points, assembly guess, and the
    sweep's closest approach to a dead point."""

    bodies: list[Body]
    joints: list[Joint]
    ground_points: dict
    guess: TableGuess
    length_ref: float
    period: float
    dead_point: DeadPointMargin | None = None

class AssemblyError(ValueError):
    """A general linkage cannot be assembled (one-line message naming the links)."""


_GENERAL_CACHE: dict[str, tuple[TableGuess, DeadPointMargin]] = {}


def _body_angle0(b) -> float:
    if b.axis is None:
        return 0.0
    pa, pb = b.points[b.axis[0]], b.points[b.axis[1]]
    return math.atan2(pb[1] - pa[1], pb[0] - pa[0])


def _general_topology(m) -> tuple[list[Body], list[Joint], dict, dict, float]:
    """Bodies (driven first, in driver order, then the others in config order), ideal joints (driver joints
    removed), ground points, drawn poses of the free bodies, reference length."""
    cfg_bodies = {b.name: b for b in m.bodies}
    phi0 = {n: _body_angle0(b) for n, b in cfg_bodies.items()}
    phi0[GROUND] = 0.0
    jmap = {j.name: j for j in m.joints}
    drivers: dict[str, Driver] = {}
    for d in m.drivers:
        j = jmap[d.joint]
        (bi, pi), (bj, pj) = (r.split(".") for r in j.connects)
        (body, bpt), gpt = ((bj, pj), pi) if bi == GROUND else ((bi, pi), pj)
        drivers[body] = Driver(tuple(m.ground_points[gpt]), bpt, phi0[body], d.speed)

    def local(name: str, p) -> tuple[float, float]:
        b = cfg_bodies[name]
        return rotate(-phi0[name], (p[0] - b.com[0], p[1] - b.com[1]))

    order = list(drivers) + [n for n in cfg_bodies if n not in drivers]
    bodies = []
    for n in order:
        b = cfg_bodies[n]
        bodies.append(Body(n, b.mass, b.inertia, {k: local(n, p) for k, p in b.points.items()},
                           driver=drivers.get(n), force=tuple(b.force), torque=b.torque))
    driver_joints = {d.joint for d in m.drivers}
    joints = []
    for j in m.joints:
        if j.name in driver_joints:
            continue
        (bi, pi), (bj, pj) = (r.split(".") for r in j.connects)
        if j.type == "revolute":
            joints.append(Joint(j.name, "revolute", bi, pi, bj, pj))
        else:
            d = j.direction
            nrm = (-d[1] / math.hypot(*d), d[0] / math.hypot(*d))
            joints.append(Joint(j.name, "prismatic", bi, pi, bj, pj, normal_i=rotate(-phi0[bi], nrm),
                                angle0=phi0[bi] - phi0[bj]))
    poses = {n: (cfg_bodies[n].com[0], cfg_bodies[n].com[1], phi0[n]) for n in order if n not in drivers}
    lref = drawn_link_size([b.points.values() for b in m.bodies])
    return bodies, joints, {k: tuple(v) for k, v in m.ground_points.items()}, poses, lref


def drawn_link_size(points_of_bodies) -> float:
    """The reference length of a drawn general linkage: the median over its bodies of the largest distance
    between two points of one body (0.01 m for a linkage of point bodies)."""
    sizes = []
    for points in points_of_bodies:
        pts = list(points)
        if len(pts) > 1:
            sizes.append(max(math.dist(p, q) for p in pts for q in pts))
    return float(np.median(sizes)) if sizes else 0.01


#: Fraction of the median link size above which a drawn gap that the assembly closes is worth a warning: a drawing
#: whose coordinates are rounded to 0.01 mm stays below it on links of 10 mm and more, a misplaced point does not.
GAP_WARNING = 1e-3


def joint_gaps(m) -> list[tuple[int, object, float]]:
    """(index, joint, gap in m) of each joint of a general mechanism: a revolute joint's distance between its two
    drawn points, a prismatic joint's distance of its second point from its guide (the line through its first point
    along ``direction``)."""
    pts = {(b.name, k): p for b in m.bodies for k, p in b.points.items()}
    pts.update({(GROUND, k): p for k, p in m.ground_points.items()})
    out = []
    for i, j in enumerate(m.joints):
        a, b = (pts[tuple(r.split("."))] for r in j.connects)
        if j.type == "revolute":
            out.append((i, j, math.dist(a, b)))
        else:
            d = j.direction
            out.append((i, j, abs((b[0] - a[0]) * d[1] - (b[1] - a[1]) * d[0]) / math.hypot(*d)))
    return out


def gap_text(joint, gap: float) -> str:
    """What a drawn gap of ``joint`` is, in words: two points apart (revolute) or a point off its guide (prismatic)."""
    if joint.type == "revolute":
        return (f"the drawn points {joint.connects[0]} and {joint.connects[1]} of revolute joint '{joint.name}' are "
                f"{gap * 1e3:.4g} mm apart")
    return (f"the drawn point {joint.connects[1]} of prismatic joint '{joint.name}' lies {gap * 1e3:.4g} mm off its "
            f"guide (the line through {joint.connects[0]} along its direction)")


def _joint_gap_check(m, lref: float) -> None:
    """The two drawn points of a revolute joint must (nearly) coincide, a prismatic joint's point (nearly) lie on
    its guide."""
    names = [j.name for j in m.joints]
    for i, j, gap in joint_gaps(m):
        if gap > m.closure_tolerance * lref:
            raise AssemblyError(
                f"joints[{item_key(i, names)}].connects: {gap_text(j, gap)} (allowed "
                f"{m.closure_tolerance * lref * 1e3:.4g} mm = closure_tolerance x median link size): "
                + ("draw them at the same place" if j.type == "revolute" else "draw the point on the guide")
                + " (a point mistyped, or a body's points in other units than the rest: points_mm against points, "
                "which are in m)"
            )


def _culprits(model: MechanismModel, u: np.ndarray, v: np.ndarray, frac: float = 0.1) -> list[str]:
    """Links of a singular Jacobian: the bodies carrying both the self-stress (left singular vector u, over the
    joints) and the free motion (right singular vector v, over the free bodies); the former alone if none."""
    rows = np.abs(u)
    bad = [j for k, j in enumerate(model.joints) if max(rows[2 * k], rows[2 * k + 1]) >= frac * rows.max()]
    stressed = {b for j in bad for b in (j.body_i, j.body_j)}
    both = stressed & set(_links_of(model, v, frac))
    return [b.name for b in model.bodies if b.name in (both or stressed)]


def _links_of(model: MechanismModel, v: np.ndarray, frac: float = 0.1) -> list[str]:
    """Free bodies with a large share of the vector v over the free coordinates."""
    free = [b.name for b in model.free_bodies]
    mag = np.array([np.linalg.norm(v[3 * k: 3 * k + 3]) for k in range(len(free))])
    if mag.size == 0 or mag.max() == 0:
        return free
    return [n for n, x in zip(free, mag) if x >= frac * mag.max()]


def _assemble_at(model: MechanismModel, arrays, t: float, q: np.ndarray, lref: float, where: str
                 ) -> tuple[np.ndarray, np.ndarray, float, np.ndarray, np.ndarray]:
    """Positions and velocities at time t from the predicted q (model.newton, angle columns scaled to lengths:
    a dimensionless condition number), the ratio sv_min / sv_max of the scaled constraint Jacobian there and its
    singular vectors of sv_min (left over the joints, right over the free coordinates). AssemblyError naming the
    links when the loop does not close or the constraint Jacobian is singular."""
    zero = np.zeros_like(q)
    scale = np.ones_like(q)
    scale[2::3] = lref
    q_start = q.copy()
    q, _ = model.newton(t, q, arrays, tol=1e-13, max_iter=30, scale=scale, max_step=10.0)
    phi, phid0, _, jac = model.constraint_eval(t, q, zero, arrays)
    if not np.all(np.isfinite(phi)) or np.max(np.abs(phi)) > 1e-10 * lref:
        # the loop that fails: the near-singular direction of the Jacobian where Newton started (close to a
        # limit position the loop that cannot close has a vanishing singular value)
        _, _, jac0 = model.constraint_eval(t, q_start, zero, arrays)[1:]
        u0, _, vt0 = np.linalg.svd(jac0 / scale[None, :], full_matrices=False)
        raise AssemblyError(
            f"cannot assemble {where}: the loop through links {', '.join(_culprits(model, u0[:, -1], vt0[-1]))} "
            "does not close (links too short or too long for this position, or a dead point)"
        )
    u, sv, vt = np.linalg.svd(jac / scale[None, :], full_matrices=False)
    if sv[-1] < 1e-6 * sv[0]:
        raise AssemblyError(
            f"cannot assemble {where}: the constraint Jacobian is singular (dead point, lock-up or redundant joints) "
            f"at links {', '.join(_culprits(model, u[:, -1], vt[-1]))}"
        )
    qd = np.linalg.solve(jac, -phid0) if jac.shape[0] == jac.shape[1] else np.linalg.lstsq(jac, -phid0, rcond=None)[0]
    # the dead-point margin: a constraint on angles alone (a prismatic joint's parallelism) is dimensionless, so its
    # row is brought to lengths too (x L_ref); otherwise its 1 / L_ref entry alone sets sv_max (a slider-crank with a
    # 75-deg transmission angle would read 0.02)
    angle_rows = ~np.any(jac[:, (np.arange(q.size) % 3) != 2] != 0.0, axis=1)
    if np.any(angle_rows):
        scaled = jac / scale[None, :]
        scaled[angle_rows] *= lref
        u, sv, vt = np.linalg.svd(scaled, full_matrices=False)
    return q, qd, float(sv[-1] / sv[0]), u[:, -1], vt[-1]


def _general_parts(m) -> GeneralParts:
    """Topology, drawn-configuration assembly and the one-cycle assembly table (cached per mechanism)."""
    bodies, joints, gpts, poses, lref = _general_topology(m)
    period = 2.0 * math.pi / abs(m.drivers[0].speed)
    # the assembly depends on the geometry only (not on masses, inertias or loads): cache it by geometry, so
    # that sampled masses or materials do not redo it
    key = m.model_dump_json(exclude={"gravity": True, "bodies": {"__all__": {"mass", "inertia", "force", "torque"}}})
    hit = _GENERAL_CACHE.get(key)
    if hit is not None:
        return GeneralParts(bodies, joints, gpts, copy.deepcopy(hit[0]), lref, period, hit[1])
    _joint_gap_check(m, lref)
    model = MechanismModel(bodies=bodies, joints=joints, ground_points=gpts, length_ref=lref, period_override=period)
    arrays = model.kernel_arrays()
    q0 = model.state_from_poses(poses)
    q, qd, ratio, u_min, v_min = _assemble_at(model, arrays, 0.0, q0, lref, "at the drawn configuration")
    k_min = 0
    drawn_shift = np.abs(q - q0)
    drawn_shift[2::3] *= lref
    # a drawing is trusted to a quarter of a link; a sample that moves drawn points widens the closure tolerance
    # (uncertainty apply_sample), and the bodies may then move by five of those gaps to close them
    if np.max(drawn_shift) > max(0.25, 5.0 * m.closure_tolerance) * lref:
        k = int(np.argmax(drawn_shift)) // 3
        raise AssemblyError(
            f"cannot assemble near the drawn configuration: body '{model.free_bodies[k].name}' had to move "
            f"{np.max(drawn_shift) * 1e3:.3g} mm to close the joints (check the drawn points)"
        )
    n = int(m.assembly_steps)
    dt = period / n
    speed0 = m.drivers[0].speed
    table = [q.copy()]
    for k in range(1, n + 1):
        pred = q + qd * dt
        where = f"after the first driver turned {math.degrees(speed0 * k * dt):+.1f} deg from the drawing"
        q_new, qd, r_k, u_k, v_k = _assemble_at(model, arrays, k * dt, pred, lref, where)
        if r_k < ratio:  # the sweep's closest approach to a dead point (its links found once, below)
            ratio, u_min, v_min, k_min = r_k, u_k, v_k, k
        jump = np.abs(q_new - pred)
        jump[2::3] *= lref
        if np.max(jump) > 0.05 * lref:
            raise AssemblyError(
                f"cannot assemble {where}: links {', '.join(_links_of(model, jump))} jump to another assembly "
                "branch (the linkage passes a dead point)"
            )
        q = q_new
        table.append(q.copy())
    tab = np.array(table)
    if model.n_dof > 0:  # free motion is decided by the dynamics: only the existence of an assembly is checked
        tab[-1] = tab[0]  # the guess table is periodic; its rows are assembled (minimum-norm) poses
        gap = np.zeros(1)
    else:
        gap = np.abs(tab[-1] - tab[0])
        gap[2::3] = np.abs((gap[2::3] + math.pi) % (2 * math.pi) - math.pi) * lref
    if np.max(gap) > 1e-6 * lref:
        raise AssemblyError(
            f"cannot assemble: links {', '.join(_links_of(model, gap))} do not return to the drawn configuration "
            "after one revolution of the first driver (branch change)"
        )
    guess = TableGuess(period, [b.name for b in model.free_bodies], tab)
    turn = math.degrees(speed0 * k_min * dt)
    angle0 = bodies[0].driver.angle0 if bodies[0].driver is not None else 0.0
    margin = DeadPointMargin(ratio, turn, (math.degrees(angle0) + turn) % 360.0,
                             tuple(_culprits(model, u_min, v_min)))
    if len(_GENERAL_CACHE) > 32:
        _GENERAL_CACHE.pop(next(iter(_GENERAL_CACHE)))
    _GENERAL_CACHE[key] = (copy.deepcopy(guess), margin)
    return GeneralParts(bodies, joints, gpts, guess, lref, period, margin)


def check_assembly(config) -> None:
    """The numerical assembly check that follows the schema.

    Parameters
    ----------
    config : StudyConfig
        A config validated by the schema. A general linkage must assemble over its whole cycle; the closure of
        the four-bar and the slider-crank is a schema rule (nothing to do here).

    Raises
    ------
    ConfigError
        'mechanism: cannot assemble ...', naming the links.
    """
    if config.mechanism.type == "general":
        general_parts(config.mechanism)


def general_parts(m) -> GeneralParts:
    """The parts of a general linkage (cached by geometry), ConfigError 'mechanism: ...' when it cannot assemble."""
    try:
        return _general_parts(m)
    except AssemblyError as exc:
        text = f"mechanism.{exc}" if str(exc).startswith(("joints[", "bodies[")) else f"mechanism: {exc}"
        raise ConfigError(text, [text]) from None
