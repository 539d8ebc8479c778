"""The wear reliability study: joins the wear model, the random variables and the reliability engine.

One true-model call maps a sample x of the random variables to the whole wear history of the first
clearance joint, read at the cycle counts of the R(N) curve: delta_max(x, N_1..N_m). The limit state
of level k is G_k = delta_0 - delta_max(x, N_k) (paper Eq. 42); one shared design serves the whole curve
(:func:`jointwear.reliability.akmcs_multi`). Samples that cannot run are handled by the rule of
``config.uncertainty.clearance.infeasible_rule`` (truncated clearance by default) and, for anything else
(a linkage that cannot assemble, an integrator failure), by the reliability engine's NaN rule: a failed
call counts as a failure of the mechanism, never as safe, and is reported.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from jointwear.config import ConfigError, StudyConfig, config_from_dict
from jointwear.uncertainty.targets import (
    CLEARANCE_SUFFIX,
    set_clearance,
    set_target,
    target_error,
)


# ---------------------------------------------------------------------------------------------
# samples -> configs
# ---------------------------------------------------------------------------------------------
def apply_sample(base: StudyConfig | dict, targets: Sequence[str], x: Sequence[float]) -> StudyConfig:
    """A copy of the config with each target field set to the sample value (SI).

    A target ``clearance_joints.<i>.clearance`` sets the bearing radius to journal radius + c after all
    other targets (so a sampled journal radius and a sampled clearance combine as R_i = R_j + c).
    Raises ConfigError when the sample gives an invalid config (e.g. a linkage that cannot assemble).
    """
    data = base.model_dump() if isinstance(base, StudyConfig) else copy.deepcopy(base)
    derived = []
    for path, value in zip(targets, x):
        problem = target_error(data, path)
        if problem:
            raise ConfigError(f"uncertainty: target {problem}")
        if path.endswith(CLEARANCE_SUFFIX):
            derived.append((path, float(value)))
        else:
            set_target(data, path, float(value))
    for path, c in derived:
        set_clearance(data, path, c)
    return config_from_dict(data, source="sample")


# ---------------------------------------------------------------------------------------------
# the true model
# ---------------------------------------------------------------------------------------------
@dataclass
class WearModelCall:
    """One true-model call: sample x -> max bearing wear (m) of joint 0 at each of ``cycles``.

    A plain picklable object so that worker processes and Dask workers can run it.
    """

    base: dict
    targets: list[str]
    cycles: list[int]

    def __call__(self, x: np.ndarray):
        from jointwear.mechanism import build_model
        from jointwear.wear import wear_history

        try:
            cfg = apply_sample(self.base, self.targets, x)
        except ConfigError as exc:
            return np.full(len(self.cycles), np.nan), f"infeasible sample: {exc}"
        model = build_model(cfg)
        res = wear_history(model, cfg.wear, max(self.cycles))
        return np.asarray(res.max_wear_at(np.asarray(self.cycles, dtype=float)), dtype=float), "ok"


def nominal_wear(config: StudyConfig, n_cycles: int):
    """Wear history of the nominal mechanism (no sampling)."""
    from jointwear.mechanism import build_model
    from jointwear.wear import wear_history

    return wear_history(build_model(config), config.wear, n_cycles)


# ---------------------------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------------------------
@dataclass
class ReliabilityStudyResult:
    """R(N) curve, life at the target reliability and the wear distributions of a study."""

    cycles: np.ndarray
    reliability: np.ndarray
    pf: np.ndarray
    pf_cov: np.ndarray
    below_floor: np.ndarray
    pf_error: np.ndarray
    target: float
    life_cycles: float | None
    life_hours: float | None
    model_calls: int
    failed_calls: int
    n_mc: int
    converged: bool
    wall_seconds: float
    names: list[str]
    histograms: dict
    mean_max_wear: dict
    convergence: dict
    design_x: np.ndarray
    design_wear: np.ndarray
    engine: Any = field(repr=False, default=None)
    wear_surrogates: Any = field(repr=False, default=None)
    population: np.ndarray | None = field(repr=False, default=None)
    infeasible: dict = field(default_factory=dict)

    def as_json(self) -> dict:
        return {
            "curve": {"cycles": self.cycles.tolist(), "reliability": self.reliability.tolist(),
                      "pf": self.pf.tolist(), "pf_cov": self.pf_cov.tolist(),
                      "pf_error_estimate": self.pf_error.tolist(),
                      "cov_waived_below_pf_floor": self.below_floor.tolist()},
            "life_at_target": {"target": self.target, "cycles": self.life_cycles, "hours": self.life_hours},
            "model_calls": self.model_calls,
            "failed_calls": self.failed_calls,
            "n_mc": self.n_mc,
            "converged": self.converged,
            "wall_seconds": self.wall_seconds,
            "variables": self.names,
            "histograms": self.histograms,
            "mean_max_wear_mm": self.mean_max_wear,
            "convergence": self.convergence,
            "infeasible": self.infeasible,
        }


def life_at(cycles: np.ndarray, reliability: np.ndarray, target: float) -> float | None:
    """First cycle count where R(N) falls to ``target``, by linear interpolation of R(N)."""
    r = np.asarray(reliability, dtype=float)
    n = np.asarray(cycles, dtype=float)
    below = np.nonzero(r <= target)[0]
    if below.size == 0 or below[0] == 0:
        return None if below.size == 0 else float(n[0])
    i = below[0]
    r0, r1 = r[i - 1], r[i]
    if r0 == r1:
        return float(n[i])
    return float(n[i - 1] + (r0 - target) * (n[i] - n[i - 1]) / (r0 - r1))


def crank_speed(config: StudyConfig) -> float:
    """Crank speed, rad/s."""
    return float(config.mechanism.crank_speed)


def cycles_to_hours(cycles: float, config: StudyConfig) -> float:
    return cycles * (2.0 * math.pi / abs(crank_speed(config))) / 3600.0


# ---------------------------------------------------------------------------------------------
# the reliability study
# ---------------------------------------------------------------------------------------------
def life_from_history(cycles: np.ndarray, wear: np.ndarray, allowance: float | np.ndarray) -> np.ndarray:
    """Cycles N_f at which the max wear first reaches the allowance, for each row of ``wear`` (n, H).

    Linear interpolation in the history (which starts at zero wear at N = 0); past the last history point,
    linear extrapolation with the slope of the last history segment (the wear grows linearly in N, paper
    Fig. 20 and paper-notes). NaN rows (failed calls) give NaN; a history that stops growing gives +inf.
    """
    n_h = np.concatenate([[0.0], np.asarray(cycles, dtype=float)])
    w = np.atleast_2d(np.asarray(wear, dtype=float))
    w = np.concatenate([np.zeros((w.shape[0], 1)), w], axis=1)
    a = np.broadcast_to(np.asarray(allowance, dtype=float).reshape(-1), (w.shape[0],))
    out = np.full(w.shape[0], np.nan)
    for i in range(w.shape[0]):
        row = w[i]
        if not np.all(np.isfinite(row)):
            continue
        above = np.nonzero(row >= a[i])[0]
        if above.size:
            k = above[0]
            w0, w1 = row[k - 1], row[k]
            out[i] = n_h[k - 1] + (a[i] - w0) * (n_h[k] - n_h[k - 1]) / (w1 - w0)
        else:
            slope = (row[-1] - row[-2]) / (n_h[-1] - n_h[-2])
            out[i] = np.inf if slope <= 0 else n_h[-1] + (a[i] - row[-1]) / slope
    return out


@dataclass
class StudyContext:
    """What a study's stages share: the config, the random inputs and the evaluator of true-model calls."""

    config: StudyConfig
    names: list[str]
    labels: list[str]
    marginals: list
    targets: list[str]
    cycles: list[int]
    history_cycles: list[int]
    evaluator: Any
    random_allowance: bool
    _wear_cache: dict = field(default_factory=dict, repr=False)

    @property
    def allowance(self) -> float:
        return float(self.config.reliability.allowance)

    def wear(self, X: np.ndarray) -> np.ndarray:
        """Max bearing wear (m) at ``history_cycles`` for each row of the model inputs (n, H)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        todo = [i for i, row in enumerate(X) if row.tobytes() not in self._wear_cache]
        if todo:
            y = np.asarray(self.evaluator(X[todo]), dtype=float).reshape(len(todo), -1)
            for i, row in zip(todo, y):
                self._wear_cache[X[i].tobytes()] = row
        return np.stack([self._wear_cache[row.tobytes()] for row in X])

    @property
    def n_evaluated(self) -> int:
        """Distinct model inputs evaluated (or read back from the store) through this context."""
        return len(self._wear_cache)

    def split(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray | float]:
        X = np.atleast_2d(np.asarray(X, dtype=float))
        if self.random_allowance:
            return X[:, :-1], X[:, -1]
        return X, self.allowance

    def life(self, X: np.ndarray) -> np.ndarray:
        """Wear life N_f(x): cycles to reach the allowance (see :func:`life_from_history`)."""
        x_model, allowance = self.split(X)
        return life_from_history(np.asarray(self.history_cycles, dtype=float), self.wear(x_model), allowance)

    def log_life(self, X: np.ndarray) -> np.ndarray:
        """ln N_f(x), shape (n,); NaN for failed calls.

        The limit state of level N_k is G_k = ln N_f(x) - ln N_k (``akmcs_multi(levels=log_levels())``):
        G_k < 0 exactly when delta_max(x, N_k) > delta_0, the paper's failure event (Eq. 42-43), because the
        max wear grows with N. All levels are one function shifted by constants, so one Kriging serves them
        and R(N) is monotone by construction; the logarithm makes the Archard response (a product of powers
        of k, H, F, ...) nearly linear in the inputs.
        """
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.log(self.life(X))

    def log_levels(self) -> np.ndarray:
        return np.log(np.asarray(self.cycles, dtype=float))


def study_context(config: StudyConfig, evaluator_factory: Callable[[WearModelCall], Any]) -> StudyContext:
    """Random inputs and the true model of the study (checked once, here, at the boundary)."""
    unc = config.uncertainty
    if unc is None or not unc.all_specs():
        raise ConfigError("uncertainty: the study needs random variables ([uncertainty] section)")
    if not config.clearance_joints:
        raise ConfigError("clearance_joints: the wear study needs at least one clearance joint")
    specs = unc.all_specs()
    names = [s.name for s in specs]
    labels = [s.label or s.name for s in specs]
    # The learning always runs on feasible samples (clearance above its minimum); under the 'fail' rule the
    # infeasible probability mass is added to Pf afterwards (run_reliability), which is exact because the
    # truncated distribution is the conditional one given feasibility.
    marginals = unc.marginals(feasible=True)
    rel = config.reliability
    cycles = rel.curve_cycles()
    step = rel.cycles_step
    history = sorted(set(range(step, max(cycles) + 1, step)) | set(cycles))
    call = WearModelCall(base=config.model_dump(), targets=[s.target for s in specs], cycles=history)
    random_allowance = rel.allowance_std > 0
    if random_allowance:
        from scipy import stats

        names.append("delta_0")
        labels.append("wear allowance")
        marginals.append(stats.norm(rel.allowance, rel.allowance_std))
    return StudyContext(config, names, labels, marginals, [s.target for s in specs], cycles, history,
                        evaluator_factory(call), random_allowance)


def population(marginals: Sequence, n: int, seed: int) -> np.ndarray:
    """A Monte Carlo population of the inputs (physical space)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([m.rvs(size=n, random_state=rng) for m in marginals])


