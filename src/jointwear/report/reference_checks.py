"""The study's numbers beside its cited reference results (the config's ``[reference]``, see
:mod:`jointwear.reference`): one :class:`Check` per reference value, with its acceptance band and status.

Shared by the report's comparison section and :mod:`jointwear.report.compare` (Markdown for the docs).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from jointwear.study.results import ReliabilityCurve, SensitivityResult, StudyResults, WearSummary
from jointwear.study.stage_lines import curve_misses_life_line

from .markup import format_number

__all__ = ["Check", "CheckTally", "tally", "checks_summary", "PASS", "FAIL", "INFO", "NA", "reference_checks",
           "reference_of", "reference_values", "reference_label", "group_key", "second_peak", "life_with_note",
           "circular_difference", "ranking_rows"]

PASS, FAIL, INFO, NA = "pass", "fail", "info", "n/a"

#: how dimensionless reference quantities are labelled in the comparison ("-": a plain number)
_COUNT_UNITS = {"life_cycles": "cycles", "model_calls": "calls", "reliability": "-"}


@dataclass
class Check:
    """One number of the study beside the reference's, with its acceptance band and status."""

    quantity: str
    reference: float | None
    ours: float | None
    unit: str
    band: str
    status: str
    note: str = ""
    digits: int = 4
    source: str = ""
    justification: str = ""
    #: an order of variables, not a number: it can match the reference's (pass) but never fails, so the tally
    #: counts it apart from the judged numbers
    ranking: bool = False
    #: a ranking that differs from the reference's only between neighbours the study does not separate
    within_error: bool = False
    #: a probability, whose difference is read in absolute terms (a relative one round R = 0.006 read +2642.8 %)
    absolute: bool = False

    @property
    def rel_diff(self) -> float | None:
        """(ours - reference) / |reference|; None for an angle, whose origin is a convention (its note gives the
        difference in degrees), and for a probability (:attr:`absolute`)."""
        if self.reference in (None, 0) or self.ours is None or self.unit == "deg" or self.absolute:
            return None
        return (self.ours - self.reference) / abs(self.reference)

    @property
    def difference_text(self) -> str:
        """The difference as the comparison shows it: '+6.5 %', '+0.159 absolute' for a probability, an em dash
        where there is none (an angle's is in its note)."""
        if self.absolute and self.reference is not None and self.ours is not None:
            return f"{self.ours - self.reference:+.3f} absolute"
        return "\u2014" if self.rel_diff is None else f"{self.rel_diff * 100:+.1f} %"


def _float(v) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def circular_difference(a: float, b: float) -> float:
    """Smallest angle between two angles, deg."""
    d = abs((a - b) % 360.0)
    return min(d, 360.0 - d)


def _interp_at(xs, ys, x: float) -> float | None:
    """Linear interpolation of (xs, ys) at x; None outside the data."""
    xs = np.asarray(xs, dtype=float)
    ys = np.asarray([np.nan if v is None else v for v in ys], dtype=float)
    ok = np.isfinite(xs) & np.isfinite(ys)
    xs, ys = xs[ok], ys[ok]
    if xs.size == 0 or x < xs.min() - 1e-9 or x > xs.max() + 1e-9:
        return None
    order = np.argsort(xs)
    return float(np.interp(x, xs[order], ys[order]))


# ------------------------------------------------------------------------------------------- the reference
def reference_of(config: Mapping | None) -> dict | None:
    """The cited reference results of the study (``reference`` of its ``config.json``), or None."""
    ref = (config or {}).get("reference")
    if isinstance(ref, Mapping) and ref.get("values"):
        return dict(ref)
    return None


def reference_values(ref: Mapping | None, quantity: str) -> list[Mapping]:
    """The reference's values of one quantity, in the order the config gives them."""
    return [v for v in (ref or {}).get("values") or [] if v.get("quantity") == quantity]


def reference_label(ref: Mapping | None) -> str:
    """Short name of the reference for figures and tables ('reference' when it has none)."""
    return str((ref or {}).get("label") or "reference")


