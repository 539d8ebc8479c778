"""The report's sections about the study's answers: the wear reliability, its validation against the true model,
the sensitivity, the comparison with a cited reference, the summary cards and the list of files."""

from __future__ import annotations

import datetime as _dt
import math
from collections.abc import Callable, Mapping, Sequence
from types import SimpleNamespace

import numpy as np

from jointwear.reliability.results import Z95
from jointwear.study.limit_state import life_status, nominal_lives
from jointwear.study.reliability_results import (
    SurrogateFit,
    interval_cells,
    interval_text,
    scatter_sentence,
    signed_percent,
)
from jointwear.study.sensitivity import coordinate_shift_sentence
from jointwear.study.stage_lines import error_tolerances, linear_trend_hint, posterior_error_line

from . import figures as F
from .alt_text import reliability_curve_alt, tornado_alt, validation_alt
from .markup import Figures, cards, e, format_number, missing, table
from .read import StudyOutputs
from .reference_checks import (
    FAIL,
    INFO,
    NA,
    PASS,
    Check,
    checks_summary,
    curve_misses_life,
    group_key,
    life_with_note,
    ranking_rows,
    ranking_text,
    reference_label,
    reference_of,
    reference_values,
    tally,
    unresolved_pairs,
)
from .study_sections import allowance_mm, not_run, warning

__all__ = ["reliability_section", "sensitivity_section", "validation_section", "comparison_section",
           "summary_cards", "summary_caveats", "files_section"]


def _pill(status: str) -> str:
    text = {PASS: "PASS", FAIL: "FAIL", INFO: "info", NA: "no data"}.get(status, status)
    return f'<span class="pill {e(status.replace("/", ""))}">{e(text)}</span>'


def running_time(hours: float) -> str:
    """A life's running time at the study's crank speed, in a unit that shows its digits: '12.3 h', '6.6 min',
    '42 s' (two decimals of an hour hid a 5.5-minute life as '0.09 h')."""
    if hours >= 10:
        return f"{hours:,.0f} h"
    if hours >= 1:
        return f"{hours:.3g} h"
    if hours * 60 >= 1:
        return f"{60 * hours:.3g} min"
    return f"{3600 * hours:.3g} s"


def probability_pair(r: float, pf: float) -> tuple[str, str]:
    """R and Pf to four significant digits each, the one that would round to 1 written as 1 less its complement
    ('1 \u2212 3.9e-06' beside Pf 3.943e-06), so neither reads as certain beside a small other."""
    def one(x: float, other: float) -> str:
        text = format_number(x, 4)
        return f"1 \u2212 {other:.2g}" if text == "1" and 0 < other else text
    return one(r, pf), one(pf, r)


def _life_text(life: float | None, note: str) -> str:
    return "\u2014" if life is None else ("\u2264 " if "at most" in note else "") + f"{life:,.0f} cycles"


def _q2_text(fit) -> str:
    return "\u2014" if fit.q2 is None else f"{fit.q2:.2f}"


def _scatter_text(fit) -> str:
    return f"\u00b1{100 * fit.life_scatter:.2g} %"


def _surrogate_fit_cards(fit, record_cycles=None) -> list[tuple]:
    """The life surrogate's leave-one-out Q^2 and the call-to-call scatter it estimated (none for an older
    result); ``record_cycles``: the cycles each wear block records (wear.record_cycles), which set part of that
    scatter."""
    if fit is None:
        return []
    recorded = f" (this study records {record_cycles:g})" if record_cycles else ""
    return [("surrogate fit, Q\u00b2", _q2_text(fit),
             f"leave-one-out predictive R\u00b2 over the {fit.n_points} design points: the share of the variance of "
             "their ln N_f that the surrogate predicts at each point when refitted without it (1: all of it)"),
            ("scatter of a call's life", _scatter_text(fit),
             "one standard deviation about the smooth surrogate, estimated by the fit (its nugget: the Kriging's "
             "noise term); R(N) counts it as part of each mechanism's life"
             + ("; at the top of its range" if fit.nugget_at_bound else "")
             # docs/wear.md "Sampling scatter": a chaotic contact's wear map differs from cycle to cycle
             + ". Part of it can be the sampling noise of recording few cycles of chaotic contact dynamics per wear "
             f"block{recorded}, not a difference between mechanisms: more cycles (wear.record_cycles) lower that "
             "part (docs/wear.md)")]


def _joint_fit_table(rel) -> str:
    """Per judged joint of a per-joint study: its share of the failures at the life and how well its own Kriging
    explains its life (Q^2, the call-to-call scatter it estimated); empty for a result without them."""
    if not any(joint.get("surrogate_fit") for joint in rel.joints):
        return ""
    shares = rel.governing_shares()
    lives, curves = rel.joint_lives(), rel.joint_curves()
    rows = []
    for joint in rel.joints:  # a joint without a fit had fewer than two finite lives (one that does not wear)
        fit = SurrogateFit.from_json(joint.get("surrogate_fit"))
        life, low, high = lives.get(joint["name"], (None, None, None))
        status = life_status(curves[joint["name"]][0], rel.target) if joint["name"] in curves else "beyond_curve"
        outside = status.replace("_", " the ")  # before the curve, beyond the curve
        rows.append((joint["name"], f"{100 * shares.get(joint['name'], 0.0):.0f} %",
                     outside if life is None else f"{life:,.0f}"
                     + ("" if low is None and high is None else f" ({interval_cells(low, high)})"),
                     "not fitted" if fit is None else _q2_text(fit), "\u2014" if fit is None else _scatter_text(fit)))
    return table(["joint", "share of the failures at the life", f"its own life at R = {rel.target:g} (95 %)",
                  "Q\u00b2 of its life", "scatter of a call's life"], rows, cls="kv")


def _esc_part(rel, cycles: float) -> str:
    """ESC's part of the error estimate at ``cycles`` (the learning's own measure), when the result has it."""
    if rel.pf_error_esc is None:
        return ""
    k = min(range(len(rel.cycles)), key=lambda i: abs(float(rel.cycles[i]) - cycles))
    esc, total = float(rel.pf_error_esc[k]), float(rel.pf_error[k])
    if esc < total:
        return f"; set by the Kriging's posterior spread (ESC's count alone: {esc:.3f})"
    return "; set by ESC's count of misclassified samples"


#: How far the presets' learnt lives read from their true models' on the same samples (tests/test_docs_study_record.py
#: ties it to benchmarks/results/surrogate_bias.json and the validation records)
LIFE_TRUST = ("How far to trust the life: not measured for this study yet. <code>jointwear validate</code> runs its "
              "true model on fresh samples and reads the learnt life on the same ones (a few hundred samples tell its "
              "error). On the flapping-wing presets the learnt lives are 1.8 % (uniform mode) and 1.4 % "
              "(profile mode) short, as much as or more than their 95 % intervals' half-widths (1.4 % and 0.8 %), "
              "because the Kriging's life spreads a little wider than the true model's (the early failures come "
              "early; docs/reliability.md, \"The learnt life's spread\").")


def numerics_unchecked(out: StudyOutputs) -> str:
    """That the wear history's numerical settings are outside the life's interval and not checked on this study
    (docs/study.md, "How far to trust the life"), with the cycles each block records; '' once ``jointwear
    converge`` has run on the folder (its own verdicts are reported then)."""
    if out.results.wear_convergence is not None:
        return ""
    record, settle = (out.results.setting(f"wear.{k}") for k in ("record_cycles", "settle_cycles"))
    here = (f"; this study records {record:g} cycle{'s' if record != 1 else ''}"
            + (f" and settles {settle:g}" if settle is not None else "") + " per wear block" if record else "")
    return ("the wear history's numerical settings (the cycles each wear block records and settles, the block, the "
            "grid, the tolerances) are outside the life's interval and have not been checked on this study"
            f"{here}; jointwear converge refines each and tells whether the nominal life moves (docs/wear.md, "
            "\"Is my history converged?\")")


def _fit_title(rel) -> str:
    """The title of the life surrogate's warning: 'The surrogate explains little' below the Q^2 floor."""
    fit = rel.surrogate_fit
    return "The surrogate explains little" if fit is None or fit.poor else "The surrogate's fit"


def _short_long(low: float, high: float) -> str:
    """A paired ratio's 95 % bounds as a side: '0.6-3.6 % short', '0.2-1.0 % long', '3.6 % short to 1.1 % long'."""
    if high <= 0:
        return f"{-100 * high:.1f}-{-100 * low:.1f} % short"
    if low >= 0:
        return f"{100 * low:.1f}-{100 * high:.1f} % long"
    return f"{-100 * low:.1f} % short to {100 * high:.1f} % long"


