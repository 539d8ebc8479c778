"""Results of the wear history: per-joint profiles and histories, peaks, the block log (typed, SI)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .angles import report_angle_deg
from .cycle import CycleWear
from .kernels import worn_area
from .settings import WearSettings

TOP_TOLERANCE = 1e-3  # cells within 0.1 % of a peak's depth make its top


def top_centre(profile: np.ndarray, index: int, tolerance: float = TOP_TOLERANCE) -> float:
    """Grid position (a fractional, periodic index) of the middle of the top round ``index``: the run of cells next to
    it within ``tolerance`` of its depth. A flat-topped hump (uniform mode under a contact that wanders) has its
    deepest cell anywhere on its top, often at an edge; its middle is where the load acts. A profile flat all round
    has no top to centre: ``index`` itself."""
    p = np.asarray(profile, dtype=float)
    n = p.size
    floor = p[index] - tolerance * abs(p[index])
    left = right = 0
    while left < n and p[(index - left - 1) % n] >= floor:
        left += 1
    while right < n and p[(index + right + 1) % n] >= floor:
        right += 1
    if left + right + 1 >= n:
        return float(index)
    return float((index + 0.5 * (right - left)) % n)


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
    # (n_grid,) the last block's growth of the bearing's depth per cycle (m/cycle), bearing frame: the wear laid, where
    # diagnostics.bearing is the rate its recorded cycles wear on the geometry the block starts from
    last_growth: np.ndarray | None = None

    @property
    def pocket_depth(self) -> float:
        """Depth the journal can sink into its wear, m: the bore's depth range plus the journal's (max less min of
        each). A ring worn evenly round the bore, or round the pin, is no pocket; a flat worn on a pin under a load
        fixed on it is one, as a pocket in the bore is."""
        return float(np.ptp(self.bearing_wear) + np.ptp(self.journal_wear))

    @property
    def conformal_arc(self) -> float:
        """Worn arc (rad) of a bore worn to the journal's shape as deep as this wear: a journal that has sunk by the
        pocket depth h (:attr:`pocket_depth`) into a bore of radial clearance c0 touches it over
        2 acos(c0 / (c0 + h))."""
        c0 = self.bearing_radius - self.journal_radius
        return 2.0 * math.acos(c0 / (c0 + self.pocket_depth))

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
    def max_bearing_wear(self) -> float:
        """Deepest point of the worn bearing at the history's end, m."""
        return float(self.bearing_wear.max())

    def grid_angle_deg(self, position: float) -> float:
        """Report angle (deg, as :attr:`angle_deg`) of a fractional grid position (:func:`top_centre`)."""
        return report_angle_deg(2.0 * math.pi * position / self.theta.size, self.mean_orientation)

    @property
    def max_wear_angle_deg(self) -> float:
        """Report angle (deg, as :attr:`angle_deg`) of the deepest point of the worn bearing: the middle of its top
        (:func:`top_centre`) where the deepest cells make a plateau."""
        return self.grid_angle_deg(top_centre(self.bearing_wear, int(np.argmax(self.bearing_wear))))

    def max_wear_at(self, n_cycles):
        """Max bearing depth (m) at any cycle count(s), as :func:`history_at` reads it."""
        y = history_at(self.history_cycles, self.history_max_bearing, n_cycles)
        return float(y) if y.ndim == 0 else y


def history_at(history_cycles: np.ndarray, series: np.ndarray, n_cycles) -> np.ndarray:
    """A wear history's ``series`` at any cycle count(s): linear between its points, extrapolated linearly from its
    last two past the end (the wear grows linearly in N)."""
    x = np.asarray(n_cycles, dtype=float)
    c = history_cycles
    y = np.interp(x, c, series)
    if c.size >= 2:
        slope = (series[-1] - series[-2]) / (c[-1] - c[-2])
        y = np.where(x > c[-1], series[-1] + slope * (x - c[-1]), y)
    return y


@dataclass
class BlockRecord:
    start: int
    size: int
    peak_rate: float  # max bearing depth rate of joint 0 (m / cycle)
    rate_change: float  # relative change of joint 0's bearing volume rate vs the previous block (nan for the first)
    sim_seconds: float
    n_steps: int
    contact_revolutions: tuple[float, ...] = ()  # per joint: contact-point revolutions per recorded cycle
    whirl: tuple[bool, ...] = ()  # per joint: a friction-driven whirl (jointwear.mechanism.whirl_measure)


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
    stopped_at: int | None = None  # cycles at which a joint was worn away and the history stopped (history.used_up)
    stop_reason: str | None = None

    @property
    def cycles(self) -> np.ndarray:
        """Cycle counts of the history points (joint 0's; every joint shares them)."""
        return self.joints[0].history_cycles

    @property
    def max_bearing_wear(self) -> np.ndarray:
        """Max bearing depth (m) at every history point of joint 0."""
        return self.joints[0].history_max_bearing

    def max_wear_at(self, n_cycles, joint: int = 0):
        """Max bearing depth (m) of joint ``joint`` at any cycle count(s) (:meth:`JointWear.max_wear_at`)."""
        return self.joints[joint].max_wear_at(n_cycles)

    @property
    def bearing_profile(self) -> np.ndarray:
        """Joint 0's bearing wear depth (m) at every grid angle at the history's end."""
        return self.joints[0].bearing_wear

    @property
    def journal_profile(self) -> np.ndarray:
        """Joint 0's journal wear depth (m) at every grid angle at the history's end."""
        return self.joints[0].journal_wear

    @property
    def peaks(self) -> list[dict]:
        """Joint 0's wear peaks (:attr:`JointWear.peaks`)."""
        return self.joints[0].peaks

    @property
    def conformity(self) -> float:
        """Joint 0's conformity (JointWear.conformity): above 1, uniform mode is outside its range."""
        return self.joints[0].conformity

    @property
    def uniform_mode_valid(self) -> bool:
        """Joint 0's :attr:`JointWear.uniform_mode_valid`."""
        return self.joints[0].uniform_mode_valid


def conservation_error(joint: JointWear) -> tuple[float, float]:
    """Relative error |worn area x width - Archard volume| / volume for the bearing and the journal."""
    eb = abs(worn_area(joint.bearing_wear, joint.bearing_radius) * joint.width - joint.volume_bearing)
    ej = abs(worn_area(joint.journal_wear, joint.journal_radius) * joint.width - joint.volume_journal)
    return eb / max(joint.volume_bearing, 1e-300), ej / max(joint.volume_journal, 1e-300)
