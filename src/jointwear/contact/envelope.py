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
def _edge_distance(r, i, px, py):
    """Distance from (px, py) to edge i of the polygon through r[j] (cos, sin)(2 pi j / n)."""
    n = r.shape[0]
    d = TWO_PI / n
    a0 = i * d
    j0 = i % n
    j1 = (i + 1) % n
    ax = r[j0] * math.cos(a0)
    ay = r[j0] * math.sin(a0)
    bx = r[j1] * math.cos(a0 + d) - ax
    by = r[j1] * math.sin(a0 + d) - ay
    qx = px - ax
    qy = py - ay
    u = (qx * bx + qy * by) / (bx * bx + by * by)
    u = min(1.0, max(0.0, u))
    dx = qx - u * bx
    dy = qy - u * by
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=True)
def polygon_distance(r, px, py):
    """Distance from an outside point to the convex polygon through r[j] u_j (walks from the point's own edge while
    the distance decreases: along the visible chain of a convex polygon it is unimodal)."""
    n = r.shape[0]
    ang = math.atan2(py, px) % TWO_PI
    i0 = int(ang / (TWO_PI / n)) % n
    best = _edge_distance(r, i0, px, py)
    for step in (1, -1):
        i = i0
        for _ in range(n // 2):
            d = _edge_distance(r, i + step, px, py)
            if d < best:
                best = d
                i += step
            else:
                break
    return best


@njit(cache=True)
def admissible_radius(c, out):
    """Radial function of S = {e : e . u_k <= c_k} at the grid angles: min_k c_k / cos(theta_k - theta_i) over
    |theta_k - theta_i| < 90 deg (first order in clearance / radius, as kernels.contact_envelope)."""
    n = c.shape[0]
    delta = TWO_PI / n
    q = int(math.floor((0.5 * math.pi - 1e-9) / delta))
    inv = np.empty(2 * q + 1)
    for d in range(-q, q + 1):
        inv[d + q] = 1.0 / math.cos(d * delta)
    for i in range(n):
        best = c[i]
        for d in range(-q, q + 1):
            v = c[(i + d) % n] * inv[d + q]
            if v < best:
                best = v
        out[i] = best


@njit(cache=True)
def rounded_envelope(c, rho, out):
    """Radial function (at the grid angles) of S' = (S eroded by rho) dilated by rho, S the admissible set of the
    local clearances c (n,): the largest t with dist(t u_i, S_rho) <= rho, S_rho the set of the clearances c - rho,
    found by bisection to 1e-6 of rho. rho must be < min(c)."""
    n = c.shape[0]
    r_in = np.empty(n)
    admissible_radius(c - rho, r_in)
    delta = TWO_PI / n
    for i in range(n):
        cx = math.cos(i * delta)
        sy = math.sin(i * delta)
        lo = r_in[i]
        hi = r_in[i] + 2.0 * rho
        while polygon_distance(r_in, hi * cx, hi * sy) < rho:
            hi += rho
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if polygon_distance(r_in, mid * cx, mid * sy) < rho:
                lo = mid
            else:
                hi = mid
            if hi - lo < 1e-6 * rho:
                break
        out[i] = 0.5 * (lo + hi)
