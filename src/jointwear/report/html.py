"""The self-contained HTML report of a study: ``build_report(out_dir) -> out_dir / "report.html"``.

The page needs nothing but the file: figures are PNG data URIs, the CSS is inline, there is no script and no
external resource. It reads whatever of the stage outputs are present in ``out_dir`` and says plainly what is
missing; a malformed file or key spoils only its own section.

Files and keys read (all optional; units in the key names)
-----------------------------------------------------------
``config.json`` (or ``settings.json``): the study's resolved configuration::

    {"preset": "jin2025_flapping_wing" | null,
     "citation": "Jin et al. ... Drones 2025, 9(4), 282.",
     "source": "preset" | "path/to/study.toml",
     "seed": 12345, "jointwear_version": "0.1.0",              # any other top-level scalars are listed too
     "mechanism": {"type": "crank_rocker", "crank_mm": 6, "rod_mm": 38, "rocker_mm": 12,
                   "pivot_mm": [11.5, 38], "branch": 1, "clearance_joint": "A"},   # for the sketch
     "settings": [{"name": "friction.mu_dynamic", "value": 0.1, "unit": null,
                   "source": "paper-notes.md: Eq. 19 garbled", "paper_open": true,
                   "description": "..."}, ...]}

  Without a ``settings`` list, a nested config dump is flattened into dotted names (no sources then).
  ``allowance_mm``: the configured allowable wear (drawn on the wear figures before any stage's own value).
  ``reference``: the config's cited reference results (``jointwear.reference``, in mm / deg / h; see
  :mod:`jointwear.report.settings`). The comparison section, the reference's points on the figures and the
  acceptance bands appear only when it is present; without it the report is about the study alone.

``simulate.json``: ``contact_force_mean_N``, ``contact_force_max_N``, ``contact_fraction``,
``impacts_per_cycle``, ``steps_per_cycle``, ``wall_seconds_per_cycle`` (DESIGN.md) and, for the figures,
``clearance_mm``, ``orbit`` {``x_mm``, ``y_mm``} (journal centre relative to the bearing centre, bearing
frame) and ``contact_force`` {``crank_angle_deg``, ``force_N``[, ``ideal_force_N``]}. Where the series are not in
the JSON, any ``*.csv`` in ``out_dir`` (or ``out_dir/data``) with columns ``x_mm``/``y_mm`` and
``crank_angle_deg``/``contact_force_N`` (or ``force_N``) is used; ``_um``, ``_m``, ``_mN``, ``_rad`` suffixes are
converted.

``wear.json``: ``cycles``, ``max_wear_mm``, ``max_wear_angle_deg``, ``peaks`` [{``angle_deg``, ``depth_mm``}],
``profile`` {``angle_deg``, ``depth_mm``[, ``contact_force_N``, ``slip_mm``, ``contact_area_mm2``]},
``history`` {``cycles``, ``max_wear_mm``}, ``wall_seconds`` and optionally ``bearing_radius_mm``,
``geometry_mode``, ``limit_mm``, ``journal_profile`` {``angle_deg``, ``depth_mm``}. The Fig. 17 columns may
instead be in a CSV with an ``angle_deg`` column.

``reliability.json``: ``curve`` {``cycles``, ``reliability``, ``pf_cov``}, ``life_at_target`` {``target``,
``cycles``, ``hours``}, ``model_calls``, ``n_mc``, ``wall_seconds``; optionally ``histograms`` {``cycles``,
``max_wear_mm``: [[...], ...]}, ``convergence`` {``n_calls``, ``pf``[, ``cov``, ``cycles``]},
``mean_max_wear_mm`` {``cycles``, ``mean``}, ``limit_mm``, and any other scalar (listed as is).

``sensitivity.json``: ``variables`` [{``name``, ``label``, ``reliability_low``, ``reliability_high``[,
``group``, ``reliability_low_error``, ``reliability_high_error``]}], ``reliability_nominal``, ``cycles``,
optionally ``unresolved_pairs`` [{``first``, ``second``, ...}] (neighbours of a ranking within the surrogate's
error, shown as ≈) and ``sobol`` {``names``, ``S1``, ``ST``[, ``S1_conf``, ``ST_conf``, ``output``]}.

Any ``*.png`` in ``out_dir`` is embedded where the report has no data to draw that figure itself (matched by
name: orbit, force, polar/profile, fig17/panels, history, reliability, histogram, convergence, tornado, sobol)
and the others in an appendix.
"""

from __future__ import annotations

import base64
import csv
import datetime as _dt
import html
import json
import math
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import figures as F
from .design_section import design_section
from .style import DPI, to_data_uri

__all__ = ["build_report", "Check", "reference_checks", "reference_of", "read_inputs"]

PASS, FAIL, INFO, NA = "pass", "fail", "info", "n/a"


def e(x) -> str:
    """HTML-escaped text of anything."""
    return html.escape("" if x is None else str(x), quote=True)


def _num(v, digits: int = 4) -> str:
    if v is None:
        return "\u2014"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return f"{int(v):,}"
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            return str(v)
        if 1000 <= abs(v) < 1e9:
            return f"{v:,.0f}"
        if v != 0 and (abs(v) < 1e-3 or abs(v) >= 1e9):
            return f"{v:.{digits - 1}e}"
        return f"{v:.{digits}g}"
    if isinstance(v, (list, tuple)):
        if len(v) > 8:
            return f"[{', '.join(_num(x, digits) for x in v[:6])}, \u2026 ({len(v)} values)]"
        return "[" + ", ".join(_num(x, digits) for x in v) + "]"
    return str(v)


def format_number(v, digits: int = 4) -> str:
    """A number as the report shows it (thousands separators, ``digits`` significant digits, em dash for None)."""
    return _num(v, digits)


def _float(v) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


# ------------------------------------------------------------------------------------------------ reading
@dataclass
class Inputs:
    out_dir: Path
    data: dict[str, dict] = field(default_factory=dict)  # stage -> parsed JSON
    errors: dict[str, str] = field(default_factory=dict)  # stage -> why it could not be read
    files: list[Path] = field(default_factory=list)
    csv_tables: list[tuple[str, dict[str, np.ndarray]]] = field(default_factory=list)
    pngs: dict[str, Path] = field(default_factory=dict)  # stem -> path
    used_pngs: set[str] = field(default_factory=set)
    results: object = None  # jointwear.study.StudyResults


def _read_json(path: Path):
    text = path.read_text(encoding="utf-8")
    obj = json.loads(text)
    if not isinstance(obj, dict):
        raise ValueError(f"expected a JSON object, found {type(obj).__name__}")
    return obj


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    rows: list[list[str]] = []
    with path.open(newline="", encoding="utf-8", errors="replace") as fh:
        lines = (ln for ln in fh if ln.strip() and not ln.lstrip().startswith("#"))
        reader = csv.reader(lines)
        header = next(reader, None)
        if not header:
            return {}
        for row in reader:
            rows.append(row)
    names = [h.strip() for h in header]
    out: dict[str, np.ndarray] = {}
    for j, name in enumerate(names):
        col = []
        for r in rows:
            try:
                col.append(float(r[j]))
            except (ValueError, IndexError):
                col.append(np.nan)
        out[name] = np.asarray(col, dtype=float)
    return out


def read_inputs(out_dir: Path) -> Inputs:
    """The study's results through :func:`jointwear.load_results` (typed, checked), their canonical JSON for
    the sections, and the folder's CSV tables and PNG files."""
    from jointwear.study import load_results
    from jointwear.study.io import strict

    inp = Inputs(Path(out_dir))
    results = load_results(inp.out_dir)
    inp.results = results
    inp.errors.update(results.errors)
    if results.config is not None:
        inp.data["config"] = results.config
        inp.files.append(inp.out_dir / "config.json")
    for stage in results.stages:
        result = getattr(results, stage)
        inp.data[stage] = json.loads(json.dumps(strict(result.to_json())))
        inp.files.append(inp.out_dir / result.FILE)
    for folder in (inp.out_dir, inp.out_dir / "data"):
        if not folder.is_dir():
            continue
        for p in sorted(folder.glob("*.csv")):
            if p.stat().st_size > 200e6:
                continue
            try:
                table = _read_csv(p)
            except Exception:
                continue
            if table:
                inp.csv_tables.append((p.name, table))
                inp.files.append(p)
        for p in sorted(folder.glob("*.png")):
            inp.pngs[p.stem] = p
    return inp


_UNITS = {
    "length_mm": {"mm": 1.0, "um": 1e-3, "m": 1e3},
    "force_N": {"N": 1.0, "mN": 1e-3},
    "area_mm2": {"mm2": 1.0, "um2": 1e-6, "m2": 1e6},
    "angle_deg": {"deg": 1.0, "rad": 180.0 / math.pi},
    "plain": {"": 1.0},
    "slip_density": {"mm_per_deg_per_cycle": 1.0},
}


def _lookup(sources: Sequence[Mapping], bases: Sequence[str], kind: str) -> np.ndarray | None:
    """The first series named ``base_suffix`` (converted to the kind's unit) in the first source that has it."""
    for src in sources:
        if not isinstance(src, Mapping):
            continue
        for base in bases:
            for suffix, factor in _UNITS[kind].items():
                key = f"{base}_{suffix}" if suffix else base
                if key in src and src[key] is not None:
                    try:
                        arr = np.asarray(src[key], dtype=float).ravel() * factor
                    except (TypeError, ValueError):
                        continue
                    if arr.size:
                        return arr
    return None


def _pair(inp: Inputs, json_src: Mapping | None, xb, xk, yb, yk):
    """Two series from the same source: the JSON object first, then each CSV table."""
    sources = ([json_src] if isinstance(json_src, Mapping) else []) + [t for _, t in inp.csv_tables]
    for src in sources:
        x = _lookup([src], xb, xk)
        y = _lookup([src], yb, yk)
        if x is not None and y is not None and x.size == y.size:
            return x, y, src
    return None, None, None


