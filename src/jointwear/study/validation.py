"""Direct validation of the R(N) curve against the true wear model, sampled directly.

N fresh random samples (a seed the study's populations do not use) each make one true-model call; the
reliability at every level is then the binomial proportion of samples whose wear life exceeds it, with an
exact (Clopper-Pearson) 95 % interval. The surrogate's curve agrees at a level when the two estimates differ
by less than the sum of their 95 % half-widths (the binomial interval's, the surrogate curve's Monte Carlo
interval and its own error estimate). The surrogate is also cross-validated: the leave-one-out prediction of
each design point's log life against its true value, with the Q^2 score.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy import stats

from jointwear.study.limit_state import bounded_ends, curve_cycles, intervals_overlap, life_at
from jointwear.study.reliability import StudyContext, kriging_options, life_offset, life_scatter_sd
from jointwear.study.reliability_results import SurrogateFit
from jointwear.study.results import ReliabilityCurve, ValidationResult

#: Offset of the validation samples' seed from the study's seed (the study's own draws use seed + 0..7).
SEED_OFFSET = 1000
#: Bootstrap resamples of the paired check (its 2.5 % and 97.5 % percentiles then rest on 25 resamples each)
PAIRED_RESAMPLES = 1000


def clopper_pearson(k: float, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact (Clopper-Pearson) confidence interval of a proportion k / n: the beta quantiles
    B(a/2; k, n - k + 1) and B(1 - a/2; k + 1, n - k), as ``scipy.stats.binomtest(k, n).proportion_ci(method="exact")``
    for a count, and continued to an expected count ``k`` (a sum of probabilities)."""
    a = 1.0 - level
    low = 0.0 if k <= 0 else float(stats.beta.ppf(a / 2, k, n - k + 1))
    high = 1.0 if k >= n else float(stats.beta.ppf(1 - a / 2, k + 1, n - k))
    return low, high


def leave_one_out(ctx: StudyContext, reliability: ReliabilityCurve, seed: int) -> dict:
    """Leave-one-out predictions of ln N_f at the design points by the surrogate behind R(N) (its hyperparameters
    kept: :meth:`~jointwear.reliability.KrigingSurrogate.leave_one_out`), with its Q^2 (the reliability stage's
    ``surrogate_fit``); the smallest joint's prediction when the study learns one Kriging per joint. A result read
    back from disk holds no surrogate: a Kriging is then fitted anew to the design points."""
    from jointwear.reliability import KrigingSurrogate, SeriesSurrogate

    design_x = np.asarray(reliability.design_x, dtype=float)
    engine = reliability.engine
    if engine is not None:
        full, shift = engine.response_surrogate, float(engine.levels[0])  # fitted to ln N_f - ln N_1
    else:
        u = ctx.iso().to_u(design_x)
        options = kriging_options(ctx.config)
        shift = 0.0
        if ctx.per_joint:
            lives = ctx.log_joint_lives(design_x)
            full = SeriesSurrogate(lives.shape[1], seed=seed, **options).fit(u, lives)
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                y = np.log(ctx.life(design_x))
            ok = np.isfinite(y)
            full = KrigingSurrogate(seed=seed, offset=life_offset(ctx), **options).fit(u[ok], y[ok])
    pred, var = full.leave_one_out()
    fit = SurrogateFit.of(full, loo=pred)
    y = full.training_outputs
    return {"log_life_true": (y + shift).tolist(), "log_life_loo": (pred + shift).tolist(),
            "log_life_loo_sd": np.sqrt(var).tolist(), "q2": fit.q2, "rmse_log_life": fit.rmse_log_life,
            "n_points": fit.n_points, "n_failed_points": int(design_x.shape[0] - y.size)}