def paired_life_verdict(val, target: float, strong: Callable[[str], str] = lambda text: f"<b>{text}</b>"
                        ) -> tuple[str, str] | None:
    """The validation's paired check of the life at ``target``: its verdict ('within', 'unresolved', 'beyond':
    :meth:`ValidationResult.paired_life_allowed`) and the sentence the summary and the reliability section both
    give ('on the same samples the surrogate's life at R = 0.9 is 33,869 cycles, 1.9 % below the true model's
    34,519 (95 % interval -3.6 % to -0.6 %): the learnt life reads 1.9 % short (95 %: 0.6-3.6 % short), on the
    safe side; across the edge of what the life's 95 % interval allows ...'); None without a paired check.
    ``strong`` marks an error beyond the interval (the report's bold; ``str`` for plain text)."""
    if val is None or not (paired := val.paired_life_sentence(target)):
        return None
    row = next(r for r in val.life_table if r.get("target") == target)
    ratio, low, high = row["paired_ratio"], row.get("paired_ratio_low"), row.get("paired_ratio_high")
    side = ("on the safe side: a short life is conservative" if ratio < 0
            else "on the unsafe side: a long life is not conservative")
    bounds = "" if low is None or high is None else f" (95 %: {_short_long(float(low), float(high))})"
    reads = (f"the learnt life reads {100 * abs(ratio):.1f} % {'short' if ratio < 0 else 'long'}{bounds}, {side}"
             if ratio else f"the learnt life reads true{bounds}")
    check = val.paired_life_allowed(target)
    verdict = "within" if check is None else check[2]
    return verdict, f"{paired}: {reads}; {_paired_verdict(val, target, strong)}"


def life_trust_sentence(out: StudyOutputs, target: float) -> str:
    """How far to trust the life: this study's own validation when it was run at ``target`` (its paired check where
    it has one: :func:`paired_life_verdict`), else the presets' (:data:`LIFE_TRUST`)."""
    val = out.results.validation
    row = next((r for r in (val.life_table if val is not None else ()) if r.get("target") == target), None)
    if row is None or row.get("cycles") is None or row.get("surrogate_cycles") is None:
        return LIFE_TRUST
    if paired := paired_life_verdict(val, target):
        return (f"How far to trust the life: the validation below ran this study's true model on {val.n_samples:,} "
                f"samples; {paired[1]}.")
    change = float(row["surrogate_cycles"]) / float(row["cycles"]) - 1.0
    side = "below" if change < 0 else "above"
    verdict = ("their 95 % intervals overlap" if row.get("agree")
               else "<b>their 95 % intervals do not overlap</b>: the life's interval is too narrow")
    return (f"How far to trust the life: on {val.n_samples:,} direct samples of this study's true model "
            f"(the validation below), the life reads {100 * abs(change):.1f} % {side} the true model's "
            f"{float(row['cycles']):,.0f} cycles ({interval_text(row.get('cycles_low'), row.get('cycles_high'))}); "
            f"{verdict}.")


def _paired_verdict(val, target: float, strong: Callable[[str], str] = lambda text: f"<b>{text}</b>") -> str:
    """Whether the surrogate's error of the life, measured on the validation's samples, lies within what the life's
    own 95 % interval allows (:meth:`ValidationResult.paired_life_allowed`); ``strong`` marks an error beyond it."""
    check = val.paired_life_allowed(target)
    if check is None:
        return "the surrogate's own error, not the sampling noise the two share"
    low, high, verdict = check
    allows = f"what the life's 95 % interval allows ({signed_percent(low)} to {signed_percent(high)})"
    if verdict == "within":
        return f"within {allows}"
    if verdict == "unresolved":
        return f"across the edge of {allows}: these samples cannot tell whether the interval holds it"
    return (f"{strong(f'beyond {allows}')}: the interval holds the surrogate's error as the surrogate estimates it, "
            "and here it errs by more")


def _curve_pf_at(rel, cycles) -> float | None:
    """The R(N) curve's Pf at the level ``cycles`` (None where the curve has no such level)."""
    if cycles is None:
        return None
    levels = [float(c) for c in rel.cycles]
    return float(rel.pf[levels.index(float(cycles))]) if float(cycles) in levels else None


def _other_lives(rel) -> list[tuple[float, float, float | None, float | None]]:
    """(target, life, low, high) of the life table's targets other than the headline's, where the curve reaches
    them."""
    out = []
    for row in rel.life_table:
        target = float(row["target"])
        life, note = life_with_note(rel, target)
        if target != rel.target and life is not None and not note:
            out.append((target, life, *rel.life_interval(target)))
    return out


