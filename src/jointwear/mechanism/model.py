"""Planar multibody model: bodies, joints, drivers, clearance joints, kinematics of the ideal mechanism.

Body frames have their origin at the centre of mass.  A body with a :class:`Driver` turns at
constant speed about a ground pivot and is prescribed (not in the state vector).  Free bodies carry
q = (x, y, phi) and qd. Clearance joints and the integrator hold their validated settings
(``ClearanceJointConfig``, ``SimulationConfig``) as they are.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from jointwear.contact.geometry import DEFAULT_N_GRID, ClearanceGeometry
from jointwear.contact.laws import FRICTION_CODES, LAW_CODES, contact_stiffness
from jointwear.contact.settings import ClearanceJointConfig
from jointwear.mechanism import kernel as K
from jointwear.mechanism.settings import SimulationConfig

GROUND = "ground"


def profile_sides(g: ClearanceGeometry) -> int:
    """The kernel's profile bits (kernel.PROF_BEARING | kernel.PROF_JOURNAL) of a geometry: the sides whose worn
    profile the contact reads. A side worn nowhere is round, which is exact and spares its lookup; with neither side
    worn the bearing's (zero) profile is still read, so that profile mode's stiffness is the same expression on
    every block."""
    if not g.use_profile:
        return 0
    sides = (K.PROF_BEARING if g.bearing_wear.any() else 0) | (K.PROF_JOURNAL if g.journal_wear.any() else 0)
    return sides or K.PROF_BEARING


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
class ClearanceJoint:
    """A revolute joint with clearance placed in the model: its validated settings and the body points it joins
    (journal on journal_body inside a bearing on bearing_body)."""

    spec: ClearanceJointConfig
    bearing_point: str
    journal_point: str

    @property
    def name(self) -> str:
        """The clearance joint's name in the config."""
        return self.spec.name

    @property
    def bearing_body(self) -> str:
        """Name of the body that holds the bore."""
        return self.spec.bearing_body

    @property
    def journal_body(self) -> str:
        """Name of the body that holds the pin."""
        return self.spec.journal_body


