"""The reliability methods' results: one dataclass for every single-limit-state method, one for the levels of
``akmcs_multi``, the record of an active-learning iteration, and the estimators they share."""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.special import ndtr, ndtri

from .kriging import gaussian_draws
from .system import series_failure_probability

__all__ = [
    "IterationRecord",
    "MultiReliabilityResult",
    "ReliabilityResult",
    "Z95",
    "cov_population",
    "mc_cov",
    "pf_to_beta",
    "population_size",
    "posterior_failure_spread",
]

#: the two-sided 95 % quantile of the standard normal distribution, Phi^-1(0.975) (scipy.stats.norm.ppf(0.975)):
#: the half-width of a 95 % interval in standard deviations
Z95 = 1.959963984540054


def pf_to_beta(pf: float | np.ndarray) -> float | np.ndarray:
    """Generalised reliability index beta = -Phi^-1(pf) (+inf for pf = 0)."""
    with np.errstate(divide="ignore"):
        b = -ndtri(np.asarray(pf, dtype=float))
    return float(b) if np.ndim(b) == 0 else b


def mc_cov(pf: float | np.ndarray, n: int) -> float | np.ndarray:
    """Coefficient of variation of a crude Monte Carlo estimate: sqrt((1 - pf) / ((n - 1) pf))."""
    pf = np.asarray(pf, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(pf > 0, np.sqrt((1.0 - pf) / (max(n - 1, 1) * pf)), np.inf)
    return float(c) if c.ndim == 0 else c


def failure_probability(g, noise_sd: float = 0.0) -> np.ndarray:
    """P(G < 0 | x) of each sample whose limit state is the surrogate's mean ``g`` plus Gaussian noise of standard
    deviation ``noise_sd``: Phi(-g / noise_sd), the indicator g < 0 when noise_sd = 0. A NaN g is a failure."""
    g = np.asarray(g, dtype=float)
    p = ndtr(-g / noise_sd) if noise_sd > 0 else (g < 0).astype(float)
    return np.where(np.isnan(g), 1.0, p)


def posterior_failure_spread(mean: np.ndarray, cov: np.ndarray, shifts, noise_sd: float = 0.0, n_draws: int = 400,
                             rng: np.random.Generator | None = None) -> np.ndarray:
    """Standard deviation of Pf_k = mean_i P(g_i - shifts[k] < 0) (:func:`failure_probability`) over the surrogate's
    Gaussian posterior of g at the points, N(mean, cov): ``n_draws`` conditional simulations (the posterior
    distribution of the probability of failure, Bect et al., Stat. Comput. 22 (2012) 773-793). Unlike a count of
    misclassified points, it keeps the correlation of the surrogate's errors between the points, which moves a
    smoothed Pf (``noise_sd`` > 0) as a whole. Returns one value per shift."""
    rng = np.random.default_rng() if rng is None else rng
    return failure_spread(gaussian_draws(mean, cov, n_draws, rng), shifts, noise_sd)


#: failure probabilities held at once by :meth:`MultiReliabilityResult.estimate_on` (8 bytes each: 40 MB)
MAX_PROBABILITIES = 5_000_000

#: posterior draws :meth:`MultiReliabilityResult.posterior_pf_sd` keeps (the least recently used go first): a study's
#: nominal points and one shifted population at a time
DRAWS_KEPT = 2


def failure_spread(draws: np.ndarray, shifts, noise_sd: float = 0.0) -> np.ndarray:
    """Standard deviation over the columns of ``draws`` (m points, one column per posterior draw of g) of
    Pf_k = mean_i P(g_i - shifts[k] < 0) (:func:`failure_probability`), one value per shift."""
    return np.array([failure_probability(draws - shift, noise_sd).mean(axis=0).std(ddof=1) for shift in shifts])


def cov_population(pf: float, cov_target: float) -> float:
    """Samples a Monte Carlo estimate of ``pf`` > 0 needs for a coefficient of variation ``cov_target``:
    COV^2 = (1 - pf) / (n pf)."""
    return (1.0 - pf) / (cov_target**2 * pf)


def population_size(pf: float, cov_target: float, n_max: int, *, grow_from: int = 0) -> int:
    """Monte Carlo population that brings COV(Pf) below ``cov_target`` at ``pf``: 10 % over the size the COV
    formula asks for, at least 20 % more than ``grow_from`` (the current population), at most ``n_max``. At
    pf = 0 (no failure seen, the COV is infinite) it takes 2.2 ``grow_from`` (double, and the 10 %), or ``n_max`` from
    nothing."""
    if pf > 0:
        target = cov_population(pf, cov_target) + 1.0
    else:
        target = 2.0 * grow_from if grow_from else np.inf
    return int(min(n_max, max(1.1 * target, 1.2 * grow_from)))


@dataclass
class IterationRecord:
    """One AK-MCS iteration (arrays of one value per column in ``akmcs_multi``)."""

    iteration: int
    n_calls: int
    n_mc: int
    pf: Any
    cov: Any
    min_u: Any
    error: Any  # estimated relative error of pf from the surrogate's sign uncertainty (ESC)
    wall_seconds: float


@dataclass
class ReliabilityResult:
    """Result of every reliability method (fields not used by a method are None/NaN).

    ``pf``: failure probability P[g(X) < 0]; ``cov``: its coefficient of variation (sampling methods; NaN for
    FORM/SORM); ``beta``: generalised reliability index -Phi^-1(pf); ``n_calls``: the limit state's evaluations
    (the length of ``design_x``, plus FORM's for the methods that start from it: ``sorm``, ``importance_sampling``,
    ``akis``); ``n_failed_calls``: calls that returned NaN/raised (counted as failures, see the NaN rule).
    """

    method: str
    pf: float
    cov: float
    beta: float
    n_calls: int
    converged: bool
    design_x: np.ndarray | None = None
    design_g: np.ndarray | None = None
    design_u: np.ndarray | None = None
    n_failed_calls: int = 0
    failure_reasons: dict[int, str] = field(default_factory=dict)
    history: list[IterationRecord] = field(default_factory=list)
    surrogate: Any = None
    n_mc: int = 0
    error_estimate: float = float("nan")
    error_absolute: float = float("nan")  # the ESC estimate of the absolute error of pf (learning.esc_errors)
    design_point_u: np.ndarray | None = None
    design_point_x: np.ndarray | None = None
    alpha: np.ndarray | None = None
    curvatures: np.ndarray | None = None
    details: dict[str, Any] = field(default_factory=dict)
    message: str = ""
    wall_seconds: float = 0.0

    def __repr__(self) -> str:  # short: the design can be large
        return (
            f"ReliabilityResult(method={self.method!r}, pf={self.pf:.4g}, cov={self.cov:.3g}, beta={self.beta:.4g}, "
            f"n_calls={self.n_calls}, converged={self.converged}, n_failed_calls={self.n_failed_calls})"
        )


@dataclass
class MultiReliabilityResult:
    """Result of :func:`akmcs_multi`: one pf/cov/beta per column (limit-state level) from one shared design."""

    pf: np.ndarray
    cov: np.ndarray
    beta: np.ndarray
    n_calls: int
    converged: bool
    column_converged: np.ndarray
    below_floor: np.ndarray  # columns with pf < pf_floor: U criterion met, COV criterion waived
    design_x: np.ndarray
    design_g: np.ndarray
    design_u: np.ndarray
    n_failed_calls: int
    failure_reasons: dict[int, str]
    history: list[IterationRecord]
    surrogates: list
    min_u: np.ndarray
    error_estimate: np.ndarray  # relative ESC error of each column's pf (+inf where unbounded)
    error_absolute: np.ndarray  # absolute ESC error of each column's pf, finite (learning.esc_errors)
    n_mc: int
    message: str = ""
    wall_seconds: float = 0.0
    method: str = "akmcs_multi"
    #: the thresholds of ``akmcs_multi(levels=...)`` (column k is y - levels[k]); None for separate limit states
    levels: np.ndarray | None = None
    #: the final population (u space) of ``akmcs_multi(keep_population=True)``, else None
    population_u: np.ndarray | None = None
    #: the last posterior draws of :meth:`posterior_pf_sd` (a study reads R at many thresholds on the same points)
    _draws: OrderedDict = field(default_factory=OrderedDict, init=False, repr=False, compare=False)

    def predict(self, u: np.ndarray, shifts=None) -> np.ndarray:
        """The surrogates' mean of every column at standard-normal points ``u``, shape (n, m); with ``levels=``,
        of the first level's margin less each of ``shifts`` instead of each level's (:meth:`_level_shifts`)."""
        if self.levels is None:
            return np.column_stack([s.predict(u, return_variance=False)[0] for s in self.surrogates])
        # one response shifted per level: a single Kriging prediction serves every column
        mu0 = self.surrogates[0].predict(u, return_variance=False)[0]
        return mu0[:, None] - (self._level_shifts() if shifts is None else np.asarray(shifts, dtype=float))[None, :]

    @property
    def response_surrogate(self):
        """The Kriging of the learned response of ``akmcs_multi(levels=...)``, which every level shifts."""
        if self.levels is None:
            raise ValueError("response_surrogate needs a result of akmcs_multi(levels=...)")
        return self.surrogates[0].surrogate

    def response(self, u: np.ndarray) -> np.ndarray:
        """The learned response y(u) of ``akmcs_multi(levels=...)`` (the value every level is compared with)."""
        if self.levels is None:
            raise ValueError("response() needs a result of akmcs_multi(levels=...)")
        return self.surrogates[0].predict(u, return_variance=False)[0] + self.levels[0]

    @property
    def noise_sd(self) -> float:
        """Standard deviation of the noise the shared Kriging of ``akmcs_multi(levels=...)`` estimated on the
        response (0 for separate limit states)."""
        if self.levels is None:
            return 0.0
        return self.response_surrogate.noise_sd

    def failure_probabilities(self, u: np.ndarray, noise_sd: float = 0.0, thresholds=None) -> np.ndarray:
        """Each point's probability of failure at every column, shape (n, m): the surrogates' mean plus a Gaussian
        scatter of standard deviation ``noise_sd`` (:func:`failure_probability`; the indicator of mu < 0 for 0). A
        series system's surrogate (``system="series"``) takes each component's own scatter instead when
        ``noise_sd`` > 0 (:meth:`SeriesSurrogate.failure_probability`). ``thresholds``: with ``levels=``, other
        thresholds on the response than the levels (one column each): the curve between its levels, no call."""
        if thresholds is None and self.levels is None:
            return failure_probability(self.predict(u), noise_sd)
        shifts = self._level_shifts(thresholds)
        if noise_sd > 0 and hasattr(self.response_surrogate, "failure_probability"):
            return self.response_surrogate.failure_probability(u, shifts)
        return failure_probability(self.predict(u, shifts), noise_sd)

    def _level_shifts(self, thresholds=None) -> np.ndarray:
        """Each level's (or each of ``thresholds``') threshold on the response the shared Kriging of ``levels=``
        is fitted to (the first level's margin)."""
        if self.levels is None:
            raise ValueError("thresholds need a result of akmcs_multi(levels=...)")
        if thresholds is not None:
            return np.asarray(thresholds, dtype=float).reshape(-1) - self.levels[0]
        offsets = np.array([s.offset for s in self.surrogates])
        return offsets - offsets[0]

    def estimate_on(self, draw_u: Callable[[int, int], np.ndarray], n: int, chunk: int = 200_000,
                    noise_sd: float = 0.0, thresholds=None) -> tuple[np.ndarray, np.ndarray]:
        """Pf and its Monte Carlo COV of every column on a new population of ``n`` points, classified by the
        final surrogates (no model call): AK-MCS's population growth, for a caller whose learning ended on
        its call budget. ``draw_u(m, start)`` returns rows ``start .. start + m`` of the population (u space),
        drawn ``chunk`` rows at a time to bound the memory. With ``noise_sd`` > 0 each point fails with
        probability Phi(-g / noise_sd) (:func:`failure_probability`: the response's scatter is part of the
        model; :meth:`failure_probabilities`) and the COV is that of the mean of those probabilities.
        ``thresholds``: Pf at other thresholds on the response than the levels (:meth:`failure_probabilities`),
        on the same population."""
        n_columns = len(self.surrogates) if thresholds is None else np.size(thresholds)
        rows = max(1_000, MAX_PROBABILITIES // n_columns)  # the population is drawn by chunk whatever the columns
        total = np.zeros(n_columns)
        total_sq = np.zeros(n_columns)
        done = 0
        while done < n:
            m = min(chunk, n - done)
            u = draw_u(m, done)
            for start in range(0, m, rows):
                p = self.failure_probabilities(u[start:start + rows], noise_sd, thresholds)
                total += p.sum(axis=0)
                total_sq += (p * p).sum(axis=0)
            done += m
        pf = total / n
        if noise_sd <= 0:
            return pf, np.atleast_1d(mc_cov(pf, n))
        var = np.maximum(total_sq / n - pf * pf, 0.0) * n / max(n - 1, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            cov = np.where(pf > 0, np.sqrt(var / n) / pf, np.inf)
        return pf, cov

    def posterior_pf_sd(self, u: np.ndarray, noise_sd: float = 0.0, n_draws: int = 400, seed: int = 0,
                        thresholds=None, point_shifts=None) -> np.ndarray:
        """The Kriging's own uncertainty of every column's Pf: its standard deviation over the posterior of the
        shared Kriging of ``akmcs_multi(levels=...)`` at the points ``u`` (a sample of the population, m points:
        m^2 memory), each point failing with probability Phi(-g / noise_sd) (:func:`posterior_failure_spread`); a
        series system's, from its components' draws, each with its own scatter when ``noise_sd`` > 0.
        ``thresholds``: at other thresholds on the response than the levels; ``point_shifts`` (m,): added to every
        threshold at each point (a threshold that differs from point to point)."""
        if self.levels is None:
            raise ValueError("posterior_pf_sd needs a result of akmcs_multi(levels=...)")
        shifts = self._level_shifts(thresholds)
        if point_shifts is not None:
            shifts = [shift + np.asarray(point_shifts, dtype=float)[:, None] for shift in shifts]
        sur = self.response_surrogate
        if noise_sd > 0 and hasattr(sur, "failure_probability"):  # a series system: each component's own scatter
            draws = self._posterior_draws(u, n_draws, seed, components=True)
            return np.array([series_failure_probability(draws - shift, sur.scatter_sds).mean(axis=0).std(ddof=1)
                             for shift in shifts])
        return failure_spread(self._posterior_draws(u, n_draws, seed, components=False), shifts, noise_sd)

    def posterior_failure_draws(self, u: np.ndarray, threshold: float, noise_sd: float = 0.0, n_draws: int = 400,
                                seed: int = 0) -> np.ndarray:
        """Each point's probability of failure at ``threshold`` on the response under each posterior draw of the
        shared Kriging (m, n_draws): the draws :meth:`posterior_pf_sd` averages over the points, for another
        statistic of them (a derivative's score estimator weighs the points)."""
        shift = self._level_shifts([threshold])[0]
        sur = self.response_surrogate
        if noise_sd > 0 and hasattr(sur, "failure_probability"):
            return series_failure_probability(self._posterior_draws(u, n_draws, seed, components=True) - shift,
                                              sur.scatter_sds)
        return failure_probability(self._posterior_draws(u, n_draws, seed, components=False) - shift, noise_sd)

    def _posterior_draws(self, u: np.ndarray, n_draws: int, seed: int, components: bool) -> np.ndarray:
        """The response surrogate's posterior draws at ``u`` from ``default_rng(seed)`` (each component's, shape
        (J, m, n_draws), when ``components``), the last DRAWS_KEPT kept: the same points, count and seed give the
        same draws, which cost an m x m factorisation (``seed=None``: fresh draws each time, none kept)."""
        u = np.ascontiguousarray(u, dtype=float)
        key = (hashlib.blake2b(u.tobytes(), digest_size=16).digest(), u.shape, int(n_draws), seed, components)
        if key in self._draws:
            self._draws.move_to_end(key)
            return self._draws[key]
        sur, rng = self.response_surrogate, np.random.default_rng(seed)
        draws = sur.posterior_component_draws(u, n_draws, rng) if components else sur.posterior_draws(u, n_draws, rng)
        if seed is None:
            return draws
        self._draws[key] = draws
        while len(self._draws) > DRAWS_KEPT:
            self._draws.popitem(last=False)
        return draws

    def __repr__(self) -> str:
        return (
            f"MultiReliabilityResult(pf={np.array2string(self.pf, precision=4)}, n_calls={self.n_calls}, "
            f"converged={self.converged}, n_failed_calls={self.n_failed_calls})"
        )
