"""The self-contained HTML report of a study: ``build_report(out_dir) -> out_dir / "report.html"``.

The page needs nothing but the file: figures are PNG data URIs, the CSS is inline, there is no script and no
external resource. It reads the study through :func:`jointwear.load_results` (typed results, exact keys) and
the dynamics stage's ``simulate.npz``; it says plainly what is missing, and a result that cannot be read or shown
spoils only its own section. The comparison section, the reference's points on the figures and the acceptance
bands appear only when the study's config declares a ``[reference]``.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

from .design_section import design_section
from .glossary import glossary_section
from .markup import Figures, e, html_page, safe, section, write_page
from .read import read_outputs
from .reference_checks import reference_checks, reference_label, reference_of
from .result_sections import (
    comparison_section,
    files_section,
    reliability_section,
    sensitivity_section,
    summary_cards,
    summary_caveats,
    validation_section,
)
from .study_sections import (
    convergence_section,
    dynamics_section,
    provenance_line,
    settings_section,
    wear_section,
)

__all__ = ["build_report"]


def build_report(out_dir: Path | str, *, output: Path | str | None = None, title: str | None = None) -> Path:
    """Write a self-contained ``report.html`` of the study in ``out_dir``; returns its path.

    ``output`` overrides the page's path (default ``out_dir / "report.html"``). Raises ``FileNotFoundError``
    only when ``out_dir`` is not a directory.
    """
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        raise FileNotFoundError(f"report: no such directory: {out_dir}")
    out = read_outputs(out_dir)
    figs = Figures(out.pngs)
    cfg = out.config
    ref = reference_of(cfg)
    checks = reference_checks(out.results, ref) if ref else []
    label = reference_label(ref)

    several = any(isinstance(getattr(r, "joints", None), list) and len(r.joints) > 1
                  for r in (out.results.simulate, out.results.wear))
    sections = [
        *([("comparison", f"Comparison with {label}", lambda: comparison_section(checks, ref),
            f"Every number the reference reports beside this study's ({label}).")] if ref else []),
        ("study", "Study and settings", lambda: settings_section(out, figs),
         "The mechanism and every setting of this study" + (
             f"; settings the reference ({label}) leaves open are flagged with the source of the value chosen."
             if ref else ".")),
        ("dynamics", "Dynamics of the clearance joints" if several else "Dynamics of the clearance joint",
         lambda: dynamics_section(out, figs),
         f"Journal motion and contact force in the revolute clearance joint{'s' if several else ''}."),
        ("wear", "Wear of the joints" if several else "Wear of the joint", lambda: wear_section(out, figs),
         "Archard wear on the bearing; angles in the bearing frame, 0 deg at the leftmost point, clockwise."),
        *([("wear-convergence", "Convergence of the wear history", lambda: convergence_section(out),
            "Whether the nominal history is converged in its numerical settings on this mechanism "
            "(jointwear converge).")] if out.results.wear_convergence is not None else []),
        ("reliability", "Wear reliability", lambda: reliability_section(out, figs),
         "Limit state G = ln N_f(x) \u2212 ln N: failure when the wear life N_f, the cycles at which the max wear "
         "reaches the allowance \u03b4\u2080 (read from each model call's wear history, extrapolated linearly past "
         "its end), is below N; the same event as \u03b4max(x, N) > \u03b4\u2080. R(N) and its band between the "
         "curve's levels are read off the surrogate at 256 or more points, where the life at each target is found."),
        *([("validation", "Validation against the true model", lambda: validation_section(out, figs),
            "The R(N) curve checked against direct Monte Carlo of the true wear model.")]
          if out.results.validation is not None else []),
        ("sensitivity", "Sensitivity", lambda: sensitivity_section(out, figs), ""),
        *([("design", "Uncertainty control: the cheapest controls", lambda: design_section(out_dir, figs),
            "The tolerance grades, fit and material specifications that reach the target life at the target "
            "reliability at the least cost (docs/design.md).")]
          if (out_dir / "design.json").is_file() else []),
        ("files", "Files of this study", lambda: files_section(out), ""),
    ]
    bodies = [(sid, t, safe(b, t.lower()), lead) for sid, t, b, lead in sections]
    extra = figs.leftovers()
    if extra:
        bodies.insert(-1, ("stage-figures", "Figures written by the stages",
                           '<div class="grid">' + "".join(extra) + "</div>",
                           "PNG files found in the output folder that the sections above do not show."))
    summary = summary_cards(out, checks, ref) + summary_caveats(out)
    terms = glossary_section(summary + "".join(f"<p>{e(lead)}</p>{b}" for _sid, _t, b, lead in bodies))
    if terms:
        bodies.append(("glossary", "Glossary", terms, "The terms of the trade this page uses, in plain words."))

    preset, source, name = cfg.get("preset"), cfg.get("source"), cfg.get("name")
    sub = " \u00b7 ".join([
        *([f"study {name}"] if name and name != preset else []),
        f"preset {preset}" if preset else (f"config {source}" if source else "config unknown"),
        f"folder {out_dir.resolve().name}",
        "generated " + _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
    ])
    page_title = title or "jointwear study report"
    cited = cfg.get("citation")
    summary_lead = "".join([
        '<p class="lead">The terms of the trade this page uses (surrogate, ESC, Q\u00b2, ...) are explained in the '
        '<a href="#glossary">Glossary</a> at its foot.</p>' if terms else "",
        f'<p class="lead">Source of the study\'s data: {e(cited)}</p>' if cited else "",
        f'<p class="lead">Compared with: {e(ref.get("citation") or label)}</p>' if ref else
        '<p class="lead">The study declares no reference results ([reference]); nothing is compared.</p>'])
    nav = "".join(f'<a href="#{e(sid)}">{e(t)}</a>' for sid, t, _b, _l in bodies)
    main = "".join(section(sid, t, b, lead=lead) for sid, t, b, lead in bodies)
    body = f"""<section id="summary"><h2>Summary</h2>{summary}
{summary_lead}</section>
{main}"""
    doc = html_page(page_title, "Wear of revolute clearance joints and wear reliability of a planar mechanism "
                    f"\u00b7 {sub}", nav, body,
                    " \u00b7 ".join(x for x in (f"{figs.count} figures embedded", provenance_line(out)) if x))
    return write_page(output if output is not None else out_dir / "report.html", doc)
