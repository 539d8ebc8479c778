"""Synthetic ContactTrace-like data and a fake dynamics for unit tests of the wear stage (duck typing)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from jointwear.config import ClearanceJointConfig, SimulationConfig, load_config

# Flapping-wing joint A (paper Tables 2 and 4 as the preset reads them: radii, width, materials).
JOINT = load_config("jin2025_flapping_wing").clearance_joints[0]
PERIOD = 0.125  # s, 480 rpm


@dataclass
class FakeGeometry:
    bearing_radius: float = 1.002e-3
    journal_radius: float = 1.0e-3
    clearance_growth: float = 0.0
    bearing_wear: np.ndarray = field(default_factory=lambda: np.zeros(0))
    journal_wear: np.ndarray = field(default_factory=lambda: np.zeros(0))
    use_profile: bool = False


@dataclass
class FakeTrace:
    t: np.ndarray
    dt_weight: np.ndarray
    theta_bearing: np.ndarray
    theta_journal: np.ndarray
    force_normal: np.ndarray
    force_tangential: np.ndarray
    slip_speed: np.ndarray
    penetration: np.ndarray
    in_contact: np.ndarray
    bearing_body_angle: np.ndarray
    eccentricity_global: np.ndarray | None = None  # (m, 2): journal centre from the bearing centre, global frame
    normal_tilt: np.ndarray | None = None
    bearing_radius: float = 1.002e-3
    journal_radius: float = 1.0e-3
    clearance_used: float = 2e-6
    joint: ClearanceJointConfig = JOINT


def make_trace(n_cycles=2, steps_per_cycle=3000, f0=0.05, rate_scale=1.0, seed=0, **over) -> FakeTrace:
    """A rod-like joint: the normal flips between two near-opposite directions of the bearing frame (a two-force
    member), with a force that varies over the cycle, and the journal turning once per cycle against the rod."""
    rng = np.random.default_rng(seed)
    m = n_cycles * steps_per_cycle
    t = np.sort(rng.uniform(0, n_cycles * PERIOD, m))
    edges = np.concatenate([[0.0], 0.5 * (t[1:] + t[:-1]), [n_cycles * PERIOD]])
    dt = np.diff(edges)
    ph = 2 * np.pi * t / PERIOD
    flip = np.sin(ph) > -0.3
    th_b = np.where(flip, 1.2 + 0.15 * np.sin(2 * ph), 1.2 + np.pi + 0.1 * np.cos(ph))
    F = f0 * rate_scale * np.where(flip, 1.0 + 0.4 * np.sin(ph), 0.35)
    inc = rng.uniform(size=m) > 0.03
    F = np.where(inc, F, 0.0)
    th_j = th_b - ph  # the journal turns a revolution per cycle against the bearing
    slip = 50.0 * 1e-3 * (1 + 0.2 * np.cos(ph))
    pen = np.where(inc, 1e-8, 0.0)
    psi = -0.3 + 0.05 * np.sin(ph)
    ecc = (2e-6 + pen)[:, None] * np.column_stack([np.cos(th_b + psi), np.sin(th_b + psi)])
    tr = FakeTrace(t=t, dt_weight=dt, theta_bearing=th_b, theta_journal=th_j, force_normal=F,
                   force_tangential=0.1 * F, slip_speed=slip, penetration=pen, in_contact=inc,
                   bearing_body_angle=psi, eccentricity_global=ecc, normal_tilt=np.zeros(m))
    return dataclasses.replace(tr, **over)


@dataclass
class FakeResult:
    joints: list
    state_end: object
    n_steps: int
    n_cycles: float
    settle_cycles: float
    wall_seconds: float = 0.0


class FakeModel:
    """Stands in for MechanismModel: the force grows mildly with the clearance, so the wear rate drifts."""

    def __init__(self, n_joints=1, steps_per_cycle=800, settle_cycles=3, **trace_over):
        self.n_joints = n_joints
        self.settings = SimulationConfig(settle_cycles=settle_cycles)  # the dynamics' settle from rest
        self.steps_per_cycle = steps_per_cycle
        self.trace_over = trace_over
        self.calls = []

    def initial_geometry(self):
        return [FakeGeometry() for _ in range(self.n_joints)]


def fake_simulate(model, n_cycles, geometry=None, settle_cycles=None, rtol=None, atol=None, state0=None):
    model.calls.append(dict(n_cycles=n_cycles, settle=settle_cycles, state0=state0,
                            growth=[g.clearance_growth for g in geometry], use_profile=[g.use_profile for g in geometry]))
    joints = []
    for g in geometry:
        extra = g.clearance_growth + (float(np.max(g.bearing_wear)) if g.use_profile and g.bearing_wear.size else 0.0)
        scale = 1.0 + extra / 1e-3  # rate up by 2 % per 20 um of wear (flapping preset: a few % over the history)
        joints.append(make_trace(n_cycles, model.steps_per_cycle, rate_scale=scale, **model.trace_over))
    # the end state counts the blocks of this chain (deterministic when blocks run in threads)
    return FakeResult(joints, state_end=(state0 or 0) + 1, n_steps=n_cycles * model.steps_per_cycle, n_cycles=n_cycles,
                      settle_cycles=model.settings.settle_cycles if settle_cycles is None else settle_cycles)
