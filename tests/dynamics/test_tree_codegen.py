"""The tree kernel specialised per linkage shape (jointwear.mechanism.tree_codegen), which simulate runs for a tree
linkage, against the general tree kernel (kernel.rhs_tree). Its cycle statistics against the Cartesian kernel:
test_tree_kernel."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_tree_slider import MODELS as SLIDER_MODELS

from jointwear.config import config_from_dict, load_config
from jointwear.mechanism import build_model
from jointwear.mechanism import kernel as K
from jointwear.mechanism import tree_codegen as G
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.simulate import Runner
from jointwear.mechanism.tree import tree_layout

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


def loop_against_evaluation(model, n_cycles: float):
    """Run the loop simulate picks from the assembled start over n_cycles, recording every accepted step, then evaluate
    the equations once at each recorded point (Runner.eval: the general kernel at its base point, dt = 0), the
    contact memory replayed from the record as the loop's acceptance updates it (kernel.accept_point).

    Returns the loop's accelerations and contact outputs (from its last stage: y != yb, dt = h) and the evaluation's,
    as (steps, ny / 2) and (steps, joints, outputs) arrays."""
    s = model.settings
    run = Runner(model, None, s.rtol, s.atol)
    assert run.mode == 2
    st = initial_state(model)
    y = run.to_internal(st.y)
    cstate = np.array(st.cstate, dtype=float)
    run.a["cstate"][:] = cstate
    run.eval(st.t, y)
    rec = run.buffers(100_000)
    counters = np.zeros(4, dtype=np.int64)
    run.run(st.t, y, st.t + n_cycles * model.period, 1e-7, model.period / 200, -math.inf, rec, 100_000, counters)
    n = int(counters[0])
    assert counters[3] == 0 and n > 10
    loop_acc, loop_out = rec["rec_acc"][:n].copy(), np.moveaxis(rec["rec_c"][:, :, :n], 2, 0).copy()
    v0min = run.a["cpar"][:, K.C_V0MIN]
    acc, out = np.empty_like(loop_acc), np.empty_like(loop_out)
    for i in range(n):
        touching = loop_out[i, :, K.O_DELTA] > 0.0
        onset = touching & (cstate[:, K.S_INC] < 0.5)
        cstate[onset, K.S_V0] = np.maximum(loop_out[i, onset, K.O_VN], v0min[onset])
        cstate[:, K.S_INC] = touching
        run.a["cstate"][:] = cstate
        run.eval(rec["rec_t"][i], rec["rec_y"][i])
        acc[i], out[i] = run.ks[0][run.ny // 2:], run.w["cout"]
    return loop_acc, loop_out, acc, out


SLIDERS = ["flores", "line_owned_by_the_slider", "rod_hangs_from_the_slider", "turning_guide"]  # test_tree_slider


@pytest.mark.parametrize("which", ["six_bar", "six_bar_three_clearances", *SLIDERS])
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
    models = {"six_bar": lambda: six, "six_bar_three_clearances": six_bar_three_clearances, **SLIDER_MODELS}
    loop_acc, loop_out, acc, out = loop_against_evaluation(models[which](), 0.01)
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
