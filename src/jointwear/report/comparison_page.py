"""Finished studies side by side as a self-contained page, ``comparison.html`` (``jointwear compare --out``): the
life of each study at one target with its 95 % interval and the verdict against the baseline, the R(N) curves, and
the settings that differ. The same numbers as ``comparison.md`` (:class:`jointwear.study.StudyComparison`)."""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

from .markup import e, figure_html, html_page, missing, png_data_uri, section, table, write_page

#: what the verdicts mean and what the intervals cover (docs/study.md, "How far to trust the life")
READING = ("Two lives differ beyond their errors when their 95 % intervals do not overlap ('longer' or 'shorter' "
           "than the baseline's); otherwise they are 'within the errors'. The intervals cover each study's error in "
           "estimating R(N) (the Monte Carlo population and the surrogate), not the wear model's assumptions: two "
           "studies that differ in those (for example the wear mode) are compared as they stand.")


def lives_table(comparison) -> str:
    """The table of the studies' lives (the rows of ``comparison.md``) as HTML."""
    return table(list(comparison.COLUMNS), comparison.rows(), cls="kv")


def settings_table(comparison) -> str:
    """The settings that differ between the studies as an HTML table (or a sentence saying none does)."""
    unrecorded = comparison.unrecorded_note()
    note = f"<p>{e(unrecorded)}</p>" if unrecorded else ""
    if not comparison.differences:
        return "<p>No setting differs between the studies.</p>" + note
    return table(["setting", *comparison.labels], comparison.setting_rows(), cls="settings") + note


def write_comparison_page(comparison, path: Path | str, *, figure: Path | None = None) -> Path:
    """Write ``comparison`` (a :class:`jointwear.study.StudyComparison`) as an HTML page at ``path``, with the PNG
    ``figure`` of its curves embedded when given; returns the path."""
    uri = png_data_uri(figure) if figure is not None else None
    curves = (figure_html(uri, f"R(N) of each study with its 95 % band; the target R = {comparison.target:g} "
                               "and each life with its interval") if uri
              else missing("No figure of the curves (written without figures)."))
    settings = settings_table(comparison)
    sections = [
        ("lives", f"Life at R = {comparison.target:g}",
         lives_table(comparison)
         + "".join(f'<p class="warn">{e(note)}</p>' for note in (comparison.wear_mode_note(), comparison.seed_note())
                   if note)
         + f'<p class="lead">{e(READING)}</p>',
         f"The first study, {comparison.labels[0]}, is the baseline."),
        ("curves", "Reliability R(N)", curves, ""),
        ("settings", "Settings that differ", settings, "In the units of the config files."),
        ("folders", "Studies compared",
         table(["study", "folder"], [(s["label"], str(s["folder"])) for s in comparison.studies], cls="kv"), ""),
    ]
    nav = "".join(f'<a href="#{sid}">{e(title)}</a>' for sid, title, _b, _l in sections)
    body = "".join(section(sid, title, html, lead=lead) for sid, title, html, lead in sections)
    sub = (f"{len(comparison.studies)} studies at R = {comparison.target:g} \u00b7 generated "
           + _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"))
    return write_page(path, html_page("jointwear comparison of studies", sub, nav, body,
                                      "1 figure embedded" if uri else "no figure"))