def run_validation(ctx: StudyContext, reliability: ReliabilityCurve, n_samples: int) -> ValidationResult:
    """The true model on ``n_samples`` fresh samples against the surrogate's R(N)."""
    t0 = time.perf_counter()
    rel = ctx.config.reliability
    before = ctx.n_model_calls
    x = ctx.sample(n_samples, rel.seed + SEED_OFFSET)
    life = ctx.life(x)
    calls = ctx.n_model_calls - before  # new calls only: a resumed validation reads its samples back
    failed = np.isnan(life)
    levels = np.asarray(ctx.cycles, dtype=float)
    p_inf = ctx.config.uncertainty.infeasible_probability()
    r_mc, lo, hi = true_reliability(life, levels, p_inf)
    r_sur = np.asarray(reliability.reliability, dtype=float)
    agree = agreement(r_mc, lo, hi, r_sur, reliability.half_width).tolist()
    cv = leave_one_out(ctx, reliability, seed=rel.seed)
    # the true model's life is read between the levels too, where the study reads its own (each sample's life is
    # known: its curve is exact at any N)
    fine = curve_cycles(levels)
    true_fine = true_reliability(life, fine, p_inf)
    life_table = [life_check(fine, *true_fine, reliability, float(row["target"]), n_samples=int(n_samples))
                  for row in reliability.life_table]
    joints = joint_checks(ctx, reliability, x, levels) if len(ctx.limit_state.joints) > 1 else []
    tested = [float(row["target"]) for row in life_table if row["cycles"] is not None]  # targets these samples resolve
    paired = paired_check(ctx, reliability, x, life, fine, p_inf, tested, seed=int(rel.seed + SEED_OFFSET))
    paired_fields = {}
    if paired is not None:
        at_levels = np.searchsorted(fine, levels)
        paired_fields = {"paired_reliability_surrogate": paired.r_surrogate[at_levels],
                         "paired_difference_low": paired.difference_low[at_levels],
                         "paired_difference_high": paired.difference_high[at_levels]}
        for row in life_table:
            row.update(paired.lives.get(float(row["target"]), {}))
    return ValidationResult(
        cycles=levels, reliability_mc=r_mc.tolist(), ci_low=lo.tolist(), ci_high=hi.tolist(),
        reliability_surrogate=r_sur,
        surrogate_error=reliability.pf_error,  # NaN where not estimated, not 0
        surrogate_cov=reliability.pf_cov,
        agreement=agree, n_samples=int(n_samples), model_calls=int(calls), failed_calls=int(failed.sum()),
        seed=int(rel.seed + SEED_OFFSET), cross_validation=cv, life_table=life_table, joints=joints,
        names=list(ctx.names), units=list(ctx.units), sample_x=x, sample_life=life,
        wall_seconds=time.perf_counter() - t0, **paired_fields)


@dataclass
class PairedCheck:
    """The surrogate's R(N) on the validation's samples (``r_surrogate``, at the curve's cycle counts) and the 95 %
    bounds of its difference from the true model's on the same samples (``difference_low``, ``_high``); ``lives``:
    at each target, the surrogate's life on these samples and its ratio to the true model's less 1 with 95 % bounds
    (None where a life lies outside the curve, the bounds also where any resample's does)."""

    r_surrogate: np.ndarray
    difference_low: np.ndarray
    difference_high: np.ndarray
    lives: dict[float, dict]


