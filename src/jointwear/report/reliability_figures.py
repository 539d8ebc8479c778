"""Figures of the reliability stages: R(N), the wear histograms, the learning's convergence, the sensitivity
(tornado, Sobol' indices) and the validation against the true model. Plain data in (as in the JSON contracts),
a styled :class:`~matplotlib.figure.Figure` out; see :mod:`jointwear.report.figures`."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from jointwear.reliability.results import Z95
from jointwear.study.limit_state import curve_half_width
from jointwear.study.reliability_results import interval_text

from .style import (
    COLORS,
    CYCLES_LABEL,
    LIMIT_COLOR,
    PAPER_COLOR,
    TARGET_COLOR,
    axis_label,
    figure,
    hline,
    kilo_cycles,
    note,
    panel_letter,
    require_array,
    styled,
    vline,
)

__all__ = ["reliability_curve_figure", "comparison_figure", "wear_histograms_figure", "convergence_figure",
           "tornado_figure", "sobol_figure", "validation_figure", "cross_validation_figure"]

Array = Sequence[float] | np.ndarray


# --------------------------------------------------------------------------------------------- reliability
#: each joint's own R(N) beside the mechanism's (none near the target's colour)
JOINT_COLORS = (COLORS[2], COLORS[5], COLORS[4], COLORS[3])


def _band(ax, n, rel, half, color: str, label: str | None = None) -> None:
    """R -/+ half (clipped to [0, 1]) as a shaded band over the curve's levels n (thousands of cycles)."""
    ax.fill_between(n, np.clip(rel - half, 0, 1), np.clip(rel + half, 0, 1), color=color, alpha=0.2, lw=0,
                    label=label)


def _life_bar(ax, n, target: float, low: float | None, high: float | None, color: str,
              label: str | None = None) -> None:
    """A life's interval (cycles) as a bar along the target line; an end that is None runs to the curve's end."""
    if not n.size:
        return
    lo = n[0] if low is None else low / 1e3
    hi = n[-1] if high is None else high / 1e3
    ax.plot([lo, hi], [target, target], color=color, lw=3, solid_capstyle="butt", zorder=4, label=label)


def _life_marker(ax, n, target: float, life: float, interval: tuple[float | None, float | None] | None, color: str,
                 marker: str, label: str) -> None:
    """A life (cycles) at its target R, with its 95 % interval as a bar with end caps (an end that is None runs to
    the curve's end), in the legend as ``label``: a bar alone hid under the marker when the interval was narrow."""
    x = life / 1e3
    if interval is None or not n.size:  # the life's line already names it
        ax.plot(x, target, marker, color=color, ms=6, zorder=5, ls="none")
        return
    low, high = interval
    lo = n[0] if low is None else low / 1e3
    hi = n[-1] if high is None else high / 1e3
    ax.errorbar([x], [target], xerr=[[max(x - lo, 0.0)], [max(hi - x, 0.0)]], fmt=marker, color=color, ms=5,
                elinewidth=2.5, capsize=5, capthick=2, zorder=5, label=label)


