"""Checks shared by the kernel tests: one kernel's accelerations against the Cartesian kernel's at the same states, and
the loop specialised to a linkage's shape against one evaluation of the general tree kernel."""

from __future__ import annotations

import math

import numpy as np

from jointwear.mechanism import kernel as K
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.simulate import Runner
from jointwear.mechanism.tree import to_cartesian


def assert_tree_accelerations_match_cartesian(model, res, n_states: int, force_atol: float) -> None:
    """At ``n_states`` states of the tree-kernel run ``res`` (mapped to Cartesian through the tree), the Cartesian
    kernel's accelerations equal the tree's to 1e-9 of the largest, and the contact forces to 1e-9 relative (+
    ``force_atol`` N). The tolerance's derivation is in test_tree_kernel's test of the same name."""
    cart = Runner(model, None, 1e-6, 1e-9, fast=False)
    tree = Runner(model, None, 1e-6, 1e-9)
    cart.a["cstate"][:] = res.state_end.cstate
    tree.a["cstate"][:] = res.state_end.cstate
    nq = res.q.shape[1]
    for i in np.linspace(0, res.t.size - 1, n_states).astype(int):
        y_tree = tree.to_internal(np.concatenate([res.q[i], res.qd[i]]))
        tree.eval(res.t[i], y_tree)
        q, qd, qdd = to_cartesian(tree.tree, tree.a["dpar"], np.array([res.t[i]]), y_tree[None, :],
                                  tree.ks[0][None, tree.ny // 2:])
        cart.eval(res.t[i], np.concatenate([q[0], qd[0]]))
        scale = np.max(np.abs(qdd[0]))
        assert np.max(np.abs(cart.ks[0][nq:] - qdd[0])) < 1e-9 * scale
        np.testing.assert_allclose(tree.w["cout"][:, K.O_FN], cart.w["cout"][:, K.O_FN], rtol=1e-9, atol=force_atol)


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
