"""simulation.max_steps bounds the steps of a whole simulate() call (settling and every record chunk together), so
a collapsing step size stops with SimulationError instead of growing the record without bound."""

from __future__ import annotations

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
