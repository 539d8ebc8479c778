"""The wear reliability stage: joins the true model, the random variables and the reliability engine.

One true-model call maps a sample x of the random variables to the wear histories of the judged joints,
read at the cycle counts of the R(N) curve. The limit state of level k is G_k = ln N_f(x) - ln N_k with
N_f the series-system life (:mod:`jointwear.study.limit_state`); one shared design serves the whole curve
(:func:`jointwear.reliability.akmcs_multi`). Samples that cannot run are handled by the rule of
each clearance's ``infeasible_rule`` (truncated clearance by default) and, for anything else
(a linkage that cannot assemble, an integrator failure), by the reliability engine's NaN rule: a failed
call counts as a failure of the mechanism, never as safe, and is reported.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from jointwear.config import StudyConfig, target_display_unit
from jointwear.reliability.results import Z95
from jointwear.schema import ConfigError
from jointwear.study.limit_state import (
    LimitState,
    archard_power,
    archard_trend_applies,
    curve_cycles,
    curve_half_width,
    life_at,
    life_interval,
    life_status,
    limit_state_from_config,
)
from jointwear.study.model_call import WORN_AWAY_WEAR, WearModelCall
from jointwear.study.reliability_results import SurrogateFit
from jointwear.study.results import ReliabilityCurve
from jointwear.units import SUFFIXES


def crank_speed_rpm(config: StudyConfig) -> float:
    """The config's crank speed in rpm (its magnitude; the config holds rad/s)."""
    return abs(float(config.mechanism.crank_speed)) / SUFFIXES["rpm"][0]


def cycles_to_hours(cycles: float, config: StudyConfig) -> float:
    """Operating hours of ``cycles`` crank revolutions at the config's crank speed: N / (60 rpm)."""
    return cycles / (60.0 * crank_speed_rpm(config))


@dataclass
class StudyContext:
    """What a study's stages share: the config, the random inputs, the limit state and the evaluator of
    true-model calls (a :class:`jointwear.compute.Evaluator`: it serves every input row it has run or read
    again without a new call, so the stages ask it for what they need)."""

    config: StudyConfig
    names: list[str]
    labels: list[str]
    units: list[str]  # SI unit of each input ("" for a plain number)
    marginals: list
    targets: list[str]
    cycles: list[int]
    history_cycles: list[int]
    evaluator: Any
    random_allowance: bool
    limit_state: LimitState
    copula: Any = None
    #: why each failed model call failed, by its input row's bytes (the engines see only its NaN outputs)
    call_failures: dict[bytes, str] = field(default_factory=dict, repr=False)

    def sample(self, n: int, seed: int) -> np.ndarray:
        """A Monte Carlo population of the study's inputs (their copula honoured)."""
        return population(self.marginals, n, seed, self.copula)

    def iso(self):
        """The iso-probabilistic transform of the study's inputs (marginals and copula)."""
        from jointwear.reliability import IsoTransform

        return IsoTransform(self.marginals, self.copula)

    @property
    def allowance(self) -> float:
        """The allowance of the first judged joint, m."""
        return self.limit_state.reference_allowance

    def outputs(self, X: np.ndarray) -> np.ndarray:
        """The model outputs (n, J * H): the wear quantity of every judged joint at ``history_cycles``."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        batch = self.evaluator.evaluate(X)
        for i, status, reason in batch.failures:
            self.call_failures[np.ascontiguousarray(X[i]).tobytes()] = f"{status}: {reason}" if reason else status
        return np.asarray(batch.Y, dtype=float).reshape(X.shape[0], -1)

    def failure_reason(self, x_model: np.ndarray) -> str | None:
        """Why the model call at the input row ``x_model`` failed (None when it did not, or is unknown)."""
        return self.call_failures.get(np.ascontiguousarray(np.asarray(x_model, dtype=float)).tobytes())

    def wear(self, X: np.ndarray, joint: int = 0) -> np.ndarray:
        """The wear quantity (m) of judged joint ``joint`` at ``history_cycles``, shape (n, H)."""
        h = len(self.history_cycles)
        return self.outputs(X)[:, joint * h:(joint + 1) * h]

    @property
    def n_evaluated(self) -> int:
        """Distinct model inputs evaluated (or read back from the store) through this context."""
        return self.evaluator.n_known

    @property
    def n_model_calls(self) -> int:
        """True-model calls made through this context (not those read back from the store or from memory)."""
        return int(self.evaluator.n_model_calls)

    def split(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """Model inputs and the sampled allowance (None when the allowance is deterministic)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        if self.random_allowance:
            return X[:, :-1], X[:, -1]
        return X, None

    def joint_lives(self, X: np.ndarray) -> np.ndarray:
        """N_f,j(x) of every judged joint, shape (n, J)."""
        x_model, draw = self.split(X)
        return self.limit_state.joint_lives(self.history_cycles, self.outputs(x_model), draw)

    def life(self, X: np.ndarray) -> np.ndarray:
        """Wear life N_f(x) of the mechanism: the first judged joint to reach its allowance."""
        x_model, draw = self.split(X)
        return self.limit_state.life(self.history_cycles, self.outputs(x_model), draw)

    def log_life(self, X: np.ndarray) -> np.ndarray:
        """ln N_f(x), shape (n,); NaN for failed calls.

        The limit state of level N_k is G_k = ln N_f(x) - ln N_k (``akmcs_multi(levels=log_levels())``):
        G_k < 0 exactly when the wear of some judged joint exceeds its allowance at N_k (paper Eq. 42-43),
        because the wear grows with N. All levels are one function shifted by constants, so one Kriging
        serves them and R(N) is monotone by construction; the logarithm makes the Archard response (a
        product of powers of k, H, F, ...) nearly linear in the inputs.
        """
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.log(self.life(X))

    def log_joint_lives(self, X: np.ndarray) -> np.ndarray:
        """ln N_f,j(x) of every judged joint, shape (n, J); NaN for failed calls: the components of the series
        system whose minimum is :meth:`log_life`."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.log(self.joint_lives(X))

    @property
    def per_joint(self) -> bool:
        """Whether the life is learnt one Kriging per judged joint (several joints, ``reliability.surrogate``)."""
        return len(self.limit_state.joints) > 1 and self.config.reliability.surrogate == "per_joint"

    @property
    def learnt_response(self) -> tuple[Callable[[np.ndarray], np.ndarray], str | None]:
        """What the reliability engine learns and how (its ``g`` and ``system``): each judged joint's ln N_f,j as a
        series system in a per-joint study, else the mechanism's ln N_f."""
        return (self.log_joint_lives, "series") if self.per_joint else (self.log_life, None)

    def log_levels(self) -> np.ndarray:
        return np.log(np.asarray(self.cycles, dtype=float))


