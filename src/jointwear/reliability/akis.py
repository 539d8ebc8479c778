"""AK-IS: active-learning Kriging + importance sampling, for small failure probabilities
(Echard, Gayton, Lemaire & Relun 2013, Reliab. Eng. Syst. Saf. 111:232-240).

AK-MCS needs a candidate population of about 400 / Pf points (COV 5 %): 4e9 for Pf = 1e-7, beyond any
memory. AK-IS classifies an importance-sampling population instead, which needs about as many points at
Pf = 1e-7 as crude Monte Carlo at Pf = 0.1:

1. FORM (improved HL-RF, :func:`jointwear.reliability.form`) finds the design point u*; its model calls are
   the initial design (points closer than ``min_distance`` to an earlier one are dropped: the finite-difference
   pairs would make the Kriging correlation matrix singular), completed to ``n_initial`` points by a Latin
   hypercube in [u* - b, u* + b] (b = ``initial_bound``).
2. Population u_i = u* + z_i, z_i ~ N(0, I), weights w_i = phi(u_i) / phi(u_i - u*) = exp(-u_i . u* + |u*|^2 / 2).
3. Fit the Kriging, predict mean and standard deviation on the population, U = |mu| / s (evaluated points: their
   true sign), Pf = mean(w I[mu < 0]), COV = std(w I[mu < 0]) / (sqrt(N) Pf).
4. Learning stop: min U >= ``u_threshold`` (2, as in AK-MCS). Otherwise evaluate the lowest-U candidate(s)
   (``batch_size``, spread by k-means as in AK-MCS) and go to 3.
5. When learned: if COV >= ``cov_target``, grow the population (+10 % over the size the COV formula asks for)
   and go to 3; otherwise done.

The estimator is unbiased for any u* (the weights are exact); FORM only decides how efficient it is. A second
failure region far from u* would be missed by the sampling density, as with any single-point IS: use
subset simulation (:func:`jointwear.reliability.subset_simulation`) when one is suspected.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np
from scipy.stats import qmc

from .checks import check_positive, check_positive_int, check_seed
from .evaluation import Evaluation, evaluation_or_default
from .inputs import IsoTransform, check_marginals
from .kriging import KrigingSurrogate
from .learning import needs_optimisation, select_batch, u_function
from .methods import form, is_estimate, is_weights
from .results import IterationRecord, ReliabilityResult, pf_to_beta

__all__ = ["akis"]


def _thin(u: np.ndarray, g: np.ndarray, min_distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Keep the first of points closer than min_distance to each other (in u)."""
    keep: list[int] = []
    for i in range(u.shape[0]):
        if all(np.linalg.norm(u[i] - u[j]) >= min_distance for j in keep):
            keep.append(i)
    return u[keep], g[keep]