def group_key(group: object) -> str:
    """'tolerances' / 'tolerance' / 'bearing material' / 'bearing_material' -> one key."""
    g = str(group or "").strip().lower().replace(" ", "_")
    return g[:-1] if g.endswith("s") else g


def _readable(band: Mapping | None) -> Mapping | None:
    """The band, or None when it says nothing a number can be judged by (an unknown kind without limits, as in a
    tampered config.json): judged as no band, not as a pass."""
    if band is None or band.get("kind") in ("absolute", "relative", "same_order"):
        return band
    return band if _float(band.get("lower")) is not None or _float(band.get("upper")) is not None else None


def _band_text(band: Mapping | None, unit: str) -> str:
    if band is None:
        return "reported (no band)"
    kind = band.get("kind")
    u = "" if unit in ("", "-") else f" {unit}"
    if kind == "absolute":
        a = float(band["absolute"])
        return f"within {a:g}{u}" if unit == "deg" else (f"\u00b1{a:g} absolute" if not u else f"\u00b1{a:g}{u}")
    if kind == "relative":
        return f"within {100 * float(band['relative']):g} %"
    if kind == "same_order":
        return "same order as the reference"
    lo, hi = _float(band.get("lower")), _float(band.get("upper"))
    if lo is not None and hi is not None:
        return f"{lo:g}-{hi:g}{u}"
    return f"\u2264 {hi:g}{u}" if hi is not None else f"\u2265 {lo:g}{u}"


def _judge(ours: float | None, ref: float | None, band: Mapping | None, unit: str) -> str:
    """PASS / FAIL inside or outside the band, INFO without a band, NA without our number."""
    if ours is None:
        return NA
    if band is None or ref is None and band.get("kind") in ("absolute", "relative"):
        return INFO
    kind = band.get("kind")
    if kind == "absolute":
        d = circular_difference(ours, ref) if unit == "deg" else abs(ours - ref)
        return PASS if d <= float(band["absolute"]) else FAIL
    if kind == "relative":
        return PASS if abs(ours - ref) <= float(band["relative"]) * abs(ref) else FAIL
    lo, hi = _float(band.get("lower")), _float(band.get("upper"))
    return PASS if (lo is None or ours >= lo) and (hi is None or ours <= hi) else FAIL


# ------------------------------------------------------------------------------------------- the study's side
def second_peak(wear: WearSummary) -> tuple[float, float] | None:
    """(angle deg, depth mm) of the largest wear more than 90 deg from the main peak."""
    main = wear.max_wear_angle_deg
    far = [(p["angle_deg"], p["depth_mm"]) for p in wear.peaks
           if main is not None and circular_difference(p["angle_deg"], main) > 90.0]
    if far:
        return max(far, key=lambda p: p[1])
    ang = np.asarray(wear.profile.get("angle_deg", []), dtype=float)
    dep = np.asarray(wear.profile.get("depth_mm", []), dtype=float)
    if main is None or ang.size == 0:
        return None
    mask = np.array([circular_difference(a, main) > 90.0 for a in ang])
    if not mask.any():
        return None
    i = int(np.argmax(np.where(mask, dep, -np.inf)))
    return float(ang[i]), float(dep[i])


def _mean_max_wear(rel: ReliabilityCurve, levels) -> dict[float, float]:
    """The study's mean of the max wear (mm) at each of ``levels`` (cycles) where it has one."""
    m = rel.mean_max_wear_mm
    out: dict[float, float] = {}
    for n in levels:
        v = _interp_at(m["cycles"], m["mean"], n) if m.get("cycles") else None
        if v is not None:
            out[n] = v
    return out


def life_with_note(rel: ReliabilityCurve, target: float) -> tuple[float | None, str]:
    """The study's life at ``target`` (cycles) and a note on how it was read: from the life table, else
    interpolated on the curve; 'at most' when R is below the target at the curve's first level."""
    row = rel.life_row(target)
    life = None if row is None else row.get("cycles")
    note = ""
    if life is None and row is None:
        life = rel.life(target)
        note = "read on the R(N) curve" if life is not None else ""
    status = None if row is None else row.get("status")
    if status == "before_curve" or (rel.cycles.size and rel.reliability[0] < target and life is not None
                                    and life <= rel.cycles[0]):
        life = float(rel.cycles[0])
        note = (f"R = {rel.reliability[0]:.3f} < {target:g} already at the first cycle count of the curve "
                f"({rel.cycles[0]:,.0f}): the life is at most this")
    return life, note


