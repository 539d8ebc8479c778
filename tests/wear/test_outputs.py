"""wear.json keys (DESIGN.md), CSV and figures from a synthetic history (fast)."""

import json

import pytest
from wear_synthetic import FakeModel, fake_simulate

from jointwear.wear import WearSettings, wear_history
from jointwear.wear.cli import write_outputs


def test_write_outputs(tmp_path):
    r = wear_history(FakeModel(), WearSettings(n_grid=360), 50_000, simulate=fake_simulate)
    s = write_outputs(r, tmp_path)
    d = json.loads((tmp_path / "wear.json").read_text())
    for k in ("cycles", "max_wear_mm", "max_wear_angle_deg", "peaks", "profile", "history", "wall_seconds"):
        assert k in d
    assert d["cycles"] == 50_000
    assert set(d["profile"]) == {"angle_deg", "depth_mm"} and len(d["profile"]["angle_deg"]) == 360
    assert set(d["history"]) == {"cycles", "max_wear_mm"} and d["history"]["cycles"][-1] == 50_000
    assert d["peaks"][0]["depth_mm"] == pytest.approx(d["max_wear_mm"])
    assert d["max_wear_mm"] == pytest.approx(r.joints[0].max_bearing_wear * 1e3)
    for f in ("wear_profile.csv", "wear_history.csv", "wear_journal_profile.csv", "wear_polar.png",
              "wear_vs_angle.png", "wear_history.png"):
        assert (tmp_path / f).stat().st_size > 0
    assert s["max_wear_mm"] == d["max_wear_mm"]


@pytest.mark.parametrize("bad", [0, -1, float("nan"), "many"])
def test_wear_command_rejects_cycles(bad, tmp_path):
    from jointwear.wear.cli import wear_command

    with pytest.raises(ValueError, match="cycles"):
        wear_command(None, bad, tmp_path)