def akis(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    n_is: int = 10_000,
    n_is_max: int = 2_000_000,
    form_result: ReliabilityResult | None = None,
    n_initial: int | None = None,
    initial_bound: float = 1.5,
    min_distance: float = 1e-3,
    batch_size: int = 1,
    u_threshold: float = 2.0,
    cov_target: float = 0.05,
    max_calls: int = 500,
    seed: int | None = 0,
    evaluation: Evaluation | None = None,
    kriging: dict | None = None,
    form_kwargs: dict | None = None,
) -> ReliabilityResult:
    """AK-IS estimate of Pf = P[g(X) < 0] (small Pf), same call and result as :func:`akmcs`.

    Parameters
    ----------
    n_is, n_is_max:
        Initial and largest importance-sampling population (candidates).
    form_result:
        A FORM result to start from (its design point and, when it kept them, its evaluated points);
        default: run :func:`form` with ``form_kwargs`` through the same caller. Its default tolerance here is
        1e-2, not 1e-6: the estimator is unbiased for any centre, a rough design point only costs a little
        efficiency, and HL-RF converges slowly on curved limit states (cubic_parabolic: 21 calls at 1e-2,
        202 at 1e-6 for a design point 0.02 sigma away).
    n_initial:
        Size of the initial design: FORM's distinct points completed by a Latin hypercube around u*;
        default max(12, 2 d + 2) as in AK-MCS.
    initial_bound:
        Half-width (in standard deviations) of that Latin hypercube around u*.
    min_distance:
        FORM points closer than this (in u) to an earlier one are not used for the Kriging.

    Notes
    -----
    Other parameters as :func:`akmcs`. ``n_calls`` counts the FORM calls; ``details["form"]`` is the FORM result.
    """
    t_start = time.perf_counter()
    marginals = check_marginals(marginals)
    d = len(marginals)
    n_is = check_positive_int("n_is", n_is, 2)
    n_is_max = max(n_is, check_positive_int("n_is_max", n_is_max, 2))
    n_initial = check_positive_int("n_initial", max(12, 2 * d + 2) if n_initial is None else n_initial, 2)
    batch_size = check_positive_int("batch_size", batch_size)
    u_threshold = check_positive("u_threshold", u_threshold)
    cov_target = check_positive("cov_target", cov_target)
    initial_bound = check_positive("initial_bound", initial_bound)
    min_distance = check_positive("min_distance", min_distance)
    max_calls = check_positive_int("max_calls", max_calls, 2)

    evaluation = evaluation_or_default(evaluation)
    progress = evaluation.progress
    ev = evaluation.caller_for(g, d)
    transform = IsoTransform(marginals, copula)
    if form_result is None:  # FORM calls g through the same caller: one design, one call count
        form_result = form(g, marginals, copula=copula, evaluation=replace(evaluation, caller=ev),
                           **{"tol": 1e-2, **(form_kwargs or {})})
    ustar = np.asarray(form_result.design_point_u, dtype=float).ravel()
    if ustar.size != d:
        raise ValueError(f"form_result has a {ustar.size}-dimensional design point but there are {d} marginals")
    n_form = int(form_result.n_calls)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)

    # ---- initial design: FORM's distinct points + a Latin hypercube around u*
    if form_result.design_x is not None and form_result.design_g is not None and len(form_result.design_x):
        du = transform.to_u(np.asarray(form_result.design_x, dtype=float))
        dg = np.asarray(form_result.design_g, dtype=float).reshape(-1)
        ok = np.isfinite(dg)
        design_u, design_g = _thin(du[ok], dg[ok], min_distance)
    else:
        design_u, design_g = np.empty((0, d)), np.empty(0)
    n_lhs = max(0, min(n_initial - design_u.shape[0], max_calls - n_form))
    if n_lhs:
        lhs = qmc.LatinHypercube(d=d, seed=rng).random(n_lhs)
        new_u = ustar[None, :] + (2.0 * lhs - 1.0) * initial_bound
        new_g = np.asarray(ev.evaluate(transform.to_x(new_u)), dtype=float).reshape(n_lhs)
        design_u = np.vstack([design_u, new_u])
        design_g = np.concatenate([design_g, new_g])
    n_own = n_lhs  # calls made by AK-IS itself (FORM's are counted separately)

    u_pop = ustar[None, :] + rng.standard_normal((n_is, d))
    w_pop = is_weights(u_pop, ustar)
    known = np.zeros(n_is, dtype=bool)
    known_g = np.full(n_is, np.nan)
    surrogate = KrigingSurrogate(seed=None if seed is None else int(seed), **dict(kriging or {}))
    history: list[IterationRecord] = []
    converged = False
    message = ""
    iteration = 0
    n_at_opt = 0
    force_opt = False
    while True:
        ok = np.isfinite(design_g)
        if int(ok.sum()) < 2:
            raise ValueError("fewer than 2 finite g values in the design; cannot fit Kriging")
        n_ok = int(ok.sum())
        optimize = needs_optimisation(force_opt, n_at_opt, n_ok, 0.1)
        surrogate.fit(design_u[ok], design_g[ok], optimize=optimize)
        if optimize:
            n_at_opt = n_ok
        force_opt = False
        mu, var = surrogate.predict(u_pop)
        U = u_function(mu, np.sqrt(var))
        fail = mu < 0
        U[known] = np.inf
        fail[known] = ~(known_g[known] >= 0)  # NaN -> failure (conservative)
        pf, cov = is_estimate(fail, w_pop)
        min_u = float(U.min())
        rec = IterationRecord(iteration=iteration, n_calls=n_form + n_own, n_mc=int(u_pop.shape[0]), pf=pf, cov=cov,
                              min_u=min_u, error=float("nan"), wall_seconds=time.perf_counter() - t_start)
        history.append(rec)
        if progress is not None:
            progress(rec)
        iteration += 1
        if min_u >= u_threshold:
            if n_at_opt != n_ok:  # accept only a surrogate with freshly optimised hyperparameters
                force_opt = True
                continue
            if cov < cov_target:
                converged = True
                message = "converged"
                break
            n_pop = u_pop.shape[0]
            if n_pop >= n_is_max:
                message = f"COV target {cov_target} not met with the maximum population n_is_max={n_is_max}"
                break
            target = (cov / cov_target) ** 2 * n_pop if math.isfinite(cov) else 4.0 * n_pop
            new_n = int(min(n_is_max, max(1.1 * target, 1.2 * n_pop)))
            extra = ustar[None, :] + rng.standard_normal((new_n - n_pop, d))
            u_pop = np.vstack([u_pop, extra])
            w_pop = np.concatenate([w_pop, is_weights(extra, ustar)])
            known = np.concatenate([known, np.zeros(extra.shape[0], dtype=bool)])
            known_g = np.concatenate([known_g, np.full(extra.shape[0], np.nan)])
            continue
        if n_form + n_own >= max_calls:
            message = f"max_calls={max_calls} reached before the learning criterion was met"
            break
        k = min(batch_size, max_calls - n_form - n_own)
        sel = select_batch(U, u_pop, k, u_threshold, rng, known)
        if sel.size == 0:
            message = "no candidate left to evaluate"
            break
        gv = np.asarray(ev.evaluate(transform.to_x(u_pop[sel])), dtype=float).reshape(sel.size)
        known[sel] = True
        known_g[sel] = gv
        design_u = np.vstack([design_u, u_pop[sel]])
        design_g = np.concatenate([design_g, gv])
        n_own += sel.size

    return ReliabilityResult(
        method="akis", pf=pf, cov=cov, beta=pf_to_beta(pf), n_calls=n_form + n_own, converged=converged,
        design_x=transform.to_x(design_u), design_g=design_g, design_u=design_u,
        n_failed_calls=int(getattr(ev, "n_failed_calls", 0)), failure_reasons=dict(getattr(ev, "failure_reasons", {})),
        history=history, surrogate=surrogate, n_mc=int(u_pop.shape[0]), design_point_u=ustar,
        design_point_x=form_result.design_point_x, alpha=form_result.alpha,
        details={"form": form_result, "min_u": min_u, "n_form_calls": n_form}, message=message,
        wall_seconds=time.perf_counter() - t_start,
    )
