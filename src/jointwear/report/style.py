"""One matplotlib style for every figure of jointwear.

Every stage that draws a figure should go through this module::

    from jointwear.report.style import figure, savefig, label_axes

    fig, ax = figure()                      # styled Figure on the Agg canvas, no pyplot
    ax.plot(angle_deg, depth_um)
    label_axes(ax, "angle on the bearing", "deg", "wear depth", "um")
    savefig(fig, out_dir / "wear_profile.png")

Figures are built as :class:`matplotlib.figure.Figure` objects attached to an Agg canvas, never through
``pyplot``: they render the same on a headless machine, in a worker process or in a notebook, they hold no
global state and there is nothing to leak if a figure is not closed. (If a figure was made with pyplot after all,
:func:`savefig` closes it.)

The style itself is plain ``rcParams`` (:data:`RC`); every figure function is wrapped in :func:`styled`, which
applies it through ``matplotlib.rc_context`` for the drawing only (a notebook user's own figures keep their
style).
"""

from __future__ import annotations

import base64
import io
import math
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

import matplotlib
import numpy as np
from cycler import cycler
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image, PngImagePlugin

__all__ = [
    "COLORS",
    "PAPER_COLOR",
    "LIMIT_COLOR",
    "TARGET_COLOR",
    "DPI",
    "SIZES",
    "RC",
    "styled",
    "figure",
    "savefig",
    "to_png_bytes",
    "to_data_uri",
    "label_axes",
    "axis_label",
    "scale_to_unit",
    "angle_axis",
    "hline",
    "vline",
    "note",
    "no_data",
    "panel_letter",
]

#: Colour cycle: Paul Tol's "bright" scheme, distinguishable with the common colour-vision deficiencies and
#: in grey-scale print.
COLORS: tuple[str, ...] = ("#4477AA", "#EE6677", "#228833", "#CCBB44", "#66CCEE", "#AA3377", "#BBBBBB")
#: Colour for values taken from the reference paper, when drawn beside ours.
PAPER_COLOR = "#222222"
#: Colour of a failure limit (the allowable wear delta_0).
LIMIT_COLOR = "#CC3311"
#: Colour of a target (the required reliability).
TARGET_COLOR = "#EE7733"

#: Resolution of every saved PNG (dots per inch).
DPI = 150

#: Figure sizes in inches: one column of a report page, a full-width figure, a tall panel figure, a square.
SIZES: dict[str, tuple[float, float]] = {
    "single": (6.4, 4.0),
    "wide": (9.6, 4.0),
    "panels": (9.6, 6.8),
    "square": (5.6, 5.6),
    "tall": (6.4, 6.4),
}

#: The rcParams of the house style.
RC: dict[str, object] = {
    "figure.dpi": 100,
    "savefig.dpi": DPI,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.08,
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
    "font.family": "sans-serif",
    "font.sans-serif": ["DejaVu Sans", "Arial", "Helvetica", "sans-serif"],
    "font.size": 10.0,
    "axes.titlesize": 11.0,
    "axes.titleweight": "bold",
    "axes.titlelocation": "left",
    "axes.labelsize": 10.0,
    "xtick.labelsize": 9.0,
    "ytick.labelsize": 9.0,
    "legend.fontsize": 9.0,
    "legend.frameon": False,
    "figure.titlesize": 12.0,
    "axes.prop_cycle": cycler(color=list(COLORS)),
    "axes.grid": True,
    "axes.axisbelow": True,
    "grid.color": "#D9D9D9",
    "grid.linewidth": 0.6,
    "grid.linestyle": "-",
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.edgecolor": "#555555",
    "axes.linewidth": 0.8,
    "lines.linewidth": 1.6,
    "lines.markersize": 5.0,
    "patch.linewidth": 0.6,
    "hist.bins": "auto",
    "xtick.direction": "out",
    "ytick.direction": "out",
    "axes.formatter.useoffset": False,
    "axes.formatter.limits": (-4, 5),
    "mathtext.default": "regular",
}


def styled(draw):
    """Run a figure-drawing function inside ``matplotlib.rc_context(RC)``: the house style for the figures it
    draws, and the user's own ``rcParams`` untouched."""
    import functools

    @functools.wraps(draw)
    def wrapper(*args, **kwargs):
        with matplotlib.rc_context(RC):
            return draw(*args, **kwargs)

    return wrapper