def reliability_section(out: StudyOutputs, figs: Figures) -> str:
    rel = out.results.reliability
    if rel is None:
        return not_run(out, "reliability", "the reliability study")
    life, note = life_with_note(rel, rel.target)
    cov = rel.largest_cov()
    worst = rel.largest_error()
    interval = rel.life_interval()
    life_notes = (([] if rel.life_hours is None else [running_time(rel.life_hours)])
                  + ([] if life is None or note else [interval_text(*interval)]))
    parts = [cards([
        (f"life at R = {rel.target:g}", _life_text(life, note), "; ".join(life_notes) or None),
        ("true-model calls", format_number(rel.model_calls), "for the whole curve"),
        ("Monte Carlo population", format_number(rel.n_mc), "n_mc"),
        ("learning converged", "yes" if rel.converged else "NO", (
            "its stopping rule met (reliability.stopping: ESC's count, or min U); the error beside is the larger "
            "estimate") if rel.converged else (
            rel.learning_stop if rel.stopped_while_confirming
            else "stopped by the budget of model calls" if rel.stopped_by_budget or not rel.learning_stop
            else rel.learning_stop)),
        ("surrogate error of R", "\u2014" if worst is None else f"{worst[0]:.3f}",
         None if worst is None else f"largest estimate, at {worst[1]:,.0f} cycles{_esc_part(rel, worst[1])}"),
        ("max COV of Pf", "\u2014" if cov is None else f"{cov:.3g}", "over the levels with Pf \u2265 pf_floor"),
        *_surrogate_fit_cards(rel.surrogate_fit, out.results.setting("wear.record_cycles")),
        ("wall time", f"{rel.wall_seconds:.4g} s", None),
    ])]
    parts += [warning(title, sentence) for title, sentence in (("Failed model calls.", rel.failed_calls_sentence()),
                                                              ("Joints worn away.", rel.worn_away_sentence()),
                                                              (_fit_title(rel) + ".", rel.surrogate_fit_sentence()))
              if sentence]
    if life is not None and not note:
        unchecked = numerics_unchecked(out)
        parts.append(f"<p>{life_trust_sentence(out, rel.target)}"
                     + (f" Beyond that, {e(unchecked)}." if unchecked else "") + "</p>")
    missed = curve_misses_life(rel, out.results.wear)
    if missed:
        parts.append(f'<p class="warn"><strong>The curve misses the life.</strong> {missed}</p>')
    if truncated := rel.truncation_sentence():
        parts.append(f"<p>{e(truncated[:1].upper() + truncated[1:])}.</p>")
    if len(rel.life_table) > 1:
        parts.append(table(["target R", "life (cycles)", "95 % interval (cycles)", "running time", "where"], [
            (format_number(r["target"], 6), format_number(r["cycles"]),
             interval_cells(*rel.life_interval(float(r["target"])), reach=rel.life_reach(float(r["target"]))),
             "\u2014" if r.get("hours") is None else running_time(float(r["hours"])),
             str(r.get("status", "")).replace("_", " ")) for r in rel.life_table], cls="kv"))
    if len(rel.joints) > 1:
        series = (f"<p>Series system of {len(rel.joints)} joints; the joint that governs: "
                  f"<b>{e(rel.governing_joint)}</b>. The system's life has a kink where two joints' lives cross")
        if rel.life_surrogate == "per_joint":
            parts.append(series + "; the life was learnt one Kriging per joint, each smooth there, and judged by the "
                         "joint that fails first. On an analytic two-joint system the life's 95 % interval held the "
                         "exact life in 18 of 20 runs at R = 0.9 and 20 of 20 at R = 0.5 (docs/study.md, \"How far to "
                         "trust the life\").</p>")
            parts.append(_joint_fit_table(rel))
        else:
            parts.append(series + ", and one Kriging of the system's life (<code>reliability.surrogate = "
                         "\"system_life\"</code>) can be confidently wrong there: on an analytic two-joint system "
                         "the life's 95 % interval held the exact life in 9 of 20 runs at R = 0.9, and in 18 of 20 "
                         "learnt one Kriging per joint (<code>\"per_joint\"</code>, the default; docs/study.md, "
                         "\"How far to trust the life\"). Check it with <code>jointwear validate</code>.</p>")
    ref = reference_of(out.config)
    label = reference_label(ref)
    ref_r = {float(v["cycles"]): float(v["value"]) for v in reference_values(ref, "reliability")}
    ref_life = next((float(v["value"]) for v in reference_values(ref, "life_cycles")
                     if v.get("target_reliability") == rel.target), None)
    other_lives = _other_lives(rel)
    parts.append('<div class="grid">')
    parts.append(figs.draw(
        lambda: F.reliability_curve_figure(rel.cycles, rel.reliability, pf_cov=rel.pf_cov, pf_error=rel.pf_error,
                                           target=rel.target, life_cycles=life,
                                           life_interval=None if note else interval, reference=ref_r or None,
                                           reference_life=ref_life, reference_label=label,
                                           joints=rel.joint_curves() or None, fine=rel.fine_curve(),
                                           other_lives=other_lives),
        "Reliability R(N) with a 95 % band (the Monte Carlo half-width from the COV of Pf plus the surrogate's error "
        "estimate), the target and the life, with its 95 % interval as a capped bar"
        + ("; the other targets' lives at their R" if other_lives else "")
        + ("; dashed: each judged joint's own R(N) with its band" if len(rel.joints) > 1 else "")
        + (f"; crosses: the values of the reference ({label})." if ref_r else "."),
        png_keys=("reliability_curve",),
        alt=reliability_curve_alt(rel.cycles, rel.reliability, rel.target, None if note else life)))
    conv = rel.convergence
    at = f" at {conv['cycles']:,.0f} cycles" if conv.get("cycles") else ""
    fit = rel.surrogate_fit  # a life with a call-to-call scatter: the curve integrates it, the learning does not
    curve_pf = _curve_pf_at(rel, conv.get("cycles")) if fit is not None and fit.life_scatter > 0 else None
    scatter = (f"; it is the learning's own estimator, the share of its Monte Carlo population whose surrogate mean "
               "fails, without the life's call-to-call scatter that R(N) counts, so its last value differs from the "
               f"curve's Pf there ({curve_pf:.4g}, dashed), which the tables and the life read"
               if curve_pf is not None and conv.get("pf") and f"{conv['pf'][-1]:.4g}" != f"{curve_pf:.4g}" else "")
    parts.append(figs.draw(
        (lambda: F.convergence_figure(conv["n_calls"], conv["pf"], cov=conv.get("cov"),
                                      curve_pf=curve_pf if scatter else None)) if conv.get("n_calls")
        else None,
        f"Convergence of the failure probability{at} against the number of true-model calls{scatter}; its band is "
        "the Monte Carlo part alone (1.96 COV of Pf), not the surrogate's error estimate.",
        png_keys=("convergence",), missing_text="Convergence of Pf: not recorded in this result."))
    parts.append("</div>")
    hist = rel.histograms
    ref_mean = {float(v["cycles"]): float(v["value"]) for v in reference_values(ref, "mean_max_wear")}
    parts.append(figs.draw(
        (lambda: F.wear_histograms_figure(hist["cycles"], hist["max_wear_mm"],
                                          limit_mm=allowance_mm(out, hist.get("joint")),
                                          reference_means=ref_mean or None, reference_label=label))
        if hist.get("cycles") else None,
        "Distribution of the max wear"
        + (f" of joint {hist['joint']}" if len(rel.joints) > 1 and hist.get("joint") else "")
        + " over the random inputs"
        + (f" at {', '.join(f'{c:,.0f}' for c in hist['cycles'])} cycles" if hist.get("cycles") else "")
        + (f", {hist['n_samples_shown']:,} of the {hist['n_population']:,} samples drawn for these histograms, the "
           f"wear read from the life surrogate (the curve and the tables read the study's own population of "
           f"{format_number(rel.n_mc)}, so the means and exceedances shown here differ from theirs by the sampling)"
           if hist.get("n_samples_shown") and hist.get("n_population") else "")
        + "; solid line: mean"
        + (f", dotted: the mean the reference reports ({label})" if ref_mean else "")
        + ", dashed: the allowable wear.", png_keys=("histogram",), wide=True,
        missing_text="Max wear histograms: none requested ([reliability] histogram levels)."))
    rows = [(format_number(float(c)), *probability_pair(float(r), float(p)),
             format_number(float(cv), 3), format_number(float(err), 2))
            for c, r, p, cv, err in zip(rel.cycles, rel.reliability, rel.pf, rel.pf_cov, rel.pf_error)]
    parts.append('<details class="numbers"><summary>R(N) as numbers</summary>')
    parts.append(table(["cycles", "R(N)", "Pf", "COV of Pf", "surrogate error of R"], rows, cls="num"))
    parts.append("</details>")
    return "".join(parts)


