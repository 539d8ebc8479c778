"""The typed result of the design stage (``design.json``, ``design_pareto.csv``, ``design_candidates.csv``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from jointwear.study.reliability_results import SurrogateFit
from jointwear.study.stage_result import StageResult

#: share of a candidate's population outside the study's inputs beyond which its estimate is called extrapolated
EXTRAPOLATED_SHARE = 0.05
#: relative nugget (noise variance over process variance) from which a verification's model is read as scattering
#: from call to call: noise sd 1 % of the process's; the noise grid's floor (1e-8) is what a noise-free model fits
SCATTER_NUGGET = 1e-4


#: a candidate's values at each target other than the headline, beside the headline's (key + target_suffix(k))
OTHER_TARGET_KEYS = ("reliability_at_target_life", "reliability_error", "life_at_target_cycles")


def target_suffix(k: int) -> str:
    """The suffix of target ``k``'s (0-based) columns beside the headline's: '_t2' for the second target."""
    return f"_t{k + 1}"


def verification_verdict(reliability: float, error: float, target: float) -> str:
    """'meets' when R(N*) - error >= R*, 'within_error' when only R(N*) + error >= R*, else 'misses'."""
    if reliability - error >= target:
        return "meets"
    return "within_error" if reliability + error >= target else "misses"


def every_target_verification_text(checked: dict) -> str:
    """A verification at several targets as a reader reads it: 'verified at every target on the true model: R(N*) =
    0.9412 +- 0.0087 (meets), 0.9871 +- 0.0040 (within_error): not proven at every target'."""
    parts = ", ".join(f"{r:.4f} +- {e:.4f} ({v})" for r, e, v in zip(checked["reliability_at_target_life"],
                                                                   checked["error"], checked["verdicts"]))
    verdict = {"meets": "meets every target", "within_error": "not proven at every target",
               "misses": "refuted: misses a target"}[checked["verdict"]]
    return f"verified at every target on the true model: R(N*) = {parts}: {verdict}"


def choices_text(choices: dict) -> str:
    """A candidate's options as a reader reads them: 'l1 IT10, fit H7/g6, HB_b hardened'."""
    return ", ".join(f"{k} {v}" for k, v in choices.items())


def life_interval_text(row: dict) -> str:
    """A row's life at R* with its 95 % interval: '40,135 (39,210-41,060)' (an unknown end as '?')."""
    life = row.get("life_at_target_cycles")
    if life is None:
        return "-"
    low, high = row.get("life_at_target_low_cycles"), row.get("life_at_target_high_cycles")
    if low is None and high is None:
        return f"{life:,.0f}"
    return (f"{life:,.0f} ({'?' if low is None else format(low, ',.0f')}-"
            f"{'?' if high is None else format(high, ',.0f')})")


def is_undecided(reliability: float, target: float, surrogate_error: float, outside_fraction: float) -> bool:
    """Whether a candidate's R(N*) lies within the surrogate's error of R* (the share of its population outside the
    study's inputs added, as that mass may be misclassified wholesale): only refinement calls can settle it."""
    return abs(reliability - target) <= surrogate_error + outside_fraction


