"""Figure functions of jointwear: plain data in, a styled :class:`~matplotlib.figure.Figure` out.

Every function takes arrays, lists or numbers as they appear in the JSON contracts (millimetres, degrees,
newtons, cycles) and returns a figure in the house style of :mod:`jointwear.report.style`; write it with
:func:`jointwear.report.style.savefig` or embed it with :func:`jointwear.report.style.to_data_uri`. No function
reads files, so the stages and the HTML report draw the same figure from the same numbers.

Angles on the bearing follow the paper (Section 6.1.3, Figs. 17-18): the bearing's (rod's) frame, 0 deg at the
leftmost point, growing clockwise. The reliability figures live in :mod:`jointwear.report.reliability_figures`
and are re-exported here.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from .reliability_figures import (
    comparison_figure,
    convergence_figure,
    cross_validation_figure,
    reliability_curve_figure,
    sobol_figure,
    tornado_figure,
    validation_figure,
    wear_histograms_figure,
)
from .style import (
    CYCLES_LABEL,
    kilo_cycles,
    require_array,
    styled,
    COLORS,
    LIMIT_COLOR,
    PAPER_COLOR,
    angle_axis,
    axis_label,
    figure,
    hline,
    label_axes,
    nice_number,
    no_data,
    panel_letter,
    scale_to_unit,
)

__all__ = [
    "mechanism_figure",
    "slider_crank_figure",
    "linkage_figure",
    "orbit_figure",
    "contact_force_figure",
    "wear_polar_figure",
    "wear_panels_figure",
    "wear_history_figure",
    "reliability_curve_figure",
    "comparison_figure",
    "wear_histograms_figure",
    "convergence_figure",
    "tornado_figure",
    "sobol_figure",
    "validation_figure",
    "cross_validation_figure",
]

Array = Sequence[float] | np.ndarray


def _break_wraps(angle_deg: np.ndarray, *ys: np.ndarray):
    """Insert NaN where an angle series wraps (360 -> 0), so a line does not jump across the plot."""
    a = np.mod(angle_deg, 360.0)
    jumps = np.where(np.diff(a) < -180.0)[0] + 1
    if jumps.size == 0:
        return (a, *ys)
    a = np.insert(a, jumps, np.nan)
    return (a, *(np.insert(y, jumps, np.nan) for y in ys))


# --------------------------------------------------------------------------------------------- mechanism
def _four_bar_B(a: np.ndarray, rod: float, rocker: float, pivot: np.ndarray, branch: int) -> np.ndarray | None:
    d = pivot - a
    dist = float(np.hypot(*d))
    if dist == 0 or dist > rod + rocker or dist < abs(rod - rocker):
        return None
    along = (rod**2 - rocker**2 + dist**2) / (2 * dist)
    h = np.sqrt(max(rod**2 - along**2, 0.0))
    base = a + along * d / dist
    perp = np.array([-d[1], d[0]]) / dist
    return base + (1 if branch >= 0 else -1) * h * perp


def mechanism_figure(
    crank_mm: float,
    rod_mm: float,
    rocker_mm: float,
    pivot_mm: Sequence[float],
    *,
    branch: int = 1,
    crank_angle_deg: float = 45.0,
    clearance_joint: str = "A",
    n_ghosts: int = 12,
) -> Figure:
    """Sketch of the crank-rocker: crank O-A about O = (0, 0), rod A-B, rocker B-C about the ground pivot C.

    ``branch`` (+1 / -1) picks the assembly; faint ghosts show the linkage over a crank turn, the bold
    linkage sits at ``crank_angle_deg``; the clearance joint is ringed.
    """
    pivot = np.asarray(pivot_mm, dtype=float)
    fig, ax = figure(size="square")
    o = np.zeros(2)
    for phi in np.linspace(0, 2 * np.pi, n_ghosts, endpoint=False):
        a = crank_mm * np.array([np.cos(phi), np.sin(phi)])
        b = _four_bar_B(a, rod_mm, rocker_mm, pivot, branch)
        if b is None:
            continue
        ax.plot(*np.c_[o, a, b, pivot], color="#BBBBBB", lw=0.7, zorder=1)
    ax.add_patch(_circle(o, crank_mm, ls=":", ec="#999999"))
    phi = np.deg2rad(crank_angle_deg)
    a = crank_mm * np.array([np.cos(phi), np.sin(phi)])
    b = _four_bar_B(a, rod_mm, rocker_mm, pivot, branch)
    if b is None:
        no_data(ax, "the linkage does not assemble at this crank angle")
        return fig
    ax.plot(*np.c_[o, a], color=COLORS[0], lw=3, label=f"crank {crank_mm:g} mm", zorder=3)
    ax.plot(*np.c_[a, b], color=COLORS[1], lw=3, label=f"rod {rod_mm:g} mm", zorder=3)
    ax.plot(*np.c_[b, pivot], color=COLORS[2], lw=3, label=f"rocker {rocker_mm:g} mm", zorder=3)
    _finish_sketch(ax, {"O": o, "A": a, "B": b, "C": pivot}, ("O", "C"), clearance_joint, "crank-rocker")
    return fig


def _finish_sketch(ax, points: Mapping[str, np.ndarray], ground: Sequence[str], clearance_joint: str,
                   kind: str) -> None:
    """The named points of a sketch (ground ones as triangles), the clearance joint ringed, axes in mm."""
    for name, p in points.items():
        grounded = name in ground
        ax.plot(*p, marker="^" if grounded else "o", ms=9 if grounded else 6, color="#333333", zorder=4)
        ax.annotate(name, p, xytext=(6, 4), textcoords="offset points", fontsize=10, fontweight="bold")
    if clearance_joint in points:
        ax.plot(*points[clearance_joint], marker="o", ms=16, mfc="none", mec=LIMIT_COLOR, mew=1.8, zorder=5,
                label=f"clearance joint {clearance_joint}")
    ax.set_aspect("equal", adjustable="datalim")
    label_axes(ax, "x", "mm", "y", "mm")
    ax.legend(loc="lower right")
    ax.set_title(f"Mechanism ({kind})")


def slider_crank_figure(
    crank_mm: float,
    rod_mm: float,
    *,
    offset_mm: float = 0.0,
    guide_angle_deg: float = 0.0,
    branch: int = 1,
    crank_angle_deg: float = 45.0,
    clearance_joint: str = "B",
    n_ghosts: int = 12,
) -> Figure:
    """Sketch of the slider-crank: crank O-A about O = (0, 0), rod A-B, slider B on the guide line offset * n + s u
    (u along ``guide_angle_deg``, n its normal), s = A.u + branch sqrt(l2^2 - (offset - A.n)^2); ghosts over a crank
    turn, the bold linkage at ``crank_angle_deg``, the clearance joint ringed."""
    gamma = np.deg2rad(guide_angle_deg)
    u, n = np.array([np.cos(gamma), np.sin(gamma)]), np.array([-np.sin(gamma), np.cos(gamma)])

    def pose(phi: float) -> tuple[np.ndarray, np.ndarray]:
        a = crank_mm * np.array([np.cos(phi), np.sin(phi)])
        s = a @ u + branch * np.sqrt(max(rod_mm**2 - (offset_mm - a @ n) ** 2, 0.0))
        return a, offset_mm * n + s * u

    fig, ax = figure(size="square")
    o = np.zeros(2)
    ends = []
    for phi in np.linspace(0, 2 * np.pi, n_ghosts, endpoint=False):
        a, b = pose(phi)
        ends.append(b)
        ax.plot(*np.c_[o, a, b], color="#BBBBBB", lw=0.7, zorder=1)
    stroke = np.array([b @ u for b in ends])
    reach = 0.15 * (stroke.max() - stroke.min() + crank_mm)
    guide = [offset_mm * n + (stroke.min() - reach) * u, offset_mm * n + (stroke.max() + reach) * u]
    ax.plot(*np.c_[guide[0], guide[1]], color="#666666", lw=1.0, ls="--", zorder=1, label="slider guide")
    ax.add_patch(_circle(o, crank_mm, ls=":", ec="#999999"))
    a, b = pose(np.deg2rad(crank_angle_deg))
    ax.plot(*np.c_[o, a], color=COLORS[0], lw=3, label=f"crank {crank_mm:g} mm", zorder=3)
    ax.plot(*np.c_[a, b], color=COLORS[1], lw=3, label=f"rod {rod_mm:g} mm", zorder=3)
    ax.plot(*b, marker="s", ms=18, mfc=COLORS[2], mec="#333333", alpha=0.6, zorder=3, ls="none", label="slider")
    _finish_sketch(ax, {"O": o, "A": a, "B": b}, ("O",), clearance_joint, "slider-crank")
    return fig


def linkage_figure(mech: Mapping) -> Figure:
    """Sketch of a general linkage as drawn (its TOML's global coordinates at t = 0, mm): each body a line through
    its points (a shaded polygon for three or more) with its centre of mass, ground points as triangles, revolute
    joints as dots and prismatic ones as squares, the driven joints and the clearance joints ringed."""
    fig, ax = figure(size="square")
    drawn = np.array([p for b in mech.get("bodies", []) for p in b["points_mm"].values()]
                     + list(mech.get("ground_mm", {}).values()), dtype=float).reshape(-1, 2)
    span = float(np.ptp(drawn, axis=0).max()) if len(drawn) > 1 else 1.0
    for k, body in enumerate(mech.get("bodies", [])):
        pts = np.array(list(body["points_mm"].values()), dtype=float).reshape(-1, 2)
        color = COLORS[k % len(COLORS)]
        if len(pts) >= 3:
            from matplotlib.patches import Polygon

            ax.add_patch(Polygon(pts, closed=True, fc=color, ec=color, alpha=0.25, lw=2, zorder=2))
        # a body of one point (a slider block) is drawn as a block, as a line of one point would not show
        ax.plot(*pts.T, color=color, lw=3, zorder=3, label=body["name"],
                **({"marker": "s", "ms": 16, "alpha": 0.6} if len(pts) == 1 else {}))
        ax.plot(*np.asarray(body["com_mm"], dtype=float), marker="+", ms=9, mew=1.5, color=color, zorder=4)
    for p in mech.get("ground_mm", {}).values():
        ax.plot(*p, marker="^", ms=10, color="#333333", zorder=4)
    driven = set(mech.get("driven_joints", []))
    clearance = set(mech.get("clearance_joints", []))
    labelled: list[tuple] = []
    for j in mech.get("joints", []):
        if j.get("at_mm") is None:
            continue
        p = np.asarray(j["at_mm"], dtype=float)
        ax.plot(*p, marker="s" if j.get("type") == "prismatic" else "o", ms=6, color="#333333", zorder=5)
        if j.get("direction") is not None:  # the sliding line, through the joint along its drawn direction
            d = np.asarray(j["direction"], dtype=float)
            d = 0.5 * span * d / (np.hypot(*d) or 1.0)
            ax.plot(*np.c_[p - d, p + d], color="#666666", lw=1.0, ls="--", zorder=1)
        stacked = labelled.count(tuple(np.round(p, 6)))  # joints drawn at one point: their names one under another
        labelled.append(tuple(np.round(p, 6)))
        ax.annotate(j["name"], p, xytext=(6, 4 - 13 * stacked), textcoords="offset points", fontsize=10,
                    fontweight="bold")
        if j["name"] in driven:
            ax.plot(*p, marker="o", ms=13, mfc="none", mec="#333333", mew=1.2, ls="none", zorder=5)
        if j["name"] in clearance:
            ax.plot(*p, marker="o", ms=18, mfc="none", mec=LIMIT_COLOR, mew=1.8, ls="none", zorder=6)
    ax.plot([], [], marker="o", ms=13, mfc="none", mec="#333333", ls="none", label="driven joint")
    if clearance:
        ax.plot([], [], marker="o", ms=16, mfc="none", mec=LIMIT_COLOR, mew=1.8, ls="none",
                label="clearance joint " + ", ".join(sorted(clearance)))
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.15)
    label_axes(ax, "x", "mm", "y", "mm")
    ax.legend(loc="best")
    ax.set_title("Mechanism as drawn (t = 0)")
    return fig


def _circle(center, radius, **kw):
    from matplotlib.patches import Circle

    style = {"fill": False, "lw": 1.2, "ec": "#555555"}
    style.update(kw)
    return Circle(tuple(center), radius, **style)


# --------------------------------------------------------------------------------------------- dynamics
def orbit_figure(
    x_mm: Array,
    y_mm: Array,
    clearance_mm: float | None = None,
    *,
    angle_labels: bool = False,
    title: str = "Journal centre orbit in the bearing frame",
) -> Figure:
    """The journal centre relative to the bearing centre, in the bearing frame, with the clearance circle.

    Plotted in micrometres. With ``angle_labels`` (only when x, y are already laid as in the paper: x to the
    right, y up), the paper's bearing angles (0 deg at the leftmost point, clockwise) are marked on the circle.
    """
    x = require_array(x_mm) * 1e3
    y = require_array(y_mm) * 1e3
    fig, ax = figure(size="square")
    ax.plot(x, y, color=COLORS[0], lw=0.9, label="journal centre")
    if x.size:
        ax.plot(x[0], y[0], "o", color=COLORS[2], ms=5, label="start")
    if clearance_mm is not None and clearance_mm > 0:
        c = clearance_mm * 1e3
        ax.add_patch(_circle((0, 0), c, ec=LIMIT_COLOR, ls="--", lw=1.3, label=f"clearance c = {c:.3g} \u00b5m"))
        for deg, (ha, va) in ({0: ("right", "center"), 90: ("center", "bottom"), 180: ("left", "center"),
                               270: ("center", "top")} if angle_labels else {}).items():
            t = np.deg2rad(deg)
            px, py = -np.cos(t) * c * 1.06, np.sin(t) * c * 1.06
            ax.text(px, py, f"{deg}\u00b0", ha=ha, va=va, fontsize=8.5, color="#666666")
        lim = 1.25 * max(c, float(np.nanmax(np.hypot(x, y))) if x.size else c)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
    ax.plot(0, 0, "+", color="#555555", ms=8)
    ax.set_aspect("equal")
    label_axes(ax, "x, bearing frame", "um", "y, bearing frame", "um")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title)
    return fig


def contact_force_figure(
    crank_angle_deg: Array,
    force_N: Array,
    *,
    mean_N: float | None = None,
    ideal_N: Array | None = None,
    title: str = "Contact force in the clearance joint",
) -> Figure:
    """Normal contact force against crank angle (several cycles overlay, wrapped to 0-360 deg).

    ``ideal_N`` (same length) draws the reaction of the ideal joint for comparison.
    """
    force, unit = scale_to_unit(require_array(force_N), "N")
    factor = (float(np.nanmax(np.abs(require_array(force_N)))) / float(np.nanmax(np.abs(force)))) if np.nanmax(
        np.abs(force)) > 0 else 1.0
    ang = require_array(crank_angle_deg)
    a, f = _break_wraps(ang, force)
    fig, ax = figure()
    ax.plot(a, f, color=COLORS[0], lw=1.0, label="clearance joint")
    if ideal_N is not None:
        a2, f2 = _break_wraps(ang, require_array(ideal_N) / factor)
        ax.plot(a2, f2, color=PAPER_COLOR, lw=1.0, ls="--", label="ideal joint")
    if mean_N is not None:
        hline(ax, mean_N / factor, f"mean {mean_N / factor:.3g} {unit}", color=COLORS[1])
    angle_axis(ax, "x", step=60.0, label="crank angle")
    ax.set_ylabel(axis_label("normal contact force", unit))
    ax.set_ylim(bottom=0)
    if ideal_N is not None:
        ax.legend(loc="upper left")
    ax.set_title(title)
    return fig


# --------------------------------------------------------------------------------------------- wear
def _peak_list(peaks) -> list[tuple[float, float]]:
    out = []
    for p in peaks or []:
        if isinstance(p, Mapping):
            a, d = p.get("angle_deg"), p.get("depth_mm")
        else:
            a, d = p
        if a is not None and d is not None:
            out.append((float(a), float(d)))
    return out


def wear_polar_figure(
    angle_deg: Array,
    depth_mm: Array,
    *,
    radius_mm: float | None = None,
    exaggeration: float | None = None,
    peaks: Sequence | None = None,
    cycles: float | None = None,
    title: str | None = None,
) -> Figure:
    """The worn bearing profile over its initial circle (the paper's Fig. 18).

    Bearing frame, 0 deg at the leftmost point, clockwise. The wear depth is drawn radially outwards,
    multiplied by ``exaggeration`` (chosen so the largest wear shows as about 30 % of the radius when not given);
    the factor is written on the figure. ``radius_mm`` is the initial bearing radius (1 when unknown).
    """
    ang = require_array(angle_deg)
    depth = np.nan_to_num(require_array(depth_mm))
    order = np.argsort(np.mod(ang, 360))
    ang, depth = np.mod(ang, 360)[order], depth[order]
    r0 = float(radius_mm) if radius_mm else 1.0
    dmax = float(depth.max()) if depth.size else 0.0
    if exaggeration is None:
        exaggeration = nice_number(0.3 * r0 / dmax) if dmax > 0 else 1.0
    theta = np.deg2rad(np.r_[ang, ang[:1] + 360.0]) if ang.size else np.array([])
    r = r0 + exaggeration * np.r_[depth, depth[:1]] if ang.size else np.array([])
    fig, ax = figure(size="square", polar=True)
    ax.set_theta_zero_location("W")
    ax.set_theta_direction(-1)
    circ = np.linspace(0, 2 * np.pi, 361)
    ax.fill_between(theta, r0, r, color=COLORS[1], alpha=0.35, lw=0, label="worn material")
    ax.plot(circ, np.full_like(circ, r0), color="#555555", ls="--", lw=1.2, label="initial profile")
    ax.plot(theta, r, color=COLORS[1], lw=1.8, label="worn profile")
    pk = _peak_list(peaks)
    if not pk and dmax > 0:
        i = int(np.argmax(depth))
        pk = [(float(ang[i]), dmax)]
    for a, d in pk[:3]:
        ax.plot(np.deg2rad(a), r0 + exaggeration * d, "o", color=PAPER_COLOR, ms=5, zorder=5)
        ux, uy = -np.cos(np.deg2rad(a)), np.sin(np.deg2rad(a))  # outward direction on the page
        ax.annotate(f"{d:.4f} mm\nat {a:.0f}\u00b0", (np.deg2rad(a), r0 + exaggeration * d),
                    xytext=(-16 * ux, -16 * uy), textcoords="offset points", fontsize=8.5,
                    ha="right" if ux >= 0 else "left", va="top" if uy >= 0 else "bottom",
                    bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.8})
    rmax = r0 + exaggeration * dmax if dmax > 0 else r0
    ax.set_rlim(0, rmax * 1.08)
    ax.set_yticklabels([])
    ax.set_thetagrids(np.arange(0, 360, 45), [f"{d}\u00b0" for d in range(0, 360, 45)])
    ax.grid(True, color="#E0E0E0")
    cyc = f" after {cycles:,.0f} cycles" if cycles else ""
    ax.set_title(title or f"Bearing wear profile{cyc}", pad=14)
    r0_txt = f"initial radius R0 = {r0:g} mm" if radius_mm else "initial circle (radius not given)"
    fig.text(0.02, -0.01, f"angle on the bearing (deg): 0\u00b0 = leftmost point, clockwise; {r0_txt} (dashed);\n"
             f"wear depth (mm) drawn radially outwards, exaggerated \u00d7{exaggeration:g}", fontsize=8.5,
             color="#444444", va="top")
    ax.legend(loc="upper right", bbox_to_anchor=(1.12, 1.12), fontsize=8)
    return fig


def wear_panels_figure(
    angle_deg: Array,
    depth_mm: Array,
    *,
    slip_mm: Array | None = None,
    contact_force_N: Array | None = None,
    contact_area_mm2: Array | None = None,
    slip_angle_deg: Array | None = None,
    force_angle_deg: Array | None = None,
    area_angle_deg: Array | None = None,
    cycles: float | None = None,
    slip_quantity: str = "relative slip distance",
    slip_unit: str | None = None,
    joint: str | None = None,
) -> Figure:
    """The paper's Fig. 17: (a) relative slip distance, (b) contact force, (c) contact area and (d) bearing wear
    depth against the angle on the bearing. Panels without data say so. Each quantity may have its own angle
    grid (``*_angle_deg``); by default all share ``angle_deg``. ``joint``: the clearance joint's name, in the title
    (a mechanism with several)."""
    fig, axes = figure(2, 2, size="panels")
    ang = require_array(angle_deg)

    def series(ax, a, y, color):
        a = np.mod(ang if a is None else require_array(a), 360)
        order = np.argsort(a)
        ax.plot(a[order], y[order], color=color, lw=1.3)

    ax = axes[0, 0]
    panel_letter(ax, "a")
    if slip_mm is not None:
        if slip_unit is None:  # a distance in mm: shown with a readable prefix
            s, unit = scale_to_unit(require_array(slip_mm) * 1e-3, "m")
        else:  # a distribution (for example mm per degree of bearing per cycle): as given
            s, unit = require_array(slip_mm), slip_unit
        series(ax, slip_angle_deg, s, COLORS[0])
        ax.set_ylabel(axis_label(slip_quantity, unit))
        angle_axis(ax, "x")
    else:
        no_data(ax, f"{slip_quantity}: not provided")
    ax.set_title(slip_quantity, loc="center", fontweight="normal")

    ax = axes[0, 1]
    panel_letter(ax, "b")
    if contact_force_N is not None:
        f, unit = scale_to_unit(require_array(contact_force_N), "N")
        series(ax, force_angle_deg, f, COLORS[2])
        ax.set_ylabel(axis_label("contact force", unit))
        angle_axis(ax, "x")
    else:
        no_data(ax, "contact force: not provided")
    ax.set_title("contact force", loc="center", fontweight="normal")

    ax = axes[1, 0]
    panel_letter(ax, "c")
    if contact_area_mm2 is not None:
        area = require_array(contact_area_mm2)
        unit = "mm2"
        if np.nanmax(np.abs(area)) < 0.1:
            area, unit = area * 1e6, "um2"
        series(ax, area_angle_deg, area, COLORS[3])
        ax.set_ylabel(axis_label("contact area", unit))
        angle_axis(ax, "x")
    else:
        no_data(ax, "contact area: not provided")
    ax.set_title("contact area", loc="center", fontweight="normal")

    ax = axes[1, 1]
    panel_letter(ax, "d")
    series(ax, None, np.nan_to_num(require_array(depth_mm)), COLORS[1])
    ax.set_ylabel(axis_label("bearing wear depth", "mm"))
    angle_axis(ax, "x")
    ax.set_ylim(bottom=0)
    cyc = f" ({cycles:,.0f} cycles)" if cycles else ""
    ax.set_title("bearing wear depth" + cyc, loc="center", fontweight="normal")
    fig.suptitle("Wear data" + (f" of joint {joint}" if joint else "")
                 + " against the angle on the bearing (0\u00b0 = leftmost point, clockwise)")
    return fig


def wear_history_figure(
    cycles: Array,
    max_wear_mm: Array,
    *,
    limit_mm: float | None = None,
    mean_cycles: Array | None = None,
    mean_max_wear_mm: Array | None = None,
    reference_mean: Mapping[float, float] | None = None,
    reference_nominal: tuple[float, float] | None = None,
    reference_label: str = "reference",
    joint: str | None = None,
) -> Figure:
    """Max bearing wear against cycles: the nominal history, optionally the Monte Carlo mean of the max wear,
    the allowable wear ``limit_mm`` (the study's configured allowance) and a cited reference's values
    (``reference_mean`` {cycles: mm}, ``reference_nominal`` (cycles, mm)), labelled ``reference_label``.
    ``joint``: the clearance joint's name, in the title (a mechanism with several)."""
    fig, ax = figure()
    ax.plot(kilo_cycles(cycles), require_array(max_wear_mm), color=COLORS[0], label="nominal design")
    if mean_cycles is not None and mean_max_wear_mm is not None:
        ax.plot(kilo_cycles(mean_cycles), require_array(mean_max_wear_mm), color=COLORS[2], ls="-", marker="o", ms=3.5,
                label="mean over the random inputs")
    if reference_mean:
        ks = sorted(reference_mean)
        ax.plot(np.array(ks) / 1e3, [reference_mean[k] for k in ks], "x", color=PAPER_COLOR, ms=7, mew=1.8,
                label=f"{reference_label}, mean")
    if reference_nominal:
        ax.plot(reference_nominal[0] / 1e3, reference_nominal[1], "s", mfc="none", color=PAPER_COLOR, ms=7,
                label=f"{reference_label}, nominal")
    if limit_mm is not None:
        hline(ax, limit_mm, f"allowable wear \u03b4\u2080 = {limit_mm:g} mm")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(CYCLES_LABEL)
    ax.set_ylabel(axis_label("max bearing wear", "mm"))
    ax.legend(loc="lower right")
    ax.set_title("Max wear" + (f" of joint {joint}" if joint else "") + " against cycles")
    return fig


# every figure is drawn in the house style without touching the user's rcParams (the reliability figures are
# styled in their own module)
for _name in ("mechanism_figure", "orbit_figure", "contact_force_figure", "wear_polar_figure", "wear_panels_figure",
              "wear_history_figure"):
    globals()[_name] = styled(globals()[_name])
del _name