def sensitivity_section(out: StudyOutputs, figs: Figures) -> str:
    sens = out.results.sensitivity
    if sens is None:
        return not_run(out, "sensitivity", "the sensitivity study")
    nominal = sens.reliability_nominal
    lo_f, hi_f = sens.factors
    population = f" on the sensitivity's population of {sens.n_population:,}" if sens.n_population else ""
    rel = out.results.reliability
    curve = None
    if rel is not None and sens.cycles in set(float(c) for c in rel.cycles):
        curve = float(rel.reliability[[float(c) for c in rel.cycles].index(float(sens.cycles))])
    if curve is not None and f"{curve:.3f}" != f"{nominal:.3f}":
        population += f"; the R(N) curve, on its own population, reads {curve:.4g} there"
    parts = [f"<p>{e(f'Reliability at {sens.cycles:,.0f} cycles (nominal {nominal:.3f}{population}) when the mean of each variable is moved to {lo_f * 100:g} % and to {hi_f * 100:g} % of its value, the others fixed.')}"
             f"{e(_level_against_life(sens, rel))}</p>"]
    if not sens.shifts_move_reliability:
        parts.append(f'<p class="warn"><strong>No mean shift changes the reliability here.</strong> At '
                     f"{sens.cycles:,.0f} cycles R = {nominal:.3f} whatever the shift: the level lies outside the "
                     "scatter of the wear, so the tornado and the ranking below rank nothing. Put the R(N) curve where "
                     "R passes the target (<code>reliability.cycles_start</code>, <code>cycles_stop</code>) or set "
                     "<code>sensitivity.cycles</code> to a level inside it; the Sobol' indices of the wear still "
                     "hold.</p>")
    groups: dict[str, list[Mapping]] = {}
    for v in sens.variables:
        groups.setdefault(str(v.get("group") or "variables"), []).append(v)
    parts.append('<div class="grid">')
    unresolved = unresolved_pairs(sens)
    ranked = ranking_rows(sens)
    for g, vs in groups.items():
        title = g.replace("_", " ")
        parts.append(figs.draw(lambda vs=vs, title=title: sens.plot(vs, title=title[:1].upper() + title[1:]),
            _tornado_caption(sens, title, ranked.get(g, []), unresolved), png_keys=("tornado",),
            alt=tornado_alt([str(v.get("label") or v["name"]) for v in vs], [v["reliability_low"] for v in vs],
                            [v["reliability_high"] for v in vs], nominal, sens.cycles,
                            names=[str(v["name"]) for v in vs], unresolved=unresolved)))
    parts.append("</div>")
    of_joint = f" of joint {sens.sobol['joint']}" if sens.sobol.get("joint") else ""  # whose wear the indices are of
    whose = ("the Monte Carlo error and the surrogate's own" if any("dR_dmean_error" in v for v in sens.variables)
             else "the Monte Carlo error on the surrogate, not the surrogate's own error")  # a folder before it
    optional = [("elasticity_mean", f"elasticity of R to the mean, (\u03bc/R) dR/d\u03bc (\u00b1 95 %: {whose})"),
                ("S1", f"Sobol' S1{of_joint} (\u00b1 95 %)"), ("ST", f"Sobol' ST{of_joint} (\u00b1 95 %)")]
    extra_cols = [(k, h) for k, h in optional if any(v.get(k) is not None for v in sens.variables)]
    has_err = any(v.get("reliability_low_error") is not None for v in sens.variables)
    rows = []
    for v in sorted(sens.variables, key=lambda v: (str(v.get("group")), -max(
            abs(v["reliability_low"] - nominal), abs(v["reliability_high"] - nominal)))):
        swing = max(abs(v["reliability_low"] - nominal), abs(v["reliability_high"] - nominal))
        err = ((format_number(v.get("reliability_low_error"), 3) + " / "
                + format_number(v.get("reliability_high_error"), 3),) if has_err else ())
        rows.append((str(v.get("label") or v["name"]), str(v["name"]), str(v.get("group") or "").replace("_", " "),
                     format_number(v["reliability_low"], 3), format_number(v["reliability_high"], 3),
                     format_number(swing, 3)) + err
                    + tuple(_elasticity_text(sens.derivatives, v) if k == "elasticity_mean"
                            else _index_text(sens.sobol, v, k) for k, _h in extra_cols))
    parts.append('<details class="numbers"><summary>Sensitivity as numbers</summary>')
    parts.append(table(["variable", "name", "group", f"R at mean \u00d7 {lo_f:g}", f"R at mean \u00d7 {hi_f:g}",
                        "largest change of R"] + (["surrogate error of R (low / high)"] if has_err else [])
                       + [h for _k, h in extra_cols], rows, cls="num"))
    parts.append("</details>")
    flagged = [str(v.get("label") or v["name"]) for v in sens.variables if v.get("slope_contradicts_shifts")]
    if flagged:
        parts.append(f'<p class="warn"><strong>Local slope contradicts the mean shifts</strong> for '
                     f"{e(', '.join(flagged))}: the derivative at the nominal point has the opposite sign to the trend "
                     "of R between the two shifted means (both beyond their errors). The slope reads the surrogate at "
                     "the scale of the tolerance, where the wear need not be smooth; trust the mean shifts for the "
                     "trend.</p>")
    ref = reference_of(out.config)
    labels = {str(v["name"]): str(v.get("label") or v["name"]) for v in sens.variables}
    ref_ranks = {group_key(v.get("group")): [labels.get(str(n), str(n)) for n in v.get("ranking") or []]
                 for v in reference_values(ref, "sensitivity_ranking")}
    rrows = []
    for g, items in ranked.items():
        row = (g.replace("_", " "), ranking_text(items, unresolved))
        if ref:
            theirs = ref_ranks.get(group_key(g))
            row += (" > ".join(theirs) if theirs else "\u2014",)
        rrows.append(row)
    head = ["group", "this study (largest change of R first; \u2248: the difference is within the surrogate's "
            "error estimate of the two reliabilities)"]
    parts.append(f"<h3>Ranking beside the reference's ({e(reference_label(ref))})</h3>" if ref else "<h3>Ranking</h3>")
    targets = {str(v.get("name")): str(v.get("target") or "") for v in (out.config or {}).get("random_variables") or []}
    parts.append(ranking_meaning(sens, targets, ((out.config or {}).get("study_config") or {}).get("mechanism")))
    parts.append(table(head + [reference_label(ref)] if ref else head, rrows, cls="kv"))
    parts.append(far_shift_part(sens, labels))
    parts.append(archard_check_part(sens))
    sob = sens.sobol
    if sob.get("names"):
        output = str(sob.get("output") or "max wear")
        names = [f"{labels[str(n)]} ({n})" if str(n) in labels else str(n) for n in sob["names"]]
        parts.append(figs.draw(lambda: F.sobol_figure(names, sob["S1"], sob["ST"], S1_conf=sob.get("S1_conf"),
                                                      ST_conf=sob.get("ST_conf"), output=output),
                               f"First-order and total Sobol' indices of the {output}, on the surrogate.",
                               png_keys=("sobol",), wide=True))
        parts.append(sobol_by_joint_part(sob, labels))
    else:
        parts.append(figs.draw(None, "Sobol' indices", png_keys=("sobol",),
                               missing_text="Sobol' indices: not computed in this result."))
    return "".join(parts)


def _tornado_caption(sens, title: str, items: Sequence[tuple[str, str]], unresolved: set[tuple[str, str]]) -> str:
    """A group's tornado: what the bars, whiskers and line are, and the variables whose order its bars draw but the
    surrogate's error does not resolve (the ranking writes them with ≈)."""
    lo_f, hi_f = sens.factors
    text = (f"Sensitivity of the reliability: {title}. R at {sens.cycles:,.0f} cycles with each mean at "
            f"\u00d7 {lo_f:g} and \u00d7 {hi_f:g}, drawn from the nominal R (the vertical line), longest change on "
            "top; whiskers: each shifted R's 95 % error")
    tied = [f"{items[k][1]} \u2248 {items[k + 1][1]}" for k in range(len(items) - 1)
            if (items[k][0], items[k + 1][0]) in unresolved]
    if tied:
        text += (". The ranking below (\u2248: not told apart within the surrogate's error, so the bars' order "
                 f"between them is not resolved): {ranking_text(items, unresolved)}")
    return text + "."


def _level_against_life(sens, rel) -> str:
    """' This level is not the life's: ...' when the sensitivity's level differs from the life at the study's
    target, where a variable's effect on R, and so the ranking, may differ ('' otherwise)."""
    if rel is None:
        return ""
    life, note = life_with_note(rel, rel.target)
    if life is None or note or abs(float(sens.cycles) - life) <= 0.005 * life:
        return ""
    return (f" This level (sensitivity.cycles) is not the life at R = {rel.target:g} ({life:,.0f} cycles): a mean "
            "shift moves R most where the level sits in the middle of the lives' scatter, so the changes and the "
            "ranking read at the life can differ from these.")


def sobol_by_joint_part(sobol: Mapping, labels: Mapping[str, str]) -> str:
    """With several judged joints, the total Sobol' index of each joint's wear, a column per joint (the figure and
    the table above are the first joint's); empty otherwise."""
    by_joint = sobol.get("by_joint") or {}
    if len(by_joint) < 2:
        return ""
    names = [str(n) for n in sobol["names"]]
    rows = []
    for k, name in enumerate(names):
        cells = []
        for indices in by_joint.values():
            half = (indices.get("ST_conf") or [None] * len(names))[k]
            text = format_number(indices["ST"][k], 3)
            cells.append(text if half is None else f"{text} \u00b1 {format_number(float(half), 2)}")
        rows.append((labels.get(name, name), name, *cells))
    head = ["variable", "name", *(f"ST of joint {joint}'s wear (\u00b1 95 %)" for joint in by_joint)]
    return (f"<h3>Sobol' total index of each judged joint's wear</h3><p>The figure and the table above are of the "
            f"{e(str(sobol.get('output') or 'first joint'))}; here each judged joint's own wear, on its own "
            "surrogate.</p>" + table(head, rows, cls="num"))


def _elasticity_text(derivatives: Mapping, variable: Mapping) -> str:
    """:func:`_elasticity_value`, with 'local slope contradicts the mean shifts' when the study flagged it
    (``slope_contradicts_shifts``)."""
    flag = " (local slope contradicts the mean shifts)" if variable.get("slope_contradicts_shifts") else ""
    return _elasticity_value(derivatives, variable) + flag


def _elasticity_value(derivatives: Mapping, variable: Mapping) -> str:
    """The elasticity of R to a mean with its 95 % half-width, from that of the derivative it scales
    (``dR_dmean_error``: the Monte Carlo error and the surrogate's own over its posterior; a folder written before
    it was recorded: 1.96 SE, the Monte Carlo error alone); 'not resolved' when the half-width exceeds the value (a
    sign the study cannot tell)."""
    value = variable.get("elasticity_mean")
    text = format_number(value, 3)
    names = [str(n) for n in derivatives.get("names") or []]
    if value is None or str(variable["name"]) not in names or not derivatives.get("dpf_dmean_se"):
        return text
    k = names.index(str(variable["name"]))
    slope = derivatives["dpf_dmean"][k]
    error = variable.get("dR_dmean_error")
    if error is None or not math.isfinite(error):
        error = Z95 * derivatives["dpf_dmean_se"][k]
    if not slope:
        return text
    half = abs(value) * error / abs(slope)
    return f"{text} \u00b1 {format_number(half, 2)}" + (" (not resolved)" if half > abs(value) else "")


def _index_text(sobol: Mapping, variable: Mapping, key: str) -> str:
    """A column of the sensitivity table; a Sobol' index with its 95 % confidence half-width where it has one
    (on a small base sample ST can read below S1 within them)."""
    text = format_number(variable.get(key), 3)
    names = [str(n) for n in sobol.get("names") or []]
    conf = sobol.get(f"{key}_conf") if key in ("S1", "ST") else None
    if conf is None or str(variable["name"]) not in names or variable.get(key) is None:
        return text
    half = conf[names.index(str(variable["name"]))]
    return text if half is None else f"{text} \u00b1 {format_number(float(half), 2)}"


