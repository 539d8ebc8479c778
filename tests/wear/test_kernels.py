"""Kernel-level tests of the Archard spreading (fast, synthetic data)."""

import math

import numpy as np
import pytest
from wear_synthetic import JOINT, make_trace

from jointwear.mechanism.results import ContactTrace
from jointwear.wear.cycle import JointMaterials, cycle_wear
from jointwear.wear.kernels import (
    TWO_PI,
    periodic_interp,
    spread_patch,
    spread_swept_pair,
    worn_area,
)
from jointwear.wear.settings import WearSettings

# Conservation tolerance 1e-6: issue 3 acceptance ("relative error < 1e-6"); the spreading is exact up to rounding.
CONS_TOL = 1e-6


@pytest.mark.parametrize("hertz", [False, True])
@pytest.mark.parametrize("center,half", [(0.3, 0.02), (6.28, 0.05), (0.0, 1e-6), (3.0, 4.0), (1.0, 0.0)])
def test_spread_conserves_area(hertz, center, half):
    g = np.zeros(360)
    spread_patch(g, center, half, 2.5e-7, hertz)
    assert abs(g.sum() * TWO_PI / 360 - 2.5e-7) / 2.5e-7 < 1e-12  # exact telescoping sum: rounding only


@pytest.mark.parametrize("hertz", [False, True])
def test_spread_is_grid_independent(hertz):
    """The cell averages of a fine grid, averaged onto a coarse grid, equal the coarse grid's values: the
    spreading integrates the patch exactly over each cell, so the grid only sets the resolution."""
    rng = np.random.default_rng(1)
    fine, coarse = np.zeros(1080), np.zeros(360)
    for _ in range(200):
        c, h, a = rng.uniform(0, TWO_PI), rng.uniform(0.001, 0.08), rng.uniform(0.1, 1.0)
        spread_patch(fine, c, h, a, hertz)
        spread_patch(coarse, c, h, a, hertz)
    # cells are centred at 2 pi k / n, so grids nest for odd refinement: coarse cell k = fine cells 3k-1 .. 3k+1
    agg = np.roll(fine, 1).reshape(360, 3).mean(axis=1)
    np.testing.assert_allclose(agg, coarse, rtol=1e-10, atol=1e-12 * coarse.max())


@pytest.mark.parametrize("hertz", [False, True])
@pytest.mark.parametrize("start,arc,half", [(0.3, 0.05, 0.02), (6.27, 0.04, 0.01), (0.01, -0.03, 0.02),
                                            (1.0, 0.2, 0.0), (2.0, 1e-9, 0.02), (3.0, 0.1, 4.0)])
def test_swept_patch_conserves_area(hertz, start, arc, half):
    g = np.zeros(360)
    spread_swept_pair(g, start, arc, 0.0, half, 2.5e-7, 0.0, hertz)  # one arc
    assert abs(g.sum() * TWO_PI / 360 - 2.5e-7) / 2.5e-7 < 1e-12  # telescoping sum: rounding only


@pytest.mark.parametrize("hertz", [False, True])
def test_swept_patch_limits(hertz):
    """No arc: the patch itself; an arc of many patch widths: uniform depth area / arc on the cells well inside it;
    a coarse grid holds the cell averages of a fine one (exact integration over each cell)."""
    a, b = np.zeros(3600), np.zeros(3600)
    spread_patch(a, 1.0, 0.02, 1.0, hertz)
    spread_swept_pair(b, 1.0, 0.0, 0.0, 0.02, 1.0, 0.0, hertz)  # one arc
    np.testing.assert_array_equal(a, b)
    g = np.zeros(3600)
    spread_swept_pair(g, 1.0, 0.5, 0.0, 0.02, 1.0, 0.0, hertz)  # one arc
    k = np.arange(3600) * TWO_PI / 3600
    inner = g[(k > 1.03) & (k < 1.47)]
    np.testing.assert_allclose(inner, 1.0 / 0.5, rtol=1e-9)
    fine, coarse = np.zeros(1080), np.zeros(360)
    rng = np.random.default_rng(2)
    for _ in range(100):
        c, arc, h = rng.uniform(0, TWO_PI), rng.uniform(-0.1, 0.1), rng.uniform(0.0, 0.05)
        spread_swept_pair(fine, c, arc, 0.0, h, 1.0, 0.0, hertz)  # one arc
        spread_swept_pair(coarse, c, arc, 0.0, h, 1.0, 0.0, hertz)  # one arc
    np.testing.assert_allclose(np.roll(fine, 1).reshape(360, 3).mean(axis=1), coarse, rtol=1e-10,
                               atol=1e-12 * coarse.max())


