"""Where a rigid round journal can go in a worn bore: the admissible set of journal-centre positions, its corners
rounded (profile mode's contact geometry; compiled helpers called once per geometry update).

A bore cell k at angle theta_k with local clearance c_k admits the journal centres e with e . u_k <= c_k; the
admissible set S is the intersection of these half-planes (convex). A journal resting in a pocket it has worn to
its own shape sits at a corner of S (it touches the whole worn arc at once). The contact search of the dynamics
measures the penetration along the centre line against the radial function of S; at a corner that function has a
cusp, the contact normal flips from one flank to the other, and the integrator chatters with ever smaller steps.
The dynamics is therefore given the radial function of S rounded with a radius rho: S' = (S eroded by rho) dilated
by rho, which equals S wherever S is smoother than rho (a round bore is unchanged) and replaces each corner by a
circular arc of radius rho.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

TWO_PI = 2.0 * math.pi


@njit(cache=True)
def edge_table(n):
    """cos and sin of the ends of the polygon edges i = -n .. 2n - 1 of an n-cell grid (rows: cos a, sin a,
    cos(a + d), sin(a + d) with a = i d, d = 2 pi / n, column i + n), computed once per polygon instead of per
    distance evaluation."""
    d = TWO_PI / n
    tab = np.empty((4, 3 * n))
    for c in range(3 * n):
        a0 = (c - n) * d
        tab[0, c] = math.cos(a0)
        tab[1, c] = math.sin(a0)
        tab[2, c] = math.cos(a0 + d)
        tab[3, c] = math.sin(a0 + d)
    return tab


@njit(cache=True)
def _edge_distance(r, tab, i, px, py):
    """Distance from (px, py) to edge i of the polygon through r[j] (cos, sin)(2 pi j / n) (tab: edge_table(n))."""
    n = r.shape[0]
    j0 = i % n
    j1 = (i + 1) % n
    ax = r[j0] * tab[0, i + n]
    ay = r[j0] * tab[1, i + n]
    bx = r[j1] * tab[2, i + n] - ax
    by = r[j1] * tab[3, i + n] - ay
    qx = px - ax
    qy = py - ay
    u = (qx * bx + qy * by) / (bx * bx + by * by)
    u = min(1.0, max(0.0, u))
    dx = qx - u * bx
    dy = qy - u * by
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=True)
def polygon_distance(r, tab, px, py):
    """Distance from an outside point to the convex polygon through r[j] u_j (walks from the point's own edge while
    the distance decreases: along the visible chain of a convex polygon it is unimodal). tab: edge_table(n)."""
    n = r.shape[0]
    ang = math.atan2(py, px) % TWO_PI
    i0 = int(ang / (TWO_PI / n)) % n
    best = _edge_distance(r, tab, i0, px, py)
    for step in (1, -1):
        i = i0
        for _ in range(n // 2):
            d = _edge_distance(r, tab, i + step, px, py)
            if d < best:
                best = d
                i += step
            else:
                break
    return best


@njit(cache=True)
def polar_hull(c, px, py, hull):
    """The cells whose half-planes e . u_k <= c_k bound the admissible set S (its edges), in angular order: the
    vertices of the convex hull of the polar dual points p_k = u_k / c_k (written to px, py; see polar_scan).
    Returns nh; hull[0 .. nh - 1] are the cells, hull[nh] = hull[0]. The corner of S between edges hull[t] and
    hull[t + 1] supports S along every direction between their normals."""
    n = c.shape[0]
    delta = TWO_PI / n
    for k in range(n):
        px[k] = math.cos(k * delta) / c[k]
        py[k] = math.sin(k * delta) / c[k]
    return polar_scan(px, py, int(np.argmin(c)), hull)


@njit(cache=True, nogil=True)
def polar_scan(px, py, k0, hull):
    """polar_hull's Graham scan of points p_k that come in angular order round the origin (which lies inside),
    starting at k0, a hull vertex (the p_k farthest from the origin). Returns nh as polar_hull."""
    n = px.shape[0]
    m = 0
    for j in range(n + 1):
        k = (k0 + j) % n
        while m >= 2:
            a = hull[m - 2]
            b = hull[m - 1]
            cr = (px[b] - px[a]) * (py[k] - py[a]) - (py[b] - py[a]) * (px[k] - px[a])
            if cr > 0.0:  # a left turn: b stays on the hull
                break
            m -= 1
        hull[m] = k
        m += 1
    return m - 1  # hull[m - 1] is k0 again


@njit(cache=True)
def admissible_set(c, out_c, out_idx):
    """Radial function of the admissible journal-centre set S = {e : e . u_k <= c_k} at the grid angles,
    out_c[i] = min_k c_k / cos(theta_k - theta_i) over |theta_k - theta_i| < 90 deg (first order in clearance /
    radius), and out_idx[i] the k that attains it (the bore point that touches).

    c (n,) is the local clearance c0 + h(theta_k): a journal whose centre is displaced by e along theta_i closes the
    gap c_k - e cos(theta_k - theta_i) first at that k. S is convex, so a wear pocket narrower than the journal is
    bridged at its flanks instead of being entered radially.

    The minimum is 1 / max_k (p_k . u_i) with p_k = u_k / c_k (the polar dual of S): the k that attains it is a
    vertex of the convex hull of the p_k, found for all n directions in O(n) (the p_k come in angular order round
    the origin, which lies inside, so a Graham scan gives the hull; the supporting vertex turns with the direction,
    so one pointer walks the hull once). A direct scan over the half circle costs O(n^2) on a deep pocket.
    """
    n = c.shape[0]
    delta = TWO_PI / n
    px = np.empty(n)
    py = np.empty(n)
    hull = np.empty(n + 1, dtype=np.int64)
    nh = polar_hull(c, px, py, hull)
    # the supporting vertex of direction 0: a scan of the hull once, then a pointer that only moves forward
    j = 0
    best = -1e300
    for t in range(nh):
        v = px[hull[t]]
        if v > best:
            best = v
            j = t
    for i in range(n):
        ci = math.cos(i * delta)
        si = math.sin(i * delta)
        cur = px[hull[j]] * ci + py[hull[j]] * si
        for _ in range(nh):
            jn = j + 1 if j + 1 < nh else 0
            nxt = px[hull[jn]] * ci + py[hull[jn]] * si
            if nxt > cur:
                j = jn
                cur = nxt
            else:
                break
        k = hull[j]
        d = k - i
        if d < 0:
            d = -d
        if d > n - d:
            d = n - d
        v = c[k] * (1.0 / math.cos(d * delta))
        if v < c[i]:
            out_c[i] = v
            out_idx[i] = k
        else:  # the direction's own cell (also on a tie, as a scan that starts there)
            out_c[i] = c[i]
            out_idx[i] = i


@njit(cache=True)
def admissible_radius(c, out):
    """The radial function of :func:`admissible_set` alone."""
    admissible_set(c, out, np.empty(c.shape[0], dtype=np.int64))


@njit(cache=True)
def rounded_envelope(c, rho, out):
    """Radial function (at the grid angles) of S' = (S eroded by rho) dilated by rho, S the admissible set of the
    local clearances c (n,): the largest t with dist(t u_i, S_rho) <= rho, S_rho the set of the clearances c - rho.
    Found by false position (Illinois) to 1e-6 of rho; where S_rho is locally round, t = r_rho + rho at once.
    rho must be < min(c)."""
    n = c.shape[0]
    r_in = np.empty(n)
    admissible_radius(c - rho, r_in)
    tab = edge_table(n)
    delta = TWO_PI / n
    tol = 1e-6 * rho
    for i in range(n):
        cx = math.cos(i * delta)
        sy = math.sin(i * delta)
        t = r_in[i] + rho
        f = polygon_distance(r_in, tab, t * cx, t * sy) - rho
        if abs(f) <= tol:
            out[i] = t
            continue
        lo, flo = r_in[i], -rho
        hi, fhi = t, f
        while fhi < 0.0:
            lo, flo = hi, fhi
            hi = hi + rho
            fhi = polygon_distance(r_in, tab, hi * cx, hi * sy) - rho
        side = 0
        mid = hi
        for _ in range(100):
            mid = (lo * fhi - hi * flo) / (fhi - flo)
            fm = polygon_distance(r_in, tab, mid * cx, mid * sy) - rho
            if abs(fm) <= tol or hi - lo <= tol:
                break
            if fm < 0.0:
                lo, flo = mid, fm
                if side == -1:
                    fhi *= 0.5
                side = -1
            else:
                hi, fhi = mid, fm
                if side == 1:
                    flo *= 0.5
                side = 1
        out[i] = mid
