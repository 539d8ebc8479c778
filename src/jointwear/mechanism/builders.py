"""A MechanismModel from a validated StudyConfig: the four-bar, the slider-crank and the general linkage.

The model holds the config's clearance-joint and simulation settings as they are; only the topology (bodies,
body-frame points, ideal joints, drivers) and the assembly guess are derived here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from jointwear.mechanism.assembly import general_parts
from jointwear.mechanism.model import (
    GROUND,
    Body,
    ClearanceJoint,
    Driver,
    Joint,
    MechanismModel,
)

if TYPE_CHECKING:
    from jointwear.config import StudyConfig


@dataclass
class FourBarGuess:
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
class SliderCrankGuess:
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
    c1, c2, c3 = m.crank.com, m.rod.com, m.rocker.com
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
    guess = FourBarGuess(O, C, l1, l2, l3, c1, c2, c3, m.crank_angle0, m.crank_speed, m.assembly_branch)
    return [crank, rod, rocker], joints, {"O": O, "C": C}, guess


def _slider_crank(cfg) -> tuple[list[Body], list[Joint], dict, Callable]:
    m = cfg.mechanism
    l1, l2 = m.crank.length, m.rod.length
    c1, c2 = m.crank.com, m.rod.com
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
    guess = SliderCrankGuess(O, P0, u, nrm, l1, l2, c1, c2, g, m.crank_angle0, m.crank_speed, m.assembly_branch)
    return [crank, rod, slider], joints, {"O": O, "P0": P0}, guess


def build_model(config: StudyConfig) -> MechanismModel:
    """MechanismModel from a validated StudyConfig (clearance joints replace their ideal revolutes).

    Raises ConfigError naming the field when a general linkage cannot assemble over its cycle
    (jointwear.mechanism.assembly.check_assembly).
    """
    mcfg = config.mechanism
    period = None
    if mcfg.type == "four_bar":
        bodies, joints, gpoints, guess = _four_bar(config)
        lref = float(np.median([mcfg.crank.length, mcfg.rod.length, mcfg.rocker.length]))
    elif mcfg.type == "slider_crank":
        bodies, joints, gpoints, guess = _slider_crank(config)
        lref = float(np.median([mcfg.crank.length, mcfg.rod.length]))
    else:
        p = general_parts(mcfg)
        bodies, joints, gpoints, guess, lref, period = p.bodies, p.joints, p.ground_points, p.guess, p.length_ref, p.period
    cjs: list[ClearanceJoint] = []
    for cc in config.clearance_joints:
        ideal = next(j for j in joints if j.name == cc.joint)
        joints.remove(ideal)
        pts = {ideal.body_i: ideal.point_i, ideal.body_j: ideal.point_j}
        cjs.append(ClearanceJoint(cc, bearing_point=pts[cc.bearing_body], journal_point=pts[cc.journal_body]))
    return MechanismModel(bodies=bodies, joints=joints, clearance_joints=cjs, ground_points=gpoints,
                          gravity=tuple(mcfg.gravity), settings=config.simulation, guess=guess, name=config.name,
                          length_ref=lref, period_override=period)