def _npz_series(inp: Inputs, sim: Mapping) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Orbit and contact force of the first clearance joint from the dynamics stage's ``series_file`` (npz):
    ``crank_angle_rad``, ``<joint>_eccentricity_bearing_frame_m`` (n x 2), ``<joint>_force_normal_N``."""
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    name = sim.get("series_file")
    if not isinstance(name, str):
        return out
    path = (inp.out_dir / name).resolve()
    if inp.out_dir.resolve() not in path.parents or not path.is_file():
        return out
    try:
        with np.load(path, allow_pickle=False) as z:
            keys = list(z.files)
            joints = sim.get("joints") if isinstance(sim.get("joints"), list) else []
            prefix = f"{joints[0].get('name')}_" if joints and isinstance(joints[0], Mapping) else ""
            ecc = next((k for k in keys if k.startswith(prefix) and k.endswith("eccentricity_bearing_frame_m")), None)
            if ecc is not None:
                e_ = np.asarray(z[ecc], dtype=float)
                if e_.ndim == 2 and e_.shape[1] == 2:
                    out["orbit"] = (e_[:, 0] * 1e3, e_[:, 1] * 1e3)
            fkey = next((k for k in keys if k.startswith(prefix) and k.endswith("force_normal_N")), None)
            if fkey is not None and "crank_angle_rad" in keys:
                out["force"] = (np.degrees(np.asarray(z["crank_angle_rad"], dtype=float)),
                                np.asarray(z[fkey], dtype=float))
    except Exception:  # an unreadable series file leaves the figures to the other sources
        return {}
    return out


# ------------------------------------------------------------------------------------------------ html bits
def _png_width(uri: str) -> int | None:
    """Width in pixels of a PNG data URI (from its IHDR chunk)."""
    try:
        head = base64.b64decode(uri.split(",", 1)[1][:48])
        return int.from_bytes(head[16:20], "big") if head[:8] == b"\x89PNG\r\n\x1a\n" else None
    except Exception:
        return None


def _figure_html(uri: str, caption: str, *, wide: bool = False) -> str:
    """A figure shown at its physical size (DPI pixels per inch), never wider than the page."""
    cls = "fig wide" if wide else "fig"
    px = _png_width(uri)
    width = f' width="{round(px * 96 / DPI)}"' if px else ""
    return (f'<figure class="{cls}"><img src="{uri}"{width} alt="{e(caption)}">'
            f"<figcaption>{e(caption)}</figcaption></figure>")


def _missing(text: str) -> str:
    return f'<p class="missing">{e(text)}</p>'


def _cards(items: Sequence[tuple[str, str, str | None]]) -> str:
    """Key numbers as cards: (label, value, note)."""
    out = ['<div class="cards">']
    for label, value, note in items:
        out.append(f'<div class="card"><div class="card-label">{e(label)}</div>'
                   f'<div class="card-value">{e(value)}</div>'
                   + (f'<div class="card-note">{e(note)}</div>' if note else "") + "</div>")
    out.append("</div>")
    return "".join(out)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], *, cls: str = "",
           raw_cols: Sequence[int] = (), row_cls: Sequence[str] | None = None) -> str:
    """A table; cells are escaped except the columns in ``raw_cols`` (already HTML)."""
    out = [f'<table class="{cls}"><thead><tr>' + "".join(f"<th>{e(h)}</th>" for h in header) + "</tr></thead><tbody>"]
    for i, r in enumerate(rows):
        rc = f' class="{row_cls[i]}"' if row_cls and row_cls[i] else ""
        out.append(f"<tr{rc}>" + "".join(f"<td>{c if j in raw_cols else e(c)}</td>" for j, c in enumerate(r))
                   + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def _pill(status: str) -> str:
    text = {PASS: "PASS", FAIL: "FAIL", INFO: "info", NA: "no data"}.get(status, status)
    return f'<span class="pill {e(status.replace("/", ""))}">{e(text)}</span>'


class _Figures:
    """Draws figures, falling back to a stage's PNG file, and records failures instead of raising."""

    def __init__(self, inp: Inputs):
        self.inp = inp
        self.count = 0

    def draw(self, make: Callable[[], object] | None, caption: str, *, png_keys: Sequence[str] = (),
             wide: bool = False, missing: str | None = None) -> str:
        if make is not None:
            try:
                uri = to_data_uri(make())
                self.count += 1
                self._supersede(png_keys)
                return _figure_html(uri, caption, wide=wide)
            except Exception as exc:  # a figure that cannot be drawn must not end the report
                err = f"{type(exc).__name__}: {exc}"
                png = self._png(png_keys)
                if png:
                    return png
                return _missing(f"{caption}: the figure could not be drawn ({err}).")
        png = self._png(png_keys, caption)
        if png:
            return png
        return _missing(missing or f"{caption}: no data in this folder.")

    def _supersede(self, keys: Sequence[str]) -> None:
        """The stage's own file of a figure drawn here from data is not shown again in the appendix."""
        for key in keys:
            for stem in sorted(self.inp.pngs):
                if stem not in self.inp.used_pngs and key in stem.lower():
                    self.inp.used_pngs.add(stem)
                    return

    def _png(self, keys: Sequence[str], caption: str = "") -> str | None:
        for key in keys:
            for stem, path in sorted(self.inp.pngs.items()):
                if stem in self.inp.used_pngs or key not in stem.lower():
                    continue
                try:
                    data = path.read_bytes()
                except OSError:
                    continue
                if not data.startswith(b"\x89PNG"):
                    continue
                self.inp.used_pngs.add(stem)
                self.count += 1
                uri = "data:image/png;base64," + base64.b64encode(data).decode("ascii")
                return _figure_html(uri, f"{caption} (figure file {path.name})" if caption else path.name)
        return None


# ------------------------------------------------------------------------------------------------ checks
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

    @property
    def rel_diff(self) -> float | None:
        if self.reference in (None, 0) or self.ours is None:
            return None
        return (self.ours - self.reference) / abs(self.reference)


def _circ_diff(a: float, b: float) -> float:
    d = abs((a - b) % 360.0)
    return min(d, 360.0 - d)


def _interp_at(xs, ys, x: float) -> float | None:
    try:
        xs = np.asarray(xs, dtype=float)
        ys = np.asarray([np.nan if v is None else v for v in ys], dtype=float)
    except (TypeError, ValueError):
        return None
    ok = np.isfinite(xs) & np.isfinite(ys)
    xs, ys = xs[ok], ys[ok]
    if xs.size == 0 or x < xs.min() - 1e-9 or x > xs.max() + 1e-9:
        return None
    order = np.argsort(xs)
    return float(np.interp(x, xs[order], ys[order]))


def _life_from_curve(cycles, rel, target: float) -> float | None:
    try:
        c = np.asarray(cycles, dtype=float)
        r = np.asarray([np.nan if v is None else v for v in rel], dtype=float)
    except (TypeError, ValueError):
        return None
    order = np.argsort(c)
    c, r = c[order], r[order]
    for i in range(len(c) - 1):
        if r[i] >= target > r[i + 1]:
            return float(c[i] + (c[i + 1] - c[i]) * (r[i] - target) / (r[i] - r[i + 1]))
    return None


def _geometry_mode(wear: Mapping) -> str | None:
    mode = wear.get("geometry_mode")
    if mode is None and isinstance(wear.get("settings"), Mapping):
        mode = wear["settings"].get("geometry_mode")
    return None if mode is None else str(mode)


def _limit_mm(*sources: Mapping) -> float | None:
    """The allowable wear delta_0 (mm): ``allowance_mm`` or ``limit_mm`` of the first source that has one
    (callers put the study's settings first, so the configured allowance wins over a stage's own line)."""
    for src in sources:
        for key in ("allowance_mm", "limit_mm"):
            v = _float(src.get(key)) if isinstance(src, Mapping) else None
            if v is not None:
                return v
    return None


def _second_peak(wear: Mapping) -> tuple[float, float] | None:
    """The largest wear on the far side (more than 90 deg from the main peak)."""
    main = _float(wear.get("max_wear_angle_deg"))
    peaks = [(float(p["angle_deg"]), float(p["depth_mm"])) for p in wear.get("peaks") or []
             if isinstance(p, Mapping) and _float(p.get("angle_deg")) is not None
             and _float(p.get("depth_mm")) is not None]
    prof = wear.get("profile") or {}
    ang = np.asarray(prof.get("angle_deg") or [], dtype=float)
    dep = np.asarray([np.nan if v is None else v for v in prof.get("depth_mm") or []], dtype=float)
    if main is None:
        if peaks:
            main = max(peaks, key=lambda p: p[1])[0]
        elif ang.size and ang.size == dep.size:
            main = float(ang[np.nanargmax(dep)])
        else:
            return None
    far = [p for p in peaks if _circ_diff(p[0], main) > 90.0]
    if far:
        return max(far, key=lambda p: p[1])
    if ang.size and ang.size == dep.size:
        mask = np.array([_circ_diff(a, main) > 90.0 for a in ang])
        if mask.any():
            i = np.nanargmax(np.where(mask, dep, -np.inf))
            return float(ang[i]), float(dep[i])
    return None


