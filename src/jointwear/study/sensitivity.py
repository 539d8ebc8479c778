"""The sensitivity stage: how the reliability moves with each random variable (paper Section 6.2.3)."""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from jointwear.reliability import Z95, esc_absolute_error, failure_probability
from jointwear.study.reliability import (
    POSTERIOR_DRAWS,
    StudyContext,
    WearSurrogates,
    archard_exponent,
    life_scatter_sd,
    population,
)
from jointwear.study.results import ReliabilityCurve, SensitivityResult

if TYPE_CHECKING:  # jointwear.sensitivity is imported on use (it loads SALib)
    from jointwear.sensitivity import MeanShiftResult, ReliabilityDerivatives

#: population points of the posterior spread of each shifted reliability: one Cholesky factor of m x m per shifted
#: population (m = 3000, the curve's, took ~1 s each). Fewer points add each point's own variance over m to the
#: spread, so the smaller sample errs wide in expectation (on a noisy two-joint study: 0.95 of the curve's at its level)
SHIFT_POSTERIOR_POINTS = 1000

#: inputs on which the call-to-call scatter's share of the wear's variance is read (its sampling error ~ 1 %)
SCATTER_SHARE_SAMPLES = 20_000

#: a random variable's target that is a drawn point's coordinate (mechanism...points.D.y, ground_points.C.x)
COORDINATE_TARGET = re.compile(r"(^|\.)(points|ground_points)\.[^.]+\.[xy]$")


def coordinate_shift_sentence(targets: dict[str, str], factors: tuple[float, float],
                              mechanism: dict | None = None) -> str:
    """For the random variables whose targets are drawn coordinates (name -> target): their mean shifts move a point
    by a share of its distance from the drawing's origin, not of a link, so their ranking depends on where the
    origin lies ('' when there is none). With the config's ``mechanism`` (SI, as dumped), a coordinate that scales
    a link is left out: its point on an axis through another point of its body at the origin (a crank O-A drawn
    from O = (0, 0) along x, toleranced as A.x)."""
    names = [name for name, target in targets.items() if COORDINATE_TARGET.search(str(target))
             and not (mechanism and scales_a_link(mechanism, str(target)))]
    if not names:
        return ""
    which = " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
    verb = "are coordinates" if len(names) > 1 else "is a coordinate"
    return (f"{which} {verb} of the drawing: each mean x {factors[0]:g} / x {factors[1]:g} moves its point by that "
            "share of its distance from the origin, not of a link's length, so its place in the mean-shift ranking "
            "depends on where the origin is drawn (the Sobol' ranking does not)")


def scales_a_link(mechanism: dict, target: str) -> bool:
    """Whether moving the drawn coordinate ``target`` by a factor scales the distance of its point from another point
    of the same body (or of the ground) that lies at the origin: the point's other coordinate is 0."""
    keys = target.split(".")
    try:
        if keys[1] == "ground_points":
            points, point, axis = mechanism["ground_points"], keys[2], keys[3]
        else:
            bodies = mechanism["bodies"]
            body = bodies[int(keys[2])] if keys[2].isdigit() else next(b for b in bodies if b.get("name") == keys[2])
            points, point, axis = body["points"], keys[4], keys[5]
        other = points[point][1 if axis == "x" else 0]
    except (KeyError, IndexError, StopIteration, TypeError, ValueError):
        return False
    return other == 0 and any(name != point and tuple(xy) == (0.0, 0.0) for name, xy in points.items())


def far_shift_calls(config) -> int:
    """The true-model calls the sensitivity stage makes (read back where the store holds them): one at each mean
    shifted further than ``sensitivity.surrogate_shift_limit`` standard deviations (the separable scaling rule of
    :func:`run_sensitivity`), and one at the nominal means when there is any."""
    unc, sens = config.uncertainty, config.sensitivity
    if unc is None:
        return 0
    far = sum(abs((factor - 1.0) * m.mean()) > sens.surrogate_shift_limit * m.std()
              for m in unc.marginals(feasible=True) for factor in sens.factors)
    return far + 1 if far else 0


def sensitivity_level(ctx: StudyContext, reliability: ReliabilityCurve) -> int:
    """The cycle count of the sensitivity study: the configured one, else the curve level whose reliability is
    nearest the (first) target reliability."""
    configured = ctx.config.sensitivity.cycles
    if configured is not None:
        return int(configured)
    r = np.asarray(reliability.reliability, dtype=float)
    return int(ctx.cycles[int(np.argmin(np.abs(r - reliability.target)))])