class WearSurrogates:
    """Kriging of ln delta_max(x, N) at a few cycle counts, fitted once on the final design (no learning).

    The reliability itself comes from the learned life surrogate; these give the wear distributions (paper
    Fig. 20) and the Sobol' indices of the max wear.
    """

    def __init__(self, ctx: StudyContext, design_x: np.ndarray, cycles: Sequence[int], seed: int = 0):
        from jointwear.reliability import IsoTransform, KrigingSurrogate

        self.cycles = list(cycles)
        self.iso = IsoTransform(ctx.marginals)
        x_model, _ = ctx.split(design_x)
        wear = ctx.wear(x_model)
        cols = [ctx.history_cycles.index(c) for c in self.cycles]
        u = self.iso.to_u(design_x)
        self.surrogates = []
        for j in cols:
            y = np.log(wear[:, j])
            ok = np.isfinite(y)
            self.surrogates.append(KrigingSurrogate(seed=seed + j).fit(u[ok], y[ok]))

    def predict(self, x: np.ndarray) -> np.ndarray:
        """Max wear (m), shape (n, len(cycles))."""
        u = self.iso.to_u(x)
        return np.column_stack([np.exp(s.predict(u, return_variance=False)[0]) for s in self.surrogates])


def run_reliability(ctx: StudyContext, *, progress: Callable | None = None) -> ReliabilityStudyResult:
    """R(N) over the curve's cycle counts from one shared AK-MCS design (paper Sections 5-6.2)."""
    from jointwear.reliability import akmcs_multi

    rel = ctx.config.reliability
    t0 = time.perf_counter()
    engine = akmcs_multi(
        ctx.log_life, ctx.marginals, levels=ctx.log_levels(), n_mc=rel.n_mc, n_mc_max=rel.n_mc_max, n_initial=rel.n_initial,
        batch_size=rel.batch_size, u_threshold=rel.u_threshold, cov_target=rel.cov_target,
        pf_floor=rel.pf_floor, max_calls=rel.max_calls, seed=rel.seed, progress=progress,
        stopping=rel.stopping, error_tol=rel.error_tol, error_abs_tol=rel.error_abs_tol, kriging={"estimate_nugget": rel.noise == "estimate"})
    cycles = np.asarray(ctx.cycles, dtype=float)
    pf = np.asarray(engine.pf, dtype=float)
    pf_cov = np.asarray(engine.cov, dtype=float)
    n_mc = int(engine.n_mc)
    pf, pf_cov, n_mc = _meet_cov_target(ctx, engine, pf, pf_cov, n_mc)
    clearance = ctx.config.uncertainty.clearance
    if clearance is not None and clearance.infeasible_rule == "fail":
        # 'fail' rule: a sample whose clearance is at or below the minimum is a failure at every N.
        p_inf = clearance.infeasible_probability()
        pf_feasible = pf
        pf = p_inf + (1.0 - p_inf) * pf_feasible
        with np.errstate(divide="ignore", invalid="ignore"):
            pf_cov = np.where(pf > 0, pf_cov * (1.0 - p_inf) * pf_feasible / pf, pf_cov)
    reliability = 1.0 - pf
    life = life_at(cycles, reliability, rel.target_reliability)

    # Wear distributions over the random inputs (paper Fig. 20) from wear surrogates fitted on the design.
    n_hist = min(engine.n_mc, 100_000)
    pop = population(ctx.marginals, n_hist, rel.seed + 1)
    wear_levels = sorted(set(rel.histogram_cycles) | set(ctx.cycles))
    wear_model = WearSurrogates(ctx, np.asarray(engine.design_x), wear_levels, seed=rel.seed)
    wear_all = wear_model.predict(pop)
    hist_cols = [wear_levels.index(c) for c in rel.histogram_cycles]
    histograms = {"cycles": list(rel.histogram_cycles),
                  "max_wear_mm": [(wear_all[:2000, j] * 1e3).tolist() for j in hist_cols],
                  "n_samples_shown": 2000, "n_population": int(n_hist)}
    mean_max = {"cycles": wear_levels, "mean": (wear_all.mean(axis=0) * 1e3).tolist(),
                "std": (wear_all.std(axis=0) * 1e3).tolist()}
    hist = engine.history
    ref = reference_level(ctx.cycles)
    convergence = {"cycles": ctx.cycles[ref], "n_calls": [h.n_calls for h in hist],
                   "pf": [_at(h.pf, ref) for h in hist], "cov": [_at(h.cov, ref) for h in hist],
                   "error_estimate": [_at(h.error, ref) for h in hist], "min_u": [_at(h.min_u, ref) for h in hist]}
    design_wear = ctx.wear(ctx.split(np.asarray(engine.design_x))[0])
    unc = ctx.config.uncertainty
    infeasible = {}
    if unc.clearance is not None:
        infeasible = {"rule": unc.clearance.infeasible_rule, "minimum_clearance_m": unc.clearance.minimum,
                      "probability_below_minimum": unc.clearance.infeasible_probability()}
    infeasible["failed_calls"] = int(engine.n_failed_calls)
    infeasible["failure_reasons"] = {str(k): v for k, v in engine.failure_reasons.items()}
    return ReliabilityStudyResult(
        cycles=cycles, reliability=reliability, pf=pf, pf_cov=pf_cov,
        below_floor=pf < rel.pf_floor, target=rel.target_reliability,
        pf_error=np.asarray(engine.error_estimate, dtype=float) * pf,
        life_cycles=life, life_hours=None if life is None else cycles_to_hours(life, ctx.config),
        model_calls=int(engine.n_calls), failed_calls=int(engine.n_failed_calls), n_mc=n_mc,
        converged=bool(engine.converged), wall_seconds=time.perf_counter() - t0, names=ctx.names,
        histograms=histograms, mean_max_wear=mean_max, convergence=convergence,
        design_x=np.asarray(engine.design_x), design_wear=design_wear, engine=engine, infeasible=infeasible,
        wear_surrogates=wear_model)