def _mean_max_wear(rel: Mapping, levels) -> dict[float, float]:
    """The study's mean of the max wear (mm) at each of ``levels`` (cycles) where it has one."""
    out: dict[float, float] = {}
    m = rel.get("mean_max_wear_mm")
    if isinstance(m, Mapping) and m.get("cycles") is not None and m.get("mean") is not None:
        for n in levels:
            v = _interp_at(m["cycles"], m["mean"], n)
            if v is not None:
                out[n] = v
    h = rel.get("histograms")
    if isinstance(h, Mapping) and h.get("cycles") is not None and h.get("max_wear_mm") is not None:
        for c, s in zip(h["cycles"], h["max_wear_mm"]):
            c = _float(c)
            if c in levels and c not in out:
                arr = np.asarray([np.nan if v is None else v for v in s], dtype=float)
                if np.isfinite(arr).any():
                    out[c] = float(np.nanmean(arr))
    return out


_TOL_KEYS = [("rod length", ("rod", "l2")), ("clearance", ("clearance",)), ("journal radius", ("journal radius", "r_j")),
             ("crank length", ("crank", "l1")), ("rocker length", ("rocker", "l_bc"))]
_MAT_KEYS = [("Brinell hardness", ("hardness", "brinell", "hb")), ("Young's modulus", ("young", "modulus")),
             ("wear coefficient", ("wear coef", "wear_coef")), ("Poisson's ratio", ("poisson",))]


def _classify(var: Mapping) -> tuple[str | None, str | None]:
    """(group, paper quantity) of a sensitivity variable, from its group, label and name."""
    label = str(var.get("label") or "").lower()
    name = str(var.get("name") or "").lower()
    text = f"{label} | {name}"
    group = str(var.get("group") or "").lower().replace("_", " ").strip() or None
    group = {"tolerance": "tolerances", "other": None}.get(group, group) if group else None
    for qty, keys in _MAT_KEYS:
        if any(k in text for k in keys) or (qty == "Young's modulus" and name.startswith("e_")) or (
                qty == "Poisson's ratio" and name.startswith("nu")) or (
                qty == "wear coefficient" and name.startswith("k_")):
            if group is None:
                if "journal" in text or name.endswith("_j"):
                    group = "journal material"
                elif "bearing" in text or name.endswith("_b"):
                    group = "bearing material"
            return group, qty
    for qty, keys in _TOL_KEYS:
        if any(k == name or k in label for k in keys):
            return group or "tolerances", qty
    return group, None


def _spread(var: Mapping, nominal: float) -> float:
    vals = [_float(var.get("reliability_low")), _float(var.get("reliability_high"))]
    return max([abs(v - nominal) for v in vals if v is not None] or [0.0])


def _rankings(sens: Mapping) -> dict[str, list[tuple[str, str | None, float, str]]]:
    """Per group, the variables by decreasing effect on R: (display label, paper quantity, spread, name)."""
    nominal = _float(sens.get("reliability_nominal"))
    out: dict[str, list] = {}
    if nominal is None:
        return out
    for var in sens.get("variables") or []:
        if not isinstance(var, Mapping):
            continue
        group, qty = _classify(var)
        out.setdefault(group or "variables", []).append(
            (str(var.get("label") or var.get("name")), qty, _spread(var, nominal), str(var.get("name"))))
    for g in out:
        out[g].sort(key=lambda t: -t[2])
    return out


def _unresolved(sens: Mapping) -> set[tuple[str, str]]:
    """(first, second) names of ranking neighbours the study's surrogate error does not separate."""
    pairs = sens.get("unresolved_pairs") or []
    return {(str(p.get("first")), str(p.get("second"))) for p in pairs if isinstance(p, Mapping)}


def _ranking_text(items: Sequence[tuple], unresolved: set[tuple[str, str]], field: int = 0) -> str:
    """'a > b ≈ c': ≈ between neighbours whose order is within the surrogate's error."""
    text = ""
    for k, item in enumerate(items):
        if k:
            text += " ≈ " if (items[k - 1][3], item[3]) in unresolved else " > "
        text += str(item[field])
    return text


def reference_of(data: Mapping[str, Mapping]) -> dict | None:
    """The cited reference results of the study (``reference`` in the settings JSON), or None."""
    cfg = data.get("config")
    ref = cfg.get("reference") if isinstance(cfg, Mapping) else None
    if isinstance(ref, Mapping) and isinstance(ref.get("values"), list) and ref["values"]:
        return dict(ref)
    return None


def reference_values(ref: Mapping | None, quantity: str) -> list[Mapping]:
    """The reference's values of one quantity, in the order the config gives them."""
    if not ref:
        return []
    return [v for v in ref.get("values") or [] if isinstance(v, Mapping) and v.get("quantity") == quantity]


def reference_label(ref: Mapping | None) -> str:
    """Short name of the reference for figures and tables ('reference' when it has none)."""
    return str((ref or {}).get("label") or "reference")


def _group_key(group: object) -> str:
    """'tolerances' / 'tolerance' / 'bearing material' -> one key."""
    g = str(group or "").strip().lower().replace(" ", "_")
    return g[:-1] if g.endswith("s") else g


_GROUP_TITLES = {"tolerance": "tolerances"}


def _band_text(band: Mapping | None, unit: str) -> str:
    if not isinstance(band, Mapping):
        return "reported (no band)"
    kind = band.get("kind")
    u = "" if unit in ("", "-") else f" {unit}"
    if kind == "absolute":
        a = _float(band.get("absolute"))
        return f"within {a:g}{u}" if unit == "deg" else (f"\u00b1{a:g} absolute" if not u else f"\u00b1{a:g}{u}")
    if kind == "relative":
        return f"within {100 * _float(band.get('relative')):g} %"
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
    if not isinstance(band, Mapping) or ref is None and band.get("kind") in ("absolute", "relative"):
        return INFO
    kind = band.get("kind")
    if kind == "absolute":
        d = _circ_diff(ours, ref) if unit == "deg" else abs(ours - ref)
        return PASS if d <= float(band["absolute"]) else FAIL
    if kind == "relative":
        return PASS if abs(ours - ref) <= float(band["relative"]) * abs(ref) else FAIL
    lo, hi = _float(band.get("lower")), _float(band.get("upper"))
    return PASS if (lo is None or ours >= lo) and (hi is None or ours <= hi) else FAIL


def _life_at_target(rel: Mapping, target: float) -> tuple[float | None, float | None]:
    """(cycles, hours) of the life at ``target`` that reliability.json reports (one record or a list)."""
    lt = rel.get("life_at_target")
    records = (lt if isinstance(lt, list) else [lt]) + list(rel.get("life_table") or [])
    for r in records:
        if isinstance(r, Mapping):
            t = _float(r.get("target"))
            if t is None or abs(t - target) < 1e-12:
                return _float(r.get("cycles")), _float(r.get("hours"))
    return None, None


def _our_life(rel: Mapping, target: float) -> tuple[float | None, str]:
    """The study's life at ``target`` (cycles) and a note on how it was read."""
    curve = rel.get("curve") if isinstance(rel.get("curve"), Mapping) else {}
    life, _h = _life_at_target(rel, target)
    note = ""
    if life is None and curve.get("cycles") is not None and curve.get("reliability") is not None:
        life = _life_from_curve(curve["cycles"], curve["reliability"], target)
        note = "interpolated on the R(N) curve" if life is not None else ""
    if life is not None and curve.get("cycles") is not None and curve.get("reliability") is not None:
        try:
            first = int(np.nanargmin(np.asarray(curve["cycles"], dtype=float)))
            r_first = _float(curve["reliability"][first])
            n_first = _float(curve["cycles"][first])
        except (TypeError, ValueError, IndexError):
            r_first = n_first = None
        if r_first is not None and n_first is not None and r_first < target and life <= n_first:
            note = (f"R = {r_first:.3f} < {target:g} already at the first cycle count of the curve "
                    f"({n_first:,.0f}): the life is at most this")
    return life, note


def _ranking_check(sens: Mapping, v: Mapping) -> Check:
    group = str(v.get("group") or "")
    title = f"sensitivity ranking, {_GROUP_TITLES.get(_group_key(group), group.replace('_', ' '))}"
    ref_rank = [str(x) for x in v.get("ranking") or []]
    band = v.get("band") if isinstance(v.get("band"), Mapping) else None
    nominal = _float(sens.get("reliability_nominal")) if sens else None
    variables = [x for x in (sens.get("variables") or []) if isinstance(x, Mapping)] if sens else []
    labels = {str(x.get("name")): str(x.get("label") or x.get("name")) for x in variables}
    members = [x for x in variables if _group_key(x.get("group") or _classify(x)[0]) == _group_key(group)]
    src, just = str(v.get("source") or ""), str((band or {}).get("justification") or "")
    if nominal is None or not members:
        return Check(title, None, None, "", _band_text(band, ""), NA, " > ".join(labels.get(n, n) for n in ref_rank),
                     source=src, justification=just)
    members.sort(key=lambda x: -_spread(x, nominal))
    names = [str(x.get("name")) for x in members]
    ours_rank = [n for n in names if n in ref_rank]
    ref_shown = [n for n in ref_rank if n in names]
    same = bool(ours_rank) and ours_rank == ref_shown
    top = bool(ours_rank) and bool(ref_shown) and ours_rank[0] == ref_shown[0]
    unresolved = _unresolved(sens)
    tied = [f"{labels[a]} \u2248 {labels[b]}" for a, b in zip(names, names[1:])
            if (a, b) in unresolved and a in ref_rank and b in ref_rank]
    missing = [n for n in ref_rank if n not in names]
    note = (f"ours: {' > '.join(labels[n] for n in ours_rank)} | reference: "
            f"{' > '.join(labels.get(n, n) for n in ref_rank)}"
            + ("" if same else (" (same most influential)" if top else " (differs)"))
            + (f"; not resolved within the surrogate's error: {', '.join(tied)}" if tied else "")
            + (f"; not in this study: {', '.join(missing)}" if missing else ""))
    status = (PASS if same else INFO) if band is not None else INFO
    return Check(title, None, None, "", _band_text(band, ""), status, note, source=src, justification=just)


