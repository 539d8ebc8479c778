"""contact.envelope.admissible_set against its definition evaluated by brute force: min over the half circle of
c_k / cos(theta_k - theta_i), on bores with pockets, several pockets, noise and a round bore."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointwear.contact.envelope import admissible_radius, admissible_set, rounded_envelope

TWO_PI = 2.0 * math.pi


def brute_force(c):
    n = c.size
    delta = TWO_PI / n
    q = int(math.floor((0.5 * math.pi - 1e-9) / delta))
    out = np.empty(n)
    idx = np.empty(n, dtype=np.int64)
    for i in range(n):
        best, arg = c[i], i
        for d in range(1, q + 1):
            inv = 1.0 / math.cos(d * delta)
            for k in ((i + d) % n, (i - d) % n):
                v = c[k] * inv
                if v < best:
                    best, arg = v, k
        out[i], idx[i] = best, arg
    return out, idx


def bores(n):
    th = TWO_PI * np.arange(n) / n
    rng = np.random.default_rng(7)
    c0 = 2e-6
    ang = lambda a: np.angle(np.exp(1j * (th - a)))  # noqa: E731
    yield np.full(n, c0)
    yield c0 + 30e-6 * np.maximum(np.cos(th - 2.0), 0.0) ** 2  # a conformal cap
    yield c0 + 25e-6 * np.exp(-0.5 * (ang(1.0) / 0.3) ** 2)  # a pocket narrower than the journal
    yield c0 + 10e-6 * np.exp(-0.5 * (ang(1.0) / 0.5) ** 2) + 6e-6 * np.exp(-0.5 * (ang(4.0) / 0.2) ** 2)
    yield c0 * (1.0 + 0.3 * rng.random(n))  # rough
    yield c0 + 1e-5 * rng.random(n)  # very rough: many corners


@pytest.mark.parametrize("n", [180, 720])
def test_admissible_set_is_the_minimum_over_the_half_circle(n):
    for c in bores(n):
        out, idx = np.empty(n), np.empty(n, dtype=np.int64)
        admissible_set(c, out, idx)
        ref, ref_idx = brute_force(c)
        # the same expression c_k / cos(d delta) at the same k: equal to the last bit; where two cells tie to
        # rounding the other may be picked, with a value equal to a few ulps
        np.testing.assert_allclose(out, ref, rtol=4e-16, atol=0)
        assert np.mean(idx == ref_idx) > 0.99


def polygon_distance_brute(r, px, py):
    """Distance from (px, py) to the polygon through r[j] (cos, sin)(2 pi j / n), over every edge."""
    n = r.size
    th = TWO_PI * np.arange(n) / n
    ax, ay = r * np.cos(th), r * np.sin(th)
    bx, by = np.roll(ax, -1) - ax, np.roll(ay, -1) - ay
    u = np.clip(((px - ax) * bx + (py - ay) * by) / (bx * bx + by * by), 0.0, 1.0)
    return float(np.min(np.hypot(px - ax - u * bx, py - ay - u * by)))


@pytest.mark.parametrize("n", [180, 720])
def test_rounded_envelope_keeps_rho_from_the_eroded_set(n):
    """rounded_envelope's t_i: the point t_i u_i lies at distance rho from S_rho (the admissible set of c - rho),
    to the 1e-6 rho its false position stops at; a round bore is unchanged."""
    for c in bores(n):
        rho = 0.2 * c.min()
        out = np.empty(n)
        rounded_envelope(c, rho, out)
        r_in = np.empty(n)
        admissible_radius(c - rho, r_in)
        th = TWO_PI * np.arange(n) / n
        dist = np.array([polygon_distance_brute(r_in, t * math.cos(a), t * math.sin(a)) for t, a in zip(out, th)])
        # the walk's answer against every edge; 1e-6 rho is the stopping tolerance, doubled for the last
        # false-position step
        np.testing.assert_allclose(dist, rho, rtol=0, atol=2e-6 * rho)
        if np.ptp(c) == 0.0:
            np.testing.assert_allclose(out, c, rtol=1e-12)