def paired_check(ctx: StudyContext, reliability: ReliabilityCurve, x: np.ndarray, life: np.ndarray,
                 cycles: np.ndarray, p_inf: float, targets: list[float], seed: int) -> PairedCheck | None:
    """The true model (its ``life`` at the samples ``x``) against the study's surrogate at the same samples, at
    ``cycles`` and for the life at ``targets``: the sampling noise the two share cancels in their difference, which
    then measures the surrogate's own error (its classification, or with a call-to-call scatter its failure
    probability Phi((ln N - mu(x)) / s), as R(N) counts it). 95 % bounds from ``PAIRED_RESAMPLES`` paired bootstrap
    resamples of the samples (``scipy.stats.bootstrap``, percentile intervals; Efron & Tibshirani 1993). A failed call
    counts as a failure, and the 'fail' rule's infeasible mass ``p_inf`` is added to both curves, as
    :func:`true_reliability` and the study count them. None for a result read back from disk, which holds no
    surrogate."""
    engine = reliability.engine
    if engine is None or life.size < 2:
        return None
    cycles = np.asarray(cycles, dtype=float)
    p_surrogate = engine.failure_probabilities(ctx.iso().to_u(x), life_scatter_sd(ctx, engine),
                                               thresholds=np.log(cycles))
    fails = np.where(np.isnan(life)[:, None], True, life[:, None] <= cycles[None, :]).astype(float)

    def reliability_of(pf_feasible):
        return 1.0 - (p_inf + (1.0 - p_inf) * pf_feasible)

    def ratios(r_true, r_surrogate, target):
        """The surrogate's life over the true one less 1 for every curve (cycles along the first axis); NaN where
        either life lies outside the curve."""
        out = [np.nan if t is None or s is None else s / t - 1.0
               for t, s in ((life_at(cycles, a, target), life_at(cycles, b, target))
                            for a, b in zip(r_true.reshape(len(cycles), -1).T, r_surrogate.reshape(len(cycles), -1).T))]
        return np.reshape(out, r_true.shape[1:])

    def statistic(f, p, axis):
        """R_surrogate - R_true at every cycle count, then the life ratio at every target."""
        r_true, r_surrogate = reliability_of(f.mean(axis=axis)), reliability_of(p.mean(axis=axis))
        lives = np.reshape([ratios(r_true, r_surrogate, t) for t in targets], (len(targets), *r_true.shape[1:]))
        return np.concatenate([r_surrogate - r_true, lives])

    boot = stats.bootstrap((fails, p_surrogate), statistic, paired=True, vectorized=True, axis=0,
                           n_resamples=PAIRED_RESAMPLES, batch=20, method="percentile",
                           rng=np.random.default_rng(seed))
    low, high = boot.confidence_interval
    point = statistic(fails, p_surrogate, 0)
    r_surrogate = reliability_of(p_surrogate.mean(axis=0))
    lives = {}
    for k, target in enumerate(targets):
        ratio, lo, hi = (float(v[len(cycles) + k]) for v in (point, low, high))
        bounded = np.isfinite(lo) and np.isfinite(hi)
        lives[target] = {"paired_surrogate_cycles": life_at(cycles, r_surrogate, target),
                         "paired_ratio": ratio if np.isfinite(ratio) else None,
                         "paired_ratio_low": lo if bounded else None, "paired_ratio_high": hi if bounded else None}
    return PairedCheck(r_surrogate, low[:len(cycles)], high[:len(cycles)], lives)


