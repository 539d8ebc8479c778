"""The joint-coordinate tree kernel (kernel.rhs_tree) gives the same answers as the general Cartesian kernel; the loop
specialised per linkage shape (jointwear.mechanism.tree_codegen), which simulate runs for a tree linkage, gives the
general tree kernel's (the sliders' shapes: test_tree_slider). Each shape's tests sit in one module: its generated
kernel compiles once, not on two test workers at once."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_checks import assert_tree_accelerations_match_cartesian, loop_against_evaluation

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism import build_model, simulate
from jointwear.mechanism import kernel as K
from jointwear.mechanism import tree_codegen as G
from jointwear.mechanism.simulate import Runner
from jointwear.mechanism.tree import to_cartesian, tree_layout
from jointwear.wear import WearSettings
from jointwear.wear.history import cycle_wear

SIX = "watt_six_bar_two_clearances"


@pytest.fixture(scope="module")
def six():
    return build_model(load_config(SIX))


def six_bar_three_clearances():
    """The six-bar with a third clearance joint at the output's ground pivot F: the output then hangs from no ideal
    joint and moves freely between its two clearance joints (x, y, phi in the tree)."""
    data = load_config(SIX).model_dump(mode="json")
    third = {**data["clearance_joints"][1], "name": "F", "joint": "F", "bearing_body": "ground", "journal_body": "output"}
    data["clearance_joints"] = [*data["clearance_joints"], third]
    return build_model(config_from_dict(data))


def test_tree_kernel_selected(six):
    assert simulate(six, 0.002, settle_cycles=0).extra["kernel"] == "tree"
    assert simulate(six, 0.002, settle_cycles=0, fast=False).extra["kernel"] == "cartesian"
    # closed loops of ideal joints, and sliders on a driven body, stay on the Cartesian kernel (tree sliders:
    # test_tree_slider.py)
    assert tree_layout(six.ideal().kernel_arrays()) is None
    assert tree_layout(build_model(load_config("flores_slider_crank")).kernel_arrays()).has_slider
    on_driven = {"nb": 1, "jint": np.array([[K.PRISMATIC, 1, 0]]), "jpar": np.zeros((1, 7)),
                 "bpar": np.ones((1, 3)), "dpar": np.zeros((1, 6))}  # body 0 slides on driven body 1
    assert tree_layout(on_driven) is None
    on_driven["jint"] = np.array([[K.REVOLUTE, 1, 0]])
    assert tree_layout(on_driven) is not None
    lay = tree_layout(six_bar_three_clearances().kernel_arrays())
    assert list(lay.jint[:, K.T_KIND]).count(K.TREE_FLOATING) == 1 and lay.n == 3 + 3


@pytest.mark.parametrize("which", ["six_bar", "six_bar_three_clearances"])
def test_tree_accelerations_equal_cartesian_at_the_same_states(six, which):
    """At states on the ideal joints' manifold (tree states mapped to Cartesian), both kernels' accelerations agree.

    Tolerance: both solve the same equations; they differ by rounding amplified by the condition of the systems
    solved (the Cartesian Schur complement over 4-5 joints, the tree mass matrix: ~1e3-1e4 with angle rows scaled by
    the ~50 mm links) and by the Cartesian kernel's Baumgarte terms, which act on the rounding-level constraint
    residual of the mapped state (beta^2 |Phi| ~ 1e4 x 1e-17 m). 1e-9 of the largest acceleration is 1e4 times the
    unit rounding times that condition number; measured 1e-13 (two clearances) and 1e-14 (three)."""
    model = six if which == "six_bar" else six_bar_three_clearances()
    res = simulate(model, 0.01, settle_cycles=0)
    assert res.extra["kernel"] == "tree"
    assert_tree_accelerations_match_cartesian(model, res, 6, force_atol=1e-12)


def test_tree_state_round_trip(six):
    """Cartesian -> tree -> Cartesian returns the start state to rounding (positions 1e-15 m of ~50 mm links: a few
    ulp; the preloaded start satisfies the ideal joints to the assembly's Newton tolerance 1e-10 L_ref, which the tree
    enforces exactly: 1e-12 m; measured 0 for both)."""
    res = simulate(six, 0.0, settle_cycles=0)
    run = Runner(six, None, 1e-6, 1e-9)
    y = res.state_end.y
    q, qd, _ = to_cartesian(run.tree, run.a["dpar"], np.array([res.state_end.t]), run.to_internal(y)[None, :])
    nq = y.size // 2
    assert np.max(np.abs(q[0] - y[:nq])) < 1e-12
    assert np.max(np.abs(qd[0] - y[nq:])) < 1e-9  # velocities ~0.1-1 m/s, rad/s: 1e-9 relative


def test_tree_same_trajectory_short_window(six):
    """Over the first 2 ms both kernels at tight tolerances follow the same trajectory."""
    n = 0.004  # cycles: 2 ms
    a = simulate(six, n, settle_cycles=0, fast=False, rtol=1e-10, atol=1e-14)
    b = simulate(six, n, settle_cycles=0, rtol=1e-10, atol=1e-14)
    assert b.extra["kernel"] == "tree"
    t = np.linspace(a.t[0], a.t[-1], 50)
    for k in range(a.q.shape[1]):
        qa = np.interp(t, a.t, a.q[:, k])
        qb = np.interp(t, b.t, b.q[:, k])
        # positions 1e-11 m (5e-7 of the clearance), angles 1e-9 rad: linear interpolation between the two
        # kernels' different step sequences limits the comparison (measured 3e-12 m, 2e-10 rad)
        assert np.max(np.abs(qa - qb)) < (1e-9 if k % 3 == 2 else 1e-11)
    for ja, jb in zip(a.joints, b.joints):
        fa = np.interp(t, a.t, ja.force_normal)
        fb = np.interp(t, b.t, jb.force_normal)
        assert np.max(np.abs(fa - fb)) < 1e-4 * np.max(fa)  # measured 5e-5: interpolated force pulses


def test_tree_cycle_statistics_match_a_tight_reference(six):
    """Half a cycle from a settled state: the tree kernel at the default tolerance against both kernels at rtol 1e-9.

    The two tight references agree in mean force to 7e-7 (same equations, integration error ~1e-7): 2e-5; in max
    penetration to 2e-5 (a maximum over the steps depends on where the steps fall): 1e-4. The default tolerance
    against them: mean force 2e-4 and max penetration 2e-3 relative in the measurements (the Cartesian kernel at the
    same tolerance over two cycles: 4e-5-1e-4 and 1.4e-3; a 1-ulp nudge of an angle moves them by 1e-6 and 2e-4:
    this contact does not rattle, so the nudge scatter is below the integration error of either kernel): 1e-3, 5e-3.
    The wear the two tight runs deposit (jointwear.wear.history.cycle_wear): the worn volume, an integral like the mean
    force, to 2e-5 (measured 1.3e-6); the deepest cell of bearing and journal, a maximum like the penetration, over
    the 720-cell grid, to 1e-3 (measured 8e-5 and 2e-4)."""
    st = simulate(six, 0.0, settle_cycles=1).state_end
    d = simulate(six, 0.5, settle_cycles=0, state0=st)
    rt = simulate(six, 0.5, settle_cycles=0, state0=st, rtol=1e-9, atol=1e-12)
    rc = simulate(six, 0.5, settle_cycles=0, state0=st, rtol=1e-9, atol=1e-12, fast=False)
    assert d.extra["kernel"] == rt.extra["kernel"] == "tree" and rc.extra["kernel"] == "cartesian"
    for jd, jt, jc in zip(d.joints, rt.joints, rc.joints):
        assert jt.mean_force == pytest.approx(jc.mean_force, rel=2e-5)
        assert jt.penetration.max() == pytest.approx(jc.penetration.max(), rel=1e-4)
        assert jd.mean_force == pytest.approx(jt.mean_force, rel=1e-3)
        assert jd.penetration.max() == pytest.approx(jt.penetration.max(), rel=5e-3)
        assert jd.n_impacts == jt.n_impacts == jc.n_impacts
        wt, wc = cycle_wear(jt, WearSettings(), 1.0), cycle_wear(jc, WearSettings(), 1.0)
        assert wt.volume_bearing == pytest.approx(wc.volume_bearing, rel=2e-5)
        assert wt.bearing.max() == pytest.approx(wc.bearing.max(), rel=1e-3)
        assert wt.journal.max() == pytest.approx(wc.journal.max(), rel=1e-3)


@pytest.mark.parametrize("which", ["six_bar", "six_bar_three_clearances"])
def test_specialised_loop_equals_general_evaluation(six, which):
    """The loop specialised to the linkage's shape (simulate's default for it) records, at each accepted step, the
    accelerations and contact outputs of its last stage (y != yb, dt = h: the rotated cos/sin); one evaluation of the
    general kernel (kernel.rhs_tree) at that point gives the same.

    Tolerance: the same equations, with the positions rounded along another path (rotated cos/sin against fresh ones,
    the mass matrix factorised leaves first against a dense L D L^T): ~2e-17 m in the eccentricity, 1e-9 of the
    20-30 nm penetrations of the six-bar, 1.5e-9 of its contact forces (K delta^1.5). The contact outputs: 1e-8 of
    each one's largest value over the record (measured 1.2e-9). The accelerations: sums of contact-force terms that
    cancel to a net up to ~20 times smaller, so 1e-7 of the largest one (measured 2.1e-8 on the six-bar, 2.2e-8 with
    three clearances, 2e-10 on the sliders). A wrong term (a sign, a lever, a Coriolis term) moves them by 1e-3 or
    more. The slider linkages of test_tree_slider cover the generated slide (its Coriolis term on the turning guide, a
    revolute body hung from a sliding one).
    """
    loop_acc, loop_out, acc, out = loop_against_evaluation(six if which == "six_bar" else six_bar_three_clearances(),
                                                           0.01)
    assert np.all(np.abs(loop_acc - acc) <= 1e-7 * np.abs(acc).max())
    scale = np.abs(out).max(axis=(0, 1))
    assert np.all(np.abs(loop_out - out) <= 1e-8 * scale)


def test_generated_module_is_cached_per_shape(six, tmp_path, monkeypatch):
    """One module per shape, written once; another shape gets another file."""
    monkeypatch.setenv("JOINTWEAR_KERNEL_CACHE", str(tmp_path))
    monkeypatch.setattr(G, "_BY_KEY", {})
    monkeypatch.setattr(G, "_LOADED", {})
    a = six.kernel_arrays()
    lay = tree_layout(a)
    m1 = G.specialised_module(lay, a["dpar"].shape[0], a["cint"])
    assert G.specialised_module(lay, a["dpar"].shape[0], a["cint"]) is m1
    assert [p.name for p in tmp_path.glob("*.py")] == [m1.__name__ + ".py"]
    src = G.rhs_source(G.shape_key(lay, a["dpar"].shape[0], a["cint"]))
    assert "jint[" not in src and "mm[" not in src  # no table walks, no dense matrix: all literal
    three = six_bar_three_clearances().kernel_arrays()
    key3 = G.shape_key(tree_layout(three), three["dpar"].shape[0], three["cint"])
    assert key3 != G.shape_key(lay, a["dpar"].shape[0], a["cint"])