@dataclass(repr=False, eq=False)  # StageResult compares by value
class DesignResult(StageResult):
    """The cheapest controls that reach N* cycles at reliability R*, and the Pareto front of cost vs life at R*.

    ``chosen`` and every ``pareto`` row: ``choices`` (control -> option), ``cost`` (relative), the life at R*
    (``life_at_target_cycles``) and R(N*) (``reliability_at_target_life``) on the study's surrogate, with its
    error bound ``reliability_error`` (the surrogate's ESC bound, plus the exact 95 % Monte Carlo half-width, plus
    the share of the population outside the study design's region, which the surrogate may misclassify) and the
    share of the candidate's population outside the study design's region (``outside_design_fraction``).
    ``verification``: the chosen design's own AK-MCS study on the true model at N* (``reliability_at_target_life``,
    ``error``, ``model_calls``, ``confirmed``: R + error >= R*, i.e. not refuted; ``verdict`` 'meets' when
    R - error >= R*). ``model_calls``: the distinct true-model inputs the design rests on (study, refinement and
    verification; ``calls`` splits them). ``targets``: the same for every target (the first is the headline).
    ``chosen_every_target``: with several targets, the cheapest candidate that meets all of them at once (its R(N*)
    and error per target, in their order; None with one target or when none does), which a drawing needs; each
    target's own choice may miss the others. ``baseline_choices`` and ``baseline_cost``: today's design (the study's
    own distributions) as options of the controls and its cost, None when some control has no option of the study's
    distribution (``baseline_unmatched`` names them). ``life_resolution``: the relative half-width of the study's own
    life interval at R*; a dearer candidate enters the Pareto front only when its life at R* exceeds the best cheaper
    one's by more than that. ``refuted``: the choices whose verification missed the headline target (``choices``,
    ``cost``, the verified ``reliability_at_target_life`` and ``error``), each left out of the search from then on;
    ``no_choice_reason`` says why there is no choice. ``decision_rule``: ``design.require``, the rule that chose
    ('not_refuted' or 'proven'); under 'proven', ``unproven`` lists the candidates whose verification straddled R*
    (passed over up the front, as ``refuted``) and ``unverified_next`` the front point the verification budget did
    not reach (a candidate row; None when none). Every candidate and front row also has the 95 % interval of its
    life at R* (``life_at_target_low_cycles``, ``life_at_target_high_cycles``), every front row ``step_resolved``
    (its interval wholly above the previous point's), and with several targets each further target's
    ``reliability_at_target_life``, ``reliability_error`` and ``life_at_target_cycles`` with the suffix ``_t2``,
    ``_t3``, ... (:func:`target_suffix`).
    """

    FILE: ClassVar[str] = "design.json"

    target_life_cycles: float
    target_reliability: float
    chosen: dict | None
    pareto: list[dict]
    verification: dict | None
    model_calls: int
    wall_seconds: float
    baseline_life_cycles: float | None = None
    baseline_reliability_at_target_life: float | None = None  # today's design (the study's inputs) on the surrogate
    baseline_reliability_error: float | None = None  # its error bound, as a candidate's reliability_error
    life_factor: float | None = None
    baseline_life_interval: list[float] | None = None  # the study's 95 % interval of baseline_life_cycles
    targets: list[dict] = field(default_factory=list)
    controls: list[dict] = field(default_factory=list)
    candidates: list[dict] = field(default_factory=list)
    calls: dict = field(default_factory=dict)
    refinement: dict = field(default_factory=dict)
    n_population: int = 0
    n_candidates: int = 0
    provenance: dict = field(default_factory=dict)
    chosen_every_target: dict | None = None
    study_curve_cycles: list[float] = field(default_factory=list)  # first and last level of the study's R(N)
    baseline_choices: dict | None = None  # today's design as options of the controls (None: not among them)
    baseline_cost: float | None = None
    baseline_unmatched: list[str] = field(default_factory=list)  # controls with no option of the study's distribution
    life_resolution: float = 0.0  # relative: a dearer candidate enters the front only beyond it
    refuted: list[dict] = field(default_factory=list)  # choices their verification refuted, left out of the search
    decision_rule: str = "not_refuted"  # design.require: what the verification must say of the headline choice
    unproven: list[dict] = field(default_factory=list)  # require = 'proven': candidates verified 'within_error'
    unverified_next: dict | None = None  # require = 'proven': the next front point, left unverified by the budget

    def target_outside_curve_sentence(self) -> str:
        """A target life outside the study's R(N) curve (empty when inside, or unknown): the learning refined the
        surrogate near the curve's levels, so a life far from them is judged where it was not refined."""
        if len(self.study_curve_cycles) != 2:
            return ""
        lo, hi = self.study_curve_cycles
        n_star = self.target_life_cycles
        if lo <= n_star <= hi:
            return ""
        side = "below" if n_star < lo else "beyond"
        return (f"the target life {n_star:,.0f} cycles lies {side} the study's R(N) curve ({lo:,.0f} to {hi:,.0f} "
                "cycles), where its learning did not refine the surrogate: the candidates' R(N*) there is less sure "
                "than its error says; move reliability.cycles_start / cycles_stop to cover it and run the study again")

    @property
    def feasible(self) -> bool:
        """Whether some candidate reaches the headline target on the surrogate."""
        return self.chosen is not None

    @property
    def no_choice_reason(self) -> str | None:
        """Why there is no choice: 'unproven' (require = 'proven': no candidate's verification met the target beyond
        its error within the budget), 'refuted' (every candidate that reached the target on the surrogate was refuted
        by its own verification), 'unreached' (none reached it on the surrogate); None with a choice."""
        if self.chosen is not None:
            return None
        if self.decision_rule == "proven" and (self.unproven or self.unverified_next is not None):
            return "unproven"
        return "refuted" if self.refuted else "unreached"

    def no_choice_sentence(self) -> str:
        """Why there is no choice, with the nearest candidate when none reached the target ('' with a choice)."""
        reason = self.no_choice_reason
        if reason is None:
            return ""
        if reason == "unproven":
            return self._unproven_no_choice_sentence()
        if reason == "refuted":
            n = len(self.refuted)
            each = "; ".join(f"{choices_text(r['choices'])} (cost {r['cost']:.4g}: R(N*) = "
                             f"{r['reliability_at_target_life']:.4f} +/- {r['error']:.4f})" for r in self.refuted)
            return (f"no choice is left that its verification did not refute: the {n} candidate"
                    f"{'' if n == 1 else 's'} that reached {self.target_life_cycles:,.0f} cycles at "
                    f"R = {self.target_reliability:g} on the surrogate missed it on the true model ({each}), and no "
                    "other candidate reaches it on the surrogate: relax the target, or add options that reach it")
        nearest = self.nearest_sentence()
        return (f"no candidate reaches the target on the surrogate ({self.target_life_cycles:,.0f} cycles at "
                f"R = {self.target_reliability:g})" + (f"; {nearest}" if nearest else ""))

    def _unproven_no_choice_sentence(self) -> str:
        """No choice under require = 'proven': which candidates were not proven, and why the walk up the front
        stopped."""
        text = (f"no candidate is proven to meet {self.target_life_cycles:,.0f} cycles at R = "
                f"{self.target_reliability:g} (design.require = 'proven')")
        if self.unproven:
            each = "; ".join(f"{choices_text(r['choices'])} (cost {r['cost']:.4g}: R(N*) = "
                             f"{r['reliability_at_target_life']:.4f} +/- {r['error']:.4f})" for r in self.unproven)
            text += f": the verification of {each} straddles R*"
        nxt = self.unverified_next
        if nxt is not None:
            text += (f"; the verification budget ran out before {choices_text(nxt['choices'])} (cost "
                     f"{nxt['cost']:.4g}, R(N*) {nxt['reliability_at_target_life']:.4f} +/- "
                     f"{nxt['reliability_error']:.4f} on the surrogate) was verified: raise "
                     "design.verification_total_max_calls and run again with --resume (resume=True in Python)")
        else:
            text += "; no dearer point of the Pareto front reaches the target on the surrogate"
        return (text + "; or take the cheapest design its verification does not refute, told as not proven, with "
                "design.require = 'not_refuted'")

    def change_sentence(self) -> str:
        """What the choice changes against today's design and what that costs, or why today's design cannot be
        compared ('' without a choice)."""
        chosen = self.chosen
        if chosen is None:
            return ""
        if self.baseline_choices is None:
            which = " and ".join(self.baseline_unmatched) or "some control"
            return (f"today's design is not among the candidates ({which}: the study's distribution is none of the "
                    "options), so the change in cost is not known")
        changes = [f"{k} {v} -> {chosen['choices'][k]}" for k, v in self.baseline_choices.items()
                   if chosen["choices"].get(k) != v]
        today = (f"today's design ({choices_text(self.baseline_choices)}, cost "
                 f"{self.baseline_cost:.4g}" + ("" if self.baseline_reliability_at_target_life is None
                                                else f", R(N*) {self.baseline_reliability_text()}") + ")")
        if not changes:
            return f"{today} is the choice: it meets the target as it is"
        return f"against {today}: cost {self.cost_change:+.4g}; changes {', '.join(changes)}"

    def baseline_reliability_text(self) -> str:
        """Today's R(N*) with its error bound when known ('0.8234 +- 0.0123'; '' without it)."""
        r = self.baseline_reliability_at_target_life
        if r is None:
            return ""
        err = self.baseline_reliability_error
        return f"{r:.4f}" + ("" if err is None else f" +- {err:.4f}")

    @property
    def cost_change(self) -> float | None:
        """The choice's cost less today's design's (None without either)."""
        if self.chosen is None or self.baseline_cost is None:
            return None
        return self.chosen["cost"] - self.baseline_cost

    def every_target_sentence(self) -> str:
        """With several targets, when the headline choice misses one: the cheapest design that meets them all at once
        (its R(N*) and error per target on the surrogate, and its verification at every target when it ran), or that
        none does; '' otherwise."""
        every = self.chosen_every_target
        if len(self.targets) < 2 or self.chosen is None or (every is not None
                                                             and every["choices"] == self.chosen["choices"]):
            return ""
        if every is None:
            return "no candidate meets every target at once"
        errors = ", ".join(f"{r:.4f} +/- {err:.4f}" for r, err in zip(every["reliability_at_target_life"],
                                                                     every["reliability_error"]))
        checked = every.get("verification")
        told = ("only the headline choice is verified on the true model" if checked is None
                else every_target_verification_text(checked))
        return (f"the cheapest design that meets every target at once: {choices_text(every['choices'])} (cost "
                f"{every['cost']:.4g}; R(N*) {errors} at the targets in order, on the surrogate); {told}")

    def every_target_check_sentence(self) -> str:
        """With several targets, when the headline choice meets them all on the surrogate and was verified at every
        target (its own verification checks the first only): that verification; '' otherwise."""
        every = self.chosen_every_target
        if (len(self.targets) < 2 or self.chosen is None or every is None or every["choices"] != self.chosen["choices"]
                or every.get("verification") is None):
            return ""
        checked = every_target_verification_text(every["verification"])
        return f"the choice meets every target on the surrogate; {checked}"

    def _nearest_rows(self) -> tuple[dict, dict] | None:
        """With no choice: (the cheapest candidate whose R(N*) the surrogate does not tell from the highest, their
        difference within the sum of their error estimates; the highest), refuted candidates left out; else None."""
        refuted = [r["choices"] for r in self.refuted]
        rows = [r for r in self.candidates if r.get("reliability_at_target_life") is not None
                and r["choices"] not in refuted]  # a refuted candidate's surrogate estimate is known to be wrong
        if self.chosen is not None or not rows:
            return None
        top = max(rows, key=lambda r: (r["reliability_at_target_life"], -r["cost"]))

        def level_with_top(r: dict) -> bool:
            gap = top["reliability_at_target_life"] - r["reliability_at_target_life"]
            return gap <= (top.get("reliability_error") or 0.0) + (r.get("reliability_error") or 0.0)

        best = min((r for r in rows if level_with_top(r)), key=lambda r: (r["cost"], -r["reliability_at_target_life"]))
        return best, top

    @property
    def nearest(self) -> dict | None:
        """With no choice, the candidate :meth:`nearest_sentence` names: its ``choices``, ``cost``,
        ``reliability_at_target_life`` and ``reliability_error`` on the surrogate; None with a choice. With no choice
        under require = 'proven' ('unproven'), the candidate not proven whose verified R(N*) minus its error is the
        highest, with its verified R(N*) and error."""
        if self.no_choice_reason == "unproven" and self.unproven:
            best = max(self.unproven, key=lambda r: r["reliability_at_target_life"] - r["error"])
            return {"choices": best["choices"], "cost": best["cost"],
                    "reliability_at_target_life": best["reliability_at_target_life"],
                    "reliability_error": best["error"]}
        found = self._nearest_rows()
        if found is None:
            return None
        return {k: found[0].get(k) for k in ("choices", "cost", "reliability_at_target_life", "reliability_error")}

    def to_json(self) -> dict:
        """The fields, and why there is no choice with the nearest candidate (both null with a choice; read back
        from the fields they derive from)."""
        return {**super().to_json(), "no_choice_reason": self.no_choice_reason, "nearest": self.nearest}

    def nearest_sentence(self) -> str:
        """With no choice: the cheapest candidate whose R(N*) the surrogate does not tell from the highest (their
        difference within the sum of their error estimates), '' otherwise. The strictly highest R could cost 2.4 more
        for a gain of 0.003 against errors of 0.04."""
        found = self._nearest_rows()
        if found is None:
            return ""
        best, top = found
        text = (f"the nearest is {choices_text(best['choices'])} (cost {best['cost']:.4g}): R = "
                f"{best['reliability_at_target_life']:.4f} +/- {best['reliability_error']:.4f} at "
                f"{self.target_life_cycles:,.0f} cycles")
        if best is not top:
            text += (f", as near as the highest, {choices_text(top['choices'])} (cost {top['cost']:.4g}, R = "
                     f"{top['reliability_at_target_life']:.4f} +/- {top['reliability_error']:.4f}), within their "
                     "errors")
        return text

    def undecided_sentence(self) -> str:
        """What candidates left undecided by the refinement mean for the choice (empty when none was left, or when
        only the choice itself was and its verification met the target beyond its error)."""
        ref = self.refinement or {}
        n = int(ref.get("undecided_left") or 0)
        if not n:
            return ""
        others = int(ref.get("undecided_other_than_choice", n))
        if not others:  # only the choice: its verification on the true model settles it
            if self.verdict() == "meets":
                return ""
            return ("the choice's R(N*) on the surrogate lies within its error of the target, and only its "
                    "verification on the true model can settle that"
                    + (" (it was not verified)" if self.verdict() == "not_verified" else " (its verdict above)"))
        start = ("no refinement was allowed (design.refine_max_calls = 0)" if ref.get("budget") == 0
                 else "the refinement's budget (design.refine_max_calls) ran out")
        text = (f"{start} with {others} candidate(s) no dearer than the choice still undecided (their estimate's "
                "error spans the target): a cheaper one may meet it; raise design.refine_max_calls and run again "
                "with --resume (resume=True in Python)")
        return text + self._unresolvable()

    def _unresolvable(self) -> str:
        """'; but the cheapest of them, ..., lies closer to R* than its population resolves ...' when more
        refinement calls cannot settle the cheapest undecided candidate ('' otherwise)."""
        from jointwear.design.search import monte_carlo_half_width

        chosen, r_star, n = self.chosen, self.target_reliability, self.n_population
        if chosen is None or not n:
            return ""
        refuted = [r["choices"] for r in self.refuted]  # out of the search: not undecided
        left = [r for r in self.candidates if r["cost"] <= chosen["cost"] and r["choices"] != chosen["choices"]
                and r["choices"] not in refuted and r.get("surrogate_error") is not None
                and is_undecided(r["reliability_at_target_life"], r_star, r["surrogate_error"],
                              r.get("outside_design_fraction") or 0.0)]
        if not left:
            return ""
        row = min(left, key=lambda r: r["cost"])
        gap = abs(row["reliability_at_target_life"] - r_star)
        resolution = monte_carlo_half_width(r_star * n, n)
        if gap >= resolution:
            return ""
        return (f"; but the cheapest of them ({choices_text(row['choices'])}, cost {row['cost']:.4g}, R(N*) "
                f"{row['reliability_at_target_life']:.4f}) lies {gap:.2g} from R*, closer than its population of "
                f"{n:,} resolves (+/- {resolution:.2g}): more calls cannot settle it; judge it by a reliability "
                "study of that design")

    def verdict(self) -> str | None:
        """The verification's verdict on the choice: 'meets' (R(N*) - error >= R*), 'within_error' (only
        R(N*) + error >= R*), 'misses', 'not_verified'; None without a choice."""
        ver = self.verification
        if self.chosen is None or ver is None:
            return None if self.chosen is None else "not_verified"
        r, err = ver.get("reliability_at_target_life"), ver.get("error")
        if r is None or err is None:
            return "not_verified"
        return verification_verdict(r, err, self.target_reliability)

    def verification_sentence(self) -> str:
        """What the verification says of the choice, in words (empty without a choice)."""
        verdict, ver = self.verdict(), self.verification or {}
        if verdict is None:
            return ""
        if verdict == "not_verified":
            why = f" ({ver['note']})" if ver.get("note") else ""
            return f"the choice is not verified on the true model{why}: its R(N*) rests on the study's surrogate alone"
        rounds = ver.get("rounds") or []
        calls = f"{ver.get('model_calls', 0)} true-model calls"
        if len(rounds) > 1:  # model_calls counts every round's; the choice's own study is the last round
            calls = f"{rounds[-1].get('model_calls', 0)} true-model calls; {calls} in the {len(rounds)} verifications"
        text = (f"{self.rule_sentence()}: its own reliability study ({calls}) gives R(N*) = "
                f"{ver['reliability_at_target_life']:.4f} +/- {ver['error']:.4f}: ")
        text += {"meets": "it meets R* beyond its error",
                 "within_error": f"R* = {self.target_reliability:g} lies within its error, so the target is not "
                                 "excluded, nor proven",
                 "misses": f"it misses R* = {self.target_reliability:g}"}[verdict]
        fit = SurrogateFit.from_json(ver.get("surrogate_fit"))
        if ver.get("converged") is False:
            text += ("; its learning stopped on its budget of calls (design.verification_max_calls) before its "
                     "tolerance, so its error is the estimate of a Kriging that has not met its own stopping rule and "
                     "may be too small")
            if fit is None or fit.relative_nugget < SCATTER_NUGGET:
                text += " (raise the budget and run again with --resume to settle it)"
            else:  # the nugget keeps U low near the limit state: the rule (min U >= 2) may not hold at any budget
                text += (f". On this model a call's life scatters by about {100 * fit.life_scatter:.2g} % about what "
                         "the inputs set, so the learning's stopping rule may hold at no budget, and more calls narrow "
                         "the error only slowly")
                if verdict == "within_error":
                    gap = abs(ver["reliability_at_target_life"] - self.target_reliability)
                    text += (f"; the verdict is limited by that scatter: R(N*) lies {gap:.2g} from R*, and a larger "
                             "budget (--resume) settles it only if the error falls below that distance")
        if fit is not None and (warning := fit.warning()):  # its R(N*) may be far off, more than its error says
            text += "; in that study " + warning
        return text

    def rule_sentence(self) -> str:
        """Which rule chose (``design.require``), and under 'proven' the candidates it passed over as not proven."""
        if self.decision_rule != "proven":
            return "chosen by design.require = 'not_refuted' (the cheapest that its verification does not refute)"
        text = "chosen by design.require = 'proven' (the cheapest up the front that its verification proves)"
        if self.unproven:
            each = "; ".join(f"{choices_text(r['choices'])}, cost {r['cost']:.4g}: R(N*) = "
                             f"{r['reliability_at_target_life']:.4f} +/- {r['error']:.4f}" for r in self.unproven)
            text += f" after {len(self.unproven)} not proven ({each})"
        return text

    def margin_choice(self) -> dict | None:
        """The first point of the Pareto front dearer than the choice whose surrogate R(N*) minus its error clears R*
        (refuted candidates left out): the cheapest design with margin on the front; None without a choice or such a
        point."""
        chosen = self.chosen
        if chosen is None:
            return None
        refuted = [r["choices"] for r in self.refuted]
        return next((r for r in self.pareto if r["cost"] >= chosen["cost"] and r["choices"] != chosen["choices"]
                     and r["choices"] not in refuted and r.get("reliability_error") is not None
                     and r["reliability_at_target_life"] - r["reliability_error"] >= self.target_reliability), None)

    def relative_target_sentence(self) -> str:
        """Where N* is ``life_factor`` times the study's own life at R*: the range N* inherits from that life's 95 %
        interval, and what to do for a contractual target; '' for a target given in cycles."""
        if not self.life_factor or self.baseline_life_cycles is None:
            return ""
        text = (f"the target N* = {self.life_factor:g} x today's life at R = {self.target_reliability:g} "
                f"({self.baseline_life_cycles:,.0f} cycles, the study's estimate)")
        if self.baseline_life_interval:
            low, high = (self.life_factor * v for v in self.baseline_life_interval)
            text += f" carries that life's 95 % interval: N* is {low:,.0f}-{high:,.0f} cycles within it"
        return (text + "; for a contractual target, check today's life with jointwear validate or give "
                "design.targets.life_cycles")

    def unproven_sentence(self) -> str:
        """When the verification's verdict is 'within_error': that the choice is not proven to meet R* by the true
        model, and the cheapest design with margin (:meth:`margin_choice`); '' otherwise."""
        if self.verdict() != "within_error":
            return ""
        ver = self.verification
        text = (f"not proven: the true model's R(N*) = {ver['reliability_at_target_life']:.4f} +- {ver['error']:.4f} "
                f"straddles R* = {self.target_reliability:g}")
        margin = self.margin_choice()
        rule = "; design.require = 'proven' chooses the cheapest design its verification proves"
        if margin is None:
            return text + "; no dearer design on the Pareto front clears R* by its error on the surrogate" + rule
        return (text + f"; the cheapest design with margin is {choices_text(margin['choices'])} (cost "
                f"{margin['cost']:.4g}, R(N*) {margin['reliability_at_target_life']:.4f} +- "
                f"{margin['reliability_error']:.4f} on the surrogate, not verified)" + rule)

    def tables(self) -> dict[str, dict[str, Any]]:
        """``design_pareto`` (the front) and ``design_candidates`` (every candidate): each control's choice, the
        cost, the life at the target reliability with its 95 % interval and the reliability at the target life with
        its error (the front: whether each step up it is resolved), then each further target's R(N*), its error and
        life at R* (suffix ``_t2``, ...); and ``design_pareto_t2``, ... (each further target's own front)."""
        names = [c["name"] for c in self.controls]
        base = ("cost", "life_at_target_cycles", "life_at_target_low_cycles", "life_at_target_high_cycles",
                "reliability_at_target_life", "reliability_error", "outside_design_fraction")
        others = tuple(f"{key}{target_suffix(k)}" for k in range(1, len(self.targets)) for key in OTHER_TARGET_KEYS)

        def table(rows: list[dict], keys: tuple[str, ...]) -> dict[str, list]:
            cols = {n: [r["choices"][n] for r in rows] for n in names}
            cols.update({key: [r.get(key) for r in rows] for key in keys})
            return cols

        out = {"design_pareto": table(self.pareto, base + ("step_resolved",) + others),
               "design_candidates": table(self.candidates, base + others)}
        for k in range(1, len(self.targets)):
            out[f"design_pareto{target_suffix(k)}"] = table(self.targets[k].get("pareto") or [],
                                                             base + ("step_resolved",))
        return out

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``design.json``, the front and every candidate (:meth:`tables`) and the front's figure."""
        folder = Path(folder)
        self.write_tables(folder)
        if figures and self.pareto:
            from jointwear.report.design_section import design_pareto_figure
            from jointwear.report.style import savefig

            savefig(design_pareto_figure(self), folder / "design_pareto.png")
        return self.write(folder)  # last: a result whose JSON is there is whole
