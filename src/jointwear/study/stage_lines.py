"""The one-line texts the study's stages print (and the report reuses): forces, wear, lives, why a learning stopped,
the sensitivity's rankings."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from jointwear.reliability import cov_population
from jointwear.study.limit_state import OUTSIDE_CURVE, nominal_lives
from jointwear.study.reliability_results import ReliabilityCurve, SensitivityResult, interval_text
from jointwear.study.results import SimulationSummary, WearSummary
from jointwear.wear.angles import angle_text


def learning_stop_line(res: ReliabilityCurve, settings) -> str:
    """What an unconverged learning means for the curve: why it stopped, the surrogate's largest error estimate of R
    against the tolerance of the stopping rule, and what to do."""
    worst = res.largest_error()
    rule = (f"tolerance {settings.error_abs_tol:g} in R or {settings.error_tol * 100:.3g} % of Pf"
            if settings.stopping == "error"
            else f"the learning's rule is min U >= {settings.u_threshold:g} at every level, stopping = 'u'")
    error = "" if worst is None else (
        f"; the surrogate's error estimate of R reaches {worst[0]:.3f} at {worst[1]:,.0f} cycles ({rule})")
    cov = res.largest_cov()
    if cov is not None and cov >= settings.cov_target:  # the criterion left when the surrogate's error is met
        error += f"; the COV of Pf reaches {cov:.3g} (target {settings.cov_target:g})"
    reason = res.learning_stop or "not converged"
    if res.stopped_by_budget:
        advice = ("; raise reliability.max_calls and run again with --resume (resume=True in Python) to continue it "
                  "(the calls made are read back)")
    elif "n_mc_max" in reason:
        unmet = [float(p) for p, c, waived in zip(res.pf, res.pf_cov, res.below_floor)  # not those pf_floor waives
                 if p > 0 and c >= settings.cov_target and not waived]
        need = "" if not unmet else (
            f"; a COV of {settings.cov_target:g} at Pf = {min(unmet):.3g} needs about "
            f"{cov_population(min(unmet), settings.cov_target):,.0f} samples")
        return (f"the Monte Carlo population reached its maximum before the COV of Pf met its target ({reason})"
                f"{error}{need}; raise reliability.n_mc_max (a larger population costs no model call), or raise "
                "reliability.pf_floor above that Pf if so small a Pf need not be known that well")
    else:
        advice = ""
    if res.stopped_while_confirming:
        return f"the learning's stopping rule held but was not yet confirmed when it stopped ({reason}){error}{advice}"
    return f"the learning stopped before its stopping rule was met ({reason}){error}{advice}"


def error_tolerances(res: ReliabilityCurve, settings) -> np.ndarray:
    """Each level's tolerance of the 'error' rule as it reads it: ``error_abs_tol`` in R or ``error_tol`` of Pf,
    the larger."""
    return np.maximum(settings.error_abs_tol, settings.error_tol * np.asarray(res.pf, dtype=float))


def posterior_error_line(res: ReliabilityCurve, settings) -> str:
    """A learning that met its error rule while its error estimate with the Kriging's posterior exceeds the rule's
    tolerance: the rule reads ESC's part alone (docs/reliability.md, "The surrogate's error of R(N)"), so
    'converged' does not say the whole estimate met it; '' otherwise."""
    if settings is None or not res.converged or settings.stopping != "error" or res.pf_error_esc is None:
        return ""
    error = np.asarray(res.pf_error, dtype=float)
    tolerance = error_tolerances(res, settings)  # over the counted levels
    counted = np.isfinite(error) & ~np.asarray(res.below_floor, dtype=bool)
    ratio = np.where(counted, error / tolerance, -np.inf)
    k = int(np.argmax(ratio)) if ratio.size else 0
    if not ratio.size or not ratio[k] > 1.0:
        return ""
    return (f"the learning met its rule on ESC's error of R (tolerance {settings.error_abs_tol:g} in R or "
            f"{settings.error_tol * 100:.3g} % of Pf), but its error estimate with the Kriging's posterior reaches "
            f"{error[k]:.3f} at {res.cycles[k]:,.0f} cycles, {ratio[k]:.2g} times the tolerance there; the R(N) "
            "band and the life's interval carry it, and both are the surrogate's own estimate, which `jointwear "
            "validate` checks against the true model")


def linear_trend_hint(trend: str | None) -> str:
    """The cure to name where a validation finds the learnt life beyond its interval: '' where the study already
    learns with the linear trend (docs/reliability.md, "The learnt life's spread")."""
    if trend == "linear":
        return ""
    return ("try reliability.trend = \"linear\" (a linear trend under the Kriging, which a constant trend otherwise "
            "bends around) and validate again: it took such an error away on the slider-crank, default and six-bar "
            "presets, but not on every model")


def curve_misses_life_line(rel: ReliabilityCurve, wear: WearSummary | None,
                           code: Callable[[str], str] = str) -> str | None:
    """Why and how to move an R(N) curve that does not contain the life at its headline target (the life table
    says 'before_curve' or 'beyond_curve'), or None when it does. Where the judged quantity is the bearing's max
    depth, the nominal design's own crossing of the allowance (its wear history; the first judged joint to cross
    it) says where to put the curve. ``code`` marks a setting's name (the report's markup)."""
    row = rel.life_row()
    status = None if row is None else row.get("status")
    if status not in ("before_curve", "beyond_curve") or rel.cycles.size == 0:
        return None
    if status == "before_curve":
        text = (f"The life at R = {rel.target:g} lies before this curve: R = {rel.reliability[0]:.3f} already at "
                f"its first level ({rel.cycles[0]:,.0f} cycles). Lower {code('reliability.cycles_start')}")
    else:
        text = (f"The life at R = {rel.target:g} lies beyond this curve: R = {rel.reliability[-1]:.3f} still at "
                f"its last level ({rel.cycles[-1]:,.0f} cycles). Raise {code('reliability.cycles_stop')}")
    judged = {str(j.get("name")): j.get("allowance_mm") for j in rel.joints}
    lives = {} if wear is None or None in judged.values() else nominal_lives(wear.joints, judged, rel.quantity)
    if rel.quantity == "bearing_max_depth" and judged and len(lives) == len(judged):
        crossing = min(lives.values())
        if crossing <= wear.cycles:  # inside the history: no extrapolation
            text += (f"; the nominal design reaches its allowance after about {crossing:,.0f} cycles (its wear "
                     "history), and the curve should hold that count")
        else:
            text += (f"; the nominal design stays below its allowance over its whole wear history "
                     f"({wear.cycles:,.0f} cycles)")
    return text + "."


def force_line(result: SimulationSummary) -> str:
    """'6.843 N', or each joint's when there are several: 'A 6.676 N, E 1.02 N' (the headline is the first's)."""
    def newtons(value: float | None) -> str:
        return f"{value if value is not None else float('nan'):.4g} N"

    if len(result.joints) <= 1:
        return newtons(result.contact_force_mean_N)
    return ", ".join(f"{j['name']} {newtons(j.get('contact_force_mean_N'))}" for j in result.joints)


def wear_line(result: WearSummary) -> str:
    """'0.0266 mm at 125 deg', or each joint's when there are several: 'A 0.0287 mm at 108 deg, E 0.0033 mm ...'."""
    def depth_at(depth: float, angle: float) -> str:
        return "0 mm (no wear)" if not depth else f"{depth:.3g} mm at {angle_text(angle)} deg"

    if len(result.joints) <= 1:
        return depth_at(result.max_wear_mm, result.max_wear_angle_deg)
    return ", ".join(f"{j['name']} {depth_at(j['max_wear_mm'], j['max_wear_angle_deg'])}" for j in result.joints)


