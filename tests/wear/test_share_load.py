"""kernels.share_load against its definition evaluated by brute force (the support corner of the admissible set by
enumerating its vertices, the overlaps over every cell), on round, conformal, narrow-pocket and rough bores: the hull
walk and the window of cells the kernel scans must not change the shares."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointwear.wear.kernels import grid_directions, share_load

TWO_PI = 2.0 * math.pi


def support_corner(c, cs, sn, m):
    """The point of S = {e : e . u_k <= c_k} farthest along m, by enumerating S's vertices: the feasible
    intersections of two edge lines (each with its pair of cells)."""
    n = c.size
    i, j = np.triu_indices(n, 1)
    det = cs[i] * sn[j] - sn[i] * cs[j]
    ok = np.abs(det) > 1e-9
    i, j, det = i[ok], j[ok], det[ok]
    x = (c[i] * sn[j] - c[j] * sn[i]) / det
    y = (cs[i] * c[j] - cs[j] * c[i]) / det
    feasible = np.all(np.outer(x, cs) + np.outer(y, sn) <= c * (1.0 + 1e-12), axis=1)
    x, y = x[feasible], y[feasible]
    k = np.argmax(x * m[0] + y * m[1])
    return x[k], y[k]


def brute_force(bins, c_bore, cs, sn, r_b0, width):
    n = c_bore.size
    delta = TWO_PI / n
    wear = np.zeros(n)
    gcell = np.zeros(n)
    vol = 0.0
    for c in range(n):
        acc_v = bins[0, c]
        if not acc_v > 0.0:
            continue
        m = bins[1:3, c] / math.hypot(*bins[1:3, c])
        dh = bins[3, c] / acc_v
        xs, ys = support_corner(c_bore, cs, sn, m)
        ex, ey = xs + dh * m[0], ys + dh * m[1]
        o = ex * cs + ey * sn - c_bore
        f = cs * m[0] + sn * m[1]
        on = (o > 0.0) & (f > 0.1)
        wproj = float(np.sum(o[on] * f[on]))
        if not wproj > 0.0:
            wear[c] += acc_v / (width * r_b0 * delta)
            vol += acc_v
            continue
        scale = acc_v / wproj
        wear[on] += scale * o[on] / (width * r_b0 * delta)
        gcell[on] += scale / (width * r_b0 * delta)
        vol += scale * float(np.sum(o[on]))
    return wear, vol, gcell.max()


def bores(n):
    th = TWO_PI * np.arange(n) / n
    rng = np.random.default_rng(11)
    c0 = 2e-6
    ang = lambda a: np.angle(np.exp(1j * (th - a)))  # noqa: E731
    yield "round", np.full(n, c0)
    e0 = 27e-6  # a pocket worn to the journal's own shape (the journal displaced by e0 along 2 rad)
    yield "conformal", np.maximum(c0, e0 * np.cos(th - 2.0))
    yield "narrow pocket", c0 + 25e-6 * np.exp(-0.5 * (ang(1.0) / 0.3) ** 2)
    yield "two pockets", c0 + 10e-6 * np.exp(-0.5 * (ang(1.0) / 0.5) ** 2) + 6e-6 * np.exp(-0.5 * (ang(4.0) / 0.2) ** 2)
    yield "rough", c0 * (1.0 + 0.3 * rng.random(n))


def load_bins(n, seed):
    """Loads gathered by direction as gather_directions leaves them: per cell its Archard volume, the volume-weighted
    sums of cos m and sin m (m within the cell) and of delta_H; loads over 3/4 of the circle, delta_H 1e-12-5e-8 m."""
    rng = np.random.default_rng(seed)
    delta = TWO_PI / n
    bins = np.zeros((4, n))
    for c in range(n):
        if rng.random() < 0.25:
            continue
        v = rng.lognormal(-20.0, 1.0)
        m = c * delta + rng.uniform(-0.5, 0.5) * delta
        bins[:, c] = v, v * math.cos(m), v * math.sin(m), v * 10.0 ** rng.uniform(-12.0, -7.3)
    return bins


@pytest.mark.parametrize("n", [90, 180])
def test_share_load_equals_its_definition(n):
    cs, sn = np.empty(n), np.empty(n)
    grid_directions(cs, sn)
    for name, c in bores(n):
        bins = load_bins(n, seed=n)
        out = np.zeros(n)
        vol, g = share_load(bins, c, cs, sn, 5e-3, 1e-2, out)
        ref, ref_vol, ref_g = brute_force(bins, c, cs, sn, 5e-3, 1e-2)
        # the overlaps are differences of the journal's position and the bore of up to 1e4 times their size (27 um
        # against ~1e-9 m): rounding in the corner (two edge lines a grid cell apart) reaches them at ~1e-6
        np.testing.assert_allclose(out, ref, rtol=1e-6, atol=1e-9 * ref.max(), err_msg=name)
        assert vol == pytest.approx(ref_vol, rel=1e-6) and g == pytest.approx(ref_g, rel=1e-6), name
        assert np.count_nonzero(out) > 0


def test_share_load_in_a_conformal_pocket_spreads_as_cos():
    """A pocket worn to the journal's shape (all its edges through one corner e0): the journal at e0 + delta_H m
    overlaps every pocket cell by delta_H cos(theta_k - theta_m), the conformal bearing's pressure."""
    n = 720
    cs, sn = np.empty(n), np.empty(n)
    grid_directions(cs, sn)
    th = TWO_PI * np.arange(n) / n
    e0 = 27e-6
    c = np.maximum(2e-6, e0 * np.cos(th - 2.0))
    bins = np.zeros((4, n))
    k = int(round(2.1 / (TWO_PI / n)))
    m = 2.1 + 0.1 * TWO_PI / n
    v, dh = 1e-18, 1e-9
    bins[:, k] = v, v * math.cos(m), v * math.sin(m), v * dh
    out = np.zeros(n)
    share_load(bins, c, cs, sn, 5e-3, 1e-2, out)
    f = np.cos(th - m)
    pocket = (np.cos(th - 2.0) * e0 > 2e-6 + 1e-12) & (f > 0.1)
    expect = np.where(pocket, dh * f, 0.0)
    expect *= v / np.sum(expect * f) / (1e-2 * 5e-3 * TWO_PI / n)
    # the corner of 160 cells' edges: each cell's overlap dh cos to rounding of the 27 um positions
    np.testing.assert_allclose(out, expect, rtol=1e-5, atol=1e-6 * expect.max())


