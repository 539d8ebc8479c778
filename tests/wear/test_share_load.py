"""kernels.share_load against its definition evaluated by brute force (full half-circle scans, the same arithmetic
in the same order), on round, conformal, narrow-pocket and rough bores: the windows that let the kernel skip cells
(the cap walk for the support point, the edge and neighbour windows for the overlaps, the bounded runs) must not
change a single share."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointwear.contact.envelope import admissible_set
from jointwear.wear.kernels import grid_directions, share_load

TWO_PI = 2.0 * math.pi


def brute_force(bins, c_bore, r_adm, cs, sn, r_b0, width):
    n = c_bore.size
    delta = TWO_PI / n
    q = n // 4
    wear = np.zeros(n)
    gcell = np.zeros(n)
    vol = 0.0
    for c in range(n):
        acc_v = bins[0, c]
        if not acc_v > 0.0:
            continue
        cm, sm = bins[1, c], bins[2, c]
        nm = math.sqrt(cm * cm + sm * sm)
        cm, sm = cm / nm, sm / nm
        dh = bins[3, c] / acc_v
        kbest, best = c, -1e300
        for d in range(-q, q + 1):  # the first max over the half circle
            k = (c + d) % n
            v = r_adm[k] * (cs[k] * cm + sn[k] * sm)
            if v > best:
                best, kbest = v, k
        ex = r_adm[kbest] * cs[kbest] + dh * cm
        ey = r_adm[kbest] * sn[kbest] + dh * sm
        cells, wproj = [], 0.0
        for d in range(-q, q + 1):
            k = (kbest + d) % n
            a = cs[k] * cm + sn[k] * sm
            o = ex * cs[k] + ey * sn[k] - c_bore[k]
            if o > 0.0 and a > 0.1:
                cells.append((k, o))
                wproj += o * a
        if not wproj > 0.0:
            wear[c] += acc_v / (width * r_b0 * delta)
            vol += acc_v
            continue
        scale = acc_v / wproj
        for k, o in cells:
            wear[k] += scale * o / (width * r_b0 * delta)
            gcell[k] += scale / (width * r_b0 * delta)
            vol += scale * o
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


@pytest.mark.parametrize("n", [180, 720])
def test_share_load_equals_its_definition(n):
    cs, sn = np.empty(n), np.empty(n)
    grid_directions(cs, sn)
    for name, c in bores(n):
        r_adm, r_idx = np.empty(n), np.empty(n, dtype=np.int64)
        admissible_set(c, r_adm, r_idx)
        bins = load_bins(n, seed=n)
        out = np.zeros(n)
        vol, g = share_load(bins, c, r_adm, r_idx, cs, sn, 5e-3, 1e-2, out)
        ref, ref_vol, ref_g = brute_force(bins, c, r_adm, cs, sn, 5e-3, 1e-2)
        # the same cells in the same order with the same arithmetic: equal to the last bit
        assert np.array_equal(out, ref), name
        assert vol == ref_vol and g == ref_g, name
        assert np.count_nonzero(out) > 0