def reference_checks(data: Mapping[str, Mapping], reference: Mapping | None = None) -> list[Check]:
    """Every number the reference reports beside the study's, in the order the reference lists them.

    ``reference`` (the ``reference`` of the settings JSON: values in report units) defaults to the one in
    ``data["config"]``; without a reference there is nothing to compare and the list is empty.
    """
    ref = reference if reference is not None else reference_of(data)
    if not ref:
        return []
    wear = data.get("wear") if isinstance(data.get("wear"), Mapping) else {}
    rel = data.get("reliability") if isinstance(data.get("reliability"), Mapping) else {}
    sens = data.get("sensitivity") if isinstance(data.get("sensitivity"), Mapping) else {}
    curve = rel.get("curve") if isinstance(rel.get("curve"), Mapping) else {}
    means = _mean_max_wear(rel, [_float(v.get("cycles")) for v in reference_values(ref, "mean_max_wear")])
    sp = _second_peak(wear) if wear else None
    checks: list[Check] = []
    for v in ref.get("values") or []:
        if not isinstance(v, Mapping):
            continue
        q = v.get("quantity")
        if q == "sensitivity_ranking":
            checks.append(_ranking_check(sens, v))
            continue
        pv = _float(v.get("value"))
        n = _float(v.get("cycles"))
        t = _float(v.get("target_reliability"))
        band = v.get("band") if isinstance(v.get("band"), Mapping) else None
        ours, note, digits = None, "", 4
        if q == "nominal_max_wear" and n is not None:
            title, unit = f"nominal max bearing wear after {n:,.0f} cycles", "mm"
            if wear:
                wc = _float(wear.get("cycles"))
                if wc == n:
                    ours = _float(wear.get("max_wear_mm"))
                else:
                    h = wear.get("history") or {}
                    if h.get("cycles") is not None and h.get("max_wear_mm") is not None:
                        ours = _interp_at(h["cycles"], h["max_wear_mm"], n)
                        note = "read from the wear history" if ours is not None else ""
                    if ours is None:
                        note = f"the wear run stopped at {_num(wc)} cycles" if wc else "no wear result"
                mode = _geometry_mode(wear)
                if mode:
                    note = (note + "; " if note else "") + f"geometry mode: {mode}"
        elif q == "nominal_max_wear_angle":
            title, unit = "angle of the max wear", "deg"
            ours = _float(wear.get("max_wear_angle_deg")) if wear else None
            if ours is not None and pv is not None:
                note = f"{_circ_diff(ours, pv):.1f} deg from the reference's"
        elif q == "second_peak_depth":
            title, unit = "second wear peak, depth", "mm"
            ours = None if sp is None else sp[1]
            note = "largest wear more than 90 deg from the main peak" if sp else ""
        elif q == "second_peak_angle":
            title, unit = "second wear peak, angle", "deg"
            ours = None if sp is None else sp[0]
            if ours is not None and pv is not None:
                note = f"{_circ_diff(ours, pv):.1f} deg from the reference's"
        elif q == "mean_max_wear" and n is not None:
            title, unit = f"mean of the max wear at {n:,.0f} cycles", "mm"
            ours = means.get(n)
        elif q == "reliability" and n is not None:
            title, unit, digits = f"reliability R(N) at {n:,.0f} cycles", "-", 3
            if curve.get("cycles") is not None and curve.get("reliability") is not None:
                ours = _interp_at(curve["cycles"], curve["reliability"], n)
            note = "" if ours is not None or not curve else "outside the computed curve"
            if ours is not None and pv is not None:
                note = f"absolute difference {ours - pv:+.3f}"
                err = curve.get("pf_error_estimate")
                e_n = _interp_at(curve["cycles"], err, n) if err is not None else None
                if e_n is not None:
                    # the surrogate's estimated error of Pf (= of R) at this N: a pass or fail closer to the
                    # band edge than this is not resolved by the study
                    note += f"; surrogate error estimate {e_n:.3f}"
        elif q == "life_cycles" and t is not None:
            title, unit = f"life at R = {t:g}", "cycles"
            ours, note = _our_life(rel, t) if rel else (None, "")
        elif q == "life_hours" and t is not None:
            rpm = _float(rel.get("crank_speed_rpm")) if rel else None
            title, unit = f"life at R = {t:g}, " + (f"hours at {rpm:g} rpm" if rpm else "in hours"), "h"
            _c, ours = _life_at_target(rel, t) if rel else (None, None)
            if ours is None and rpm:
                life, _n = _our_life(rel, t)
                ours = None if life is None else life / (rpm * 60.0)
        elif q == "model_calls":
            title, unit = "true-model calls (whole curve)", "calls"
            ours = _float(rel.get("model_calls")) if rel else None
        else:  # a quantity this report does not know (a newer config): listed, not compared
            title, unit = str(q), str(v.get("unit") or "")
        extra = str(v.get("note") or "")
        note = "; ".join(x for x in (note, extra) if x)
        checks.append(Check(title, pv, ours, unit, _band_text(band, str(v.get("unit") or "")),
                            _judge(ours, pv, band, str(v.get("unit") or "")), note, digits,
                            source=str(v.get("source") or ""),
                            justification=str((band or {}).get("justification") or "")))
    return checks


# ------------------------------------------------------------------------------------------------ sections
def _section(sid: str, title: str, body: str, *, lead: str = "") -> str:
    lead_html = f'<p class="lead">{e(lead)}</p>' if lead else ""
    return f'<section id="{e(sid)}"><h2>{e(title)}</h2>{lead_html}{body}</section>'


def _safe(builder: Callable[[], str], what: str) -> str:
    try:
        return builder()
    except Exception as exc:  # one bad key spoils one section, never the report
        tb = traceback.format_exception_only(type(exc), exc)[-1].strip()
        return _missing(f"The {what} could not be shown: {tb}")


def _flatten(obj, prefix: str = "") -> list[tuple[str, object]]:
    out: list[tuple[str, object]] = []
    if isinstance(obj, Mapping):
        for k, v in obj.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
    else:
        out.append((prefix, obj))
    return out


def _settings_section(inp: Inputs, figs: _Figures) -> str:
    cfg = inp.data.get("config")
    parts: list[str] = []
    if cfg is None:
        msg = inp.errors.get("config") or ("No config.json or settings.json in this folder: the settings of the "
                                           "study are not known to the report.")
        return _missing(msg)
    meta = [(k, v) for k, v in cfg.items() if k not in ("settings", "mechanism", "citation")
            and not isinstance(v, (Mapping, list))]
    if cfg.get("citation"):
        parts.append(f'<p class="citation"><b>Source of the preset:</b> {e(cfg["citation"])}</p>')
    parts.append('<div class="grid"><div>')
    if meta:
        parts.append(_table(["item", "value"], [(k, _num(v)) for k, v in meta], cls="kv"))
    mech = cfg.get("mechanism")
    if isinstance(mech, Mapping):
        parts.append(_table(["mechanism", "value"], [(k, _num(v)) for k, v in mech.items()], cls="kv"))
    parts.append("</div>")
    if isinstance(mech, Mapping) and all(mech.get(k) is not None for k in ("crank_mm", "rod_mm", "rocker_mm",
                                                                          "pivot_mm")):
        parts.append(figs.draw(lambda: F.mechanism_figure(
            float(mech["crank_mm"]), float(mech["rod_mm"]), float(mech["rocker_mm"]), mech["pivot_mm"],
            branch=int(mech.get("branch", 1) or 1), clearance_joint=str(mech.get("clearance_joint", "A"))),
            "The mechanism at a crank angle of 45 deg, with ghosts over one crank turn; the clearance joint is ringed.",
            png_keys=("mechanism",)))
    else:
        parts.append(figs.draw(None, "Mechanism sketch", png_keys=("mechanism",),
                               missing="Mechanism sketch: no 'mechanism' geometry in the config dump."))
    parts.append("</div>")
    settings = cfg.get("settings")
    ref = reference_of(inp.data)
    if isinstance(settings, list) and ref:
        recs = [x for x in settings if isinstance(x, Mapping)]
        label = reference_label(ref)

        def row(x: Mapping) -> tuple:
            open_ = bool(x.get("paper_open"))
            flag = '<span class="pill open">open</span>' if open_ else ""
            src = e(x.get("source") or "\u2014")
            if x.get("description") and x.get("description") != x.get("source"):
                src += f'<div class="desc">{e(x["description"])}</div>'
            return (e(x.get("name")), e(_num(x.get("value"))), e(x.get("unit") or ""), flag, src)

        open_recs = [x for x in recs if x.get("paper_open")]
        parts.append(f"<h3>Settings the reference ({e(label)}) leaves open ({len(open_recs)})</h3>")
        parts.append("<p>Each value below is this project's baseline reading of the reference (see the user guide), "
                     "not a number printed in it; the source says where it comes from.</p>")
        if open_recs:
            parts.append(_table(["setting", "value", "unit", "", "source"], [row(x) for x in open_recs],
                                cls="settings", raw_cols=(0, 1, 2, 3, 4), row_cls=["open"] * len(open_recs)))
        else:
            parts.append(_missing("No setting is marked as left open by the reference in the config dump."))
        parts.append(f"<details><summary>All {len(recs)} settings of this study</summary>")
        parts.append(_table(["setting", "value", "unit", "", "source"], [row(x) for x in recs], cls="settings",
                            raw_cols=(0, 1, 2, 3, 4), row_cls=["open" if x.get("paper_open") else "" for x in recs]))
        parts.append("</details>")
    elif isinstance(settings, list):
        # no reference: the study's own values; where a default comes from is documented in docs/config.md
        recs = [x for x in settings if isinstance(x, Mapping)]
        given = {True: "the config", False: "jointwear default", None: "\u2014"}
        rows = [(str(x.get("name")), _num(x.get("value")), str(x.get("unit") or ""),
                 given[x.get("explicit") if isinstance(x.get("explicit"), bool) else None]) for x in recs]
        n_set = sum(x.get("explicit") is True for x in recs)
        parts.append(f"<h3>Settings of this study ({len(recs)}, {n_set} given in the config)</h3>")
        parts.append("<p>Values not given in the config are jointwear's defaults; <code>jointwear check CONFIG</code> "
                     "prints them and docs/config.md says where each comes from.</p>")
        parts.append(f"<details open><summary>All {len(recs)} settings of this study</summary>")
        parts.append(_table(["setting", "value", "unit", "from"], rows, cls="settings"))
        parts.append("</details>")
    else:
        flat = [(k, v) for k, v in _flatten({k: v for k, v in cfg.items() if k not in ("citation",)})]
        parts.append(_missing("The config dump has no 'settings' list with sources; its values are listed as is."))
        parts.append(_table(["setting", "value"], [(k, _num(v)) for k, v in flat], cls="kv"))
    return "".join(parts)


