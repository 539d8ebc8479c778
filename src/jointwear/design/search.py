"""Uncertainty control: the cheapest combination of controls that reaches a target life at a target reliability.

Method (docs/design.md):

1. The study's reliability stage has learned the log wear life ln N_f(x) on a design of true-model calls.
   A Kriging of ln N_f is fitted on that design in the study's standard-normal space u.
2. Every candidate (one option per control) is the same model under other input distributions. Its
   population is drawn with common random numbers (the same standard-normal draws z for every candidate,
   x = T_cand^-1(z)) and mapped to the study's u, where the surrogate predicts ln N_f with its variance.
   R(N*) is the share of the population with ln N_f > ln N*; the life at R* is the (1 - R*) quantile of the
   predicted life. The surrogate's error on R(N*) is the ESC bound (Wang & Shafieezadeh 2019) over the
   candidate's population; points outside the study design's region show up there as large Kriging variance.
3. Refinement: a candidate decides the answer when it is no dearer than the current choice and its R(N*) is
   within its error of R*. For such candidates, the population point with the lowest U = |mu - ln N*| / sigma
   (Echard et al. 2011) is run with the true model and the Kriging refitted, until no candidate is undecided
   or the budget ends.
4. The Pareto front is the set of candidates that no cheaper candidate matches in life at R*; the choice is
   the cheapest candidate with R(N*) >= R*. It is verified by its own AK-MCS study on the true model at N*.
5. A choice its verification refutes (verdict 'misses') is out of the search for the headline target from then on:
   its calls join the surrogate and the next cheapest candidate is chosen and verified, until one is not refuted,
   the verification budget ends, or no candidate is left that was not refuted (``DesignResult.no_choice_reason``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Container
from dataclasses import dataclass

import numpy as np

from jointwear.design.candidates import (
    Candidate,
    Control,
    build_controls,
    changes_from,
    enumerate_candidates,
    today_candidate,
    today_picks,
)
from jointwear.design.results import (
    EXTRAPOLATED_SHARE,
    OTHER_TARGET_KEYS,
    DesignResult,
    choices_text,
    is_undecided,
    target_suffix,
    verification_verdict,
)
from jointwear.design.settings import DesignSettings
from jointwear.reliability import (
    IsoTransform,
    KrigingSurrogate,
    SeriesSurrogate,
    akmcs_multi,
    esc_absolute_error,
    failure_probability,
)
from jointwear.study.reliability import (
    POSTERIOR_POINTS,
    StudyContext,
    archard_trend_unused,
    kriging_options,
    life_offset,
    life_scatter_sd,
    life_trend,
    surrogate_pf_error,
)
from jointwear.study.reliability_results import SurrogateFit
from jointwear.study.validation import clopper_pearson

_Z95 = 1.959963984540054


@dataclass
class Estimate:
    """A candidate's reliability at N* and life at R* on the surrogate."""

    reliability: float
    error: float  # surrogate (ESC) bound + Monte Carlo 95 % half-width + share outside the design, absolute, on R
    surrogate_error: float
    life_cycles: float | None
    outside_fraction: float
    # the life at R*'s 95 % interval: where R -/+ its error bound at that life crosses R* (None: outside the population)
    life_low: float | None = None
    life_high: float | None = None


def monte_carlo_half_width(k: float, n: int) -> float:
    """The larger side of the exact (Clopper-Pearson) 95 % interval of a proportion k / n: unlike the normal
    approximation it is not 0 when every sample lies on one side (R = 1 of 10 samples: 0.31). ``k`` may be an
    expected count (a sum of survival probabilities), whose estimate varies less than a count's: the bound is then
    conservative."""
    lo, hi = clopper_pearson(k, n)
    return max(k / n - lo, hi - k / n)


