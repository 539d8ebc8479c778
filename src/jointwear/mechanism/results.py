"""Typed results of a forward simulation: the state to continue from, the contact trace of every clearance joint
and the recorded steps (like SciPy's OdeResult)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from jointwear.contact.settings import ClearanceJointConfig


@dataclass
class SimulationState:
    """Everything needed to continue a simulation: time, free-body state, contact memory, step size."""

    t: float
    y: np.ndarray
    cstate: np.ndarray
    h: float


@dataclass
class ContactTrace:
    """One clearance joint over the recorded accepted steps (after the settling cycles).

    Angles: theta_bearing / theta_journal are the directions of n (bearing centre -> journal
    centre) in the bearing / journal body frames, CCW from the body x axis, in [0, 2 pi).
    force_tangential is the friction force on the journal along t = k x n (signed);
    slip_speed the relative tangential velocity of the journal's contact point w.r.t. the bearing's.
    """

    name: str
    bearing_body: str
    journal_body: str
    t: np.ndarray
    dt_weight: np.ndarray
    theta_bearing: np.ndarray
    theta_journal: np.ndarray
    force_normal: np.ndarray
    force_tangential: np.ndarray
    slip_speed: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    in_contact: np.ndarray
    eccentricity_global: np.ndarray  # (steps, 2): e = journal centre - bearing centre, global frame
    bearing_body_angle: np.ndarray
    journal_body_angle: np.ndarray
    stiffness: np.ndarray  # K used at each sample (N/m^1.5)
    normal_tilt: np.ndarray  # angle from n to the contact normal (rad); 0 unless a worn profile is used
    bearing_radius: float
    journal_radius: float
    clearance_used: float
    joint: ClearanceJointConfig  # the joint's validated settings: radii, width, materials, contact and friction laws

    @property
    def eccentricity(self) -> np.ndarray:
        """(steps, 2): e in the bearing body's frame (computed on access: two trigonometric calls per step)."""
        cb, sb = np.cos(self.bearing_body_angle), np.sin(self.bearing_body_angle)
        ex, ey = self.eccentricity_global[:, 0], self.eccentricity_global[:, 1]
        return np.column_stack([cb * ex + sb * ey, -sb * ex + cb * ey])

    @property
    def duration(self) -> float:
        """Time the trace covers, s (the sum of its steps' weights)."""
        return float(self.dt_weight.sum())

    @property
    def contact_force(self) -> np.ndarray:
        """Magnitude of the contact force (normal and friction), N."""
        return np.hypot(self.force_normal, self.force_tangential)

    @property
    def n_impacts(self) -> int:
        """Number of transitions from free flight to contact."""
        c = self.in_contact.astype(np.int8)
        return int(np.count_nonzero(np.diff(c) == 1))

    @property
    def contact_fraction(self) -> float:
        """Fraction of the time the journal touches the bearing."""
        return float(np.sum(self.dt_weight * self.in_contact) / self.duration)

    @property
    def mean_force(self) -> float:
        """Time-average of the contact force magnitude, N."""
        return float(np.sum(self.dt_weight * self.contact_force) / self.duration)

    @property
    def contact_revolutions(self) -> float:
        """Revolutions the contact point slides or rolls round the bearing while the journal stays in contact (CCW in
        the bearing body's frame > 0): the steps of theta_bearing, each wrapped to [-pi, pi], between consecutive
        samples both in contact, summed, over 2 pi. A step with either end in free flight is left out, so on an
        impacting joint the contact point's moves through free flight (from where the journal leaves the bore to
        where it strikes it next) are not counted: this is not the net migration of the contact zone, which only
        a joint in continuous contact has equal to it. The whirl flag (:func:`whirl_measure`) reads it."""
        contact = np.asarray(self.in_contact, dtype=bool)
        step = _wrapped_steps(self.theta_bearing)
        return float(np.sum(step[contact[1:] & contact[:-1]]) / (2.0 * np.pi))

    @property
    def relative_revolutions(self) -> float:
        """Net revolutions of the journal body relative to the bearing body over the trace."""
        return float(np.sum(_wrapped_steps(self.journal_body_angle - self.bearing_body_angle)) / (2.0 * np.pi))