def _meet_cov_target(ctx: StudyContext, engine, pf, pf_cov, n_mc):
    """Grow the Monte Carlo population on the final surrogate until COV(Pf) < target at every level above
    the floor (AK-MCS Step 6). The engine does this itself when its learning converges; when the call budget
    ends the learning first, the population is grown here, on the last surrogate (no model call)."""
    from jointwear.reliability import IsoTransform

    rel = ctx.config.reliability
    need = (pf >= rel.pf_floor) & ~(pf_cov < rel.cov_target)
    if not need.any():
        return pf, pf_cov, n_mc
    p = pf[need].min()
    n = int(min(rel.n_mc_max, 1.1 * ((1.0 - p) / (rel.cov_target**2 * p) + 1.0)))
    if n <= n_mc:
        return pf, pf_cov, n_mc
    iso = IsoTransform(ctx.marginals)
    # the study learns one response for every level (akmcs_multi(levels=...)): level j is level 0 minus a constant
    offsets = np.array([engine.surrogates[j].offset for j in range(len(ctx.cycles))])
    fails = np.zeros(len(ctx.cycles))
    rng_seed = rel.seed + 7
    done = 0
    chunk = 200_000
    while done < n:
        m = min(chunk, n - done)
        u = iso.to_u(population(ctx.marginals, m, rng_seed + done))
        mu0, _ = engine.surrogates[0].predict(u, return_variance=False)
        fails += np.count_nonzero(mu0[:, None] - (offsets[None, :] - offsets[0]) < 0, axis=0)
        done += m
    pf_new = fails / n
    with np.errstate(divide="ignore", invalid="ignore"):
        cov_new = np.where(pf_new > 0, np.sqrt((1.0 - pf_new) / ((n - 1) * pf_new)), np.inf)
    return pf_new, cov_new, n