def _dynamics_section(inp: Inputs, figs: _Figures) -> str:
    sim = inp.data.get("simulate")
    parts: list[str] = []
    if sim is None:
        parts.append(_missing(inp.errors.get("simulate") or "No simulate.json in this folder: the dynamics stage "
                                                            "has not been run (jointwear simulate)."))
        sim = {}
    else:
        f_mean, f_max = _float(sim.get("contact_force_mean_N")), _float(sim.get("contact_force_max_N"))
        cards = [
            ("mean contact force", "\u2014" if f_mean is None else f"{f_mean * 1e3:.4g} mN", None),
            ("peak contact force", "\u2014" if f_max is None else f"{f_max * 1e3:.4g} mN", None),
            ("contact fraction", _num(sim.get("contact_fraction"), 3), "share of the cycle in contact"),
            ("impacts per cycle", _num(sim.get("impacts_per_cycle"), 3), None),
            ("steps per cycle", _num(sim.get("steps_per_cycle")), None),
            ("wall time per cycle", "\u2014" if _float(sim.get("wall_seconds_per_cycle")) is None
             else f"{_float(sim['wall_seconds_per_cycle']) * 1e3:.3g} ms", None),
        ]
        parts.append(_cards(cards))
        extra = [(k, _num(v)) for k, v in sim.items() if not isinstance(v, (Mapping, list)) and k not in (
            "contact_force_mean_N", "contact_force_max_N", "contact_fraction", "impacts_per_cycle",
            "steps_per_cycle", "wall_seconds_per_cycle")]
        if extra:
            parts.append(_table(["other result", "value"], extra, cls="kv"))
    x, y, _ = _pair(inp, sim.get("orbit"), ("x", "journal_x", "orbit_x", "ex"), "length_mm",
                    ("y", "journal_y", "orbit_y", "ey"), "length_mm")
    npz = _npz_series(inp, sim)
    if x is None and npz.get("orbit") is not None:
        x, y = npz["orbit"]
    clearance = _float(sim.get("clearance_mm"))
    if clearance is None:
        joints = sim.get("joints") if isinstance(sim.get("joints"), list) else []
        cm = _float(joints[0].get("clearance_m")) if joints and isinstance(joints[0], Mapping) else None
        clearance = None if cm is None else cm * 1e3
    parts.append('<div class="grid">')
    parts.append(figs.draw(None if x is None else (lambda: F.orbit_figure(x, y, clearance)),
                           "Journal centre orbit relative to the bearing centre, in the bearing (rod) frame; "
                           "dashed: the clearance circle.", png_keys=("orbit",),
                           missing="Journal orbit: no orbit series (simulate.json 'orbit' or a CSV with "
                                   "x_mm, y_mm)."))
    cf = sim.get("contact_force") if isinstance(sim.get("contact_force"), Mapping) else None
    a, f, src = _pair(inp, cf, ("crank_angle",), "angle_deg", ("force", "contact_force", "normal_force"), "force_N")
    ideal = _lookup([src], ("ideal_force", "ideal"), "force_N") if src is not None else None
    if a is None and npz.get("force") is not None:
        a, f = npz["force"]
    if ideal is not None and a is not None and ideal.size != a.size:
        ideal = None
    parts.append(figs.draw(
        None if a is None else (lambda: F.contact_force_figure(a, f, mean_N=_float(sim.get("contact_force_mean_N")),
                                                               ideal_N=ideal)),
        "Normal contact force in the clearance joint against the crank angle.", png_keys=("contact_force", "force"),
        missing="Contact force: no series (simulate.json 'contact_force' or a CSV with crank_angle_deg, "
                "contact_force_N)."))
    parts.append("</div>")
    return "".join(parts)


def _wear_section(inp: Inputs, figs: _Figures) -> str:
    wear = inp.data.get("wear")
    if wear is None:
        return _missing(inp.errors.get("wear") or "No wear.json in this folder: the wear stage has not been run "
                                                  "(jointwear wear).")
    parts: list[str] = []
    if wear.get("geometry_mode", "uniform") == "uniform" and wear.get("uniform_mode_valid") is False:
        parts.append(
            '<p class="warn"><strong>Uniform mode is outside its range here.</strong> The worn pocket is wider than '
            f'the contact patch (conformity {_num(wear.get("conformity"), 3)} &gt; 1): the journal fits into its own '
            'wear, the pressure spreads and the depth grows more slowly than uniform mode assumes. Run the study with '
            '<code>wear.geometry_mode = "profile"</code> and trust that answer (docs/wear.md).</p>')
    cycles = _float(wear.get("cycles"))
    sp = _second_peak(wear)
    cards = [
        ("cycles simulated", _num(wear.get("cycles")), None),
        ("max bearing wear", f"{_num(wear.get('max_wear_mm'))} mm", None),
        ("at angle", f"{_num(wear.get('max_wear_angle_deg'), 4)} deg", "0 deg = leftmost, clockwise"),
        ("second peak", "\u2014" if sp is None else f"{sp[1]:.4g} mm", None if sp is None else f"at {sp[0]:.0f} deg"),
        ("wall time", "\u2014" if _float(wear.get("wall_seconds")) is None else f"{float(wear['wall_seconds']):.3g} s",
         None),
    ]
    journal = wear.get("journal") if isinstance(wear.get("journal"), Mapping) else {}
    if _float(journal.get("max_wear_mm")) is not None:
        cards.append(("journal max wear", f"{_float(journal['max_wear_mm']):.4g} mm", "crank pin, over its circumference"))
    if _geometry_mode(wear):
        cards.append(("geometry mode", _geometry_mode(wear), None))
    parts.append(_cards(cards))
    prof = wear.get("profile") if isinstance(wear.get("profile"), Mapping) else {}
    ang, depth, _ = _pair(inp, prof, ("angle",), "angle_deg", ("depth", "wear_depth", "bearing_depth"), "length_mm")
    radius = _float(wear.get("bearing_radius_mm"))
    if radius is None:
        cfg = inp.data.get("config") or {}
        for s in cfg.get("settings") or []:
            if isinstance(s, Mapping) and "bearing_radius" in str(s.get("name")) and str(s.get("unit")) == "mm":
                radius = _float(s.get("value"))
    parts.append('<div class="grid">')
    parts.append(figs.draw(
        None if ang is None else (lambda: F.wear_polar_figure(ang, depth, radius_mm=radius, peaks=wear.get("peaks"),
                                                              cycles=cycles)),
        "Bearing wear profile over the initial circle; the radial exaggeration factor "
        "is written on the figure.", png_keys=("polar",),
        missing="Polar wear profile: no profile (wear.json 'profile')."))
    h = wear.get("history") if isinstance(wear.get("history"), Mapping) else {}
    rel = inp.data.get("reliability") or {}
    mm = rel.get("mean_max_wear_mm") if isinstance(rel.get("mean_max_wear_mm"), Mapping) else {}
    limit = _limit_mm(inp.data.get("config") or {}, rel, wear)
    ref = reference_of(inp.data)
    label = reference_label(ref)
    ref_mean = {_float(v.get("cycles")): _float(v.get("value")) for v in reference_values(ref, "mean_max_wear")}
    nominal = next(((_float(v.get("cycles")), _float(v.get("value")))
                    for v in reference_values(ref, "nominal_max_wear")), None)
    hc, hw = h.get("cycles"), h.get("max_wear_mm")
    parts.append(figs.draw(
        None if hc is None or hw is None else (lambda: F.wear_history_figure(
            hc, hw, limit_mm=limit, mean_cycles=mm.get("cycles"), mean_max_wear_mm=mm.get("mean"),
            reference_mean=ref_mean or None, reference_nominal=nominal, reference_label=label)),
        "Max bearing wear against cycles: the nominal design, the Monte Carlo mean (if computed)"
        + (f", the values of the reference ({label})" if ref_mean or nominal else "")
        + (f" and the configured allowance ({limit:g} mm, dashed)." if limit is not None else "."),
        png_keys=("history",), missing="Wear history: no history (wear.json 'history')."))
    parts.append("</div>")
    # Fig. 17 panels: JSON profile columns first, then CSV columns on an angle grid
    series = {}
    for key, bases, kind in (("contact_force_N", ("contact_force", "force", "contact_force_mean"), "force_N"),
                             ("slip_mm", ("slip", "slip_distance", "relative_slip"), "length_mm"),
                             ("slip_density", ("sliding", "slip", "slip_distance"), "slip_density"),
                             ("contact_area_mm2", ("contact_area", "area", "contact_area_mean"), "area_mm2")):
        a2, v2, _ = _pair(inp, prof, ("angle",), "angle_deg", bases, kind)
        if a2 is not None:
            series[key] = (a2, v2)
    slip = series.get("slip_mm") or series.get("slip_density") or (None, None)
    if ang is not None:
        parts.append(figs.draw(lambda: F.wear_panels_figure(
            ang, depth, cycles=cycles,
            slip_mm=slip[1], slip_angle_deg=slip[0], slip_unit=None if "slip_mm" in series else "mm/deg per cycle",
            slip_quantity="relative slip distance" if "slip_mm" in series else "sliding distance",
            contact_force_N=series.get("contact_force_N", (None, None))[1],
            force_angle_deg=series.get("contact_force_N", (None, None))[0],
            contact_area_mm2=series.get("contact_area_mm2", (None, None))[1],
            area_angle_deg=series.get("contact_area_mm2", (None, None))[0]),
            "Relative slip distance, contact force, contact area and bearing wear depth against the angle on the "
            "bearing.", png_keys=("fig17", "panels", "vs_angle"), wide=True))
    else:
        parts.append(figs.draw(None, "Wear panels", png_keys=("fig17", "panels", "vs_angle"),
                               missing="Wear against the angle (slip, force, area, depth): no wear profile."))
    peaks = [p for p in wear.get("peaks") or [] if isinstance(p, Mapping)]
    if peaks:
        parts.append("<h3>Wear peaks</h3>")
        parts.append(_table(["angle (deg)", "depth (mm)"], [(_num(p.get("angle_deg"), 4), _num(p.get("depth_mm")))
                                                          for p in peaks], cls="kv"))
    jp = wear.get("journal_profile")
    if isinstance(jp, Mapping) and jp.get("depth_mm"):
        jd = np.asarray([np.nan if v is None else v for v in jp["depth_mm"]], dtype=float)
        parts.append(f"<p>Journal (crank pin) wear: max {np.nanmax(jd):.4g} mm, spread over its circumference.</p>")
    return "".join(parts)