def figure(
    nrows: int = 1,
    ncols: int = 1,
    *,
    size: str | tuple[float, float] = "single",
    polar: bool = False,
    squeeze: bool = True,
    **subplot_kw,
):
    """A styled figure and its axes, on the Agg canvas (no pyplot, no display needed).

    ``size`` is a key of :data:`SIZES` or ``(width, height)`` in inches. Returns ``(fig, ax)`` where ``ax`` is one
    Axes when ``nrows == ncols == 1`` and ``squeeze`` is true, otherwise an array of Axes, as
    :func:`matplotlib.pyplot.subplots`.
    """
    figsize = SIZES[size] if isinstance(size, str) else tuple(size)
    with matplotlib.rc_context(RC):  # the axes keep the style's colour cycle, ticks and spines
        fig = Figure(figsize=figsize, layout="constrained")
        FigureCanvasAgg(fig)
        if polar:
            subplot_kw = {**subplot_kw, "projection": "polar"}
        axes = fig.subplots(nrows, ncols, squeeze=squeeze, subplot_kw=subplot_kw or None)
    return fig, axes


def _close(fig: Figure) -> None:
    import sys

    plt = sys.modules.get("matplotlib.pyplot")  # only if someone imported pyplot already
    if plt is not None:
        try:
            plt.close(fig)
        except Exception:  # a Figure that pyplot does not manage
            pass