def physical_marginal(ctx: StudyContext, i: int, marginal):
    """A shifted clearance keeps its physical floor: the normal with the shifted mean truncated at the
    configured minimum (shifting the truncated law as a whole would move the truncation point with it, below the
    floor, to negative clearances, and read the surrogate far outside its design)."""
    clearance = ctx.config.uncertainty.clearance_named(ctx.names[i])
    if clearance is None or "loc" not in marginal.kwds:
        return marginal
    return clearance.model_copy(update={"mean": float(marginal.kwds["loc"])}).feasible()


def survival(margin: np.ndarray, scatter_sd: float) -> float:
    """R over a population from the life surrogate's margins ln N_f - ln N, the life's call-to-call scatter
    integrated as R(N) integrates it (``failure_probability``)."""
    return float(1.0 - np.mean(failure_probability(margin, scatter_sd)))


def archard_check(ctx: StudyContext, i: int, shifted, exponent: int, pop: np.ndarray, margin: np.ndarray,
                  margin_sd: np.ndarray, factor: float, r_surrogate: float, error: float, cycles: float,
                  learned: tuple[float, float], scatter_sd: float = 0.0,
                  posterior_error: Callable[[np.ndarray], float] | None = None) -> dict:
    """The shifted reliability by Archard's law, against the surrogate's (``scatter_sd``: the life's call-to-call
    scatter, integrated as R(N) integrates it; ``posterior_error(point_shifts)``: the 95 % spread of R over the
    Kriging's posterior with each nominal point's threshold moved by its shift, see :func:`run_sensitivity`).

    The judged depth is proportional to (k / H) of its body, so a sample whose variable i moves from x_i to
    x_i' (paired by quantile) has its life divided by (x_i' / x_i)^exponent; the life itself comes from the
    surrogate inside its design (the nominal population). Exact up to the feedback of the wear on the dynamics
    (the clearance growth), which the surrogate-based rule includes. Both readings carry the surrogate's error, each
    on its own population: its estimate (the shifted one's ``error``; the Archard one's from the nominal margin
    moved by the scaling, ``margin_sd`` unchanged), and never less than the accuracy the learning was asked for
    (``reliability.error_tol`` x Pf or ``error_abs_tol``), which the estimate can understate (on an analytic
    Archard model the true error at a learned level reached 3x the estimate, within that accuracy). They agree
    when they differ by less than the sum of the two plus the Monte Carlo noise of two populations of the same size.

    The scaling moves the limit state to the life ``cycles x factor^exponent``, and the surrogate is learned only
    around the curve's levels (``learned``: its first and last cycle counts); outside them its error estimate is
    not to be trusted, so the check is not made there (``consistent`` None, with the level it would need).
    """
    needed = cycles * factor**exponent
    out = {"variable": ctx.names[i], "factor": factor, "reliability_surrogate": r_surrogate,
           "life_level_needed": needed}
    if not learned[0] <= needed <= learned[1]:
        out["consistent"] = None
        out["note"] = (f"not checked: the Archard reading needs the life surrogate at {needed:,.0f} cycles, outside "
                       f"the learned curve ({learned[0]:,.0f}-{learned[1]:,.0f})")
        return out
    x = pop[:, i]
    x_shifted = shifted.ppf(np.clip(ctx.marginals[i].cdf(x), 1e-15, 1 - 1e-15))
    with np.errstate(divide="ignore", invalid="ignore"):
        moved = margin - exponent * np.log(x_shifted / x)
    r_exact = survival(moved, scatter_sd)
    error_archard = esc_absolute_error(moved, margin_sd)
    if posterior_error is not None:
        error_archard = max(error_archard, posterior_error(exponent * np.log(x_shifted / x)))
    rel = ctx.config.reliability

    def accuracy(r: float, estimate: float) -> float:
        return max(estimate, rel.error_tol * (1.0 - r), rel.error_abs_tol)

    noise = Z95 * math.sqrt(2.0 * max(r_exact * (1.0 - r_exact), 1e-12) / pop.shape[0])
    tolerance = accuracy(r_surrogate, error) + accuracy(r_exact, error_archard) + noise
    return out | {"reliability_archard": r_exact, "difference": r_surrogate - r_exact, "error_surrogate": error,
                  "error_archard": error_archard, "tolerance": tolerance,
                  "consistent": bool(abs(r_surrogate - r_exact) <= tolerance)}


