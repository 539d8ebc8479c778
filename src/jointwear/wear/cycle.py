"""Archard wear per cycle of one clearance joint from one set of recorded steady cycles (paper Eqs. 29-34).

The dynamics records the contact of a few cycles (a ContactTrace); :func:`cycle_wear` integrates the Archard
wear of every recorded step on the bearing's and the journal's angular grids and divides by the cycles recorded.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .angles import circular_mean
from .kernels import (
    accumulate_wear,
    gather_directions,
    gaussian_taps,
    grid_directions,
    lay_substeps,
    map_touch_angles,
    periodic_interp,
    share_load,
    smooth_periodic,
)
from .settings import WearSettings


@dataclass(frozen=True)
class JointMaterials:
    """Contact constants of one joint as seen by the wear model (SI)."""

    r_b0: float
    r_j0: float
    width: float
    h_b: float  # (1 - nu^2) / E
    h_j: float
    kH_b: float  # k / H (1/Pa)
    kH_j: float

    @classmethod
    def from_trace(cls, trace, geom=None) -> "JointMaterials":
        """The constants of a ContactTrace's joint (its validated settings: materials, width) with the unworn radii
        of ``geom`` (default: the trace's)."""
        vals = {}
        for mat in (trace.joint.bearing_material, trace.joint.journal_material):
            nu = mat.poissons_ratio
            vals[len(vals)] = ((1.0 - nu * nu) / mat.youngs_modulus, mat.wear_coefficient / mat.hardness)
        src = geom if geom is not None else trace
        return cls(float(src.bearing_radius), float(src.journal_radius), float(trace.joint.width),
                   vals[0][0], vals[1][0], vals[0][1], vals[1][1])


@dataclass
class CycleWear:
    """Wear of one joint per cycle from one set of recorded steady cycles (SI)."""

    bearing: np.ndarray  # (n_grid,) depth per cycle (m / cycle), bearing frame
    journal: np.ndarray  # (n_grid,) depth per cycle, journal frame
    volume_bearing: float  # Archard volume per cycle (m^3 / cycle)
    volume_journal: float
    sliding_distance: float  # m / cycle
    contact_time: np.ndarray  # (n_grid,) s / cycle with the contact normal in the cell (bearing frame)
    force_mean: np.ndarray  # (n_grid,) time-mean normal force while in the cell (N); nan where never
    slip_distance: np.ndarray  # (n_grid,) sliding distance per cycle in the cell (m / cycle)
    area_mean: np.ndarray  # (n_grid,) time-mean contact area (m^2); nan where never
    max_half_width: float  # m
    mean_orientation: float  # rod (bearing body) mean orientation over the cycles (rad, global)
    levelling_rate: float = 0.0  # profile mode, distributed deposit: 1/cycle (kernels.share_load)
    share: "ConformalShare | None" = dataclasses.field(default=None, repr=False)  # distributed deposit only
    journal_levelling_rate: float = 0.0  # the same for the journal, on its own grid
    journal_share: "ConformalShare | None" = dataclasses.field(default=None, repr=False)


@dataclass
class ConformalShare:
    """The recorded loads of a block gathered by contact direction (per cycle), shared over any bore profile
    (profile mode, distributed deposit; kernels.gather_directions / share_load)."""

    bins: np.ndarray  # (4, n_grid) per cycle
    c0: float
    r_b0: float
    width: float
    directions: tuple[np.ndarray, np.ndarray] = dataclasses.field(init=False, repr=False)

    def __post_init__(self):
        n = self.bins.shape[1]
        self.directions = (np.empty(n), np.empty(n))
        grid_directions(*self.directions)

    def merged(self, factor: int) -> "ConformalShare":
        """The same loads gathered into direction cells `factor` times wider (sums over each group of cells, laid
        at the cell of the group's mean direction)."""
        n = self.bins.shape[1]
        m = -(-n // factor)
        groups = np.zeros((4, m * factor))
        groups[:, :n] = self.bins
        tot = groups.reshape(4, m, factor).sum(axis=2)  # each group's additions in cell order
        tot = tot[:, tot[0] > 0.0]
        k = np.floor(np.mod(np.arctan2(tot[2], tot[1]), 2.0 * math.pi) / (2.0 * math.pi / n) + 0.5).astype(np.int64) % n
        out = np.zeros_like(self.bins)
        np.add.at(out, (slice(None), k), tot)
        return ConformalShare(out, self.c0, self.r_b0, self.width)

    def lay(self, wb: np.ndarray, steps: int, dt: float, smoothing_deg: float) -> float:
        """`steps` explicit sub-steps of dt cycles on the bearing profile wb (in place), each sharing the loads over
        the bore laid so far: wb += dt max(S rate, 0), rate the shares on the bore max(S wb, 0), S the running-in
        smoothing (kernels.smooth_periodic). Returns the Archard volume laid (m^3)."""
        taps = np.ones(1) if smoothing_deg <= 0.0 else gaussian_taps(wb.shape[0], float(smoothing_deg))
        if taps is not None:  # compiled: the deposit lays thousands of sub-steps per history
            return float(lay_substeps(self.bins, self.c0, *self.directions, self.r_b0, self.width, taps, wb,
                                      int(steps), float(dt)))
        vol = 0.0
        for _ in range(steps):  # a kernel too wide for real-space taps: FFT smoothing
            rate, vrate, _ = self(np.maximum(smooth_periodic(wb, smoothing_deg), 0.0))
            wb += np.maximum(smooth_periodic(rate, smoothing_deg), 0.0) * dt
            vol += vrate * dt
        return vol

    def __call__(self, bore: np.ndarray) -> tuple[np.ndarray, float, float]:
        """(bearing depth per cycle, Archard volume per cycle, levelling rate per cycle) on the bore profile."""
        c_bore = np.ascontiguousarray(self.c0 + bore, dtype=float)
        out = np.zeros(c_bore.shape[0])
        vol, g = share_load(self.bins, c_bore, *self.directions, self.r_b0, self.width, out)
        return out, vol, g


def sweep_shares(t, n: int) -> np.ndarray | None:
    """The fraction of each recorded step's trapezoid weight that lies before it in time (kernels.accumulate_wear
    lays that share along the arc back to the previous step's contact angle, the rest on to the next); None when the
    record has no times (each step's wear is then laid at its own angle)."""
    if t is None:
        return None
    t = np.asarray(t, dtype=float)
    if t.shape != (n,):
        return None
    d = np.diff(t)
    before = np.concatenate(([0.0], d))
    after = np.concatenate((d, [0.0]))
    tot = before + after
    return np.where(tot > 0.0, before / np.where(tot > 0.0, tot, 1.0), 0.5)


def cycle_wear(
    trace,
    settings: WearSettings,
    n_cycles: float,
    materials: JointMaterials | None = None,
    growth: float = 0.0,
    bearing_profile: np.ndarray | None = None,
    journal_profile: np.ndarray | None = None,
    bearing_touch: np.ndarray | None = None,
    journal_touch: np.ndarray | None = None,
    bearing_bore: np.ndarray | None = None,
    journal_surface: np.ndarray | None = None,
) -> CycleWear:
    """Archard wear per cycle of one ContactTrace-like record that spans `n_cycles` cycles.

    The radii used for R* are those the contact search used: uniform mode R_b0 + growth/2 and R_j0 - growth/2
    (paper Eqs. 36-37); profile mode (when profiles are given) the local radii R_b0 + h_b(theta_b) and
    R_j0 - h_j(theta_j), with the profiles exactly as given to the contact search. bearing_touch / journal_touch
    (profile mode, 'envelope' contact): grid index of the bore point that touches for each centre-line direction
    (contact.envelope.admissible_set); the wear is laid there. Each step's wear is laid along the arc its contact
    angle sweeps over its time weight (the angle linear in time between the recorded steps; sweep_shares), not at
    its one recorded angle. bearing_bore (profile mode, `profile_deposit =
    "distributed"`): the bore's contact profile (smoothed wear, m); each step's bearing wear is shared over the
    cells the journal touches (kernels.gather_directions, share_load) instead. journal_surface: the same for the
    journal, its contact profile on its own grid, shared in the journal's frame (a flat worn on a pin under a load
    fixed on the pin is the bore's pocket mirrored: e . u <= c0 + h_j(u) to first order in c0 / R).

    Each side shares the load over its own profile only; the contact's Archard volume is (k/H) sum_k N_k ds on both
    sides, with sum_k N_k / F the larger of the two sides' ratios (the side worn to the other's shape sets how far
    the pressure spreads).
    """
    mat = materials or JointMaterials.from_trace(trace)
    n = settings.n_grid
    F = np.ascontiguousarray(trace.force_normal, dtype=float)
    F = np.where(np.asarray(trace.in_contact, dtype=bool), F, 0.0)
    tb = np.ascontiguousarray(trace.theta_bearing, dtype=float)
    tj = np.ascontiguousarray(trace.theta_journal, dtype=float)
    v = np.ascontiguousarray(trace.slip_speed, dtype=float)
    dt = np.ascontiguousarray(trace.dt_weight, dtype=float)
    if bearing_profile is not None:
        r_b = mat.r_b0 + periodic_interp(bearing_profile, tb)
        worn_j = journal_profile is not None and journal_profile.any()  # (zeros would subtract 0.0: the same)
        r_j = mat.r_j0 - (periodic_interp(journal_profile, tj) if worn_j else 0.0)
        r_j = np.broadcast_to(r_j, r_b.shape).copy()
    else:
        r_b = np.full(F.shape, mat.r_b0 + 0.5 * growth)
        r_j = np.full(F.shape, mat.r_j0 - 0.5 * growth)
    tb_w, tj_w = tb, tj
    if bearing_touch is not None:
        tb_w = np.empty_like(tb)
        map_touch_angles(tb, bearing_touch, tb_w)
    if journal_touch is not None:
        tj_w = np.empty_like(tj)
        map_touch_angles(tj, journal_touch, tj_w)
    wb = np.zeros(n)
    wj = np.zeros(n)
    diag = np.zeros((4, n))
    left = sweep_shares(getattr(trace, "t", None), F.shape[0])
    vb, vj, s, bmax = accumulate_wear(
        tb_w, tj_w, F, v, dt, r_b, r_j, mat.r_b0, mat.r_j0, mat.h_b, mat.h_j,
        mat.kH_b if bearing_bore is None else 0.0, mat.kH_j if journal_surface is None else 0.0, mat.width,
        settings.half_width_factor, settings.pressure == "hertz", settings.track_journal, wb, wj, diag,
        math.radians(settings.profile_smoothing_deg) * math.sqrt(3.0) if bearing_profile is not None else 0.0,
        left,
    )
    sides = []  # the sides laid by the shared load: (side, k/H, shares per unit k/H, their deposit on the side)
    tilt = np.ascontiguousarray(trace.normal_tilt, dtype=float)
    for side, kH, radius, bore, theta in ((0, mat.kH_b, mat.r_b0, bearing_bore, tb),
                                          (1, mat.kH_j, mat.r_j0, journal_surface, tj)):
        if bore is None:
            continue
        bins = np.zeros((4, n))
        gather_directions(theta, tilt, F, v, dt, mat.h_b + mat.h_j, 1.0, mat.width, settings.half_width_factor, bins,
                          left)
        shared = ConformalShare(bins / n_cycles, mat.r_b0 - mat.r_j0, radius, mat.width)  # per unit k/H
        sides.append((side, kH, shared, shared(bore)))
    g_level, share, g_journal, share_j = 0.0, None, 0.0, None
    if sides:
        fds = float(np.sum(F * np.abs(v) * dt))  # (1/(k/H)) x the Archard volume of a point contact
        # sum_k N_k / F of each side sharing the load, 1 for a side laid at its touching point
        ratios = [vrate * n_cycles / fds if fds > 0.0 else 1.0 for _, _, _, (_, vrate, _) in sides]
        ratio = max(ratios + ([1.0] if len(sides) < 2 else []))
        for (side, kH, shared, (rate, vrate, g)), own in zip(sides, ratios):
            f = kH * ratio / own  # this side's k/H, times the contact's ratio over its own
            shared.bins *= f  # the shares laid by the block's sub-steps carry the side's k/H and the ratio
            laid = shared if f > 0.0 else None
            if side == 0:
                wb += rate * (f * n_cycles)
                vb = vrate * f * n_cycles
                g_level, share = g * f, laid
            else:
                wj += rate * (f * n_cycles)
                vj = vrate * f * n_cycles
                g_journal, share_j = g * f, laid
        if journal_surface is None and fds > 0.0:  # the journal laid at its touching point takes the contact's ratio
            wj *= ratio
            vj *= ratio
    inv = 1.0 / n_cycles
    with np.errstate(invalid="ignore", divide="ignore"):
        fmean = np.where(diag[0] > 0, diag[1] / diag[0], np.nan)
        amean = np.where(diag[0] > 0, diag[3] / diag[0], np.nan)
    mean_or = circular_mean(trace.bearing_body_angle, dt)
    return CycleWear(wb * inv, wj * inv, vb * inv, vj * inv, s * inv, diag[0] * inv, fmean, diag[2] * inv, amean,
                     bmax, mean_or, g_level, share, g_journal, share_j)


def mean_half_width(cw: CycleWear, mat: JointMaterials, settings: WearSettings) -> float:
    """Johnson's half-width (m) at the time-mean normal force while in contact, on the unworn radii."""
    ct = cw.contact_time
    if not np.any(ct > 0):
        return math.nan
    force = float(np.nansum(np.where(ct > 0, cw.force_mean, 0.0) * ct) / ct.sum())
    rstar = mat.r_b0 * mat.r_j0 / (mat.r_b0 - mat.r_j0)
    return settings.half_width_factor * math.sqrt(force * rstar * (mat.h_b + mat.h_j) / mat.width)