def ranking_meaning(sens, targets: Mapping[str, str] | None = None, mechanism: Mapping | None = None) -> str:
    """What the ranking measures, and what it does not: the change of R when one mean moves by a fixed fraction is
    a change of the nominal design (for a toleranced length, many of its standard deviations), not of the
    variable's scatter, whose share in the scatter of the wear the Sobol' indices give."""
    lo_f, hi_f = sens.factors
    ranked = sens.variance_ranking()
    output = str(sens.sobol.get("output") or "wear")
    by_variance = (f" By total-effect Sobol' index of the {output} (ST, below: a variable's share of the variance "
                   "with all its interactions, so the indices add up to 1 or more): "
                   + ", ".join(f"{name} {format_number(st, 2)}" for name, st in ranked) + "." if ranked else "")
    text = (f"The ranking is of the change of R when one mean alone moves to {lo_f * 100:g} % and {hi_f * 100:g} % "
            "of its value: a change of the nominal design (for a toleranced length, many standard deviations of its "
            "tolerance), not of the variable's scatter. Which scatter drives the scatter of the wear is what the "
            "Sobol' indices tell." + by_variance)
    if scatter := scatter_sentence(sens.sobol):
        text += f" Beside them, {scatter}."
    if coordinates := coordinate_shift_sentence(dict(targets or {}), tuple(sens.factors),
                                                dict(mechanism) if mechanism else None):
        text += f" Here {coordinates}."  # not capitalised: it begins with a variable's name (l_OA)
    return f"<p>{e(text)}</p>"


def far_shift_part(sens, labels: Mapping[str, str]) -> str:
    """The mean shifts too far from the population for the surrogate (SensitivityResult.rules, rule
    ``separable_scaling``): read from true-model runs of the shifted nominal mechanism, and flagged where that
    mechanism could not be built or run (R = 0 then measures that, not the wear's sensitivity)."""
    far = sens.far_shifts()
    if not far:
        return ""
    failed = sens.unbuilt_shifts()  # the shifted mechanism did not run
    rows, classes = [], []
    for r in far:
        name = str(r["variable"])
        rows.append((f"{labels.get(name, name)} ({name})", f"\u00d7 {float(r['factor']):g}",
                     format_number(r.get("reliability"), 3),
                     "0 (exact)" if r in failed else format_number(r.get("error_estimate"), 3),
                     str(r.get("reason") or "") if r in failed else f"wear \u00d7 {format_number(r['wear_ratio'], 3)}"))
        classes.append("bad" if r in failed else "")
    parts = ["<h3>Shifts outside the learned region</h3>",
             "<p>These means moved more standard deviations than the surrogate was learned over "
             "(<code>sensitivity.surrogate_shift_limit</code>). Each was read from two runs of the true model, the "
             "nominal mechanism and the shifted one: the population's wear is scaled by their ratio.</p>"]
    if failed:
        names = sorted({labels.get(str(r["variable"]), str(r["variable"])) for r in failed})
        parts.append(f'<p class="warn"><strong>The shifted mechanism could not be built or run for '
                     f'{e(", ".join(names))}</strong> (the table gives the reason): its reliability is counted as 0. '
                     "That measures the shifted mechanism's failure to work, not the wear's sensitivity to the "
                     "variable; read its rank with that in mind.</p>")
    if extreme := sens.extreme_shifts_sentence():
        parts.append(f'<p class="warn"><strong>A shifted mechanism that moves otherwise.</strong> '
                     f"{e(extreme[:1].upper() + extreme[1:])}.</p>")
    parts.append(table(["variable", "shift of the mean", "R", "error of R (the surrogate's and the wear ratio's "
                        "scatter)", "read from: the nominal population's wear scaled by"], rows, cls="num",
                       row_cls=classes))
    return "".join(parts)


def archard_check_part(sens) -> str:
    """The mean shifts of the judged body's k and H against Archard's exact scaling (SensitivityResult.
    archard_checks), with a warning when they disagree: then the shifted reliabilities are less certain than their
    error estimates say."""
    checks = sens.archard_checks
    if not checks:
        return ""
    rows, classes = [], []
    for c in checks:
        made = c.get("consistent") is not None
        verdict = ("agree" if c["consistent"] else "DISAGREE") if made else str(c.get("note") or "not checked")
        rows.append((str(c["variable"]), f"\u00d7 {float(c['factor']):g}",
                     format_number(c.get("reliability_surrogate"), 3),
                     format_number(c.get("reliability_archard"), 3) if made else "\u2014",
                     format_number(c.get("difference"), 3) if made else "\u2014",
                     format_number(c.get("tolerance"), 3) if made else "\u2014", verdict))
        classes.append("bad" if made and not c["consistent"] else "")
    bad = [c for c in checks if c.get("consistent") is False]
    parts = ["<h3>Check against Archard's law</h3>",
             "<p>The judged wear is proportional to the bearing's k / H, so shifting k or H scales every sample's "
             "life exactly (up to the wear's feedback on the dynamics). Each row compares the surrogate's direct "
             "reading of the shifted population with that scaling applied to the nominal population, where the "
             "surrogate was learned; they agree when they differ by less than their combined errors. Where the "
             "check can be made, the sensitivity above reports the scaling.</p>"]
    if bad:
        worst = max(abs(float(c["difference"])) for c in bad)
        parts.append(f'<p class="warn"><strong>The surrogate disagrees with Archard\'s law by up to '
                     f"{worst:.3f} in R.</strong> Its direct readings of shifted means are uncertain by about that "
                     "much, more than their error estimates say: the other variables' shifted reliabilities, which "
                     "have no such check, may be too.</p>")
    parts.append(table(["variable", "mean", "R, surrogate", "R, Archard scaling", "difference", "tolerance",
                        "verdict"], rows, cls="num", row_cls=classes))
    return "".join(parts)


def _validated_life_card(row: Mapping) -> tuple[str, str, str]:
    """The life at the headline target on the true model's curve, beside the surrogate's."""
    value = "\u2014" if row.get("cycles") is None else f"{row['cycles']:,.0f} cycles"
    surrogate = ("\u2014" if row.get("surrogate_cycles") is None else f"{row['surrogate_cycles']:,.0f}")
    true_model = row.get("note") or f"true model, {interval_text(row.get('cycles_low'), row.get('cycles_high'))}"
    note = (f"{true_model}; surrogate {surrogate}, "
            f"{interval_text(row.get('surrogate_cycles_low'), row.get('surrogate_cycles_high'))}"
            + (": the intervals do not overlap" if row.get("agree") is False else ""))
    return (f"life at R = {row['target']:g}", value, note)


def _paired_life_card(row: Mapping) -> tuple[str, str, str]:
    """The surrogate's life against the true model's on the same samples: the surrogate's own error."""
    low, high = row.get("paired_ratio_low"), row.get("paired_ratio_high")
    bounds = "" if low is None or high is None else f"95 % interval {signed_percent(low)} to {signed_percent(high)}; "
    return ("surrogate's life on these samples", signed_percent(row["paired_ratio"]),
            f"{bounds}against the true model's on the same samples: the surrogate's own error, without the sampling "
            "noise the two share")


_ALLOWED = {"within": "within", "unresolved": "across its edge", "beyond": "BEYOND"}


def _validated_life_table(val) -> str:
    """Every target's life on the true model's curve beside the surrogate's, and the paired check's reading of it
    against what the life's 95 % interval allows (the cards above give the first target's); empty without a life
    table."""
    if not val.life_table:
        return ""
    paired = any(row.get("paired_ratio") is not None for row in val.life_table)
    rows = []
    for row in val.life_table:
        true = ("\u2014" if row.get("cycles") is None
                else f"{row['cycles']:,.0f} ({interval_cells(row.get('cycles_low'), row.get('cycles_high'))})")
        surrogate = ("\u2014" if row.get("surrogate_cycles") is None else f"{row['surrogate_cycles']:,.0f} "
                     f"({interval_cells(row.get('surrogate_cycles_low'), row.get('surrogate_cycles_high'))})")
        cells = (format_number(row["target"], 6), true + (f"; {row['note']}" if row.get("note") else ""), surrogate,
                 {True: "yes", False: "NO"}.get(row.get("agree"), "\u2014"))
        if paired:
            low, high = row.get("paired_ratio_low"), row.get("paired_ratio_high")
            ratio = ("\u2014" if row.get("paired_ratio") is None else signed_percent(row["paired_ratio"])
                     + ("" if low is None or high is None else f" ({signed_percent(low)} to {signed_percent(high)})"))
            check = val.paired_life_allowed(float(row["target"]))
            cells += (ratio, "\u2014" if check is None
                      else f"{_ALLOWED[check[2]]} ({signed_percent(check[0])} to {signed_percent(check[1])})")
        rows.append(cells)
    heads = ["target R", "life, true model (95 %)", "life, surrogate (95 %)", "intervals overlap"]
    if paired:
        heads += ["surrogate / true \u2212 1 on the same samples (95 %)", "against what the life's 95 % interval "
                  "allows"]
    return "<p>The life at every target on the true model's curve and on the surrogate's:</p>" + table(
        heads, rows, cls="kv")


