"""`jointwear simulate` writes simulate.json (DESIGN.md keys), the series and the figures, each key of them in
docs/results.md."""

import json

import numpy as np
import pytest
from result_keys import undocumented_keys

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
    # the columns of body_angles_rad are named; the window starts after the settling cycle (docs/results.md)
    assert z["body_names"].tolist() == ["crank", "rod", "rocker"]
    assert z["body_angles_rad"].shape == (z["t_s"].size, 3)
    np.testing.assert_allclose(np.mod(z["body_angles_rad"][:, 0], 2 * np.pi), z["crank_angle_rad"], rtol=0,
                               atol=1e-9)  # the same angle wrapped apart, to its rounding (1e-15 of 2 pi x turns)
    assert z["t_s"][0] == pytest.approx(d["settle_cycles"] * d["period_s"], rel=1e-12)
    assert z["t_s"][-1] == pytest.approx((d["settle_cycles"] + d["cycles"]) * d["period_s"], rel=1e-12)
    # the driver's torque (tests/dynamics/test_driver_torque.py) and its summary, the trapezoid rule on t_s
    tau, w = z["driver_torque_N_m"], np.gradient(z["t_s"])
    w[0], w[-1] = w[0] / 2, w[-1] / 2  # the trapezoid weights
    assert d["driver_torque_mean_N_m"] == pytest.approx(np.sum(w * tau) / np.sum(w), rel=1e-9)  # rounding
    assert d["driver_torque_rms_N_m"] == pytest.approx(np.sqrt(np.sum(w * tau**2) / np.sum(w)), rel=1e-9)
    assert d["driver_torque_max_N_m"] == np.max(np.abs(tau)) > 0
    # every key of the three files is in its section of docs/results.md (tests/result_keys.py)
    for name in ("simulate.json", "simulate.npz", "simulate_joints.csv"):
        assert undocumented_keys(tmp_path / name) == [], name


def test_an_undocumented_series_or_column_is_found(tmp_path):
    """The key check of the series file and the joints' table can fail: a key docs/results.md does not give is
    named, a joint's key by its generic `<joint>_` form, whatever the joint's name."""
    (tmp_path / "simulate.json").write_text(json.dumps({"joints": [{"name": "pin_1"}, {"name": "E"}]}))
    n = 3
    np.savez(tmp_path / "simulate.npz", t_s=np.zeros(n), body_names=np.array(["crank"]),
             pin_1_force_normal_N=np.zeros(n), E_in_contact=np.zeros(n, bool),
             driver_power_W=np.zeros(n), E_hidden_m=np.zeros(n), pin_2_force_normal_N=np.zeros(n))
    assert undocumented_keys(tmp_path / "simulate.npz") == ["E_hidden_m", "driver_power_W", "pin_2_force_normal_N"]
    (tmp_path / "simulate_joints.csv").write_text("name,contact_fraction,secret_N\nA,1,2\n")
    assert undocumented_keys(tmp_path / "simulate_joints.csv") == ["secret_N"]


@pytest.mark.parametrize("preset, kernel", [("jin2025_flapping_wing", "natural_fourbar"),
                                            ("flores_slider_crank", "tree")])
def test_reaction_says_which_kernel_lacks_it(preset, kernel):
    """The default kernels record no multipliers of the ideal joints: reaction() says so and how to get them,
    instead of returning NaN; the Cartesian kernel's are finite."""
    model = build_model(load_config(preset))
    res = simulate(model, 0.02, settle_cycles=0)
    assert res.extra["kernel"] == kernel
    joint = res.joint_names[0]
    with pytest.raises(ValueError, match=rf"{kernel} kernel .* simulate\(\.\.\., fast=False\)"):
        res.reaction(joint)
    cart = simulate(model, 0.02, settle_cycles=0, fast=False)
    assert cart.extra["kernel"] == "cartesian"
    reaction = cart.reaction(joint)
    assert reaction.shape == (cart.t.size, 2) and np.isfinite(reaction).all()


def test_simulate_rejects_bad_arguments():
    model = build_model(load_config("jin2025_flapping_wing"))
    with pytest.raises(ValueError, match="n_cycles"):
        simulate(model, -1)
    with pytest.raises(ValueError, match="rtol"):
        simulate(model, 1, rtol=0.0)
    with pytest.raises(ValueError, match="geometry"):
        simulate(model, 1, geometry=[])
