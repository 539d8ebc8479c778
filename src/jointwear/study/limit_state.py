"""The wear limit state of a study: which quantity of which clearance joints is judged against which allowance.

For a judged joint j the wear life N_f,j(x) is the cycle count at which its wear quantity q_j(x, N) first
reaches the allowance delta_0,j (paper Eq. 42: G = delta_0 - delta_max). With several judged joints the
mechanism fails when the first of them fails (a series system): N_f(x) = min_j N_f,j(x).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from jointwear.reliability.results import Z95

QUANTITY_LABELS = {
    "bearing_max_depth": "max bearing wear depth",
    "journal_max_depth": "max journal wear depth",
    "clearance_growth": "radial clearance growth",
}


@dataclass(frozen=True)
class LimitState:
    """The judged joints (indices into ``config.clearance_joints`` and names), their allowances (m) and the
    wear quantity."""

    quantity: str
    joints: tuple[int, ...]
    names: tuple[str, ...]
    allowances: tuple[float, ...]

    @property
    def reference_allowance(self) -> float:
        """The allowance a random allowance variable is centred on: that of the first judged joint."""
        return self.allowances[0]

    @property
    def label(self) -> str:
        """The judged quantity as the report names it."""
        return QUANTITY_LABELS[self.quantity]

    def joint_lives(self, history_cycles, outputs: np.ndarray, allowance_draw=None) -> np.ndarray:
        """N_f,j(x) of every judged joint, shape (n, J), from the model outputs (n, J * H).

        ``allowance_draw`` (n,): a sampled allowance of the first joint; every joint's allowance is scaled by
        the same factor (delta_0,j x draw / delta_0,1).
        """
        out = np.atleast_2d(np.asarray(outputs, dtype=float))
        n_hist = len(history_cycles)
        lives = np.empty((out.shape[0], len(self.joints)))
        for k, a in enumerate(self.allowances):
            block = out[:, k * n_hist:(k + 1) * n_hist]
            if allowance_draw is None:
                allowance = a
            else:
                allowance = np.asarray(allowance_draw, dtype=float) * (a / self.reference_allowance)
            lives[:, k] = life_from_history(history_cycles, block, allowance)
        return lives

    def life(self, history_cycles, outputs: np.ndarray, allowance_draw=None) -> np.ndarray:
        """N_f(x) = min_j N_f,j(x), shape (n,); NaN where a call failed."""
        lives = self.joint_lives(history_cycles, outputs, allowance_draw)
        return lives.min(axis=1) if lives.shape[1] > 1 else lives[:, 0]


def limit_state_from_config(config) -> LimitState:
    """The limit state that ``config.reliability`` describes (the config is assumed checked)."""
    rel = config.reliability
    names_all = [cj.name for cj in config.clearance_joints]
    chosen = list(rel.joints) if rel.joints else names_all
    idx = tuple(names_all.index(n) for n in chosen)
    allowances = tuple(joint_allowance(rel, config.clearance_joints[i]) for i in idx)
    return LimitState(rel.quantity, idx, tuple(chosen), allowances)


def archard_trend_applies(config) -> bool:
    """Whether ``reliability.trend = "archard"`` has a known part to tell the Kriging: a random wear coefficient or
    hardness of the judged body of a single judged joint (:func:`archard_power` of some random variable's target)."""
    if config.uncertainty is None:
        return False
    limit = limit_state_from_config(config)
    return any(archard_power(config, limit, spec.target) for spec in config.uncertainty.all_specs())


def archard_power(config, limit: LimitState, target: str) -> int | None:
    """+1 when the judged wear quantity is proportional to the value at ``target`` under Archard's law (the wear
    coefficient of the judged body of the single judged joint), -1 when inversely proportional (its hardness), else
    None."""
    body = {"bearing_max_depth": "bearing_material", "journal_max_depth": "journal_material"}.get(limit.quantity)
    parts = target.split(".")
    if body is None or len(limit.joints) != 1 or len(parts) != 4 or parts[0] != "clearance_joints" or parts[2] != body:
        return None
    names = [cj.name for cj in config.clearance_joints]
    joint = int(parts[1]) if parts[1].isdigit() else (names.index(parts[1]) if parts[1] in names else -1)
    if joint != limit.joints[0]:
        return None
    return {"wear_coefficient": 1, "hardness": -1}.get(parts[3])


def joint_allowance(rel, joint) -> float | None:
    """The allowance of one clearance joint, m: its entry in ``allowances``, else ``allowance``, else 0.01 D with D
    its bearing's outer diameter (the paper's rule); None when none of them is given."""
    if joint.name in rel.allowances:
        return float(rel.allowances[joint.name])
    if rel.allowance is not None:
        return float(rel.allowance)
    if joint.bearing_outer_radius is not None:
        return 0.01 * 2.0 * float(joint.bearing_outer_radius)
    return None


def limit_state_problems(config) -> list[str]:
    """What keeps the configured limit state from being defined (empty when it is)."""
    rel = config.reliability
    names_all = [cj.name for cj in config.clearance_joints]
    problems = []
    if not names_all:
        return ["clearance_joints: the wear study needs at least one clearance joint"]
    chosen = list(rel.joints) if rel.joints else names_all
    unknown = [n for n in chosen if n not in names_all]
    if unknown:
        problems.append(f"reliability.joints: {unknown} are not clearance joints (have: {names_all})")
    if rel.joints is not None and not rel.joints:
        problems.append("reliability.joints: give at least one clearance joint (or leave it out for all)")
    extra = [n for n in rel.allowances if n not in chosen]
    if extra:
        suffixed = [n for n in extra if "_" in n and n.rsplit("_", 1)[0] in chosen]  # 'E_mm': a unit on one entry
        joint = suffixed[0].rsplit("_", 1)[0] if suffixed else ""
        hint = (f"; a unit suffix goes on the table, not on a joint: allowances_mm = {{{joint} = ...}} in TOML, "
                f"{{\"reliability.allowances_mm\": {{\"{joint}\": ...}}}} in updated()" if suffixed else "")
        problems.append(f"reliability.allowances: {extra} are not judged joints (judged: {chosen}){hint}")
    for n in chosen:
        if n not in names_all:
            continue
        joint = config.clearance_joints[names_all.index(n)]
        if joint_allowance(rel, joint) is None:
            problems.append(f"reliability.allowance: required for joint {n} (or give clearance_joints.{n}."
                            "bearing_outer_radius for the default 0.01 D)")
    return problems + allowance_stock_problems(config, [n for n in chosen if n in names_all])


def allowance_stock_problems(config, joints: list[str] | None = None) -> list[str]:
    """Each allowance of ``joints`` (default: every clearance joint) at or beyond what its part can wear
    (:func:`wearable_stock`): the part is worn through before the quantity reaches it. The wear stage draws and tells
    the allowance too, so this holds without a reliability stage."""
    rel = config.reliability
    problems = []
    for joint in config.clearance_joints:
        if joints is not None and joint.name not in joints:
            continue
        allowance = joint_allowance(rel, joint)
        stock = wearable_stock(rel.quantity, joint)
        if allowance is not None and stock is not None and allowance >= stock[0]:
            where = f"reliability.allowances.{joint.name}" if joint.name in rel.allowances else "reliability.allowance"
            problems.append(f"{where}: {allowance * 1e3:.6g} mm for joint {joint.name} is not less than its {stock[1]} "
                            f"({stock[0] * 1e3:.6g} mm): the part is worn through before the "
                            f"{QUANTITY_LABELS[rel.quantity]} reaches it (a unit slip? without a suffix the allowance "
                            "is in m: allowance_mm, allowance_um; or in the joint's radii, whose difference that is)")
    return problems


def wearable_stock(quantity: str, joint) -> tuple[float, str] | None:
    """The most the judged wear quantity of ``joint`` can grow before a part is worn through (m), and what that is:
    the bearing's wall (outer - inner radius), the journal's radius, or both for the clearance growth; None where
    the bearing's outer radius is needed and not given."""
    wall = None if joint.bearing_outer_radius is None else joint.bearing_outer_radius - joint.bearing_radius
    if quantity == "journal_max_depth":
        return float(joint.journal_radius), "journal radius"
    if wall is None:
        return None
    if quantity == "bearing_max_depth":
        return float(wall), "bearing wall (bearing_outer_radius - bearing_radius)"
    return float(wall + joint.journal_radius), "bearing wall plus journal radius"


def life_from_history(cycles, wear, allowance) -> np.ndarray:
    """Cycles N_f at which the wear quantity first reaches the allowance, for each row of ``wear`` (n, H).

    Linear interpolation in the history (which starts at zero wear at N = 0); past the last history point,
    linear extrapolation with the slope of the last history segment (the wear grows linearly in N, paper
    Fig. 20). NaN rows (failed calls) give NaN; a history that stops growing gives +inf.
    """
    n_h = np.concatenate([[0.0], np.asarray(cycles, dtype=float)])
    w = np.atleast_2d(np.asarray(wear, dtype=float))
    w = np.concatenate([np.zeros((w.shape[0], 1)), w], axis=1)
    a = np.broadcast_to(np.asarray(allowance, dtype=float).reshape(-1), (w.shape[0],))
    out = np.full(w.shape[0], np.nan)
    for i in range(w.shape[0]):
        row = w[i]
        if not np.all(np.isfinite(row)):
            continue
        above = np.nonzero(row >= a[i])[0]
        if above.size:
            k = above[0]
            w0, w1 = row[k - 1], row[k]
            out[i] = n_h[k - 1] + (a[i] - w0) * (n_h[k] - n_h[k - 1]) / (w1 - w0)
        else:
            slope = (row[-1] - row[-2]) / (n_h[-1] - n_h[-2])
            out[i] = np.inf if slope <= 0 else n_h[-1] + (a[i] - row[-1]) / slope
    return out


#: points of the curve where the life is read, at least (its levels included). A straight line between points
#: misses a curved R(N) by the square of their spacing: between levels 100,000 cycles apart, 8 points per interval
#: still read a life 0.6 % short on the two-joint analytic model; 256 over the curve leave about 0.01 %
LIFE_CURVE_POINTS = 256


def curve_cycles(levels, subdivisions: int | None = None) -> np.ndarray:
    """The curve's levels with ``subdivisions - 1`` evenly spaced cycle counts between each two (sorted); by default
    as many as give :data:`LIFE_CURVE_POINTS` points over the curve."""
    levels = np.asarray(levels, dtype=float)
    if levels.size < 2:
        return levels.copy()
    if subdivisions is None:
        subdivisions = -(-LIFE_CURVE_POINTS // (levels.size - 1))
    steps = np.linspace(0.0, 1.0, subdivisions + 1)[:-1]
    inner = (levels[:-1, None] + steps[None, :] * np.diff(levels)[:, None]).ravel()
    return np.append(inner, levels[-1])


def life_at(cycles, reliability, target: float) -> float | None:
    """First cycle count where R(N) falls to ``target``, by linear interpolation of R(N); None when that
    crossing is not inside the curve (see :func:`life_status`)."""
    r = np.asarray(reliability, dtype=float)
    n = np.asarray(cycles, dtype=float)
    below = np.nonzero(r <= target)[0]
    if below.size == 0 or below[0] == 0:
        return None
    i = below[0]
    r0, r1 = r[i - 1], r[i]
    if r0 == r1:
        return float(n[i])
    return float(n[i - 1] + (r0 - target) * (n[i] - n[i - 1]) / (r0 - r1))


def curve_half_width(pf, pf_cov, pf_error=None) -> np.ndarray:
    """95 % half-width of an R(N) estimate at each level: the Monte Carlo part 1.96 COV(Pf) Pf plus the
    surrogate's own absolute error estimate ``pf_error`` (each taken as 0 where it is undefined, e.g. the COV
    where Pf = 0). The band the report draws and the validation compares with."""
    pf = np.asarray(pf, dtype=float)
    cov = np.asarray(pf_cov, dtype=float)
    half = Z95 * np.where(np.isfinite(cov), cov, 0.0) * pf
    if pf_error is not None:  # an unbounded estimate leaves R anywhere in [0, 1]
        half = half + np.nan_to_num(np.asarray(pf_error, dtype=float), posinf=1.0)
    return half


def life_interval(cycles, reliability, half_width, target: float) -> tuple[float | None, float | None]:
    """The 95 % interval of the life at ``target``: where the band R -/+ ``half_width`` crosses the target
    (linear interpolation, as :func:`life_at`). The true curve lies in the band at each level, so its crossing
    lies between the band's crossings. A side is None where its crossing is not inside the curve: the low end
    when R - half is at or below the target already at the first level, the high end when R + half stays above it
    to the last."""
    r = np.asarray(reliability, dtype=float)
    half = np.asarray(half_width, dtype=float)
    return life_at(cycles, r - half, target), life_at(cycles, r + half, target)


def interval_reach(cycles, reliability, half_width, target: float) -> tuple[float, float]:
    """:func:`life_interval`'s ends as numbers, for comparing two intervals: an end outside the curve becomes the
    bound its side gives. Before the first level a low end reaches -inf and a high end at most that level; beyond
    the last level a low end is at least that level and a high end reaches +inf. (A life before one curve and inside
    another read 'within the errors' when both missing ends counted as unbounded.)"""
    r, h = np.asarray(reliability, dtype=float), np.asarray(half_width, dtype=float)
    return bounded_ends(cycles, r - h, r + h, target, *life_interval(cycles, reliability, half_width, target))


def bounded_ends(cycles, lower, upper, target: float, low: float | None, high: float | None) -> tuple[float, float]:
    """The ends ``low``, ``high`` of a life interval read where the curves ``lower`` and ``upper`` (R's bounds at
    the levels ``cycles``) cross ``target``, with an end outside the curve (None) replaced by the bound its side
    gives (:func:`interval_reach`)."""
    c, lo_r, up_r = (np.asarray(a, dtype=float) for a in (cycles, lower, upper))
    if low is None:
        low = -math.inf if lo_r[0] <= target else float(c[-1])
    if high is None:
        high = float(c[0]) if up_r[0] <= target else math.inf
    return low, high


def intervals_overlap(low: float | None, high: float | None, other_low: float | None,
                      other_high: float | None) -> bool:
    """Whether two life intervals share a point; an end that is None (outside its curve) reaches as far as it
    may."""
    lo = max(-math.inf if low is None else low, -math.inf if other_low is None else other_low)
    hi = min(math.inf if high is None else high, math.inf if other_high is None else other_high)
    return lo <= hi


def life_status(reliability, target: float) -> str:
    """Where the life at ``target`` lies: 'in_curve', 'beyond_curve' (R stays above the target to the last
    level: the life is longer than the curve) or 'before_curve' (R is already at or below the target at the
    first level: the life is shorter than the curve's start)."""
    r = np.asarray(reliability, dtype=float)
    below = np.nonzero(r <= target)[0]
    if below.size == 0:
        return "beyond_curve"
    return "before_curve" if below[0] == 0 else "in_curve"


#: where a life outside the curve lies, by its :func:`life_status`, and the setting that brings it in
OUTSIDE_CURVE = {"before_curve": ("before the curve's first level", "lower cycles_start"),
                 "beyond_curve": ("beyond the curve's last level", "extend cycles_stop")}


#: the wear history's key (wear.json, each joint's ``history``) of each judged quantity, in mm
HISTORY_KEYS = {"bearing_max_depth": "max_wear_mm", "journal_max_depth": "max_journal_wear_mm",
                "clearance_growth": "clearance_growth_mm"}

#: a nominal life this many times beyond the curve's last level (or short of its first) is worth a warning
CURVE_MISS_FACTOR = 2.0


def nominal_lives(joints: list[dict], allowances_mm: dict[str, float], quantity: str) -> dict[str, float]:
    """Each named joint's cycles to its allowance (mm) in the nominal wear history (``joints`` of wear.json),
    extrapolated linearly past the history's end (inf where it stops growing); a joint without that history is
    left out."""
    by_name = {str(j.get("name")): j.get("history") or {} for j in joints}
    lives = {}
    for name, allowance in allowances_mm.items():
        life = history_life(by_name.get(name) or {}, allowance, quantity)
        if life is not None:
            lives[name] = life
    return lives


def history_life(history: dict, allowance_mm: float, quantity: str) -> float | None:
    """The cycles at which a joint's nominal wear history (a ``joints[].history`` of wear.json) reaches
    ``allowance_mm`` in the judged ``quantity``, extrapolated linearly past its end (inf where it stops growing);
    None where the history lacks that quantity."""
    depth = history.get(HISTORY_KEYS[quantity])
    if not depth:
        return None
    return float(life_from_history(history["cycles"], [depth], float(allowance_mm))[0])


def life_within_history(history: dict, allowance_mm: float | None, quantity: str) -> float | None:
    """:func:`history_life` within the history only: None where the history stays below the allowance (a count past
    the history is not known from it) or there is no allowance."""
    life = None if allowance_mm is None else history_life(history, allowance_mm, quantity)
    return life if life is not None and life <= max(history["cycles"]) else None


#: a nominal life more than this many times the wear history's length is told as only that (project choice)
NOMINAL_LIFE_FAR = 1000


def nominal_life_line(config, joints: list[dict]) -> str:
    """When the nominal design's wear history (``joints`` of wear.json) reaches each judged joint's allowance:
    'the nominal design reaches its allowance (0.03 mm of bearing max depth) after about 148,749 cycles ...', one
    clause per judged joint; empty without a limit state or where the history stops growing."""
    if limit_state_problems(config):
        return ""
    ls = limit_state_from_config(config)
    allowances = {name: a * 1e3 for name, a in zip(ls.names, ls.allowances)}
    lives = {name: life for name, life in nominal_lives(joints, allowances, ls.quantity).items() if np.isfinite(life)}
    if not lives:
        return ""
    measure = ls.quantity.replace("_", " ")
    end = history_end(joints)

    def after(n: float) -> str:  # a straight line drawn far past the history says only that it is far
        far = NOMINAL_LIFE_FAR * end
        return f"after more than {far:,.0f}" if end > 0 and n > far else f"after about {n:,.0f}"

    (first, life), *rest = lives.items()
    whose = "its" if len(allowances) == 1 else f"joint {first}'s"
    reached = (f"{whose} allowance ({allowances[first]:.3g} mm of {measure}) {after(life)} cycles"
               + "".join(f", joint {name}'s ({allowances[name]:.3g} mm) {after(n)}" for name, n in rest))
    return f"the nominal design reaches {reached} (read off {how_read(max(lives.values()), end)})"


def history_end(joints: list[dict]) -> float:
    """The last cycle count of the nominal wear histories (``joints`` of wear.json); 0 without one."""
    return max((max(j.get("history", {}).get("cycles") or [0.0]) for j in joints), default=0.0)


#: a life read more than this many times the history's length past its end is told as rough (project choice)
LONG_EXTRAPOLATION = 3.0


def how_read(life: float, end: float) -> str:
    """How a nominal life was read off a history ending at ``end`` cycles. A straight line drawn far past the end
    reads long where the depth grows faster than linearly (uniform mode under a steady load) and short where it
    grows slower (profile mode's widening pocket): docs/tutorial.md, section 4."""
    if life <= end:
        return "its wear history"
    if LONG_EXTRAPOLATION * end < life <= NOMINAL_LIFE_FAR * end:
        return (f"its wear history, extrapolated linearly to {life / end:.2g} times its length: a rough reading where "
                "the depth's growth is not steady; a history that long, wear.cycles or --cycles, reads it")
    return "its wear history, extrapolated linearly past its end"


def nominal_life_outside_curve(config, joints: list[dict]) -> str:
    """Where the nominal design's wear history (``joints`` of wear.json) reaches the allowance, when that lies more
    than ``CURVE_MISS_FACTOR`` times beyond the R(N) curve's last level or short of its first: the curve would then
    read R near 1 (or 0) at every level, and the reliability stage would spend its calls on it (empty otherwise, and
    without an R(N) curve)."""
    rel = config.reliability
    if config.uncertainty is None or rel.curve_problems() or limit_state_problems(config):
        return ""
    ls = limit_state_from_config(config)
    lives = nominal_lives(joints, {name: a * 1e3 for name, a in zip(ls.names, ls.allowances)}, ls.quantity)
    life = min(lives.values(), default=float("nan"))
    if not np.isfinite(life):
        return ""
    whose = "" if len(lives) < 2 else f" (joint {min(lives, key=lives.get)}'s, the first to reach its own)"
    first, last = rel.cycles_start, rel.cycles_stop
    if life > CURVE_MISS_FACTOR * last:
        where, reads = f"{life / last:.1f} times the R(N) curve's last level ({last:,} cycles)", "close to 1"
    elif life < first / CURVE_MISS_FACTOR:
        where, reads = f"{first / life:.1f} times short of the R(N) curve's first level ({first:,} cycles)", "near 0"
    else:
        return ""
    return (f"the nominal design reaches its allowance{whose} after about {life:,.0f} cycles "
            f"({how_read(life, history_end(joints))}), {where}: the curve will read R {reads} at every level; put it "
            "round the nominal life (reliability.cycles_start, cycles_stop), about 0.6 to 1.5 times it")