def _reliability_section(inp: Inputs, figs: _Figures) -> str:
    rel = inp.data.get("reliability")
    if rel is None:
        return _missing(inp.errors.get("reliability") or "No reliability.json in this folder: the reliability study "
                                                         "has not been run (jointwear reliability).")
    parts: list[str] = []
    lt = rel.get("life_at_target")
    lt = next((x for x in lt if isinstance(x, Mapping)), {}) if isinstance(lt, list) else lt
    lt = lt if isinstance(lt, Mapping) else {}
    curve = rel.get("curve") if isinstance(rel.get("curve"), Mapping) else {}
    target = _float(lt.get("target"))
    life = _float(lt.get("cycles"))
    hours = _float(lt.get("hours"))
    covs = [v for v in (curve.get("pf_cov") or []) if _float(v) is not None]
    bound = ""
    try:
        i0 = int(np.nanargmin(np.asarray(curve.get("cycles"), dtype=float)))
        r0, n0 = _float(curve["reliability"][i0]), _float(curve["cycles"][i0])
        if life is not None and target is not None and r0 is not None and r0 < target and life <= n0:
            bound = "\u2264 "
    except (TypeError, ValueError, IndexError, KeyError):
        pass
    cards = [
        (f"life at R = {target:g}" if target is not None else "life at target",
         "\u2014" if life is None else f"{bound}{life:,.0f} cycles",
         None if hours is None else f"{bound}{hours:.3g} h"),
        ("true-model calls", _num(rel.get("model_calls")), "for the whole curve"),
        ("Monte Carlo population", _num(rel.get("n_mc")), "n_mc"),
        *([("learning converged", "yes" if rel["converged"] else "NO",
            None if rel["converged"] else "stopped by the budget of model calls")]
          if isinstance(rel.get("converged"), bool) else []),
        ("max COV of Pf", "\u2014" if not covs else f"{max(float(v) for v in covs):.3g}", "over the curve"),
        ("wall time", "\u2014" if _float(rel.get("wall_seconds")) is None else f"{float(rel['wall_seconds']):.4g} s",
         None),
    ]
    parts.append(_cards(cards))
    cyc, r = curve.get("cycles"), curve.get("reliability")
    ref = reference_of(inp.data)
    label = reference_label(ref)
    ref_r = {_float(v.get("cycles")): _float(v.get("value")) for v in reference_values(ref, "reliability")}
    ref_life = next((_float(v.get("value")) for v in reference_values(ref, "life_cycles")
                     if target is not None and _float(v.get("target_reliability")) == target), None)
    parts.append('<div class="grid">')
    parts.append(figs.draw(
        None if cyc is None or r is None else (lambda: F.reliability_curve_figure(
            cyc, r, pf_cov=curve.get("pf_cov"), target=target, life_cycles=life, reference=ref_r or None,
            reference_life=ref_life, reference_label=label)),
        "Reliability R(N) with a 95 % band from the COV of Pf, the target and the life"
        + (f"; crosses: the values of the reference ({label})." if ref_r else "."),
        png_keys=("reliability", "r_n", "rn_curve"),
        missing="R(N): no curve (reliability.json 'curve')."))
    conv = rel.get("convergence") if isinstance(rel.get("convergence"), Mapping) else {}
    cn, cp = conv.get("n_calls"), conv.get("pf")
    at = f" at {_float(conv.get('cycles')):,.0f} cycles" if _float(conv.get("cycles")) else ""
    parts.append(figs.draw(
        None if cn is None or cp is None else (lambda: F.convergence_figure(cn, cp, cov=conv.get("cov"))),
        f"Convergence of the failure probability{at} against the number of true-model calls.",
        png_keys=("convergence",),
        missing="Convergence of Pf: not recorded (reliability.json 'convergence')."))
    parts.append("</div>")
    hist = rel.get("histograms") if isinstance(rel.get("histograms"), Mapping) else {}
    limit = _limit_mm(inp.data.get("config") or {}, rel, inp.data.get("wear") or {})
    ref_mean = {_float(v.get("cycles")): _float(v.get("value")) for v in reference_values(ref, "mean_max_wear")}
    parts.append(figs.draw(
        None if not hist.get("cycles") or not hist.get("max_wear_mm") else (lambda: F.wear_histograms_figure(
            hist["cycles"], hist["max_wear_mm"], limit_mm=limit, reference_means=ref_mean or None,
            reference_label=label)),
        "Distribution of the max wear over the random inputs; solid line: mean"
        + (f", dotted: the mean the reference reports ({label})" if ref_mean else "")
        + ", dashed: the allowable wear.", png_keys=("histogram",), wide=True,
        missing="Max wear histograms: not recorded (reliability.json 'histograms')."))
    if cyc is not None and r is not None:
        rows = []
        covl = curve.get("pf_cov") or [None] * len(cyc)
        for c, rv, cv in zip(cyc, r, covl):
            rows.append((_num(_float(c)), _num(_float(rv), 4), _num(_float(1 - rv) if _float(rv) is not None else None),
                         _num(_float(cv), 3)))
        parts.append('<details><summary>R(N) as numbers</summary>')
        parts.append(_table(["cycles", "R(N)", "Pf", "COV of Pf"], rows, cls="num"))
        parts.append("</details>")
    known = {"curve", "life_at_target", "model_calls", "n_mc", "wall_seconds", "histograms", "convergence",
             "mean_max_wear_mm"}
    extra = [(k, _num(v)) for k, v in rel.items() if k not in known and not isinstance(v, (Mapping, list))]
    if extra:
        parts.append(_table(["other result", "value"], extra, cls="kv"))
    return "".join(parts)