def test_merged_loads_keep_their_sums_and_mean_directions():
    """ConformalShare.merged: each group of cells keeps its Archard volume, its volume-weighted direction sums and
    delta_H sum (exact sums), laid at the cell of its mean direction, so the sharing sees the same loads coarser."""
    from jointwear.wear.cycle import ConformalShare

    n = 720
    bins = load_bins(n, seed=3)
    share = ConformalShare(bins, 2e-6, 5e-3, 1e-2)
    merged = share.merged(4)
    np.testing.assert_allclose(merged.bins.sum(axis=1), bins.sum(axis=1), rtol=1e-12)
    cells = np.flatnonzero(merged.bins[0] > 0)
    assert cells.size == np.count_nonzero(bins[0].reshape(-1, 4).sum(axis=1) > 0)
    ang = np.arctan2(merged.bins[2, cells], merged.bins[1, cells]) % TWO_PI
    # each merged load sits in the cell of its own mean direction (half a cell at most)
    assert np.all(np.abs(np.angle(np.exp(1j * (ang - cells * TWO_PI / n)))) <= 0.5 * TWO_PI / n + 1e-12)


def test_merged_loads_on_a_grid_the_factor_does_not_divide():
    """n = 721 cells in groups of 4: the last group has one cell; every group keeps its sums, and each merged load
    sits in the cell of its own mean direction, as the direct per-group definition has it."""
    from jointwear.wear.cycle import ConformalShare

    n, f = 721, 4
    bins = load_bins(n, seed=5)
    merged = ConformalShare(bins, 2e-6, 5e-3, 1e-2).merged(f).bins
    expect = np.zeros_like(bins)
    for k0 in range(0, n, f):
        tot = bins[:, k0:k0 + f].sum(axis=1)
        if tot[0] > 0.0:
            k = int(np.floor((np.arctan2(tot[2], tot[1]) % TWO_PI) / (TWO_PI / n) + 0.5)) % n
            expect[:, k] += tot
    np.testing.assert_array_equal(merged, expect)


@pytest.mark.parametrize("n, smoothing_deg", [(360, 3.0), (360, 0.0), (72, 3.0)])
def test_conformal_share_lay_is_its_loop(n, smoothing_deg):
    """ConformalShare.lay (compiled; FFT smoothing in Python where the kernel is too wide for real-space taps, as on
    the 72-cell grid) equals its definition written as a loop: each sub-step shares the loads over the bore laid so
    far, max(S wb, 0), and lays max(S rate, 0) dt, S the FFT smoothing. Few sub-steps, so the shares' rounding
    (1e-12 of a cell's depth, test_share_load_equals_its_definition) is not amplified (benchmarks/wear.py
    profile_deposit: 1e-13 grows to a few % over a block's 200 sub-steps)."""
    from jointwear.wear.cycle import ConformalShare
    from jointwear.wear.kernels import gaussian_multiplier

    def smooth(p):
        if smoothing_deg <= 0.0:
            return p
        return np.fft.irfft(np.fft.rfft(p) * gaussian_multiplier(n, smoothing_deg), n)

    share = ConformalShare(load_bins(n, seed=3) * 2e-6, 2e-6, 5e-3, 1e-2)  # each sub-step lays ~1 um
    th = TWO_PI * np.arange(n) / n
    wb0 = 25e-6 * np.maximum(np.cos(th - 2.0), 0.0) ** 3  # a worn pocket
    wb = wb0.copy()
    dt, steps = 100.0, 4
    vol = share.lay(wb, steps, dt, smoothing_deg)
    ref, ref_vol = wb0.copy(), 0.0
    for _ in range(steps):
        rate, vrate, _ = share(np.maximum(smooth(ref), 0.0))
        ref += np.maximum(smooth(rate), 0.0) * dt
        ref_vol += vrate * dt
    assert not np.array_equal(ref, wb0)
    # the two smoothings differ by 1e-15 (test_kernels.py), and the overlaps are differences of numbers up to 1e4
    # times larger (above), growing over the sub-steps: 4e-10 of the laid depth on the 360-cell grid
    np.testing.assert_allclose(wb - wb0, ref - wb0, rtol=0.0, atol=1e-8 * (ref - wb0).max())
    assert vol == pytest.approx(ref_vol, rel=1e-8)