def slope_contradicts_shifts(dr_dmean: float, dr_dmean_error: float, r_nominal: float,
                             r_shifted: tuple[float, float], errors: tuple[float, float],
                             shifted_means: tuple[float, float]) -> bool:
    """True when the local dR/dmu is resolved (|dR/dmu| > its 95 % error) and of the opposite sign to the trend of R
    between the shifted means (``r_shifted``, at ``shifted_means``): each shifted R beyond its error estimate from R
    nominal tells the trend's sign on its side, and one such side is enough unless the other tells the opposite (R
    not monotone over the shifts: no trend). The local slope then reads a scale finer than the shifts (a wear that
    is not smooth in the variable at its tolerance's scale, or a trend the surrogate only guesses), and the mean
    shifts, read by true-model calls or inside the surrogate's learned region, are the trend to trust."""
    (r_lo, r_hi), (e_lo, e_hi), (m_lo, m_hi) = r_shifted, errors, shifted_means
    if not (math.isfinite(dr_dmean) and abs(dr_dmean) > dr_dmean_error) or m_lo == m_hi:
        return False
    up = 1.0 if m_hi > m_lo else -1.0  # the sign of the mean's move to the 'high' factor
    signs = {float(np.sign(r_hi - r_nominal)) * up} if abs(r_hi - r_nominal) > e_hi else set()
    if abs(r_lo - r_nominal) > e_lo:
        signs.add(-float(np.sign(r_lo - r_nominal)) * up)
    return len(signs) == 1 and signs.pop() * dr_dmean < 0


def failure_reason(ctx: StudyContext, x_point: np.ndarray) -> str:
    """Why the true model failed at ``x_point``, as its evaluation recorded it (read back, not run again)."""
    evaluate = getattr(ctx.evaluator, "evaluate", None)  # a compute.Evaluator keeps the reasons; a bare callable not
    failures = evaluate(np.atleast_2d(x_point)).failures if evaluate is not None else []
    return " ".join(str(failures[0][2]).split()) if failures and failures[0][2] else "no reason recorded"


def run_sensitivity(ctx: StudyContext, reliability: ReliabilityCurve) -> SensitivityResult:
    """Mean shifts (paper Figs. 22-24), Sobol' indices and reliability derivatives at one cycle count.

    Re-uses the reliability study's surrogate; see docs/study.md ("Sensitivity") for the three rules:

    * a shift that stays inside the design's region (|shift| <= ``sensitivity.surrogate_shift_limit`` = 4
      sigma by default; the initial design spans +-5 sigma) is evaluated on the surrogate with a shifted Monte Carlo
      population (no model call);
    * except the judged body's wear coefficient and hardness, read by Archard's exact scaling of the nominal
      population where the scaled limit state lies inside the curve (archard_check; the surrogate's direct reading
      is its check);
    * a larger shift (the geometric means moved by 20 % are hundreds of standard deviations away) is
      evaluated by the *separable scaling* rule: one true-model call at the shifted nominal point and one at
      the nominal point give the ratio rho of the max wear, and the reliability is P(rho * delta_max(x) <
      delta_0) over the nominal population; its error adds to the surrogate's that of rho itself, whose two calls
      each scatter by the life's call-to-call scatter (in quadrature). A shifted mechanism that cannot run (e.g. a
      rod too short to close the loop) has reliability 0, with its reason reported.

    The reliability derivatives are the score estimator's for normal marginals (exact with the Gaussian copula) and
    central differences with common random numbers on the surrogate for the others (``derivatives.FD_STEP``
    sigma); ``slope_contradicts_shifts`` marks a local slope against a consistent mean-shift trend.
    """
    t0 = time.perf_counter()
    level = read_level(ctx, reliability)
    shifts = mean_shifts(level, reliability)
    by_joint = sobol_by_joint(ctx, reliability, level.cycles)
    slopes = reliability_slopes(level)
    return sensitivity_result(level, shifts, by_joint, slopes, wall_seconds=time.perf_counter() - t0)


