"""The tree kernel specialised per linkage shape (jointwear.mechanism.tree_codegen) against the general tree kernel
(kernel.rhs_tree and kernel.integrate_tree), which it replaces in simulate."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from test_tree_slider import MODELS as SLIDER_MODELS

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism import build_model, simulate
from jointwear.mechanism import kernel as K
from jointwear.mechanism import tree_codegen as G
from jointwear.mechanism.simulate import Runner
from jointwear.mechanism.tree import tree_layout
from jointwear.wear import WearSettings
from jointwear.wear.history import cycle_wear

SIX = "watt_six_bar_two_clearances"


def six_bar_three_clearances():
    """The six-bar with a third clearance joint at the output's ground pivot F (the output then moves freely between
    its two clearance joints: a floating body in the tree), as in test_tree_kernel."""
    data = load_config(SIX).model_dump(mode="json")
    third = {**data["clearance_joints"][1], "name": "F", "joint": "F", "bearing_body": "ground", "journal_body": "output"}
    data["clearance_joints"] = [*data["clearance_joints"], third]
    return build_model(config_from_dict(data))


@pytest.fixture(scope="module")
def six():
    return build_model(load_config(SIX))


@njit(error_model="numpy")
def _general(t, dt, y, yb, dy, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, kin, cb, sb, cacc,
             jt, mm, gq, f, cout):
    K.tree_base(t - dt, yb, jint, dpar, kin, cb, sb)
    K.rhs_tree(t, dt, y, yb, dy, 0, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, kin, cb, sb,
               cacc, jt, mm, gq, f, cout)


def _specialised(rhs_spec):
    @njit(error_model="numpy")
    def run(t, dt, y, yb, dy, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, kin, cb, sb, cacc,
            jt, mm, gq, f, cout):
        K.tree_base(t - dt, yb, jint, dpar, kin, cb, sb)
        rhs_spec(t, dt, y, yb, dy, 0, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, kin, cb, sb,
                 cacc, jt, mm, gq, f, cout)

    return run


SLIDERS = ["flores", "line_owned_by_the_slider", "rod_hangs_from_the_slider", "turning_guide"]  # test_tree_slider


@pytest.mark.parametrize("which", ["six_bar", "six_bar_three_clearances", *SLIDERS])
def test_specialised_rhs_equals_general(six, which):
    """Same accelerations and contact outputs as kernel.rhs_tree at states along a trajectory, at a stage (y != yb,
    dt > 0: the rotated cos/sin) and at the step's base point.

    Tolerance: the same equations, the mass matrix factorised in another order (leaves first instead of a dense
    L D L^T) and sums regrouped: rounding (1.1e-16) amplified by the mass matrix's condition (~1e3-1e4, angle rows
    scaled by the ~50 mm links): 1e-11 of the largest component; measured ~1e-16. The slider linkages of
    test_tree_slider cover the generated slide (its Coriolis term on the turning guide, a revolute body hung from a
    sliding one)."""
    models = {"six_bar": lambda: six, "six_bar_three_clearances": six_bar_three_clearances, **SLIDER_MODELS}
    model = models[which]()
    res = simulate(model, 0.01, settle_cycles=0)
    run = Runner(model, None, 1e-6, 1e-9)
    assert res.extra["kernel"] == "tree" and run.mode == 2
    a = run.a
    mod = G.specialised_module(run.tree, a["dpar"].shape[0], a["cint"])
    spec = _specialised(mod.rhs_spec)
    args = run._args()
    tables, work = args[0:11], args[12:21]
    run.a["cstate"][:] = res.state_end.cstate
    checked = 0
    for i in np.linspace(0, res.t.size - 2, 5).astype(int):
        yb = run.to_internal(np.concatenate([res.q[i], res.qd[i]]))
        y1 = run.to_internal(np.concatenate([res.q[i + 1], res.qd[i + 1]]))
        for y, dt in ((yb, 0.0), (y1, res.t[i + 1] - res.t[i])):
            t = res.t[i] + dt
            d_gen, d_spec = np.zeros((1, y.size)), np.zeros((1, y.size))
            _general(t, dt, y, yb, d_gen, *tables, *work)
            c_gen = work[-1].copy()
            work[-1][:] = 0.0
            spec(t, dt, y, yb, d_spec, *tables, *work)
            c_spec = work[-1].copy()
            scale = np.abs(d_gen).max()
            assert np.all(np.abs(d_spec - d_gen) <= 1e-11 * scale)
            cscale = np.abs(c_gen).max(axis=0) + 1e-300
            assert np.all(np.abs(c_spec - c_gen) <= 1e-11 * cscale)
            checked += 1
    assert checked == 10


def test_specialised_loop_cycle_matches_general(six):
    """One cycle from a settled state on the specialised loop (simulate's default) and on the general one
    (kernel.integrate_tree with kernel.rhs_tree): mean and peak contact force and one cycle's wear depth of each joint.

    Tolerance: the two differ by rounding in each evaluation, which the step control turns into different step
    sequences, as a 1-ulp nudge of an angle of the start state does: that nudge moves the mean force by up to 4e-5,
    the peak force by up to 2.5e-4 and the deepest cell of a cycle's wear by up to 1.5e-4
    (benchmarks/results/dynamics.json, six_bar_accuracy and six_bar_specialised; the specialised loop against the
    general one: 1.4e-6, 2e-4, 1.9e-4): 5e-4 relative."""
    st = simulate(six, 0.0).state_end
    spec = simulate(six, 1, settle_cycles=0, state0=st)
    assert spec.extra["kernel"] == "tree"

    orig = Runner.__init__

    def general_init(self, *args, **kw):
        orig(self, *args, **kw)
        self.integrate = K.integrate_tree

    Runner.__init__ = general_init
    try:
        gen = simulate(six, 1, settle_cycles=0, state0=st)
    finally:
        Runner.__init__ = orig
    ws = WearSettings()
    for tg, ts in zip(gen.joints, spec.joints):
        assert ts.mean_force == pytest.approx(tg.mean_force, rel=5e-4)
        assert ts.force_normal.max() == pytest.approx(tg.force_normal.max(), rel=5e-4)
        wg, wsp = cycle_wear(tg, ws, 1.0), cycle_wear(ts, ws, 1.0)
        assert wsp.bearing.max() == pytest.approx(wg.bearing.max(), rel=5e-4)
        assert wsp.volume_bearing == pytest.approx(wg.volume_bearing, rel=5e-4)


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
