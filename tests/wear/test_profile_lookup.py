"""The worn-profile lookup of the contact search (mechanism.kernel.profile_at): one stencil gives the value and
the slope of the periodic Catmull-Rom interpolation that the contact normal follows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointwear.mechanism.kernel import profile_at

N = 72


@pytest.fixture
def prof():
    rng = np.random.default_rng(3)
    p = np.zeros((1, 2, N))
    p[0, 0] = 1e-5 * (1.0 + np.cos(np.arange(N) * 2 * math.pi / N)) + 1e-7 * rng.random(N)
    p[0, 1] = 2e-6 * rng.random(N)
    return p


def test_values_at_the_grid_points_are_the_profile(prof):
    # interpolation through the data: exact at the nodes (t = 0 gives p1), to rounding
    for side in (0, 1):
        for i in range(N):
            h, _ = profile_at(prof, 0, side, N, 2 * math.pi * i / N)
            assert h == pytest.approx(prof[0, side, i], rel=1e-12, abs=1e-20)


def test_slope_is_the_derivative_of_the_value(prof):
    # central difference of a cubic inside a cell: error (step^2 / 6) |h'''|, with h''' bounded by
    # 3 * 4 max|p| / cell^3 for this stencil; step = cell / 1000 puts it below 1e-5 of the slope's scale
    cell = 2 * math.pi / N
    eps = cell / 1000
    scale = np.abs(prof).max() / cell
    for ang in np.linspace(-7.0, 7.0, 301):
        # stay inside one cell so that the difference does not straddle a node (the slope is only C0 there)
        x = (ang / cell) % 1.0
        if x < 2e-3 or x > 1 - 2e-3:
            continue
        _, s = profile_at(prof, 0, 0, N, ang)
        hp, _ = profile_at(prof, 0, 0, N, ang + eps)
        hm, _ = profile_at(prof, 0, 0, N, ang - eps)
        assert s == pytest.approx((hp - hm) / (2 * eps), abs=1e-5 * scale)


def test_slope_is_continuous_across_a_node(prof):
    # C1: the slope from both sides of a node agrees (Catmull-Rom tangents (p_{i+1} - p_{i-1}) / 2 per cell); 1e-12 rad
    # from the node the slope moves by |h''| 1e-12, far below rel=1e-6 of it
    cell = 2 * math.pi / N
    for i in (0, 5, N - 1):
        _, left = profile_at(prof, 0, 0, N, i * cell - 1e-12)
        _, right = profile_at(prof, 0, 0, N, i * cell + 1e-12)
        expected = (prof[0, 0, (i + 1) % N] - prof[0, 0, i - 1]) / (2 * cell)
        assert left == pytest.approx(expected, rel=1e-6)
        assert right == pytest.approx(expected, rel=1e-6)


def test_round_bore_is_exact():
    p = np.full((1, 2, N), 3e-6)
    for ang in (-1.0, 0.0, 0.3, 6.5):
        h, s = profile_at(p, 0, 0, N, ang)
        assert h == pytest.approx(3e-6, rel=1e-14) and abs(s) < 1e-18