@dataclass(eq=False)
class LevelReading:
    """The nominal population at the sensitivity's cycle count read on the reliability study's life surrogate: what
    the mean shifts and the derivatives start from, and how they read a population of their own."""

    ctx: StudyContext
    engine: Any
    cycles: int
    col: int  # the level's index on the curve
    log_level: float  # ln of the level, the threshold of the life surrogate's margin
    pop: np.ndarray  # the nominal population (physical)
    u_pop: np.ndarray  # its standard-normal points
    iso: Any
    scatter: float  # the life's call-to-call scatter, in ln
    n_posterior: int
    margin: np.ndarray = field(init=False)  # ln N_f - ln N_s on the nominal population, and its Kriging sd
    margin_sd: np.ndarray = field(init=False)
    fail_nominal: np.ndarray = field(init=False)
    r_nominal: float = field(init=False)
    r_nominal_error: float = field(init=False)
    col_lo: np.ndarray = field(init=False)  # each column's range over the population
    col_hi: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        """The nominal population's margins, failure probabilities and reliability, with its error."""
        self.margin, self.margin_sd = self.log_life_margin(self.u_pop)
        self.fail_nominal = self.failure_at_level(self.u_pop, self.margin)
        self.r_nominal = float(1.0 - self.fail_nominal.mean())
        self.r_nominal_error = max(esc_absolute_error(self.margin, self.margin_sd), self.posterior_error(self.u_pop))
        self.col_lo, self.col_hi = self.pop.min(axis=0), self.pop.max(axis=0)

    @property
    def n_pop(self) -> int:
        """The size of the nominal population."""
        return self.pop.shape[0]

    def log_life_margin(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ln N_f - ln N_s at the standard-normal points u from the learned life surrogate (failure where < 0) and
        its Kriging standard deviation."""
        mu, var = self.engine.surrogates[self.col].predict(u)
        return mu, np.sqrt(np.maximum(var, 0.0))

    def failure_at_level(self, u: np.ndarray, margin: np.ndarray, log_shift: float = 0.0) -> np.ndarray:
        """Each row's probability of failure at N_s with its life divided by exp(log_shift), the life's scatter
        integrated as R(N) integrates it: each judged joint's own in a per-joint study, else ``failure_probability``
        of the margin."""
        if self.ctx.per_joint and self.scatter > 0:  # the engine's own rule (each joint's scatter), not the margin's
            return self.engine.failure_probabilities(u, self.scatter, [self.log_level + log_shift])[:, 0]
        return failure_probability(margin - log_shift, self.scatter)

    def posterior_error(self, u: np.ndarray, log_shift: float = 0.0, point_shifts=None) -> float:
        """1.96 x the standard deviation of R at N_s over the Kriging's posterior, on the first rows of ``u``, each
        life divided by exp(log_shift + its point_shifts): the surrogate's error that ESC's count of misclassified
        points misses where the life's scatter is integrated (its errors, correlated between the points, move R as
        a whole), as the curve's error counts it (``surrogate_pf_error``)."""
        shifts = None if point_shifts is None else np.asarray(point_shifts)[:self.n_posterior]
        sd = self.engine.posterior_pf_sd(u[:self.n_posterior], self.scatter, POSTERIOR_DRAWS,
                                         seed=self.ctx.config.reliability.seed + 23,
                                         thresholds=[self.log_level + log_shift], point_shifts=shifts)
        return float(Z95 * sd[0])

    def moved_u(self, x_shifted: np.ndarray, i: int) -> np.ndarray:
        """The points of a population that differs from the first rows of ``pop`` in column i only (a value beyond
        the population's own range of that column is read at its end)."""
        column = np.clip(x_shifted[:, i], self.col_lo[i], self.col_hi[i])
        if self.ctx.copula is None:
            u = self.u_pop[:len(column)].copy()
            u[:, i] = self.iso.normal_score(i, column)
            return u
        moved = self.pop[:len(column)].copy()
        moved[:, i] = column
        return self.iso.to_u(moved)

    def failure_of(self, x_shifted: np.ndarray, i: int) -> np.ndarray:
        """Each row's probability of failure at N_s, for a population that differs from ``pop`` in column i only."""
        u = self.moved_u(x_shifted, i)
        return self.failure_at_level(u, self.log_life_margin(u)[0])


