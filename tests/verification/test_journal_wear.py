"""Journal wear: k N / (H L) per revolution, the same all round the pin (docs/verification.md, case 4)."""

import pytest

from jointwear.mechanism import build_model, simulate
from jointwear.wear import WearSettings
from jointwear.wear.cycle import JointMaterials, cycle_wear

from .conftest import still_config


def test_a_pin_turning_under_a_steady_load_wears_evenly(rig_config, rig):
    cfg = still_config(rig_config, journal_wear_coefficient=2e-5)  # k/H = 1e-14 m^2/N, as the bearing
    tr = simulate(build_model(cfg), 1, settle_cycles=3, rtol=5e-7, atol=5e-10).joints[0]
    mat = JointMaterials.from_trace(tr)
    cw = cycle_wear(tr, WearSettings(), 1.0, mat)
    expected = mat.kH_j * rig.weight / rig.width
    # each point of the pin passes the contact once per revolution and takes (k/H) p ds over the patch, whose
    # integral is (k/H) F / L whatever the patch: exact up to the load's steadiness (its ringing, 0.2 % in the mean)
    assert cw.journal.mean() == pytest.approx(expected, rel=2e-3)
    # all round: the recorded revolution ends where it began to one step (its share of the patch, < 1 %)
    assert cw.journal.min() == pytest.approx(expected, rel=1e-2)
    assert cw.journal.max() == pytest.approx(expected, rel=1e-2)
