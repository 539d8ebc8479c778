"""The report's design section: the Pareto front of cost against the life at R*, the chosen controls, their cost
and the verified R(N*) (read from ``design.json``)."""

from __future__ import annotations

import html
from collections.abc import Mapping
from pathlib import Path

from jointwear.design.results import EXTRAPOLATED_SHARE, life_interval_text
from jointwear.report.markup import figure_html
from jointwear.report.study_sections import warning
from jointwear.report.style import TARGET_COLOR, figure, label_axes, styled, to_data_uri


def _get(result, key: str, default=None):
    return result.get(key, default) if isinstance(result, Mapping) else getattr(result, key, default)


@styled
def design_pareto_figure(result):
    """Cost against the life at R* of every candidate (grey), the Pareto front (line), the target life and the
    chosen design. ``result``: a :class:`jointwear.design.DesignResult` or the dict of ``design.json``."""
    fig, ax = figure()
    candidates = _get(result, "candidates") or []
    pts = [(r["cost"], r["life_at_target_cycles"]) for r in candidates if r.get("life_at_target_cycles")]
    if pts:
        ax.scatter([p[0] for p in pts], [p[1] / 1e3 for p in pts], s=8, color="#BBBBBB", label="candidates")
    far = [r for r in candidates + (_get(result, "pareto") or [])
           if r.get("life_at_target_cycles") and (r.get("outside_design_fraction") or 0.0) > EXTRAPOLATED_SHARE]
    if far:  # their life is the surrogate's extrapolation: drawn open, not as points of the same standing
        ax.scatter([r["cost"] for r in far], [r["life_at_target_cycles"] / 1e3 for r in far], s=40,
                   facecolors="none", edgecolors="#AA3377", zorder=3,
                   label=f"extrapolated (> {EXTRAPOLATED_SHARE:.0%} outside the study's inputs)")
    front = [r for r in _get(result, "pareto") or [] if r.get("life_at_target_cycles")]
    if front:
        ax.plot([r["cost"] for r in front], [r["life_at_target_cycles"] / 1e3 for r in front], "o-", ms=4,
                label="Pareto front")
        # each point's 95 % interval of its life at R* (an end outside the population drawn to the point)
        lives = [r["life_at_target_cycles"] for r in front]
        low = [life - (r.get("life_at_target_low_cycles") or life) for r, life in zip(front, lives)]
        high = [(r.get("life_at_target_high_cycles") or life) - life for r, life in zip(front, lives)]
        if any(low) or any(high):
            ax.errorbar([r["cost"] for r in front], [v / 1e3 for v in lives],
                        yerr=[[v / 1e3 for v in low], [v / 1e3 for v in high]], fmt="none", capsize=3, lw=1)
    target = _get(result, "target_life_cycles")
    if target:
        ax.axhline(target / 1e3, color=TARGET_COLOR, ls="--", lw=1, label="target life")
    chosen = _get(result, "chosen")
    if chosen and chosen.get("life_at_target_cycles"):
        ax.plot([chosen["cost"]], [chosen["life_at_target_cycles"] / 1e3], "*", ms=14, color=TARGET_COLOR,
                label="chosen")
    r_star = _get(result, "target_reliability")
    label_axes(ax, "relative cost", None, f"life at R = {r_star:g}" if r_star else "life", "10^3 cycles")
    ax.legend(loc="lower right")
    return fig


def _fmt(v, spec: str = ".4g") -> str:
    return "-" if v is None else format(v, spec)