def read_level(ctx: StudyContext, reliability: ReliabilityCurve) -> LevelReading:
    """The nominal population at the sensitivity's cycle count and the reliability there on the learned surrogate."""
    rel = ctx.config.reliability
    cycles = sensitivity_level(ctx, reliability)
    col = ctx.cycles.index(cycles)
    engine = reliability.engine
    n_pop = min(max(engine.n_mc, 100_000), 400_000)
    pop = ctx.sample(n_pop, rel.seed + 2)
    iso = ctx.iso()
    scatter = life_scatter_sd(ctx, engine)
    log_level = ctx.log_levels()[col]
    return LevelReading(ctx, engine, cycles, col, log_level, pop, iso.to_u(pop), iso, scatter,
                        n_posterior=min(SHIFT_POSTERIOR_POINTS, n_pop))


@dataclass
class MeanShifts:
    """The reliability at each mean x factor, the rule that read each shift, the Archard checks made, and the
    true-model calls beyond the study's design that the shifts needed."""

    table: MeanShiftResult
    rules: list[dict]
    archard_checks: list[dict]
    extra_model_calls: int


def mean_shifts(level: LevelReading, reliability: ReliabilityCurve) -> MeanShifts:
    """Each variable's mean moved to each ``sensitivity.factors`` in turn, read by the rule its shift falls under."""
    from jointwear.sensitivity import mean_shift_table

    ctx, sens = level.ctx, level.ctx.config.sensitivity
    n_model = len(ctx.targets)
    means = np.array([m.mean() for m in ctx.marginals[:n_model]])
    hist_col = ctx.history_cycles.index(level.cycles)
    # the points this stage needs beyond the study's design, counted whether they are run now or read back, so the
    # result is the same computed twice
    design = {np.asarray(x[:n_model], dtype=float).tobytes() for x in np.atleast_2d(reliability.design_x)}
    asked: set[bytes] = set()

    def true_wear(x_point: np.ndarray) -> float:
        """Wear at the sensitivity's cycle count by a true-model call (cached by the study context); with
        several judged joints, the inverse of the series-system life (the same ratio under linear growth)."""
        asked.add(np.asarray(x_point[:n_model], dtype=float).tobytes())
        if len(ctx.limit_state.joints) > 1:
            x_full = x_point if not ctx.random_allowance else np.append(x_point, ctx.allowance)
            return float(1.0 / ctx.life(x_full[None, :])[0])
        return float(ctx.wear(x_point[None, :])[0, hist_col])

    rules: list[dict] = []
    archard_checks: list[dict] = []
    exponents = [archard_exponent(ctx, i) for i in range(len(ctx.names))]

    def reliability_of(marginals):
        """R and the new true-model calls with at most one marginal shifted (``mean_shift_table``'s callback)."""
        changed = [i for i, (a, b) in enumerate(zip(marginals, ctx.marginals)) if a is not b]
        if not changed:
            return level.r_nominal, 0
        i = changed[0]
        shifted = physical_marginal(ctx, i, marginals[i])
        if abs(shifted.mean() - ctx.marginals[i].mean()) <= sens.surrogate_shift_limit * ctx.marginals[i].std():
            rule, check = surrogate_shift(level, i, marginals[i], shifted, exponents[i])
            if check is not None:
                archard_checks.append(check)
            rules.append(rule)
            return rule["reliability"], 0
        before = ctx.n_evaluated
        rule = separable_shift(level, i, marginals[i], means, true_wear)
        rules.append(rule)
        return rule["reliability"], ctx.n_evaluated - before

    table = mean_shift_table(reliability_of, ctx.marginals, ctx.names, ctx.labels, factors=tuple(sens.factors),
                             reliability_nominal=level.r_nominal)
    return MeanShifts(table, rules, archard_checks, len(asked - design))


