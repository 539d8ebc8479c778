"""A clearance put on a joint that cannot carry one says why: the joint is prismatic, or driven (a designer put one
on his press's ram slider P and on its driven crank pivot O and was told only the joints allowed)."""

from pathlib import Path

import pytest

from jointwear.config import load_config, updated
from jointwear.schema import ConfigError

PUMP = Path(__file__).resolve().parents[1] / "examples" / "piston_pump.toml"


def test_a_clearance_on_a_prismatic_joint_says_it_is_prismatic():
    with pytest.raises(ConfigError) as caught:
        updated(load_config(PUMP), {"clearance_joints[B].joint": "P"})
    message = str(caught.value)
    assert "clearance_joints[B].joint: 'P' is not a joint that can carry clearance" in message
    assert "P is a prismatic joint" in message and "(allowed: A, B)" in message


def test_a_clearance_on_a_driven_joint_says_it_is_driven():
    with pytest.raises(ConfigError, match=r"'O' is not a joint that can carry clearance: O is driven "
                                          r"\(mechanism\.drivers\[0\]\.joint\)"):
        updated(load_config("watt_six_bar_two_clearances"), {"clearance_joints[A].joint": "O"})
    # a built-in linkage's O is its crank's driven pivot
    with pytest.raises(ConfigError, match="O is the crank's driven pivot"):
        updated(load_config(), {"clearance_joints[0].joint": "O"})


def test_a_name_that_is_no_joint_keeps_the_short_message():
    with pytest.raises(ConfigError) as caught:
        updated(load_config("watt_six_bar_two_clearances"), {"clearance_joints[A].joint": "knee"})
    assert str(caught.value).endswith("'knee' is not a joint that can carry clearance (allowed: A, B, C, D, E, F)")