def _sensitivity_section(inp: Inputs, figs: _Figures) -> str:
    sens = inp.data.get("sensitivity")
    if sens is None:
        return _missing(inp.errors.get("sensitivity") or "No sensitivity.json in this folder: the sensitivity study "
                                                         "has not been run (jointwear sensitivity).")
    parts: list[str] = []
    nominal = _float(sens.get("reliability_nominal"))
    cyc = _float(sens.get("cycles"))
    variables = [v for v in sens.get("variables") or [] if isinstance(v, Mapping)]
    factors = sens.get("factors") if isinstance(sens.get("factors"), list) and len(sens["factors"]) == 2 else []
    lo_f = _float(factors[0]) if factors else None
    hi_f = _float(factors[1]) if factors else None
    lo_f = 0.8 if lo_f is None else lo_f
    hi_f = 1.2 if hi_f is None else hi_f
    lead = (f"Reliability at {cyc:,.0f} cycles" if cyc else "Reliability") + (
        f" (nominal {nominal:.3f})" if nominal is not None else "") + \
        f" when the mean of each variable is moved to {lo_f * 100:g} % and to {hi_f * 100:g} % of its value, the others " \
        "fixed."
    parts.append(f"<p>{e(lead)}</p>")
    if variables and nominal is not None:
        groups: dict[str, list[Mapping]] = {}
        for v in variables:
            groups.setdefault(_classify(v)[0] or "variables", []).append(v)
        parts.append('<div class="grid">')
        for g, vs in groups.items():
            parts.append(figs.draw(lambda vs=vs, g=g: F.tornado_figure(
                [str(v.get("label") or v.get("name")) for v in vs],
                [_float(v.get("reliability_low")) if _float(v.get("reliability_low")) is not None else np.nan
                 for v in vs],
                [_float(v.get("reliability_high")) if _float(v.get("reliability_high")) is not None else np.nan
                 for v in vs], nominal, cycles=cyc, title=g[:1].upper() + g[1:],
                low_label=f"mean \u00d7 {lo_f:g}", high_label=f"mean \u00d7 {hi_f:g}"),
                f"Sensitivity of the reliability: {g}.", png_keys=("tornado",)))
        parts.append("</div>")
        rows = []
        optional = [("elasticity_mean", "elasticity of R to the mean"), ("S1", "Sobol' S1"), ("ST", "Sobol' ST")]
        extra_cols = [(k, h) for k, h in optional if any(_float(v.get(k)) is not None for v in variables)]
        has_err = any(_float(v.get("reliability_low_error")) is not None for v in variables)
        for v in variables:
            lo, hi = _float(v.get("reliability_low")), _float(v.get("reliability_high"))
            err = ((_num(_float(v.get("reliability_low_error")), 3) + " / "
                    + _num(_float(v.get("reliability_high_error")), 3),) if has_err else ())
            rows.append((str(v.get("label") or v.get("name")), str(v.get("name")), _classify(v)[0] or "",
                         _num(lo, 3), _num(hi, 3), _num(_spread(v, nominal), 3)) + err
                        + tuple(_num(_float(v.get(k)), 3) for k, _h in extra_cols))
        rows.sort(key=lambda r: (r[2], -float(r[5]) if r[5] not in ("\u2014",) else 0))
        parts.append('<details><summary>Sensitivity as numbers</summary>')
        parts.append(_table(["variable", "name", "group", f"R at mean \u00d7 {lo_f:g}", f"R at mean \u00d7 {hi_f:g}",
                             "largest change of R"] + (["surrogate error of R (low / high)"] if has_err else [])
                            + [h for _k, h in extra_cols], rows, cls="num"))
        parts.append("</details>")
        ranks = _rankings(sens)
        unresolved = _unresolved(sens)
        ref = reference_of(inp.data)
        labels = {str(v.get("name")): str(v.get("label") or v.get("name")) for v in variables}
        ref_ranks = {_group_key(v.get("group")): [labels.get(str(n), str(n)) for n in v.get("ranking") or []]
                     for v in reference_values(ref, "sensitivity_ranking")}
        rrows = []
        for g, items in ranks.items():
            row = (g, _ranking_text(items, unresolved))
            if ref:
                theirs = ref_ranks.get(_group_key(g))
                row += (" > ".join(theirs) if theirs else "\u2014",)
            rrows.append(row)
        head = ["group", "this study (largest change of R first; \u2248: the difference is within the surrogate's "
                "error estimate of the two reliabilities)"]
        if ref:
            parts.append(f"<h3>Ranking beside the reference's ({e(reference_label(ref))})</h3>")
            parts.append(_table(head + [reference_label(ref)], rrows, cls="kv"))
        else:
            parts.append("<h3>Ranking</h3>")
            parts.append(_table(head, rrows, cls="kv"))
    else:
        parts.append(figs.draw(None, "Tornado", png_keys=("tornado",),
                               missing="Tornado: no per-variable reliabilities (sensitivity.json 'variables', "
                                       "'reliability_nominal')."))
    sob = sens.get("sobol") if isinstance(sens.get("sobol"), Mapping) else {}
    if sob.get("names") and sob.get("S1") is not None and sob.get("ST") is not None:
        out = str(sob.get("output") or "max wear")
        labels = {str(v.get("name")): str(v.get("label")) for v in variables if v.get("label")}
        names = [f"{labels[str(n)]} ({n})" if str(n) in labels else str(n) for n in sob["names"]]
        parts.append(figs.draw(lambda: F.sobol_figure(names, sob["S1"], sob["ST"], S1_conf=sob.get("S1_conf"),
                                                      ST_conf=sob.get("ST_conf"), output=out),
                               f"First-order and total Sobol' indices of the {out}, on the surrogate.",
                               png_keys=("sobol",), wide=True))
    else:
        parts.append(figs.draw(None, "Sobol' indices", png_keys=("sobol",),
                               missing="Sobol' indices: not computed (sensitivity.json 'sobol')."))
    return "".join(parts)


def _validation_section(inp: Inputs, figs: _Figures) -> str:
    """The surrogate's R(N) against the true model sampled directly, and its cross-validation."""
    val = getattr(inp.results, "validation", None)
    if val is None:
        return _missing("validation.json: run `jointwear validate` to check R(N) against the true model.")
    agree = sum(bool(a) for a in val.agreement)
    cv = val.cross_validation or {}
    q2 = cv.get("q2")
    cards = _cards([
        ("true-model samples", f"{val.n_samples:,}", f"{val.model_calls:,} new model calls"),
        ("levels in agreement", f"{agree} of {len(val.agreement)}",
         "within the combined 95 % half-widths"),
        ("cross-validation Q\u00b2", "-" if q2 is None else f"{q2:.3f}",
         f"leave-one-out over {cv.get('n_points', 0)} design points"),
    ])
    rows = [[f"{c:,}", _num(r), f"[{_num(lo)}, {_num(hi)}]", _num(rs), _num(err), "yes" if a else "NO"]
            for c, r, lo, hi, rs, err, a in zip(val.cycles, val.reliability_mc, val.ci_low, val.ci_high,
                                                val.reliability_surrogate, val.surrogate_error, val.agreement)]
    table = _table(["cycles", "R, true model", "exact 95 % CI", "R, surrogate", "surrogate error", "agree"], rows)
    fig1 = figs.draw(lambda: F.validation_figure(val.cycles, val.reliability_mc, val.ci_low, val.ci_high,
                                                 val.reliability_surrogate, val.surrogate_error,
                                                 n_samples=val.n_samples),
                     "R(N): the surrogate against the true model sampled directly", png_keys=("validation",))
    fig2 = ""
    if cv.get("log_life_true"):
        fig2 = figs.draw(lambda: F.cross_validation_figure(cv["log_life_true"], cv["log_life_loo"],
                                                           cv.get("log_life_loo_sd"), q2=q2),
                         "Leave-one-out cross-validation of the life surrogate", png_keys=("cross_validation",))
    lead = ("<p>Each sample is one run of the true wear model; its reliability at a level is the share of samples "
            "whose wear life is longer, with an exact (Clopper-Pearson) 95 % interval. A level agrees when the "
            "two estimates differ by less than the sum of their 95 % half-widths (the surrogate's: its Monte "
            "Carlo interval plus its own error estimate).</p>")
    return cards + lead + table + f'<div class="grid">{fig1}{fig2}</div>'


def _comparison_section(checks: Sequence[Check], ref: Mapping) -> str:
    label = reference_label(ref)
    rows, classes = [], []
    for c in checks:
        rd = c.rel_diff
        unit = "" if c.unit in ("-", "") else f" {c.unit}"
        band = e(c.band) + (f'<div class="desc">{e(c.justification)}</div>' if c.justification else "")
        rows.append((e(c.quantity), e("\u2014" if c.reference is None else _num(c.reference, c.digits) + unit),
                     e("\u2014" if c.ours is None else _num(c.ours, c.digits) + unit),
                     e("\u2014" if rd is None else f"{rd * 100:+.1f} %"), band, _pill(c.status), e(c.note),
                     e(c.source)))
        classes.append(c.status.replace("/", ""))
    n_pass = sum(c.status == PASS for c in checks)
    n_fail = sum(c.status == FAIL for c in checks)
    n_na = sum(c.status == NA for c in checks)
    head = (f"<p><b>{n_pass}</b> within their band, <b>{n_fail}</b> outside, <b>{n_na}</b> without data. "
            f"Reference values: {e(ref.get('citation') or label)}; each row names the table, figure or section it "
            "comes from, and each band says why it is that wide (the config's <code>[reference]</code>).")
    if ref.get("note"):
        head += f" {e(ref['note'])}"
    head += "</p>"
    return head + _table(["quantity", label, "this study", "relative difference", "band", "status", "note",
                          "source"], rows, cls="compare", raw_cols=(0, 1, 2, 3, 4, 5, 6, 7), row_cls=classes)


def _summary_cards(inp: Inputs, checks: Sequence[Check], ref: Mapping | None) -> str:
    """Key numbers of the study; with a reference, how many of its numbers are within their bands."""
    wear = inp.data.get("wear") if isinstance(inp.data.get("wear"), Mapping) else {}
    rel = inp.data.get("reliability") if isinstance(inp.data.get("reliability"), Mapping) else {}
    cards: list[tuple[str, str, str | None]] = []
    if ref:
        n_pass = sum(c.status == PASS for c in checks)
        n_fail = sum(c.status == FAIL for c in checks)
        n_banded = sum(c.status in (PASS, FAIL) for c in checks)
        cards.append((f"checks against {reference_label(ref)}", f"{n_pass} / {n_banded}" if n_banded else "\u2014",
                      f"{n_fail} outside the band" if n_banded else "no results yet"))

    def ref_note(quantity: str, **match) -> str | None:
        for v in reference_values(ref, quantity):
            if all(_float(v.get(k)) == x for k, x in match.items()) and _float(v.get("value")) is not None:
                unit = "" if not v.get("unit") else f" {v['unit']}"
                return f"{reference_label(ref)}: {_num(_float(v['value']))}{unit}"
        return None

    wc = _float(wear.get("cycles")) if wear else None
    wmax = _float(wear.get("max_wear_mm")) if wear else None
    cards.append((f"nominal max wear, {wc:,.0f} cycles" if wc else "nominal max wear",
                  "\u2014" if wmax is None else f"{wmax:.4g} mm",
                  ref_note("nominal_max_wear", cycles=wc) if wc else None))
    lt = rel.get("life_at_target") if rel else None
    lt = next((x for x in lt if isinstance(x, Mapping)), None) if isinstance(lt, list) else lt
    if isinstance(lt, Mapping) and _float(lt.get("target")) is not None:
        t = _float(lt["target"])
        life, note = _our_life(rel, t)
        cards.append((f"life at R = {t:g}", "\u2014" if life is None else
                      ("\u2264 " if "at most" in note else "") + f"{life:,.0f} cycles",
                      ref_note("life_cycles", target_reliability=t)))
    else:
        cards.append(("life at the target R", "\u2014", "no reliability result"))
    cards.append(("true-model calls", _num(rel.get("model_calls")) if rel else "\u2014",
                  ref_note("model_calls") or "reliability analysis"))
    return _cards(cards).replace('class="cards"', 'class="cards summary"', 1)


