"""The start state of a simulation: the ideal kinematics at t0, every journal preloaded against its bearing."""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

from jointwear.contact.geometry import ClearanceGeometry
from jointwear.contact.laws import contact_stiffness
from jointwear.mechanism.kernel import profile_at
from jointwear.mechanism.model import MechanismModel
from jointwear.mechanism.results import SimulationState

TWO_PI = 2.0 * math.pi


def initial_state(model: MechanismModel, t0: float = 0.0, preload: bool = True,
                  geometry: list[ClearanceGeometry] | None = None) -> SimulationState:
    """Start state at t0 from the ideal kinematics.

    preload=True (default): every journal starts in contact, pushed against its bearing along the
    ideal joint reaction with the static penetration (|R| / K)^(1/n), and the contact is marked as
    established (v0 = max(v0_min, clearance x driver speed)); this removes most of the start-up transient.
    preload=False: journals centred in their bearings. geometry: the (worn) clearance geometry whose
    local clearance in the preload direction is used (default: nominal).
    """
    q, qd, qdd = model.kinematics(t0)
    ncj = len(model.clearance_joints)
    cstate = np.zeros((ncj, 2))
    if preload and ncj:
        ideal = copy.deepcopy(model.ideal())
        reac = model.inverse_dynamics(t0, q, qd, qdd)
        free = [b.name for b in model.free_bodies]
        for k, cj in enumerate(model.clearance_joints):
            r = np.asarray(reac[cj.name], dtype=float)  # force on the journal body by the bearing body
            fmag = float(np.hypot(*r))
            if fmag <= 0.0:
                continue
            n = -r / fmag

            def body_angle(name):
                if name == "ground":
                    return 0.0
                if name in free:
                    return q[3 * free.index(name) + 2]
                b = model.body(name)
                return b.driver.angle0 + b.driver.speed * t0

            phib = body_angle(cj.bearing_body)
            spec = cj.spec
            clear = spec.clearance
            kst = spec.stiffness
            if geometry is not None:
                g = geometry[k]
                clear = g.clearance
                rb, rj = g.bearing_radius + g.clearance_growth / 2, g.journal_radius - g.clearance_growth / 2
                if g.use_profile:
                    ang = np.arctan2(n[1], n[0])
                    hb = profile_value(g.bearing_wear, ang - phib)
                    hj = profile_value(g.journal_wear, ang - body_angle(cj.journal_body))
                    clear += hb + hj
                    rb, rj = rb + hb, rj - hj
                kst = contact_stiffness(spec.hsum, rb, rj)
            delta = (fmag / kst) ** (1.0 / spec.exponent)
            e = (clear + delta) * n
            c, s = np.cos(phib), np.sin(phib)
            local = (c * e[0] + s * e[1], -s * e[0] + c * e[1])
            joint = next(j for j in ideal.joints if j.name == cj.name)
            # the shifted bearing point gets a name of its own: another joint at the same point (a slider's pin)
            # keeps the drawn one
            moved = f"{joint.point_i} (preload of {cj.name})"
            if joint.body_i == "ground":
                p = ideal.ground_points[joint.point_i]
                ideal.ground_points = {**ideal.ground_points, moved: (p[0] + local[0], p[1] + local[1])}
            else:
                body = ideal.body(joint.body_i)
                p = body.points[joint.point_i]
                body.points = {**body.points, moved: (p[0] + local[0], p[1] + local[1])}
            ideal.joints = [dataclasses.replace(j, point_i=moved) if j is joint else j for j in ideal.joints]
            # contact memory: established, with the impact speed scale clearance x driver speed
            # (floored by v0_min): flapping wing 2 um x 50 rad/s = 1e-4 m/s; slider-crank 0.26 m/s.
            # v0_min alone would make the damping of a fast mechanism absurdly stiff until the first
            # separation.
            per = model.period
            wdrv = TWO_PI / per if per else 0.0
            cstate[k] = (max(spec.v0_min, clear * wdrv), 1.0)
        ideal.guess = None
        q, qd, _ = ideal.kinematics(t0, q_guess=q)
    return SimulationState(t0, np.concatenate([q, qd]), cstate, 0.0)


def profile_value(prof: np.ndarray, ang: float) -> float:
    """A worn profile at angle ``ang`` as the dynamics reads it (kernel.profile_at: periodic Catmull-Rom), so that the
    preload places the journal where the kernel finds it in contact."""
    p = np.ascontiguousarray(prof, dtype=float).reshape(1, 1, -1)
    return float(profile_at(p, 0, 0, p.shape[2], float(ang))[0])