def profile_mode_line(result: WearSummary) -> str:
    """In profile mode, whether uniform mode would have been fair here (the conformity indicator, docs/wear.md "When
    uniform mode is fair"); '' in uniform mode, which warns when it is outside its range. With several joints each is
    named: those past 1 when any is (as uniform mode's warning names them), else all."""
    if result.geometry_mode != "profile":
        return ""
    # the verdict is every joint's: one joint past 1 makes profile mode the answer to trust
    given = [(None, result.conformity)] if len(result.joints) < 2 else \
        [(j["name"], j.get("conformity")) for j in result.joints]
    measured = [(name, c) for name, c in given if c is not None and not math.isnan(c)]
    if not measured:
        return ""
    past = any(c > 1.0 for _, c in measured)
    values = ", ".join(f"{c:.3g}" + (f" at joint {name}" if name else "") for name, c in measured
                       if c > 1.0 or not past)
    if past:
        return (f"profile mode follows the worn shape here (conformity {values} > 1: the journal fits into its own "
                "wear, which uniform mode ignores): this is the answer to trust")
    return f"uniform mode would be fair here too (conformity {values} <= 1: the worn arc within the contact patch)"


#: a reliability budget projected to take longer than this (s of model calls in all) is told after the wear stage
LONG_BUDGET_SECONDS = 1800.0