def reference_level(cycles: Sequence[int]) -> int:
    """Index of the curve level that progress and convergence records follow: 400k cycles (the paper's
    headline), else the middle level."""
    return list(cycles).index(400_000) if 400_000 in cycles else len(cycles) // 2


def _at(value, index: int) -> float:
    arr = np.atleast_1d(np.asarray(value, dtype=float))
    return float(arr[min(index, arr.size - 1)]) if arr.size else float("nan")


# ---------------------------------------------------------------------------------------------
# sensitivity
# ---------------------------------------------------------------------------------------------
PAPER_RANKINGS = {
    "tolerance": ["l2", "c", "Rj", "l1", "lBC"],
    "journal_material": ["HB_j", "E_j", "k_j", "nu_j"],
    "bearing_material": ["HB_b", "k_b", "E_b", "nu_b"],
}


def run_sensitivity(ctx: StudyContext, reliability: ReliabilityStudyResult) -> dict:
    """Mean shifts (paper Figs. 22-24), Sobol' indices and reliability derivatives at one cycle count.

    Re-uses the reliability study's surrogate; see docs/sensitivity.md for the two rules:

    * a shift that stays inside the design's region (|shift| <= ``sensitivity.surrogate_shift_limit`` = 4
      sigma by default; the initial design spans +-5 sigma) is evaluated on the surrogate with a shifted Monte Carlo population (no model call);
    * a larger shift (the geometric means moved by 20 % are hundreds of standard deviations away) is
      evaluated by the *separable scaling* rule: one true-model call at the shifted nominal point and one at
      the nominal point give the ratio rho of the max wear, and the reliability is P(rho * delta_max(x) <
      delta_0) over the nominal population. A shifted mechanism that cannot run (e.g. a rod too short to
      close the loop) has reliability 0, with its reason reported.
    """
    from jointwear.reliability import IsoTransform, esc_absolute_error
    from jointwear.sensitivity import (
        mean_shift_table,
        reliability_derivatives,
        sobol_indices,
        unresolved_pairs,
    )

    sens = ctx.config.sensitivity
    rel = ctx.config.reliability
    if sens.cycles not in ctx.cycles:
        raise ConfigError(f"sensitivity.cycles: {sens.cycles} is not on the R(N) curve grid {ctx.cycles}")
    col = ctx.cycles.index(sens.cycles)
    engine = reliability.engine
    n_pop = min(max(engine.n_mc, 100_000), 400_000)
    pop = population(ctx.marginals, n_pop, rel.seed + 2)

    iso = IsoTransform(ctx.marginals)

    def log_life_margin(x):
        """ln N_f(x) - ln N_s from the learned life surrogate (failure where < 0) and its Kriging standard
        deviation."""
        mu, var = engine.surrogates[col].predict(iso.to_u(x))
        return mu, np.sqrt(np.maximum(var, 0.0))

    margin_nominal_pop, margin_sd_nominal_pop = log_life_margin(pop)
    r_nominal = float(np.mean(margin_nominal_pop > 0))
    r_nominal_error = esc_absolute_error(margin_nominal_pop, margin_sd_nominal_pop)
    wear_col = reliability.wear_surrogates.cycles.index(sens.cycles)

    n_model = len(ctx.targets)
    means = np.array([m.mean() for m in ctx.marginals[:n_model]])
    hist_col = ctx.history_cycles.index(sens.cycles)
    known_before = ctx.n_evaluated

    def true_wear(x_point: np.ndarray) -> float:
        """Max wear at the sensitivity's cycle count by a true-model call (cached by the study context)."""
        return float(ctx.wear(x_point[None, :])[0, hist_col])

    rules: list[dict] = []

    def reliability_of(marginals):
        changed = [i for i, (a, b) in enumerate(zip(marginals, ctx.marginals)) if a is not b]
        if not changed:
            return r_nominal, 0
        i = changed[0]
        shift = marginals[i].mean() - ctx.marginals[i].mean()
        sigma = ctx.marginals[i].std()
        if abs(shift) <= sens.surrogate_shift_limit * sigma:
            shifted_pop = pop.copy()
            shifted_pop[:, i] = population([marginals[i]], n_pop, rel.seed + 3 + i)[:, 0]
            mu, sd = log_life_margin(shifted_pop)
            r = float(np.mean(mu > 0))
            rules.append({"variable": ctx.names[i], "factor": marginals[i].mean() / ctx.marginals[i].mean(),
                          "rule": "surrogate", "reliability": r, "error_estimate": esc_absolute_error(mu, sd)})
            return r, 0
        before = ctx.n_evaluated
        base_wear = true_wear(means)
        x_s = means.copy()
        x_s[i] = marginals[i].mean()
        shifted_wear = true_wear(x_s)
        entry = {"variable": ctx.names[i], "factor": marginals[i].mean() / ctx.marginals[i].mean(),
                 "rule": "separable_scaling"}
        if not math.isfinite(shifted_wear):
            entry.update(reliability=0.0, reason="the shifted mechanism could not run (counted as failure)")
            rules.append(entry)
            return 0.0, ctx.n_evaluated - before
        rho = shifted_wear / base_wear
        # wear x rho <=> life / rho (the wear grows linearly in N): failure where ln N_f - ln rho < ln N_s
        mu = margin_nominal_pop - math.log(rho)
        r = float(np.mean(mu > 0))
        # the surrogate's error only (rho comes from two true-model calls)
        entry.update(reliability=r, wear_ratio=rho, error_estimate=esc_absolute_error(mu, margin_sd_nominal_pop))
        rules.append(entry)
        return r, ctx.n_evaluated - before

    table = mean_shift_table(reliability_of, ctx.marginals, ctx.names, ctx.labels, factors=tuple(sens.factors),
                             reliability_nominal=r_nominal)
    sobol = sobol_indices(lambda x: reliability.wear_surrogates.predict(x)[:, wear_col] * 1e3, ctx.marginals,
                          ctx.names, n_base=sens.sobol_base_samples, seed=rel.seed)
    deriv = reliability_derivatives(pop, margin_nominal_pop <= 0, ctx.marginals, ctx.names)
    groups = {}
    specs = ctx.config.uncertainty.all_specs()
    for spec in specs:
        groups.setdefault(spec.group, []).append(spec.name)
    ranking = table.ranking()
    ranking_by_group = {g: [n for n in ranking if n in members] for g, members in groups.items()}
    # error estimate of each shifted reliability (0 where the shifted mechanism could not run: R = 0 is exact)
    shift_error = {(e["variable"], round(e["factor"], 9)): e.get("error_estimate", 0.0) for e in rules}
    errors_low, errors_high, swing_error = [], [], {}
    for k, name in enumerate(ctx.names):
        lo_err = shift_error.get((name, round(sens.factors[0], 9)), 0.0)
        hi_err = shift_error.get((name, round(sens.factors[1], 9)), 0.0)
        errors_low.append(lo_err)
        errors_high.append(hi_err)
        lo, hi = table.reliability_low[k], table.reliability_high[k]
        swing_error[name] = lo_err if abs(lo - r_nominal) >= abs(hi - r_nominal) else hi_err
    unresolved = unresolved_pairs(ranking, dict(zip(ctx.names, table.swings())), swing_error, groups)
    variables = []
    for k, name in enumerate(ctx.names):
        variables.append({
            "name": name, "label": ctx.labels[k],
            "group": specs[k].group if k < len(specs) else "other",
            "reliability_low": table.reliability_low[k], "reliability_high": table.reliability_high[k],
            "reliability_low_error": errors_low[k], "reliability_high_error": errors_high[k],
            "dR_dmean": float(-deriv.dpf_dmean[k]), "dR_dstd": float(-deriv.dpf_dstd[k]),
            "elasticity_mean": float(-deriv.elasticity_mean[k]) if deriv.pf > 0 else 0.0,
            "S1": float(sobol.S1[k]), "ST": float(sobol.ST[k]),
        })
    return {
        "cycles": sens.cycles, "factors": list(sens.factors), "reliability_nominal": r_nominal,
        "reliability_nominal_error": r_nominal_error,
        "variables": variables, "ranking": ranking, "ranking_by_group": ranking_by_group,
        "unresolved_pairs": unresolved,
        "paper_ranking_by_group": PAPER_RANKINGS, "rules": rules,
        "extra_model_calls": ctx.n_evaluated - known_before,
        "sobol": sobol.as_dict(), "derivatives": deriv.as_dict(), "n_population": n_pop,
    }