@dataclass
class MechanismModel:
    """A planar mechanism ready to simulate. Build it with :func:`build_model` or by hand."""

    bodies: list[Body]
    joints: list[Joint]
    clearance_joints: list[ClearanceJoint] = field(default_factory=list)
    ground_points: dict[str, tuple[float, float]] = field(default_factory=dict)
    gravity: tuple[float, float] = (0.0, 0.0)
    settings: SimulationConfig = field(default_factory=SimulationConfig)
    guess: Callable[[float], dict[str, tuple[float, float, float]]] | None = None
    name: str = "mechanism"
    length_ref: float = 0.01  # m, scales the angle tolerance
    period_override: float | None = None

    # ---- topology ---------------------------------------------------------------------------
    @property
    def free_bodies(self) -> list[Body]:
        """The bodies the dynamics moves (every body without a driver), in their order in q."""
        return [b for b in self.bodies if b.driver is None]

    @property
    def driven_bodies(self) -> list[Body]:
        """The bodies with a prescribed motion."""
        return [b for b in self.bodies if b.driver is not None]

    @property
    def body_names(self) -> list[str]:
        """Every body's name, free and driven."""
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
        """The first driven body (None without one)."""
        d = self.driven_bodies
        return d[0] if d else None

    def body(self, name: str) -> Body:
        """The body named ``name`` (KeyError if none)."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)

    def body_code(self, name: str) -> int:
        """Index of a body in the kernel arrays: free bodies first, then driven ones; -1 for the ground."""
        if name == GROUND:
            return -1
        free = [b.name for b in self.free_bodies]
        if name in free:
            return free.index(name)
        driven = [b.name for b in self.driven_bodies]
        return len(free) + driven.index(name)

    def point(self, body: str, point: str) -> tuple[float, float]:
        """Body-frame coordinates of a body's point (global for the ground)."""
        if body == GROUND:
            return self.ground_points[point]
        return self.body(body).points[point]

    @property
    def n_dof(self) -> int:
        """Degrees of freedom left by the ideal joints: 3 per free body - 2 per joint (drivers not counted)."""
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
            ClearanceGeometry(cj.spec.bearing_radius, cj.spec.journal_radius, 0.0, np.zeros(n_grid), np.zeros(n_grid),
                              False)
            for cj in self.clearance_joints
        ]

    # ---- kernel arrays ----------------------------------------------------------------------
    def kernel_arrays(self, geometry: list[ClearanceGeometry] | None = None) -> dict[str, np.ndarray]:
        """The model as the compiled kernel's flat arrays (bodies, joints, drivers, clearance geometry)."""
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
            jint[k] = (K.REVOLUTE if j.kind == "revolute" else K.PRISMATIC, self.body_code(j.body_i), self.body_code(j.body_j))
            jpar[k, 0:2] = self.point(j.body_i, j.point_i)
            jpar[k, 2:4] = self.point(j.body_j, j.point_j)
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
            s, fr = cj.spec, cj.spec.friction
            cint[k] = (self.body_code(cj.bearing_body), self.body_code(cj.journal_body), LAW_CODES[s.contact_law],
                       FRICTION_CODES[fr.law], profile_sides(g))
            rb = g.bearing_radius + 0.5 * g.clearance_growth
            rj = g.journal_radius - 0.5 * g.clearance_growth
            cpar[k] = (*self.point(cj.bearing_body, cj.bearing_point), *self.point(cj.journal_body, cj.journal_point),
                       g.bearing_radius, g.journal_radius, g.clearance_growth, s.hsum,
                       contact_stiffness(s.hsum, rb, rj), s.exponent, s.restitution, s.v0_min,
                       fr.mu_d, fr.mu_s, fr.v_s, fr.v_d)
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
    def constraint_eval(self, t: float, q: np.ndarray, qd: np.ndarray, arrays=None):
        """(Phi, Phi_t + J qd terms, the acceleration right-hand side's rest, J) of the ideal joints at (t, q, qd)."""
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
        if q_guess is None:
            if self.guess is None:
                raise ValueError("no assembly guess available")
            q_guess = ideal.state_from_poses(self.guess(t))
        arrays = ideal.kernel_arrays()
        q, converged = ideal.newton(t, q_guess, arrays, tol=tol * max(1.0, self.length_ref), max_iter=50)
        if not converged:
            raise ValueError(f"assembly did not converge at t = {t:g} s")
        phi, phid0, _, jac = ideal.constraint_eval(t, q, np.zeros_like(q), arrays)
        if np.max(np.abs(phi)) > 1e-10 * self.length_ref:
            raise ValueError(f"mechanism cannot be assembled at t = {t:g} s (residual {np.max(np.abs(phi)):.3g})")
        if ideal.n_dof == 0:
            qd = np.linalg.solve(jac, -phid0)
            _, _, rest, _ = ideal.constraint_eval(t, q, qd, arrays)
            qdd = np.linalg.solve(jac, -rest)
            return q, qd, qdd
        winv, f = arrays["winv"], arrays["fext"].ravel()
        jw = jac * winv[None, :]
        schur = jw @ jac.T
        qd = winv * (jac.T @ np.linalg.solve(schur, -phid0))  # J qd = -Phi_t, smallest kinetic energy
        _, _, rest, _ = ideal.constraint_eval(t, q, qd, arrays)
        lam = np.linalg.solve(schur, jw @ f + rest)  # J qdd = gamma = -rest with M qdd + J^T lam = f
        qdd = winv * (f - jac.T @ lam)
        return q, qd, qdd

    def newton(self, t: float, q0: np.ndarray, arrays, *, tol: float, max_iter: int, scale=1.0,
               max_step: float = math.inf) -> tuple[np.ndarray, bool]:
        """Positions satisfying the ideal joints' constraints at t: Newton iteration from q0, each correction
        J dq = -Phi solved (square J) or minimum-norm (degrees of freedom left). Converged when max |dq / scale|
        < tol; stops unconverged after max_iter corrections, on a singular J or a correction above max_step
        (scaled). Returns (q, converged); the caller checks the residual."""
        q = np.array(q0, dtype=float)
        zero = np.zeros_like(q)
        for _ in range(max_iter):
            phi, _, _, jac = self.constraint_eval(t, q, zero, arrays)
            try:
                dq = (np.linalg.solve(jac, -phi) if jac.shape[0] == jac.shape[1]
                      else np.linalg.lstsq(jac, -phi, rcond=None)[0])
            except np.linalg.LinAlgError:
                return q, False
            size = np.max(np.abs(dq / scale))
            if not np.isfinite(size) or size > max_step:
                return q, False
            q += dq
            if size < tol:
                return q, True
        return q, False

    def inverse_dynamics(self, t: float, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> dict[str, np.ndarray]:
        """Reaction forces of the ideal joints from a known motion (ideal mechanism, no contact forces).

        Solves J^T lam = f - M qdd in the least-squares sense. Returns, per joint name, what body_i exerts on
        body_j (:meth:`reactions`): the force (N, global x and y) of a revolute joint; the moment (N m) and the
        force along the guide's normal (N) of a prismatic one.
        """
        ideal = self.ideal() if self.clearance_joints else self
        arrays = ideal.kernel_arrays()
        _, _, _, jac = ideal.constraint_eval(t, q, qd, arrays)
        m = np.repeat(arrays["bpar"][:, 0], 3)
        m[2::3] = arrays["bpar"][:, 1]
        f = arrays["fext"].ravel()
        lam, *_ = np.linalg.lstsq(jac.T, f - m * qdd, rcond=None)
        return ideal.reactions(lam)

    def reactions(self, lam: np.ndarray) -> dict[str, np.ndarray]:
        """The ideal joints' reactions, by name, from their multipliers lam (..., 2 n_joints): what body_i exerts on
        body_j. Revolute: the force (x, y), N. Prismatic: the moment, N m, and the force along the guide's normal n
        (the sliding direction turned 90 degrees counter-clockwise), N; its constraint row carries +n for body_j, so
        the force is -lam there."""
        lam = np.asarray(lam, dtype=float)
        out = {}
        for k, j in enumerate(self.joints):
            pair = lam[..., 2 * k: 2 * k + 2].copy()
            if j.kind == "prismatic":
                pair[..., 1] *= -1.0
            out[j.name] = pair
        return out