def validation_section(out: StudyOutputs, figs: Figures) -> str:
    """The surrogate's R(N) against the true model sampled directly, and its cross-validation."""
    val = out.results.validation
    agree = sum(bool(a) for a in val.agreement)
    cv = val.cross_validation
    q2 = cv.get("q2")
    resolution = val.resolution
    head = cards([
        ("true-model samples", f"{val.n_samples:,}", f"{val.model_calls:,} new model calls"),
        ("levels in agreement", f"{agree} of {len(val.agreement)}", "their 95 % intervals overlap (a lenient test)"),
        ("levels passing a 95 % test", f"{int((~val.differs_at_95()).sum())} of {len(val.agreement)}",
         "the difference within the root sum of squares of the 95 % half-widths"),
        ("resolution in R", f"\u00b1{resolution:.2g}", "the widest 95 % half-width of the direct estimate: smaller "
         "differences from the surrogate cannot be seen with these samples"),
        ("cross-validation Q\u00b2", "-" if q2 is None else f"{q2:.3f}",
         f"leave-one-out over {cv.get('n_points', 0)} design points"),
        *[_validated_life_card(row) for row in val.life_table[:1]],
        *[_paired_life_card(row) for row in val.life_table[:1] if row.get("paired_ratio") is not None],
    ])
    # the half-width the overlap test adds (Monte Carlo part and error estimate), with the error estimate beside it
    rows = [[f"{c:,}", format_number(r), f"[{format_number(lo)}, {format_number(hi)}]", format_number(rs),
             f"{format_number(hw)} ({format_number(err)})", "yes" if a else "NO", "NO" if d else "yes"]
            for c, r, lo, hi, rs, hw, err, a, d in zip(val.cycles, val.reliability_mc, val.ci_low, val.ci_high,
                                                       val.reliability_surrogate, val.surrogate_half_width,
                                                       val.surrogate_error, val.agreement, val.differs_at_95())]
    heads = ["cycles", "R, true model", "exact 95 % CI", "R, surrogate", "its 95 % half-width (error estimate)",
             "intervals overlap", "95 % test"]
    if val.paired:
        heads += ["same samples: surrogate \u2212 true (95 %)", "|difference| / error estimate"]
        degrees = {"inside": "inside", "reaches": "reaches it", "exceeds": "EXCEEDS it"}
        for row, d, lo, hi, ratio, verdict in zip(rows, val.paired_difference(), val.paired_difference_low,
                                                  val.paired_difference_high, val.paired_error_ratio(),
                                                  val.paired_verdict()):
            degree = degrees[str(verdict)]
            row += [f"{d:+.3f} [{lo:+.3f}, {hi:+.3f}]",
                    f"{ratio:.2g} ({degree})" if math.isfinite(ratio) else degree]
    body = table(heads, rows)
    fig1 = figs.draw(lambda: F.validation_figure(val.cycles, val.reliability_mc, val.ci_low, val.ci_high,
                                                 val.reliability_surrogate, val.surrogate_half_width,
                                                 n_samples=val.n_samples),
                     "R(N): the surrogate against the true model sampled directly", png_keys=("validation",),
                     alt=validation_alt(val.cycles, val.reliability_mc, val.reliability_surrogate, val.agreement,
                                        val.n_samples))
    fig2 = ""
    if cv.get("log_life_true"):
        fig2 = figs.draw(lambda: F.cross_validation_figure(cv["log_life_true"], cv["log_life_loo"],
                                                           cv.get("log_life_loo_sd"), q2=q2),
                         "Leave-one-out cross-validation of the life surrogate: each design point's ln N_f (the "
                         "natural log of its wear life in cycles) predicted by the surrogate refitted without it, "
                         "against its true value, with the prediction's 95 % interval; Q\u00b2 is the leave-one-out "
                         "predictive R\u00b2, the share of the points' variance of ln N_f so predicted (1: all of "
                         "it).", png_keys=("cross_validation",))
    lead = ("<p>Each sample is one run of the true wear model; its reliability at a level is the share of samples "
            "whose wear life is longer, with an exact (Clopper-Pearson) 95 % interval. A level agrees when the "
            "two estimates differ by less than the sum of their 95 % half-widths (the surrogate's: its Monte "
            "Carlo interval plus its own error estimate), that is when the two intervals overlap: a lenient test, "
            "which two independent errors of equal width fail only 0.6 % of the time. The 95 % test asks more: "
            "the difference within the root sum of squares of the three 95 % half-widths (the true model's "
            "sampling, the surrogate's Monte Carlo and the surrogate's error estimate).</p>")
    if val.paired:
        lead += ("<p>The surrogate is also read on the same samples as the true model: their difference then holds "
                 "the surrogate's own error alone, as the noise of sampling the two share cancels (95 % bootstrap "
                 "interval). Against the surrogate's own error estimate e at each level: <em>inside</em> when that "
                 "interval lies within +-e (the estimate holds), <em>reaches it</em> when it only overlaps +-e (not "
                 "refuted, not shown), <em>exceeds it</em> when it lies beyond (the surrogate errs by more than it "
                 "says); the ratio is |difference| / e.</p>")
    if val.joints:
        n = len(val.cycles)
        banded = all("levels_agree" in j for j in val.joints)  # results written before the joints had a band
        body += ("<p>Each judged joint's own R(N) on the same samples (the share whose life at that joint is longer) "
                 "against the study's R(N) of that joint" + (", agreeing at a level by the same rule as the "
                 "mechanism's curve" if banded else "") + ":</p>"
                 + table(["joint", "largest difference in R", "levels where the study's R lies in the exact 95 % "
                          "interval"] + (["levels in agreement"] if banded else []),
                         [(j["name"], f"{j['largest_difference']:.3f}", f"{j['levels_within_interval']} of {n}")
                          + ((f"{j['levels_agree']} of {n}",) if banded else ()) for j in val.joints], cls="kv"))
    return head + _validated_life_table(val) + lead + body + f'<div class="grid">{fig1}{fig2}</div>'


def comparison_section(checks: Sequence[Check], ref: Mapping) -> str:
    label = reference_label(ref)
    rows, classes = [], []
    for c in checks:
        unit = "" if c.unit in ("-", "") else f" {c.unit}"
        band = e(c.band) + (f'<div class="desc">{e(c.justification)}</div>' if c.justification else "")
        rows.append((e(c.quantity), e("\u2014" if c.reference is None else format_number(c.reference, c.digits) + unit),
                     e("\u2014" if c.ours is None else format_number(c.ours, c.digits) + unit),
                     e(c.difference_text), band, _pill(c.status), e(c.note),
                     e(c.source)))
        classes.append(c.status.replace("/", ""))
    head = (f"<p>{e(checks_summary(checks))}. Reference values: {e(ref.get('citation') or label)}; each row names "
            "the table, figure or section it comes from, and each band says why it is that wide (the config's "
            "<code>[reference]</code>).")
    if ref.get("note"):
        head += f" {e(ref['note'])}"
    head += "</p>"
    return head + table(["quantity", label, "this study", "difference (relative; absolute for R)", "band", "status",
                         "note", "source"],
                        rows, cls="compare", raw_cols=(0, 1, 2, 3, 4, 5, 6, 7), row_cls=classes)


_QUANTITY_TEXT = {"bearing_max_depth": "the max wear depth of {}'s bearing",
                  "journal_max_depth": "the max wear depth of {}'s journal",
                  "clearance_growth": "the clearance growth of {}"}