def surrogate_shift(level: LevelReading, i: int, marginal, shifted, exponent: int | None) -> tuple[dict, dict | None]:
    """A shift inside the surrogate's learned region: its reading of the shifted population, or for the judged body's
    k or H Archard's exact scaling with that reading as its check; the rule applied and the check (None if none)."""
    ctx, rel = level.ctx, level.ctx.config.reliability
    factor = marginal.mean() / ctx.marginals[i].mean()
    if ctx.copula is None:  # independent inputs: one column drawn anew, and mapped alone
        shifted_u = level.u_pop.copy()
        shifted_u[:, i] = level.iso.normal_score(i, population([shifted], level.n_pop, rel.seed + 3 + i)[:, 0])
    else:  # dependent inputs: move the column by quantile so the copula is kept
        shifted_pop = level.pop.copy()
        q = np.clip(ctx.marginals[i].cdf(level.pop[:, i]), 1e-15, 1 - 1e-15)
        shifted_pop[:, i] = shifted.ppf(q)
        shifted_u = level.iso.to_u(shifted_pop)
    mu, sd = level.log_life_margin(shifted_u)
    r = float(1.0 - level.failure_at_level(shifted_u, mu).mean())
    error = max(esc_absolute_error(mu, sd), level.posterior_error(shifted_u))
    check = None
    if exponent is not None:
        check = archard_check(ctx, i, shifted, exponent, level.pop, level.margin, level.margin_sd, factor, r, error,
                              level.cycles, (min(ctx.cycles), max(ctx.cycles)), scatter_sd=level.scatter,
                              posterior_error=lambda shifts: level.posterior_error(level.u_pop, point_shifts=shifts))
        if check["consistent"] is not None:
            # the judged body's k or H: Archard's exact scaling of the nominal population, where the surrogate was
            # learned (its direct reading on the shifted population is the check)
            return {"variable": ctx.names[i], "factor": factor, "rule": "archard_scaling",
                    "reliability": check["reliability_archard"], "error_estimate": check["error_archard"],
                    "reliability_surrogate": r}, check
    return {"variable": ctx.names[i], "factor": factor, "rule": "surrogate", "reliability": r,
            "error_estimate": error}, check


def separable_shift(level: LevelReading, i: int, marginal, means: np.ndarray,
                    true_wear: Callable[[np.ndarray], float]) -> dict:
    """A shift beyond the surrogate's region, by the separable scaling rule: the ratio rho of the wear at the shifted
    and at the nominal means (two true-model calls) moves the nominal population's lives; the rule applied."""
    ctx = level.ctx
    base_wear = true_wear(means)
    x_s = means.copy()
    x_s[i] = marginal.mean()
    shifted_wear = true_wear(x_s)
    # the shift as configured, without the ratio's rounding noise (0.8000000000000002)
    entry = {"variable": ctx.names[i], "factor": round(marginal.mean() / ctx.marginals[i].mean(), 12),
             "rule": "separable_scaling"}
    if not math.isfinite(shifted_wear):
        entry.update(reliability=0.0, reason="the shifted mechanism could not run (counted as failure): "
                                             + failure_reason(ctx, x_s))
        return entry
    rho = shifted_wear / base_wear
    # wear x rho <=> life / rho (the wear grows linearly in N): failure where ln N_f - ln rho < ln N_s
    mu = level.margin - math.log(rho)
    r = float(1.0 - level.failure_at_level(level.u_pop, level.margin, math.log(rho)).mean())
    surrogate = max(esc_absolute_error(mu, level.margin_sd), level.posterior_error(level.u_pop, math.log(rho)))
    # rho's own error: each of its two calls scatters by the life's call-to-call scatter in ln (a chaotic
    # model), so ln rho by sqrt(2) of it; R read at ln rho -+ 1.96 of that gives its 95 % half-width
    rho_sd = math.sqrt(2.0) * level.scatter
    ratio = 0.0
    if rho_sd > 0:
        ends = [float(1.0 - level.failure_at_level(level.u_pop, level.margin, math.log(rho) + d).mean())
                for d in (-Z95 * rho_sd, Z95 * rho_sd)]
        ratio = abs(ends[1] - ends[0]) / 2.0
    entry.update(reliability=r, wear_ratio=rho, wear_ratio_sd_log=rho_sd, error_surrogate=surrogate,
                 error_wear_ratio=ratio, error_estimate=math.hypot(surrogate, ratio))
    return entry


def sobol_by_joint(ctx: StudyContext, reliability: ReliabilityCurve, cycles: int) -> dict[str, dict]:
    """Sobol' indices of each judged joint's wear at ``cycles`` on a wear surrogate of the study's design, with the
    share of its variance that the model's call-to-call scatter makes."""
    from jointwear.sensitivity import sobol_indices

    rel, sens = ctx.config.reliability, ctx.config.sensitivity
    by_joint = {}
    independent = population(ctx.marginals, SCATTER_SHARE_SAMPLES, rel.seed)  # drawn independently, as the indices'
    for j, joint in enumerate(ctx.limit_state.names):
        wear_model = WearSurrogates(ctx, np.asarray(reliability.design_x), [cycles], seed=rel.seed, joint=j)
        indices = sobol_indices(lambda x, m=wear_model: m.predict(x)[:, 0] * 1e3, ctx.marginals,
                                ctx.names, n_base=sens.sobol_base_samples, seed=rel.seed)
        by_joint[joint] = {**indices.as_dict(), "joint": joint,
                           "output": f"{ctx.limit_state.label} of joint {joint} at {cycles:,} cycles",
                           "scatter_share": wear_model.scatter_share(independent)}
    return by_joint


