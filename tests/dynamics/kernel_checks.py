"""Checks shared by the kernel tests: one kernel's accelerations against the Cartesian kernel's at the same states."""

from __future__ import annotations

import numpy as np

from jointwear.mechanism import kernel as K
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