def reliability_curve_figure(
    cycles: Array,
    reliability: Array,
    *,
    pf_cov: Array | None = None,
    pf_error: Array | None = None,
    target: float | None = None,
    life_cycles: float | None = None,
    life_interval: tuple[float | None, float | None] | None = None,
    reference: Mapping[float, float] | None = None,
    reference_life: float | None = None,
    reference_label: str = "reference",
    joints: Mapping[str, tuple[Array, Array | None]] | None = None,
    fine: tuple[Array, Array, Array] | None = None,
    other_lives: Sequence[tuple[float, float, float | None, float | None]] = (),
) -> Figure:
    """R(N) with a 95 % band, the Monte Carlo half-width 1.96 COV Pf plus the surrogate's error estimate
    ``pf_error`` (absolute, in R) when given, the target line, the life at the target with its 95 % interval
    ``life_interval`` (cycles; an end that is None is drawn to the curve's end) and, when given, a
    cited reference's points ``reference`` {cycles: R} and life ``reference_life`` (cycles at the target),
    labelled ``reference_label``, and each joint's own R(N) of a series system ``joints`` {name: (R, its 95 %
    half-width or None)}, dashed (on ``fine``'s cycles when as long). ``fine``: (cycles, R, 95 % half-width) of
    the curve between its levels too, where the life is read: the line and the band follow it, the levels marked
    on it. ``other_lives``: (target, life, low, high) of the study's other targets, each drawn at its R with its
    interval. A life's interval is drawn as a bar with end caps, which show however narrow it is."""
    n = kilo_cycles(cycles)
    rel = require_array(reliability)
    fig, ax = figure()
    label = "this study" if not joints else "the mechanism"
    band_label = "95 % band (COV of Pf" + ("" if pf_error is None else " + surrogate error") + ")"
    if fine is not None:
        n_fine, r_fine, half_fine = kilo_cycles(fine[0]), require_array(fine[1]), require_array(fine[2])
        _band(ax, n_fine, r_fine, half_fine, COLORS[0], band_label)
        ax.plot(n_fine, r_fine, color=COLORS[0], label=label)
        ax.plot(n, rel, "o", color=COLORS[0], ms=3)
    else:
        if pf_cov is not None:
            half = curve_half_width(1.0 - rel, require_array(pf_cov),
                                    None if pf_error is None else require_array(pf_error))
            _band(ax, n, rel, half, COLORS[0], band_label)
        ax.plot(n, rel, color=COLORS[0], marker="o", ms=3, label=label)
    for k, (name, (r_joint, half_joint)) in enumerate((joints or {}).items()):
        color = JOINT_COLORS[k % len(JOINT_COLORS)]
        r_joint = require_array(r_joint)
        x = n_fine if fine is not None and r_joint.size == n_fine.size else n  # a joint's curve where it was read
        if half_joint is not None:
            _band(ax, x, r_joint, require_array(half_joint), color)
        ax.plot(x, r_joint, color=color, ls="--", lw=1.2, label=f"joint {name} alone")
    if reference:
        ks = sorted(reference)
        ax.plot(np.array(ks) / 1e3, [reference[k] for k in ks], "x", color=PAPER_COLOR, ms=7, mew=1.8,
                label=reference_label)
    if target is not None:
        hline(ax, target, f"target R = {target:g}", color=TARGET_COLOR)
    if life_cycles is not None and np.isfinite(life_cycles):
        vline(ax, life_cycles / 1e3, f"life {life_cycles:,.0f} cycles", color=TARGET_COLOR)
        if target is not None:
            _life_marker(ax, n, target, life_cycles, life_interval, TARGET_COLOR, "D",
                         f"life at R = {target:g}: {life_cycles:,.0f} cycles"
                         + (f", {interval_text(*life_interval)}" if life_interval else ""))
    for k, (t, life, low, high) in enumerate(other_lives):
        if life is not None and np.isfinite(life):
            _life_marker(ax, n, t, life, (low, high), JOINT_COLORS[(k + 1) % len(JOINT_COLORS)], "s",
                         f"life at R = {t:g}: {life:,.0f} cycles, {interval_text(low, high)}")
    if reference_life is not None and target is not None:
        ax.plot(reference_life / 1e3, target, "D", mfc="none", color=PAPER_COLOR, ms=7,
                label=f"{reference_label}: life {reference_life:,.0f} cycles")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(CYCLES_LABEL)
    ax.set_ylabel(axis_label("reliability R(N)", None))
    ax.legend(loc="lower left")
    ax.set_title("Reliability against cycles")
    return fig


def comparison_figure(
    curves: Sequence[Mapping],
    labels: Sequence[str],
    *,
    target: float | None = None,
    lives: Sequence[tuple[float | None, float | None, float | None]] | None = None,
) -> Figure:
    """Several studies' R(N) on one axis: each curve (``cycles``, ``reliability``, ``half_width``: its 95 %
    half-width) with its band, the target line and, from ``lives`` (life, low, high per study, cycles; None where
    outside the curve), each life with its 95 % interval."""
    fig, ax = figure()
    for k, (curve, label) in enumerate(zip(curves, labels)):
        color = COLORS[k % len(COLORS)]
        n = kilo_cycles(curve["cycles"])
        rel = require_array(curve["reliability"])
        _band(ax, n, rel, np.nan_to_num(require_array(curve["half_width"])), color)
        ax.plot(n, rel, color=color, marker="o", ms=3, label=label)
        life, low, high = lives[k] if lives is not None else (None, None, None)
        if target is not None and life is not None:
            _life_bar(ax, n, target, low, high, color)
            ax.plot(life / 1e3, target, "D", color=color, ms=6, zorder=5)
    if target is not None:
        hline(ax, target, f"target R = {target:g}", color=TARGET_COLOR)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(CYCLES_LABEL)
    ax.set_ylabel(axis_label("reliability R(N)", None))
    ax.fill_between([], [], [], color=COLORS[-1], alpha=0.4, lw=0,
                    label="95 % bands (Monte Carlo + surrogate error); bars: the lives' 95 % intervals")
    ax.legend(loc="lower left")
    ax.set_title("Reliability against cycles: the studies compared")
    return fig