def curve_misses_life(rel: ReliabilityCurve, wear: WearSummary | None) -> str | None:
    """:func:`~jointwear.study.stage_lines.curve_misses_life_line` with its setting names as code."""
    return curve_misses_life_line(rel, wear, code=lambda name: f"<code>{name}</code>")


def _life_hours(rel: ReliabilityCurve, target: float) -> float | None:
    row = rel.life_row(target)
    if row is not None and row.get("hours") is not None:
        return float(row["hours"])
    life, _note = life_with_note(rel, target)
    return rel.hours(life)


def _swing(var: Mapping, nominal: float) -> float:
    return max(abs(var["reliability_low"] - nominal), abs(var["reliability_high"] - nominal))


def ranking_rows(sens: SensitivityResult) -> dict[str, list[tuple[str, str]]]:
    """Per group, (name, label) of its variables by decreasing effect on R."""
    out: dict[str, list] = {}
    for v in sorted(sens.variables, key=lambda v: -_swing(v, sens.reliability_nominal)):
        out.setdefault(str(v.get("group") or "variables"), []).append((str(v["name"]), str(v.get("label") or v["name"])))
    return out


def ranking_text(items: Sequence[tuple[str, str]], unresolved: set[tuple[str, str]]) -> str:
    """'a > b ≈ c': ≈ between neighbours whose order is within the surrogate's error."""
    text = ""
    for k, (name, label) in enumerate(items):
        if k:
            text += " \u2248 " if (items[k - 1][0], name) in unresolved else " > "
        text += label
    return text


def unresolved_pairs(sens: SensitivityResult) -> set[tuple[str, str]]:
    """(first, second) names of ranking neighbours the study's surrogate error does not separate."""
    return {(str(p["first"]), str(p["second"])) for p in sens.unresolved_pairs}


def _ranking_check(sens: SensitivityResult | None, v: Mapping) -> Check:
    group = str(v.get("group") or "")
    title = f"sensitivity ranking, {'tolerances' if group_key(group) == 'tolerance' else group.replace('_', ' ')}"
    ref_rank = [str(x) for x in v.get("ranking") or []]
    band = _readable(v.get("band"))
    src, just = str(v.get("source") or ""), str((v.get("band") or {}).get("justification") or "")
    rows = {} if sens is None else {group_key(g): items for g, items in ranking_rows(sens).items()}
    members = rows.get(group_key(group), [])
    labels = {n: lab for n, lab in members}
    if not members:
        return Check(title, None, None, "", _band_text(band, ""), NA, " > ".join(ref_rank), source=src,
                     justification=just, ranking=True)
    names = [n for n, _lab in members]
    ours_rank = [n for n in names if n in ref_rank]
    ref_shown = [n for n in ref_rank if n in names]
    same = bool(ours_rank) and ours_rank == ref_shown
    top = bool(ours_rank) and ours_rank[0] == ref_shown[0]
    unresolved = unresolved_pairs(sens)
    tied = [f"{labels[a]} \u2248 {labels[b]}" for a, b in zip(names, names[1:])
            if (a, b) in unresolved and a in ref_rank and b in ref_rank]
    tied_top = len(ours_rank) > 1 and (ours_rank[0], ours_rank[1]) in unresolved
    within = not same and bool(ours_rank) and order_within_ties(names, unresolved, ref_shown)
    not_here = [n for n in ref_rank if n not in names]
    verdict = (" (the same order within the surrogate's error)" if within else
               " (same most influential" + (", not resolved from the next" if tied_top else "") + ")" if top else
               " (differs)")
    note = (f"ours: {' > '.join(labels[n] for n in ours_rank)} | reference: "
            f"{' > '.join(labels.get(n, n) for n in ref_rank)}" + ("" if same else verdict)
            + (f"; not resolved within the surrogate's error: {', '.join(tied)}" if tied else "")
            + (f"; not in this study: {', '.join(not_here)}" if not_here else ""))
    status = PASS if same and band is not None else INFO
    return Check(title, None, None, "", _band_text(band, ""), status, note, source=src, justification=just,
                 ranking=True, within_error=within)


