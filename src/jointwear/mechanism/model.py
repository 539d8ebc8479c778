"""Planar multibody model: bodies, joints, drivers, clearance joints, assembly and kinematics.

Body frames have their origin at the centre of mass.  A body with a :class:`Driver` turns at
constant speed about a ground pivot and is prescribed (not in the state vector).  Free bodies carry
q = (x, y, phi) and qd.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from jointwear.config import ConfigError, StudyConfig
from jointwear.contact.geometry import DEFAULT_N_GRID, ClearanceGeometry
from jointwear.contact.laws import FRICTION_CODES, LAW_CODES, contact_stiffness_py
from jointwear.mechanism import kernel as K

GROUND = "ground"


@dataclass
class Driver:
    """Constant-speed rotation of a body about a ground pivot: phi(t) = angle0 + speed * t."""

    pivot: tuple[float, float]  # global coordinates of the pivot (m)
    point: str  # name of the body point that sits on the pivot
    angle0: float  # rad
    speed: float  # rad/s, CCW positive


@dataclass
class Body:
    name: str
    mass: float
    inertia: float
    points: dict[str, tuple[float, float]]  # body-frame coordinates (m), origin at the centre of mass
    driver: Driver | None = None
    force: tuple[float, float] = (0.0, 0.0)  # constant applied force at the centre of mass (N)
    torque: float = 0.0  # constant applied torque (N m)


@dataclass
class Joint:
    """Ideal joint between body_i and body_j ('ground' allowed)."""

    name: str
    kind: str  # "revolute" | "prismatic"
    body_i: str
    point_i: str
    body_j: str
    point_j: str
    normal_i: tuple[float, float] = (0.0, 1.0)  # prismatic: normal to the sliding axis, body-i frame
    angle0: float = 0.0  # prismatic: phi_i - phi_j


@dataclass
class Material:
    name: str
    youngs_modulus: float  # Pa
    poissons_ratio: float
    hardness: float  # Pa
    wear_coefficient: float  # dimensionless

    @property
    def h(self) -> float:
        """(1 - nu^2) / E, 1/Pa."""
        return (1.0 - self.poissons_ratio**2) / self.youngs_modulus


@dataclass
class ClearanceJoint:
    """A revolute joint with clearance: journal on journal_body inside a bearing on bearing_body."""

    name: str
    bearing_body: str
    bearing_point: str
    journal_body: str
    journal_point: str
    bearing_radius: float
    journal_radius: float
    width: float
    bearing_material: Material
    journal_material: Material
    bearing_outer_radius: float | None = None
    contact_law: str = "lankarani_nikravesh"
    exponent: float = 1.5
    restitution: float = 0.9
    v0_min: float = 1e-4
    friction_law: str = "ambrosio"
    mu_d: float = 0.1
    mu_s: float = 0.15
    v_s: float = 1e-4
    v_d: float = 1e-3

    @property
    def clearance(self) -> float:
        return self.bearing_radius - self.journal_radius

    @property
    def hsum(self) -> float:
        return self.bearing_material.h + self.journal_material.h

    @property
    def stiffness(self) -> float:
        """Nominal K (unworn), N/m^1.5."""
        bm, jm = self.bearing_material, self.journal_material
        return contact_stiffness_py(bm.youngs_modulus, bm.poissons_ratio, jm.youngs_modulus, jm.poissons_ratio,
                                    self.bearing_radius, self.journal_radius)


@dataclass
class IntegratorSettings:
    rtol: float = 1e-6
    atol: float = 1e-9
    max_step: float | None = None
    clearance_step_fraction: float = 0.25
    baumgarte_alpha: float = 100.0
    baumgarte_beta: float = 100.0
    settle_cycles: int = 3
    max_steps: int = 50_000_000
    method: str = "dopri5"  # "dopri5" (explicit, default) or "radau5" (implicit, jointwear.mechanism.radau)


@dataclass
class MechanismModel:
    """A planar mechanism ready to simulate. Build it with :func:`build_model` or by hand."""

    bodies: list[Body]
    joints: list[Joint]
    clearance_joints: list[ClearanceJoint] = field(default_factory=list)
    ground_points: dict[str, tuple[float, float]] = field(default_factory=dict)
    gravity: tuple[float, float] = (0.0, 0.0)
    settings: IntegratorSettings = field(default_factory=IntegratorSettings)
    guess: Callable[[float], dict[str, tuple[float, float, float]]] | None = None
    name: str = "mechanism"
    length_ref: float = 0.01  # m, scales the angle tolerance
    period_override: float | None = None

    # ---- topology ---------------------------------------------------------------------------
    @property
    def free_bodies(self) -> list[Body]:
        return [b for b in self.bodies if b.driver is None]

    @property
    def driven_bodies(self) -> list[Body]:
        return [b for b in self.bodies if b.driver is not None]

    @property
    def body_names(self) -> list[str]:
        return [b.name for b in self.bodies]

    @property
    def period(self) -> float | None:
        """Period of the first driver (s), or period_override, or None."""
        if self.period_override is not None:
            return self.period_override
        for b in self.driven_bodies:
            if b.driver.speed != 0.0:
                return 2.0 * math.pi / abs(b.driver.speed)
        return None

    @property
    def crank(self) -> Body | None:
        d = self.driven_bodies
        return d[0] if d else None

    def body(self, name: str) -> Body:
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)

    def _code(self, name: str) -> int:
        if name == GROUND:
            return -1
        free = [b.name for b in self.free_bodies]
        if name in free:
            return free.index(name)
        driven = [b.name for b in self.driven_bodies]
        return len(free) + driven.index(name)

    def _point(self, body: str, point: str) -> tuple[float, float]:
        if body == GROUND:
            return self.ground_points[point]
        return self.body(body).points[point]

    @property
    def n_dof(self) -> int:
        return 3 * len(self.free_bodies) - 2 * len(self.joints)

    # ---- variants ---------------------------------------------------------------------------
    def ideal(self) -> MechanismModel:
        """The same mechanism with every clearance joint replaced by an ideal revolute joint."""
        m = copy.copy(self)
        m.joints = list(self.joints) + [
            Joint(cj.name, "revolute", cj.bearing_body, cj.bearing_point, cj.journal_body, cj.journal_point)
            for cj in self.clearance_joints
        ]
        m.clearance_joints = []
        return m

    def initial_geometry(self, n_grid: int = DEFAULT_N_GRID) -> list[ClearanceGeometry]:
        """Unworn geometry of every clearance joint."""
        return [
            ClearanceGeometry(cj.bearing_radius, cj.journal_radius, 0.0, np.zeros(n_grid), np.zeros(n_grid), False)
            for cj in self.clearance_joints
        ]

    # ---- kernel arrays ----------------------------------------------------------------------
    def kernel_arrays(self, geometry: list[ClearanceGeometry] | None = None) -> dict[str, np.ndarray]:
        free, driven = self.free_bodies, self.driven_bodies
        nb = len(free)
        bpar = np.array([[b.mass, b.inertia] for b in free], dtype=float).reshape(nb, 2)
        fext = np.array(
            [[b.mass * self.gravity[0] + b.force[0], b.mass * self.gravity[1] + b.force[1], b.torque] for b in free],
            dtype=float,
        ).reshape(nb, 3)
        dpar = np.array(
            [[*b.driver.pivot, *b.points[b.driver.point], b.driver.angle0, b.driver.speed] for b in driven], dtype=float
        ).reshape(len(driven), 6)
        nj = len(self.joints)
        jint = np.zeros((nj, 3), dtype=np.int64)
        jpar = np.zeros((nj, 7))
        for k, j in enumerate(self.joints):
            jint[k] = (K.REVOLUTE if j.kind == "revolute" else K.PRISMATIC, self._code(j.body_i), self._code(j.body_j))
            jpar[k, 0:2] = self._point(j.body_i, j.point_i)
            jpar[k, 2:4] = self._point(j.body_j, j.point_j)
            jpar[k, 4:6] = j.normal_i
            jpar[k, 6] = j.angle0
        ncj = len(self.clearance_joints)
        if geometry is None:
            geometry = self.initial_geometry()
        if len(geometry) != ncj:
            raise ValueError(f"geometry has {len(geometry)} entries but the model has {ncj} clearance joints")
        cint = np.zeros((ncj, 5), dtype=np.int64)
        cpar = np.zeros((ncj, K.NCPAR))
        ngmax = max([2] + [max(g.bearing_wear.size, g.journal_wear.size) for g in geometry])
        prof = np.zeros((ncj, 2, ngmax))
        ngrid = np.zeros((ncj, 2), dtype=np.int64)
        for k, (cj, g) in enumerate(zip(self.clearance_joints, geometry)):
            if not g.clearance > 0:
                raise ValueError(f"clearance joint {cj.name}: clearance {g.clearance:g} m must be > 0")
            cint[k] = (self._code(cj.bearing_body), self._code(cj.journal_body), LAW_CODES[cj.contact_law],
                       FRICTION_CODES[cj.friction_law], 1 if g.use_profile else 0)
            rb = g.bearing_radius + 0.5 * g.clearance_growth
            rj = g.journal_radius - 0.5 * g.clearance_growth
            cpar[k] = (*self._point(cj.bearing_body, cj.bearing_point), *self._point(cj.journal_body, cj.journal_point),
                       g.bearing_radius, g.journal_radius, g.clearance_growth, cj.hsum,
                       4.0 / (3.0 * cj.hsum) * math.sqrt(rb * rj / (rb - rj)), cj.exponent, cj.restitution, cj.v0_min,
                       cj.mu_d, cj.mu_s, cj.v_s, cj.v_d)
            prof[k, 0, : g.bearing_wear.size] = g.bearing_wear
            prof[k, 1, : g.journal_wear.size] = g.journal_wear
            ngrid[k] = (g.bearing_wear.size, g.journal_wear.size)
        s = self.settings
        baum = np.array([s.baumgarte_alpha, s.baumgarte_beta])
        winv = np.empty(3 * nb)
        winv[0::3] = 1.0 / bpar[:, 0]
        winv[1::3] = 1.0 / bpar[:, 0]
        winv[2::3] = 1.0 / bpar[:, 1]
        return {"nb": nb, "bpar": bpar, "winv": winv, "fext": fext, "dpar": dpar, "jint": jint, "jpar": jpar, "cint": cint, "cpar": cpar, "prof": prof,
                    "ngrid": ngrid, "cstate": np.zeros((ncj, 2)), "baum": baum}

    def state_from_poses(self, poses: dict[str, tuple[float, float, float]]) -> np.ndarray:
        """q vector of the free bodies from a dict body -> (x, y, phi)."""
        return np.array([v for b in self.free_bodies for v in poses[b.name]], dtype=float)

    # ---- kinematics of the ideal mechanism -----------------------------------------------------
    def _constraint_eval(self, t: float, q: np.ndarray, qd: np.ndarray, arrays=None):
        a = arrays or self.kernel_arrays()
        nb = a["nb"]
        nd = a["dpar"].shape[0]
        nc = 2 * a["jint"].shape[0]
        w = K.empty_work(nb, nd, a["jint"].shape[0], 0)
        y = np.concatenate([q, qd])
        K.fill_kinematics(t, y, nb, a["dpar"], w["kin"])
        K.eval_constraints(nb, nd, a["jint"], a["jpar"], w["kin"], w["phi_"], w["phid"], w["rest"], w["jac"])
        return w["phi_"][:nc].copy(), w["phid"][:nc].copy(), w["rest"][:nc].copy(), w["jac"].copy()

    def kinematics(self, t: float, q_guess: np.ndarray | None = None, tol: float = 1e-13
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions, velocities, accelerations of the free bodies of the *ideal* mechanism at time t.

        A kinematically determined ideal mechanism (0 degrees of freedom with clearance joints made
        ideal): Newton iteration from the assembly-branch guess, then the velocity and acceleration
        equations. With degrees of freedom left (> 0; general linkages): minimum-norm Newton steps from the
        guess, the mass-weighted minimum-norm velocity (no free motion beyond what the drivers impose: the
        start "at rest") and the accelerations of the forward dynamics of the ideal mechanism under its
        applied loads.
        """
        ideal = self.ideal() if self.clearance_joints else self
        if ideal.n_dof < 0:
            raise ValueError(f"kinematics() needs >= 0 degrees of freedom; the ideal mechanism has {ideal.n_dof}")
        if ideal.n_dof > 0:
            return ideal._kinematics_free(t, self.guess if q_guess is None else None, q_guess, tol)
        arrays = ideal.kernel_arrays()
        q, phid0, jac = ideal._assemble(t, self.guess, q_guess, tol, arrays, np.linalg.solve)
        qd = np.linalg.solve(jac, -phid0)
        _, _, rest, _ = ideal._constraint_eval(t, q, qd, arrays)
        qdd = np.linalg.solve(jac, -rest)
        return q, qd, qdd

    def _assemble(self, t: float, guess, q_guess, tol: float, arrays, step) -> tuple[np.ndarray, ...]:
        """Positions satisfying the constraints at t by Newton iteration from q_guess (or the branch guess), each
        correction ``step(J, -Phi)`` (a solve, or minimum-norm least squares with degrees of freedom left);
        returns (q, Phi_t, J). Raises ValueError when it does not converge or leaves a residual."""
        if q_guess is None:
            if guess is None:
                raise ValueError("no assembly guess available")
            q_guess = self.state_from_poses(guess(t))
        q = np.array(q_guess, dtype=float)
        zero = np.zeros_like(q)
        for _ in range(50):
            phi, _, _, jac = self._constraint_eval(t, q, zero, arrays)
            dq = step(jac, -phi)
            q += dq
            if np.max(np.abs(dq)) < tol * max(1.0, self.length_ref):
                break
        else:
            raise ValueError(f"assembly did not converge at t = {t:g} s")
        phi, phid0, _, jac = self._constraint_eval(t, q, zero, arrays)
        if np.max(np.abs(phi)) > 1e-10 * self.length_ref:
            raise ValueError(f"mechanism cannot be assembled at t = {t:g} s (residual {np.max(np.abs(phi)):.3g})")
        return q, phid0, jac

    def _kinematics_free(self, t: float, guess, q_guess, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """kinematics() of an ideal mechanism with degrees of freedom left (see there)."""
        arrays = self.kernel_arrays()
        q, phid0, jac = self._assemble(t, guess, q_guess, tol, arrays,
                                       lambda a, b: np.linalg.lstsq(a, b, rcond=None)[0])  # minimum-norm steps
        winv, f = arrays["winv"], arrays["fext"].ravel()
        jw = jac * winv[None, :]
        schur = jw @ jac.T
        qd = winv * (jac.T @ np.linalg.solve(schur, -phid0))  # J qd = -Phi_t, smallest kinetic energy
        _, _, rest, _ = self._constraint_eval(t, q, qd, arrays)
        lam = np.linalg.solve(schur, jw @ f + rest)  # J qdd = gamma = -rest with M qdd + J^T lam = f
        qdd = winv * (f - jac.T @ lam)
        return q, qd, qdd

    def inverse_dynamics(self, t: float, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> dict[str, np.ndarray]:
        """Reaction forces of the ideal joints from a known motion (ideal mechanism, no contact forces).

        Solves J^T lam = f - M qdd in the least-squares sense. Returns, per joint name, the force
        exerted on body_j by body_i (N, global frame): (lam_x, lam_y) for revolute joints,
        (torque, normal force) for prismatic joints.
        """
        ideal = self.ideal() if self.clearance_joints else self
        arrays = ideal.kernel_arrays()
        _, _, _, jac = ideal._constraint_eval(t, q, qd, arrays)
        m = np.repeat(arrays["bpar"][:, 0], 3)
        m[2::3] = arrays["bpar"][:, 1]
        f = arrays["fext"].ravel()
        lam, *_ = np.linalg.lstsq(jac.T, f - m * qdd, rcond=None)
        return {j.name: lam[2 * k: 2 * k + 2] for k, j in enumerate(ideal.joints)}


# ---------------------------------------------------------------------------------------------
# building from a config
# ---------------------------------------------------------------------------------------------
def _material(mc) -> Material:
    return Material(mc.name, mc.youngs_modulus, mc.poissons_ratio, mc.hardness, mc.wear_coefficient)


def _rot(phi: float, v: tuple[float, float]) -> tuple[float, float]:
    c, s = math.cos(phi), math.sin(phi)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


@dataclass
class _FourBarGuess:
    """Closed-form assembly of the four-bar on a branch (picklable; used as Newton's start)."""

    O: tuple
    C: tuple
    l1: float
    l2: float
    l3: float
    c1: float
    c2: float
    c3: float
    angle0: float
    speed: float
    branch: int

    def __call__(self, t: float) -> dict[str, tuple[float, float, float]]:
        O, C, l1, l2, l3 = self.O, self.C, self.l1, self.l2, self.l3
        th = self.angle0 + self.speed * t
        ax, ay = O[0] + l1 * math.cos(th), O[1] + l1 * math.sin(th)
        dx, dy = C[0] - ax, C[1] - ay
        d = math.hypot(dx, dy)
        a = (l2 * l2 - l3 * l3 + d * d) / (2 * d)
        h = math.sqrt(max(l2 * l2 - a * a, 0.0))
        ux, uy = dx / d, dy / d
        bx = ax + a * ux - self.branch * h * uy
        by = ay + a * uy + self.branch * h * ux
        p2 = math.atan2(by - ay, bx - ax)
        p3 = math.atan2(by - C[1], bx - C[0])
        return {
            "crank": (O[0] + self.c1 * math.cos(th), O[1] + self.c1 * math.sin(th), th),
            "rod": (ax + self.c2 * math.cos(p2), ay + self.c2 * math.sin(p2), p2),
            "rocker": (C[0] + self.c3 * math.cos(p3), C[1] + self.c3 * math.sin(p3), p3),
        }


@dataclass
class _SliderCrankGuess:
    """Closed-form assembly of the slider-crank on a branch (picklable)."""

    O: tuple
    P0: tuple
    u: tuple
    nrm: tuple
    l1: float
    l2: float
    c1: float
    c2: float
    guide: float
    angle0: float
    speed: float
    branch: int

    def __call__(self, t: float) -> dict[str, tuple[float, float, float]]:
        O, P0, u, nrm = self.O, self.P0, self.u, self.nrm
        th = self.angle0 + self.speed * t
        ax, ay = O[0] + self.l1 * math.cos(th), O[1] + self.l1 * math.sin(th)
        rx, ry = ax - P0[0], ay - P0[1]
        along = rx * u[0] + ry * u[1]
        perp = rx * nrm[0] + ry * nrm[1]
        s = along + self.branch * math.sqrt(max(self.l2 * self.l2 - perp * perp, 0.0))
        bx, by = P0[0] + s * u[0], P0[1] + s * u[1]
        p2 = math.atan2(by - ay, bx - ax)
        return {
            "crank": (O[0] + self.c1 * math.cos(th), O[1] + self.c1 * math.sin(th), th),
            "rod": (ax + self.c2 * math.cos(p2), ay + self.c2 * math.sin(p2), p2),
            "slider": (bx, by, self.guide),
        }


def _four_bar(cfg) -> tuple[list[Body], list[Joint], dict, Callable]:
    m = cfg.mechanism
    l1, l2, l3 = m.crank.length, m.rod.length, m.rocker.length
    c1 = m.crank.length / 2 if m.crank.com_offset is None else m.crank.com_offset
    c2 = m.rod.length / 2 if m.rod.com_offset is None else m.rod.com_offset
    c3 = m.rocker.length / 2 if m.rocker.com_offset is None else m.rocker.com_offset
    O, C = tuple(m.crank_pivot), tuple(m.rocker_pivot)
    crank = Body("crank", m.crank.mass, m.crank.inertia, {"O": (-c1, 0.0), "A": (l1 - c1, 0.0)},
                 driver=Driver(O, "O", m.crank_angle0, m.crank_speed))
    rod = Body("rod", m.rod.mass, m.rod.inertia, {"A": (-c2, 0.0), "B": (l2 - c2, 0.0)}, force=tuple(m.rod_force))
    rocker = Body("rocker", m.rocker.mass, m.rocker.inertia, {"C": (-c3, 0.0), "B": (l3 - c3, 0.0)},
                  torque=m.rocker_torque)
    joints = [
        Joint("A", "revolute", "rod", "A", "crank", "A"),
        Joint("B", "revolute", "rocker", "B", "rod", "B"),
        Joint("C", "revolute", GROUND, "C", "rocker", "C"),
    ]
    guess = _FourBarGuess(O, C, l1, l2, l3, c1, c2, c3, m.crank_angle0, m.crank_speed, m.assembly_branch)
    return [crank, rod, rocker], joints, {"O": O, "C": C}, guess


def _slider_crank(cfg) -> tuple[list[Body], list[Joint], dict, Callable]:
    m = cfg.mechanism
    l1, l2 = m.crank.length, m.rod.length
    c1 = l1 / 2 if m.crank.com_offset is None else m.crank.com_offset
    c2 = l2 / 2 if m.rod.com_offset is None else m.rod.com_offset
    O = tuple(m.crank_pivot)
    g = m.guide_angle
    u = (math.cos(g), math.sin(g))
    nrm = (-math.sin(g), math.cos(g))
    P0 = (O[0] + m.offset * nrm[0], O[1] + m.offset * nrm[1])
    crank = Body("crank", m.crank.mass, m.crank.inertia, {"O": (-c1, 0.0), "A": (l1 - c1, 0.0)},
                 driver=Driver(O, "O", m.crank_angle0, m.crank_speed))
    rod = Body("rod", m.rod.mass, m.rod.inertia, {"A": (-c2, 0.0), "B": (l2 - c2, 0.0)})
    slider = Body("slider", m.slider.mass, m.slider.inertia, {"B": (0.0, 0.0)})
    joints = [
        Joint("A", "revolute", "rod", "A", "crank", "A"),
        Joint("B", "revolute", "slider", "B", "rod", "B"),
        Joint("P", "prismatic", GROUND, "P0", "slider", "B", normal_i=nrm, angle0=-g),
    ]
    guess = _SliderCrankGuess(O, P0, u, nrm, l1, l2, c1, c2, g, m.crank_angle0, m.crank_speed, m.assembly_branch)
    return [crank, rod, slider], joints, {"O": O, "P0": P0}, guess



# ---------------------------------------------------------------------------------------------
# general linkage (mechanism.type = "general")
# ---------------------------------------------------------------------------------------------
@dataclass
class _TableGuess:
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


@dataclass
class _GeneralParts:
    bodies: list[Body]
    joints: list[Joint]
    ground_points: dict
    guess: _TableGuess
    length_ref: float
    period: float


class AssemblyError(ValueError):
    """A general linkage cannot be assembled (one-line message naming the links)."""


_GENERAL_CACHE: dict[str, _TableGuess] = {}


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
        return _rot(-phi0[name], (p[0] - b.com[0], p[1] - b.com[1]))

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
            joints.append(Joint(j.name, "prismatic", bi, pi, bj, pj, normal_i=_rot(-phi0[bi], nrm),
                                angle0=phi0[bi] - phi0[bj]))
    poses = {n: (cfg_bodies[n].com[0], cfg_bodies[n].com[1], phi0[n]) for n in order if n not in drivers}
    sizes = []
    for b in m.bodies:
        pts = list(b.points.values())
        if len(pts) > 1:
            sizes.append(max(math.dist(p, q) for p in pts for q in pts))
    lref = float(np.median(sizes)) if sizes else 0.01
    return bodies, joints, {k: tuple(v) for k, v in m.ground_points.items()}, poses, lref


def _joint_gap_check(m, lref: float) -> None:
    """The two drawn points of a revolute joint must (nearly) coincide."""
    pts = {(b.name, k): p for b in m.bodies for k, p in b.points.items()}
    pts.update({(GROUND, k): p for k, p in m.ground_points.items()})
    for i, j in enumerate(m.joints):
        if j.type != "revolute":
            continue
        a, b = (pts[tuple(r.split("."))] for r in j.connects)
        gap = math.dist(a, b)
        if gap > m.closure_tolerance * lref:
            raise AssemblyError(
                f"joints[{i}].connects: the drawn points {j.connects[0]} and {j.connects[1]} of revolute joint "
                f"'{j.name}' are {gap * 1e3:.4g} mm apart (allowed {m.closure_tolerance * lref * 1e3:.4g} mm = "
                f"closure_tolerance x median link size): draw them at the same place"
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


def _assemble(model: MechanismModel, arrays, t: float, q: np.ndarray, lref: float, where: str
              ) -> tuple[np.ndarray, np.ndarray]:
    """Newton on the constraints at time t from q; returns (q, qd). AssemblyError naming the links."""
    zero = np.zeros_like(q)
    scale = np.ones_like(q)
    scale[2::3] = lref  # angle columns scaled to lengths: a dimensionless condition number
    q_start = q.copy()
    for _ in range(30):
        phi, _, _, jac = model._constraint_eval(t, q, zero, arrays)
        try:
            dq = np.linalg.solve(jac, -phi) if jac.shape[0] == jac.shape[1] else np.linalg.lstsq(jac, -phi, rcond=None)[0]
        except np.linalg.LinAlgError:
            dq = np.full_like(q, np.nan)
        if not np.all(np.isfinite(dq)) or np.max(np.abs(dq / scale)) > 10.0:
            break
        q = q + dq
        if np.max(np.abs(dq / scale)) < 1e-13:
            break
    phi, phid0, _, jac = model._constraint_eval(t, q, zero, arrays)
    if not np.all(np.isfinite(phi)) or np.max(np.abs(phi)) > 1e-10 * lref:
        # the loop that fails: the near-singular direction of the Jacobian where Newton started (close to a
        # limit position the loop that cannot close has a vanishing singular value)
        _, _, jac0 = model._constraint_eval(t, q_start, zero, arrays)[1:]
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
    return q, qd


def _general_parts(m) -> _GeneralParts:
    """Topology, drawn-configuration assembly and the one-cycle assembly table (cached per mechanism)."""
    bodies, joints, gpts, poses, lref = _general_topology(m)
    period = 2.0 * math.pi / abs(m.drivers[0].speed)
    # the assembly depends on the geometry only (not on masses, inertias or loads): cache it by geometry, so
    # that sampled masses or materials do not redo it
    key = m.model_dump_json(exclude={"gravity": True, "bodies": {"__all__": {"mass", "inertia", "force", "torque"}}})
    hit = _GENERAL_CACHE.get(key)
    if hit is not None:
        return _GeneralParts(bodies, joints, gpts, copy.deepcopy(hit), lref, period)
    _joint_gap_check(m, lref)
    model = MechanismModel(bodies=bodies, joints=joints, ground_points=gpts, length_ref=lref, period_override=period)
    arrays = model.kernel_arrays()
    q0 = model.state_from_poses(poses)
    q, qd = _assemble(model, arrays, 0.0, q0, lref, "at the drawn configuration")
    drawn_shift = np.abs(q - q0)
    drawn_shift[2::3] *= lref
    if np.max(drawn_shift) > 0.25 * lref:
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
        q_new, qd = _assemble(model, arrays, k * dt, pred, lref, where)
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
    guess = _TableGuess(period, [b.name for b in model.free_bodies], tab)
    if len(_GENERAL_CACHE) > 32:
        _GENERAL_CACHE.pop(next(iter(_GENERAL_CACHE)))
    _GENERAL_CACHE[key] = copy.deepcopy(guess)
    return _GeneralParts(bodies, joints, gpts, guess, lref, period)


def check_general_assembly(m) -> None:
    """Config-time check of a general linkage (raises ValueError -> one-line ConfigError naming the field)."""
    _general_parts(m)


def _general(cfg) -> tuple[list[Body], list[Joint], dict, Callable, float, float]:
    p = _general_parts(cfg.mechanism)
    return p.bodies, p.joints, p.ground_points, p.guess, p.length_ref, p.period


def _revalidate(config: StudyConfig) -> None:
    """Re-check the mechanism and clearance sections (configs changed with model_copy are not validated):
    a linkage that cannot close or a non-positive clearance becomes a ConfigError naming the field."""
    from pydantic import ValidationError

    from jointwear.config import ClearanceJointConfig, validation_problems

    try:
        type(config.mechanism).model_validate(config.mechanism.model_dump())
    except ValidationError as exc:
        raise ConfigError(f"mechanism: {'; '.join(validation_problems(exc))}") from None
    for i, cj in enumerate(config.clearance_joints):
        try:
            ClearanceJointConfig.model_validate(cj.model_dump())
        except ValidationError as exc:
            raise ConfigError(f"clearance_joints[{i}].{'; '.join(validation_problems(exc))}") from None


def build_model(config: StudyConfig) -> MechanismModel:
    """MechanismModel from a StudyConfig (clearance joints replace their ideal revolutes).

    Raises ConfigError if the mechanism cannot assemble over a full crank turn or a clearance is <= 0
    (re-checked here because configs derived with ``model_copy(update=...)`` skip validation).
    """
    _revalidate(config)
    mcfg = config.mechanism
    if mcfg.type == "four_bar":
        bodies, joints, gpoints, guess = _four_bar(config)
        lref = float(np.median([mcfg.crank.length, mcfg.rod.length, mcfg.rocker.length]))
    elif mcfg.type == "slider_crank":
        bodies, joints, gpoints, guess = _slider_crank(config)
        lref = float(np.median([mcfg.crank.length, mcfg.rod.length]))
    elif mcfg.type == "general":
        bodies, joints, gpoints, guess, lref, period = _general(config)
    else:  # pragma: no cover - guarded by the config schema
        raise ConfigError(f"mechanism.type: unknown type {mcfg.type!r}")
    if mcfg.type != "general":
        period = None
    cjs: list[ClearanceJoint] = []
    for cc in config.clearance_joints:
        ideal = next(j for j in joints if j.name == cc.joint)
        joints.remove(ideal)
        pts = {ideal.body_i: ideal.point_i, ideal.body_j: ideal.point_j}
        fr = cc.friction
        cjs.append(ClearanceJoint(
            name=cc.name, bearing_body=cc.bearing_body, bearing_point=pts[cc.bearing_body],
            journal_body=cc.journal_body, journal_point=pts[cc.journal_body],
            bearing_radius=cc.bearing_radius, journal_radius=cc.journal_radius, width=cc.width,
            bearing_material=_material(cc.bearing_material), journal_material=_material(cc.journal_material),
            bearing_outer_radius=cc.bearing_outer_radius, contact_law=cc.contact_law, exponent=cc.exponent,
            restitution=cc.restitution, v0_min=cc.v0_min, friction_law=fr.law, mu_d=fr.mu_d, mu_s=fr.mu_s,
            v_s=fr.v_s, v_d=fr.v_d,
        ))
    s = config.simulation
    settings = IntegratorSettings(rtol=s.rtol, atol=s.atol, max_step=s.max_step,
                                  clearance_step_fraction=s.clearance_step_fraction,
                                  baumgarte_alpha=s.baumgarte_alpha, baumgarte_beta=s.baumgarte_beta,
                                  settle_cycles=s.settle_cycles, max_steps=s.max_steps, method=s.method)
    return MechanismModel(bodies=bodies, joints=joints, clearance_joints=cjs, ground_points=gpoints,
                          gravity=tuple(mcfg.gravity), settings=settings, guess=guess, name=config.name,
                          length_ref=lref, period_override=period)