def wear_histograms_figure(
    cycles: Sequence[float],
    max_wear_mm: Sequence[Array],
    *,
    limit_mm: float | None = None,
    reference_means: Mapping[float, float] | None = None,
    reference_label: str = "reference",
) -> Figure:
    """Histograms of the max wear over the random inputs at a few cycle counts, and all of them together;
    ``reference_means`` {cycles: mm} marks a cited reference's means (dotted)."""
    sets = [(float(c), require_array(s)[np.isfinite(require_array(s))]) for c, s in zip(cycles, max_wear_mm)]
    npanel = len(sets) + (1 if len(sets) > 1 else 0)
    ncols = 2 if npanel == 4 else min(npanel, 3)
    nrows = int(np.ceil(npanel / ncols))
    fig, axes = figure(nrows, ncols, size=(9.6, 3.4 * nrows), squeeze=False)
    axes = axes.ravel()
    allvals = np.concatenate([s for _, s in sets]) if sets else np.array([])
    bins = np.histogram_bin_edges(allvals, bins=40) if allvals.size else 10
    letters = "abcdefghij"
    for k, (c, s) in enumerate(sets):
        ax = axes[k]
        color = COLORS[k % len(COLORS)]
        ax.hist(s, bins=bins, density=True, color=color, alpha=0.75, edgecolor="white")
        m = float(np.mean(s)) if s.size else np.nan
        vline(ax, m, None, color=PAPER_COLOR, ls="-")
        if reference_means and c in reference_means:
            vline(ax, reference_means[c], None, color=PAPER_COLOR, ls=":")
        if limit_mm is not None:
            vline(ax, limit_mm, None, color=LIMIT_COLOR, ls="--")
        # the figure's own samples: the study's R(N) and means come from its whole population
        txt = f"these n = {s.size:,} samples:\nmean = {m:.4f} mm\nstd = {np.std(s):.4f} mm"
        if reference_means and c in reference_means:
            txt += f"\n{reference_label} mean = {reference_means[c]:.4f} mm"
        if limit_mm is not None and s.size:
            txt += f"\nP(> {limit_mm:g} mm) = {np.mean(s > limit_mm):.3f}"
        centre = 0.5 * (bins[0] + bins[-1]) if not isinstance(bins, int) else m
        note(ax, txt, loc="upper left" if m > centre else "upper right")
        ax.set_xlabel(axis_label("max wear", "mm"))
        ax.set_ylabel(axis_label("probability density", "1/mm"))
        panel_letter(ax, letters[k])
        ax.set_title(f"{c:,.0f} cycles", loc="center", fontweight="normal")
    if len(sets) > 1:
        ax = axes[len(sets)]
        for k, (c, s) in enumerate(sets):
            ax.hist(s, bins=bins, density=True, histtype="step", lw=1.6, color=COLORS[k % len(COLORS)],
                    label=f"{c:,.0f} cycles")
        if limit_mm is not None:
            vline(ax, limit_mm, f"\u03b4\u2080 = {limit_mm:g} mm", color=LIMIT_COLOR, ls="--")
        ax.set_xlabel(axis_label("max wear", "mm"))
        ax.set_ylabel(axis_label("probability density", "1/mm"))
        ax.legend(loc="upper right")
        panel_letter(ax, letters[len(sets)])
        ax.set_title("together", loc="center", fontweight="normal")
    for ax in axes[npanel:]:
        ax.set_visible(False)
    fig.suptitle("Distribution of the max wear of the joint")
    return fig


