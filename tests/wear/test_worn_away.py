"""A wear history whose pin wears away stops there, says why, and still answers the limit state.

Dry mild steel on mild steel (Archard and Hirst's k = 7e-3, 190 HB) in the tutorial's linkage wears its 2 mm pin
away within about a million cycles; uniform mode's dynamics would then need a journal of negative radius (it raised
a math domain error, and every such reliability sample was a failed call left out of the surrogate).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from jointwear.config import load_config, updated
from jointwear.mechanism import build_model
from jointwear.study.limit_state import life_from_history
from jointwear.study.model_call import WORN_AWAY_WEAR, WearModelCall
from jointwear.wear import wear_history
from jointwear.wear.history import used_up
from jointwear.wear.settings import WearSettings

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml"


def test_used_up_at_the_journal_radius_and_at_a_growth_of_its_diameter():
    g = SimpleNamespace(journal_radius=2e-3, clearance_growth=0.0)
    uniform, profile = WearSettings(geometry_mode="uniform"), WearSettings(geometry_mode="profile")
    assert used_up(g, uniform, np.array([0.0, 1.999e-3]), 3.999e-3) is None
    assert "as deep as its radius" in used_up(g, profile, np.array([0.0, 2e-3]), 0.0)
    assert "no radius" in used_up(g, uniform, np.array([0.0, 1e-3]), 4e-3)
    assert used_up(g, profile, np.array([0.0, 1e-3]), 4e-3) is None  # profile mode grows no uniform clearance


@pytest.fixture(scope="module")
def dry_steel():
    steel = {"youngs_modulus": 207e9, "poissons_ratio": 0.3, "hardness": 1.863e9, "wear_coefficient": 7e-3}
    cfg = load_config(EXAMPLE)
    return updated(cfg, {"clearance_joints.B.bearing_material": steel, "clearance_joints.B.journal_material": steel,
                         "wear.block_cycles": 100_000})


def test_a_pin_worn_away_stops_the_history_instead_of_raising(dry_steel):
    res = wear_history(build_model(dry_steel), dry_steel.wear, 2_000_000)
    assert res.stopped_at is not None and res.stopped_at < 2_000_000
    jw = res.joints[0]
    assert jw.history_cycles[-1] == res.stopped_at
    r_j = dry_steel.clearance_joints[0].journal_radius
    assert jw.history_max_journal[-1] >= r_j or jw.history_clearance_growth[-1] >= 2.0 * r_j
    assert "joint B" in res.stop_reason
    # a model call reports, past the stop, a wear no allowance reaches: the call does not fail, and its life ends
    # at the stop (within one step of its cycle grid) instead of running on along an extrapolated history
    cycles = list(range(100_000, 2_000_001, 100_000))
    call = WearModelCall(dry_steel.model_dump(), ["clearance_joints.B.bearing_material.wear_coefficient"], cycles)
    out, status = call(np.array([7e-3]))
    assert status == "ok" and np.all(np.isfinite(out))
    after = np.asarray(cycles) > res.stopped_at
    assert np.all(out[after] == WORN_AWAY_WEAR) and np.all(out[~after] < r_j)
    allowance = 1.05 * out[~after][-1]  # not reached before the stop
    life = life_from_history(cycles, out[None, :], allowance)[0]
    assert res.stopped_at <= life < res.stopped_at + 100_000


def test_an_infeasible_sample_gives_its_reason_once(dry_steel):
    # a hardness of 72 Pa (a unit slip) cannot build the model: the call fails with the schema's reason, named once
    call = WearModelCall(dry_steel.model_dump(), ["clearance_joints.B.bearing_material.hardness"], [100_000])
    out, status = call(np.array([72.0]))
    assert np.all(np.isnan(out)) and status.startswith("infeasible sample: clearance_joints")
    assert "sample: sample:" not in status and "hardness" in status


@pytest.mark.parametrize("threads", [1, 2])
def test_no_block_is_run_or_left_running_past_the_stop(dry_steel, threads):
    """A history stopped at a worn-away joint ran (serially) or waited for (in threads) the look-ahead block of its
    other lane: on the default study's l2 x 1.2 sensitivity call that block held 2.5 GB and half the call's time."""
    from jointwear.mechanism import SimulationCancelled
    from jointwear.mechanism import simulate as mechanism_simulate

    finished, cancelled, events = [], [], []

    def counted(*args, cancel=None, **kwargs):
        events.append(cancel)
        try:
            res = mechanism_simulate(*args, cancel=cancel, **kwargs)
        except SimulationCancelled:
            cancelled.append(1)
            raise
        finished.append(1)
        return res

    settings = dry_steel.wear.model_copy(update={"lanes": 2})
    model = build_model(dry_steel)
    res = wear_history(model, settings, 2_000_000, threads=threads)
    again = wear_history(model, settings, 2_000_000, threads=threads, simulate=counted)
    assert again.stopped_at == res.stopped_at is not None
    np.testing.assert_array_equal(again.joints[0].bearing_wear, res.joints[0].bearing_wear)
    blocks = len(res.blocks)
    assert events[0] is not None and events[0].is_set()  # the stop is told to any block still in flight
    if threads == 1:
        assert len(finished) == blocks and not cancelled  # nothing simulated past the stop
    else:  # the other lane's block: not started (its future cancelled), cancelled running, or done before the stop
        assert blocks <= len(finished) + len(cancelled) <= blocks + 1 and len(finished) <= blocks + 1