def archard_exponent(ctx: StudyContext, i: int) -> int | None:
    """+1 when the judged wear quantity is proportional to variable i under Archard's law, -1 when inversely
    proportional, else None (:func:`~jointwear.study.limit_state.archard_power` of its target)."""
    return archard_power(ctx.config, ctx.limit_state, ctx.targets[i]) if i < len(ctx.targets) else None


def archard_trend_unused(ctx: StudyContext) -> bool:
    """Whether the Kriging learns a constant trend where ``reliability.trend = "archard"`` would tell it Archard's
    scaling (a wear coefficient or hardness of the judged body of a single judged joint is random)."""
    return ctx.config.reliability.trend == "constant" and archard_trend_applies(ctx.config)


#: the shortest correlation length (standard deviations of an input) a Kriging with the linear trend on may fit where
#: the noise is estimated: shorter, the likelihood reads the rest's scatter as signal and the nugget collapses (on the
#: slider-crank preset's 80 points; docs/reliability.md). The constant phase before the trend keeps the default bounds.
LINEAR_TREND_MIN_LENGTH = 1.0


def kriging_options(config) -> dict:
    """The life Kriging's settings from ``reliability.noise`` and ``reliability.trend`` (``KrigingSurrogate``'s
    keywords), the same for the study's learning, its replay, the validation and the design."""
    from jointwear.reliability.kriging import SCALE_BOUNDS

    rel = config.reliability
    options: dict = {"estimate_nugget": rel.noise == "estimate"}
    if rel.trend == "linear":
        options["linear_trend"] = True
        if rel.noise == "estimate":
            options["trend_scale_bounds"] = (LINEAR_TREND_MIN_LENGTH, SCALE_BOUNDS[1])
    return options