def design_section(out_dir: Path | str, figs=None) -> str | None:
    """HTML of the design section from ``out_dir/design.json``; None when there is no design result. ``figs`` (the
    report's :class:`jointwear.report.markup.Figures`) draws the front, so that the stage's own file of it is not
    shown again among the figures no section shows."""
    from jointwear.design.results import DesignResult

    if not (Path(out_dir) / DesignResult.FILE).is_file():
        return None
    d = DesignResult.load(out_dir)
    e = html.escape
    parts = []
    r_star, n_star = _get(d, "target_reliability"), _get(d, "target_life_cycles")
    head = f"Target: {_fmt(n_star, ',.0f')} cycles at R = {_fmt(r_star, 'g')}"
    if relative := d.relative_target_sentence():
        head += f" ({relative})"
    if _get(d, "baseline_reliability_at_target_life") is not None:
        head += (f"; today's design (the study's own inputs) reads R(N*) = {d.baseline_reliability_text()} on the "
                 "surrogate the candidates are read on (the design stage's own Kriging of the true-model points; the "
                 "study's R(N) curve, from the reliability stage's, may differ within their errors)")
    parts.append(f"<p>{e(head)}; {_get(d, 'n_candidates', 0)} candidate designs, "
                 f"{_get(d, 'model_calls', 0)} true-model calls in all.</p>")
    chosen = _get(d, "chosen")
    if chosen is None:
        sentence = d.no_choice_sentence()
        parts.append(f'<p class="missing">{e(sentence[:1].upper() + sentence[1:])}.</p>')
    else:
        costs = {c["name"]: {o["name"]: o.get("cost") for o in c.get("options", [])}
                 for c in _get(d, "controls") or []}
        base = _get(d, "baseline_choices")
        rows = "".join(f"<tr><td>{e(str(k))}</td>"
                       + (f"<td>{e(str(base.get(k, '-')))}</td>" if base else "")
                       + f"<td>{e(str(v))}</td><td>{_fmt(costs.get(k, {}).get(v), '.4g')}</td></tr>"
                       for k, v in chosen["choices"].items())
        today_head = "<th>today</th>" if base else ""
        parts.append(f"<table><thead><tr><th>control</th>{today_head}<th>chosen option</th><th>its cost</th></tr>"
                     f"</thead><tbody>{rows}</tbody></table>")
        life, rpm = chosen.get("life_at_target_cycles"), _crank_rpm(out_dir)
        hours = f" ({life / rpm / 60:,.2f} h)" if life and rpm else ""
        text = (f"Cost {chosen['cost']:.4g} (relative units: the sum of the options' costs); on the study's "
                f"surrogate R(N*) = {chosen['reliability_at_target_life']:.4f} +/- "
                f"{chosen.get('reliability_error', 0):.4f} and a life of {life_interval_text(chosen)} cycles{hours} "
                "at R* (95 % interval in brackets). ")
        change = d.change_sentence()
        text += change[:1].upper() + change[1:] + ". "
        sentence = d.verification_sentence()
        text += sentence[:1].upper() + sentence[1:] + "."
        cls = "" if d.verdict() in ("meets", "within_error") else ' class="warn"'  # misses, or not verified
        parts.append(f"<p{cls}>{e(text)}</p>")
        if unproven := d.unproven_sentence():
            parts.append(warning("The choice is not proven to meet the target.", unproven))
    if every := d.every_target_sentence():
        parts.append('<p class="warn"><strong>The headline choice does not meet every target.</strong> '
                     f"{e(every[:1].upper() + every[1:])}.</p>")
    if check := d.every_target_check_sentence():
        cls = "" if d.chosen_every_target["verification"]["verdict"] == "meets" else ' class="warn"'
        parts.append(f"<p{cls}>{e(check[:1].upper() + check[1:])}.</p>")
    if undecided := d.undecided_sentence():
        parts.append(warning("Candidates left undecided.", undecided))
    if outside := d.target_outside_curve_sentence():
        parts.append(warning("The target lies outside the study's curve.", outside))
    if _get(d, "pareto"):
        caption = "Cost of every candidate design against its life at the target reliability; the front and the choice."
        if figs is not None:
            parts.append(figs.draw(lambda: design_pareto_figure(d), caption, png_keys=("design_pareto",)))
        else:
            parts.append(figure_html(to_data_uri(design_pareto_figure(d)), caption))
        front = _get(d, "pareto")
        names = list(front[0]["choices"])
        header = "".join(f"<th>{e(n)}</th>" for n in names) + (
            "<th>cost</th><th>life at R* (95 % interval), cycles</th><th>step resolved</th><th>R(N*)</th>"
            "<th>+/- error</th><th>outside the study's inputs</th>")
        steps = {True: "yes", False: "no", None: "-"}
        body = "".join("<tr>" + "".join(f"<td>{e(str(r['choices'][n]))}</td>" for n in names)
                       + f"<td>{r['cost']:.4g}</td><td>{e(life_interval_text(r))}</td>"
                       f"<td>{steps[r.get('step_resolved')]}</td>"
                       f"<td>{r['reliability_at_target_life']:.4f}</td><td>{_fmt(r.get('reliability_error'), '.4f')}"
                       f"</td><td>{_fmt(r.get('outside_design_fraction'), '.1%')}</td></tr>"
                       for r in front)
        parts.append(f"<table><thead><tr>{header}</tr></thead><tbody>{body}</tbody></table>")
        if resolution := _get(d, "life_resolution"):
            parts.append(f"<p>The front: each well-estimated design costs more than the well-estimated one above it "
                         f"and lives longer at R* by more than {resolution:.1%}, the half-width of the study's own "
                         "life interval (a longer life within it is not resolved). Extrapolated designs (the last "
                         f"column above {EXTRAPOLATED_SHARE:.0%}) stand beside them and push none of them off, so the "
                         "front may step back in life where one of them stands.</p>")
        parts.append("<p>A life's interval is the surrogate's own error of that life (where R(N) -/+ its error bound "
                     "crosses R*). It assumes, as the error of R(N*) does, that the Kriging's variance is calibrated: "
                     "where a validation finds the study's life outside the study's own interval, read these as too "
                     "narrow as well.</p>")
        unresolved = sum(1 for r in front if r.get("step_resolved") is False)
        if unresolved:
            parts.append(f"<p>{unresolved} of the {len(front) - 1} steps up the front are not resolved by the "
                         "surrogate's own error of the lives ('step resolved' no: the point's life interval overlaps "
                         "the previous point's): the two designs may live equally long at R*, so that step buys an "
                         "improvement the surrogate cannot show; verify the dearer design before paying for it.</p>")
        far = [r for r in _get(d, "pareto") + ([chosen] if chosen else [])
               if (r.get("outside_design_fraction") or 0.0) > EXTRAPOLATED_SHARE]
        if far:
            parts.insert(0, '<p class="warn"><strong>Extrapolated candidates.</strong> '
                         f"{len({str(r['choices']) for r in far})} of these designs draw more than "
                         f"{EXTRAPOLATED_SHARE:.0%} of their population outside the inputs the study's surrogate "
                         "learned from (the last column): their R(N*) and life are extrapolations, however certain "
                         "they look. Widen the study's inputs to cover them, or verify one with its own study, before "
                         "choosing it.</p>")
    from jointwear.study.results import WearSummary

    wear = WearSummary.load_if_present(out_dir)
    if wear is not None and wear.uniform_out_of_range:
        parts.insert(0, '<p class="warn"><strong>The wear model is outside its range.</strong> This choice rests on '
                     f"uniform-mode wear, and the wear stage found the worn pocket wider than the contact "
                     f"(conformity {wear.conformity:.3g} &gt; 1): rerun the study and the design with "
                     '<code>wear.geometry_mode = "profile"</code> before deciding (docs/wear.md).</p>')
    return "".join(parts)


def _crank_rpm(out_dir: Path | str) -> float | None:
    """The crank speed the study recorded in reliability.json (to give lives in hours), None without it."""
    from jointwear.study.results import ReliabilityCurve

    rel = ReliabilityCurve.load_if_present(out_dir)
    return None if rel is None else rel.crank_speed_rpm
