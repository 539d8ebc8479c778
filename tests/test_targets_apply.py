"""Target values applied to a config: updated() and a study's samples (apply_sample) share one rule, the plain
targets first and the derived clearance R_i = R_j + c after them."""

import pytest

from jointwear.config import load_config, updated
from jointwear.study.model_call import apply_sample


@pytest.fixture(scope="module")
def base():
    return load_config("jin2025_flapping_wing")


def _joint(cfg, name):
    return next(j for j in cfg.clearance_joints if j.name == name)


@pytest.mark.parametrize("clearance_key", ["clearance", "clearance_um"])
@pytest.mark.parametrize("clearance_first", [True, False])
def test_a_clearance_and_a_journal_radius_combine_in_either_order(base, clearance_first, clearance_key):
    """The clearance given before the journal radius was applied to the old radius: 25 um instead of 5 um."""
    name = base.clearance_joints[0].name
    r = base.clearance_joints[0].journal_radius - 20e-6
    c = 5e-6
    items = [(f"clearance_joints.{name}.{clearance_key}", c * 1e6 if clearance_key.endswith("_um") else c),
             (f"clearance_joints.{name}.journal_radius", r)]
    joint = _joint(updated(base, dict(items if clearance_first else items[::-1])), name)
    assert joint.journal_radius == r
    assert joint.clearance == pytest.approx(c, rel=1e-9)


def test_updated_and_a_sample_agree_on_a_clearance_and_a_journal_radius(base):
    name = base.clearance_joints[0].name
    targets = [f"clearance_joints.{name}.clearance", f"clearance_joints.{name}.journal_radius"]
    x = [5e-6, base.clearance_joints[0].journal_radius - 20e-6]
    sample = apply_sample(base, targets, x)
    assert _joint(sample, name).clearance == pytest.approx(5e-6, rel=1e-9)
    for order in (targets, targets[::-1]):
        varied = updated(base, {path: dict(zip(targets, x))[path] for path in order})
        assert varied.clearance_joints[0].model_dump() == sample.clearance_joints[0].model_dump()