class LifeSurrogate:
    """Kriging of ln N_f(x) on the true-model design, in the study's standard-normal space; one per judged joint
    when the study learns its life so (:class:`~jointwear.reliability.SeriesSurrogate`)."""

    def __init__(self, ctx: StudyContext, design_x: np.ndarray, seed: int):
        self.ctx = ctx
        self.iso = IsoTransform(ctx.marginals)
        self.seed = seed
        self.estimate_nugget = ctx.config.reliability.noise == "estimate"
        self.x = np.atleast_2d(np.asarray(design_x, dtype=float))
        self.fit()

    def fit(self) -> None:
        u = self.iso.to_u(self.x)
        lives = self.ctx.log_joint_lives(self.x)
        with np.errstate(invalid="ignore"):
            y = lives.min(axis=1)
        ok = np.isfinite(y) & np.all(np.isfinite(u), axis=1)
        self.u_design = u[ok]
        self.lo, self.hi = self.u_design.min(axis=0), self.u_design.max(axis=0)
        if self.per_joint:
            self.model = SeriesSurrogate(lives.shape[1], seed=self.seed, **kriging_options(self.ctx.config)).fit(
                u[ok], lives[ok])
        else:
            self.model = KrigingSurrogate(seed=self.seed, offset=life_offset(self.ctx, self.iso),
                                          **kriging_options(self.ctx.config)).fit(u[ok], y[ok])

    @property
    def per_joint(self) -> bool:
        """Whether the life is learnt one Kriging per judged joint (as the study learns it)."""
        return self.ctx.per_joint

    def add(self, x_new: np.ndarray) -> None:
        self.x = np.vstack([self.x, np.atleast_2d(x_new)])
        self.fit()

    def predict(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        mu, var = self.model.predict(u)
        return mu, np.sqrt(np.maximum(var, 0.0))

    @property
    def scatter_sd(self) -> float:
        """The call-to-call scatter of ln N_f the Kriging estimated as its noise (0 without a noise estimate), which
        a candidate's R(N*) integrates as the study's R(N) does (docs/reliability.md, 'A noisy model')."""
        return self.model.noise_sd if self.estimate_nugget else 0.0

    def outside(self, u: np.ndarray) -> np.ndarray:
        """Rows outside the box spanned by the design (the surrogate extrapolates there)."""
        return np.any((u < self.lo) | (u > self.hi), axis=1)


class CandidateSpace:
    """Candidates' populations in the study's u space, built column by column (each option sets its own
    variables' columns, so a column is computed once per option, not once per candidate)."""

    def __init__(self, ctx: StudyContext, controls: list[Control], n: int, seed: int):
        self.ctx, self.controls = ctx, controls
        self.names = list(ctx.names)
        self.z = np.random.default_rng(seed).standard_normal((n, len(self.names)))
        # each row's draw of the life's call-to-call scatter (common to every candidate, as z is)
        self.scatter = np.random.default_rng(seed + 1).standard_normal(n)
        self._seed = seed
        self._scatter_joints: np.ndarray | None = None
        self.base_iso = IsoTransform(ctx.marginals)
        self.base_x = self.base_iso.to_x(self.z)
        self.base_u = self.z
        self._cols: dict = {}

    def scatter_draws(self, n_joints: int) -> np.ndarray:
        """Each row's draws of every judged joint's scatter, shape (n, n_joints): the first joint's is
        :attr:`scatter`, so that one joint draws as before (common to every candidate)."""
        if n_joints == 1:
            return self.scatter[:, None]
        if self._scatter_joints is None or self._scatter_joints.shape[1] != n_joints - 1:
            self._scatter_joints = np.random.default_rng(self._seed + 2).standard_normal(
                (self.scatter.size, n_joints - 1))
        return np.column_stack([self.scatter, self._scatter_joints])

    def _column(self, k: int, j: int, var: str):
        key = (k, j, var)
        if key not in self._cols:
            i = self.names.index(var)
            dist = self.controls[k].options[j].marginals[var]
            x = IsoTransform([dist]).to_x(self.z[:, i:i + 1])
            u = IsoTransform([self.ctx.marginals[i]]).to_u(x)
            self._cols[key] = (i, x[:, 0], u[:, 0])
        return self._cols[key]

    def population(self, cand: Candidate) -> tuple[np.ndarray, np.ndarray]:
        """(x, u): the candidate's population in physical space and in the study's u space."""
        x, u = self.base_x.copy(), self.base_u.copy()
        for k, j in enumerate(cand.picks):
            for var in self.controls[k].options[j].marginals:
                i, xc, uc = self._column(k, j, var)
                x[:, i], u[:, i] = xc, uc
        return x, u

    @property
    def p_inf_default(self) -> float:
        """The study's own share of failed assemblies (its fits, 'fail' rule)."""
        return self.ctx.config.uncertainty.infeasible_probability()

    def infeasible_probability(self, cand: Candidate) -> float:
        return cand.infeasible_probability(self.controls, self.ctx.config.uncertainty)


def surviving(sur: LifeSurrogate, u: np.ndarray, mu: np.ndarray, log_target: float) -> float:
    """How many of the population points ``u`` (surrogate means ``mu`` of ln N_f) outlive the target: a count, or
    with the life's call-to-call scatter the expected count, a sum of probabilities (each judged joint its own)."""
    scatter = sur.scatter_sd
    if scatter == 0:
        return int(np.count_nonzero(mu > log_target))
    if sur.per_joint:
        return float(mu.size - sur.model.failure_probability(u, [log_target]).sum())
    return float(mu.size - failure_probability(mu - log_target, scatter).sum())


def estimate(space: CandidateSpace, sur: LifeSurrogate, cand: Candidate, log_target: float,
             reliability_target: float) -> Estimate:
    """R(N*) with its error bound, and the life at R*, of one candidate on the surrogate."""
    _, u = space.population(cand)
    return estimate_on(space, sur, u, space.infeasible_probability(cand), log_target, reliability_target)


def estimate_on(space: CandidateSpace, sur: LifeSurrogate, u: np.ndarray, p_inf: float, log_target: float,
                reliability_target: float) -> Estimate:
    """R(N*) with its error bound, and the life at R* with its 95 % interval, of the population ``u`` (a candidate's,
    or today's design's) whose clearance is infeasible with probability ``p_inf``."""
    mu, sd = sur.predict(u)
    outside = float(np.mean(sur.outside(u)))
    reliability, sur_err, error = _reliability_error(sur, u, mu, sd, p_inf, outside, log_target)
    scatter = sur.scatter_sd
    if scatter == 0:
        log_life = mu
    elif sur.per_joint:
        log_life = sur.model.response_draws(u, space.scatter_draws(len(sur.model.components)))
    else:
        log_life = mu + scatter * space.scatter

    def life_at(r: float) -> float | None:  # the life where the population's R is r (None outside it)
        level = 1.0 - r / (1.0 - p_inf)
        return float(np.exp(np.quantile(log_life, level))) if 0.0 < level < 1.0 else None

    life = life_at(reliability_target)
    low = high = None
    if life is not None:
        # the study's life interval, made for a candidate: the band R -/+ its error (its error read at the life itself,
        # where a dearer design's R(N*) error near 0 says nothing) crosses R* (docs/design.md, step 2)
        e_life = _reliability_error(sur, u, mu, sd, p_inf, outside, math.log(life))[2]
        low, high = life_at(reliability_target + e_life), life_at(reliability_target - e_life)
    return Estimate(reliability, error, sur_err, life, outside, low, high)


def _reliability_error(sur: LifeSurrogate, u: np.ndarray, mu: np.ndarray, sd: np.ndarray, p_inf: float,
                       outside: float, log_target: float) -> tuple[float, float, float]:
    """(R, the surrogate's ESC bound, the whole error bound) of the population ``u`` at ln N = ``log_target``."""
    n = mu.size
    k = surviving(sur, u, mu, log_target)
    # 'fail' rule: an infeasible clearance is a failure at every N (the learning runs on the feasible part)
    reliability = (1.0 - p_inf) * k / n
    sur_err = (1.0 - p_inf) * esc_absolute_error(mu - log_target, sd)  # Pf = P[g <= 0]: the same absolute error as R
    mc_err = (1.0 - p_inf) * monte_carlo_half_width(k, n)
    # the share drawn outside the design's region may be misclassified wholesale: the Kriging extrapolates there,
    # with a variance that need not say so (a far PTFE option read R = 1.0000 +/- 0.0000, its own study 0.9 at 1.8x)
    error = min(sur_err + mc_err + (1.0 - p_inf) * outside, 1.0)  # R is a probability: no error exceeds 1
    return reliability, sur_err, error


def _refine_point(space: CandidateSpace, sur: LifeSurrogate, cand: Candidate, log_target: float,
                  widen: bool = False) -> np.ndarray:
    """The population point of ``cand`` whose sign of ln N_f - ln N* is least certain (lowest U); with ``widen``, the
    least certain of those outside the design's box, which a point inside it would leave as they are (a candidate
    undecided only by the share of its population there, a loose grade's spread beyond the study's +-5 sigma)."""
    x, u = space.population(cand)
    mu, sd = sur.predict(u)
    with np.errstate(divide="ignore", invalid="ignore"):
        score = np.abs(mu - log_target) / sd
    score[~np.isfinite(score)] = np.inf
    if widen:
        outside = sur.outside(u)
        if outside.any():
            score = np.where(outside, score, np.inf)
    return x[int(np.argmin(score))]


def pareto_front(rows: list[dict], resolution: float = 0.0, keep: int | None = None) -> list[dict]:
    """Candidates that no cheaper (or equally cheap) candidate matches in life at R*, cheapest first, each living
    longer than the front's previous point by more than the relative ``resolution`` (the study's own life interval:
    a longer life within it is not resolved). A life read by extrapolation (more than
    ``EXTRAPOLATED_SHARE`` of the candidate's population outside the study's inputs) puts no candidate off the front:
    a well-estimated alternative stays on it beside the extrapolated one. ``rows[keep]`` (the choice) is on the
    front whatever its life: a front without it read as if the cheapest design that works were a dearer one."""
    front: list[dict] = []
    best, best_trusted = -math.inf, -math.inf  # the longest life of any cheaper candidate
    shown, shown_trusted = -math.inf, -math.inf  # the longest life on the front so far
    kept = None if keep is None else rows[keep]
    for row in sorted(rows, key=lambda r: (r["cost"], -(r["life_at_target_cycles"] or 0.0))):
        life = row["life_at_target_cycles"] or 0.0
        trusted = (row.get("outside_design_fraction") or 0.0) <= EXTRAPOLATED_SHARE
        dominated = life <= (best_trusted if trusted else best)
        resolved = life > (shown_trusted if trusted else shown) * (1.0 + resolution)
        if row is kept or (not dominated and resolved):
            front.append(dict(row, step_resolved=_step_resolved(front[-1] if front else None, row)))
            shown = max(shown, life)
            if trusted:
                shown_trusted = max(shown_trusted, life)
        best = max(best, life)
        if trusted:
            best_trusted = max(best_trusted, life)
    return front


def _step_resolved(previous: dict | None, row: dict) -> bool | None:
    """Whether ``row``'s life interval at R* lies wholly above ``previous``'s (the step up the front is then resolved
    by the surrogate's own error of the two lives); None for the first point or where an end is unknown."""
    if previous is None:
        return None
    low, high = row.get("life_at_target_low_cycles"), previous.get("life_at_target_high_cycles")
    if low is None or high is None:
        return None
    return bool(low > high)


def _row(cand: Candidate, controls: list[Control], est: Estimate) -> dict:
    return {"choices": cand.choices(controls), "cost": cand.cost(controls),
            "life_at_target_cycles": est.life_cycles, "life_at_target_low_cycles": est.life_low,
            "life_at_target_high_cycles": est.life_high, "reliability_at_target_life": est.reliability,
            "reliability_error": est.error, "surrogate_error": est.surrogate_error,
            "outside_design_fraction": est.outside_fraction}


def life_resolution(reliability_result, target: float) -> float:
    """The relative half-width of the study's own 95 % life interval at ``target`` (0 where the curve does not give
    it): the resolution of a life at R* on this surrogate."""
    life = reliability_result.life(target)
    low, high = reliability_result.life_interval(target)
    if life is None or low is None or high is None or life <= 0:
        return 0.0
    return float((high - low) / (2.0 * life))


def baseline_life(ctx: StudyContext, reliability_result, target: float, space: CandidateSpace,
                  sur: LifeSurrogate) -> float | None:
    """Today's life at R*: the study's R(N) curve where it reaches R*, else the surrogate's quantile."""
    life = reliability_result.life(target)
    if life is not None:
        return float(life)
    mu, _ = sur.predict(space.base_u)
    level = 1.0 - target / (1.0 - space.p_inf_default)
    return float(np.exp(np.quantile(mu, level))) if 0.0 < level < 1.0 else None


def run_design(ctx: StudyContext, reliability_result, settings: DesignSettings | None = None, *,
               echo: Callable[[str], None] | None = None,
               on_phase: Callable[[str, int | None], None] | None = None) -> DesignResult:
    """The cheapest controls meeting each target and, with several, every target at once; the Pareto front of cost
    vs life at R*; and the verification of the headline target's choice (see the module docstring). ``on_phase``
    (description, budget of calls) is told when the refinement and each verification start (the progress display)."""
    t0 = time.perf_counter()
    settings = settings if settings is not None else ctx.config.design
    say = echo if echo is not None else (lambda _m: None)
    calls_before, made_before = ctx.n_evaluated, ctx.n_model_calls
    controls = build_controls(ctx.config, settings)
    space = CandidateSpace(ctx, controls, settings.n_population, settings.seed)
    sur = LifeSurrogate(ctx, np.asarray(reliability_result.design_x, dtype=float), seed=settings.seed)
    study_points = int(sur.x.shape[0])

    targets = []
    for t in settings.targets:
        base = baseline_life(ctx, reliability_result, t.reliability, space, sur)
        if t.life_cycles is not None:
            life = float(t.life_cycles)
        elif base is None:
            from jointwear.schema import ConfigError

            raise ConfigError(f"design.targets: life_factor needs the study's life at R = {t.reliability:g}, "
                              "which the R(N) curve does not reach (give life_cycles instead)")
        else:
            life = t.life_factor * base
        interval = list(reliability_result.life_interval(t.reliability))  # [None, None] off the curve
        targets.append({"reliability": float(t.reliability), "life_cycles": life, "log_life": math.log(life),
                        "life_factor": t.life_factor, "baseline_life_cycles": base,
                        "baseline_life_interval": interval if None not in interval else None})

    candidates = list(enumerate_candidates(controls))
    # equal costs (to rounding: the same option costs summed in another order) rank by the fewest changes from
    # today's design; _cheapest_meeting then prefers the highest R(N*) - error among them (docs/design.md, step 4)
    today = today_picks(controls, ctx.config.uncertainty)
    rank = [(round(c.cost(controls), 9), changes_from(c, today)) for c in candidates]
    order = sorted(range(len(candidates)), key=rank.__getitem__)

    def evaluate_all(indices) -> dict:
        return {(i, k): estimate(space, sur, candidates[i], t["log_life"], t["reliability"])
                for i in indices for k, t in enumerate(targets)}

    refuted: set[int] = set()  # candidates whose verification missed the headline target: never chosen for it again
    # require = 'proven': candidates whose verification straddled R* ('within_error'); the search walks up the front
    # past them (docs/design.md, 'Requiring a proven choice')
    unproven: set[int] = set()
    proven = settings.require == "proven"
    head_resolution = life_resolution(reliability_result, targets[0]["reliability"])

    def excluded(k: int, est: dict) -> set[int]:
        """The candidates out of the search for target ``k``: those refuted at the headline target and, under
        require = 'proven', those not proven and every candidate whose life at R* is not resolved above theirs
        (the next point of the front is the cheapest candidate left)."""
        if k != 0:
            return set()
        if not unproven:
            return refuted
        floor = max(est[(i, 0)].life_cycles or 0.0 for i in unproven) * (1.0 + head_resolution)
        return refuted | unproven | {i for i in range(len(candidates)) if (est[(i, 0)].life_cycles or 0.0) <= floor}

    def undecided(est: dict) -> list[tuple[int, int]]:
        """(candidate, target) pairs no dearer than the target's current choice whose R(N*) is within the
        surrogate's error of R* (the Monte Carlo part of the error is not reduced by model calls)."""
        out = []
        for k, t in enumerate(targets):
            out_k = excluded(k, est)
            chosen_i = _cheapest_meeting(est, order, k, t["reliability"], out_k, rank)
            chosen_cost = math.inf if chosen_i is None else rank[chosen_i][0]
            for i in order:
                if rank[i][0] > chosen_cost:
                    break
                if i in out_k:
                    continue
                e = est[(i, k)]
                if is_undecided(e.reliability, t["reliability"], e.surrogate_error, e.outside_fraction):
                    out.append((i, k))
        return out

    def _relevant(est: dict) -> list[int]:
        """Candidates no dearer than the dearest current choice (the only ones a refinement can change)."""
        limit = 0.0
        for k, t in enumerate(targets):
            chosen_i = _cheapest_meeting(est, order, k, t["reliability"], excluded(k, est), rank)
            limit = max(limit, math.inf if chosen_i is None else candidates[chosen_i].cost(controls))
        return [i for i in order if candidates[i].cost(controls) <= limit]

    est = evaluate_all(range(len(candidates)))
    # the budget counts the points asked for: a point the store already holds (a failed call, a resumed run) costs
    # no new call, and counting only new calls let a refinement that kept asking for it loop without end
    refine_calls, refine_points, iterations, verification_calls = 0, 0, 0, 0
    verifications: list[dict] = []
    verified: dict[int, dict] = {}
    phase = on_phase if on_phase is not None else (lambda _d, _n: None)
    total_budget = settings.verification_budget
    while True:
        todo = undecided(est) if refine_points < settings.refine_max_calls else []
        if todo:
            phase("design refinement", settings.refine_max_calls - refine_points)
        while refine_points < settings.refine_max_calls and todo:
            picks, seen = [], set()
            for i, k in todo:
                if i in seen:
                    continue
                seen.add(i)
                e = est[(i, k)]  # undecided by its outside share alone: widen the box rather than refine inside it
                widen = abs(e.reliability - targets[k]["reliability"]) > e.surrogate_error
                picks.append(_refine_point(space, sur, candidates[i], targets[k]["log_life"], widen=widen))
                if len(picks) >= min(settings.batch_size, settings.refine_max_calls - refine_points):
                    break
            before = ctx.n_evaluated
            x_new = np.vstack(picks)
            ctx.log_life(x_new)  # true-model calls (through the evaluator and the evaluation store)
            refine_calls += max(ctx.n_evaluated - before, 0)
            refine_points += x_new.shape[0]
            sur.add(x_new)
            iterations += 1
            est.update(evaluate_all(_relevant(est) if len(candidates) > 2000 else range(len(candidates))))
            left_now = undecided(est)  # the count after the round's calls (the log said the count before it)
            say(f"design: refinement {iterations}: {len(todo)} undecided before it, {len(left_now)} after; "
                f"{refine_calls} call{'' if refine_calls == 1 else 's'}")
            todo = left_now
        if len(candidates) > 2000:
            est = evaluate_all(range(len(candidates)))
        head_i = _cheapest_meeting(est, order, 0, targets[0]["reliability"], excluded(0, est), rank)
        budget = min(settings.verification_max_calls, total_budget - verification_calls)
        if not settings.verify or head_i is None or head_i in verified or budget <= 0:
            break
        say(f"design: verifying {choices_text(candidates[head_i].choices(controls))} with its own reliability study")
        phase("design verification", budget)
        ver, x_ver = verify(ctx, candidates[head_i], controls, space, targets[0], budget, settings.seed,
                            settings.verification_stopping)
        verification_calls += ver["new_model_calls"]
        ver["choices"] = candidates[head_i].choices(controls)
        verified[head_i] = ver
        verifications.append(ver)
        if ver["verdict"] == "meets" or (ver["confirmed"] and not proven):
            break
        if ver["confirmed"]:  # 'within_error' under require = 'proven': verify the next point of the front
            unproven.add(head_i)  # its calls do not refute the surrogate, which stays as it is
            say(f"design: {choices_text(ver['choices'])} is not proven (R(N*) = {ver['reliability_at_target_life']:.4f}"
                f" +/- {ver['error']:.4f} straddles R* = {targets[0]['reliability']:g}); design.require = 'proven': "
                "the next point of the front")
            continue
        # Refuted: the candidate leaves the search for the headline target (its surrogate estimate may still meet it
        # after the few calls below, and it was chosen again), the verification's true calls enter the life
        # surrogate and the search runs again.
        refuted.add(head_i)
        sur.add(x_ver)
        est = evaluate_all(range(len(candidates)))
    left = undecided(est)

    pending = None  # require = 'proven': the candidate the walk reached but could not verify (budget spent)
    per_target = []
    rows_of = [[_row(candidates[i], controls, est[(i, k)]) for i in range(len(candidates))]
               for k in range(len(targets))]
    for k in range(1, len(targets)):  # the other targets beside the headline's, in its candidates and front
        for row, other in zip(rows_of[0], rows_of[k]):
            row.update({f"{key}{target_suffix(k)}": other[key] for key in OTHER_TARGET_KEYS})
    for k, t in enumerate(targets):
        rows = rows_of[k]
        resolution = life_resolution(reliability_result, t["reliability"])
        chosen_i = _cheapest_meeting(est, order, k, t["reliability"], excluded(k, est), rank)
        if k == 0 and proven and chosen_i is not None and verified.get(chosen_i, {}).get("verdict") != "meets":
            pending, chosen_i = chosen_i, None  # not proven: under this rule no choice
        chosen = None
        if chosen_i is not None:
            chosen = _row(candidates[chosen_i], controls, est[(chosen_i, k)])
            chosen["distributions"] = candidates[chosen_i].distributions(controls)
        per_target.append({"target_life_cycles": t["life_cycles"], "target_reliability": t["reliability"],
                           "life_factor": t["life_factor"], "baseline_life_cycles": t["baseline_life_cycles"],
                           "baseline_life_interval": t["baseline_life_interval"],
                           "chosen": chosen, "chosen_index": chosen_i,
                           "pareto": pareto_front(rows, resolution, keep=chosen_i),
                           "life_resolution": resolution, "rows": rows,
                           "undecided": sum(1 for _, kk in left if kk == k)})

    every, every_calls = None, 0
    if len(targets) > 1:  # a drawing must meet every target at once: the cheapest candidate that does
        both = _cheapest(order, lambda i: i not in refuted and all(est[(i, k)].reliability >= t["reliability"]
                                                                   for k, t in enumerate(targets)),
                         lambda i: est[(i, 0)].reliability - est[(i, 0)].error, rank)
        if both is not None:
            every = {"choices": candidates[both].choices(controls), "cost": candidates[both].cost(controls),
                     "reliability_at_target_life": [est[(both, k)].reliability for k in range(len(targets))],
                     "reliability_error": [est[(both, k)].error for k in range(len(targets))]}
        if every is not None and settings.verify and settings.verify_every_target and settings.verification_max_calls:
            say(f"design: verifying {choices_text(every['choices'])} at every target with its own reliability study")
            phase("design verification, every target", settings.verification_max_calls)
            every["verification"] = every_target_verification(
                verify_targets(ctx, candidates[both], controls, space, targets, settings.verification_max_calls,
                               settings.seed, settings.verification_stopping)[0])
            every_calls = every["verification"]["new_model_calls"]
    head = per_target[0]
    verification = verified.get(head["chosen_index"]) if head["chosen_index"] is not None else None
    if verification is not None:
        verification = dict(verification, model_calls=verification_calls, rounds=verifications)
    elif head["chosen_index"] is None and proven and (unproven or pending is not None):
        note = ("no point of the front above the candidates not proven reaches the target on the surrogate"
                if pending is None else f"verification budget spent before "
                f"{choices_text(candidates[pending].choices(controls))} was verified")
        last = verifications[-1] if verifications else {"reliability_at_target_life": None, "error": None,
                                                        "confirmed": False, "verdict": "not_verified"}
        verification = dict(last, model_calls=verification_calls, rounds=verifications, note=note)
    elif head["chosen_index"] is None and refuted:  # every candidate that met the target was refuted
        verification = dict(verifications[-1], model_calls=verification_calls, rounds=verifications,
                            note="no candidate left that its verification did not refute")
    elif verifications:  # the budget ended before the latest choice could be verified
        verification = {"reliability_at_target_life": None, "error": None, "model_calls": verification_calls,
                        "confirmed": False, "verdict": "not_verified", "rounds": verifications,
                        "note": "verification budget spent before the final choice was verified"}
    elif head["chosen_index"] is not None:
        reason = "design.verify = false" if not settings.verify else "design.verification_max_calls = 0"
        verification = {"reliability_at_target_life": None, "error": None, "model_calls": 0, "confirmed": False,
                        "verdict": "not_verified", "rounds": [], "note": reason}
    others = [i for i, k in left if k == 0 and i != head["chosen_index"]]
    # today's design (the study's own distributions) on the final surrogate, for comparison with the choice
    # read as every candidate is (with the life's scatter and its error bound), so that the two compare
    today = estimate_on(space, sur, space.base_u, space.p_inf_default, targets[0]["log_life"],
                        targets[0]["reliability"])
    # the inputs the design rests on; the session's other stages (sensitivity, validation) evaluated more
    total_calls = study_points + refine_calls + verification_calls + every_calls
    today_cand, unmatched = today_candidate(controls, ctx.config.uncertainty)
    return DesignResult(
        target_life_cycles=head["target_life_cycles"], target_reliability=head["target_reliability"],
        chosen=head["chosen"], pareto=head["pareto"], verification=verification,
        model_calls=int(total_calls),
        wall_seconds=time.perf_counter() - t0,
        baseline_life_cycles=head["baseline_life_cycles"], life_factor=head["life_factor"],
        baseline_life_interval=head["baseline_life_interval"],
        baseline_reliability_at_target_life=today.reliability, baseline_reliability_error=today.error,
        targets=[{k: v for k, v in row.items() if k not in ("rows", "chosen_index")} for row in per_target],
        controls=[c.to_json() for c in controls], candidates=head["rows"],
        calls={"study": study_points, "refinement": int(refine_calls),
               "verification": int(verification_calls + every_calls),
               "new_in_this_stage": int(ctx.n_evaluated - calls_before),
               "run_now": int(ctx.n_model_calls - made_before)},
        refinement={"iterations": iterations, "model_calls": int(refine_calls),
                    "undecided_left": len(left), "undecided_other_than_choice": len(others),
                    "budget": int(settings.refine_max_calls), "design_points": int(sur.x.shape[0])},
        n_population=settings.n_population, n_candidates=len(candidates), chosen_every_target=every,
        study_curve_cycles=[float(np.min(reliability_result.cycles)), float(np.max(reliability_result.cycles))]
        if len(reliability_result.cycles) else [],
        baseline_choices=None if today_cand is None else today_cand.choices(controls),
        baseline_cost=None if today_cand is None else today_cand.cost(controls), baseline_unmatched=unmatched,
        life_resolution=head["life_resolution"],
        refuted=[{"choices": v["choices"], "cost": candidates[i].cost(controls),
                  "reliability_at_target_life": v["reliability_at_target_life"], "error": v["error"]}
                 for i, v in verified.items() if i in refuted],
        decision_rule=settings.require,
        unproven=[{"choices": v["choices"], "cost": candidates[i].cost(controls),
                   "reliability_at_target_life": v["reliability_at_target_life"], "error": v["error"]}
                  for i, v in verified.items() if i in unproven],
        unverified_next=None if pending is None else _row(candidates[pending], controls, est[(pending, 0)]))


def _cheapest_meeting(est: dict, order: list[int], k: int, reliability: float,
                      excluded: Container[int] = (), rank: list | None = None) -> int | None:
    """The cheapest candidate outside ``excluded`` whose R(N*) on the surrogate meets target ``k``; of several tied
    in ``rank``, the one with the highest R(N*) - error."""
    return _cheapest(order, lambda i: i not in excluded and est[(i, k)].reliability >= reliability,
                     lambda i: est[(i, k)].reliability - est[(i, k)].error, rank)


def _cheapest(order: list[int], ok: Callable[[int], bool], margin: Callable[[int], float],
              rank: list | None = None) -> int | None:
    """The first candidate of ``order`` that is ``ok`` and, of those ``ok`` that ``rank`` ties with it (equal cost and
    changes from today's design: ``order`` is sorted by ``rank``), the one of the highest ``margin`` (the first of
    equal margins)."""
    it = iter(order)
    first = next((i for i in it if ok(i)), None)
    if first is None or rank is None:
        return first
    best = first
    for i in it:
        if rank[i] != rank[first]:
            break
        if ok(i) and margin(i) > margin(best):
            best = i
    return best


def every_target_verification(verdicts: list[dict]) -> dict:
    """One verification at several targets as one record: per target (in order) its R(N*), error and verdict; the
    overall verdict the worst of them ('misses' before 'within_error' before 'meets'); the shared counts once."""
    worst = min((v["verdict"] for v in verdicts), key=["misses", "within_error", "meets"].index)
    return {"verdict": worst, "confirmed": worst != "misses",
            "verdicts": [v["verdict"] for v in verdicts],
            "reliability_at_target_life": [v["reliability_at_target_life"] for v in verdicts],
            "error": [v["error"] for v in verdicts],
            **{key: verdicts[0][key] for key in ("model_calls", "new_model_calls", "run_now", "n_mc", "converged",
                                                  "failed_calls", "surrogate_fit")}}


def verify(ctx: StudyContext, cand: Candidate, controls: list[Control], space: CandidateSpace, target: dict,
           max_calls: int, seed: int, stopping: str = "u") -> tuple[dict, np.ndarray]:
    """The chosen design's own reliability study at N*: AK-MCS on the true model (through the study's evaluator
    and store) with the candidate's input distributions and the study's reliability settings (one Kriging per judged
    joint when the study learns its life so). Returns the verdict and the study's design points (true-model inputs).

    Its initial design has at least 2 d + 2 points (the engine's default, Echard et al. 2011) even where the
    study's own is smaller: with fewer points than about twice the dimension, the Kriging variance after a
    maximum-likelihood fit can be too small for the error bound to be trusted.
    """
    verdicts, x = verify_targets(ctx, cand, controls, space, [target], max_calls, seed, stopping)
    return verdicts[0], x


def verify_targets(ctx: StudyContext, cand: Candidate, controls: list[Control], space: CandidateSpace,
                   targets: list[dict], max_calls: int, seed: int,
                   stopping: str = "u") -> tuple[list[dict], np.ndarray]:
    """:func:`verify` at every target's N* at once (one AK-MCS learning all their levels): one verdict per target,
    in their order, each with the study's shared counts, and the study's design points."""
    rel = ctx.config.reliability
    marginals = cand.marginals(controls, ctx.names, ctx.marginals)
    before, made_before = ctx.n_evaluated, ctx.n_model_calls
    n_initial = min(max(rel.n_initial, 2 * len(marginals) + 2), max_calls)
    g, system = ctx.learnt_response
    eng = akmcs_multi(
        g, marginals, levels=np.array([t["log_life"] for t in targets]), system=system, n_mc=rel.n_mc,
        n_mc_max=rel.n_mc_max, n_initial=n_initial, batch_size=rel.batch_size, u_threshold=rel.u_threshold,
        cov_target=rel.cov_target, pf_floor=rel.pf_floor, max_calls=max_calls,
        seed=rel.seed + 17 + seed, stopping=stopping, error_tol=rel.error_tol, hold_iterations=rel.hold_iterations,
        error_abs_tol=rel.error_abs_tol, kriging=kriging_options(ctx.config), trend=life_trend(ctx))
    p_inf = space.infeasible_probability(cand)
    pf_feasible = np.asarray(eng.pf, dtype=float)
    cov = np.asarray(eng.cov, dtype=float)
    scatter = life_scatter_sd(ctx, eng)
    if scatter > 0:  # the life's call-to-call scatter, integrated as the study's R(N) does
        rng = np.random.default_rng(seed + 23)
        pf_arr, cov_arr = eng.estimate_on(lambda m, start: rng.standard_normal((m, len(marginals))), eng.n_mc,
                                          noise_sd=scatter)
        pf_feasible, cov = np.asarray(pf_arr, dtype=float), np.asarray(cov_arr, dtype=float)
    # the bound: the surrogate's own absolute error (the larger of ESC's and its posterior spread, as the study's
    # band) plus the 95 % Monte Carlo half-width
    u_posterior = np.random.default_rng(seed + 29).standard_normal((POSTERIOR_POINTS, len(marginals)))
    sur_errs = np.asarray(surrogate_pf_error(eng, u_posterior, scatter, seed + 31), dtype=float)
    fit = SurrogateFit.of(eng.response_surrogate, archard_trend_hint=archard_trend_unused(ctx)).to_json()
    verdicts = []
    for k, target in enumerate(targets):
        pf_k, cov_k = float(pf_feasible[k]), float(cov[k])
        pf = p_inf + (1.0 - p_inf) * pf_k
        sur_err = (1.0 - p_inf) * float(sur_errs[k])
        mc_err = _Z95 * (1.0 - p_inf) * (cov_k * pf_k if math.isfinite(cov_k) else 0.0)
        reliability = 1.0 - pf
        error = sur_err + mc_err
        verdict = verification_verdict(reliability, error, target["reliability"])
        verdicts.append({
            "reliability_at_target_life": reliability, "error": error,
            # new_model_calls: the inputs it added to the design (its budget counts them, so a resumed run replays
            # the same rounds); run_now: the calls it made in this process, the rest read back from the store
            "model_calls": int(eng.n_calls), "new_model_calls": int(ctx.n_evaluated - before),
            "run_now": int(ctx.n_model_calls - made_before),
            "confirmed": verdict != "misses", "verdict": verdict,
            "meets_target_without_error": bool(reliability >= target["reliability"]),
            "pf_cov": cov_k, "surrogate_error": sur_err, "n_mc": int(eng.n_mc), "converged": bool(eng.converged),
            "failed_calls": int(eng.n_failed_calls), "surrogate_fit": fit})
    return verdicts, np.asarray(eng.design_x, dtype=float)


__all__ = ["run_design", "verify", "verify_targets", "estimate", "LifeSurrogate", "CandidateSpace", "Estimate"]
