"""The record buffers are pooled between simulate() calls: a result, or any array taken from it, must never be
overwritten by a later call, also when calls run in threads (the wear stage's lanes)."""

import importlib
import threading

import numpy as np
import pytest

from jointwear.config import load_config
from jointwear.mechanism import build_model, simulate

S = importlib.import_module("jointwear.mechanism.simulate")


@pytest.fixture(scope="module")
def model_and_state():
    model = build_model(load_config("jin2025_flapping_wing"))
    return model, simulate(model, 0.0, settle_cycles=1).state_end


def _snapshot(res):
    tr = res.joints[0]
    return [res.t.copy(), res.crank_angle.copy(), tr.force_normal.copy(), tr.theta_bearing.copy(), res.q.copy()]


def test_pool_reuses_free_buffers_only():
    shapes = (("rec_t", (2000,)), ("rec_c", (1, 15, 2000)))
    a = S._record_buffers(shapes)
    first = id(a)
    del a
    b = S._record_buffers(shapes)
    assert id(b) == first  # released: reused
    view = b["rec_c"][0, 3, :10]
    del b
    c = S._record_buffers(shapes)
    assert id(c) != first  # a view of it lives: not reused
    del c, view
    assert id(S._record_buffers(shapes)) == first


def test_kept_results_and_views_survive_later_calls(model_and_state):
    model, st = model_and_state
    a = simulate(model, 0.5, settle_cycles=0, state0=st)
    before = _snapshot(a)
    force_view = a.joints[0].force_normal
    force_copy = force_view.copy()
    # later calls start elsewhere (an overwrite would change the numbers, not rewrite the same ones)
    other = a.state_end
    for _ in range(3):
        other = simulate(model, 0.5, settle_cycles=0, state0=other).state_end
    for x, y in zip(before, _snapshot(a)):
        np.testing.assert_array_equal(x, y)
    del a
    for _ in range(3):
        other = simulate(model, 0.5, settle_cycles=0, state0=other).state_end
    np.testing.assert_array_equal(force_view, force_copy)


def test_threads_get_distinct_buffers(model_and_state):
    """Two threads simulating at once, from different states, give the same results as one after the other (the
    integrator releases the GIL, so the calls overlap)."""
    model, st = model_and_state
    starts = [st, simulate(model, 0.3, settle_cycles=0, state0=st).state_end]
    serial = [_snapshot(simulate(model, 0.5, settle_cycles=0, state0=s0)) for s0 in starts]
    out = [None, None]

    def work(i):
        out[i] = _snapshot(simulate(model, 0.5, settle_cycles=0, state0=starts[i]))

    for _ in range(3):
        threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        for ref, got in zip(serial, out):
            for x, y in zip(ref, got):
                np.testing.assert_array_equal(x, y)
