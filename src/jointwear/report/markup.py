"""HTML building blocks of the report: escaped text, numbers as the report prints them, cards, tables, sections and
figures embedded as PNG data URIs (falling back to a stage's own PNG file when a figure cannot be drawn)."""

from __future__ import annotations

import base64
import html
import math
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from .style import DPI, to_data_uri

__all__ = ["e", "format_number", "figure_html", "missing", "cards", "table", "section", "safe", "Figures", "CSS",
           "html_page", "write_page"]


def e(x) -> str:
    """HTML-escaped text of anything (empty for None)."""
    return html.escape("" if x is None else str(x), quote=True)


def format_number(v, digits: int = 4) -> str:
    """A number as the report shows it: thousands separators for large values, ``digits`` significant digits,
    scientific notation for very small or very large ones, an em dash for None."""
    if v is None:
        return "\u2014"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return f"{int(v):,}"
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            return "\u2014" if math.isnan(v) else str(v)
        if 1000 <= abs(v) < 1e9:
            return f"{v:,.0f}"
        if v != 0 and (abs(v) < 1e-3 or abs(v) >= 1e9):
            return f"{v:.{digits - 1}e}"
        return f"{v:.{digits}g}"
    if isinstance(v, (list, tuple)):
        if len(v) > 8:
            return f"[{', '.join(format_number(x, digits) for x in v[:6])}, \u2026 ({len(v)} values)]"
        return "[" + ", ".join(format_number(x, digits) for x in v) + "]"
    if isinstance(v, dict):  # a table of named values, e.g. the points of a body
        return "{" + ", ".join(f"{k}: {format_number(x, digits)}" for k, x in v.items()) + "}"
    return str(v)


def png_width(uri: str) -> int | None:
    """Width in pixels of a PNG data URI (from its IHDR chunk)."""
    try:
        head = base64.b64decode(uri.split(",", 1)[1][:48])
        return int.from_bytes(head[16:20], "big") if head[:8] == b"\x89PNG\r\n\x1a\n" else None
    except Exception:
        return None


def figure_html(uri: str, caption: str, *, wide: bool = False, alt: str | None = None) -> str:
    """A figure shown at its physical size (DPI pixels per inch), never wider than the page. ``alt``: what the figure
    shows, for a reader who cannot see it (its numbers, not its caption again); the caption where none is given."""
    cls = "fig wide" if wide else "fig"
    px = png_width(uri)
    width = f' width="{round(px * 96 / DPI)}"' if px else ""
    return (f'<figure class="{cls}"><img src="{uri}"{width} alt="{e(alt or caption)}">'
            f"<figcaption>{e(caption)}</figcaption></figure>")


def html_page(title: str, sub: str, nav: str, body: str, footer: str) -> str:
    """A self-contained page in the report's style: header (``title``, the line ``sub``), the navigation links
    ``nav``, the sections ``body`` (HTML) and a footer that starts with ``footer``."""
    from jointwear import __version__ as version

    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="jointwear {e(version)}">
<title>{e(title)}</title>
<style>{CSS}</style>
</head>
<body>
<header><div class="wrap"><h1>{e(title)}</h1>
<div class="sub">{e(sub)}</div>
</div></header>
<nav><div class="wrap">{nav}</div></nav>
<main><div class="wrap">
{body}
</div></main>
<footer>jointwear {e(version)} \u00b7 {e(footer)} \u00b7 self-contained page: no scripts, no external
resources</footer>
</body>
</html>
"""


def write_page(path: Path | str, doc: str) -> Path:
    """Write the page ``doc`` at ``path`` through a temporary file, so a reader never sees half a page (and a
    symlink planted in the folder is never written through)."""
    from jointwear.study.io import write_text_atomic

    return write_text_atomic(Path(path), doc)


def png_data_uri(path: Path) -> str | None:
    """The file as a PNG data URI, or None when it is not a readable PNG."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if not data.startswith(b"\x89PNG"):
        return None
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def missing(text: str) -> str:
    """A notice that something is not in the folder (or could not be shown)."""
    return f'<p class="missing">{e(text)}</p>'


def cards(items: Sequence[tuple[str, str, str | None]], *, cls: str = "cards") -> str:
    """Key numbers as cards: (label, value, note)."""
    out = [f'<div class="{cls}">']
    for label, value, note in items:
        out.append(f'<div class="card"><div class="card-label">{e(label)}</div>'
                   f'<div class="card-value">{e(value)}</div>'
                   + (f'<div class="card-note">{e(note)}</div>' if note else "") + "</div>")
    out.append("</div>")
    return "".join(out)


#: a cell longer than this is prose (a reason, a verdict): it wraps even in a table of numbers
PROSE_CELL = 48


def _prose(cell: object) -> str:
    """' class="prose"' for a long text cell, which must wrap (a table of numbers keeps its cells on one line, and a
    reason 900 characters long made the page 4,000 px wide and cut it in print)."""
    return ' class="prose"' if len(str(cell)) > PROSE_CELL else ""