def life_trend(ctx: StudyContext) -> Callable[[np.ndarray], np.ndarray] | None:
    """The known part of ln N_f(x) the Kriging need not learn (``reliability.trend = "archard"``): Archard's exact
    scaling of the life in the judged body's wear coefficient k and hardness H, ln N_f = -ln(k / k_mean) + ln(H /
    H_mean) + the rest (the wear depth is k / H times a history that the wear shapes alike, docs/reliability.md, "The
    learnt life's spread"). None: nothing known (``"constant"``, or no such variable is random)."""
    if ctx.config.reliability.trend != "archard":
        return None
    exponents = [(i, archard_exponent(ctx, i)) for i in range(len(ctx.names))]
    terms = [(i, e, float(ctx.marginals[i].mean())) for i, e in exponents if e]
    if not terms:
        return None

    def trend(x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        return -sum(e * np.log(np.clip(x[:, i] / ref, 1e-12, None)) for i, e, ref in terms)

    return trend


def life_offset(ctx: StudyContext, iso=None) -> Callable[[np.ndarray], np.ndarray] | None:
    """:func:`life_trend` as a function of the standard-normal inputs of ``iso`` (default the study's): the
    ``offset`` of a Kriging of ln N_f fitted in that space, or None."""
    trend = life_trend(ctx)
    if trend is None:
        return None
    iso = ctx.iso() if iso is None else iso
    return lambda u: trend(iso.to_x(u))


def study_context(config: StudyConfig, evaluator_factory: Callable[[WearModelCall], Any],
                  threads: int | None = None) -> StudyContext:
    """Random inputs, limit state and true model of the study (the config is checked by the caller); ``threads``:
    most threads of one model call (WearModelCall.threads)."""
    unc = config.uncertainty
    if unc is None or not unc.all_specs():
        raise ConfigError("uncertainty: the study needs random variables ([uncertainty] section)")
    if not config.clearance_joints:
        raise ConfigError("clearance_joints: the wear study needs at least one clearance joint")
    specs = unc.all_specs()
    names = [s.name for s in specs]
    labels = [s.label or s.name for s in specs]
    units = [target_display_unit(s.target) or "" for s in specs]
    # The learning always runs on feasible samples (every clearance above its minimum); under the 'fail' rule the
    # infeasible probability mass is added to Pf afterwards (run_reliability), which is exact because the
    # truncated distributions are the conditional ones given feasibility (the clearances independent).
    marginals = unc.marginals(feasible=True)
    rel = config.reliability
    limit = limit_state_from_config(config)
    call = model_call(config, threads)
    random_allowance = rel.allowance_std > 0
    if random_allowance:
        from scipy import stats

        names.append("delta_0")
        labels.append("wear allowance")
        units.append("m")
        marginals.append(stats.norm(limit.reference_allowance, rel.allowance_std))
    return StudyContext(config, names, labels, units, marginals, [s.target for s in specs], rel.curve_cycles(),
                        call.cycles, evaluator_factory(call), random_allowance, limit, copula=unc.copula(names))


def store_digest(config: StudyConfig, out=None) -> str:
    """The key of a study's evaluation store: the hash of what its model calls' outputs depend on
    (:meth:`WearModelCall.identity`), so a study resumed with other learning or report settings reuses its calls.
    With the output folder ``out``: the key its store was made with when that is the former key of the same calls
    (``identity(former=True)``), so a store made before the stage-only settings left the key still resumes."""
    from jointwear.compute import EvaluationStore, config_hash

    call = model_call(config)
    digest = config_hash(call.identity())
    if out is not None and EvaluationStore.refusal(out, digest, resume=True) is not None:
        former = config_hash(call.identity(former=True))
        if EvaluationStore.refusal(out, former, resume=True) is None:
            return former
    return digest


def model_call(config: StudyConfig, threads: int | None = None) -> WearModelCall:
    """The study's true model: a sample of the random variables -> the wear quantity of every judged joint at the
    history's cycle counts (every curve level, and every ``reliability.step()`` up to the last level)."""
    rel = config.reliability
    cycles = rel.curve_cycles()
    step = rel.step()
    history = sorted(set(range(step, max(cycles) + 1, step)) | set(cycles))
    specs = config.uncertainty.all_specs() if config.uncertainty is not None else []
    limit = limit_state_from_config(config)
    return WearModelCall(base=config.model_dump(), targets=[s.target for s in specs], cycles=history,
                         joints=list(limit.joints), quantity=limit.quantity, threads=threads)


def population(marginals: Sequence, n: int, seed: int, copula: Any = None) -> np.ndarray:
    """A Monte Carlo population of the inputs (physical space), joined by ``copula`` when given."""
    if copula is not None:
        from jointwear.reliability import sample

        return sample(marginals, n, seed, copula)
    rng = np.random.default_rng(seed)
    return np.column_stack([m.rvs(size=n, random_state=rng) for m in marginals])


class WearSurrogates:
    """Kriging of ln q(x, N) of judged joint ``joint`` (the first by default) at a few cycle counts, fitted once on
    the final design (no learning): the Sobol' indices of the wear. The reliability and the wear distributions
    come from the learned life surrogate. Its noise is estimated as the life surrogate's is (``reliability.noise``):
    fitted exactly, a chaotic wear's call-to-call scatter bent the Kriging into variables the wear does not depend on
    (on a two-joint six-bar, the other joint's wear coefficient took the largest total index).
    """

    def __init__(self, ctx: StudyContext, design_x: np.ndarray, cycles: Sequence[int], seed: int = 0,
                 joint: int = 0):
        from jointwear.reliability import KrigingSurrogate

        self.cycles = list(cycles)
        self.iso = ctx.iso()
        x_model, _ = ctx.split(design_x)
        wear = ctx.wear(x_model, joint)
        cols = [ctx.history_cycles.index(c) for c in self.cycles]
        u = self.iso.to_u(design_x)
        noisy = ctx.config.reliability.noise == "estimate"
        self.surrogates = []
        for j in cols:
            with np.errstate(divide="ignore", invalid="ignore"):
                y = np.log(wear[:, j])
            ok = np.isfinite(y)
            self.surrogates.append(KrigingSurrogate(seed=seed + j, estimate_nugget=noisy).fit(u[ok], y[ok]))

    def predict(self, x: np.ndarray) -> np.ndarray:
        """Wear (m), shape (n, len(cycles))."""
        u = self.iso.to_u(x)
        return np.column_stack([np.exp(s.predict(u, return_variance=False)[0]) for s in self.surrogates])

    def scatter_share(self, x: np.ndarray, column: int = 0) -> float:
        """Share of the wear's variance over the inputs ``x`` that its call-to-call scatter holds, which belongs to
        no input: with q = exp(mu(x) + s eps) (s the Kriging's noise in ln q), E[q^2 | x] (e^{s^2} - 1) over the
        total, Var(e^mu) + E[e^{2 mu}] (e^{s^2} - 1), in units of e^{s^2}; 0 for an interpolating fit. Sobol'
        indices of the predicted wear e^mu share the rest."""
        model = self.surrogates[column]
        mu = model.predict(self.iso.to_u(x), return_variance=False)[0]
        q = np.exp(mu - mu.mean())  # the share has no scale
        scatter = float(np.mean(q**2) * np.expm1(model.noise_variance))
        total = float(np.var(q)) + scatter
        return scatter / total if total > 0.0 else 0.0


def run_reliability(ctx: StudyContext, *, progress: Callable | None = None) -> ReliabilityCurve:
    """R(N) over the curve's cycle counts from one shared AK-MCS design (paper Sections 5-6.2)."""
    rel = ctx.config.reliability
    t0 = time.perf_counter()
    engine = learn_life(ctx, progress)
    curve = estimate_curve(ctx, engine)
    pop, histograms, mean_max = wear_distributions(ctx, engine, curve.pf)
    convergence = learning_convergence(ctx, engine)
    design_x = np.asarray(engine.design_x)
    design_x_model = ctx.split(design_x)[0]
    design_wear = ctx.wear(design_x_model)
    infeasible = infeasible_record(ctx, engine, design_x_model, curve.p_inf)
    joints = _joint_breakdown(ctx, engine, design_x, pop, curve.life_curve, curve.at_levels, curve.u_posterior,
                              rel.seed + 19)
    pf, targets, lives, life_table = curve.pf, rel.targets, curve.lives, curve.life_table
    return ReliabilityCurve(
        cycles=curve.cycles, reliability=curve.reliability, pf=pf, pf_cov=curve.pf_cov,
        below_floor=pf < rel.pf_floor, target=targets[0],
        pf_error=curve.pf_error, pf_error_esc=curve.pf_error_esc,
        life_cycles=lives[0], life_hours=life_table[0]["hours"], life_table=life_table, life_curve=curve.life_curve,
        model_calls=int(engine.n_calls), failed_calls=int(engine.n_failed_calls), n_mc=curve.n_mc,
        converged=bool(engine.converged), wall_seconds=time.perf_counter() - t0, names=ctx.names, units=ctx.units,
        histograms=histograms, mean_max_wear_mm=mean_max, convergence=convergence,
        design_x=design_x, design_wear=design_wear, design_life=ctx.life(design_x),
        design_joint_lives=dict(zip(ctx.limit_state.names, ctx.joint_lives(design_x).T))
        if len(ctx.limit_state.names) > 1 else None,
        design_wear_cycles=np.asarray(ctx.history_cycles, dtype=float),
        quantity=ctx.limit_state.quantity, joints=joints,
        # 12 digits: the rpm entered comes back through rad/s as 399.99999999999994
        crank_speed_rpm=float(f"{crank_speed_rpm(ctx.config):.12g}"),
        engine=engine, infeasible=infeasible, learning_stop="" if engine.converged else str(engine.message),
        surrogate_fit=SurrogateFit.of(engine.response_surrogate, archard_trend_hint=archard_trend_unused(ctx)),
        life_surrogate="per_joint" if ctx.per_joint else "system_life")


def learn_life(ctx: StudyContext, progress: Callable | None = None):
    """The AK-MCS engine that learns the life surrogate on one design shared by every level of the curve."""
    from jointwear.reliability import Evaluation, akmcs_multi

    rel = ctx.config.reliability
    g, system = ctx.learnt_response
    return akmcs_multi(
        g, ctx.marginals, levels=ctx.log_levels(), system=system, n_mc=rel.n_mc, n_mc_max=rel.n_mc_max,
        n_initial=rel.n_initial, batch_size=rel.batch_size, u_threshold=rel.u_threshold,
        cov_target=rel.cov_target, pf_floor=rel.pf_floor, max_calls=rel.max_calls, seed=rel.seed, copula=ctx.copula,
        evaluation=Evaluation(progress=progress), stopping=rel.stopping, error_tol=rel.error_tol,
        error_abs_tol=rel.error_abs_tol, hold_iterations=rel.hold_iterations,
        quantile_pf=[1.0 - t for t in rel.targets], quantile_tol=rel.life_tol or None,
        kriging=kriging_options(ctx.config), keep_population=rel.noise == "none", trend=life_trend(ctx))


@dataclass
class CurveEstimate:
    """R(N) at the curve's levels and between them, with its errors and the lives read off it."""

    cycles: np.ndarray  # the curve's levels
    fine: np.ndarray  # the levels and the cycle counts between them
    at_levels: np.ndarray  # the levels' indices in ``fine``
    pf: np.ndarray
    pf_cov: np.ndarray
    reliability: np.ndarray
    n_mc: Any
    p_inf: float  # the probability of a sample that fails at assembly
    pf_error: np.ndarray
    pf_error_esc: np.ndarray
    u_posterior: np.ndarray  # the points of the Kriging's posterior spread
    life_curve: dict
    lives: list
    life_table: list[dict]


def estimate_curve(ctx: StudyContext, engine) -> CurveEstimate:
    """Pf, its COV and the surrogate's error at every level and between them, and the life at each target."""
    rel = ctx.config.reliability
    cycles = np.asarray(ctx.cycles, dtype=float)
    # the curve is estimated between its levels too (no call), and the life read there: R(N) is curved between
    # levels, and a straight line between them moved the life by more than its interval on a coarse curve
    fine = curve_cycles(cycles)
    at_levels = np.searchsorted(fine, cycles)
    scatter_sd = life_scatter_sd(ctx, engine)
    pf_fine, cov_fine, n_mc = _curve_estimate(ctx, engine, np.log(fine), at_levels, int(engine.n_mc), scatter_sd)
    p_inf = ctx.config.uncertainty.infeasible_probability()
    if p_inf > 0:
        # 'fail' rule: a sample with a clearance at or below its minimum is a failure at every N.
        pf_feasible = pf_fine
        pf_fine = p_inf + (1.0 - p_inf) * pf_feasible
        with np.errstate(divide="ignore", invalid="ignore"):
            cov_fine = np.where(pf_fine > 0, cov_fine * (1.0 - p_inf) * pf_feasible / pf_fine, cov_fine)
    pf, pf_cov = pf_fine[at_levels], cov_fine[at_levels]
    reliability = 1.0 - pf
    targets = rel.targets
    # the surrogate's absolute error of Pf among feasible samples (the infeasible share is exact): the larger of
    # ESC's count of misclassified samples and the spread of Pf over the Kriging's posterior
    pf_error_esc = (1.0 - p_inf) * np.asarray(engine.error_absolute, dtype=float)
    u_posterior = ctx.iso().to_u(ctx.sample(POSTERIOR_POINTS, rel.seed + 13))
    error_fine = (1.0 - p_inf) * surrogate_pf_error(engine, u_posterior, scatter_sd, rel.seed + 17, fine)
    pf_error = error_fine[at_levels]
    half_fine = curve_half_width(pf_fine, cov_fine, error_fine)
    life_curve = {"cycles": fine.tolist(), "reliability": (1.0 - pf_fine).tolist(),
                  "half_width_95": half_fine.tolist()}
    lives = [life_at(fine, 1.0 - pf_fine, t) for t in targets]
    life_table = []
    for t, n in zip(targets, lives):
        low, high = life_interval(fine, 1.0 - pf_fine, half_fine, t)
        life_table.append({"target": t, "cycles": n, "hours": None if n is None else cycles_to_hours(n, ctx.config),
                           "status": life_status(reliability, t), "cycles_low": low, "cycles_high": high})
    return CurveEstimate(cycles, fine, at_levels, pf, pf_cov, reliability, n_mc, p_inf, pf_error, pf_error_esc,
                         u_posterior, life_curve, lives, life_table)


def wear_distributions(ctx: StudyContext, engine, pf: np.ndarray) -> tuple[np.ndarray, dict, dict]:
    """The population they are drawn on, the wear histograms at the histogram levels and the mean wear at every level
    (paper Fig. 20), from the same life model as R(N), so that P(wear > allowance at N) = 1 - R(N) up to Monte Carlo
    noise."""
    rel = ctx.config.reliability
    hist_levels = rel.histogram_levels()
    n_hist = min(engine.n_mc, 100_000)
    pop = ctx.sample(n_hist, rel.seed + 1)
    wear_levels = sorted(set(hist_levels) | set(ctx.cycles))
    wear_all = implied_wear(ctx, engine, pop, wear_levels)
    hist_cols = [wear_levels.index(c) for c in hist_levels]
    a0 = ctx.limit_state.reference_allowance
    histograms = {"cycles": list(hist_levels),
                  "max_wear_mm": [(wear_all[:2000, j] * 1e3).tolist() for j in hist_cols],
                  "n_samples_shown": 2000, "n_population": int(n_hist),
                  "joint": ctx.limit_state.names[0], "quantity": ctx.limit_state.quantity,
                  "model": "the life surrogate of R(N): wear(x, N) = allowance x N / N_f(x) (linear growth), ln N_f "
                           "its mean plus a draw of the life's call-to-call scatter",
                  "exceedance": [float(np.mean(wear_all[:, j] > a0)) for j in hist_cols],
                  "one_minus_reliability": [float(pf[ctx.cycles.index(c)]) for c in hist_levels]}
    mean_max = {"cycles": wear_levels, "mean": (wear_all.mean(axis=0) * 1e3).tolist(),
                "std": (wear_all.std(axis=0) * 1e3).tolist()}
    return pop, histograms, mean_max


def learning_convergence(ctx: StudyContext, engine) -> dict:
    """The learning's Pf, COV, error estimate and least U after each step, at the progress level of the curve."""
    hist = engine.history
    ref = ctx.config.reliability.progress_level(ctx.cycles)
    return {"cycles": ctx.cycles[ref], "n_calls": [h.n_calls for h in hist],
            "pf": [_at(h.pf, ref) for h in hist], "cov": [_at(h.cov, ref) for h in hist],
            "error_estimate": [_at(h.error, ref) for h in hist], "min_u": [_at(h.min_u, ref) for h in hist]}


def infeasible_record(ctx: StudyContext, engine, design_x_model: np.ndarray, p_inf: float) -> dict:
    """The samples that cannot run: each clearance's share below its minimum, and the design's failed and worn-away
    calls with the model's reason for each failure."""
    unc = ctx.config.uncertainty
    infeasible = {"clearances": [{"name": c.name, "rule": c.infeasible_rule, "minimum_clearance_m": c.minimum,
                                  "probability_below_minimum": c.infeasible_probability()} for c in unc.clearances()],
                  "probability_failed_at_assembly": p_inf}
    infeasible["failed_calls"] = int(engine.n_failed_calls)
    with np.errstate(invalid="ignore"):  # a failed call's NaN row is no worn-away one
        infeasible["worn_away_calls"] = int(np.any(ctx.outputs(design_x_model) >= WORN_AWAY_WEAR, axis=1).sum())
    # the model's own reason for a call that returned NaN, where the engine only saw the NaN
    infeasible["failure_reasons"] = {str(k): ctx.failure_reason(design_x_model[int(k)]) or v
                                     for k, v in engine.failure_reasons.items()}
    return infeasible


def implied_wear(ctx: StudyContext, engine, pop: np.ndarray, cycles) -> np.ndarray:
    """The first judged joint's wear (m) at ``cycles`` for each row of ``pop``, implied by the learned life
    surrogate: a N / N_f(x), with a the allowance (sampled when random) and N_f from the R(N) model.

    Exact at the allowance (wear(x, N) > a exactly when N_f(x) < N, the failure event of R(N)), and the
    wear's own value elsewhere as far as the history grows linearly in N (docs/wear.md). With a call-to-call
    scatter of the life (``life_scatter_sd``), each row's ln N_f carries its own draw of it, as R(N) does. With
    several judged joints learnt one Kriging each, N_f is the first joint's own life (its own scatter drawn), so the
    wear is that joint's; learnt as one Kriging of the system's life, it is the first joint's wear scaled to the
    system's failure (no joint's own life is known then).
    """
    u = ctx.iso().to_u(pop)
    scatter = life_scatter_sd(ctx, engine)
    rng = np.random.default_rng(ctx.config.reliability.seed + 11)
    if ctx.per_joint:  # the first joint's own Kriging, with its own scatter
        sur = engine.response_surrogate
        mean = sur.component_predictions(u, variance=False)[0][:, 0]
        log_life = mean + sur.scatter_sds[0] * rng.standard_normal(u.shape[0]) + engine.levels[0]
    elif scatter > 0:  # each row's own draw of the call-to-call scatter, as R(N) integrates it
        log_life = engine.response(u) + scatter * rng.standard_normal(u.shape[0])
    else:
        log_life = engine.response(u)
    _, draw = ctx.split(pop)
    a = ctx.limit_state.reference_allowance if draw is None else draw
    n = np.asarray(cycles, dtype=float)
    return np.asarray(a, dtype=float).reshape(-1, 1) * n[None, :] * np.exp(-log_life)[:, None]


def _joint_breakdown(ctx: StudyContext, engine, design_x: np.ndarray, pop: np.ndarray, life_curve: dict,
                     at_levels: np.ndarray, u_posterior: np.ndarray, seed: int) -> list[dict]:
    """Each judged joint's allowance and, with several joints, its own R(N) with its 95 % half-width and its share
    of the system's failures at every level, from the Kriging of its log life: the learnt one of a per-joint study
    (with that joint's own scatter when the study estimates one, and its ``surrogate_fit``), else one fitted on the
    final design (no learning). The share goes to the joint with the shortest life: the predicted one, plus a draw
    of each joint's own scatter when the study counts it. Its R and half-width are also given on the system's
    ``life_curve`` (``curve``), of which the levels are the points ``at_levels``.

    The half-width (``half_width_95``) is the system curve's rule for one joint: 1.96 x (the Monte Carlo standard
    error of its Pf on ``pop`` + the standard deviation of its Pf over its Kriging's posterior at ``u_posterior``,
    drawn at POSTERIOR_SUBDIVISIONS points per interval and interpolated between).
    A joint alone is at least as reliable as the series system; a Kriging not refined by the learning can read lower
    than the system's R within its error, so a joint's R is reported no lower than the system's."""
    limit = ctx.limit_state
    fine = np.asarray(life_curve["cycles"], dtype=float)
    system_fine = np.asarray(life_curve["reliability"], dtype=float)
    rows = [{"name": n, "allowance_mm": a * 1e3} for n, a in zip(limit.names, limit.allowances)]
    if len(limit.joints) == 1:
        rows[0]["reliability"] = system_fine[at_levels].tolist()
        rows[0]["half_width_95"] = np.asarray(life_curve["half_width_95"])[at_levels].tolist()
        rows[0]["governing_share"] = [1.0] * len(ctx.cycles)
        return rows
    from jointwear.reliability import KrigingSurrogate, failure_spread

    iso = ctx.iso()
    u_pop = iso.to_u(pop)
    levels = ctx.log_levels()
    coarse = curve_cycles(ctx.cycles, POSTERIOR_SUBDIVISIONS)
    rng = np.random.default_rng(seed)
    if ctx.per_joint:  # the learnt components, fitted on each joint's margin at the first level
        sur = engine.response_surrogate
        pred = sur.component_predictions(u_pop, variance=False)[0] + levels[0]
        draws = sur.posterior_component_draws(u_posterior, POSTERIOR_DRAWS, rng) + levels[0]
    else:
        u_design = iso.to_u(design_x)
        log_lives = ctx.log_joint_lives(design_x)
        predicted, drawn = [], []
        for k in range(len(limit.joints)):
            y = log_lives[:, k]
            ok = np.isfinite(y)
            sur = KrigingSurrogate(seed=ctx.config.reliability.seed + 100 + k).fit(u_design[ok], y[ok])
            predicted.append(sur.predict(u_pop, return_variance=False)[0])
            drawn.append(sur.posterior_draws(u_posterior, POSTERIOR_DRAWS, rng))
        pred = np.column_stack(predicted)  # (n, J) ln N_f,j
        draws = np.stack(drawn)  # (J, m, draws)
    # a per-joint study with the life's scatter: each joint fails with its own (as the system's R(N) counts it), and
    # a failure goes to the joint whose drawn life is the shortest
    scatter = life_scatter_sd(ctx, engine)
    taus = engine.response_surrogate.scatter_sds if ctx.per_joint and scatter > 0 else np.zeros(len(rows))
    drawn = pred + rng.standard_normal(pred.shape) * taus[None, :] if np.any(taus > 0) else pred
    shares_fine = governing_shares_at(drawn, np.log(fine))  # (J, len(fine)); NaN where nothing has failed yet
    for k, row in enumerate(rows):
        pf, mc_sd = failure_mean_and_sd(pred[:, k], np.log(fine), float(taus[k]))
        posterior_sd = np.interp(fine, coarse, failure_spread(draws[k], np.log(coarse), float(taus[k])))
        r_fine = np.maximum(1.0 - pf, system_fine)
        half_fine = Z95 * (mc_sd + posterior_sd)
        row["reliability"] = r_fine[at_levels].tolist()
        row["half_width_95"] = half_fine[at_levels].tolist()
        row["curve"] = {"reliability": r_fine.tolist(), "half_width_95": half_fine.tolist(),
                        "governing_share": shares_fine[k].tolist()}
        row["governing_share"] = shares_fine[k][at_levels].tolist()
        if ctx.per_joint and engine.response_surrogate.fitted[k]:  # how well its own Kriging explains its life
            row["surrogate_fit"] = SurrogateFit.of(engine.response_surrogate.components[k]).to_json()
    return rows


def governing_shares_at(log_lives: np.ndarray, thresholds: np.ndarray) -> np.ndarray:
    """Each joint's share of a series system's failures by each of ``thresholds`` (ln N): among the samples whose
    shortest life ``log_lives`` (n, J) lies below the threshold, the fraction whose shortest is joint j's. (J, T);
    NaN where no sample has failed."""
    life = log_lives.min(axis=1)
    order = np.argsort(life)
    first = np.argmin(log_lives, axis=1)[order]
    failed = np.searchsorted(life[order], thresholds, side="left")  # samples with life < threshold
    counts = np.vstack([np.zeros((1, log_lives.shape[1])),
                        np.cumsum(first[:, None] == np.arange(log_lives.shape[1])[None, :], axis=0)])
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(failed > 0, counts[failed].T / failed, np.nan)


def failure_mean_and_sd(log_life: np.ndarray, thresholds: np.ndarray, scatter_sd: float = 0.0,
                        block: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Pf at each of ``thresholds`` (ln N) over the samples' ``log_life`` (each failing with probability
    Phi((ln N - ln N_f) / scatter_sd), the indicator ln N_f < ln N without a scatter) and the Monte Carlo standard
    error of that mean, a ``block`` of thresholds at a time (n x block probabilities held)."""
    from jointwear.reliability import failure_probability

    n = log_life.size
    pf, sd = [], []
    for start in range(0, len(thresholds), block):
        p = failure_probability(log_life[:, None] - thresholds[None, start:start + block], scatter_sd)
        pf.append(p.mean(axis=0))
        sd.append(p.std(axis=0, ddof=1) / math.sqrt(n))
    return np.concatenate(pf), np.concatenate(sd)


def life_scatter_sd(ctx: StudyContext, engine) -> float:
    """The call-to-call scatter of ln N_f that R(N) integrates: the Kriging's noise estimate when the study
    estimates one (``reliability.noise = "estimate"``), else 0."""
    return engine.noise_sd if ctx.config.reliability.noise == "estimate" else 0.0


#: population points of the posterior spread of Pf (its covariance takes POSTERIOR_POINTS^2 x 8 bytes: 72 MB), and
#: the conditional simulations on them (the spread's own sampling error: 1 / sqrt(2 x 400) = 3.5 %)
POSTERIOR_POINTS = 3000
POSTERIOR_DRAWS = 400
#: points per interval between two levels where the posterior spread of Pf is drawn for the life's curve
POSTERIOR_SUBDIVISIONS = 4


def surrogate_pf_error(engine, u: np.ndarray, scatter_sd: float, seed: int, cycles=None) -> np.ndarray:
    """The surrogate's absolute error of each level's Pf: the larger of ESC's (``engine.error_absolute``) and the
    95 % half-width of Pf over the Kriging's posterior, 1.96 x its standard deviation
    (``MultiReliabilityResult.posterior_pf_sd``) at ``u`` (POSTERIOR_POINTS points of the population, u space), each
    failing with the life's scatter ``scatter_sd`` as R(N) counts it. The surrogate's errors are correlated between
    the points: they move the whole curve, which ESC's count of misclassified points, made for a curve that
    classifies each point, does not see once R(N) integrates the scatter (docs/reliability.md, "The surrogate's
    error of R(N)"). fmax: a level without an ESC estimate (NaN) keeps the posterior one. ``cycles``: at these cycle
    counts instead of the levels (:func:`curve_cycles`), both parts interpolated between where they are known."""
    esc = np.asarray(engine.error_absolute, dtype=float)
    if cycles is None:
        return np.fmax(esc, Z95 * engine.posterior_pf_sd(u, scatter_sd, POSTERIOR_DRAWS, seed=seed))
    # the posterior's spread is smooth in N: drawn at POSTERIOR_SUBDIVISIONS points per interval, interpolated between
    cycles = np.asarray(cycles, dtype=float)
    coarse = curve_cycles(np.exp(engine.levels), POSTERIOR_SUBDIVISIONS)
    spread = engine.posterior_pf_sd(u, scatter_sd, POSTERIOR_DRAWS, seed=seed, thresholds=np.log(coarse))
    return np.fmax(np.interp(cycles, np.exp(engine.levels), esc), Z95 * np.interp(cycles, coarse, spread))


def _curve_estimate(ctx: StudyContext, engine, thresholds: np.ndarray, at_levels: np.ndarray, n_mc: int,
                    scatter_sd: float):
    """Pf and its COV at each of ``thresholds`` (ln N; the curve's levels are ``thresholds[at_levels]``) from the
    final surrogate (no call): on the engine's own population, which its learning classified, or, with a
    call-to-call scatter of the life, on one of its size drawn afresh, each sample failing at N with probability
    Phi((ln N - mu(x)) / s) (``failure_probability``). Then the
    population grows until COV(Pf) < target at every level above the floor (AK-MCS Step 6; the engine does it itself
    when its learning converges, not when the call budget ends it). The crude Monte Carlo size suffices for the
    smoothed estimate too, whose variance is smaller. Returns (pf, cov, population size)."""
    from jointwear.reliability import population_size

    rel = ctx.config.reliability
    iso = ctx.iso()
    seed = rel.seed + 7

    def draw(m, start):
        return iso.to_u(ctx.sample(m, seed + start))

    if scatter_sd > 0 or engine.population_u is None:
        pf, pf_cov = engine.estimate_on(draw, n_mc, noise_sd=scatter_sd, thresholds=thresholds)
    else:  # the population the learning classified (AK-MCS's own estimate at the levels)
        pf, pf_cov = engine.estimate_on(lambda m, start: engine.population_u[start:start + m], n_mc,
                                        thresholds=thresholds)
    need = (pf[at_levels] >= rel.pf_floor) & ~(pf_cov[at_levels] < rel.cov_target)
    if not need.any():
        return pf, pf_cov, n_mc
    n = population_size(pf[at_levels][need].min(), rel.cov_target, rel.n_mc_max)
    if n <= n_mc:
        return pf, pf_cov, n_mc
    pf_new, cov_new = engine.estimate_on(draw, n, noise_sd=scatter_sd, thresholds=thresholds)
    return pf_new, cov_new, n


def _at(value, index: int) -> float:
    arr = np.atleast_1d(np.asarray(value, dtype=float))
    return float(arr[min(index, arr.size - 1)]) if arr.size else float("nan")
