"""`jointwear simulate` writes simulate.json (DESIGN.md keys), the series and the figures."""

import json

import numpy as np
import pytest

from jointwear.cli import main_entry
from jointwear.config import load_config
from jointwear.mechanism import build_model, simulate


def test_simulate_command(tmp_path, capsys):
    code = main_entry(["simulate", "jin2025_flapping_wing", "--cycles", "1", "--settle", "1", "--out", str(tmp_path)])
    assert code == 0, capsys.readouterr().err
    d = json.loads((tmp_path / "simulate.json").read_text())
    for key in ("contact_force_mean_N", "contact_force_max_N", "contact_fraction", "impacts_per_cycle",
                "steps_per_cycle", "wall_seconds_per_cycle"):
        assert isinstance(d[key], (int, float)), key
    assert 0.02 < d["contact_force_mean_N"] < 0.05
    assert d["contact_force_max_N"] >= d["contact_force_mean_N"]
    assert 0.5 < d["contact_fraction"] <= 1.0
    assert d["joints"][0]["name"] == "A" and d["joints"][0]["bearing_body"] == "rod"
    z = np.load(tmp_path / "simulate.npz")
    assert z["A_eccentricity_bearing_frame_m"].shape == (z["t_s"].size, 2)
    assert z["A_force_normal_N"].size == z["crank_angle_rad"].size
    assert (tmp_path / "orbit_A.png").stat().st_size > 1000
    assert (tmp_path / "force_A.png").stat().st_size > 1000


def test_simulate_rejects_bad_arguments():
    model = build_model(load_config("jin2025_flapping_wing"))
    with pytest.raises(ValueError, match="n_cycles"):
        simulate(model, -1)
    with pytest.raises(ValueError, match="rtol"):
        simulate(model, 1, rtol=0.0)
    with pytest.raises(ValueError, match="geometry"):
        simulate(model, 1, geometry=[])