def table(header: Sequence[str], rows: Sequence[Sequence[str]], *, cls: str = "",
          raw_cols: Sequence[int] = (), row_cls: Sequence[str] | None = None) -> str:
    """A table; cells are escaped except the columns in ``raw_cols`` (already HTML)."""
    out = [f'<table class="{cls}"><thead><tr>' + "".join(f"<th>{e(h)}</th>" for h in header) + "</tr></thead><tbody>"]
    for i, r in enumerate(rows):
        rc = f' class="{row_cls[i]}"' if row_cls and row_cls[i] else ""
        out.append(f"<tr{rc}>" + "".join(f"<td{_prose(c)}>{c if j in raw_cols else e(c)}</td>"
                                          for j, c in enumerate(r)) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def section(sid: str, title: str, body: str, *, lead: str = "") -> str:
    lead_html = f'<p class="lead">{e(lead)}</p>' if lead else ""
    return f'<section id="{e(sid)}"><h2>{e(title)}</h2>{lead_html}{body}</section>'


def safe(builder: Callable[[], str], what: str) -> str:
    """The section's HTML, or a notice when building it fails: one bad result spoils one section."""
    try:
        return builder()
    except Exception as exc:
        tb = traceback.format_exception_only(type(exc), exc)[-1].strip()
        return missing(f"The {what} could not be shown: {tb}")


class Figures:
    """Draws the report's figures from the study's data, falling back to the stage's own PNG file (``pngs``: stem
    -> path) when a figure cannot be drawn; records which files were shown."""

    def __init__(self, pngs: dict[str, Path]):
        self.pngs = pngs
        self.used: set[str] = set()
        self.count = 0

    def draw(self, make: Callable[[], object] | None, caption: str, *, png_keys: Sequence[str] = (),
             wide: bool = False, missing_text: str | None = None, alt: str | None = None) -> str:
        """The figure ``make`` draws (or the stage's PNG file of it) with its caption and text alternative ``alt``
        (:func:`figure_html`)."""
        if make is not None:
            try:
                uri = to_data_uri(make())
            except Exception as exc:  # a figure that cannot be drawn must not end the report
                png = self._png(png_keys)
                return png or missing(f"{caption}: the figure could not be drawn ({type(exc).__name__}: {exc}).")
            self.count += 1
            self._supersede(png_keys)
            return figure_html(uri, caption, wide=wide, alt=alt)
        return self._png(png_keys, caption, alt) or missing(missing_text or f"{caption}: no data in this folder.")

    def leftovers(self) -> list[str]:
        """The stage PNG files no section showed, as figures."""
        out = []
        for stem, path in sorted(self.pngs.items()):
            uri = None if stem in self.used else png_data_uri(path)
            if uri:
                out.append(figure_html(uri, path.name))
                self.count += 1
        return out

    def _candidates(self, key: str) -> list[str]:
        """The unused stems ``key`` names: the one it spells exactly first (``validation`` is not
        ``cross_validation``, which sorts before it), then those that contain it."""
        stems = [s for s in sorted(self.pngs) if s not in self.used and key in s.lower()]
        return sorted(stems, key=lambda s: s.lower() != key)

    def _supersede(self, keys: Sequence[str]) -> None:
        """The stage's own file of a figure drawn here from data is not shown again in the appendix."""
        for key in keys:
            for stem in self._candidates(key):
                self.used.add(stem)
                return

    def _png(self, keys: Sequence[str], caption: str = "", alt: str | None = None) -> str | None:
        for key in keys:
            for stem in self._candidates(key):
                path = self.pngs[stem]
                uri = png_data_uri(path)
                if uri is None:
                    continue
                self.used.add(stem)
                self.count += 1
                return figure_html(uri, f"{caption} (figure file {path.name})" if caption else path.name, alt=alt)
        return None


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
table td.prose{white-space:normal;min-width:16em}
h2,h3{scroll-margin-top:80px}
table.settings tr.open{background:#fff8e6}
table.compare td:first-child{min-width:230px}
table.compare tr.fail,table.num tr.bad{background:#fdf0ef}
.desc{color:var(--muted);font-size:12.5px}
.pill{display:inline-block;padding:1px 8px;border-radius:999px;font-size:12px;font-weight:700;white-space:nowrap}
.pill.pass{background:#dcf2e1;color:var(--pass)} .pill.fail{background:#fbdcd9;color:var(--fail)}
.pill.info,.pill.na{background:#e8ecf0;color:#44505c} .pill.open{background:#ffe9b3;color:var(--open)}
.missing{color:#6b5a00;background:#fff9e0;border-left:4px solid #e0b400;padding:8px 12px;border-radius:4px}
.citation{font-size:14px}
dl.glossary{display:grid;grid-template-columns:minmax(10em,16em) 1fr;gap:6px 16px;margin:0}
dl.glossary dt{font-weight:600} dl.glossary dd{margin:0}
details{margin:8px 0}
summary{cursor:pointer;color:var(--accent);font-weight:600}
footer{color:var(--muted);font-size:12.5px;text-align:center;padding:10px 0 30px}
@media print{nav{display:none}section{break-inside:avoid-page;border:none}
details.numbers::details-content{content-visibility:visible;display:block}}
"""
