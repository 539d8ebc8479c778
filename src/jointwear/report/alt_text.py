"""Text alternatives of the report's data figures: what each figure shows, in its numbers, for a reader who cannot
see it (a screen reader reads the caption too, so these do not repeat it). Plain data in, as the figure functions of
:mod:`jointwear.report.figures` take it."""

from __future__ import annotations

from collections.abc import Collection, Sequence

import numpy as np

__all__ = ["reliability_curve_alt", "validation_alt", "tornado_alt", "wear_polar_alt", "wear_history_alt"]


def reliability_curve_alt(cycles: Sequence[float], reliability: Sequence[float], target: float,
                          life_cycles: float | None) -> str:
    """'Line chart of R against cycles: R falls from 0.998 at 300,000 cycles to 0.167 at 560,000; it crosses the
    target 0.9 at 373,680 cycles.'"""
    c, r = np.asarray(cycles, dtype=float), np.asarray(reliability, dtype=float)
    if c.size == 0:
        return "Line chart of R against cycles, with no level."
    text = (f"Line chart of R against cycles: R goes from {r[0]:.3f} at {c[0]:,.0f} cycles to {r[-1]:.3f} at "
            f"{c[-1]:,.0f}")
    if life_cycles is not None:
        text += f"; it crosses the target {target:g} at {life_cycles:,.0f} cycles"
    return text + "."


def validation_alt(cycles: Sequence[float], reliability_mc: Sequence[float], reliability_surrogate: Sequence[float],
                   agreement: Sequence[bool], n_samples: int) -> str:
    """The levels where the two curves' intervals overlap and their largest difference in R."""
    c = np.asarray(cycles, dtype=float)
    diff = np.abs(np.asarray(reliability_surrogate, dtype=float) - np.asarray(reliability_mc, dtype=float))
    text = (f"Line chart of R against cycles, the surrogate's curve beside the true model's from {n_samples:,} "
            f"samples: their 95 % intervals overlap at {int(np.sum(agreement))} of {c.size} levels")
    if np.isfinite(diff).any():
        k = int(np.nanargmax(diff))
        text += f"; the largest difference in R is {diff[k]:.3f}, at {c[k]:,.0f} cycles"
    return text + "."


def tornado_alt(labels: Sequence[str], low: Sequence[float | None], high: Sequence[float | None], nominal: float,
                cycles: float, *, names: Sequence[str] | None = None,
                unresolved: Collection[tuple[str, str]] = ()) -> str:
    """The variable whose mean shifts move R the most from the nominal (the larger of its two shifts, as the ranking
    compares them), and where its two shifts put R; with ``names`` and ``unresolved`` (pairs of ranking neighbours
    the surrogate's error does not separate, by name), the variables not told apart from it, so the text claims no
    order the ranking leaves open."""
    keys = list(names) if names is not None else list(labels)
    swings = [(max(abs(float(lo) - nominal), abs(float(h) - nominal)), name, float(lo), float(h), key)
              for name, lo, h, key in zip(labels, low, high, keys)
              if lo is not None and h is not None and np.isfinite(float(lo)) and np.isfinite(float(h))]
    text = f"Bar chart of R at {cycles:,.0f} cycles (nominal {nominal:.3f}) with each variable's mean shifted"
    if swings:
        ranked = sorted(swings, key=lambda s: -s[0])  # stable: the first of equal changes, as the ranking lists them
        _, name, lo, h, _ = ranked[0]
        tied = []
        for before, after in zip(ranked, ranked[1:]):  # the run of neighbours the ranking writes with ≈
            if (before[4], after[4]) not in unresolved:
                break
            tied.append(after[1])
        if tied:
            others = tied[0] if len(tied) == 1 else f"{', '.join(tied[:-1])} and {tied[-1]}"
            text += (f"; the largest changes of R are {name}'s (R at {lo:.3f} and {h:.3f}) and those of {others}, "
                     "not told apart within the surrogate's error")
        else:
            text += f"; the largest change of R is {name}'s, R at {lo:.3f} and {h:.3f}"
    return text + "."


def wear_polar_alt(angle_deg: Sequence[float], depth_mm: Sequence[float]) -> str:
    """The deepest point of a bearing's wear profile (cells equally spaced round the circle) and the arc worn to half
    of it."""
    a, d = np.asarray(angle_deg, dtype=float), np.asarray(depth_mm, dtype=float)
    if d.size == 0 or not np.isfinite(d).any() or np.nanmax(d) <= 0:
        return "Polar chart of the bearing's wear depth around the bore: no wear."
    k = int(np.nanargmax(d))
    arc = 360.0 * np.count_nonzero(d >= 0.5 * d[k]) / d.size  # the profile's cells share the circle equally
    return (f"Polar chart of the bearing's wear depth around the bore: deepest {d[k]:.4g} mm at {a[k]:.0f} deg; "
            f"{arc:.0f} deg of the circle worn to half that depth or more.")


def wear_history_alt(cycles: Sequence[float], max_wear_mm: Sequence[float], limit_mm: float | None) -> str:
    """The nominal design's wear at the history's end, against the allowance."""
    c, w = np.asarray(cycles, dtype=float), np.asarray(max_wear_mm, dtype=float)
    if c.size == 0:
        return "Line chart of the max bearing wear against cycles, with no point."
    text = (f"Line chart of the max bearing wear against cycles: the nominal design reaches {w[-1]:.4g} mm at "
            f"{c[-1]:,.0f}")
    if limit_mm is not None:
        text += f", against an allowance of {limit_mm:g} mm"
    return text + "."