def _files_section(inp: Inputs) -> str:
    rows = []
    for p in inp.files:
        try:
            st = p.stat()
        except OSError:
            continue
        mtime = _dt.datetime.fromtimestamp(st.st_mtime, _dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        rows.append((str(p.relative_to(inp.out_dir)), f"{st.st_size:,} bytes", mtime))
    out = _table(["file", "size", "modified"], rows, cls="kv") if rows else _missing("No study files were found.")
    if inp.errors:
        out += "".join(_missing(msg) for msg in inp.errors.values())
    return out


CSS = """
.warn{background:#fff4e5;border-left:4px solid #e08a00;padding:.6em .9em}
:root{--ink:#1d2733;--muted:#5b6673;--line:#dde3ea;--bg:#f6f8fa;--accent:#4477AA;--pass:#1e7b34;--fail:#b42318;
--open:#8a5a00}
*{box-sizing:border-box}
body{margin:0;font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;color:var(--ink);
background:var(--bg)}
header{background:#1f3a56;color:#fff;padding:28px 0 22px}
header .wrap{display:flex;flex-direction:column;gap:4px}
header h1{margin:0;font-size:26px;letter-spacing:.2px}
header .sub{color:#c9d6e3;font-size:14px}
.wrap{max-width:1180px;margin:0 auto;padding:0 24px}
nav{background:#fff;border-bottom:1px solid var(--line);position:sticky;top:0;z-index:2}
nav .wrap{display:flex;flex-wrap:wrap;gap:4px 18px;padding-top:10px;padding-bottom:10px}
nav a{color:var(--accent);text-decoration:none;font-weight:600;font-size:14px}
nav a:hover{text-decoration:underline}
main .wrap{padding-top:8px;padding-bottom:40px}
section{background:#fff;border:1px solid var(--line);border-radius:10px;padding:18px 22px 20px;margin:18px 0}
h2{margin:0 0 10px;font-size:20px;border-bottom:2px solid var(--accent);padding-bottom:6px}
h3{font-size:16px;margin:18px 0 8px}
.lead{color:var(--muted);margin-top:0}
.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(170px,1fr));gap:10px;margin:10px 0 14px}
.card{border:1px solid var(--line);border-radius:8px;padding:10px 12px;background:#fbfcfd}
.card-label{font-size:12px;color:var(--muted);text-transform:uppercase;letter-spacing:.4px}
.card-value{font-size:20px;font-weight:700;font-variant-numeric:tabular-nums}
.card-note{font-size:12px;color:var(--muted)}
.summary .card-value.pass{color:var(--pass)} .summary .card-value.fail{color:var(--fail)}
.grid{display:grid;grid-template-columns:repeat(auto-fit,minmax(460px,1fr));gap:14px;align-items:start}
figure{margin:10px 0;padding:8px;border:1px solid var(--line);border-radius:8px;background:#fff}
figure img{display:block;max-width:100%;height:auto;margin:0 auto}
figcaption{font-size:13px;color:var(--muted);margin-top:6px}
table{border-collapse:collapse;width:100%;margin:8px 0 12px;font-size:14px}
th,td{border-bottom:1px solid var(--line);padding:6px 8px;text-align:left;vertical-align:top}
th{background:#eef2f6;font-weight:600;font-size:13px}
tbody tr:nth-child(even){background:#fafbfc}
table.kv{width:auto;min-width:380px}
table.num td,table.compare td:nth-child(2),table.compare td:nth-child(3),table.compare td:nth-child(4){
font-variant-numeric:tabular-nums;white-space:nowrap}
table.settings tr.open{background:#fff8e6}
table.compare td:first-child{min-width:230px}
table.compare tr.fail{background:#fdf0ef}
.desc{color:var(--muted);font-size:12.5px}
.pill{display:inline-block;padding:1px 8px;border-radius:999px;font-size:12px;font-weight:700;white-space:nowrap}
.pill.pass{background:#dcf2e1;color:var(--pass)} .pill.fail{background:#fbdcd9;color:var(--fail)}
.pill.info,.pill.na{background:#e8ecf0;color:#44505c} .pill.open{background:#ffe9b3;color:var(--open)}
.missing{color:#6b5a00;background:#fff9e0;border-left:4px solid #e0b400;padding:8px 12px;border-radius:4px}
.citation{font-size:14px}
details{margin:8px 0}
summary{cursor:pointer;color:var(--accent);font-weight:600}
footer{color:var(--muted);font-size:12.5px;text-align:center;padding:10px 0 30px}
@media print{nav{display:none}section{break-inside:avoid-page;border:none}}
"""


def build_report(out_dir: Path | str, *, output: Path | str | None = None, title: str | None = None) -> Path:
    """Write a self-contained ``report.html`` summarising the study in ``out_dir``; returns its path.

    Reads whatever of ``config.json``/``settings.json``, ``simulate.json``, ``wear.json``, ``reliability.json``,
    ``sensitivity.json`` (and CSV and PNG files) are present; missing parts are stated in the page. ``output``
    overrides the page's path (default ``out_dir / "report.html"``). Raises ``FileNotFoundError`` only when
    ``out_dir`` is not a directory.
    """
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        raise FileNotFoundError(f"report: no such directory: {out_dir}")
    inp = read_inputs(out_dir)
    figs = _Figures(inp)
    cfg = inp.data.get("config") or {}
    ref = reference_of(inp.data)
    checks = reference_checks(inp.data, ref) if ref else []
    label = reference_label(ref)

    sections = [
        *([("comparison", f"Comparison with {label}", lambda: _comparison_section(checks, ref),
            f"Every number the reference reports beside this study's ({label}).")] if ref else []),
        ("study", "Study and settings", lambda: _settings_section(inp, figs),
         "The mechanism and every setting of this study" + (
             f"; settings the reference ({label}) leaves open are flagged with the source of the value chosen."
             if ref else ".")),
        ("dynamics", "Dynamics of the clearance joint", lambda: _dynamics_section(inp, figs),
         "Journal motion and contact force in the revolute clearance joint."),
        ("wear", "Wear of the joint", lambda: _wear_section(inp, figs),
         "Archard wear on the bearing; angles in the bearing frame, 0 deg at the leftmost point, clockwise."),
        ("reliability", "Wear reliability", lambda: _reliability_section(inp, figs),
         "Limit state G = \u03b4\u2080 \u2212 \u03b4max(x, N): failure when the max wear exceeds the allowable wear."),
        *([("validation", "Validation against the true model", lambda: _validation_section(inp, figs),
            "The R(N) curve checked against direct Monte Carlo of the true wear model.")]
          if getattr(inp.results, "validation", None) is not None else []),
        ("sensitivity", "Sensitivity", lambda: _sensitivity_section(inp, figs), ""),
        *([("design", "Uncertainty control: the cheapest controls", lambda: design_section(out_dir),
            "The tolerance grades, fit and material specifications that reach the target life at the target "
            "reliability at the least cost (docs/design.md).")]
          if (out_dir / "design.json").is_file() else []),
        ("files", "Files of this study", lambda: _files_section(inp), ""),
    ]
    bodies = [(sid, t, _safe(b, t.lower()), lead) for sid, t, b, lead in sections]
    leftovers = [p for stem, p in sorted(inp.pngs.items()) if stem not in inp.used_pngs]
    if leftovers:
        extra = []
        for p in leftovers:
            try:
                data = p.read_bytes()
            except OSError:
                continue
            if data.startswith(b"\x89PNG"):
                extra.append(_figure_html("data:image/png;base64," + base64.b64encode(data).decode("ascii"),
                                          f"{p.name}"))
                figs.count += 1
        if extra:
            bodies.insert(-1, ("stage-figures", "Figures written by the stages",
                               '<div class="grid">' + "".join(extra) + "</div>",
                               "PNG files found in the output folder that the sections above do not show."))

    summary = _summary_cards(inp, checks, ref)

    preset = cfg.get("preset")
    source = cfg.get("source")
    sub = " \u00b7 ".join(x for x in [
        f"preset {preset}" if preset else (f"config {source}" if source else "config unknown"),
        f"folder {out_dir.resolve().name}",
        "generated " + _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
    ] if x)
    page_title = title or "jointwear study report"
    cited = cfg.get("citation")
    summary_lead = "".join([
        f'<p class="lead">Source of the study\'s data: {e(cited)}</p>' if cited else "",
        f'<p class="lead">Compared with: {e(ref.get("citation") or label)}</p>' if ref else
        '<p class="lead">The study declares no reference results ([reference]); nothing is compared.</p>'])
    nav = "".join(f'<a href="#{e(sid)}">{e(t)}</a>' for sid, t, _b, _l in bodies)
    main = "".join(_section(sid, t, b, lead=lead) for sid, t, b, lead in bodies)
    try:
        from jointwear import __version__ as version
    except Exception:  # pragma: no cover
        version = "?"
    doc = f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="jointwear {e(version)}">
<title>{e(page_title)}</title>
<style>{CSS}</style>
</head>
<body>
<header><div class="wrap"><h1>{e(page_title)}</h1>
<div class="sub">Wear of revolute clearance joints and wear reliability of a planar mechanism \u00b7 {e(sub)}</div>
</div></header>
<nav><div class="wrap">{nav}</div></nav>
<main><div class="wrap">
<section id="summary"><h2>Summary</h2>{summary}
{summary_lead}</section>
{main}
</div></main>
<footer>jointwear {e(version)} \u00b7 {figs.count} figures embedded \u00b7 self-contained page: no scripts, no external
resources</footer>
</body>
</html>
"""
    path = Path(output) if output is not None else out_dir / "report.html"
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(doc, encoding="utf-8")
    tmp.replace(path)
    return path
