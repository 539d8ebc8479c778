"""Synthetic ContactTrace data and a fake dynamics for unit tests of the wear stage."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from jointwear.config import SimulationConfig, load_config
from jointwear.contact.geometry import ClearanceGeometry
from jointwear.mechanism.results import ContactTrace

# Flapping-wing joint A (paper Tables 2 and 4 as the preset reads them: radii, width, materials).
JOINT = load_config("jin2025_flapping_wing").clearance_joints[0]
PERIOD = 0.125  # s, 480 rpm


def make_trace(n_cycles=2, steps_per_cycle=3000, f0=0.05, rate_scale=1.0, seed=0, **over) -> ContactTrace:
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
    tr = ContactTrace(name="A", bearing_body="rod", journal_body="crank", t=t, dt_weight=dt, theta_bearing=th_b,
                      theta_journal=th_j, force_normal=F, force_tangential=0.1 * F, slip_speed=slip, penetration=pen,
                      penetration_rate=np.zeros(m), in_contact=inc, eccentricity_global=ecc, bearing_body_angle=psi,
                      journal_body_angle=psi - th_j + th_b, stiffness=np.full(m, 1e10), normal_tilt=np.zeros(m),
                      bearing_radius=1.002e-3, journal_radius=1.0e-3, clearance_used=2e-6, joint=JOINT)
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
        return [ClearanceGeometry(1.002e-3, 1.0e-3) for _ in range(self.n_joints)]


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
