"""Cross-check methods with the same call and result as :func:`akmcs`: crude Monte Carlo, FORM (HL-RF with
finite-difference gradients), SORM (Breitung / Hohenbichler-Rackwitz with finite-difference curvatures),
subset simulation (modified Metropolis, Au & Beck 2001) and importance sampling around the FORM design
point. All work in standard-normal space u; failure is g < 0; the NaN rule is the one of
:mod:`jointwear.reliability.evaluation` (a failed call counts as failure). Every method takes how g is called
as one :class:`~jointwear.reliability.Evaluation` (``evaluation=``; default: g called directly).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np
from scipy.special import ndtr

from .checks import check_positive, check_positive_int, check_seed
from .evaluation import AllCallsFailedError, Evaluation, evaluation_or_default
from .inputs import IsoTransform, check_marginals
from .results import ReliabilityResult, mc_cov, pf_to_beta

__all__ = ["form", "importance_sampling", "monte_carlo", "sorm", "subset_simulation"]


def _setup(g, marginals, evaluation, *, nan_policy="failure", keep=True, copula=None):
    marginals = check_marginals(marginals)
    transform = IsoTransform(marginals, copula)
    ev = evaluation.caller_for(g, len(marginals), nan_policy=nan_policy, keep=keep)
    return marginals, transform, ev


def _g_u(ev, transform, u: np.ndarray) -> np.ndarray:
    return np.asarray(ev.evaluate(transform.to_x(u)), dtype=float).reshape(len(u))


def _failed(gv: np.ndarray) -> np.ndarray:
    """Failure indicator with the NaN rule: NaN counts as failure."""
    return ~(gv >= 0)


def _first_batch_check(gv: np.ndarray, ev, d: int) -> None:
    if gv.size and not np.isfinite(gv).any():
        reason = next(iter(getattr(ev, "failure_reasons", {}).values()), "g returned NaN")
        raise AllCallsFailedError(f"g returned NaN (or failed) for every point of the first batch ({reason}); check "
                                  f"g and that it expects X with one column per marginal ({d} marginals given)")


def _common(ev, transform, t0, keep=True):
    out = dict(n_calls=int(getattr(ev, "n_calls", 0)), n_failed_calls=int(getattr(ev, "n_failed_calls", 0)),
               failure_reasons=dict(getattr(ev, "failure_reasons", {})), wall_seconds=time.perf_counter() - t0)
    if keep and hasattr(ev, "design_x"):
        out["design_x"] = ev.design_x
        out["design_g"] = ev.design_g
    return out


def is_weights(u: np.ndarray, ustar: np.ndarray) -> np.ndarray:
    """Importance weights phi(u) / phi(u - u*) of a unit normal density centred at u*."""
    return np.exp(-u @ ustar + 0.5 * float(ustar @ ustar))


def is_estimate(fail: np.ndarray, w: np.ndarray) -> tuple[float, float]:
    """Importance-sampling estimate mean(w I[fail]) and its coefficient of variation (inf when it is 0)."""
    q = np.where(fail, w, 0.0)
    pf = float(q.mean())
    if pf <= 0.0:
        return 0.0, math.inf
    return pf, float(q.std(ddof=1) / (math.sqrt(q.size) * pf))


# ------------------------------------------------------------------------------------------ Monte Carlo
def monte_carlo(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    n: int = 100_000,
    *,
    copula=None,
    batch: int = 100_000,
    cov_target: float | None = None,
    n_max: int = 10_000_000,
    seed: int | None = 0,
    keep_design: bool = False,
    evaluation: Evaluation | None = None,
) -> ReliabilityResult:
    """Crude Monte Carlo: ``n`` samples in batches of ``batch``; with ``cov_target`` keep sampling (up to
    ``n_max``) until COV(Pf) < cov_target. ``keep_design`` stores every sample (memory!)."""
    t0 = time.perf_counter()
    n = check_positive_int("n", n, 2)
    batch = check_positive_int("batch", batch)
    cov_target = None if cov_target is None else check_positive("cov_target", cov_target)
    evaluation = evaluation_or_default(evaluation)
    progress = evaluation.progress
    marginals, transform, ev = _setup(g, marginals, evaluation, keep=keep_design, copula=copula)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    d = len(marginals)
    n_done = n_fail = 0
    target = n
    first = True
    while n_done < target:
        k = min(batch, target - n_done)
        gv = _g_u(ev, transform, rng.standard_normal((k, d)))
        if first:
            _first_batch_check(gv, ev, d)
            first = False
        n_fail += int(np.count_nonzero(_failed(gv)))
        n_done += k
        pf = n_fail / n_done
        cov = mc_cov(pf, n_done)
        if progress is not None:
            progress({"n_calls": n_done, "pf": pf, "cov": cov})
        if n_done >= target and cov_target is not None and not (cov < cov_target) and target < n_max:
            need = (1 - pf) / (cov_target**2 * pf) + 1 if pf > 0 else 2 * target
            target = int(min(n_max, max(need * 1.05, target + batch)))
    pf = n_fail / n_done
    cov = mc_cov(pf, n_done)
    conv = cov_target is None or cov < cov_target
    return ReliabilityResult(method="monte_carlo", pf=pf, cov=cov, beta=pf_to_beta(pf), converged=conv, n_mc=n_done,
                             **_common(ev, transform, t0, keep_design))


# ------------------------------------------------------------------------------------------ FORM
def _gradient(ev, transform, u: np.ndarray, g0: float, h: float) -> np.ndarray:
    d = u.size
    pts = u[None, :] + h * np.eye(d)
    gv = _g_u(ev, transform, pts)
    return (gv - g0) / h


def form(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    u0: np.ndarray | None = None,
    tol: float = 1e-6,
    max_iter: int = 100,
    fd_step: float = 1e-5,
    evaluation: Evaluation | None = None,
) -> ReliabilityResult:
    """FORM by the improved HL-RF algorithm (Zhang & Der Kiureghian 1995: HL-RF direction, Armijo step on the
    merit 0.5|u|^2 + c|g|), forward finite-difference gradients in u (``fd_step``: standard deviations).

    ``pf = Phi(-beta)``, ``beta = sign(g(0)) |u*|``; ``design_point_u``/``_x`` and ``alpha = u*/beta`` (the
    unit vector towards failure) are returned; ``cov`` is NaN. A NaN during the search raises (gradients of
    a failed point mean nothing), unless ``Evaluation(nan_policy="failure")`` - then the step is halved.
    """
    t0 = time.perf_counter()
    tol = check_positive("tol", tol)
    max_iter = check_positive_int("max_iter", max_iter)
    fd_step = check_positive("fd_step", fd_step)
    marginals, transform, ev = _setup(g, marginals, evaluation_or_default(evaluation), nan_policy="raise",
                                      copula=copula)
    d = len(marginals)
    u = np.zeros(d) if u0 is None else np.asarray(u0, dtype=float).ravel()
    if u.size != d:
        raise ValueError(f"u0 has {u.size} components but there are {d} marginals")
    g_origin = None
    gu = float(_g_u(ev, transform, u[None, :])[0])
    if not np.isfinite(gu):
        raise ValueError("g is NaN at the FORM starting point")
    if u0 is None:
        g_origin = gu
    scale_g = abs(gu) if gu != 0 else 1.0
    converged = False
    history = []
    grad = _gradient(ev, transform, u, gu, fd_step)
    for it in range(max_iter):
        gn = float(np.linalg.norm(grad))
        if not np.isfinite(gn) or gn == 0:
            raise ValueError(f"FORM: gradient of g is {'zero' if gn == 0 else 'not finite'} at u = {u.tolist()}")
        # HL-RF target point
        u_new = (grad @ u - gu) / gn**2 * grad
        direction = u_new - u
        c = 2.0 * max(np.linalg.norm(u) / gn, 1.0) * 1.0
        merit = lambda uu, gg: 0.5 * uu @ uu + c * abs(gg) / 1.0
        m0 = merit(u, gu)
        step = 1.0
        while True:
            u_try = u + step * direction
            g_try = float(_g_u(ev, transform, u_try[None, :])[0])
            if np.isfinite(g_try) and (merit(u_try, g_try) <= m0 - 1e-4 * step * float(direction @ direction)
                                       or step < 1e-3):
                break
            step *= 0.5
            if step < 1e-6:
                raise ValueError("FORM: line search failed (g not finite along the search direction)")
        du = float(np.linalg.norm(u_try - u))
        u, gu = u_try, g_try
        history.append({"iteration": it, "beta": float(np.linalg.norm(u)), "g": gu, "step": step})
        grad = _gradient(ev, transform, u, gu, fd_step)
        if du <= tol * max(1.0, float(np.linalg.norm(u))) and abs(gu) <= max(tol * scale_g, 1e-12):
            converged = True
            break
    if g_origin is None:
        g_origin = float(_g_u(ev, transform, np.zeros((1, d)))[0])
    beta = float(np.linalg.norm(u)) * (1.0 if g_origin >= 0 else -1.0)
    pf = float(ndtr(-beta))
    message = ""
    if not converged:
        message = (f"FORM did not converge in {max_iter} iterations: g = {gu:.4g} at the last point (|u| = "
                   f"{np.linalg.norm(u):.4g}) against g = {scale_g:.4g} at the start")
        if abs(gu) > 1e-3 * scale_g:  # not on the limit state: no design point, and Phi(-|u|) means nothing
            message += "; the search never reached g = 0 (a g that is never 0 has no design point), so pf is NaN"
            pf, beta = math.nan, math.nan
    gn = float(np.linalg.norm(grad))
    alpha = -grad / gn
    res = ReliabilityResult(method="form", pf=pf, cov=float("nan"), beta=beta, converged=converged, message=message,
                            design_point_u=u.copy(), design_point_x=transform.to_x(u[None, :])[0], alpha=alpha,
                            details={"grad_u": grad, "iterations": history, "g_at_design_point": gu},
                            **_common(ev, transform, t0))
    return res


# ------------------------------------------------------------------------------------------ SORM
def sorm(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    form_result: ReliabilityResult | None = None,
    fd_step: float = 1e-3,
    evaluation: Evaluation | None = None,
    **form_kwargs,
) -> ReliabilityResult:
    """SORM at the FORM design point: principal curvatures from a central finite-difference Hessian in u
    (``fd_step``), rotated so that the last axis is alpha; ``pf`` is Breitung's
    Phi(-beta) prod (1 + beta k_i)^-1/2; Hohenbichler-Rackwitz (beta -> phi(beta)/Phi(-beta)) and the FORM value
    are in ``details``. Curvatures are positive when the failure domain bends away from the origin."""
    t0 = time.perf_counter()
    marginals = check_marginals(marginals)
    evaluation = evaluation_or_default(evaluation)
    if form_result is None:
        form_result = form(g, marginals, copula=copula, evaluation=evaluation, **form_kwargs)
    if not math.isfinite(form_result.beta):
        raise ValueError(f"SORM needs FORM's design point: {form_result.message}")
    _, transform, ev = _setup(g, marginals, evaluation, nan_policy="raise", copula=copula)
    d = len(marginals)
    u = form_result.design_point_u
    beta = form_result.beta
    h = check_positive("fd_step", fd_step)
    # central differences: gradient and Hessian
    e = np.eye(d)
    pts = [u]
    for i in range(d):
        pts += [u + h * e[i], u - h * e[i]]
    for i in range(d):
        for j in range(i + 1, d):
            pts += [u + h * (e[i] + e[j]), u + h * (e[i] - e[j]), u - h * (e[i] - e[j]), u - h * (e[i] + e[j])]
    gv = _g_u(ev, transform, np.array(pts))
    if not np.all(np.isfinite(gv)):
        raise ValueError("SORM: g is not finite near the design point")
    g0 = gv[0]
    grad = np.array([(gv[1 + 2 * i] - gv[2 + 2 * i]) / (2 * h) for i in range(d)])
    hess = np.zeros((d, d))
    for i in range(d):
        hess[i, i] = (gv[1 + 2 * i] - 2 * g0 + gv[2 + 2 * i]) / h**2
    k = 1 + 2 * d
    for i in range(d):
        for j in range(i + 1, d):
            pp, pm, mp, mm = gv[k : k + 4]
            hess[i, j] = hess[j, i] = (pp - pm - mp + mm) / (4 * h * h)
            k += 4
    gn = float(np.linalg.norm(grad))
    alpha = -grad / gn  # towards failure
    q, _ = np.linalg.qr(np.column_stack([alpha, np.eye(d)[:, : d - 1]]) if d > 1 else alpha[:, None])
    basis = q[:, 1:d] if d > 1 else np.empty((d, 0))
    # g = -|grad| (t - beta) + 1/2 y^T B^T H B y  =>  failure t > beta + y^T (B^T H B / (2|grad|)) y
    curv_matrix = basis.T @ hess @ basis / gn
    kappa = np.linalg.eigvalsh(curv_matrix) if d > 1 else np.empty(0)
    pf_form = float(ndtr(-beta))
    with np.errstate(invalid="ignore", divide="ignore"):
        fac = 1.0 + beta * kappa
        pf_breitung = pf_form / math.sqrt(float(np.prod(fac))) if np.all(fac > 0) else float("nan")
        psi = math.exp(-0.5 * beta * beta) / math.sqrt(2 * math.pi) / pf_form
        fac_hr = 1.0 + psi * kappa
        pf_hr = pf_form / math.sqrt(float(np.prod(fac_hr))) if np.all(fac_hr > 0) else float("nan")
    common = _common(ev, transform, t0)
    common["n_calls"] += form_result.n_calls
    msg = "" if np.isfinite(pf_breitung) else "Breitung's formula is singular (1 + beta kappa <= 0)"
    return ReliabilityResult(method="sorm", pf=pf_breitung, cov=float("nan"), beta=pf_to_beta(pf_breitung),
                             converged=form_result.converged and np.isfinite(pf_breitung), design_point_u=u,
                             design_point_x=form_result.design_point_x, alpha=alpha, curvatures=kappa,
                             details={"pf_form": pf_form, "pf_breitung": pf_breitung, "pf_hohenbichler": pf_hr,
                                      "beta_form": beta, "hessian_u": hess, "form": form_result},
                             message=msg, **common)


# ------------------------------------------------------------------------------------------ subset simulation
def subset_simulation(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    n_per_level: int = 2000,
    p0: float = 0.1,
    max_levels: int = 20,
    proposal_scale: float = 1.0,
    seed: int | None = 0,
    evaluation: Evaluation | None = None,
) -> ReliabilityResult:
    """Subset simulation (Au & Beck 2001) with the component-wise modified Metropolis sampler.

    Intermediate thresholds are the p0-quantiles of g; every level runs n p0 chains of length 1/p0 in
    parallel, so each MCMC step is one vectorised call of g with n p0 rows. COV by Au & Beck's formula with
    the chain correlation factor gamma estimated from the indicator autocorrelation; it takes the levels as
    uncorrelated, so it is a lower bound. ``n_calls`` is at most n + (levels - 1) n (1 - p0) (a proposal that moves
    no component is not evaluated).
    """
    t0 = time.perf_counter()
    n = check_positive_int("n_per_level", n_per_level, 10)
    if not (0 < p0 < 0.5):
        raise ValueError(f"p0 must be in (0, 0.5); got {p0!r}")
    n_chains = int(round(n * p0))
    chain_len = int(round(1 / p0))
    if n_chains * chain_len != n:
        raise ValueError(f"n_per_level * p0 and 1 / p0 must be integers (n_per_level={n}, p0={p0})")
    evaluation = evaluation_or_default(evaluation)
    progress = evaluation.progress
    marginals, transform, ev = _setup(g, marginals, evaluation, copula=copula)
    d = len(marginals)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, d))
    gv = _g_u(ev, transform, u)
    _first_batch_check(gv, ev, d)
    gv = np.where(np.isfinite(gv), gv, -np.inf)  # NaN rule: failed call = failure (below every threshold)
    pf = 1.0
    delta2 = 0.0
    levels = []
    converged = False
    prev_chains = None  # (chain_len, n_chains) g values of the chains that produced the current samples

    def gamma_of(chains_g: np.ndarray | None, thr: float) -> float:
        """Au & Beck (2001) correlation factor of the indicator I(g <= thr) along the chains."""
        if chains_g is None:
            return 0.0
        ind = (chains_g <= thr).astype(float)
        p_hat = ind.mean()
        if not (0 < p_hat < 1):
            return 0.0
        r0 = p_hat * (1 - p_hat)
        gam = 0.0
        for k in range(1, chain_len):
            rk = float(np.mean(ind[:-k] * ind[k:])) - p_hat**2
            gam += 2 * (1 - k / chain_len) * rk / r0
        return max(gam, 0.0)

    for level in range(max_levels):
        order = np.argsort(gv, kind="stable")
        b = float(gv[order[n_chains - 1]] + gv[order[n_chains]]) / 2.0
        if b <= 0:  # final level: count failures directly
            pfl = float(np.mean(gv < 0))
            gamma = gamma_of(prev_chains, 0.0 - 1e-300)
            delta2 += (1 - pfl) / (n * pfl) * (1 + gamma) if pfl > 0 else math.inf
            pf *= pfl
            levels.append({"threshold": 0.0, "p": pfl, "gamma": gamma})
            converged = True
            break
        gamma = gamma_of(prev_chains, b)
        pf *= p0
        delta2 += (1 - p0) / (n * p0) * (1 + gamma)
        seeds_u = u[order[:n_chains]]
        seeds_g = gv[order[:n_chains]]
        # modified Metropolis: component-wise proposals, then accept if still in the intermediate domain
        chains_u = np.empty((chain_len, n_chains, d))
        chains_g = np.empty((chain_len, n_chains))
        chains_u[0], chains_g[0] = seeds_u, seeds_g
        cur_u, cur_g = seeds_u.copy(), seeds_g.copy()
        n_acc = 0
        for step in range(1, chain_len):
            cand = cur_u + proposal_scale * rng.standard_normal(cur_u.shape)
            ratio = np.exp(-0.5 * (cand**2 - cur_u**2))
            keep = rng.random(cur_u.shape) < np.minimum(1.0, ratio)
            cand = np.where(keep, cand, cur_u)
            moved = keep.any(axis=1)
            g_c = cur_g.copy()
            if moved.any():
                gc = _g_u(ev, transform, cand[moved])
                g_c[moved] = np.where(np.isfinite(gc), gc, -np.inf)
            accept = moved & (g_c <= b)
            cur_u = np.where(accept[:, None], cand, cur_u)
            cur_g = np.where(accept, g_c, cur_g)
            n_acc += int(accept.sum())
            chains_u[step], chains_g[step] = cur_u, cur_g
        u = chains_u.transpose(1, 0, 2).reshape(n, d)
        gv = chains_g.T.reshape(n)
        prev_chains = chains_g
        levels.append({"threshold": b, "p": p0, "gamma": gamma,
                       "acceptance": n_acc / (n_chains * (chain_len - 1))})
        if progress is not None:
            progress({"level": level, "threshold": b, "pf": pf, "n_calls": getattr(ev, "n_calls", None)})
    cov = math.sqrt(delta2) if np.isfinite(delta2) else math.inf
    msg = ("the COV takes the levels as uncorrelated (Au & Beck 2001): a lower bound, so the 95 % interval is "
           "narrower than the truth" if converged
           else f"max_levels={max_levels} reached before the failure threshold; pf is an upper bound")
    return ReliabilityResult(method="subset_simulation", pf=pf, cov=cov, beta=pf_to_beta(pf), converged=converged,
                             details={"levels": levels}, message=msg, **_common(ev, transform, t0))


# ------------------------------------------------------------------------------------------ importance sampling
def importance_sampling(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    n: int = 10_000,
    form_result: ReliabilityResult | None = None,
    seed: int | None = 0,
    evaluation: Evaluation | None = None,
    **form_kwargs,
) -> ReliabilityResult:
    """Importance sampling with a unit normal density centred at the FORM design point u*:
    pf = mean(I[g < 0] phi(u) / phi(u - u*)). ``n_calls`` includes the FORM calls. One centre: a failure region
    far from u* is missed by both the estimate and its COV (its ``message`` says so)."""
    t0 = time.perf_counter()
    n = check_positive_int("n", n, 2)
    marginals = check_marginals(marginals)
    evaluation = evaluation_or_default(evaluation)
    if form_result is None:  # the search keeps FORM's own NaN policy (a NaN gradient means nothing)
        form_result = form(g, marginals, copula=copula, evaluation=replace(evaluation, nan_policy=None),
                           **form_kwargs)
    _, transform, ev = _setup(g, marginals, evaluation, copula=copula)
    d = len(marginals)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    ustar = form_result.design_point_u
    u = ustar[None, :] + rng.standard_normal((n, d))
    gv = _g_u(ev, transform, u)
    _first_batch_check(gv, ev, d)
    pf, cov = is_estimate(_failed(gv), is_weights(u, ustar))
    common = _common(ev, transform, t0)
    common["n_calls"] += form_result.n_calls
    msg = ("sampled around one design point: a failure region away from it is missed, and the COV does not see it "
           "(several failure regions: subset_simulation or akmcs)")
    return ReliabilityResult(method="importance_sampling", pf=pf, cov=cov, beta=pf_to_beta(pf), converged=pf > 0,
                             design_point_u=ustar, design_point_x=form_result.design_point_x,
                             alpha=form_result.alpha, details={"form": form_result}, message=msg, **common)
