"""Archard wear kernels: plain functions over arrays, compiled with numba.

Physics (paper Section 3 with the corrections of the user guide's baseline reading, "Wear"):

* sliding distance of a step: ds = |v_t| dt, v_t the relative tangential velocity of the contact points
  (not the paper's Eq. 30, which uses link lengths times angular speeds);
* line-contact half-width b = c sqrt(F_N R* (h_i + h_j) / L), R* = R_i R_j / (R_i - R_j), h = (1 - nu^2) / E,
  c = sqrt(4/pi) = 1.128 (Johnson's b = sqrt(4 F R* / (pi L E*)), 1/E* = h_i + h_j); contact area A = 2 b L;
* Archard depth on each body (its own k and H): dh = (k / H) p ds with p = F_N / A (the paper's Eq. 31 divides by
  A twice; that is a typo). The worn volume of the step is then (k / H) F_N ds whatever b is;
* the depth is spread over the patch |s| <= b, i.e. |theta - theta_c| <= b / R, on the body's angular grid with
  exact overlap integration of the patch shape with each cell. The cell value is the cell-average depth, so
  sum_k h_k R Delta L equals the Archard volume to rounding, and the profile does not depend on the grid;
* the patch centre theta_c moves over the step's time weight: the contact angle is taken linear in time between the
  recorded steps, and the patch is swept over that arc (exact integration again), so the profile does not depend on
  where the integrator happened to put its steps either (accumulate_wear, spread_swept_pair); profile mode's
  distributed deposit gathers the loads by the direction of the contact normal along the same arcs
  (gather_directions).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import njit

from jointwear.contact.envelope import polar_scan

TWO_PI = 2.0 * math.pi


@njit(cache=True, inline="always")
def _shape_cdf(u: float, hertz: bool) -> float:
    """Fraction of the patch load in [-1, u] (u in patch half-widths). Uniform: (u+1)/2; Hertz: elliptical."""
    if u <= -1.0:
        return 0.0
    if u >= 1.0:
        return 1.0
    if hertz:
        return 0.5 + (u * math.sqrt(1.0 - u * u) + math.asin(u)) / math.pi
    return 0.5 * (u + 1.0)


@njit(cache=True)
def spread_patch(grid: np.ndarray, center: float, half_angle: float, area: float, hertz: bool) -> None:
    """Spread a worn cross-section over a patch of `grid` (in place).

    `grid` (n,) holds cell-average depths (m) on cells centred at 2 pi k / n. `area` is the worn cross-section
    divided by the radius (m * rad), i.e. volume / (L R). The patch covers [center - half_angle, center + half_angle]
    with a uniform or elliptical (Hertz) shape. Cell k receives area * (fraction of the patch in the cell) / Delta,
    so sum(grid) * Delta increases by exactly `area`. Periodic.
    """
    n = grid.shape[0]
    delta = TWO_PI / n
    c = center % TWO_PI
    if half_angle <= 0.0 or not math.isfinite(half_angle):
        j = int(math.floor(c / delta + 0.5)) % n
        grid[j] += area / delta
        return
    j0 = int(math.floor((c - half_angle) / delta + 0.5))
    j1 = int(math.floor((c + half_angle) / delta + 0.5))
    scale = area / delta
    prev = 0.0
    for j in range(j0, j1 + 1):
        if j == j1:
            cur = 1.0
        else:
            cur = _shape_cdf(((j + 0.5) * delta - c) / half_angle, hertz)
        frac = cur - prev
        prev = cur
        if frac != 0.0:
            grid[j % n] += scale * frac


@njit(cache=True, inline="always")
def _shape_integral(y: float, h: float, hertz: bool) -> float:
    """Integral of the patch's load fraction (_shape_cdf) from -inf to y, for a patch of half-width h (same units
    as y): 0 below the patch, y above it (so a difference of two values is a difference of positions)."""
    if y <= -h:
        return 0.0
    if y >= h:
        return y
    u = y / h
    if hertz:  # integral of 0.5 + (u sqrt(1 - u^2) + asin u) / pi
        r = 1.0 - u * u
        return h * (0.5 * u + (u * math.asin(u) + math.sqrt(r) - r * math.sqrt(r) / 3.0) / math.pi)
    return (y + h) * (y + h) / (4.0 * h)


@njit(cache=True, inline="always")
def _swept_cdf(x: float, phi_x: float, arc: float, h: float, hertz: bool) -> float:
    """Fraction of the load of a patch (half-width h) swept uniformly from 0 to `arc` (signed) that lies below x;
    phi_x = _shape_integral(x, h, hertz), shared by the arcs that start at the same centre."""
    if abs(arc) > 1e-6 * h:
        return (phi_x - _shape_integral(x - arc, h, hertz)) / arc
    x -= 0.5 * arc  # shorter than rounding of the patch's own shape: the patch at the arc's middle
    if h > 0.0:
        return _shape_cdf(x / h, hertz)
    return 1.0 if x >= 0.0 else 0.0


@njit(cache=True)
def spread_swept_pair(grid: np.ndarray, center: float, arc1: float, arc2: float, half_angle: float, area1: float,
                      area2: float, hertz: bool) -> None:
    """Spread two worn cross-sections (m * rad, as spread_patch), each over a patch whose centre moves uniformly
    from `center` over a signed arc (rad): area1 over [center, center + arc1], area2 over [center, center + arc2]
    (a recorded step's wear over the halves of the arcs to its neighbours: accumulate_wear). Each is the patch shape
    of spread_patch convolved with its arc, integrated exactly over each cell, so sum(grid) * Delta increases by
    exactly area1 + area2; zero arcs are spread_patch. Periodic."""
    h = half_angle if (half_angle > 0.0 and math.isfinite(half_angle)) else 0.0
    tot = area1 + area2
    if tot == 0.0:
        return
    w1 = area1 / tot
    w2 = area2 / tot
    if not (abs(arc1) > 1e-6 * h or abs(arc2) > 1e-6 * h):  # both shorter than rounding of the patch's own shape
        spread_patch(grid, center + 0.5 * (w1 * arc1 + w2 * arc2), h, tot, hertz)
        return
    n = grid.shape[0]
    delta = TWO_PI / n
    c = center % TWO_PI
    j0 = int(math.floor((c + min(0.0, arc1, arc2) - h) / delta + 0.5))
    j1 = int(math.floor((c + max(0.0, arc1, arc2) + h) / delta + 0.5))
    scale = tot / delta
    prev = 0.0
    for j in range(j0, j1 + 1):
        if j == j1:
            cur = 1.0
        else:
            x = (j + 0.5) * delta - c
            phi = _shape_integral(x, h, hertz)
            cur = 0.0
            if w1 > 0.0:
                cur += w1 * _swept_cdf(x, phi, arc1, h, hertz)
            if w2 > 0.0:
                cur += w2 * _swept_cdf(x, phi, arc2, h, hertz)
        frac = cur - prev
        prev = cur
        if frac != 0.0:
            grid[j % n] += scale * frac


#: The largest change of the contact angle between two recorded steps that is read as the contact sweeping the arc
#: between them (accumulate_wear); a larger one is a jump (the contact changed side), and each step's wear stays at
#: its own angle. The integrator moves the journal by at most a quarter of the clearance per step
#: (SimulationConfig.clearance_step_fraction), i.e. about 15 deg of contact angle.
MAX_SWEEP = math.pi / 8.0


@njit(cache=True, inline="always")
def _arc_to(theta: np.ndarray, i: int, j: int, max_sweep: float) -> float:
    """Signed arc (rad) from theta[i] to theta[j] the short way round; 0 when j is outside the record or the arc is
    longer than max_sweep."""
    if j < 0 or j >= theta.shape[0]:
        return 0.0
    d = theta[j] - theta[i]
    if not (abs(d) <= 3.0):  # (|d| <= 3 < pi is its own short way round: floor(d / 2 pi + 0.5) = 0 exactly)
        d -= TWO_PI * math.floor(d / TWO_PI + 0.5)
    return d if abs(d) <= max_sweep else 0.0


@njit(cache=True, inline="always")
def _lay_step(grid: np.ndarray, theta: np.ndarray, i: int, half_angle: float, area: float,
              left_share: np.ndarray | None, max_sweep: float, hertz: bool) -> None:
    """Step i's worn cross-section on one body's grid: at its own angle without left_share, else swept over the
    halves of the arcs to its neighbours' angles in the shares left_share[i] and 1 - left_share[i]."""
    if left_share is None:
        spread_patch(grid, theta[i], half_angle, area, hertz)
    else:
        sl = left_share[i]
        spread_swept_pair(grid, theta[i], 0.5 * _arc_to(theta, i, i - 1, max_sweep),
                          0.5 * _arc_to(theta, i, i + 1, max_sweep), half_angle, area * sl, area * (1.0 - sl), hertz)


@njit(cache=True, nogil=True)
def accumulate_wear(
    theta_b: np.ndarray,
    theta_j: np.ndarray,
    force: np.ndarray,
    slip: np.ndarray,
    dt: np.ndarray,
    r_b: np.ndarray,
    r_j: np.ndarray,
    r_b0: float,
    r_j0: float,
    h_b: float,
    h_j: float,
    kH_b: float,
    kH_j: float,
    width: float,
    c_half: float,
    hertz: bool,
    track_journal: bool,
    wear_b: np.ndarray,
    wear_j: np.ndarray,
    diag: np.ndarray,
    min_half_angle: float = 0.0,
    left_share: np.ndarray | None = None,
    max_sweep: float = MAX_SWEEP,
) -> tuple:
    """Accumulate the Archard wear of all steps onto `wear_b` (bearing grid) and `wear_j` (journal grid).

    Per step i: theta_b/theta_j the direction of the contact normal in the bearing/journal body frame (rad),
    force the normal force (N, <= 0 out of contact), slip the relative tangential speed (m/s), dt the quadrature
    weight (s), r_b/r_j the current (local) bearing/journal radii used for R* (m). r_b0/r_j0: nominal radii that
    convert arc length to grid angle. h = (1 - nu^2)/E of each body, kH = k/H (1/Pa), width L (m), c_half the
    half-width factor.

    min_half_angle (rad): lower bound of the patch half-angle (profile mode with a running-in smoothing length;
    0 = the Hertz patch only).

    diag (4, n) on the bearing grid (nearest cell): [0] contact time (s), [1] integral of F dt (N s),
    [2] sliding distance (m), [3] integral of A dt (m^2 s).

    left_share (n,): the fraction of each step's weight that lies before it in time (trapezoid weights: the
    half-interval to the previous step over the sum of both). When given, each step's wear is laid along the arcs
    its contact angle sweeps over its weight's time, taken linear in time between steps: the share left_share over
    the half of the arc back to the previous step's angle, the rest over the half on to the next one
    (spread_swept_pair; an arc longer than max_sweep is a jump and not swept). Otherwise each step's wear is laid
    at its own angle: where the contact sweeps the bore by a large part of the patch per step (the flapping wing
    at rtol 5e-7: 2-3 deg per step, patches of +-1.6 deg) the cycle's profile is then a sum of lumps, whose
    maximum read one cycle's peak 3.5 % high while its sum (the volume) is right (benchmarks/wear_sweep.py).

    Returns (archard volume bearing, archard volume journal, sliding distance, max half-width) in SI.
    """
    n_b = wear_b.shape[0]
    delta_b = TWO_PI / n_b
    vol_b = 0.0
    vol_j = 0.0
    s_tot = 0.0
    b_max = 0.0
    hsum = h_b + h_j
    for i in range(force.shape[0]):
        f = force[i]
        if not (f > 0.0):
            continue
        ds = abs(slip[i]) * dt[i]
        rb = r_b[i]
        rj = r_j[i]
        rstar = rb * rj / (rb - rj)
        b = c_half * math.sqrt(f * rstar * hsum / width)
        if b > b_max:
            b_max = b
        # Archard volume of the step on each body: (k/H) p ds * (2 b L) = (k/H) F ds.
        dvb = kH_b * f * ds
        if dvb != 0.0:  # 0 where the bearing's wear is laid elsewhere (profile mode's distributed deposit)
            _lay_step(wear_b, theta_b, i, max(b / r_b0, min_half_angle), dvb / (width * r_b0), left_share,
                      max_sweep, hertz)
        vol_b += dvb
        if track_journal:
            dvj = kH_j * f * ds
            if dvj != 0.0:
                _lay_step(wear_j, theta_j, i, max(b / r_j0, min_half_angle), dvj / (width * r_j0), left_share,
                          max_sweep, hertz)
            vol_j += dvj
        s_tot += ds
        k = int(math.floor((theta_b[i] % TWO_PI) / delta_b + 0.5)) % n_b
        diag[0, k] += dt[i]
        diag[1, k] += f * dt[i]
        diag[2, k] += ds
        diag[3, k] += 2.0 * b * width * dt[i]
    return vol_b, vol_j, s_tot, b_max


def worn_area(profile: np.ndarray, radius: float) -> float:
    """Worn cross-section (m^2) of a cell-average depth profile on a grid of the body with nominal radius `radius`.

    Thin-layer measure sum_k h_k R Delta (the measure the spreading conserves exactly); times the width it is the
    worn volume.
    """
    profile = np.asarray(profile, dtype=float)
    return float(profile.sum() * radius * TWO_PI / profile.shape[0])


def periodic_interp(profile: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Linear periodic interpolation of a grid profile (cells centred at 2 pi k / n) at angles theta (rad)."""
    profile = np.asarray(profile, dtype=float)
    n = profile.shape[0]
    x = np.mod(np.asarray(theta, dtype=float), TWO_PI) * (n / TWO_PI)
    i0 = np.floor(x).astype(np.int64)
    w = x - i0
    i0 %= n
    return (1.0 - w) * profile[i0] + w * profile[(i0 + 1) % n]


@njit(cache=True)
def map_touch_angles(theta: np.ndarray, idx: np.ndarray, out: np.ndarray) -> None:
    """Centre-line directions theta (rad) -> angle of the bore point that actually touches (see contact.envelope.admissible_set).

    Where the direction's own cell is the active constraint the angle is unchanged; where a flank is active the
    contact sits at the flank's grid angle.
    """
    n = idx.shape[0]
    delta = TWO_PI / n
    for s in range(theta.shape[0]):
        i = int(math.floor((theta[s] % TWO_PI) / delta + 0.5)) % n
        k = idx[i]
        out[s] = theta[s] if k == i else k * delta


def smooth_periodic(profile: np.ndarray, sigma_deg: float) -> np.ndarray:
    """Periodic Gaussian smoothing (standard deviation sigma_deg) of a grid profile; conserves its sum to rounding.

    The operator is the Fourier multiplier exp(-(k sigma)^2 / 2) (gaussian_multiplier); a kernel narrow on the grid
    is applied as its circulant taps in real space (gaussian_taps, the same operator to rounding), faster than an
    FFT for the deposit's thousands of sub-steps per history."""
    p = np.asarray(profile, dtype=float)
    if sigma_deg <= 0.0:
        return p.copy()
    n = p.shape[0]
    taps = gaussian_taps(n, float(sigma_deg))
    if taps is None:
        return np.fft.irfft(np.fft.rfft(p) * gaussian_multiplier(n, float(sigma_deg)), n)
    out = np.empty(n)
    convolve_periodic(np.ascontiguousarray(p), taps, out)
    return out


@functools.lru_cache(maxsize=16)
def gaussian_multiplier(n: int, sigma_deg: float) -> np.ndarray:
    """The Fourier multiplier of smooth_periodic (read-only; cached: the deposit's sub-steps smooth thousands of
    times per history)."""
    k = np.fft.rfftfreq(n, d=1.0 / n)  # cycles per revolution
    g = np.exp(-0.5 * (k * math.radians(sigma_deg)) ** 2)
    g.flags.writeable = False
    return g


#: Circulant taps smaller than this fraction of the centre tap are dropped (the irfft that gives them rounds at
#: about 1e-16 of it).
TAP_CUTOFF = 1e-15
#: Wider kernels than this many taps are applied by FFT (about where the two cost the same on a 720-cell grid).
MAX_TAPS = 257


@functools.lru_cache(maxsize=16)
def gaussian_taps(n: int, sigma_deg: float) -> np.ndarray | None:
    """The circulant kernel of gaussian_multiplier, taps[W + d] for d = -W .. W, W the last offset whose tap is at
    least TAP_CUTOFF of the centre's, normalised to sum 1; None when it has more than MAX_TAPS taps (read-only)."""
    kern = np.fft.irfft(gaussian_multiplier(n, sigma_deg), n)
    big = np.nonzero(np.abs(kern[: n // 2 + 1]) >= TAP_CUTOFF * kern[0])[0]
    half = int(big[-1])
    if 2 * half + 1 > min(MAX_TAPS, n):
        return None
    taps = np.concatenate((kern[n - half:], kern[: half + 1]))
    taps /= taps.sum()
    taps.flags.writeable = False
    return taps


@njit(cache=True, nogil=True)
def convolve_periodic(x, taps, out):
    """out[i] = sum_d taps[W + d] x[(i + d) mod n], d = -W .. W (tap-major, so the inner loop vectorizes)."""
    n = x.shape[0]
    half = (taps.shape[0] - 1) // 2
    ext = np.empty(n + 2 * half)
    for i in range(n + 2 * half):
        ext[i] = x[(i - half) % n]
    out[:] = 0.0
    for d in range(taps.shape[0]):
        t = taps[d]
        seg = ext[d:d + n]
        for i in range(n):
            out[i] += t * seg[i]


#: Cells no wider than this (rad, n_grid >= 360) have the cos/sin and sinc of a piece of arc within a cell taken
#: from Taylor polynomials (_gather_arc) instead of math.cos/sin: at most half a cell (0.0087 rad) from the cell's
#: centre, sin x to x^5, cos x to x^6 and sin(h)/h to h^4 leave relative errors below 1e-16.
_POLY_DELTA = 0.0175


@njit(cache=True, inline="always")
def _gather_arc(bins, start, arc, dv, dh, delta, cos_c, sin_c, poly):
    """Add a load dv (and dv dh to bins[3]) spread uniformly over the directions from `start` to `start + arc`
    (rad, signed) to the direction cells of bins (4, n), cells centred at 2 pi k / n: each cell takes the part of
    the arc inside it, with the exact integrals of cos m and sin m over that part [a, b]:
    (b - a) sinc(h) (cos, sin)(c), c = (a + b) / 2 = j delta + r, h = (b - a) / 2, the direction at c from the
    cell centre's (cos_c, sin_c: cos, sin of 2 pi k / n) turned by r (|r|, h <= delta / 2; Taylor polynomials when
    poly, i.e. delta <= _POLY_DELTA). The product form loses no digits on short pieces, where sin b - sin a would
    (relative 1e-16 / (b - a))."""
    n = bins.shape[1]
    if abs(arc) < 1e-12:
        k = int(math.floor((start % TWO_PI) / delta + 0.5)) % n
        bins[0, k] += dv
        bins[1, k] += dv * math.cos(start)
        bins[2, k] += dv * math.sin(start)
        bins[3, k] += dv * dh
        return
    lo = min(start, start + arc)
    hi = max(start, start + arc)
    dens = dv / (hi - lo)
    j = int(math.floor(lo * (n / TWO_PI) + 0.5))  # (a j one off at an edge only gives a piece of zero width)
    k = j if 0 <= j < n else j % n
    a = lo
    while True:
        e = (j + 0.5) * delta  # the cell's upper edge
        b = min(hi, e)
        if b > a:
            part = dens * (b - a)
            h = 0.5 * (b - a)
            r = 0.5 * (a + b) - j * delta
            if poly:
                r2 = r * r
                sr = r * (1.0 - r2 * (1.0 / 6.0 - r2 * (1.0 / 120.0)))
                cr = 1.0 - r2 * (0.5 - r2 * (1.0 / 24.0 - r2 * (1.0 / 720.0)))
                h2 = h * h
                sinc = 1.0 - h2 * (1.0 / 6.0 - h2 * (1.0 / 120.0))
            else:
                sr, cr = math.sin(r), math.cos(r)
                sinc = math.sin(h) / h
            ps = part * sinc
            bins[0, k] += part
            bins[1, k] += ps * (cos_c[k] * cr - sin_c[k] * sr)
            bins[2, k] += ps * (sin_c[k] * cr + cos_c[k] * sr)
            bins[3, k] += part * dh
        if not (e < hi):
            return
        a = e
        j += 1
        k += 1
        if k == n:
            k = 0


@njit(cache=True, nogil=True)
def gather_directions(theta_b, tilt, force, slip, dt, hsum, kH_b, width, c_half, bins, left_share=None,
                      max_sweep=MAX_SWEEP):
    """Gather the recorded steps by the grid cell of their contact normal m (angle theta_b + tilt): bins (4, n)
    receives per cell the Archard volume (k/H) F ds, its weighted sums of cos m and sin m, and of
    delta_H = b^2 / (2 R*) (see share_load) = c_half^2 F (h_b + h_j) / (2 L): R* cancels, so the radii are not needed.

    left_share (n,): as accumulate_wear's, the fraction of each step's trapezoid weight that lies before it in time.
    When given, each step's load is spread over the directions its normal sweeps over its weight's time (m linear in
    time between steps): the share left_share over the half of the arc back to the previous step's normal, the rest
    over the half on to the next one (an arc longer than max_sweep is a jump and not swept), each cell taking the
    part of the arc inside it. Otherwise each step's load goes to the cell nearest its normal: where the normal
    sweeps several cells per step (the flapping wing at rtol 5e-7: 2-3 deg per step on 0.5 deg cells) the gathered
    load is then a comb whose teeth follow the integrator's steps (benchmarks/wear_sweep.py, profile_mode)."""
    n = bins.shape[1]
    delta = TWO_PI / n
    mu = theta_b + tilt
    cells = np.arange(n if left_share is not None else 0) * delta  # (the arcs' cells' centres)
    cos_c = np.cos(cells)
    sin_c = np.sin(cells)
    poly = delta <= _POLY_DELTA
    dh_per_f = 0.5 * c_half * c_half * hsum / width
    for i in range(force.shape[0]):
        f = force[i]
        if not (f > 0.0):
            continue
        dv = kH_b * f * abs(slip[i]) * dt[i]
        if not (dv > 0.0):
            continue
        dh = dh_per_f * f  # delta_H = b^2 / (2 R*), b = c_half sqrt(F R* (h_b + h_j) / L): R* cancels
        if left_share is None:
            _gather_arc(bins, mu[i], 0.0, dv, dh, delta, cos_c, sin_c, poly)
        else:
            sl = left_share[i]
            if sl > 0.0:
                _gather_arc(bins, mu[i], 0.5 * _arc_to(mu, i, i - 1, max_sweep), dv * sl, dh, delta,
                            cos_c, sin_c, poly)
            if sl < 1.0:
                _gather_arc(bins, mu[i], 0.5 * _arc_to(mu, i, i + 1, max_sweep), dv * (1.0 - sl), dh,
                            delta, cos_c, sin_c, poly)


@njit(cache=True, inline="always")
def edge_corner(c, cs, sn, a, b):
    """The corner where the edges e . u_a = c_a and e . u_b = c_b of the admissible set meet."""
    det = cs[a] * sn[b] - sn[a] * cs[b]
    return (c[a] * sn[b] - c[b] * sn[a]) / det, (cs[a] * c[b] - cs[b] * c[a]) / det


@njit(cache=True, inline="always")
def overlap_window(ex, ey, v1x, v1y, v2x, v2y, ref, delta, margin):
    """Cells (offsets from the angle ref, `margin` cells wider) whose directions u satisfy (e - V) . u > 0 for both
    points V = v1, v2: the intersection of two half circles. Returns (ok, lo, hi); not ok when e is too close to a
    point for its direction to be trusted or the window crosses the far side."""
    w1x = ex - v1x
    w1y = ey - v1y
    w2x = ex - v2x
    w2y = ey - v2y
    tiny = 1e-6 * math.sqrt(ex * ex + ey * ey)
    if not (math.sqrt(w1x * w1x + w1y * w1y) > tiny and math.sqrt(w2x * w2x + w2y * w2y) > tiny):
        return False, 0, 0
    a1 = math.atan2(w1y, w1x)
    dlt = math.atan2(w1x * w2y - w1y * w2x, w1x * w2x + w1y * w2y)  # angle from w1 to w2
    half_arc = 0.5 * (math.pi - abs(dlt))
    mid = (a1 + 0.5 * dlt - ref) % TWO_PI
    if mid > math.pi:
        mid -= TWO_PI
    if abs(mid) + half_arc >= math.pi:
        return False, 0, 0
    return True, int(math.floor((mid - half_arc) / delta)) - margin, int(math.ceil((mid + half_arc) / delta)) + margin


@njit(cache=True)
def grid_directions(cs, sn):
    """The unit vectors (cos, sin) of the cells of an (n,) angular grid, cells at 2 pi k / n (share_load's table)."""
    n = cs.shape[0]
    delta = TWO_PI / n
    for k in range(n):
        cs[k] = math.cos(k * delta)
        sn[k] = math.sin(k * delta)


# reassoc: the window's sums vectorize (a change of rounding only, which the deposit amplifies anyway: docs/wear.md)
@njit(cache=True, nogil=True, fastmath={"reassoc", "contract"})
def share_load(bins, c_bore, cs, sn, r_b0, width, wear_b):
    """Archard wear of the bearing in profile mode, each step's load shared by the bore cells the journal touches.

    The contact of a worn bore is not a point: a journal resting in a pocket worn to its own shape touches the whole
    worn arc. The normal force is shared over the cells k of the bore c_bore (c0 + contact profile, (n,), cells at
    2 pi k / n, unit vectors cs, sn: grid_directions) in proportion to the rigid overlap of the journal with them (an
    elastic foundation, Johnson, Contact Mechanics, Sec. 5.8), w_k = max(e'.u_k - c_k, 0) over the cells facing the
    contact normal m (angle theta_b + tilt; u_k . m > 0.1). e' is the rigid journal's position: the point of the
    admissible set S = {e : e . u_k <= c_k} farthest along m, pressed in by delta_H = b^2 / (2 R*) along m, the
    overlap at which a foundation reproduces Johnson's half-width b on a round bore. That point is the corner of S
    between the two edges whose normals bracket m (contact.envelope.polar_hull), found exactly: in a pocket worn to
    the journal's shape all the pocket's edges meet near one corner, and a point of S sampled on the grid rays would
    miss it by far more than delta_H, making the shares depend on the grid. (The dynamics' penetration is a
    Hertzian approach on a bore with rounded corners; only its force direction is used.) On a round bore the load
    spreads over |s| <= b (a parabolic pressure); in a pocket worn to the journal's shape w_k ~ cos(theta_k -
    theta_m) over the whole worn arc, the pressure of a conformal journal bearing. The shares
    N_k = F w_k / sum_j w_j (u_j . m) balance the force F along m; the Archard volume is (k/H) sum_k N_k ds >=
    (k/H) F ds.

    The steps come gathered by the grid cell of m (gather_directions, each step's load along the arc its normal
    sweeps: their Archard-weighted mean direction and delta_H), and each cell's total is shared once: the sharing is
    smooth in m within a cell.

    Returns (Archard volume (m^3), levelling rate g (1/s of the record): the largest sum over directions of
    dv / (w-projection sum) / (L R Delta), i.e. d(cell depth rate)/d(cell overlap); a cell standing out by eps is
    worn faster by g eps: the levelling that keeps a conformal contact conformal; a diagnostic).
    """
    n = wear_b.shape[0]
    delta = TWO_PI / n
    q = n // 4
    bv = bins[0]
    bmx = bins[1]
    bmy = bins[2]
    bdh = bins[3]
    px = np.empty(n)
    py = np.empty(n)
    hull = np.empty(n + 1, dtype=np.int64)
    for k in range(n):  # the polar dual points of contact.envelope.polar_hull, from the direction tables
        px[k] = cs[k] / c_bore[k]
        py[k] = sn[k] / c_bore[k]
    nh = polar_scan(px, py, int(np.argmin(c_bore)), hull)
    w = np.empty(2 * q + 1)
    cs2 = np.concatenate((cs, cs))
    sn2 = np.concatenate((sn, sn))
    c2 = np.concatenate((c_bore, c_bore))
    wear2 = np.zeros(2 * n)  # cell k's wear in k and k + n, folded at the end
    gcell2 = np.zeros(2 * n)
    gcell = np.empty(n)
    vol = 0.0
    c_min = c_bore.min()
    t = -1
    for c in range(n):
        acc_v = bv[c]
        if not (acc_v > 0.0):
            continue
        cm = bmx[c]
        sm = bmy[c]
        nm = math.sqrt(cm * cm + sm * sm)
        cm /= nm
        sm /= nm
        dh = bdh[c] / acc_v
        if nh < 3:  # no corner to rest in (a degenerate grid): the normal's cell takes the load
            wear2[c] += acc_v / (width * r_b0 * delta)
            vol += acc_v
            continue
        # the hull edge pair (a, b) whose normals bracket m; the directions come in increasing angle, so one
        # pointer walks the hull once
        if t < 0:
            t = 0
        for _ in range(nh + 1):
            a = hull[t]
            b = hull[t + 1]
            if cs[a] * sm - sn[a] * cm >= 0.0 and cm * sn[b] - sm * cs[b] > 0.0:
                break
            t = t + 1 if t + 1 < nh else 0
        a = hull[t]
        b = hull[t + 1]
        xs, ys = edge_corner(c_bore, cs, sn, a, b)
        ex = xs + dh * cm
        ey = ys + dh * sm
        emag = math.sqrt(ex * ex + ey * ey)
        # the cells that can overlap: within the window of the corners next to (xs, ys) (points V of S have
        # V . u_k <= c_k, so o_k > 0 needs (e' - V) . u_k > 0), else where |e'| cos(theta_k - theta_e') > min(c)
        d_lo = -q
        d_hi = q
        if not (emag > c_min):
            d_hi = d_lo - 1  # no cell overlaps
        else:
            ap = hull[t - 1] if t > 0 else hull[nh - 1]
            bn = hull[t + 2] if t + 2 <= nh else hull[1]
            x1, y1 = edge_corner(c_bore, cs, sn, ap, a)
            x2, y2 = edge_corner(c_bore, cs, sn, b, bn)
            ok, lo, hi = overlap_window(ex, ey, x1, y1, x2, y2, c * delta, delta, 2)
            if not ok:
                half = math.acos(c_min / emag)
                off = math.atan2(ey * cs[c] - ex * sn[c], ex * cs[c] + ey * sn[c])
                lo = int(math.floor((off - half) / delta)) - 1
                hi = int(math.ceil((off + half) / delta)) + 1
            d_lo = max(d_lo, lo)
            d_hi = min(d_hi, hi)
        # the window as one run of cells on the doubled tables (no wrap inside the loops, so they vectorize)
        ln = d_hi - d_lo + 1
        s0 = (c + d_lo) % n
        cw = cs2[s0:s0 + ln]
        sw = sn2[s0:s0 + ln]
        bw = c2[s0:s0 + ln]
        wproj = 0.0
        wsum = 0.0
        for j in range(ln):
            f = cw[j] * cm + sw[j] * sm
            o = max(ex * cw[j] + ey * sw[j] - bw[j], 0.0) * (f > 0.1)  # only cells facing the normal carry its load
            w[j] = o
            wproj += o * f
            wsum += o
        if not (wproj > 0.0):  # nothing on the grid faces the normal: the normal's cell takes it
            wear2[c] += acc_v / (width * r_b0 * delta)
            vol += acc_v
            continue
        scale = acc_v / wproj
        cell = scale / (width * r_b0 * delta)
        ww = wear2[s0:s0 + ln]
        gw = gcell2[s0:s0 + ln]
        for j in range(ln):
            ww[j] += cell * w[j]
            gw[j] += cell * (w[j] > 0.0)
        vol += scale * wsum
    for k in range(n):
        wear_b[k] += wear2[k] + wear2[k + n]
        gcell[k] = gcell2[k] + gcell2[k + n]
    return vol, gcell.max()


@njit(cache=True, nogil=True)
def lay_substeps(bins, c0, cs, sn, r_b0, width, taps, wb, steps, dt):
    """`steps` explicit sub-steps of dt cycles of the distributed deposit (history.lay_bearing), in place on the
    bearing profile wb: bore = c0 + max(S wb, 0), wb += dt max(S share_load(bins, bore), 0), S the convolution with
    `taps` (gaussian_taps; [1.0] for none). Returns the Archard volume laid (m^3)."""
    n = wb.shape[0]
    bore = np.empty(n)
    rate = np.empty(n)
    smooth = np.empty(n)
    vol = 0.0
    for _ in range(steps):
        convolve_periodic(wb, taps, bore)
        for k in range(n):
            bore[k] = c0 + max(bore[k], 0.0)
        rate[:] = 0.0
        v, _g = share_load(bins, bore, cs, sn, r_b0, width, rate)
        convolve_periodic(rate, taps, smooth)
        for k in range(n):
            wb[k] += max(smooth[k], 0.0) * dt
        vol += v * dt
    return vol