class Slopes(NamedTuple):
    """The reliability derivatives and the 95 % error of each dR/dmu."""

    derivatives: ReliabilityDerivatives
    posterior_sd: np.ndarray  # the surrogate's own standard deviation of each dPf/dmu
    error: np.ndarray  # 95 %: the Monte Carlo error and the surrogate's own, in quadrature


def reliability_slopes(level: LevelReading) -> Slopes:
    """The derivatives of R by each mean and standard deviation on the nominal population, with their errors."""
    from jointwear.sensitivity import (
        fill_by_finite_differences,
        reliability_derivatives,
    )

    ctx = level.ctx
    # normal marginals: the score (exact, with the copula's C^-1); the others: central differences with common random
    # numbers on this population's failure probability, the perturbed column read on the surrogate as fail_nominal
    # is (a value beyond the population's own range of that column is read at its end: the surrogate knows the
    # model only through the marginal's normal score, which has no value beyond a bounded support)
    deriv = reliability_derivatives(level.pop, level.fail_nominal, ctx.marginals, ctx.names, correlation=ctx.copula)
    deriv = fill_by_finite_differences(deriv, level.pop, level.failure_of, ctx.marginals)
    slope_sd = posterior_slope_sd(level, deriv)
    return Slopes(deriv, slope_sd, Z95 * np.hypot(deriv.dpf_dmean_se, np.nan_to_num(slope_sd)))


def posterior_slope_sd(level: LevelReading, deriv: ReliabilityDerivatives) -> np.ndarray:
    """The standard deviation of each dPf/dmu over the Kriging's posterior, on the first rows of the population
    (the same estimator per posterior draw: the score's weights, or the central difference's two shifted
    populations): the surrogate's own error of the slope, which the Monte Carlo standard error leaves out (a
    trend the surrogate only guesses along a variable of no effect read as a resolved slope)."""
    from jointwear.sensitivity import mean_scores, perturbed_column

    ctx, engine, pop, seed = level.ctx, level.engine, level.pop, level.ctx.config.reliability.seed
    m = level.n_posterior
    out = np.full(len(ctx.names), np.nan)
    weights = mean_scores(pop[:m], ctx.marginals, ctx.copula)
    score = [k for k, how in enumerate(deriv.method) if how == "score"]
    if score:
        p = engine.posterior_failure_draws(level.u_pop[:m], level.log_level, level.scatter, POSTERIOR_DRAWS,
                                           seed=seed + 23)
        out[score] = (weights[:, score].T @ p / m).std(axis=1, ddof=1)
    for k, how in enumerate(deriv.method):
        if how == "finite_difference":
            h = deriv.fd_step_sigma * ctx.marginals[k].std()
            ends = []
            for sign in (1.0, -1.0):
                x_end = pop[:m].copy()
                x_end[:, k] = perturbed_column(ctx.marginals[k], pop[:m, k], "mean", sign * h)
                ends.append(level.moved_u(x_end, k))
            p = engine.posterior_failure_draws(np.vstack(ends), level.log_level, level.scatter, POSTERIOR_DRAWS,
                                               seed=seed + 29)
            out[k] = ((p[:m] - p[m:]).mean(axis=0) / (2.0 * h)).std(ddof=1)
    return out