def sweep_trace(theta0: float, omega: float, step: float, duration: float, force: float = 0.1,
                slip: float = 0.05) -> ContactTrace:
    """A contact sweeping the bore at a constant angular speed omega (rad/s) under a constant load, recorded every
    `step` seconds with trapezoid weights (as the dynamics records)."""
    t = np.arange(0.0, duration + 0.5 * step, step)
    m = t.size
    w = np.zeros(m)
    w[:-1] += 0.5 * np.diff(t)
    w[1:] += 0.5 * np.diff(t)
    th = np.mod(theta0 + omega * t, TWO_PI)
    z = np.zeros(m)
    return ContactTrace(name="A", bearing_body="rod", journal_body="crank", t=t, dt_weight=w, theta_bearing=th,
                        theta_journal=th, force_normal=np.full(m, force), force_tangential=z,
                        slip_speed=np.full(m, slip), penetration=np.full(m, 1e-8), penetration_rate=z,
                        in_contact=np.ones(m, dtype=bool), eccentricity_global=np.zeros((m, 2)), bearing_body_angle=z,
                        journal_body_angle=z, stiffness=np.full(m, 1e10), normal_tilt=z, bearing_radius=1.002e-3,
                        journal_radius=1.0e-3, clearance_used=2e-6, joint=JOINT)


@pytest.mark.parametrize("pressure", ["uniform", "hertz"])
@pytest.mark.parametrize("step_over_patch", [0.1, 0.7, 1.5])
def test_swept_contact_depth_does_not_depend_on_the_step(pressure, step_over_patch):
    """A contact sweeping the bore at a constant rate under a constant load wears a uniform depth
    (k/H) F |v| / (omega L R) along the swept arc, away from its ends: exact whatever the recorded step. Laid at the
    recorded angles alone, steps 1.5 patch half-widths apart (the flapping wing at rtol 5e-7: 2-3 deg per step,
    +-1.6 deg patches) read its maximum 50 % high (uniform pressure; Hertz 23 %), 0.7 apart 9 % (Hertz 6 %)."""
    s = WearSettings(n_grid=720, pressure=pressure)
    mat = JointMaterials.from_trace(sweep_trace(1.0, 1.0, 1.0, 1.0))
    rstar = mat.r_b0 * mat.r_j0 / (mat.r_b0 - mat.r_j0)
    half = s.half_width_factor * math.sqrt(0.1 * rstar * (mat.h_b + mat.h_j) / mat.width) / mat.r_b0  # rad
    omega = 200.0  # rad/s: 1 rad in 5 ms
    tr = sweep_trace(1.0, omega, step_over_patch * half / omega, 0.005)
    cw = cycle_wear(tr, s, 1.0, mat)
    exact = mat.kH_b * 0.1 * 0.05 / (omega * mat.width * mat.r_b0)
    k = np.arange(720) * TWO_PI / 720
    inner = cw.bearing[(k > 1.0 + 2 * half) & (k < 2.0 - 2 * half)]
    np.testing.assert_allclose(inner, exact, rtol=1e-9)
    assert cw.volume_bearing == pytest.approx(mat.kH_b * 0.1 * 0.05 * 0.005, rel=1e-12)