def convergence_figure(
    n_calls: Array,
    pf: Array,
    *,
    cov: Array | None = None,
    label: str | None = None,
    curve_pf: float | None = None,
) -> Figure:
    """The failure probability estimate against the number of true-model calls during active learning.

    ``curve_pf``: the R(N) curve's Pf at the same level, drawn beside the learning's last estimate when the two
    are different estimators (the learning's counts the samples whose surrogate mean fails; the curve's also
    integrates the life's call-to-call scatter)."""
    calls = require_array(n_calls)
    p = require_array(pf)
    fig, ax = figure()
    if cov is not None:
        c = require_array(cov)
        half = Z95 * np.where(np.isfinite(c), c, 0.0) * p  # no band where the COV is undefined (Pf = 0)
        ax.fill_between(calls, np.clip(p - half, 0, 1), np.clip(p + half, 0, 1), color=COLORS[0], alpha=0.2, lw=0,
                        label="95 % band (COV of Pf)")
    ax.plot(calls, p, color=COLORS[0], marker="o", ms=3.5, label=label or (
        "Pf estimate" if curve_pf is None else "the learning's Pf (surrogate mean, no call-to-call scatter)"))
    if p.size:
        last = "learning's last Pf" if curve_pf is not None else "final Pf"
        hline(ax, float(p[-1]), f"{last} = {p[-1]:.4g}", color=COLORS[1], ls=":")
    if curve_pf is not None:  # in the legend: its value sits close to the last estimate's label
        ax.axhline(float(curve_pf), color=COLORS[2], ls="--", lw=1.2, zorder=1,
                   label=f"R(N) curve's Pf = {curve_pf:.4g} (with the scatter)")
    pos = p[p > 0]
    if pos.size and pos.max() / pos.min() > 50:
        ax.set_yscale("log")
    ax.set_xlabel(axis_label("true-model calls", "count"))
    ax.set_ylabel(axis_label("failure probability Pf", None))
    ax.legend(loc="best")
    ax.set_title("Convergence of Pf against model calls")
    return fig


# --------------------------------------------------------------------------------------------- sensitivity
def tornado_figure(
    labels: Sequence[str],
    reliability_low: Array,
    reliability_high: Array,
    reliability_nominal: float,
    *,
    cycles: float | None = None,
    low_label: str = "mean \u00d7 0.8",
    high_label: str = "mean \u00d7 1.2",
    title: str | None = None,
    error_low: Array | None = None,
    error_high: Array | None = None,
    not_run_low: Sequence[bool] | None = None,
    not_run_high: Sequence[bool] | None = None,
) -> Figure:
    """Tornado of the reliability when each variable's mean is moved to 80 % and 120 % (Figs. 22-24).

    Bars start at the nominal reliability; the most influential variable is on top. ``error_low``, ``error_high``:
    each shifted R's 95 % error, drawn as a whisker at the bar's end; ``not_run_low``, ``not_run_high``: the shifts
    whose mechanism could not run (R = 0 by the rule, not by wear), hatched.
    """
    lo = require_array(reliability_low)
    hi = require_array(reliability_high)
    nom = float(reliability_nominal)
    spread = np.nanmax(np.abs(np.c_[lo - nom, hi - nom]), axis=1) if lo.size else np.array([])
    order = np.argsort(-np.nan_to_num(spread, nan=-1.0), kind="stable")[::-1]
    fig, ax = figure(size=(6.4, max(2.4, 0.45 * len(labels) + 1.4)))
    y = np.arange(len(labels))
    for values, errors, not_run, offset, color, label in (
            (lo, error_low, not_run_low, 0.0, COLORS[0], low_label),
            (hi, error_high, not_run_high, -0.38, COLORS[1], high_label)):
        bars = ax.barh(y + offset, values[order] - nom, left=nom, height=0.38, align="edge", color=color,
                       label=label)
        if not_run is not None:
            for bar, failed in zip(bars, np.asarray(not_run, dtype=bool)[order]):
                if failed:
                    bar.set(hatch="///", facecolor="white", edgecolor=color)
        if errors is not None:
            err = np.nan_to_num(np.asarray(errors, dtype=float)[order])
            ax.errorbar(values[order], y + offset + 0.19, xerr=err, fmt="none", ecolor=PAPER_COLOR, elinewidth=0.9,
                        capsize=2)
    ax.axvline(nom, color=PAPER_COLOR, lw=1.0, label=f"nominal R = {nom:.3f}")
    handles = ax.get_legend_handles_labels()[0]
    if any(np.any(np.asarray(f, dtype=bool)) for f in (not_run_low, not_run_high) if f is not None):
        handles.append(Patch(hatch="///", facecolor="white", edgecolor=PAPER_COLOR,
                             label="could not run (R = 0)"))
    ax.set_yticks(y)
    ax.set_yticklabels([labels[i] for i in order])
    ax.set_xlim(-0.02, 1.02)
    ax.set_xlabel(axis_label("reliability R" + (f" at {cycles:,.0f} cycles" if cycles else ""), None))
    ax.grid(axis="y", visible=False)
    ax.legend(handles=handles, loc="lower left", bbox_to_anchor=(0, 1.0), ncols=min(len(handles), 3), fontsize=8.5)
    ax.set_title(title or f"Sensitivity: nominal R = {nom:.3f}", pad=22)
    return fig