def savefig(fig: Figure, path: str | Path, *, dpi: int = DPI, close: bool = True) -> Path:
    """Write ``fig`` as a PNG at :data:`DPI` (parents created) and close it. Returns the path."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        path = path.with_suffix(".png")
    from jointwear.study.io import write_bytes_atomic  # it makes the folder

    return write_bytes_atomic(path, to_png_bytes(fig, dpi=dpi, close=close))


def to_png_bytes(fig: Figure, *, dpi: int = DPI, close: bool = True) -> bytes:
    """The PNG bytes of ``fig`` (at :data:`DPI`, opaque, 256 colours); closes it unless ``close=False``.

    A palette of 256 colours holds the figures' flat colours and their anti-aliasing: it makes the files (and the
    report that embeds them) about 60 % smaller than full colour, with no visible change."""
    buf = io.BytesIO()
    if fig.canvas is None or not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    with matplotlib.rc_context(RC):
        fig.savefig(buf, dpi=dpi, format="png")
    if close:
        _close(fig)
    with Image.open(buf) as full:
        palette = full.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", "jointwear")
    out = io.BytesIO()
    palette.save(out, format="PNG", optimize=True, pnginfo=info, dpi=(dpi, dpi))
    return out.getvalue()


def to_data_uri(fig_or_png: Figure | bytes, *, dpi: int = DPI) -> str:
    """A ``data:image/png;base64,...`` URI of a figure (closed afterwards) or of PNG bytes."""
    png = fig_or_png if isinstance(fig_or_png, (bytes, bytearray)) else to_png_bytes(fig_or_png, dpi=dpi)
    return "data:image/png;base64," + base64.b64encode(bytes(png)).decode("ascii")


def axis_label(quantity: str, unit: str | None) -> str:
    """``"quantity (unit)"``; micro written as the Greek letter; dimensionless quantities get ``(-)``."""
    if unit is None or unit == "":
        return f"{quantity} (-)"
    unit = re.sub(r"(?<![A-Za-z])um(?![A-Za-z])", "\u00b5m", unit)
    unit = unit.replace("mm2", "mm\u00b2").replace("\u00b5m2", "\u00b5m\u00b2")
    return f"{quantity} ({unit})"


def label_axes(ax, xquantity: str, xunit: str | None, yquantity: str, yunit: str | None) -> None:
    """Label both axes of ``ax`` with quantity and unit (every axis of the project carries its unit)."""
    ax.set_xlabel(axis_label(xquantity, xunit))
    ax.set_ylabel(axis_label(yquantity, yunit))


_PREFIXES = [(1e-9, "n"), (1e-6, "\u00b5"), (1e-3, "m"), (1.0, "")]


def scale_to_unit(values: Iterable[float], unit: str) -> tuple[np.ndarray, str]:
    """Rescale SI-base ``values`` (unit ``"N"``, ``"m"``, ...) to a readable prefix: 0.029 N -> (29, "mN").

    The prefix is chosen from the largest absolute finite value; only n, u, m and none are used.
    """
    arr = np.asarray(list(values) if not isinstance(values, np.ndarray) else values, dtype=float)
    finite = np.abs(arr[np.isfinite(arr)])
    peak = float(finite.max()) if finite.size else 0.0
    factor, prefix = 1.0, ""
    if peak > 0:
        for f, p in _PREFIXES:
            if peak >= f:
                factor, prefix = f, p
        if peak < 1e-9:
            factor, prefix = 1e-9, "n"
    return arr / factor, prefix + unit


def angle_axis(ax, axis: str = "x", *, step: float = 45.0, label: str | None = "angle on the bearing") -> None:
    """Make ``axis`` an angle axis from 0 to 360 deg with ticks every ``step`` deg."""
    ticks = np.arange(0.0, 360.0 + 1e-9, step)
    if axis == "x":
        ax.set_xlim(0, 360)
        ax.set_xticks(ticks)
        if label:
            ax.set_xlabel(axis_label(label, "deg"))
    else:
        ax.set_ylim(0, 360)
        ax.set_yticks(ticks)
        if label:
            ax.set_ylabel(axis_label(label, "deg"))


def hline(ax, y: float, text: str | None = None, *, color: str = LIMIT_COLOR, ls: str = "--") -> None:
    """A horizontal reference line (limit, target) labelled at its right end."""
    ax.axhline(y, color=color, ls=ls, lw=1.2, zorder=1)
    if text:
        ax.annotate(text, xy=(1.0, y), xycoords=("axes fraction", "data"), xytext=(-4, 3),
                    textcoords="offset points", ha="right", va="bottom", fontsize=8.5, color=color,
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85})


def vline(ax, x: float, text: str | None = None, *, color: str = TARGET_COLOR, ls: str = ":") -> None:
    """A vertical reference line labelled near its top."""
    ax.axvline(x, color=color, ls=ls, lw=1.2, zorder=1)
    if text:
        ax.annotate(text, xy=(x, 1.0), xycoords=("data", "axes fraction"), xytext=(4, -4),
                    textcoords="offset points", ha="left", va="top", fontsize=8.5, color=color,
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85})


def note(ax, text: str, *, loc: str = "upper right") -> None:
    """A small boxed note inside the axes (for example an exaggeration factor or a sample size)."""
    pos = {"upper right": (0.98, 0.97, "right", "top"), "upper left": (0.02, 0.97, "left", "top"),
           "lower right": (0.98, 0.03, "right", "bottom"), "lower left": (0.02, 0.03, "left", "bottom")}[loc]
    ax.text(pos[0], pos[1], text, transform=ax.transAxes, ha=pos[2], va=pos[3], fontsize=8.5,
            bbox={"boxstyle": "round,pad=0.3", "fc": "white", "ec": "#BBBBBB", "alpha": 0.9})


def no_data(ax, text: str = "not provided") -> None:
    """Mark an empty panel plainly instead of leaving it blank."""
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", color="#888888", fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.grid(False)


def panel_letter(ax, letter: str) -> None:
    """Panel letters "(a)", "(b)", ... at the top left, outside the plotting area."""
    ax.set_title(f"({letter})", loc="left", fontweight="bold")


def nice_number(x: float) -> float:
    """The nearest 1, 2 or 5 times a power of ten not above ``x`` (for exaggeration factors, bins)."""
    if not (x > 0 and math.isfinite(x)):
        return 1.0
    exp = math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * 10**exp <= x:
            return m * 10**exp
    return 10**exp


def as_array(values: Sequence[float] | np.ndarray | None) -> np.ndarray | None:
    """``values`` as a 1-D float array, ``None`` kept, ``None`` entries read as NaN."""
    if values is None:
        return None
    return np.array([np.nan if v is None else v for v in np.ravel(np.asarray(values, dtype=object))], dtype=float)


def require_array(values) -> np.ndarray:
    """:func:`as_array` for data a figure cannot do without (ValueError when it is missing)."""
    out = as_array(values)
    if out is None:
        raise ValueError("missing data for a figure")
    return out


def kilo_cycles(cycles) -> np.ndarray:
    """Cycles in thousands, the unit of every cycles axis."""
    return require_array(cycles) / 1e3


CYCLES_LABEL = axis_label("crank cycles N", "\u00d710\u00b3")