@pytest.mark.parametrize("step_over_cell", [0.3, 1.7, 4.5])
def test_swept_normal_gathers_a_uniform_load_whatever_the_step(step_over_cell):
    """Profile mode's distributed deposit gathers the recorded loads by the direction of the contact normal
    (kernels.gather_directions). A normal sweeping at a constant rate under a constant load puts the same Archard
    volume (k/H) F |v| Delta / omega in every direction cell it crosses, away from the arc's ends, with its mean
    direction at the cell's centre: exact whatever the recorded step. Gathered to the cell nearest each step's
    normal, the cells held 0, 1 or 2 steps' loads, a comb that followed the integrator's steps (the flapping wing at
    rtol 5e-7 sweeps 2-3 deg per step over 0.5 deg cells)."""
    n = 720
    s = WearSettings(geometry_mode="profile", n_grid=n)
    delta = TWO_PI / n
    omega = 200.0  # rad/s: 1 rad in 5 ms
    tr = sweep_trace(1.0, omega, step_over_cell * delta / omega, 0.005)
    mat = JointMaterials.from_trace(tr)
    zero = np.zeros(n)
    cw = cycle_wear(tr, s, 1.0, mat, bearing_profile=zero, journal_profile=zero, bearing_bore=zero)
    bins = cw.share.bins / (cw.share.bins[0].sum() / (mat.kH_b * 0.1 * 0.05 * tr.t[-1]))  # the ratio sum N_k / F out
    k = np.arange(n) * delta
    inner = (k > 1.0 + 2 * delta) & (k < 1.0 + omega * tr.t[-1] - 2 * delta)  # away from the record's ends
    np.testing.assert_allclose(bins[0][inner], mat.kH_b * 0.1 * 0.05 * delta / omega, rtol=1e-9)
    np.testing.assert_allclose(np.arctan2(bins[2], bins[1])[inner], k[inner], rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("n", [64, 720])
def test_swept_normal_over_a_tiny_arc_gathers_its_exact_direction(n):
    """A normal creeping 2e-9 rad across a cell edge (the integrator near the normal's turning points): each cell's
    gathered direction sum over its load is the direction at the middle of its part of the arc, to rounding. The
    differences sin b - sin a of the arc's ends lost 1e-16 / (b - a) of it (1e-7 here); the record's pieces that
    short left 5e-11 of the largest cell's sum on the flapping wing (kernels._gather_arc's product form)."""
    from jointwear.wear.cycle import sweep_shares
    from jointwear.wear.kernels import gather_directions

    delta = TWO_PI / n
    k = n // 8
    edge = (k + 0.5) * delta
    t = np.arange(11) * 1e-6
    theta = edge - 1e-9 + 2e-4 * t  # 2e-10 rad a step
    one = np.ones(t.size)
    w = np.zeros(t.size)
    w[:-1] += 0.5 * np.diff(t)
    w[1:] += 0.5 * np.diff(t)
    bins = np.zeros((4, n))
    gather_directions(theta, 0.0 * one, one, one, w, 1e-11, 1.0, 1e-2, 1.128, bins, sweep_shares(t, t.size))
    assert set(np.flatnonzero(bins[0])) == {k, k + 1}
    for cell, a, b in ((k, theta[0], edge), (k + 1, edge, theta[-1])):
        mid = 0.5 * (a + b)
        np.testing.assert_allclose(bins[1:3, cell] / bins[0, cell], [math.cos(mid), math.sin(mid)], rtol=0.0,
                                   atol=1e-14)


def test_uniform_patch_depth_is_archard_depth():
    """A patch well inside one coarse region: the depth on the patch equals (k/H) p ds with p = F/(2bL)."""
    n = 36000
    g = np.zeros(n)
    F, ds, L, R = 0.05, 1e-3, 1e-3, 1.002e-3
    b = 2e-5
    kH = 1.2e-3 / (350 * 9.807e6)
    spread_patch(g, 1.0, b / R, kH * F * ds / (L * R), False)
    depth = kH * F / (2 * b * L) * ds
    inner = g[int(round((1.0 - 0.5 * b / R) * n / TWO_PI)):int(round((1.0 + 0.5 * b / R) * n / TWO_PI))]
    np.testing.assert_allclose(inner, depth, rtol=1e-9)  # cell fractions are differences of (u+1)/2: rounding ~1e-12


def test_hertz_shape_peak():
    n = 100000
    g = np.zeros(n)
    spread_patch(g, 2.0, 0.01, 1.0, True)
    # elliptical: peak = 4/pi x mean over the patch (mean = 1 / (2 * 0.01)); 1e-3 = discretisation of the peak cell
    assert g.max() == pytest.approx(4 / math.pi / 0.02, rel=1e-3)


@pytest.mark.parametrize("pressure", ["uniform", "hertz"])
def test_cycle_wear_conservation_both_bodies(pressure):
    s = WearSettings(n_grid=360, pressure=pressure)
    tr = make_trace(2)
    mat = JointMaterials.from_trace(tr)
    cw = cycle_wear(tr, s, 2, mat)
    for prof, vol, R in ((cw.bearing, cw.volume_bearing, mat.r_b0), (cw.journal, cw.volume_journal, mat.r_j0)):
        assert vol > 0
        assert abs(worn_area(prof, R) * mat.width - vol) / vol < CONS_TOL
    # independent Archard volume straight from the trace: (k/H) sum F |v| dt
    F = np.where(tr.in_contact, tr.force_normal, 0.0)
    ref = mat.kH_b * np.sum(F * np.abs(tr.slip_speed) * tr.dt_weight) / 2
    assert cw.volume_bearing == pytest.approx(ref, rel=1e-12)


def test_cycle_wear_grid_independent_profile():
    tr = make_trace(2)
    a = cycle_wear(tr, WearSettings(n_grid=360), 2)
    b = cycle_wear(tr, WearSettings(n_grid=1080), 2)
    agg = np.roll(b.bearing, 1).reshape(360, 3).mean(axis=1)
    np.testing.assert_allclose(agg, a.bearing, rtol=1e-9, atol=1e-12 * a.bearing.max())


def test_half_width_factor_changes_patch_not_volume():
    tr = make_trace(1)
    a = cycle_wear(tr, WearSettings(n_grid=720), 1)
    b = cycle_wear(tr, WearSettings(n_grid=720, half_width_factor=1.128 * math.sqrt(2)), 1)
    assert b.max_half_width == pytest.approx(a.max_half_width * math.sqrt(2), rel=1e-3)
    assert b.volume_bearing == pytest.approx(a.volume_bearing, rel=1e-12)


def test_periodic_interp():
    p = np.sin(TWO_PI * np.arange(720) / 720)
    th = np.array([0.0, 1.0, 6.2, -0.5, 7.0])
    np.testing.assert_allclose(periodic_interp(p, th), np.sin(th), atol=1e-4)


def test_contact_envelope_shifted_circle():
    """A bore worn into a circle shifted by d (support function c0 + d cos theta) admits exactly the disk of radius
    c0 centred at d: the envelope must be its radial function d cos t + sqrt(c0^2 - d^2 sin^2 t)."""
    from jointwear.contact.envelope import admissible_set

    n = 1440
    th = TWO_PI * np.arange(n) / n
    c0, d = 2e-6, 1.2e-6
    c = c0 + d * np.cos(th)
    out, idx = np.empty(n), np.empty(n, dtype=np.int64)
    admissible_set(c, out, idx)
    exact = d * np.cos(th) + np.sqrt(c0**2 - (d * np.sin(th)) ** 2)
    # 1e-3: the minimum is taken over grid directions only (0.25 deg): error O(delta^2) relative
    np.testing.assert_allclose(out, exact, rtol=1e-3)
    assert np.all(out <= c * (1 + 1e-12))


def test_contact_envelope_narrow_pocket_bridged():
    from jointwear.contact.envelope import admissible_set
    from jointwear.wear.kernels import map_touch_angles

    n = 720
    th = TWO_PI * np.arange(n) / n
    c0 = 2e-6
    c = c0 + 25e-6 * np.exp(-0.5 * (np.angle(np.exp(1j * (th - 1.0))) / 0.3) ** 2)
    out, idx = np.empty(n), np.empty(n, dtype=np.int64)
    admissible_set(c, out, idx)
    k = int(np.argmax(c))
    assert out[k] < 0.25 * c[k]  # the journal cannot reach the bottom of a pocket narrower than itself
    assert idx[k] != k  # it touches a flank
    touch = np.empty(1)
    map_touch_angles(np.array([th[k]]), idx, touch)
    assert abs(touch[0] - th[idx[k]]) < 1e-12
    const = np.full(n, c0)
    admissible_set(const, out, idx)
    np.testing.assert_allclose(out, c0)
    assert np.all(idx == np.arange(n))


@pytest.mark.parametrize("n, sigma_deg, real_space", [(720, 3.0, True), (360, 3.0, True), (1440, 3.0, True),
                                                      (720, 1.0, False), (72, 3.0, False), (1440, 6.0, False)])
def test_smooth_periodic_is_its_fourier_multiplier(n, sigma_deg, real_space):
    """The real-space taps apply the same operator as the Fourier multiplier exp(-(k sigma)^2 / 2): they drop taps
    below 1e-15 of the centre's and the irfft that gives them rounds at ~1e-16, so 1e-14 of the profile's scale.
    A kernel whose taps do not fall that low inside MAX_TAPS (aliased on a coarse grid, or wide) takes the FFT."""
    from jointwear.wear.kernels import gaussian_multiplier, gaussian_taps, smooth_periodic

    assert (gaussian_taps(n, sigma_deg) is not None) == real_space
    p = np.random.default_rng(n).uniform(0.0, 1e-5, n)
    ref = np.fft.irfft(np.fft.rfft(p) * gaussian_multiplier(n, sigma_deg), n)
    np.testing.assert_allclose(smooth_periodic(p, sigma_deg), ref, rtol=0.0, atol=1e-14 * 1e-5)


def test_smooth_periodic_conserves_area():
    from jointwear.wear.kernels import smooth_periodic

    rng = np.random.default_rng(3)
    p = rng.uniform(0, 1e-5, 720)
    q = smooth_periodic(p, 5.0)
    assert abs(q.sum() - p.sum()) / p.sum() < 1e-12  # the k = 0 mode is untouched: rounding only
    assert q.std() < p.std()
    np.testing.assert_allclose(smooth_periodic(p, 0.0), p)