def sobol_figure(
    names: Sequence[str],
    S1: Array,
    ST: Array,
    *,
    S1_conf: Array | None = None,
    ST_conf: Array | None = None,
    output: str = "max wear",
) -> Figure:
    """First-order and total Sobol' indices (sorted by the total index), with confidence intervals if given."""
    s1 = require_array(S1)
    st = require_array(ST)
    order = np.argsort(np.nan_to_num(st), kind="stable")  # largest total index on top
    fig, ax = figure(size=(7.2, max(2.6, 0.42 * len(names) + 1.3)))
    y = np.arange(len(names))
    h = 0.38
    ax.barh(y + h / 2, s1[order], h, color=COLORS[0], label="first order S1",
            xerr=None if S1_conf is None else require_array(S1_conf)[order], capsize=2)
    ax.barh(y - h / 2, st[order], h, color=COLORS[1], label="total ST",
            xerr=None if ST_conf is None else require_array(ST_conf)[order], capsize=2)
    ax.set_yticks(y)
    ax.set_yticklabels([names[i] for i in order])
    ax.set_xlim(left=min(0.0, float(np.nanmin(np.r_[s1, st, 0.0])) * 1.1))
    ax.set_xlabel(axis_label(f"Sobol' index of the {output}", None))
    ax.grid(axis="y", visible=False)
    ax.legend(loc="lower right")
    ax.set_title(f"Global sensitivity (Sobol') of the {output}")
    return fig


def validation_figure(
    cycles: Array,
    reliability_mc: Array,
    ci_low: Array,
    ci_high: Array,
    reliability_surrogate: Array,
    surrogate_half_width: Array | None = None,
    *,
    n_samples: int | None = None,
) -> Figure:
    """The surrogate's R(N) with its 95 % band (Monte Carlo plus its error estimate: the band the agreement test
    reads) against the true model sampled directly (exact binomial 95 % interval)."""
    n = kilo_cycles(cycles)
    r_mc, r_sur = require_array(reliability_mc), require_array(reliability_surrogate)
    fig, ax = figure()
    if surrogate_half_width is not None:
        half = np.nan_to_num(require_array(surrogate_half_width))
        ax.fill_between(n, np.clip(r_sur - half, 0, 1), np.clip(r_sur + half, 0, 1), color=COLORS[0], alpha=0.2,
                        lw=0, label="surrogate's 95 % band (Monte Carlo + error estimate)")
    ax.plot(n, r_sur, color=COLORS[0], marker="o", ms=3, label="surrogate (the study's R(N))")
    lo, hi = require_array(ci_low), require_array(ci_high)
    ax.errorbar(n, r_mc, yerr=[np.clip(r_mc - lo, 0, None), np.clip(hi - r_mc, 0, None)], fmt="s", ms=4,
                color=COLORS[1], capsize=3,
                label="true model" + (f", {n_samples:,} samples" if n_samples else "") + " (exact 95 % CI)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(CYCLES_LABEL)
    ax.set_ylabel(axis_label("reliability R(N)", None))
    ax.legend(loc="lower left")
    ax.set_title("R(N): surrogate against direct Monte Carlo of the true model")
    return fig


def cross_validation_figure(
    true_values: Array,
    loo_values: Array,
    loo_sd: Array | None = None,
    *,
    q2: float | None = None,
    quantity: str = "ln N_f (N_f: wear life in cycles)",
) -> Figure:
    """Leave-one-out predictions of the design points against their true values; on the 1:1 line a prediction
    equals the true value."""
    y, p = require_array(true_values), require_array(loo_values)
    fig, ax = figure()
    lo, hi = (float(np.nanmin(np.r_[y, p])), float(np.nanmax(np.r_[y, p]))) if y.size else (0.0, 1.0)
    ax.plot([lo, hi], [lo, hi], color="0.5", lw=1, ls="--", label="1:1, a perfect prediction")
    if loo_sd is not None:
        ax.errorbar(y, p, yerr=Z95 * require_array(loo_sd), fmt="o", ms=4, color=COLORS[0], alpha=0.8, capsize=2,
                    label="leave-one-out prediction (95 %)")
    else:
        ax.plot(y, p, "o", ms=4, color=COLORS[0], label="leave-one-out prediction")
    ax.set_xlabel(f"true {quantity}")
    ax.set_ylabel(f"predicted {quantity}")
    if q2 is not None:
        note(ax, f"Q\u00b2 = {q2:.3f}", loc="lower right")
    ax.legend(loc="upper left")
    ax.set_title("Surrogate cross-validation")
    return fig


# every figure is drawn in the house style without touching the user's rcParams
for _name in __all__:
    globals()[_name] = styled(globals()[_name])
del _name
