"""AK-MCS: active-learning Kriging + Monte Carlo simulation (Echard, Gayton & Lemaire 2011), extended.

Algorithm (standard-normal space u, x = T(u)):

1. Monte Carlo population of ``n_mc`` points u ~ N(0, I) (the candidates).
2. Initial design: ``n_initial`` Latin hypercube points, uniform in [-b, b]^d with b = ``initial_bound`` = 5
   (for normal inputs exactly the paper's [mu - 5 sigma, mu + 5 sigma]; for other marginals the same
   probability content), evaluated with the model.
3. Fit one ordinary Kriging per limit state (constant trend, Gaussian correlation; :mod:`.kriging`); for a
   series system one per component, the system judged by its weakest (AK-SYS, :mod:`.system`).
4. Predict mean mu and standard deviation s on the population; U = |mu| / s; Pf = share of candidates with
   mu < 0 (evaluated candidates use their true value; a failed call counts as failure).
5. Learning stop (``stopping``):
   * ``"u"`` (paper): min U >= ``u_threshold`` (2: probability of a wrong sign <= Phi(-2) = 2.3 % everywhere).
   * ``"error"`` (default): the estimated relative error of Pf caused by candidates whose sign may be wrong is below
     ``error_tol`` (ESC of Wang & Shafieezadeh 2019: the numbers of wrongly-safe and wrongly-failed candidates
     are Poisson-binomial with probabilities Phi(-U); their 95 % upper bounds N_sf, N_fs give
     eps = max(N_fs / (N_f - N_fs), N_sf / (N_f + N_sf))). It stops long before min U >= 2 once the remaining
     uncertain candidates cannot move Pf by more than the tolerance.
   Before stopping, a surrogate whose hyperparameters were carried over is re-optimised and re-checked. The stop
   must hold on ``hold_iterations`` successive designs (3; the points between are chosen as in step 6): a Kriging
   fitted to a dozen points can be sure of itself where it is wrong. On ``examples/api_example.py``'s 3-input limit
   state a stop on the first design where the rule holds left Pf 1.5 % off (median of 30 seeds, up to 7.4 %) against
   ``error_tol`` = 1 %; three successive designs kept all 30 within it, for 2 more calls
   (``benchmarks/esc_calibration.py``).
6. If not stopped: add ``batch_size`` points (lowest U; for k > 1 the lowest-U point of each of k k-means
   clusters of the uncertain candidates, so the batch is spread over the limit state and can run in
   parallel), evaluate, go to 3.
7. When stopped: if COV(Pf) = sqrt((1 - Pf) / ((N - 1) Pf)) >= ``cov_target``, grow the population to the size
   that meets it (+10 %) and go to 4; otherwise done.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
from scipy.stats import qmc

from .checks import check_positive, check_positive_int, check_seed
from .evaluation import AllCallsFailedError, Evaluation, evaluation_or_default
from .inputs import IsoTransform, check_marginals
from .kriging import KrigingSurrogate, ShiftedSurrogate
from .learning import (
    esc_errors,
    needs_optimisation,
    quantile_errors,
    select_batch,
    u_function,
)
from .results import (
    IterationRecord,
    MultiReliabilityResult,
    ReliabilityResult,
    mc_cov,
    pf_to_beta,
    population_size,
)
from .system import SeriesSurrogate

__all__ = ["akmcs", "akmcs_multi"]


def log_scales(surrogate) -> np.ndarray:
    """The log correlation lengths of a surrogate (of every component of a series system's), to tell when a refit
    moved them."""
    parts = getattr(surrogate, "fitted_components", [surrogate])
    return np.concatenate([np.log(p.hyperparameters.scale) for p in parts])


def _run(g, marginals, *, multi, n_mc, n_mc_max, n_initial, initial_bound, batch_size, u_threshold, cov_target,
         stopping, error_tol, max_calls, seed, evaluation, pf_floor, kriging, refit_growth, full_sweep_every=10,
         keep_population=False, levels=None, error_abs_tol=None, copula=None, system=None, hold_iterations=3,
         quantile_pf=(), quantile_tol=None, trend=None):
    t_start = time.perf_counter()
    marginals = check_marginals(marginals)
    d = len(marginals)
    n_mc = check_positive_int("n_mc", n_mc, 2)
    n_mc_max = max(n_mc, check_positive_int("n_mc_max", n_mc_max, 2))
    n_initial = check_positive_int("n_initial", max(12, 2 * d + 2) if n_initial is None else n_initial, 2)
    batch_size = check_positive_int("batch_size", batch_size)
    u_threshold = check_positive("u_threshold", u_threshold)
    cov_target = check_positive("cov_target", cov_target)
    initial_bound = check_positive("initial_bound", initial_bound)
    if stopping not in ("u", "error"):
        raise ValueError(f"stopping must be 'u' (min U >= u_threshold) or 'error' (ESC); got {stopping!r}")
    error_tol = check_positive("error_tol", error_tol)
    max_calls = check_positive_int("max_calls", max_calls, n_initial)
    hold_iterations = check_positive_int("hold_iterations", hold_iterations)
    if not (0.0 <= pf_floor < 1.0):
        raise ValueError(f"pf_floor must be in [0, 1); got {pf_floor!r}")

    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    transform = IsoTransform(marginals, copula)
    if levels is not None:
        levels = np.asarray(levels, dtype=float).reshape(-1)
        if levels.size < 1 or not np.all(np.isfinite(levels)):
            raise ValueError("levels must be a non-empty sequence of finite numbers")
    if system not in (None, "series"):
        raise ValueError(f"system must be None (one response) or 'series' (its components' minimum); got {system!r}")
    if system is not None and levels is None:
        raise ValueError("system='series' needs levels (the thresholds its response is compared with)")
    quantile_pf = [float(t) for t in np.atleast_1d(np.asarray(quantile_pf, dtype=float))]
    if quantile_tol is not None:
        quantile_tol = check_positive("quantile_tol", quantile_tol)
        if levels is None or levels.size < 2 or not quantile_pf or not all(0.0 < t < 1.0 for t in quantile_pf):
            raise ValueError("quantile_tol needs levels (two or more) and quantile_pf, Pf values in (0, 1)")
    evaluation = evaluation_or_default(evaluation)
    progress = evaluation.progress
    ev = evaluation.caller_for(g, d, n_outputs=None if (levels is not None and system is None) or not multi
                               else "auto")

    def shift(y):
        """The limit states' values (n, m) from g's outputs."""
        if system is not None:  # the components' responses (n, J); the system's is their minimum, NaN if any is
            return np.min(y, axis=1, keepdims=True) - levels[None, :]
        if levels is not None:
            return y[:, :1] - levels[None, :]
        return y

    u_pop = rng.standard_normal((n_mc, d))
    lhs = qmc.LatinHypercube(d=d, seed=rng).random(n_initial)
    design_u = (2.0 * lhs - 1.0) * initial_bound
    G0 = np.asarray(ev.evaluate(transform.to_x(design_u)), dtype=float)
    G0 = G0 if G0.ndim == 2 else G0[:, None]
    # what the surrogates are fitted to: each component's margin at the first level (series), else the columns
    design_fit = G0 - levels[0] if system is not None else None
    G0 = shift(G0)
    if multi and G0.ndim == 2 and G0.shape[1] < 1:
        raise ValueError("g returned zero columns")
    if not np.isfinite(G0).any():
        reason = next(iter(getattr(ev, "failure_reasons", {}).values()), "g returned NaN")
        raise AllCallsFailedError(
            f"g returned NaN (or failed) for every one of the {n_initial} initial design points ({reason}); "
            "check g and that it expects X with one column per marginal "
            f"({d} marginals given)"
        )
    design_g = G0
    m = design_g.shape[1]
    kriging = dict(kriging or {})
    if trend is not None:
        if system is not None:
            raise ValueError("trend: a known part of the response is for one response, not a series system")
        kriging["offset"] = lambda u: trend(transform.to_x(u))
    # With `levels`, every column is the same response shifted by a constant: one Kriging serves them all
    # (ordinary Kriging is shift-equivariant), fitted on column 0 + levels[0].
    n_fit = 1 if levels is not None else m
    if system is not None:
        surrogates = [SeriesSurrogate(design_fit.shape[1], seed=seed, **kriging)]
    else:
        surrogates = [KrigingSurrogate(seed=(None if seed is None else int(seed) * 1000 + j), **kriging)
                      for j in range(n_fit)]
    offsets = (levels - levels[0]) if levels is not None else np.zeros(m)
    n_at_opt = [0] * n_fit  # training size at the last hyperparameter optimisation

    known_idx: list[int] = []  # population indices already evaluated
    known_g: list[np.ndarray] = []

    history: list[IterationRecord] = []
    message = ""
    converged = False
    iteration = 0
    force_opt = np.zeros(n_fit, dtype=bool)
    # Active-set prediction: a full sweep over the population computes U everywhere; in between, only the
    # candidates that had U < u_active at the last sweep are re-predicted (the others keep their last sign).
    # Full sweeps happen after every hyperparameter optimisation, every `full_sweep_every` iterations, after
    # the population grows and always before a stop is accepted, so the stopping decision is exact.
    u_active = u_threshold + 1.5
    U = np.full((u_pop.shape[0], m), np.inf, order="F")  # column-major: each level's error reads a column
    fail = np.zeros((u_pop.shape[0], m), dtype=bool, order="F")
    active_idx = np.arange(u_pop.shape[0])
    need_full = True
    since_full = 0
    sweep_scales: list = [None] * n_fit
    n_sweeps = 0
    n_active_sum = 0
    n_held = 0  # successive designs on which the learning stop has held
    while True:
        # ---- fit
        for j in range(n_fit):
            ok = np.isfinite(design_g[:, j])
            n_ok = int(ok.sum())
            if n_ok < 2:
                raise ValueError(f"column {j}: fewer than 2 finite g values in the design; cannot fit Kriging")
            optimize = needs_optimisation(force_opt[j], n_at_opt[j], n_ok, refit_growth)
            if system is not None:  # each component on its own finite rows
                surrogates[j].fit(design_u, design_fit, optimize=optimize)
            else:
                surrogates[j].fit(design_u[ok], design_g[ok, j], optimize=optimize)
            if optimize:
                n_at_opt[j] = n_ok
                sc = log_scales(surrogates[j])
                if (sweep_scales[j] is None or sc.shape != sweep_scales[j].shape
                        or np.max(np.abs(sc - sweep_scales[j])) > 0.2):
                    need_full = True  # the surrogate may have changed everywhere
        force_opt[:] = False
        # ---- predict on the population (all of it, or the active set)
        n_pop = u_pop.shape[0]
        if U.shape[0] < n_pop:  # the population grew
            U = np.asfortranarray(np.vstack([U, np.full((n_pop - U.shape[0], m), np.inf)]))
            fail = np.asfortranarray(np.vstack([fail, np.zeros((n_pop - fail.shape[0], m), dtype=bool)]))
            need_full = True
        if since_full >= full_sweep_every:
            need_full = True
        was_full = need_full
        idx = slice(None) if need_full else active_idx
        known = np.zeros(n_pop, dtype=bool)
        kidx = np.array(known_idx, dtype=int)
        known[kidx] = True
        kg = np.array(known_g).reshape(len(known_idx), m) if known_idx else np.empty((0, m))
        pf = np.empty(m)
        err = np.empty(m)
        err_abs = np.empty(m)
        for j in range(m):
            if j < n_fit:
                mu0, var = surrogates[j].predict(u_pop[idx])
                sd = np.sqrt(var)
            mu = mu0 - offsets[j]
            Uj = u_function(mu, sd)
            U[idx, j] = Uj
            fail[idx, j] = mu < 0
            if kidx.size:
                U[kidx, j] = np.inf
                fail[kidx, j] = ~(kg[:, j] >= 0)  # NaN -> failure (conservative)
            pf[j] = fail[:, j].mean()
            err[j], err_abs[j] = esc_errors(U[:, j], fail[:, j], known)
        if need_full:
            active_idx = np.flatnonzero(U.min(axis=1) < u_active)
            n_sweeps += 1
            sweep_scales = [log_scales(sur) for sur in surrogates]
            need_full = False
            since_full = 0
        else:
            since_full += 1
            active_idx = active_idx[U[active_idx].min(axis=1) < u_active]  # shrinks between sweeps
        n_active_sum += active_idx.size
        cov = np.atleast_1d(mc_cov(pf, n_pop))
        min_u = U.min(axis=0)
        rec = IterationRecord(iteration=iteration, n_calls=int(design_u.shape[0]), n_mc=n_pop,
                              pf=pf.copy() if multi else float(pf[0]), cov=cov.copy() if multi else float(cov[0]),
                              min_u=min_u.copy() if multi else float(min_u[0]),
                              error=err.copy() if multi else float(err[0]),
                              wall_seconds=time.perf_counter() - t_start)
        history.append(rec)
        if progress is not None:
            progress(rec)
        iteration += 1

        # ---- learning convergence per column
        learned = min_u >= u_threshold
        if stopping == "error":
            learned |= err <= error_tol
            if error_abs_tol is not None:
                learned |= err_abs <= error_abs_tol
            if quantile_tol is not None:  # the levels that bracket a quantile also learn it to quantile_tol
                # or to half the response's fitted scatter, when larger: a noisy response's curve integrates its
                # scatter, and its sign counts would chase the noise
                tol = max(quantile_tol, 0.5 * float(getattr(surrogates[0], "noise_sd", 0.0)))
                for lo_col, hi_col, q_err in quantile_errors(levels, pf, err_abs, quantile_pf):
                    if not q_err <= tol:
                        learned[[lo_col, hi_col]] = False
        if learned.all():
            # the last fit may have reused hyperparameters: re-optimise once before accepting
            stale = np.array([n_at_opt[j] != int(np.isfinite(design_g[:, j]).sum()) for j in range(n_fit)])
            if stale.any() or not was_full:
                force_opt[:] = stale
                need_full = True
                continue
            n_held += 1
            if n_held < hold_iterations:
                if design_u.shape[0] >= max_calls:
                    message = (f"max_calls={max_calls} reached while confirming the learning stop (it held on "
                               f"{n_held} of the {hold_iterations} successive designs hold_iterations asks for)")
                    break
                learned[:] = False  # not yet confirmed: enrich as if nothing were learnt
        else:
            n_held = 0
        if learned.all():
            below = pf < pf_floor if multi else np.zeros(m, dtype=bool)
            need = (~below) & ~(cov < cov_target)
            if not need.any():
                converged = True
                message = "converged"
                if stopping == "error" and (err > error_tol).any():  # stopped by min U, the error rule unmet
                    message += (f" on min U >= {u_threshold:g}, with the error estimate {err.max():.3g} above "
                                f"error_tol={error_tol:g}")
                break
            if n_pop >= n_mc_max:
                message = (f"COV target {cov_target} not met with the maximum population n_mc_max={n_mc_max} "
                           f"(pf={pf[need].min():.3g})")
                if (pf[need] == 0).any():
                    message += (f": no failure among {n_pop:,} candidates, so Pf is below about 3 / {n_pop:,} "
                                "(or g is never negative)")
                break
            new_n = max(population_size(p, cov_target, n_mc_max, grow_from=n_pop) for p in pf[need])
            u_pop = np.vstack([u_pop, rng.standard_normal((new_n - n_pop, d))])
            need_full = True
            continue
        if design_u.shape[0] >= max_calls:
            message = f"max_calls={max_calls} reached before the learning criterion was met"
            break
        # ---- enrichment
        active = ~learned
        score = U[:, active].min(axis=1)
        k = min(batch_size, max_calls - design_u.shape[0])
        sel = select_batch(score, u_pop, k, u_threshold, rng, known)
        if sel.size == 0:
            message = "no candidate left to evaluate"
            break
        new_u = u_pop[sel]
        Gn = np.asarray(ev.evaluate(transform.to_x(new_u)), dtype=float).reshape(sel.size, -1)
        if system is not None:
            design_fit = np.vstack([design_fit, Gn - levels[0]])
        Gn = shift(Gn).reshape(sel.size, m)
        design_u = np.vstack([design_u, new_u])
        design_g = np.vstack([design_g, Gn])
        known_idx.extend(int(i) for i in sel)
        known_g.extend(Gn)

    pf_col = fail.mean(axis=0)
    cov_col = np.atleast_1d(mc_cov(pf_col, u_pop.shape[0]))
    design_x = getattr(ev, "design_x", None)
    if design_x is None or len(design_x) != design_u.shape[0]:
        design_x = transform.to_x(design_u)
    common = dict(n_calls=int(design_u.shape[0]), design_x=design_x, design_u=design_u,
                  n_failed_calls=int(getattr(ev, "n_failed_calls", int((~np.isfinite(design_g)).any(axis=1).sum()))),
                  failure_reasons=dict(getattr(ev, "failure_reasons", {})), history=history, n_mc=int(u_pop.shape[0]),
                  message=message, wall_seconds=time.perf_counter() - t_start)
    if keep_population:
        common_pop = {"population_u": u_pop, "population_fail": fail.copy()}
    else:
        common_pop = {}
    if multi:
        below = pf_col < pf_floor
        err_ok = (err <= error_tol) | ((err_abs <= error_abs_tol) if error_abs_tol is not None else False)
        col_ok = (min_u >= u_threshold) | (err_ok if stopping == "error" else False)
        col_ok = col_ok & (below | (cov_col < cov_target))
        return MultiReliabilityResult(pf=pf_col, cov=cov_col, beta=np.atleast_1d(pf_to_beta(pf_col)),
                                      converged=converged, column_converged=col_ok, below_floor=below,
                                      design_g=design_g, surrogates=surrogates if levels is None
                                      else [ShiftedSurrogate(surrogates[0], o) for o in offsets],
                                      min_u=min_u, error_estimate=err, error_absolute=err_abs,
                                      levels=levels, population_u=u_pop if keep_population else None, **common)
    return ReliabilityResult(method="akmcs", pf=float(pf_col[0]), cov=float(cov_col[0]), beta=pf_to_beta(pf_col[0]),
                             converged=converged, design_g=design_g[:, 0], surrogate=surrogates[0],
                             error_estimate=float(err[0]), error_absolute=float(err_abs[0]),
                             details={"min_u": float(min_u[0]), "n_full_sweeps": n_sweeps,
                                      "mean_active": n_active_sum / max(iteration, 1), **common_pop}, **common)


def akmcs(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    n_mc: int = 100_000,
    n_mc_max: int = 5_000_000,
    n_initial: int | None = None,
    initial_bound: float = 5.0,
    batch_size: int = 1,
    u_threshold: float = 2.0,
    cov_target: float = 0.05,
    stopping: str = "error",
    error_tol: float = 0.01,
    hold_iterations: int = 3,
    max_calls: int = 1000,
    seed: int | None = 0,
    evaluation: Evaluation | None = None,
    kriging: dict | None = None,
    refit_growth: float = 0.1,
    keep_population: bool = False,
) -> ReliabilityResult:
    """AK-MCS estimate of Pf = P[g(X) < 0] for inputs X_i ~ ``marginals[i]`` joined by ``copula``.

    Parameters
    ----------
    g:
        Vectorised limit state: X of shape (n, d) (physical units) -> array of shape (n,); failure where g < 0.
    marginals:
        Sequence of d continuous distributions: frozen ``scipy.stats``, scipy's new distribution objects
        (``scipy.stats.Normal(...)``) or OpenTURNS (``ot.Gumbel(...)``); see :mod:`jointwear.reliability.inputs`.
    copula:
        None (independent inputs), an OpenTURNS copula of dimension d (``ot.NormalCopula(R)``...) or a
        correlation matrix (the normal copula's correlation). The learning happens in the independent
        standard-normal space of OpenTURNS' iso-probabilistic transform.
    n_mc, n_mc_max:
        Initial and maximum Monte Carlo population (candidates). The population grows until
        COV(Pf) < ``cov_target``. Default 1e5 (COV 5 % down to Pf ~ 4e-3) and 5e6 (Pf ~ 8e-5).
    n_initial:
        Initial Latin hypercube design size; default max(12, 2 d + 2) (12 as in Echard et al. 2011).
    initial_bound:
        The initial design is uniform in [-b, b]^d in standard-normal space (b = 5: mu +/- 5 sigma).
    batch_size:
        Points added per iteration (k-means spread; evaluated together, in parallel with an executor).
    u_threshold, stopping, error_tol:
        Learning stop, see the module docstring: ``"error"`` (default) ESC estimated relative error of Pf
        <= error_tol (or min U >= u_threshold, whichever first); ``"u"`` min U >= u_threshold (the paper's
        rule, which resolves every candidate's sign and costs 30-50 % more calls for the same Pf accuracy,
        ``docs/reliability.md``).
    hold_iterations:
        The learning stops only when its rule has held on this many successive designs (3; 1 = stop on the first
        design where it holds, as Echard et al. 2011 and Wang & Shafieezadeh 2019 do). A budget of ``max_calls``
        reached while confirming ends the learning unconverged, and its message says so.
    cov_target:
        Required coefficient of variation of the Monte Carlo estimate.
    max_calls:
        Budget of model calls (initial design included).
    seed:
        Seed of every random choice (population, design, k-means, multistart); same seed, same result.
    evaluation:
        How g is called (executor, cache, callbacks, NaN policy; :class:`Evaluation`); its ``progress`` is
        called with an :class:`IterationRecord` (pf, cov, min_u, error, n_calls) after every iteration.
    kriging:
        Keyword arguments for :class:`KrigingSurrogate` (nugget, scale_bounds, n_starts, chunk_size).
    keep_population:
        Store the final candidate population (``details["population_u"]``) and its classification
        (``details["population_fail"]``), e.g. to compare with the true g on the same population.
    refit_growth:
        Hyperparameters are re-optimised when the design has grown by this fraction since the last
        optimisation (and always while it has <= 30 points, and before stopping); in between, the Kriging is
        re-conditioned with the previous correlation lengths (exact interpolation, much cheaper).
    """
    return _run(g, marginals, multi=False, n_mc=n_mc, n_mc_max=n_mc_max, n_initial=n_initial,
                initial_bound=initial_bound, batch_size=batch_size, u_threshold=u_threshold, cov_target=cov_target,
                stopping=stopping, error_tol=error_tol, max_calls=max_calls, seed=seed, evaluation=evaluation,
                hold_iterations=hold_iterations, pf_floor=0.0, kriging=kriging, refit_growth=refit_growth,
                keep_population=keep_population, copula=copula)


def akmcs_multi(
    g: Callable[[np.ndarray], np.ndarray],
    marginals: Sequence,
    *,
    copula=None,
    n_mc: int = 100_000,
    n_mc_max: int = 5_000_000,
    n_initial: int | None = None,
    initial_bound: float = 5.0,
    batch_size: int = 1,
    u_threshold: float = 2.0,
    cov_target: float = 0.05,
    stopping: str = "error",
    error_tol: float = 0.01,
    hold_iterations: int = 3,
    pf_floor: float = 1e-3,
    max_calls: int = 2000,
    seed: int | None = 0,
    evaluation: Evaluation | None = None,
    kriging: dict | None = None,
    refit_growth: float = 0.1,
    levels=None,
    error_abs_tol: float | None = None,
    system: str | None = None,
    keep_population: bool = False,
    quantile_pf=(),
    quantile_tol: float | None = None,
    trend: Callable[[np.ndarray], np.ndarray] | None = None,
) -> MultiReliabilityResult:
    """AK-MCS for m limit states sharing one design (e.g. one model call -> the limit state at m cycle counts).

    g returns shape (n, m). One Kriging per column; every iteration adds the candidate with the lowest U over
    the columns that have not met the learning criterion, so the final design meets it for *every* column.
    The population grows until every column with Pf >= ``pf_floor`` has COV < ``cov_target``; columns below
    the floor (``below_floor``) meet the U criterion but their COV is reported, not enforced (a Pf of 1e-5
    would need 4e7 candidates). Other parameters as :func:`akmcs`.

    ``levels``: a family of thresholds on one response. g then returns one value y per row and the limit
    states are G_k = y - levels[k] (failure where y < levels[k]), e.g. y = ln(life) and levels = ln(N_k).
    One Kriging serves every level (ordinary Kriging is shift-equivariant, so separate fits would agree),
    which costs one fit per iteration instead of m and gives Pf monotone in the level.

    ``system="series"`` (with ``levels``): g returns the responses of a series system's J components, shape
    (n, J), and the system's response is their minimum (it fails when its first component fails). One Kriging per
    component, judged by the component with the smallest mean (AK-SYS, :class:`SeriesSurrogate`): the minimum's
    kinks, where two components' responses cross, are then learnt from smooth components.

    ``error_abs_tol`` (with ``stopping="error"``): a level also counts as learned when its estimated absolute
    Pf error (relative ESC error x Pf) is below this, so a curve's small-Pf levels need not be resolved to a
    relative accuracy that matters nowhere on the curve.

    ``keep_population``: keep the final population (u space, ``population_u``), which the learning classified: the
    curve between its levels is estimated there (:meth:`MultiReliabilityResult.estimate_on`, ``thresholds``).

    ``quantile_tol`` with ``quantile_pf`` (with ``levels`` and ``stopping="error"``): the level at which Pf reaches
    each of ``quantile_pf`` (read between the two levels that bracket it) must also be learnt to within
    ``quantile_tol`` (in the levels' units; for levels ln N the relative error of the life there): the two levels'
    absolute Pf errors interpolated at it, divided by the curve's slope between them
    (:func:`~jointwear.reliability.learning.quantile_errors`). Until it is, those two levels count as not learnt,
    and the learning adds points at their limit states. A Kriging that fits a noise (``kriging={"estimate_nugget":
    True}``) learns the quantile to half its noise's standard deviation where that is larger than ``quantile_tol``.

    ``trend`` (with ``levels``, not with ``system``): a known part of the response y as a function of x (n, d) ->
    (n,), e.g. Archard's exact scaling of ln N_f in a wear coefficient and a hardness. The Kriging learns y less it
    (``KrigingSurrogate(offset=...)``, in u space through the inputs' transform) and predicts it plus its mean.
    """
    return _run(g, marginals, multi=True, n_mc=n_mc, n_mc_max=n_mc_max, n_initial=n_initial,
                initial_bound=initial_bound, batch_size=batch_size, u_threshold=u_threshold, cov_target=cov_target,
                stopping=stopping, error_tol=error_tol, max_calls=max_calls, seed=seed, evaluation=evaluation,
                hold_iterations=hold_iterations, pf_floor=pf_floor, kriging=kriging, refit_growth=refit_growth,
                levels=levels, error_abs_tol=error_abs_tol, copula=copula, system=system,
                keep_population=keep_population, quantile_pf=quantile_pf, quantile_tol=quantile_tol, trend=trend)