def order_within_ties(ranking: Sequence[str], unresolved: set[tuple[str, str]], order: Sequence[str]) -> bool:
    """Whether ``order`` (some of ``ranking``'s names) is ``ranking`` with only neighbours the study does not separate
    swapped: the names fall into runs joined by ``unresolved`` (first, second) neighbour pairs, and ``order`` visits
    the runs in ``ranking``'s order."""
    run, runs = 0, {}
    for k, name in enumerate(ranking):
        if k and (ranking[k - 1], name) not in unresolved:
            run += 1
        runs[name] = run
    visited = [runs[n] for n in order if n in runs]
    return all(a <= b for a, b in zip(visited, visited[1:]))


def _nominal_wear(wear: WearSummary | None, n: float) -> tuple[float | None, str]:
    if wear is None:
        return None, "no wear result"
    if wear.cycles == n:
        ours, note = wear.max_wear_mm, ""
    else:
        ours = _interp_at(wear.history["cycles"], wear.history["max_wear_mm"], n)
        note = "read from the wear history" if ours is not None else f"the wear run stopped at {wear.cycles:,} cycles"
    return ours, (note + "; " if note else "") + f"geometry mode: {wear.geometry_mode}"


def reference_checks(results: StudyResults, reference: Mapping | None = None) -> list[Check]:
    """Every number the reference reports beside the study's, in the order the reference lists them.

    ``reference`` (report units) defaults to the one in the study's ``config.json``; without a reference there
    is nothing to compare and the list is empty.
    """
    ref = reference if reference is not None else reference_of(results.config)
    if not ref:
        return []
    wear, rel, sens = results.wear, results.reliability, results.sensitivity
    means = {} if rel is None else _mean_max_wear(
        rel, [float(v["cycles"]) for v in reference_values(ref, "mean_max_wear")])
    sp = None if wear is None else second_peak(wear)
    checks: list[Check] = []
    for v in ref["values"]:
        q = v.get("quantity")
        if q == "sensitivity_ranking":
            checks.append(_ranking_check(sens, v))
            continue
        pv, n, t = _float(v.get("value")), _float(v.get("cycles")), _float(v.get("target_reliability"))
        unit = str(v.get("unit") or "")
        shown_unit = _COUNT_UNITS.get(q, unit)
        band = _readable(v.get("band"))
        ours, note, digits = None, "", 4
        if q == "nominal_max_wear":
            title = f"nominal max bearing wear after {n:,.0f} cycles"
            ours, note = _nominal_wear(wear, n)
        elif q == "nominal_max_wear_angle":
            title = "angle of the max wear"
            ours = None if wear is None else wear.max_wear_angle_deg
        elif q == "second_peak_depth":
            title = "second wear peak, depth"
            ours = None if sp is None else sp[1]
            note = "largest wear more than 90 deg from the main peak" if sp else ""
        elif q == "second_peak_angle":
            title = "second wear peak, angle"
            ours = None if sp is None else sp[0]
        elif q == "mean_max_wear":
            title = f"mean of the max wear at {n:,.0f} cycles"
            ours = means.get(n)
            note = ("over the random inputs, read from the life surrogate as allowance x N / N_f (linear growth), "
                    "not from the nominal history" if ours is not None else "")
        elif q == "reliability":
            title, digits = f"reliability R(N) at {n:,.0f} cycles", 3
            # between the levels, read on the curve the surrogate gives there (life_curve), as the life is, not on a
            # straight line between two levels
            fine = None if rel is None or n in set(map(float, rel.cycles)) else rel.fine_curve()
            ours = (None if rel is None else _interp_at(rel.cycles, rel.reliability, n) if fine is None
                    else _interp_at(fine[0], fine[1], n))
            note = "outside the computed curve" if rel is not None and ours is None else ""
            if ours is not None and pv is not None:
                note = f"absolute difference {ours - pv:+.3f}"
                e_n = _interp_at(rel.cycles, rel.pf_error, n)
                if e_n is not None:
                    # the surrogate's own error estimate of Pf (= of R) here: a pass or fail closer to the band
                    # edge than this is not resolved by the study
                    note += f"; surrogate error estimate {e_n:.3f}"
                if pv > 0 and not 0.5 <= ours / pv <= 2.0:
                    # an absolute band round a small R passes a value many times it: say so beside the status
                    passed = _judge(ours, pv, band, unit) == PASS
                    note += f"; {ours / pv:.3g} times the reference's R" + (": within the absolute band only"
                                                                           if passed else "")
        elif q == "life_cycles":
            title = f"life at R = {t:g}"
            ours, note = (None, "") if rel is None else life_with_note(rel, t)
        elif q == "life_hours":
            rpm = None if rel is None else rel.crank_speed_rpm
            title = f"life at R = {t:g}, " + (f"hours at {rpm:g} rpm" if rpm else "in hours")
            ours = None if rel is None else _life_hours(rel, t)
        elif q == "model_calls":
            title = "true-model calls (whole curve)"
            ours = None if rel is None else float(rel.model_calls)
            if rel is not None and not rel.converged:  # the calls stayed within the budget because it ended them
                note = ("the learning did not converge: its budget ended the calls before its stop was confirmed, "
                        "so a goal of calls with a confirmed stop is not met")
        else:  # a quantity this version does not compare: listed, not judged
            title = str(q)
        if q in ("nominal_max_wear_angle", "second_peak_angle") and ours is not None and pv is not None:
            note = f"{circular_difference(ours, pv):.1f} deg from the reference's"
        note = "; ".join(x for x in (note, str(v.get("note") or "")) if x)
        status = _judge(ours, pv, band, unit)
        if q == "model_calls" and status == PASS and rel is not None and not rel.converged:
            status = FAIL
        checks.append(Check(title, pv, ours, shown_unit, _band_text(band, unit), status, note,
                            digits, source=str(v.get("source") or ""),
                            justification=str((v.get("band") or {}).get("justification") or ""),
                            absolute=q == "reliability"))
    return checks