def duration_text(seconds: float) -> str:
    """'45 s', '12 min', '3.4 h', '2.1 days'."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h" if seconds < 172_800 else f"{seconds / 86_400:.1f} days"


def budget_line(history_seconds: float, history_cycles: int, call_cycles: int, max_calls: int,
                sensitivity_calls: int = 0) -> str:
    """What the reliability budget (and the sensitivity stage's ``sensitivity_calls`` runs of the true model) may cost
    at the nominal history's pace, when more than ``LONG_BUDGET_SECONDS`` ('' else): a model call runs the same
    history to the curve's last level."""
    if history_cycles <= 0 or history_seconds <= 0:
        return ""
    per_call = history_seconds * call_cycles / history_cycles
    if per_call * (max_calls + sensitivity_calls) <= LONG_BUDGET_SECONDS:
        return ""
    sensitivity, settings = "", "reliability.max_calls"
    if sensitivity_calls:
        sensitivity = (f", and the sensitivity stage's {sensitivity_calls} runs of means shifted beyond the learned "
                       f"region up to {duration_text(per_call * sensitivity_calls)} more")
        settings += "; sensitivity.surrogate_shift_limit, sensitivity.factors"
    return (f"each model call of the reliability stage runs such a history to {call_cycles:,} cycles, about "
            f"{duration_text(per_call)} at this history's pace: its budget of {max_calls} calls may take up to "
            f"{duration_text(per_call * max_calls)} in all{sensitivity}, shared among the workers ({settings}; a long "
            "history per cycle is its dynamics: docs/dynamics.md, \"When the step size collapses\")")


#: steps per simulated cycle above which ``simulate`` names the friction law's stick branch as a likely cause:
#: 6x the heaviest shipped preset's (the six-bar, about 38,000; benchmarks/results/dynamics.json)
MANY_STEPS_PER_CYCLE = 250_000


def simulation_cost_line(steps_per_cycle: float, seconds_per_cycle: float, simulated_cycles: float | None,
                         history_cycles: int | None, max_calls: int | None) -> str:
    """What a wear history (one model call) may cost at the simulated cycles' pace ('' without a fixed-block
    history), and where a very stiff cycle usually comes from."""
    parts = []
    if simulated_cycles and history_cycles:
        per_call = seconds_per_cycle * simulated_cycles
        budget = (f"; the reliability budget of {max_calls} calls about {duration_text(per_call * max_calls)} of "
                  "computing, shared among the workers") if max_calls else ""
        parts.append(f"a wear history of {history_cycles:,} cycles (each model call) simulates {simulated_cycles:,.0f} "
                     f"cycles of dynamics: about {duration_text(per_call)} at this pace{budget}")
    if steps_per_cycle > MANY_STEPS_PER_CYCLE:
        parts.append(f"{steps_per_cycle:,.0f} steps a cycle is many: under large contact forces the friction law's "
                     "stick branch (slope about 1.5 mu_s F_N / v_s) usually sets the step; larger friction v_s and v_d "
                     "take fewer steps but change the wear: compare the two first (docs/dynamics.md, \"When the step "
                     "size collapses\")")
    return "; ".join(parts)


def reused_text(new: int, total: int) -> str:
    """' (3 new, 17 read back from the store)' when fewer than ``total`` calls ran now; '' when all did."""
    return f" ({new} new, {total - new} read back from the store)" if new < total else ""


def life_text(row: dict) -> str:
    """'377,433 cycles = 13.11 h (95 % interval 374,429-380,517 cycles)', or where the life lies when it is
    outside the curve."""
    if row["cycles"] is not None:
        interval = (f" ({interval_text(row['cycles_low'], row['cycles_high'])})"
                    if "cycles_low" in row and "cycles_high" in row else "")
        hours = row["hours"]  # a life of minutes keeps three figures: 0.0957 h, not 0.10 h
        shown = f"{hours:.2f}" if hours >= 1 else f"{hours:.3g}"
        return f"{row['cycles']:,.0f} cycles = {shown} h{interval}"
    where = OUTSIDE_CURVE.get(row.get("status"))
    return "not reached" if where is None else f"{where[0]} ({where[1]})"


def other_lives_line(res: ReliabilityCurve) -> str:
    """The lives at the targets after the headline, '' with one target: 'R = 0.99: 301,544 cycles = 10.47 h (95 %
    interval ...); R = 0.999: before the curve's first level (lower cycles_start)'."""
    return "; ".join(f"R = {row['target']:g}: {life_text(row)}" for row in res.life_table[1:])


#: fewer expected failures than this among the posterior's points leave its spread of Pf coarse at a target
POSTERIOR_TAIL_POINTS = 20


def posterior_tail_line(res: ReliabilityCurve, posterior_points: int) -> str:
    """'' unless a target's Pf = 1 - R leaves fewer than ``POSTERIOR_TAIL_POINTS`` expected failures among the
    ``posterior_points`` population points on which the Kriging's posterior spread of Pf is drawn (R = 0.999: 3 of
    3,000); then which targets, and that ESC's part of the interval, counted on the whole population, is the one to
    lean on there."""
    thin = [row["target"] for row in res.life_table if (1.0 - row["target"]) * posterior_points < POSTERIOR_TAIL_POINTS]
    if not thin:
        return ""
    shown = ", ".join(f"{t:g}" for t in thin)
    return (f"at R = {shown} the Kriging's posterior spread of Pf, one part of the life's interval, is drawn on "
            f"{posterior_points:,} population points of which about {(1.0 - min(thin)) * posterior_points:.2g} fail: "
            "that part is coarse there, and the interval rests on ESC's count over the whole population")


def variance_line(sens: SensitivityResult, floor: float = 0.01) -> str:
    """:meth:`SensitivityResult.variance_ranking` as text: 'c 0.95 > l1 0.04 (the others < 0.01)'."""
    ranked = sens.variance_ranking(floor)
    text = " > ".join(f"{name} {st:.2g}" for name, st in ranked)
    return f"{text} (the others < {floor:g})" if text and len(ranked) < len(sens.sobol.get("names") or []) else text


#: a nominal reliability closer than this to 0 or 1 leaves the mean-shift ranking to a handful of samples
EDGE_RELIABILITY = 0.01


def ranking_line(sens: SensitivityResult) -> str:
    """Per group, the variables by their effect on R, '~' between neighbours the surrogate's error does not
    separate (said once, after the last group): 'tolerance: l2 ~ lBC > l1 | bearing_material: k_b ~ HB_b > ...';
    'none: ...' where no shift moves R."""
    if not sens.shifts_move_reliability:
        return (f"none: no mean shift changes R at {sens.cycles:,} cycles (R = {sens.reliability_nominal:.3f} "
                "whatever the shift; put the R(N) curve where R passes the target, or set sensitivity.cycles)")
    ties = {(p["first"], p["second"]) for p in sens.unresolved_pairs}
    parts, tied = [], False
    for group, names in sens.ranking_by_group.items():
        text = names[0] if names else ""
        for a, b in zip(names, names[1:]):
            tied |= (a, b) in ties
            text += (" ~ " if (a, b) in ties else " > ") + b
        parts.append(f"{group}: {text}")
    if tied:
        parts[-1] += " (~: not told apart within the surrogate's error)"
    r0 = sens.reliability_nominal
    if not EDGE_RELIABILITY < r0 < 1.0 - EDGE_RELIABILITY:  # almost every sample fails (or none): a few decide
        largest = max((max(abs(v["reliability_low"] - r0), abs(v["reliability_high"] - r0)) for v in sens.variables),
                      default=0.0)
        parts.append(f"(read with care: R = {r0:.3f} at {sens.cycles:,} cycles, where the largest shift moves it by "
                     f"{largest:.2g}; set sensitivity.cycles where R passes the target)")
    return " | ".join(parts)
