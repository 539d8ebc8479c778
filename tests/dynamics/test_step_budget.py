"""simulation.max_steps bounds the steps of a whole simulate() call (settling and every record chunk together), so
a collapsing step size stops with SimulationError instead of growing the record without bound."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from jointwear.config import load_config
from jointwear.mechanism import build_model, simulate
from jointwear.mechanism.simulate import SimulationError


def model_with_budget(max_steps: int):
    cfg = load_config(None)
    sim = cfg.simulation.model_copy(update={"max_steps": max_steps})
    return build_model(cfg.model_copy(update={"simulation": sim}))


def test_budget_counts_the_settling_and_the_record():
    free = simulate(model_with_budget(10_000_000), 0.5, settle_cycles=1)
    total = free.n_steps + free.n_rejected
    settle = total - free.n_recorded_steps  # accepted + rejected steps outside the record, at least the settling's
    assert settle > 0 and free.n_recorded_steps > 0
    # a budget above each part but below their sum: only a per-call count stops it (the record alone fits)
    budget = max(settle, free.n_recorded_steps) + (total - max(settle, free.n_recorded_steps)) // 2
    assert budget < total
    with pytest.raises(SimulationError, match="budget"):
        simulate(model_with_budget(budget), 0.5, settle_cycles=1)
    # and a budget above the sum changes nothing
    again = simulate(model_with_budget(total + 10), 0.5, settle_cycles=1)
    assert again.n_steps == free.n_steps


RIG = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"


def test_the_error_says_what_each_joint_was_doing():
    """The pendulum rig's pin slides at R_j omega = 0.031 m/s under the 100 N weight; with the friction law's stick
    speed v_s put above that, the stop is reported as sticking, with the force and the last step."""
    cfg = load_config(str(RIG))
    sim = cfg.simulation.model_copy(update={"max_steps": 1000})
    cj = cfg.clearance_joints[0]
    friction = cj.friction.model_copy(update={"mu_s": 0.12, "v_s": 0.05, "v_d": 0.1})
    joints = [cj.model_copy(update={"friction": friction})]
    model = build_model(cfg.model_copy(update={"simulation": sim, "clearance_joints": joints}))
    with pytest.raises(SimulationError) as err:
        simulate(model, 1.0, settle_cycles=1)
    msg = str(err.value)
    assert "step budget exhausted" in msg and "last step" in msg
    force = float(re.search(r"joint A: normal force ([0-9.e+-]+) N", msg).group(1))
    # the weight, 100 N, times cos(atan mu) = 0.995 (friction circle), within the settling's contact ringing (+-4 %
    # seen before t = 0.2 s; the bound is twice that)
    assert 92.0 < force < 108.0
    assert "sticking" in msg
    # with the preset's stick speed (1e-4 m/s) the sliding pin is not called stuck
    with pytest.raises(SimulationError) as err:
        simulate(build_model(cfg.model_copy(update={"simulation": sim})), 1.0, settle_cycles=1)
    assert "joint A: normal force" in str(err.value) and "sticking" not in str(err.value)