def true_reliability(life: np.ndarray, cycles: np.ndarray, p_inf: float = 0.0
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """R at each of ``cycles`` of the true model sampled directly (the share of samples whose ``life`` is longer),
    with its exact 95 % interval (low, high). A failed call (NaN life) counts as a failure of the mechanism (the
    engine's rule): never as safe. The 'fail' rule adds the infeasible mass ``p_inf`` exactly: Pf = p + (1 - p)
    Pf(feasible)."""
    n = life.size
    fails = np.where(np.isnan(life)[:, None], True, life[:, None] <= np.asarray(cycles, dtype=float)[None, :])
    k = fails.sum(axis=0)
    bounds = np.array([clopper_pearson(int(f), n) for f in k]).reshape(-1, 2)
    pf, pf_lo, pf_hi = (p_inf + (1.0 - p_inf) * v for v in (k / n, bounds[:, 0], bounds[:, 1]))
    return 1.0 - pf, 1.0 - pf_hi, 1.0 - pf_lo


def agreement(r_mc, ci_low, ci_high, r_surrogate, half_surrogate) -> np.ndarray:
    """Where the true model's R (with its exact interval [``ci_low``, ``ci_high``]) and the surrogate's agree: their
    95 % intervals overlap, the difference within the surrogate's half-width plus the exact interval's side that faces
    the surrogate (its larger side let a surrogate beyond the shorter side agree without overlapping)."""
    r_mc, r_surrogate = np.asarray(r_mc, dtype=float), np.asarray(r_surrogate, dtype=float)
    half_mc = np.where(r_surrogate > r_mc, np.asarray(ci_high) - r_mc, r_mc - np.asarray(ci_low))
    return np.abs(r_mc - r_surrogate) <= half_mc + np.asarray(half_surrogate)


def joint_checks(ctx: StudyContext, reliability: ReliabilityCurve, x: np.ndarray, levels: np.ndarray) -> list[dict]:
    """Each judged joint's own R(N) on the validation's samples (their calls read back, no new one): the share of
    feasible samples whose joint life is longer, with its exact 95 % interval, beside the study's R(N) of that joint
    (``reliability.joints``), the largest difference and the levels where the study's lies inside the interval. A
    level agrees (``agreement``, ``levels_agree``) as the system's curve does: the two differ by less than the sum of
    their 95 % half-widths (the study's: ``half_width_95`` of the joint; results written without it have no
    agreement). A failed call counts as a failure of every joint."""
    lives = ctx.joint_lives(x)
    out = []
    for k, row in enumerate(reliability.joints):
        r_mc, lo, hi = true_reliability(lives[:, k], levels)
        r_sur = np.asarray(row.get("reliability", [np.nan] * levels.size), dtype=float)
        check = {"name": row["name"], "reliability_mc": r_mc.tolist(), "ci_low": lo.tolist(),
                 "ci_high": hi.tolist(), "reliability_surrogate": r_sur.tolist(),
                 "largest_difference": float(np.nanmax(np.abs(r_sur - r_mc))),
                 "levels_within_interval": int(np.sum((r_sur >= lo) & (r_sur <= hi)))}
        if "half_width_95" in row:
            half_sur = np.asarray(row["half_width_95"], dtype=float)
            agree = agreement(r_mc, lo, hi, r_sur, half_sur)
            check.update({"surrogate_half_width": half_sur.tolist(), "agreement": agree.tolist(),
                          "levels_agree": int(agree.sum())})
        out.append(check)
    return out


def life_check(levels, r_mc, ci_low, ci_high, reliability: ReliabilityCurve, target: float,
               n_samples: int | None = None) -> dict:
    """The life at ``target`` read on the true model's curve, with the interval where its exact 95 % bounds
    cross the target, beside the surrogate's life and interval; ``agree`` when the two intervals overlap (an
    end outside its curve bounded by its side: :func:`~jointwear.study.limit_state.interval_reach`).

    A target above what ``n_samples`` samples resolve (R = 1 observed reads as R >= 0.025^(1/n), about 1 - 3.7 / n)
    is not testable: the true model's life and ``agree`` are None and ``note`` says why."""
    s_life = reliability.life(target)
    s_low, s_high = reliability.life_interval(target)
    resolved = 1.0 if n_samples is None else clopper_pearson(n_samples, n_samples)[0]
    if target > resolved:
        return {"target": target, "cycles": None, "cycles_low": None, "cycles_high": None, "surrogate_cycles": s_life,
                "surrogate_cycles_low": s_low, "surrogate_cycles_high": s_high, "agree": None,
                "note": f"not testable: {n_samples:,} samples resolve R up to {resolved:.4g}"}
    life, low, high = (life_at(levels, r, target) for r in (r_mc, ci_low, ci_high))
    # an end outside its curve is bounded by its side (before the first level, beyond the last), not unbounded
    ends = bounded_ends(levels, ci_low, ci_high, target, low, high)
    return {"target": target, "cycles": life, "cycles_low": low, "cycles_high": high, "surrogate_cycles": s_life,
            "surrogate_cycles_low": s_low, "surrogate_cycles_high": s_high,
            "agree": intervals_overlap(*ends, *reliability.life_reach(target))}
