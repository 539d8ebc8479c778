"""`check` warns of a crank speed that reads as a number of rpm written without its suffix (read as rad/s): 1,450
given so is 13,846 rpm, beyond the linkages the tool is for (the presets run at 480 and 5,000 rpm, below the
1,000 rad/s threshold)."""

import pytest

from jointwear.config import load_config, updated
from jointwear.study.checks import CRANK_SPEED_WARNING, config_warnings


def _speed_warnings(config):
    return [w for w in config_warnings(config) if "a unit slip? a number without a suffix" in w]


def test_a_suffixless_rpm_number_is_warned_of_with_the_suffix_to_write():
    (warning,) = _speed_warnings(updated(load_config("flores_slider_crank"), {"mechanism.crank_speed": 1450.0}))
    assert warning.startswith("mechanism.crank_speed: 1,450 rad/s is 13,846 rpm")
    assert "crank_speed_rpm = 1,450" in warning


@pytest.mark.parametrize("preset", ["flores_slider_crank", "jin2025_flapping_wing", "watt_six_bar_two_clearances"])
def test_the_presets_speeds_pass(preset):
    config = load_config(preset)
    assert abs(config.mechanism.crank_speed) <= CRANK_SPEED_WARNING and _speed_warnings(config) == []
