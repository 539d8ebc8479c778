"""The long run: wear of the clearance joints over hundreds of thousands of cycles.

Simulating every cycle (the paper's Step 5) costs hours per model call. Instead (paper-notes.md, "Wear"):

1. simulate a few steady cycles on the current geometry (settle, then record `record_cycles` cycles),
2. integrate the Archard wear of the recorded steps on the bearing and journal grids -> wear per cycle,
3. extrapolate that rate over a block of cycles (explicit Euler in cycles), update the geometry, repeat to N.

The block size is fixed (`block_cycles`, default) or adaptive (`block_rule = "adaptive"`: it starts at
`initial_block`, grows by `block_growth` while the bearing's Archard volume rate changes by less than
`rate_tolerance` between blocks, and is halved when it changes by more than twice that). The history (max depth
after every block) is linear between block ends to well under 1 % because the rate is nearly constant (the
paper's Monte Carlo means are linear in cycles), so `max_wear_at(N)` interpolates it.
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .angles import circular_mean, report_angle_deg
from .kernels import (
    TWO_PI,
    gather_directions,
    share_load,
    accumulate_wear,
    map_touch_angles,
    periodic_interp,
    smooth_periodic,
    worn_area,
)
from jointwear.contact.envelope import admissible_radius, admissible_set, rounded_envelope
from jointwear.contact.geometry import PROFILE_ROUNDING

from .settings import WearSettings, check_cycles, check_material


# --------------------------------------------------------------------------------------------------- trace access
def _attr(obj, *names, default=None):
    for n in names:
        if hasattr(obj, n):
            return getattr(obj, n)
    return default


def _scalar(x) -> float:
    a = np.asarray(x, dtype=float)
    return float(a.flat[0]) if a.size else float("nan")


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
        vals = {}
        for body in ("bearing", "journal"):
            E = _scalar(_attr(trace, f"E_{body}", f"{body}_E"))
            nu = _scalar(_attr(trace, f"nu_{body}", f"{body}_nu"))
            k = _scalar(_attr(trace, f"k_{body}", f"{body}_k"))
            H = _scalar(_attr(trace, f"H_{body}", f"{body}_H"))
            check_material(k, H, body)
            if not (math.isfinite(E) and E > 0.0):
                raise ValueError(f"{body}.youngs_modulus must be a finite number > 0 Pa, got {E!r}")
            if not (math.isfinite(nu) and -1.0 < nu < 0.5):
                raise ValueError(f"{body}.poisson_ratio must lie in (-1, 0.5), got {nu!r}")
            vals[body] = ((1.0 - nu * nu) / E, k / H)
        src = geom if geom is not None else trace
        r_b0 = _scalar(_attr(src, "bearing_radius"))
        r_j0 = _scalar(_attr(src, "journal_radius"))
        width = _scalar(_attr(trace, "width"))
        if not (width > 0.0):
            raise ValueError(f"joint width must be > 0 m, got {width!r}")
        return cls(r_b0, r_j0, width, vals["bearing"][0], vals["journal"][0], vals["bearing"][1], vals["journal"][1])


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


@dataclass
class ConformalShare:
    """The recorded loads of a block gathered by contact direction (per cycle), shared over any bore profile
    (profile mode, distributed deposit; kernels.gather_directions / share_load)."""

    bins: np.ndarray  # (4, n_grid) per cycle
    c0: float
    r_b0: float
    width: float

    def __call__(self, bore: np.ndarray) -> tuple[np.ndarray, float, float]:
        """(bearing depth per cycle, Archard volume per cycle, levelling rate per cycle) on the bore profile."""
        c_bore = np.ascontiguousarray(self.c0 + bore, dtype=float)
        r_adm = np.empty_like(c_bore)
        admissible_radius(c_bore, r_adm)
        out = np.zeros(c_bore.shape[0])
        vol, g = share_load(self.bins, c_bore, r_adm, self.r_b0, self.width, out)
        return out, vol, g


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
) -> CycleWear:
    """Archard wear per cycle of one ContactTrace-like record that spans `n_cycles` cycles.

    The radii used for R* are those the contact search used: uniform mode R_b0 + growth/2 and R_j0 - growth/2
    (paper Eqs. 36-37); profile mode (when profiles are given) the local radii R_b0 + h_b(theta_b) and
    R_j0 - h_j(theta_j), with the profiles exactly as given to the contact search. bearing_touch / journal_touch
    (profile mode, 'envelope' contact): grid index of the bore point that touches for each centre-line direction
    (contact.envelope.admissible_set); the wear is laid there. bearing_bore (profile mode, `profile_deposit =
    "distributed"`): the bore's contact profile (smoothed wear, m); each step's bearing wear is shared over the
    cells the journal touches (kernels.gather_directions, share_load) instead.
    """
    mat = materials or JointMaterials.from_trace(trace)
    n = settings.n_grid
    F = np.ascontiguousarray(trace.force_normal, dtype=float)
    in_c = _attr(trace, "in_contact")
    if in_c is not None:
        F = np.where(np.asarray(in_c, dtype=bool), F, 0.0)
    tb = np.ascontiguousarray(trace.theta_bearing, dtype=float)
    tj = np.ascontiguousarray(trace.theta_journal, dtype=float)
    v = np.ascontiguousarray(trace.slip_speed, dtype=float)
    dt = np.ascontiguousarray(trace.dt_weight, dtype=float)
    if bearing_profile is not None:
        r_b = mat.r_b0 + periodic_interp(bearing_profile, tb)
        r_j = mat.r_j0 - (periodic_interp(journal_profile, tj) if journal_profile is not None else 0.0)
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
    vb, vj, s, bmax = accumulate_wear(
        tb_w, tj_w, F, v, dt, r_b, r_j, mat.r_b0, mat.r_j0, mat.h_b, mat.h_j,
        mat.kH_b if bearing_bore is None else 0.0, mat.kH_j, mat.width,
        settings.half_width_factor, settings.pressure == "hertz", settings.track_journal, wb, wj, diag,
        math.radians(settings.profile_smoothing_deg) * math.sqrt(3.0) if bearing_profile is not None else 0.0,
    )
    g_level = 0.0
    share = None
    if bearing_bore is not None:
        bins = np.zeros((4, n))
        gather_directions(tb, np.ascontiguousarray(trace.normal_tilt, dtype=float), F, v, dt, r_b, r_j,
                          mat.h_b + mat.h_j, mat.kH_b, mat.width, settings.half_width_factor, bins)
        share = ConformalShare(bins / n_cycles, mat.r_b0 - mat.r_j0, mat.r_b0, mat.width)
        rate_b, vrate_b, g_level = share(bearing_bore)
        wb += rate_b * n_cycles
        vb = vrate_b * n_cycles
    inv = 1.0 / n_cycles
    with np.errstate(invalid="ignore", divide="ignore"):
        fmean = np.where(diag[0] > 0, diag[1] / diag[0], np.nan)
        amean = np.where(diag[0] > 0, diag[3] / diag[0], np.nan)
    psi = _attr(trace, "bearing_body_angle")
    mean_or = circular_mean(psi, dt) if psi is not None and np.size(psi) == dt.size else 0.0
    return CycleWear(wb * inv, wj * inv, vb * inv, vj * inv, s * inv, diag[0] * inv, fmean, diag[2] * inv, amean,
                     bmax, mean_or, g_level, share)


# --------------------------------------------------------------------------------------------------- results
def find_peaks_periodic(profile: np.ndarray, prominence_fraction: float = 0.05,
                        separation_deg: float = 30.0) -> list[int]:
    """Indices of the peaks of a periodic profile, deepest first (prominence >= fraction of the max, peaks at
    least `separation_deg` apart; of closer ones the deeper is kept)."""
    from scipy.signal import find_peaks

    p = np.asarray(profile, dtype=float)
    n = p.size
    top = float(p.max()) if n else 0.0
    if n == 0 or top <= 0.0:
        return []
    ext = np.concatenate([p, p, p])
    dist = max(1, int(round(separation_deg / 360.0 * n)))
    idx, _ = find_peaks(ext, prominence=prominence_fraction * top, distance=dist)
    idx = sorted({int(i) % n for i in idx if n <= i < 2 * n})
    if not idx:  # a plateau or a single flat-topped hump
        idx = [int(np.argmax(p))]
    return sorted(idx, key=lambda i: -p[i])


@dataclass
class JointWear:
    """Wear of one clearance joint after the history (SI: m, rad, cycles)."""

    index: int
    theta: np.ndarray  # (n_grid,) grid angles in the body frames (rad), 2 pi k / n
    bearing_wear: np.ndarray  # (n_grid,) final bearing depth (m), bearing frame
    journal_wear: np.ndarray  # (n_grid,) final journal depth (m), journal frame
    mean_orientation: float  # rod mean orientation used for reporting (rad)
    history_cycles: np.ndarray
    history_max_bearing: np.ndarray  # m
    history_max_journal: np.ndarray  # m
    history_clearance_growth: np.ndarray  # m (uniform mode: the growth passed to the dynamics)
    volume_bearing: float  # accumulated Archard volume (m^3)
    volume_journal: float
    bearing_radius: float
    journal_radius: float
    width: float
    peaks: list[dict]  # [{"angle_deg", "depth"}] deepest first (depth m)
    diagnostics: CycleWear  # per-cycle quantities of the last block (Fig. 17)
    first_rate: CycleWear  # per-cycle quantities of the first block (unworn geometry)
    contact_half_width: float = math.nan  # m, Johnson's b at the mean contact force of the first block

    @property
    def conformal_arc(self) -> float:
        """Worn arc (rad) of a bore worn to the journal's shape as deep as this one: a journal that has sunk by the
        max bearing depth h into a bore of radial clearance c0 touches it over 2 acos(c0 / (c0 + h))."""
        c0 = self.bearing_radius - self.journal_radius
        return 2.0 * math.acos(c0 / (c0 + self.max_bearing_wear))

    @property
    def conformity(self) -> float:
        """Half the conformal arc over the contact's half-angle b / R_b on the unworn bore (docs/wear.md "When uniform
        mode is fair"). Below 1 the worn pocket is narrower than the contact patch and uniform mode's round-bore
        contact is a fair model; above 1 the journal fits into its own wear and only profile mode is."""
        half = self.contact_half_width / self.bearing_radius
        return 0.5 * self.conformal_arc / half if half > 0.0 else math.inf

    @property
    def uniform_mode_valid(self) -> bool:
        """conformity <= 1: the range in which uniform mode (the paper's Eqs. 36-37) is a fair approximation."""
        return self.conformity <= 1.0

    @property
    def angle_deg(self) -> np.ndarray:
        """Report angle (deg, 0 at the leftmost point, clockwise) of every bearing grid point."""
        return report_angle_deg(self.theta, self.mean_orientation)

    @property
    def journal_angle_deg(self) -> np.ndarray:
        return report_angle_deg(self.theta, 0.0)

    @property
    def max_bearing_wear(self) -> float:
        return float(self.bearing_wear.max())

    @property
    def max_wear_angle_deg(self) -> float:
        return float(self.angle_deg[int(np.argmax(self.bearing_wear))])

    def max_wear_at(self, n_cycles):
        """Max bearing depth (m) at any cycle count(s), linear between history points, linear extrapolation past the end."""
        x = np.asarray(n_cycles, dtype=float)
        c, h = self.history_cycles, self.history_max_bearing
        y = np.interp(x, c, h)
        if c.size >= 2:
            slope = (h[-1] - h[-2]) / (c[-1] - c[-2])
            y = np.where(x > c[-1], h[-1] + slope * (x - c[-1]), y)
        return float(y) if y.ndim == 0 else y


@dataclass
class BlockRecord:
    start: int
    size: int
    peak_rate: float  # max bearing depth rate of joint 0 (m / cycle)
    rate_change: float  # relative change of joint 0's bearing volume rate vs the previous block (nan for the first)
    sim_seconds: float
    n_steps: int


@dataclass
class WearResult:
    """Result of `wear_history` (like SciPy's OdeResult): per-joint wear, history, timings. Joint 0 is the default."""

    joints: list[JointWear]
    settings: WearSettings
    n_cycles: int
    blocks: list[BlockRecord]
    wall_seconds: float
    sim_seconds: float
    n_simulated_cycles: float
    n_steps: int

    @property
    def cycles(self) -> np.ndarray:
        return self.joints[0].history_cycles

    @property
    def max_bearing_wear(self) -> np.ndarray:
        """Max bearing depth (m) at every history point of joint 0."""
        return self.joints[0].history_max_bearing

    def max_wear_at(self, n_cycles, joint: int = 0):
        return self.joints[joint].max_wear_at(n_cycles)

    @property
    def bearing_profile(self) -> np.ndarray:
        return self.joints[0].bearing_wear

    @property
    def journal_profile(self) -> np.ndarray:
        return self.joints[0].journal_wear

    @property
    def peaks(self) -> list[dict]:
        return self.joints[0].peaks

    @property
    def conformity(self) -> float:
        """Joint 0's conformity (JointWear.conformity): above 1, uniform mode is outside its range."""
        return self.joints[0].conformity

    @property
    def uniform_mode_valid(self) -> bool:
        return self.joints[0].uniform_mode_valid


# --------------------------------------------------------------------------------------------------- the loop
def contact_profiles(c0: float, wb: np.ndarray, wj: np.ndarray, settings: WearSettings):
    """Profiles given to the contact search in profile mode and the touching-point maps (None for 'radial')."""
    wb, wj = smoothed_profiles(wb, wj, settings)
    if settings.profile_contact == "radial":
        return wb.copy(), wj.copy(), None, None
    out = []
    for side, w in enumerate((wb, wj)):
        if side == 0 and settings.profile_deposit == "distributed":  # the bearing's touch map is not used
            out.append((None, None))
            continue
        ce = np.empty_like(w)
        idx = np.empty(w.shape[0], dtype=np.int64)
        admissible_set(c0 + w, ce, idx)
        out.append((np.maximum(ce - c0, 0.0), idx))
    # the bearing: the admissible set with its corners rounded (contact.envelope), so that a journal resting in a
    # pocket worn to its own shape meets a smooth contact normal
    rb = np.empty_like(wb)
    rounded_envelope(c0 + wb, PROFILE_ROUNDING * c0, rb)
    out[0] = (np.maximum(rb - c0, 0.0), out[0][1])
    return out[0][0], out[1][0], out[0][1], out[1][1]


def smoothed_profiles(wb: np.ndarray, wj: np.ndarray, settings: WearSettings):
    """The worn profiles as the contact sees them: smoothed over the running-in length, never negative."""
    if settings.profile_smoothing_deg > 0.0:
        wb = np.maximum(smooth_periodic(wb, settings.profile_smoothing_deg), 0.0)
        wj = np.maximum(smooth_periodic(wj, settings.profile_smoothing_deg), 0.0)
    return wb, wj


def _update_geometry(g0, settings: WearSettings, wb: np.ndarray, wj: np.ndarray, growth: float):
    """(geometry for the dynamics, bearing touch map, journal touch map, bore contact profile or None)."""
    if settings.geometry_mode == "profile":
        c0 = float(g0.bearing_radius - g0.journal_radius + (getattr(g0, "clearance_growth", 0.0) or 0.0))
        hb, hj, ib, ij = contact_profiles(c0, wb, wj, settings)
        bore = None
        if settings.profile_deposit == "distributed":
            bore = smoothed_profiles(wb, wj, settings)[0]
            ib = None
        return dataclasses.replace(g0, use_profile=True, bearing_wear=hb, journal_wear=hj), ib, ij, bore
    return dataclasses.replace(g0, use_profile=False, clearance_growth=float(growth)), None, None, None


#: The shares of the load level a bore cell that stands out by eps at a rate g eps (CycleWear.levelling_rate); an
#: explicit update over dn cycles overshoots that when g dn is large, and a ripple of some degrees grows from block to
#: block. A block's wear is therefore laid in sub-steps of at most LEVELLING_STEP / g cycles, re-sharing the same
#: recorded loads over the bore as it wears (the dynamics changes slowly and is not re-run), at most MAX_SUBSTEPS.
LEVELLING_STEP = 2.0
MAX_SUBSTEPS = 16


def _lay_bearing(cw: CycleWear, wb: np.ndarray, wj: np.ndarray, dn: int, settings: WearSettings):
    """Profile mode, distributed deposit: lay a block's bearing wear in sub-steps (see LEVELLING_STEP), each
    increment smoothed over the running-in length as the contact sees the bore (a ripple shorter than it is
    invisible to the shares and would otherwise grow from their grid-scale noise; the profile is the sum of the
    increments, so this smooths it once, not once per block, and conserves the worn area).
    Returns (new profile, Archard volume of the block)."""
    m = int(min(MAX_SUBSTEPS, max(1, math.ceil(cw.levelling_rate * dn / LEVELLING_STEP))))
    wb = wb.copy()
    vol = 0.0
    for j in range(m):
        if j == 0:
            rate, vrate = cw.bearing, cw.volume_bearing
        else:
            rate, vrate, _ = cw.share(smoothed_profiles(wb, wj, settings)[0])
        if settings.profile_smoothing_deg > 0.0:
            rate = np.maximum(smooth_periodic(rate, settings.profile_smoothing_deg), 0.0)
        wb += rate * (dn / m)
        vol += vrate * (dn / m)
    return wb, vol


def _growth(settings: WearSettings, wb: np.ndarray, wj: np.ndarray) -> float:
    if settings.uniform_growth == "bearing_max":
        return float(wb.max())
    return float(wb.max() + wj.max())


def lane_threads(lanes: int) -> int:
    """Threads that run the lanes: min(lanes, cores this process may use), or the environment variable
    JOINTWEAR_LANE_THREADS (set by jointwear.compute's worker processes to cores // workers, so that a pool of
    workers does not oversubscribe the machine). The result never depends on it (see WearSettings.lanes)."""
    from jointwear.compute.executors import available_cores

    env = os.environ.get("JOINTWEAR_LANE_THREADS")
    if env:
        try:
            return max(1, min(lanes, int(env)))
        except ValueError:
            pass
    return max(1, min(lanes, available_cores()))


def wear_history(
    model,
    settings: WearSettings | None = None,
    n_cycles=None,
    *,
    simulate: Callable | None = None,
    geometry: list | None = None,
    progress: Callable[[int, int], Any] | None = None,
) -> WearResult:
    """Run the wear history of every clearance joint of `model` to `n_cycles` crank cycles.

    settings: WearSettings (default: `model.config.wear` if present, else WearSettings()).
    n_cycles: cycles to run (default settings.cycles); validated (finite, > 0, whole).
    simulate: the dynamics entry point (default `jointwear.mechanism.simulate`); injectable for tests.
    geometry: initial ClearanceGeometry list (default `model.initial_geometry()`).
    """
    t_wall = time.perf_counter()
    if settings is None:
        cfg = getattr(model, "config", None)
        settings = getattr(cfg, "wear", None) if cfg is not None else None
        if not isinstance(settings, WearSettings):
            settings = WearSettings.model_validate(settings) if isinstance(settings, dict) else WearSettings()
    if n_cycles is None:
        n_cycles = settings.cycles
        if n_cycles is None:
            raise ValueError("cycles must be given (argument or wear.cycles)")
    n_cycles = check_cycles(n_cycles, "cycles")
    if simulate is None:
        from jointwear.mechanism import simulate as simulate  # noqa: PLW0127
    geoms0 = list(geometry) if geometry is not None else list(model.initial_geometry())
    nj = len(geoms0)
    if nj == 0:
        raise ValueError("the model has no clearance joint: nothing wears")
    n = settings.n_grid
    theta = TWO_PI * np.arange(n) / n
    wb = [np.zeros(n) for _ in range(nj)]
    wj = [np.zeros(n) for _ in range(nj)]
    growth = [float(getattr(g, "clearance_growth", 0.0) or 0.0) for g in geoms0]
    growth0 = list(growth)
    vol_b = [0.0] * nj
    vol_j = [0.0] * nj
    hist_c = [0]
    hist_b = [[0.0] for _ in range(nj)]
    hist_j = [[0.0] for _ in range(nj)]
    hist_g = [[g] for g in growth]
    mats: list[JointMaterials | None] = [None] * nj
    first: list[CycleWear | None] = [None] * nj
    last: list[CycleWear | None] = [None] * nj
    blocks: list[BlockRecord] = []
    done = 0
    block = settings.initial_block if settings.block_rule == "adaptive" else settings.block_cycles
    prev_vrate = None
    sim_seconds = 0.0
    sim_cycles = 0.0
    n_steps = 0
    rec = settings.record_cycles
    # lanes: independent dynamics chains simulating alternate blocks (see WearSettings.lanes). Block k continues
    # from the end state of block k - lanes and sees the wear of blocks 0 .. k - lanes; the schedule, hence the
    # result, does not depend on how many threads run it.
    lanes = settings.lanes if settings.block_rule == "fixed" else 1
    n_blocks = math.ceil(n_cycles / block) if settings.block_rule == "fixed" else None
    lane_state: list = [None] * lanes
    settle0 = settings.settle_cycles_initial
    if settle0 is None and lanes > 1:
        settle0 = _default_settle(model)
        settle0 = settle0 if math.isfinite(settle0) else 1.0
    inflight: deque = deque()
    k_next = 0

    def run_block(geoms, state, settle):
        t0 = time.perf_counter()
        res = simulate(model, rec, geometry=geoms, settle_cycles=settle, state0=state,
                       rtol=settings.rtol, atol=settings.atol)
        return res, time.perf_counter() - t0

    threads = lane_threads(lanes)
    pool = ThreadPoolExecutor(threads, thread_name_prefix="jointwear-lane") if threads > 1 else None
    try:
        while done < n_cycles:
            while len(inflight) < lanes and (k_next < n_blocks if n_blocks is not None else not inflight):
                lane = k_next % lanes
                upd = [_update_geometry(geoms0[i], settings, wb[i], wj[i], growth[i]) for i in range(nj)]
                geoms = [u[0] for u in upd]
                state = lane_state[lane]
                if state is not None:
                    settle = settings.settle_cycles
                else:  # first block of a lane: from rest; lane j settles j / lanes cycle longer (another phase)
                    settle = settle0 + lane / lanes if lane > 0 else settings.settle_cycles_initial
                job = (geoms, state, settle)
                fut = pool.submit(run_block, *job) if pool is not None else run_block(*job)
                inflight.append((lane, upd, geoms, list(growth), settle, fut))
                k_next += 1
            lane, upd, geoms, growth_used, settle, fut = inflight.popleft()
            res, dt_sim = fut.result() if pool is not None else fut
            sim_seconds += dt_sim
            used_settle = getattr(res, "settle_cycles", None)
            if used_settle is None:
                used_settle = settle if settle is not None else _default_settle(model)
            sim_cycles += float(getattr(res, "n_cycles", rec) or rec) + float(used_settle)
            n_steps += int(getattr(res, "n_steps", 0) or 0)
            lane_state[lane] = getattr(res, "state_end", None)
            rates = []
            for i, tr in enumerate(res.joints):
                if mats[i] is None:
                    mats[i] = JointMaterials.from_trace(tr, geoms0[i])
                prof = settings.geometry_mode == "profile"
                cw = cycle_wear(tr, settings, rec, mats[i], growth=growth_used[i],
                                bearing_profile=geoms[i].bearing_wear if prof else None,
                                journal_profile=geoms[i].journal_wear if prof else None,
                                bearing_touch=upd[i][1], journal_touch=upd[i][2], bearing_bore=upd[i][3])
                if first[i] is None:
                    first[i] = cw
                last[i] = cw
                rates.append(cw)
            peak = float(rates[0].bearing.max())
            vrate = rates[0].volume_bearing
            change = float("nan")
            if prev_vrate is not None:
                change = abs(vrate - prev_vrate) / max(prev_vrate, 1e-300)
                if settings.block_rule == "adaptive":
                    if change > 2.0 * settings.rate_tolerance:
                        block = max(settings.min_block, block // 2)
                    elif change < settings.rate_tolerance:
                        block = min(settings.max_block, int(round(block * settings.block_growth)))
            prev_vrate = vrate
            dn = min(block, n_cycles - done)
            for i, cw in enumerate(rates):
                if cw.share is not None:
                    wb[i], vb_add = _lay_bearing(cw, wb[i], wj[i], dn, settings)
                else:
                    wb[i] += cw.bearing * dn
                    vb_add = cw.volume_bearing * dn
                wj[i] += cw.journal * dn
                vol_b[i] += vb_add
                vol_j[i] += cw.volume_journal * dn
                if settings.geometry_mode == "uniform":
                    growth[i] = growth0[i] + _growth(settings, wb[i], wj[i])
                hist_b[i].append(float(wb[i].max()))
                hist_j[i].append(float(wj[i].max()))
                hist_g[i].append(growth[i])
            blocks.append(BlockRecord(done, dn, peak, change, dt_sim, int(getattr(res, "n_steps", 0) or 0)))
            done += dn
            hist_c.append(done)
            if progress is not None:
                progress(done, n_cycles)
    finally:
        if pool is not None:
            for item in inflight:
                item[-1].cancel()
            pool.shutdown(wait=True)

    joints = []
    for i in range(nj):
        mo = first[i].mean_orientation
        jw = JointWear(
            index=i, theta=theta, bearing_wear=wb[i], journal_wear=wj[i], mean_orientation=mo,
            history_cycles=np.asarray(hist_c, dtype=float), history_max_bearing=np.asarray(hist_b[i]),
            history_max_journal=np.asarray(hist_j[i]), history_clearance_growth=np.asarray(hist_g[i]),
            volume_bearing=vol_b[i], volume_journal=vol_j[i], bearing_radius=mats[i].r_b0,
            journal_radius=mats[i].r_j0, width=mats[i].width, peaks=[], diagnostics=last[i], first_rate=first[i],
            contact_half_width=_mean_half_width(first[i], mats[i], settings),
        )
        ang = jw.angle_deg
        jw.peaks = [{"angle_deg": float(ang[k]), "depth": float(wb[i][k])}
                    for k in find_peaks_periodic(wb[i], settings.peak_prominence, settings.peak_separation_deg)]
        joints.append(jw)
    return WearResult(joints, settings, n_cycles, blocks, time.perf_counter() - t_wall, sim_seconds, sim_cycles,
                      n_steps)


def _mean_half_width(cw: CycleWear, mat: JointMaterials, settings: WearSettings) -> float:
    """Johnson's half-width (m) at the time-mean normal force while in contact, on the unworn radii."""
    ct = cw.contact_time
    if not np.any(ct > 0):
        return math.nan
    force = float(np.nansum(np.where(ct > 0, cw.force_mean, 0.0) * ct) / ct.sum())
    rstar = mat.r_b0 * mat.r_j0 / (mat.r_b0 - mat.r_j0)
    return settings.half_width_factor * math.sqrt(force * rstar * (mat.h_b + mat.h_j) / mat.width)


def _default_settle(model) -> float:
    cfg = getattr(model, "config", None)
    for path in (("simulation", "settle_cycles"), ("integrator", "settle_cycles"), ("settle_cycles",)):
        obj = cfg
        for p in path:
            obj = getattr(obj, p, None)
        if isinstance(obj, (int, float)):
            return float(obj)
    return float("nan")


def conservation_error(joint: JointWear) -> tuple[float, float]:
    """Relative error |worn area x width - Archard volume| / volume for the bearing and the journal."""
    eb = abs(worn_area(joint.bearing_wear, joint.bearing_radius) * joint.width - joint.volume_bearing)
    ej = abs(worn_area(joint.journal_wear, joint.journal_radius) * joint.width - joint.volume_journal)
    return eb / max(joint.volume_bearing, 1e-300), ej / max(joint.volume_journal, 1e-300)
