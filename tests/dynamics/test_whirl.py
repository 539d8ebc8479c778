"""The friction-driven whirl of a journal in its bore: its measure, and that the stages find it and say so
(docs/dynamics.md, "Friction-driven whirl"; the speeds and numbers are those of benchmarks/results/whirl.json)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "wear"))
from wear_synthetic import PERIOD, make_trace  # noqa: E402

import jointwear  # noqa: E402
from jointwear.config import load_config, updated  # noqa: E402
from jointwear.mechanism import build_model, simulate, whirl_measure, whirl_threshold  # noqa: E402

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


@pytest.mark.parametrize("turns_per_cycle", [-50.0, 0.0, 3.0])
def test_contact_revolutions_count_the_contact_point_round_the_bearing(turns_per_cycle):
    """A contact point turning at a constant rate: the sum of the wrapped steps is the unwrapped change, exactly
    (to rounding), and the journal of the synthetic rod-like joint turns once per cycle against the bearing."""
    base = make_trace(n_cycles=2)
    theta = (2 * np.pi * turns_per_cycle * base.t / PERIOD) % (2 * np.pi)
    tr = dataclasses.replace(base, theta_bearing=theta, in_contact=np.ones_like(base.in_contact))
    expected = turns_per_cycle * (base.t[-1] - base.t[0]) / PERIOD
    assert tr.contact_revolutions == pytest.approx(expected, rel=1e-9, abs=1e-9)
    assert tr.relative_revolutions == pytest.approx((base.t[-1] - base.t[0]) / PERIOD, rel=1e-9)
    # steps out of contact do not count: a contact point that jumps across the bore in flight is not a whirl
    apart = dataclasses.replace(tr, in_contact=np.arange(tr.t.size) % 2 == 0)
    assert apart.contact_revolutions == 0.0


def test_contact_revolutions_leave_out_the_moves_through_free_flight():
    """docs/results.md: on an impacting joint the measure is what the contact point travels while in contact, not
    the contact zone's net migration. Two contacts each turn +0.1 revolution; between them the journal flies and
    strikes the bore 0.4 revolution back (in five steps of -0.08, each below pi): +0.2 counted, while the contact
    zone's net move is -0.2."""
    base = make_trace(n_cycles=1)
    steps = np.r_[np.full(10, 0.01), np.full(5, -0.08), np.full(10, 0.01)] * 2 * np.pi
    theta = np.mod(1.0 + np.r_[0.0, np.cumsum(steps)], 2 * np.pi)
    contact = np.r_[np.ones(11, bool), np.zeros(4, bool), np.ones(11, bool)]
    n = theta.size
    tr = dataclasses.replace(base, t=base.t[:n], dt_weight=base.dt_weight[:n], theta_bearing=theta,
                             in_contact=contact)
    assert tr.contact_revolutions == pytest.approx(0.2, abs=1e-12)  # rounding of 20 wrapped steps
    net = (np.sum(steps)) / (2 * np.pi)
    assert net == pytest.approx(-0.2, abs=1e-12)


def test_the_whirl_threshold_follows_the_relative_rotation():
    assert whirl_threshold(0.0) == 5.0 and whirl_threshold(1.0) == 6.0 and whirl_threshold(-3.0) == 12.0


@pytest.mark.parametrize("rpm, whirls", [(360, True), (480, False)])
def test_the_flapping_wing_whirls_at_360_rpm_and_not_at_480(rpm, whirls):
    """From the assembled rest state the preset whirls at 330-420 rpm (-307 revolutions per cycle at 360) and is calm
    at 480 (1.01: the contact follows the load round once per cycle); calm cases stay at or below 1.2."""
    cfg = updated(load_config(), {"mechanism.crank_speed_rpm": rpm})
    res = simulate(build_model(cfg), 1)
    revolutions, flagged = whirl_measure(res.joints[0], res.n_cycles)
    assert flagged is whirls
    assert (abs(revolutions) > 100) if whirls else (abs(revolutions) < 2)


def test_the_stages_and_the_report_tell_a_whirl(tmp_path):
    cfg = updated(load_config(), {"mechanism.crank_speed_rpm": 360, "wear.block_cycles": 10_000})
    lines: list[str] = []
    study = jointwear.Study(cfg, out=tmp_path, echo=lines.append)
    sim = study.simulate(cycles=1)
    assert sim.joints[0]["whirl"] is True and sim.joints[0]["contact_revolutions_per_cycle"] < -100
    wear = study.wear(cycles=20_000)
    assert wear.blocks[0]["whirl"] == ["A"]  # the first block starts from rest, as the simulate stage
    told = [line for line in lines if "joint A whirls" in line]
    assert [line.split(":")[0] for line in told] == ["simulate", "wear"]
    assert "blocks (" in told[1] and "docs/dynamics.md" in told[0]
    html = study.report().read_text()
    assert html.count("<strong>Friction-driven whirl.</strong>") == 2
