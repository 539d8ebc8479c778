"""Legal but probably unmeant: a random variable whose mean is far from the value drawn at its target."""

import pytest

from jointwear.config import available_presets, load_config, updated
from jointwear.study.checks import MEAN_SHIFT_WARNING_SIGMAS, config_warnings


@pytest.mark.parametrize("preset", available_presets())
def test_the_shipped_presets_draw_what_they_sample(preset):
    assert config_warnings(load_config(preset)) == []


def test_a_clearance_mean_far_from_the_drawn_gap_is_warned_with_its_distance():
    base = load_config()
    spec = base.uncertainty.clearance
    sigmas = MEAN_SHIFT_WARNING_SIGMAS + 1.0
    shifted = updated(base, {"uncertainty.clearance.mean": spec.mean + sigmas * spec.std})
    (warning,) = config_warnings(shifted)
    assert f"the mean of 'c' ({spec.mean + sigmas * spec.std:.6g} m) is {sigmas:,.0f} standard deviations" in warning
    inside = updated(base, {"uncertainty.clearance.mean": spec.mean + (MEAN_SHIFT_WARNING_SIGMAS - 0.5) * spec.std})
    assert config_warnings(inside) == []
