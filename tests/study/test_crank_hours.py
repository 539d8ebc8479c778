"""Cycles to hours at the config's crank speed through units' rpm factor: N / (60 rpm), the rule of
ReliabilityCurve.hours (audit 61-J, finding 7)."""

from __future__ import annotations

import math

import pytest

from jointwear.config import load_config, updated
from jointwear.study.reliability import crank_speed_rpm, cycles_to_hours


@pytest.mark.parametrize("rpm", [480.0, 120.0, 5000.0])
def test_an_hour_of_running_is_60_rpm_cycles(rpm):
    cfg = updated(load_config(), {"mechanism.crank_speed_rpm": rpm})
    assert crank_speed_rpm(cfg) == pytest.approx(rpm, rel=1e-15)
    assert cycles_to_hours(60.0 * rpm, cfg) == pytest.approx(1.0, rel=1e-15)
    # the period 2 pi / omega of the rad/s the config holds, to the last bit or so
    omega = abs(cfg.mechanism.crank_speed)
    assert cycles_to_hours(360_000, cfg) == pytest.approx(360_000 * 2 * math.pi / omega / 3600, rel=4e-16)