def _wrapped_steps(angle: np.ndarray) -> np.ndarray:
    """Steps between consecutive angles, each wrapped to [-pi, pi] (a step of a sampled motion is below pi)."""
    step = np.diff(angle)
    step -= 2.0 * np.pi * np.rint(step / (2.0 * np.pi))
    return step


def whirl_threshold(relative_per_cycle: float) -> float:
    """Contact-point revolutions per cycle beyond which a joint whirls: max(5, 3 (|n_rel| + 1)).

    A contact that follows the joint's load turns round the bearing a few times per cycle at most (|n_c| <= 1.2 on
    every calm case of the presets and examples, impacting ones included); a journal rolling with slip round its
    bore in a friction-driven backward whirl turns about 0.6 (R / c) |n_rel| times, and R / c >= 50 for any
    clearance under 2 % of the radius (docs/dynamics.md, "Friction-driven whirl")."""
    return max(5.0, 3.0 * (abs(relative_per_cycle) + 1.0))


def whirl_measure(trace: ContactTrace, n_cycles: float) -> tuple[float, bool]:
    """(contact-point revolutions per cycle, whether that is a whirl) of a joint's trace over n_cycles."""
    if not n_cycles > 0:
        return 0.0, False
    n_c = trace.contact_revolutions / n_cycles
    return n_c, abs(n_c) > whirl_threshold(trace.relative_revolutions / n_cycles)


#: the kernels (``SimulationResult.extra["kernel"]``) that record no multipliers of the ideal joints: the natural-
#: coordinate four-bar's are those of its link lengths, the tree kernel's joints hold by construction
UNRECORDED_MULTIPLIERS = ("natural_fourbar", "tree")