def judged_quantity(out: StudyOutputs) -> str:
    """What the life judges, for the summary's life card: 'joint B's bearing's max wear depth reaching 0.1 mm,
    uniform wear mode' ('' without a reliability result)."""
    rel = out.results.reliability
    if rel is None:
        return ""
    what = _QUANTITY_TEXT.get(rel.quantity, rel.quantity.replace("_", " ") + " of {}")
    joints = [j for j in rel.joints if j.get("name")]
    if len(joints) == 1:
        allowance = joints[0].get("allowance_mm")
        text = what.format(f"joint {joints[0]['name']}") + (f" reaching {allowance:g} mm" if allowance else "")
    else:
        names = ", ".join(str(j["name"]) for j in joints)
        text = what.format(f"each of joints {names}") + " reaching its allowance, the first to fail"
    mode = out.results.setting("wear.geometry_mode")
    return text + (f", {mode} wear mode" if mode else "")


def _unjudged_when(wear, rel, sentence: str) -> str:
    """When the unjudged part of the joint ``sentence`` names reaches the allowance in the nominal history, against
    the headline life ('; the nominal journal reaches it at about 30,300 cycles, before the life at R = 0.9');
    '' where the history does not tell."""
    quantity = rel.quantity if rel is not None else None
    part, other = {"bearing_max_depth": ("journal", "journal_max_depth"),
                   "journal_max_depth": ("bearing", "bearing_max_depth")}.get(quantity, (None, None))
    joint = next((j for j in wear.joints if sentence.startswith(f"joint {j['name']}'s")), None)
    if other is None or joint is None or not joint.get("allowance_mm"):
        return ""
    at = nominal_lives([joint], {str(joint["name"]): float(joint["allowance_mm"])}, other).get(str(joint["name"]))
    if at is None or at > wear.cycles:  # within the history only: no extrapolation
        return ""
    text = f"; the nominal {part} reaches the allowance at about {at:,.0f} cycles"
    life, note = life_with_note(rel, rel.target)
    if life is not None and not note:
        text += (f", {'before' if at < life else 'after'} the life at R = {rel.target:g} ({life:,.0f} cycles)"
                 + (": the mechanism may fail by it first" if at < life else ""))
    return text


def summary_cards(out: StudyOutputs, checks: Sequence[Check], ref: Mapping | None) -> str:
    """Key numbers of the study; with a reference, how many of its numbers are within their bands."""
    wear, rel = out.results.wear, out.results.reliability
    items: list[tuple[str, str, str | None]] = []
    if ref:
        t = tally(checks)
        items.append((f"checks against {reference_label(ref)}",
                      f"{t.passed} / {t.judged}" if t.judged else "\u2014",
                      t.details() if t.judged or t.rankings else "no results yet"))

    def ref_note(quantity: str, **match) -> str | None:
        for v in reference_values(ref, quantity):
            if all(v.get(k) == x for k, x in match.items()) and v.get("value") is not None:
                unit = f" {v['unit']}" if v.get("unit") else ""
                return f"{reference_label(ref)}: {format_number(float(v['value']))}{unit}"
        return None

    if wear is not None:
        first = f" of joint {wear.joints[0]['name']}" if len(wear.joints) > 1 else ""  # the others: in its section
        items.append((f"nominal max wear{first}, {wear.cycles:,.0f} cycles", f"{wear.max_wear_mm:.4g} mm",
                      ref_note("nominal_max_wear", cycles=wear.cycles)))
    else:
        items.append(("nominal max wear", "\u2014", "no wear result"))
    if rel is not None:
        life, note = life_with_note(rel, rel.target)
        paired = paired_life_verdict(out.results.validation, rel.target)
        flags = {"beyond": "the validation finds a larger error (caveats below); ",
                 "unresolved": "the validation's error reaches the interval's edge (caveats below); "}
        flag = (flags.get(paired[0], "") if paired is not None
                else "the validation's true model disagrees (caveats below); "
                if validated_life_disagreement(out.results.validation, rel) is not None else "")
        what = judged_quantity(out)
        shown = "; ".join(x for x in (what, "" if life is None or note else interval_text(*rel.life_interval()),
                                      ref_note("life_cycles", target_reliability=rel.target), flag.rstrip("; ")) if x)
        items.append((f"life at R = {rel.target:g}", _life_text(life, note), shown or None))
        items.append(("true-model calls", format_number(rel.model_calls),
                      "; ".join(x for x in ("for the whole R(N) curve", _other_calls(out), ref_note("model_calls"))
                                if x)))
    else:
        items.append(("life at the target R", "\u2014", "no reliability result"))
    design = out.results.design
    if design is not None:
        chosen = design.chosen
        today = ("" if design.cost_change is None
                 else f"; today's design {design.baseline_cost:.4g} ({design.cost_change:+.4g})")
        verdict = (design.verdict() or "").replace("_", " ")
        ver = design.verification or {}
        if ver.get("reliability_at_target_life") is not None and ver.get("error") is not None:
            verdict += f" (R(N*) = {ver['reliability_at_target_life']:.3f} \u00b1 {ver['error']:.3f})"
        items.append((f"design for {design.target_life_cycles:,.0f} cycles at R = {design.target_reliability:g}",
                      "no candidate" if chosen is None else f"cost {chosen['cost']:.4g}",
                      None if chosen is None else f"verification: {verdict}{today}"))
    return cards(items, cls="cards summary")


def _other_calls(out: StudyOutputs) -> str:
    """The true-model calls this study ran beyond the curve's ('beyond them this study ran 9 for the sensitivity and
    400 for the validation'), written before any reference's count so that they cannot read as the reference's; ''
    when there are none. The design's calls are in its own card."""
    sens, val = out.results.sensitivity, out.results.validation
    runs = [f"{format_number(n)} for {what}" for n, what in (
        (getattr(sens, "extra_model_calls", None), "the sensitivity"),
        (getattr(val, "n_samples", None), "the validation")) if n]  # its samples: a resumed one reads them back
    if not runs:
        return ""
    return "beyond them this study ran " + (runs[0] if len(runs) == 1 else f"{', '.join(runs[:-1])} and {runs[-1]}")


def validated_life_disagreement(val, rel) -> str | None:
    """'at R = 0.9 the true model's life is 398,667 cycles (383,602-407,581), the curve's 373,680 (...): ...' when
    the validation's life at the study's target and the curve's have 95 % intervals that do not overlap (None
    otherwise, and without a validation)."""
    if val is None or rel is None:
        return None
    row = next((r for r in val.life_table if r.get("target") == rel.target), None)
    if row is None or row.get("agree") is not False or row.get("cycles") is None:
        return None
    curve = "-" if row.get("surrogate_cycles") is None else f"{row['surrogate_cycles']:,.0f}"
    return (f"at R = {rel.target:g} the true model's life is {row['cycles']:,.0f} cycles "
            f"({interval_text(row.get('cycles_low'), row.get('cycles_high'))}), the curve's {curve} "
            f"({interval_text(*rel.life_interval())}): the 95 % intervals do not overlap, so the life above carries "
            f"more error than its interval says (the validation's {val.n_samples:,} samples)")


def _learning_rule(results) -> SimpleNamespace | None:
    """The learning's stopping rule as config.json records it (None where it records none)."""
    values = {k: results.setting(f"reliability.{k}") for k in ("stopping", "error_abs_tol", "error_tol")}
    return None if None in values.values() else SimpleNamespace(**values)


_PAIRED_LIFE_TITLES = {"beyond": "The life errs by more than its interval says",
                       "unresolved": "The life's error reaches the edge of its interval",
                       "within": "The true model's life differs from the curve's on other samples"}


def _life_validation_caveats(out: StudyOutputs) -> list[tuple[str, str, str]]:
    """The validation's verdict on the life at the study's target, for the summary: the paired check's (the same
    sentence as the reliability section's "How far to trust the life", :func:`paired_life_verdict`) where the
    validation has one, with the unpaired intervals' non-overlap as a clause; the unpaired non-overlap alone
    (:func:`validated_life_disagreement`) where it has none."""
    val, rel = out.results.validation, out.results.reliability
    if val is None or rel is None:
        return []
    hint = linear_trend_hint(out.results.setting("reliability.trend"))
    unpaired = validated_life_disagreement(val, rel)
    paired = paired_life_verdict(val, rel.target, strong=str)  # the summary's lines are escaped plain text
    if paired is None:
        return [] if unpaired is None else [("validation", "The true model's life disagrees with the curve's",
                                             unpaired + (f"; {hint}" if hint else ""))]
    verdict, sentence = paired
    if verdict == "within" and unpaired is None:
        return []
    text = f"against {val.n_samples:,} direct runs of the true model, {sentence}"
    if unpaired is not None:
        row = next(r for r in val.life_table if r.get("target") == rel.target)
        shift = float(row["paired_surrogate_cycles"]) / float(row["surrogate_cycles"]) - 1.0
        text += (f". The unpaired 95 % intervals (the true model's {float(row['cycles']):,.0f} cycles, the curve's "
                 f"{float(row['surrogate_cycles']):,.0f}) do not overlap, partly from these samples' own draw: the "
                 f"surrogate read on them gives {float(row['paired_surrogate_cycles']):,.0f} cycles, "
                 f"{100 * abs(shift):.1f} % {'above' if shift > 0 else 'below'} its life on the study's population")
    if verdict != "within" and hint:
        text += f"; {hint}"
    return [("validation", _PAIRED_LIFE_TITLES[verdict], text)]


