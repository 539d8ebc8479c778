"""Figures of the wear stage (matplotlib, Agg). Millimetres and degrees appear only here and in cli.py."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .angles import global_direction, report_angle_deg  # noqa: E402
from .history import JointWear, WearResult  # noqa: E402

MM = 1e3  # m -> mm (output edge)
STYLE = {
    "figure.dpi": 110,
    "font.size": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.4,
}
C_BEARING = "#1f4e79"
C_JOURNAL = "#c0504d"
C_REF = "#7f7f7f"


def exaggeration_factor(max_depth: float, radius: float, target: float = 0.4) -> float:
    """A round factor (1, 2, 5 x 10^k) that draws the max depth as about `target` of the radius."""
    if not (max_depth > 0):
        return 1.0
    raw = target * radius / max_depth
    k = math.floor(math.log10(raw))
    for m in (5.0, 2.0, 1.0):
        if m * 10**k <= raw:
            return m * 10**k
    return 10**k


def _sorted(jw: JointWear, y):
    ang = jw.angle_deg
    o = np.argsort(ang)
    return ang[o], np.asarray(y)[o]


def polar_profile(res: WearResult, path: Path, joint: int = 0, title: str | None = None) -> float:
    """Paper Fig. 18: the worn bearing profile over the initial circle, laid at the rod's mean orientation."""
    jw = res.joints[joint]
    R = jw.bearing_radius
    fac = exaggeration_factor(jw.max_bearing_wear, R)
    th = np.append(jw.theta, jw.theta[0])
    h = np.append(jw.bearing_wear, jw.bearing_wear[0])
    a = global_direction(th, jw.mean_orientation)
    with plt.rc_context(STYLE):
        fig, ax = plt.subplots(figsize=(5.2, 5.2))
        ax.plot(R * MM * np.cos(a), R * MM * np.sin(a), color=C_REF, ls="--", lw=1.0, label="initial bearing circle")
        r = (R + fac * h) * MM
        ax.plot(r * np.cos(a), r * np.sin(a), color=C_BEARING, label=f"worn profile (wear x {fac:g})")
        for i, pk in enumerate(jw.peaks[:3]):
            ph = math.radians(pk["angle_deg"])
            ga = math.pi - ph  # report angle -> global direction (0 deg = leftmost, clockwise)
            rr = (R + fac * pk["depth"]) * MM
            ax.plot([rr * math.cos(ga)], [rr * math.sin(ga)], "o", color=C_JOURNAL, ms=4)
            ax.annotate(f"{pk['angle_deg']:.0f} deg\n{pk['depth'] * MM:.4f} mm", (rr * math.cos(ga), rr * math.sin(ga)),
                        textcoords="offset points", xytext=(8, 4 if i == 0 else -22), fontsize=8)
        ax.annotate("0 deg", (-R * MM, 0), textcoords="offset points", xytext=(4, 2), fontsize=8, color=C_REF)
        ax.annotate("90 deg", (0, R * MM), textcoords="offset points", xytext=(-14, -12), fontsize=8, color=C_REF)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm, global directions at the rod's mean orientation)")
        ax.set_ylabel("y (mm)")
        ax.set_title(title or f"Bearing wear profile after {res.n_cycles:,} cycles\n"
                     "(angles from the leftmost point, clockwise)", fontsize=10)
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)
    return fac


def angle_panels(res: WearResult, path: Path, joint: int = 0) -> None:
    """Paper Fig. 17: sliding distance, contact force, contact area and wear depth against the bearing angle."""
    jw = res.joints[joint]
    d = jw.diagnostics
    n = jw.theta.size
    cell_deg = 360.0 / n
    with plt.rc_context(STYLE):
        fig, axs = plt.subplots(4, 1, figsize=(7.0, 8.5), sharex=True)
        x, y = _sorted(jw, d.slip_distance * MM / cell_deg)
        axs[0].plot(x, y, color=C_BEARING)
        axs[0].set_ylabel("sliding distance\n(mm / deg / cycle)")
        x, y = _sorted(jw, d.force_mean * MM)
        axs[1].plot(x, y, ".", ms=2, color=C_BEARING)
        axs[1].set_ylabel("mean contact force\n(mN)")
        x, y = _sorted(jw, d.area_mean * 1e12)
        axs[2].plot(x, y, ".", ms=2, color=C_BEARING)
        axs[2].set_ylabel("mean contact area\n(um^2)")
        x, y = _sorted(jw, jw.bearing_wear * MM)
        axs[3].plot(x, y, color=C_BEARING)
        axs[3].set_ylabel(f"bearing wear depth\nafter {res.n_cycles:,} cycles (mm)")
        axs[3].set_xlabel("bearing angle (deg, 0 = leftmost point, clockwise)")
        axs[3].set_xlim(0, 360)
        axs[3].set_xticks(np.arange(0, 361, 45))
        fig.suptitle("Contact and wear against the bearing angle (steady cycles of the last block)", fontsize=10)
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)


def history_plot(res: WearResult, path: Path, joint: int = 0, allowance: float | None = None) -> None:
    """Max bearing (and journal) wear depth against cycles, block ends marked."""
    jw = res.joints[joint]
    with plt.rc_context(STYLE):
        fig, ax = plt.subplots(figsize=(6.4, 4.0))
        ax.plot(jw.history_cycles / 1e3, jw.history_max_bearing * MM, "o-", ms=3, color=C_BEARING,
                label="bearing (max depth)")
        if np.any(jw.history_max_journal > 0):
            ax.plot(jw.history_cycles / 1e3, jw.history_max_journal * MM, "s-", ms=3, color=C_JOURNAL,
                    label="journal (max depth)")
        if allowance is not None:
            ax.axhline(allowance * MM, color=C_REF, ls="--", lw=1.0, label=f"bearing allowance 0.01 D = {allowance * MM:g} mm")
        ax.set_xlabel("crank cycles (thousands)")
        ax.set_ylabel("max wear depth (mm)")
        ax.set_title("Wear history (markers: geometry updates)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)


def journal_profile_plot(res: WearResult, path: Path, joint: int = 0) -> None:
    jw = res.joints[joint]
    ang = report_angle_deg(jw.theta, 0.0)
    o = np.argsort(ang)
    with plt.rc_context(STYLE):
        fig, ax = plt.subplots(figsize=(6.4, 3.2))
        ax.plot(ang[o], jw.journal_wear[o] * MM, color=C_JOURNAL)
        ax.set_xlabel("journal angle (deg, crank frame laid along +x; 0 = leftmost, clockwise)")
        ax.set_ylabel("journal wear depth (mm)")
        ax.set_xlim(0, 360)
        ax.set_xticks(np.arange(0, 361, 45))
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)
