"""Reproduction of the paper's Section 6.1.3 with the real dynamics (flapping-wing preset, uniform mode, 400k cycles).

Targets (issue 3 acceptance; paper: 0.0249 mm at 110 deg, second peak 0.0087 mm at 310 deg):
max bearing wear 0.021-0.029 mm, peak within 20 deg of 110 deg, a second peak on the far side.
Assembly branch -1 is the one that matches (docs/wear.md: branch +1 puts the peaks near 94 / 265 deg and gives
0.033 mm). One history takes about 15 s on 2 cores, so the test is not marked slow.
"""

import math

import numpy as np
import pytest

mechanism = pytest.importorskip("jointwear.mechanism")

from jointwear.config import load_config  # noqa: E402
from jointwear.wear import WearSettings, wear_history  # noqa: E402
from jointwear.wear.results import conservation_error  # noqa: E402

CONS_TOL = 1e-6  # issue 3 acceptance


def _angdiff(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.fixture(scope="module")
def result():
    cfg = load_config(None)
    mech = cfg.mechanism.model_copy(update={"assembly_branch": -1})
    cfg = cfg.model_copy(update={"mechanism": mech})
    model = mechanism.build_model(cfg)
    return wear_history(model, WearSettings(geometry_mode="uniform"), 400_000)


def test_max_wear_magnitude(result):
    # 0.021-0.029 mm: issue 3 acceptance band around the paper's 0.0249 mm
    assert 0.021e-3 <= result.max_wear_at(400_000) <= 0.029e-3


def test_peak_angles(result):
    j = result.joints[0]
    assert _angdiff(j.max_wear_angle_deg, 110.0) <= 20.0  # issue 3: within 20 deg of the paper's 110 deg
    assert len(j.peaks) >= 2
    second = j.peaks[1]
    # far side: the paper's second peak is 200 deg from the first (310 vs 110); accept 180 +- 45 deg
    assert _angdiff(second["angle_deg"], j.peaks[0]["angle_deg"]) >= 135.0
    assert _angdiff(second["angle_deg"], 310.0) <= 20.0
    # paper: 0.0087 / 0.0249 = 0.35 of the max; accept 0.15-0.6
    assert 0.15 <= second["depth"] / j.peaks[0]["depth"] <= 0.6


def test_history_linear_and_interpolable(result):
    c, h = result.cycles, result.max_bearing_wear
    assert c[-1] == 400_000 and np.all(np.diff(h) > 0)
    # the paper's means are linear in cycles: the mean rate over the second half is within 20 % of the first half's
    # (20 %: the sampling scatter of the max with 20 blocks, docs/wear.md)
    r1 = result.max_wear_at(200_000) / 200_000
    r2 = (result.max_wear_at(400_000) - result.max_wear_at(200_000)) / 200_000
    assert r2 / r1 == pytest.approx(1.0, abs=0.2)


def test_conservation_real_dynamics(result):
    eb, ej = conservation_error(result.joints[0])
    assert eb < CONS_TOL and ej < CONS_TOL


def test_reported_angles_in_range(result):
    j = result.joints[0]
    assert np.all((j.angle_deg >= 0) & (j.angle_deg < 360))
    assert math.isfinite(j.mean_orientation)


def test_profile_mode_runs_and_conserves():
    """Profile mode against the real dynamics, short (30k cycles, 3 blocks): conservation and the envelope feed."""
    cfg = load_config(None)
    mech = cfg.mechanism.model_copy(update={"assembly_branch": -1})
    cfg = cfg.model_copy(update={"mechanism": mech})
    model = mechanism.build_model(cfg)
    res = wear_history(model, WearSettings(geometry_mode="profile"), 30_000)
    j = res.joints[0]
    eb, ej = conservation_error(j)
    assert eb < CONS_TOL and ej < CONS_TOL
    assert len(res.blocks) == 3 and j.max_bearing_wear > 0
