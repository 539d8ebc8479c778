"""The tree kernel with sliders (prismatic joints): the same answers as the general Cartesian kernel.

Four linkages cover each way a slider enters the tree: the Flores slider-crank (the guide's line owned by the ground,
clearance at the wrist pin), the same with the joint written the other way round (the line owned by the slider), the
clearance moved to the crank pin (the rod then hangs by a revolute joint from the sliding body), and a quick-return
slotted lever (the block slides on a turning guide: the line moves, Coriolis terms).
"""

from __future__ import annotations

import numpy as np
import pytest
from kernel_checks import assert_tree_accelerations_match_cartesian, loop_against_evaluation
from scipy.interpolate import CubicHermiteSpline

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism import build_model, simulate
from jointwear.mechanism import kernel as K
from jointwear.mechanism.simulate import Runner
from jointwear.mechanism.tree import body_angles, to_cartesian, tree_layout

FLORES = "flores_slider_crank"


def _clearance(joint: str, bearing: str, journal: str, radius_mm: float, clearance_mm: float) -> dict:
    steel = {"name": "steel", "youngs_modulus": 207e9, "poissons_ratio": 0.3, "hardness": 2e9,
             "wear_coefficient": 1e-5}
    return {"name": joint, "joint": joint, "bearing_body": bearing, "journal_body": journal,
            "bearing_radius": (radius_mm + clearance_mm) * 1e-3, "journal_radius": radius_mm * 1e-3,
            "width": 8e-3, "bearing_material": steel, "journal_material": steel}


def slider_crank(reversed_slider: bool = False, clearance_at: str = "B"):
    """A piston pump drawn as a general linkage: crank 15 mm at 1500 rpm, rod 60 mm, a 150 g piston pushed back by
    200 N, its centre of mass off its pin (so that the pin moves with the piston's angle, were it free); 10 um
    clearance at the wrist pin B (rod eye, piston pin) or at the crank pin A (rod eye, crank pin)."""
    slide = ["ground.G", "piston.B"] if not reversed_slider else ["piston.B", "ground.G"]
    cj = (_clearance("B", "rod", "piston", 4.0, 0.01) if clearance_at == "B"
          else _clearance("A", "rod", "crank", 4.0, 0.01))
    data = {
        "name": "pump", "citation": "test linkage",
        "mechanism": {
            "type": "general", "ground_points": {"O": [0.0, 0.0], "G": [0.0, 0.0]},
            "bodies": [
                {"name": "crank", "mass": 0.05, "inertia": 4e-6, "com": [0.0075, 0.0],
                 "points": {"O": [0.0, 0.0], "A": [0.015, 0.0]}},
                {"name": "rod", "mass": 0.08, "inertia": 3e-5, "com": [0.0375, 0.0],
                 "points": {"A": [0.015, 0.0], "B": [0.075, 0.0]}, "axis": ["A", "B"]},
                {"name": "piston", "mass": 0.15, "inertia": 1e-5, "com": [0.082, 0.003],  # off its pin: a lever
                 "points": {"B": [0.075, 0.0]}, "force": [-200.0, 0.0]},
            ],
            "joints": [
                {"name": "O", "connects": ["ground.O", "crank.O"]},
                {"name": "A", "connects": ["rod.A", "crank.A"]},
                {"name": "B", "connects": ["piston.B", "rod.B"]},
                {"name": "P", "type": "prismatic", "connects": slide, "direction": [1.0, 0.0]},
            ],
            "drivers": [{"joint": "O", "speed": 1500 * 2 * np.pi / 60}],
        },
        "clearance_joints": [cj],
    }
    return build_model(config_from_dict(data))


def quick_return():
    """A crank-and-slotted-lever quick return: crank O-A 20 mm at 300 rpm, a block pinned to the crank pin (10 um
    clearance, block eye on the crank pin) slides in a guide that turns about the ground pivot C, 60 mm below O."""
    d = np.array([0.02, 0.06]) / np.hypot(0.02, 0.06)
    data = {
        "name": "quick_return", "citation": "test linkage",
        "mechanism": {
            "type": "general", "ground_points": {"O": [0.0, 0.0], "C": [0.0, -0.06]},
            "bodies": [
                {"name": "crank", "mass": 0.05, "inertia": 4e-6, "com": [0.01, 0.0],
                 "points": {"O": [0.0, 0.0], "A": [0.02, 0.0]}},
                {"name": "guide", "mass": 0.2, "inertia": 2e-4, "com": (np.array([0.0, -0.06]) + 0.05 * d).tolist(),
                 "points": {"C": [0.0, -0.06]}, "torque": -0.5},
                {"name": "block", "mass": 0.03, "inertia": 2e-6, "com": [0.02, 0.0], "points": {"A": [0.02, 0.0]}},
            ],
            "joints": [
                {"name": "O", "connects": ["ground.O", "crank.O"]},
                {"name": "C", "connects": ["ground.C", "guide.C"]},
                {"name": "A", "connects": ["block.A", "crank.A"]},
                {"name": "S", "type": "prismatic", "connects": ["guide.C", "block.A"], "direction": d.tolist()},
            ],
            "drivers": [{"joint": "O", "speed": 300 * 2 * np.pi / 60}],
        },
        "clearance_joints": [_clearance("A", "block", "crank", 3.0, 0.01)],
    }
    return build_model(config_from_dict(data))