@dataclass
class SimulationResult:
    """Recorded steps of a forward simulation (like scipy's OdeResult)."""

    t: np.ndarray
    crank_angle: np.ndarray  # driver angle wrapped to [0, 2 pi)
    body_angles: np.ndarray  # (steps, n_bodies), all bodies in model order (unwrapped)
    body_names: list[str]
    free_body_names: list[str]
    multipliers: np.ndarray  # (steps, n_constraints): lam of the ideal joints (M qdd + J^T lam = f); NaN but on the
    # Cartesian kernel (UNRECORDED_MULTIPLIERS)
    joint_names: list[str]  # the ideal joints, in the multipliers' order
    joints: list[ContactTrace]
    state_end: SimulationState
    n_steps: int  # accepted steps over the whole call (settling included)
    n_rejected: int
    n_recorded_steps: int
    n_cycles: float
    settle_cycles: float
    period: float
    wall_seconds: float
    status: str = "ok"
    extra: dict = field(default_factory=dict)
    prismatic: list[str] = field(default_factory=list)  # the ideal joints that are prismatic
    _cart_fn: object = field(default=None, repr=False)  # () -> (q, qd, qdd), evaluated on first access
    #: what driver_torque reads of the model (set by simulate): gravity, the free bodies' (mass, inertia, force x,
    #: force y, torque) and the driven bodies' (mass, force x, force y, torque, pivot x, y, pivot point x, y in the
    #: body frame, angle0, speed)
    drive: dict | None = field(default=None, repr=False)
    _cart: tuple | None = field(default=None, repr=False)

    def _cartesian(self) -> tuple:
        if self._cart is None:
            self._cart = self._cart_fn()
        return self._cart

    def __getstate__(self) -> dict:
        """Picklable (for process pools): the lazy Cartesian arrays are materialised."""
        state = dict(self.__dict__)
        state["_cart"] = self._cartesian()
        state["_cart_fn"] = None
        return state

    @property
    def q(self) -> np.ndarray:
        """(steps, 3 n_free): x, y, phi of the free bodies (centre of mass, global frame)."""
        return self._cartesian()[0]

    @property
    def qd(self) -> np.ndarray:
        """(steps, 3 n) velocities x', y', phi' of the free bodies, in their order (m/s, rad/s)."""
        return self._cartesian()[1]

    @property
    def qdd(self) -> np.ndarray:
        """(steps, 3 n) accelerations of the free bodies, in their order (m/s^2, rad/s^2)."""
        return self._cartesian()[2]

    def body_acceleration(self, name: str) -> np.ndarray:
        """(steps, 3) x'', y'', phi'' of a free body."""
        i = self.free_body_names.index(name)
        return self.qdd[:, 3 * i: 3 * i + 3]

    def reaction(self, joint: str) -> np.ndarray:
        """(steps, 2) what body_i exerts on body_j through an ideal joint (as ``Model.reactions``): the force (x, y),
        N, of a revolute joint; the moment, N m, and the force along the guide's normal, N, of a prismatic one.

        Only the Cartesian kernel has the ideal joints' multipliers: on the natural-coordinate and tree kernels (the
        default where a model qualifies, ``extra["kernel"]``) this raises a ValueError that says so; run
        ``simulate(..., fast=False)`` for the reactions."""
        kernel = self.extra.get("kernel", "")
        if kernel in UNRECORDED_MULTIPLIERS:
            raise ValueError(f"joint {joint}'s reaction was not recorded: the {kernel} kernel that ran this "
                             "simulation has no multipliers of the ideal joints (docs/dynamics.md, 'Which kernel "
                             "runs'); run simulate(..., fast=False) for the Cartesian kernel, which records them")
        k = self.joint_names.index(joint)
        pair = self.multipliers[:, 2 * k: 2 * k + 2].copy()
        if joint in self.prismatic:
            pair[:, 1] *= -1.0  # its constraint row carries +n for body_j
        return pair

    @property
    def driver_torque(self) -> np.ndarray:
        """(steps,) the torque the driver applies to the driven body about its pivot (the generalized force of the
        driver constraint), N m, counter-clockwise positive, on every kernel.

        From the power balance of the whole mechanism at each sample: tau omega is the rate of change of the free
        bodies' kinetic energy, less the power of gravity and the applied loads on every body and of the clearance
        joints' contact forces (-F_N d delta/dt + F_T v_t, their damping and friction included); the ideal joints do
        no work, and a driven body turning at constant speed about a fixed pivot keeps its kinetic energy. A
        ValueError where it is not defined: several driven bodies (one power, several torques), a driver at rest,
        a worn profile's contact (``normal_tilt`` not 0), a result without the model's data."""
        d = self.drive
        if d is None:
            raise ValueError("driver_torque needs the model's masses and loads: a result of simulate() has them")
        if len(d["driven"]) != 1 or d["driven"][0][-1] == 0.0:
            raise ValueError("driver_torque is defined for one driven body turning at a non-zero speed (this model "
                             f"has {len(d['driven'])} driven bodies)")
        if any(np.any(tr.normal_tilt != 0.0) for tr in self.joints):
            raise ValueError("driver_torque is not derived for a worn profile's contact (normal_tilt not 0)")
        g = np.asarray(d["gravity"], dtype=float)
        qd, qdd = self.qd, self.qdd
        power = np.zeros(self.t.size)
        for i, (mass, inertia, fx, fy, torque) in enumerate(d["free"]):
            v, a = qd[:, 3 * i: 3 * i + 2], qdd[:, 3 * i: 3 * i + 2]
            omega, alpha = qd[:, 3 * i + 2], qdd[:, 3 * i + 2]
            load = mass * g + (fx, fy)
            power += mass * (a[:, 0] * v[:, 0] + a[:, 1] * v[:, 1]) + inertia * alpha * omega
            power -= load[0] * v[:, 0] + load[1] * v[:, 1] + torque * omega
        mass, fx, fy, torque, px, py, cx, cy, angle0, speed = d["driven"][0]
        phi = angle0 + speed * self.t
        c, s = np.cos(phi), np.sin(phi)
        rx, ry = -(c * cx - s * cy), -(s * cx + c * cy)  # centre of mass - pivot, global frame
        load = mass * g + (fx, fy)
        power -= speed * (load[1] * rx - load[0] * ry) + torque * speed  # v_G = omega k x r
        for tr in self.joints:
            power -= -tr.force_normal * tr.penetration_rate + tr.force_tangential * tr.slip_speed
        return power / speed

    @property
    def steps_per_cycle(self) -> float:
        """Recorded integrator steps per cycle (NaN without a cycle)."""
        return self.n_recorded_steps / self.n_cycles if self.n_cycles else float("nan")


class SimulationError(RuntimeError):
    """The integrator could not proceed (step-size underflow or step budget exhausted)."""


class SimulationCancelled(Exception):
    """The simulation was stopped by its ``cancel`` event (a block whose result is no longer needed)."""