@dataclass(frozen=True)
class CheckTally:
    """How the checks came out: the judged numbers by status, the rankings apart (they cannot fail)."""

    passed: int
    failed: int
    unbanded: int
    no_data: int
    rankings: int
    rankings_same: int
    rankings_within_error: int = 0

    @property
    def judged(self) -> int:
        """Numbers with a band and a value of the study's: the denominator of 'n / m within their band'."""
        return self.passed + self.failed

    def details(self) -> str:
        """'2 outside the band; 2 reported without a band; 1 without data; rankings: 0 of 3 in the reference's
        order' (the parts that are not zero)."""
        parts = [f"{format_number(self.failed)} outside the band"]
        if self.unbanded:
            parts.append(f"{format_number(self.unbanded)} reported without a band")
        if self.no_data:
            parts.append(f"{format_number(self.no_data)} without data")
        if self.rankings:
            within = (f", {self.rankings_within_error} more within the surrogate's error"
                      if self.rankings_within_error else "")
            parts.append(f"rankings: {self.rankings_same} of {self.rankings} in the reference's order{within}")
        return "; ".join(parts)


def tally(checks: Sequence[Check]) -> CheckTally:
    """Count ``checks``: numbers by status, rankings (with data) apart."""
    numbers = [c for c in checks if not c.ranking]
    ranked = [c for c in checks if c.ranking]
    return CheckTally(passed=sum(c.status == PASS for c in numbers), failed=sum(c.status == FAIL for c in numbers),
                      unbanded=sum(c.status == INFO for c in numbers),
                      no_data=sum(c.status == NA for c in checks),
                      rankings=sum(c.status != NA for c in ranked), rankings_same=sum(c.status == PASS for c in ranked),
                      rankings_within_error=sum(c.within_error for c in ranked))


def checks_summary(checks: Sequence[Check]) -> str:
    """'n of m numbers within their band; ...' (:meth:`CheckTally.details`)."""
    t = tally(checks)
    return f"{format_number(t.passed)} of {format_number(t.judged)} numbers within their band; {t.details()}"