MODELS = {
    "flores": lambda: build_model(load_config(FLORES)),
    "line_owned_by_the_slider": lambda: slider_crank(reversed_slider=True),
    "rod_hangs_from_the_slider": lambda: slider_crank(clearance_at="A"),
    "turning_guide": quick_return,
}


@pytest.fixture(scope="module", params=sorted(MODELS))
def model(request):
    return MODELS[request.param]()


def test_a_slider_is_a_tree_coordinate_unless_it_rides_a_driven_body(model):
    lay = tree_layout(model.kernel_arrays())
    assert lay is not None and lay.has_slider
    assert simulate(model, 0.002, settle_cycles=0).extra["kernel"] == "tree"
    kinds = list(lay.jint[:, K.T_KIND])
    assert kinds.count(K.TREE_PRISMATIC) == 1 and lay.n == len(kinds)


def test_slider_accelerations_equal_cartesian_at_the_same_states(model):
    """As test_tree_kernel's check for revolute trees, at states along a run: tolerance 1e-9 of the largest
    acceleration (rounding amplified by the condition of the systems each kernel solves, and the Cartesian kernel's
    Baumgarte terms acting on the rounding-level constraint residual of the mapped state)."""
    res = simulate(model, 0.05, settle_cycles=0)
    assert res.extra["kernel"] == "tree"
    assert_tree_accelerations_match_cartesian(model, res, 8, force_atol=1e-9)


def test_slider_state_round_trip(model):
    """Cartesian -> tree -> Cartesian returns a state on the joints (positions to 1e-12 m: the assembly's Newton
    tolerance; velocities to 1e-9 relative), and the sliding body's angle is its parent's plus the drawn offset."""
    res = simulate(model, 0.01, settle_cycles=0)
    run = Runner(model, None, 1e-6, 1e-9)
    y = res.state_end.y
    y_tree = run.to_internal(y)
    q, qd, _ = to_cartesian(run.tree, run.a["dpar"], np.array([res.state_end.t]), y_tree[None, :])
    nq = y.size // 2
    assert np.max(np.abs(q[0] - y[:nq])) < 1e-12
    assert np.max(np.abs(qd[0] - y[nq:])) < 1e-9 * max(1.0, np.max(np.abs(y[nq:])))
    np.testing.assert_allclose(body_angles(run.tree, y_tree)[0], y[2:nq:3], atol=1e-12)


def _hermite(res, k):
    t, i = np.unique(res.t, return_index=True)
    return CubicHermiteSpline(t, res.q[i, k], res.qd[i, k])


def test_slider_same_trajectory_short_window(model):
    """Over a short window both kernels at tight tolerances follow the same trajectory: positions 1e-11 m, angles
    1e-9 rad, as for the six-bar (test_tree_kernel), read by cubic Hermite interpolation of each run's states (linear
    interpolation errs by h^2 a / 8 ~ 1e-8 m on the 5000 rpm slider-crank), and the same normal force at the end."""
    n = 0.01
    a = simulate(model, n, settle_cycles=0, fast=False, rtol=1e-10, atol=1e-14)
    b = simulate(model, n, settle_cycles=0, rtol=1e-10, atol=1e-14)
    assert a.extra["kernel"] == "cartesian" and b.extra["kernel"] == "tree"
    t = np.linspace(a.t[0], a.t[-1], 50)
    for k in range(a.q.shape[1]):
        assert np.max(np.abs(_hermite(a, k)(t) - _hermite(b, k)(t))) < (1e-9 if k % 3 == 2 else 1e-11)
    for ja, jb in zip(a.joints, b.joints):
        assert abs(ja.force_normal[-1] - jb.force_normal[-1]) < 1e-4 * max(np.max(ja.force_normal), 1e-12)


def test_specialised_loop_equals_general_evaluation(model):
    """The loop specialised to each slider linkage's shape gives, at each accepted step, one evaluation of the general
    tree kernel's accelerations and contact outputs (the generated slide: its Coriolis term on the turning guide, a
    revolute body hung from a sliding one). Tolerances: test_tree_kernel's test of the same name (measured 2e-10)."""
    loop_acc, loop_out, acc, out = loop_against_evaluation(model, 0.01)
    assert np.all(np.abs(loop_acc - acc) <= 1e-7 * np.abs(acc).max())
    scale = np.abs(out).max(axis=(0, 1))
    assert np.all(np.abs(loop_out - out) <= 1e-8 * scale)