def _paired_at_missed(val) -> str:
    """At the levels where the true model's and the curve's intervals do not overlap, what the paired check says of
    the surrogate's own error there ('; on the same samples the surrogate's difference there reaches its error
    estimate (0.97 of it): part of the disagreement is these samples' own draw'); '' unpaired."""
    if not val.paired:
        return ""
    missed = [k for k, ok in enumerate(val.agreement) if not ok][:3]
    verdicts, ratio = val.paired_verdict(), val.paired_error_ratio()
    told = []
    for k in missed:
        size = f" ({ratio[k]:.2g} of it)" if math.isfinite(ratio[k]) else ""
        where = f" at {val.cycles[k]:,.0f} cycles" if len(missed) > 1 else " there"
        told.append(f"{'lies inside' if verdicts[k] == 'inside' else verdicts[k]} its error estimate{size}{where}")
    if not told:
        return ""
    own = ("" if all(verdicts[k] == "exceeds" for k in missed)
           else ": part of the disagreement is these samples' own draw")
    return f"; on the same samples the surrogate's difference {', '.join(told)}{own}"


def _held_but_wider(rel, rule) -> str:
    """For a learning whose budget ended while its stop held on some designs: why the rule can hold while the error
    shown exceeds its tolerance (the stop tests ESC's count of misclassified samples only; the error shown adds the
    Kriging's posterior spread); '' where that is not the case."""
    if rule is None or rule.stopping != "error" or not rel.stopped_while_confirming or rel.pf_error_esc is None:
        return ""
    tolerance = error_tolerances(rel, rule)
    counted = ~np.asarray(rel.below_floor, dtype=bool)
    esc, total = np.asarray(rel.pf_error_esc, dtype=float), np.asarray(rel.pf_error, dtype=float)
    esc_ok = np.all(~counted | ~np.isfinite(esc) | (esc <= tolerance))
    over = counted & np.isfinite(total) & (total > tolerance)
    if not esc_ok or not over.any():
        return ""
    k = int(np.argmax(np.where(over, total / tolerance, -np.inf)))
    return (f". The stop held although the error shown reaches {total[k]:.3f} at {rel.cycles[k]:,.0f} cycles, over "
            f"its tolerance {tolerance[k]:.3g}: the stop tests ESC's count of misclassified samples only "
            f"({esc[k]:.3f} there), and the error shown adds the Kriging's posterior spread")


def summary_caveats(out: StudyOutputs) -> str:
    """The warnings of the sections below that bear on the summary's numbers, one line each with a link to its
    section (empty when there is none): a reader of the headline alone must not miss them."""
    sim, wear, rel = out.results.simulate, out.results.wear, out.results.reliability
    items: list[tuple[str, str, str]] = []
    if sim is not None:
        items += [("dynamics", "Outside the contact law's range", s) for s in sim.outside_hertz()]
    if wear is not None:
        if wear.uniform_out_of_range:
            items.append(("wear", "Uniform mode is outside its range",
                          "the worn pocket is wider than the contact patch, so the depth grows more slowly than "
                          'uniform mode assumes; run the study with wear.geometry_mode = "profile" and trust that '
                          "answer"))
        items += [("wear", "Worn away", s) for s in wear.worn_away()]
        items += [("wear", "Worn through", s) for s in wear.worn_through()]
        told = sim.outside_hertz_joints() if sim is not None else []
        items += [("wear", "Outside the contact law's range", s) for s in wear.outside_hertz(skip=told)]
        quantity = rel.quantity if rel is not None else out.results.setting("reliability.quantity")
        if quantity:
            items += [("wear", "Wear the limit state does not judge", s + _unjudged_when(wear, rel, s))
                      for s in wear.unjudged_wear(quantity)]
    conv = out.results.wear_convergence
    if rel is not None and (unchecked := numerics_unchecked(out)):
        items.append(("reliability", "The wear history's numerics are not checked", unchecked))
    if conv is not None and conv.not_converged():
        own = " or a joint's own" if conv.baseline.get("joints") else ""
        items.append(("wear-convergence", "The wear history is not converged",
                      f"refining {', '.join(conv.not_converged())} moves the nominal "
                      f"{'life' if conv.measure == 'life' else 'wear'}{own} by more than "
                      f"{100 * conv.tolerance:g} %; refine it in [wear] and run the study again"))
    if rel is not None:
        if not rel.converged:
            why = ("its budget of model calls ended" if rel.stopped_by_budget or not rel.learning_stop
                   else rel.learning_stop)
            max_calls = out.results.setting("reliability.max_calls")
            items.append(("reliability", "The learning did not converge",
                          f"{why}; the curve and the life carry more error than the settings ask for, and the R(N) "
                          "band and the life's interval, the surrogate's own estimate of that error, can then be too "
                          "narrow (docs/study.md; jointwear validate measures it against the true model). Raise "
                          f"reliability.max_calls{f' (now {max_calls})' if max_calls else ''} and run again with "
                          "--resume: the calls made are kept" + _held_but_wider(rel, _learning_rule(out.results))))
        elif line := posterior_error_line(rel, _learning_rule(out.results)):
            items.append(("reliability", "The whole error estimate exceeds the learning's tolerance",
                          line.replace("`jointwear validate`", "<code>jointwear validate</code>")))
        items += [("reliability", title, s) for title, s in (("Failed model calls", rel.failed_calls_sentence()),
                                                             ("Joints worn away", rel.worn_away_sentence()),
                                                             (_fit_title(rel), rel.surrogate_fit_sentence()),
                                                             ("A series system", rel.series_sentence())) if s]
    design = out.results.design
    if design is not None and design.chosen is not None:
        if design.verdict() != "meets":
            items.append(("design", "The chosen design is not proven to meet the target",
                          design.verification_sentence()))
        elif (design.verification or {}).get("converged") is False:
            items.append(("design", "The choice's verification stopped on its budget", design.verification_sentence()))
    val = out.results.validation
    missed = "" if val is None else val.disagreement()
    if missed:
        strict = int(val.differs_at_95().sum())
        also = (f"; the 95 % test of the difference rejects {strict} levels" if strict > (~val.agreement).sum()
                else "")
        items.append(("validation", "The true model disagrees with the curve",
                      f"at {int((~val.agreement).sum())} of {len(val.agreement)} levels "
                      f"({missed.removeprefix('not at ')}){_paired_at_missed(val)}{also}; the levels share the "
                      f"validation's {val.n_samples:,} samples, so they are not independent checks"))
    elif val is not None and val.differs_at_95().any():
        items.append(("validation", "The curve passes the lenient check only",
                      f"its 95 % interval overlaps the true model's at every level, but "
                      f"{val.differences_at_95()}: the curve's error estimate there is smaller than its error"))
    items += _life_validation_caveats(out)
    rows = [f'<li><a href="#{e(sid)}"><strong>{e(title)}</strong></a>: {e(sentence.rstrip("."))}.</li>'
            for sid, title, sentence in items]
    missed = None if rel is None else curve_misses_life(rel, wear)  # markup already
    if missed:
        rows.append(f'<li><a href="#reliability"><strong>The curve misses the life</strong></a>: {missed}</li>')
    if not rows:
        return ""
    what = "this caveat" if len(rows) == 1 else "these caveats"
    return f'<div class="warn"><strong>Read these numbers with {what}</strong><ul>{"".join(rows)}</ul></div>'


def files_section(out: StudyOutputs) -> str:
    rows = []
    for p in out.files:
        try:
            st = p.stat()
        except OSError:
            continue
        mtime = _dt.datetime.fromtimestamp(st.st_mtime, _dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        rows.append((str(p.relative_to(out.out_dir)), f"{st.st_size:,} bytes", mtime))
    html = table(["file", "size", "modified"], rows, cls="kv") if rows else missing("No study files were found.")
    return html + "".join(missing(msg) for msg in out.errors.values())