def sensitivity_result(level: LevelReading, shifts: MeanShifts, by_joint: dict[str, dict], slopes: Slopes,
                       wall_seconds: float) -> SensitivityResult:
    """The stage's result: one row per variable, the rankings (by group too) and the pairs they do not separate."""
    from jointwear.sensitivity import unresolved_pairs

    ctx, sens, table = level.ctx, level.ctx.config.sensitivity, shifts.table
    groups = {}
    specs = ctx.config.uncertainty.all_specs()
    for spec in specs:
        groups.setdefault(spec.group, []).append(spec.name)
    ranking = table.ranking()
    ranking_by_group = {g: [n for n in ranking if n in members] for g, members in groups.items()}
    errors_low, errors_high = shift_errors(ctx.names, sens.factors, shifts.rules)
    swing_error = {name: errors_low[k] if abs(table.reliability_low[k] - level.r_nominal)
                   >= abs(table.reliability_high[k] - level.r_nominal) else errors_high[k]
                   for k, name in enumerate(ctx.names)}
    unresolved = unresolved_pairs(ranking, dict(zip(ctx.names, table.swings())), swing_error, groups)
    sobol = next(iter(by_joint.values()))  # the headline indices: the first judged joint's
    return SensitivityResult(**{
        "cycles": level.cycles, "factors": list(sens.factors), "reliability_nominal": level.r_nominal,
        "reliability_nominal_error": level.r_nominal_error,
        "variables": variable_rows(level, table, (errors_low, errors_high), slopes, sobol),
        "ranking": ranking, "ranking_by_group": ranking_by_group,
        "unresolved_pairs": unresolved,
        "rules": shifts.rules, "archard_checks": shifts.archard_checks,
        "notes": [] if ctx.copula is None else [
            "Sobol' indices assume independent inputs: they are computed on the marginals without the copula; the "
            "mean shifts and the reliability derivatives keep it."],
        "extra_model_calls": shifts.extra_model_calls,
        "sobol": {**sobol, **({"by_joint": by_joint} if len(by_joint) > 1 else {})},
        "derivatives": slopes.derivatives.as_dict(), "n_population": level.n_pop,
        "wall_seconds": wall_seconds,
    })


def shift_errors(names: list[str], factors, rules: list[dict]) -> tuple[list[float], list[float]]:
    """The error estimate of each variable's shifted reliability at the low and the high factor (0 where the shifted
    mechanism could not run: R = 0 is exact)."""
    shift_error = {(e["variable"], round(e["factor"], 9)): e.get("error_estimate", 0.0) for e in rules}
    return ([shift_error.get((name, round(factors[0], 9)), 0.0) for name in names],
            [shift_error.get((name, round(factors[1], 9)), 0.0) for name in names])


def variable_rows(level: LevelReading, table: MeanShiftResult, errors: tuple[list[float], list[float]],
                  slopes: Slopes, sobol: dict) -> list[dict]:
    """One row per random variable: its shifted reliabilities, derivatives and Sobol' indices."""
    ctx, factors, r_nominal = level.ctx, level.ctx.config.sensitivity.factors, level.r_nominal
    deriv, slope_sd, slope_error = slopes
    errors_low, errors_high = errors
    specs = ctx.config.uncertainty.all_specs()
    means_all = [m.mean() for m in ctx.marginals]
    variables = []
    for k, name in enumerate(ctx.names):
        variables.append({
            "name": name, "label": ctx.labels[k],
            "group": specs[k].group if k < len(specs) else "other",
            "unit": ctx.units[k],  # SI: dR_dmean and dR_dstd are per this unit
            "reliability_low": table.reliability_low[k], "reliability_high": table.reliability_high[k],
            "reliability_low_error": errors_low[k], "reliability_high_error": errors_high[k],
            "dR_dmean": float(-deriv.dpf_dmean[k]), "dR_dstd": float(-deriv.dpf_dstd[k]),
            # 95 %: the Monte Carlo error and the surrogate's own (over its posterior), in quadrature
            "dR_dmean_error": float(slope_error[k]), "dR_dmean_surrogate_sd": float(slope_sd[k]),
            "derivative_method": deriv.method[k],
            "slope_contradicts_shifts": slope_contradicts_shifts(
                float(-deriv.dpf_dmean[k]), float(slope_error[k]), r_nominal,
                (table.reliability_low[k], table.reliability_high[k]), (errors_low[k], errors_high[k]),
                (factors[0] * means_all[k], factors[1] * means_all[k])),
            # the elasticity of R, (mu / R) dR/dmu = -(Pf / R) x the Pf elasticity the derivatives hold
            "elasticity_mean": (float(-deriv.elasticity_mean[k] * deriv.pf / (1.0 - deriv.pf))
                                if 0.0 < deriv.pf < 1.0 else 0.0),
            "S1": float(sobol["S1"][k]), "ST": float(sobol["ST"][k]),
        })
    return variables
