"""Kriging surrogate (ordinary, or universal with a linear trend): OpenTURNS fits, numpy predicts.

Model: ``Y(u) = beta + Z(u)`` with a constant trend ``beta`` and a stationary Gaussian process ``Z`` of
variance ``sigma^2`` and squared-exponential (Gaussian) correlation

    R(u, u') = exp(-1/2 * sum_i ((u_i - u'_i) / theta_i)^2)

(the DACE / Echard et al. 2011 model; OpenTURNS' ``SquaredExponential`` uses the same parametrisation).

* Fitting (the hyperparameters ``theta``, then ``beta`` and ``sigma^2`` in closed form) is done by
  OpenTURNS' ``GaussianProcessFitter`` (maximum likelihood; the choice among its candidates restricted with the
  linear trend, below), with bounds on the scales, a small nugget,
  an optional multistart, a warm start from the previous fit and a fallback to the previous hyperparameters
  when a fit fails or is worse (by the concentrated likelihood) than the previous one. The choice of
  library is measured in ``docs/reliability.md``.
* Prediction is done here with numpy from the fitted hyperparameters: one Cholesky factorisation of the
  correlation matrix, then per chunk of candidates one BLAS product for the squared distances, one
  element-wise ``exp``, and one BLAS product ``r @ L^-T`` for the variance. It reproduces OpenTURNS'
  ``GaussianProcessRegression`` mean and ``GaussianProcessConditionalCovariance`` variance (tested), and is
  ~20-50x faster on 1e6 candidates.

The variance is the universal-Kriging (DACE) mean squared error, which accounts for the estimated trend:

    s^2(u) = sigma^2 * (1 - r^T C^-1 r + v^T (F^T C^-1 F)^-1 v),   v = f(u) - F^T C^-1 r

with C = R + nugget I, F the design's trend basis (a column of ones for the constant trend) and f(u) that of u;
the trend's coefficients are the generalised least-squares beta = (F^T C^-1 F)^-1 F^T C^-1 y.

Outputs are standardised (zero mean, unit variance) before fitting and mapped back on prediction, so limit
states in any unit (metres of wear, pascals) fit the same way.

With ``linear_trend`` the trend is linear in the inputs, ``Y(u) = beta_0 + b^T u + Z(u)`` (universal Kriging, the
trend estimated with the process and its uncertainty in the variance), once the design holds
``LINEAR_TREND_POINTS_PER_TERM`` points per coefficient. Its correlation lengths and nugget are chosen by the
restricted likelihood (REML: the likelihood of the residuals' contrasts, which does not count the p trend
coefficients as known; Santner, Williams and Notz, The Design and Analysis of Computer Experiments, 2003, section 3.3):
with 14 coefficients on ~28 points, maximum likelihood prefers a "plane plus white noise" fit whose tail is wrong
(docs/reliability.md, "The learnt life's spread"). A constant trend must bend to follow a response that keeps rising
across the inputs, which it does as an S between an active-learning design's cluster and its far points.
"""

from __future__ import annotations

import itertools
import math
import os
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import blas, cho_solve, lapack, solve_triangular

__all__ = ["KrigingHyperparameters", "KrigingSurrogate", "ShiftedSurrogate", "blas_threads", "gaussian_draws"]


#: The large start of the relative nugget when it is estimated.
NUGGET_START = 0.1

#: Default bounds on the correlation lengths (standard-normal units); see ``KrigingSurrogate.scale_bounds``.
SCALE_BOUNDS = (0.01, 100.0)

#: A linear trend is fitted once the design holds this many points per coefficient (1 + d); before, the constant.
LINEAR_TREND_POINTS_PER_TERM = 2


def _optimizer():
    """Likelihood optimiser: NLopt BOBYQA when OpenTURNS has NLopt, else Cobyla with a larger budget.

    Measured on a 13-D test function with n = 100 (docs/reliability.md): OpenTURNS' default Cobyla stopped
    at log-likelihood 96 (R^2 0.97, or 0.55 from a poor start), BOBYQA reached 168 (R^2 0.996) in 1.8 s,
    TNC 182 (R^2 0.998) but in 14-63 s.
    """
    import openturns as ot

    try:
        algo = ot.NLopt("LN_BOBYQA")
    except Exception:
        algo = ot.Cobyla()
    algo.setMaximumCallsNumber(2000)
    return algo


_CONTROLLER = None


def _thread_pools():
    """One threadpoolctl controller for the process: building one scans every loaded library (~6 ms), which
    ``threadpool_limits`` did on each entry. numpy's and scipy's BLAS are loaded by this module's imports."""
    global _CONTROLLER
    if _CONTROLLER is None:
        from threadpoolctl import ThreadpoolController

        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER


class blas_threads:
    """Context manager limiting the BLAS libraries numpy and scipy use to ``n`` threads (threadpoolctl: OpenBLAS,
    MKL, BLIS alike); ``n=None`` leaves them alone.

    Prediction runs single-threaded BLAS inside its own chunk threads: multi-threaded OpenBLAS spin-waits and
    was 5-15x *slower* on a 2-core machine when other processes were busy (docs/reliability.md).
    """

    def __init__(self, n: int | None):
        self.n = n
        self._limits = None

    def __enter__(self):
        if self.n is not None:
            self._limits = _thread_pools().limit(limits=int(self.n), user_api="blas")
        return self

    def __exit__(self, *exc):
        if self._limits is not None:
            self._limits.restore_original_limits()
            self._limits = None
        return False


@dataclass(frozen=True)
class KrigingHyperparameters:
    """Fitted hyperparameters, on the standardised output scale."""

    scale: np.ndarray  # correlation lengths theta_i (input units: standard-normal space)
    nugget: float  # relative nugget added to the diagonal of the correlation matrix


@dataclass
class _Conditioned:
    x: np.ndarray  # (n, d) training inputs divided by the scales
    x_sq: np.ndarray  # (n,) squared norms of x
    chol: np.ndarray  # (n, n) lower Cholesky factor of C = R + nugget I
    chol_inv_t: np.ndarray | None  # (n, n) L^-T, so that r @ L^-T = (L^-1 r)^T; set for the chosen fit only
    alpha: np.ndarray  # C^-1 (y - F beta)
    c_inv_f: np.ndarray  # (n, p) C^-1 F
    gram: np.ndarray  # (p, p) G = F^T C^-1 F
    g_chol: np.ndarray  # (p, p) its lower Cholesky factor
    beta: np.ndarray  # (p,) GLS trend coefficients (standardised scale)
    sigma2: float  # process variance (standardised scale)
    loglik: float  # concentrated log-likelihood (restricted with a trend basis)

    def trend_variance(self, t: np.ndarray) -> np.ndarray:
        """The estimated trend's share of the variance, t G^-1 t^T for each row of t = f(u) - r^T C^-1 F (m, p)."""
        if self.beta.size == 1:  # the constant trend: t^2 / (1^T C^-1 1)
            return t[:, 0] * t[:, 0] / self.gram[0, 0]
        z = solve_triangular(self.g_chol, t.T, lower=True)
        return np.einsum("ij,ij->j", z, z)

    def trend_covariance(self, t: np.ndarray) -> np.ndarray:
        """Its share of the covariance, t G^-1 t^T (m, m)."""
        if self.beta.size == 1:
            return np.outer(t[:, 0], t[:, 0]) / self.gram[0, 0]
        z = solve_triangular(self.g_chol, t.T, lower=True)
        return z.T @ z


def _corr(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Gaussian correlation between pre-scaled point sets a (m, d) and b (n, d)."""
    d2 = np.sum(a * a, axis=1)[:, None] + np.sum(b * b, axis=1)[None, :] - 2.0 * (a @ b.T)
    np.maximum(d2, 0.0, out=d2)
    d2 *= -0.5
    return np.exp(d2, out=d2)


def _condition(x_scaled: np.ndarray, y: np.ndarray, nugget: float, basis: np.ndarray | None = None) -> _Conditioned:
    """Closed-form part of Kriging for fixed correlation lengths (raises LinAlgError). ``basis``: the design's trend
    basis F (n, p), None for the constant trend (ordinary Kriging, maximum likelihood); with a basis the variance
    and the likelihood are the restricted ones: sigma^2 = r^T C^-1 r / (n - p) and
    -(n - p)/2 ln sigma^2 - 1/2 ln det C - 1/2 ln det(F^T C^-1 F)."""
    n = x_scaled.shape[0]
    r = _corr(x_scaled, x_scaled)
    r[np.diag_indices(n)] += nugget
    chol = np.linalg.cholesky(r)
    if basis is None:
        ones = np.ones(n)
        w = cho_solve((chol, True), ones)
        s1 = float(ones @ w)
        c_inv_f, gram, beta = w[:, None], np.array([[s1]]), np.array([float(w @ y) / s1])
        g_chol = np.sqrt(gram)
        dof = n
    else:
        c_inv_f = cho_solve((chol, True), basis)
        gram = basis.T @ c_inv_f
        g_chol = np.linalg.cholesky(gram)
        beta = cho_solve((g_chol, True), c_inv_f.T @ y)
        dof = n - basis.shape[1]
    resid = y - (beta[0] if basis is None else basis @ beta)
    alpha = cho_solve((chol, True), resid)
    sigma2 = max(float(resid @ alpha) / dof, 1e-300)
    loglik = -0.5 * dof * math.log(sigma2) - float(np.sum(np.log(np.diag(chol))))
    if basis is not None:
        loglik -= float(np.sum(np.log(np.diag(g_chol))))
    return _Conditioned(
        x=x_scaled,
        x_sq=np.sum(x_scaled * x_scaled, axis=1),
        chol=chol,
        chol_inv_t=None,
        alpha=alpha,
        c_inv_f=c_inv_f,
        gram=gram,
        g_chol=g_chol,
        beta=beta,
        sigma2=sigma2,
        loglik=loglik,
    )


@dataclass
class KrigingSurrogate:
    """Kriging with a constant trend (ordinary) or a linear one (universal), Gaussian correlation, in standard-normal
    space.

    Parameters
    ----------
    nugget:
        Relative nugget added to the correlation matrix diagonal. Default 1e-10: the smallest value that kept
        the Cholesky factorisation positive definite with nearly duplicated AK-MCS design points on the
        benchmark problems; it is multiplied by 10 (up to 1e-4) whenever the factorisation fails.
    scale_bounds:
        Bounds on every correlation length, in standard-normal units. Default (0.01, 100): from well below the
        period of the modified Rastrigin function (~0.3 after scaling) to far beyond the +/-5 design box
        (a nearly linear limit state).
    n_starts:
        Number of starting points of the likelihood optimisation (the previous optimum, then log-uniform
        Latin hypercube points within the bounds). 1 means a warm start only.
    seed:
        Seed of the multistart points.
    offset:
        A known part of the response, a function of the inputs (m, d) -> (m,): the Kriging is fitted to the outputs
        less it and predicts it plus its own mean, ``Y(u) = offset(u) + beta + Z(u)`` (its variance unchanged). None:
        ordinary Kriging.
    linear_trend:
        Universal Kriging with a linear trend in the inputs (after ``offset``), its lengths and nugget chosen by the
        restricted likelihood, once the design holds ``LINEAR_TREND_POINTS_PER_TERM`` points per coefficient; the
        constant trend before. Off by default (the paper's ordinary Kriging).
    trend_scale_bounds:
        Bounds on the correlation lengths of the fits that carry the linear trend; None: ``scale_bounds``. The
        fits of the constant phase before it keep ``scale_bounds``, so that a design too small for the trend is
        learnt exactly as without it.
    estimate_nugget, nugget_grid:
        For a noisy model: estimate the relative nugget (noise variance over process variance) by maximum
        likelihood jointly with the correlation lengths, within the range of ``nugget_grid`` and from a small and a
        large start, then profile it over the grid at the fitted lengths. The range reaches 10, so that a model
        whose scatter from call to call swamps its inputs' effect is fitted as such. Off by default
        (deterministic models are interpolated, as in DACE).
    """

    nugget: float = 1e-10
    estimate_nugget: bool = False
    offset: Callable[[np.ndarray], np.ndarray] | None = None
    linear_trend: bool = False
    nugget_grid: tuple[float, ...] = (1e-8, 1e-6, 1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 3.0,
                                      10.0)
    scale_bounds: tuple[float, float] = SCALE_BOUNDS
    trend_scale_bounds: tuple[float, float] | None = None
    n_starts: int = 2
    seed: int | None = 0
    chunk_size: int = 2048
    n_threads: int | None = None
    hyperparameters: KrigingHyperparameters | None = None
    n_fit_failures: int = 0
    _cond: _Conditioned | None = field(default=None, repr=False)
    _x: np.ndarray | None = field(default=None, repr=False)
    _y: np.ndarray | None = field(default=None, repr=False)
    _fitted_y: np.ndarray | None = field(default=None, repr=False)  # the outputs less the offset
    _linear: bool = field(default=False, repr=False)  # whether the fit carries the linear trend
    _nugget_found: dict = field(default_factory=dict, repr=False)
    _ymean: float = 0.0
    _ystd: float = 1.0

    # ------------------------------------------------------------------ fitting
    @property
    def n_train(self) -> int:
        return 0 if self._x is None else self._x.shape[0]

    def fit(self, x: np.ndarray, y: np.ndarray, *, optimize: bool = True) -> KrigingSurrogate:
        """Fit to training data; ``optimize=False`` keeps the correlation lengths (cheap update)."""
        x = np.ascontiguousarray(x, dtype=float)
        y = np.asarray(y, dtype=float).ravel()
        if x.ndim != 2 or x.shape[0] != y.shape[0]:
            raise ValueError(f"KrigingSurrogate.fit: x {x.shape} and y {y.shape} do not match")
        if not np.all(np.isfinite(y)) or not np.all(np.isfinite(x)):
            raise ValueError("KrigingSurrogate.fit: training data must be finite")
        d = x.shape[1]
        self._x, self._y = x, y
        self._linear = self.linear_trend and x.shape[0] >= LINEAR_TREND_POINTS_PER_TERM * (d + 1)
        lo, hi = self._bounds()
        self._fitted_y = y - self._offset_at(x)
        self._ymean = float(np.mean(self._fitted_y))
        std = float(np.std(self._fitted_y))
        self._ystd = std if std > 0 else 1.0
        ys = (self._fitted_y - self._ymean) / self._ystd

        candidates: list[np.ndarray] = []
        if self.hyperparameters is not None:
            candidates.append(np.clip(np.asarray(self.hyperparameters.scale, dtype=float), lo, hi))
        if optimize or self.hyperparameters is None:
            for n_starts in dict.fromkeys((self.n_starts, 1)):  # multistart, then a single warm start
                try:
                    candidates.extend(self._fit_openturns(x, ys, n_starts))
                    break
                except (AttributeError, ImportError, NameError):  # an OpenTURNS without the API: not a bad design
                    raise
                except Exception as exc:  # OpenTURNS can fail on ill-conditioned designs: keep last good fit
                    last_exc = exc
            else:
                self.n_fit_failures += 1
                warnings.warn(f"Kriging fit failed ({last_exc}); keeping previous hyperparameters", RuntimeWarning)
            if not candidates:
                candidates.append(np.full(d, 0.5 * (np.ptp(x, axis=0).mean() + 1e-12)))

        with blas_threads(1):  # matrices of the design's size: BLAS threads cost more than they save (40x)
            cond, scale, nug = self._choose(x, ys, candidates)
            cond.chol_inv_t = solve_triangular(cond.chol, np.eye(cond.chol.shape[0]), lower=True).T.copy()
        self._cond = cond
        self.hyperparameters = KrigingHyperparameters(scale=np.array(scale, dtype=float), nugget=nug)
        return self

    def _offset_at(self, u: np.ndarray) -> np.ndarray | float:
        """The known part of the response at the points ``u`` (0 without an offset)."""
        return 0.0 if self.offset is None else np.asarray(self.offset(u), dtype=float).reshape(-1)

    def _bounds(self) -> tuple[float, float]:
        """The bounds on the correlation lengths of the current fit."""
        return self.trend_scale_bounds if self._linear and self.trend_scale_bounds else self.scale_bounds

    def _basis(self, u: np.ndarray) -> np.ndarray:
        """The trend basis f(u) at the points ``u`` (m, d): [1, u] with the linear trend on, else [1]."""
        ones = np.ones((u.shape[0], 1))
        return np.hstack([ones, u]) if self._linear else ones

    def _choose(self, x: np.ndarray, ys: np.ndarray, candidates: list[np.ndarray]
                ) -> tuple[_Conditioned, np.ndarray, float]:
        """The most likely of the candidate correlation lengths (by the restricted likelihood with the linear trend),
        each with the smallest nugget that conditions it (and, with the nugget estimated, the most likely nugget of
        the grid at the chosen lengths)."""
        basis = self._basis(x) if self._linear else None
        best: tuple[_Conditioned, np.ndarray, float] | None = None
        for scale in candidates:
            nug = self._nugget_found.get(tuple(np.asarray(scale, dtype=float)), self.nugget) if self.estimate_nugget \
                else self.nugget
            if self.estimate_nugget and self.hyperparameters is not None and nug == self.nugget:
                nug = max(self.nugget, self.hyperparameters.nugget)  # warm start keeps the last nugget
            nug_limit = max(1e-4, 10.0 * nug)
            while nug <= nug_limit:
                try:
                    cond = _condition(x / scale, ys, nug, basis)
                except np.linalg.LinAlgError:
                    nug *= 10.0
                    continue
                if best is None or cond.loglik > best[0].loglik:
                    best = (cond, scale, nug)
                break
        if best is None:
            raise np.linalg.LinAlgError("Kriging: correlation matrix not positive definite even with nugget 1e-4")
        if self.estimate_nugget:
            # Profile the concentrated likelihood over a relative nugget (homoscedastic noise variance over the
            # process variance) at the chosen correlation lengths: a noisy model (e.g. chaotic dynamics) is then
            # smoothed instead of interpolated, and the predicted variance is that of the latent mean.
            for nug in self.nugget_grid:
                if nug <= best[2]:
                    continue
                try:
                    cond = _condition(x / best[1], ys, nug, basis)
                except np.linalg.LinAlgError:
                    continue
                if cond.loglik > best[0].loglik + 1e-9:
                    best = (cond, best[1], nug)
        return best

    def _fit_openturns(self, x: np.ndarray, ys: np.ndarray, n_starts: int) -> list[np.ndarray]:
        import openturns as ot

        n, d = x.shape
        lo, hi = self._bounds()
        if self.hyperparameters is not None:
            start = np.clip(self.hyperparameters.scale, lo * 1.0001, hi * 0.9999)
        else:
            start = np.clip(np.ptp(x, axis=0) / 3.0 + 1e-3, lo * 1.0001, hi * 0.9999)
        starts = [start]
        if n_starts > 1:
            rng = np.random.default_rng(None if self.seed is None else self.seed + n)
            from scipy.stats import qmc

            lhs = qmc.LatinHypercube(d=d, seed=rng).random(n_starts - 1)
            # log-uniform in the upper-middle of the bounds (0.3..30 for the default bounds): short scales are
            # reached from there, while starts near the lower bound get stuck in interpolating optima
            starts += list(np.exp(np.log(lo) + (np.log(hi) - np.log(lo)) * (0.4 + 0.4 * lhs)))
        basis = (ot.LinearBasisFactory if self._linear else ot.ConstantBasisFactory)(d).build()
        found = []
        errors = []
        flags = ot.Log.Flags()
        ot.Log.Show(ot.Log.NONE)  # optimiser warnings (maximum evaluations reached...) are expected
        # with the nugget estimated, every scale start also starts from a large nugget: from a small one alone the
        # optimiser can end in a short-scale optimum that explains the noise as signal (docs/reliability.md)
        nugget_starts = (max(self.nugget, 1e-3), NUGGET_START) if self.estimate_nugget else (self.nugget,)
        try:
            for st, nug0 in itertools.product(starts, nugget_starts):
                cov = ot.SquaredExponential(list(map(float, st)), [1.0])
                if self.estimate_nugget:
                    # optimise the nugget factor jointly with the correlation lengths (parameter index d)
                    cov.setNuggetFactor(nug0)
                    cov.setActiveParameter(list(range(d)) + [d])
                    bounds = ot.Interval([lo] * d + [min(self.nugget_grid)], [hi] * d + [max(self.nugget_grid)])
                else:
                    cov.setNuggetFactor(self.nugget)
                    bounds = ot.Interval([lo] * d, [hi] * d)
                fitter = ot.GaussianProcessFitter(ot.Sample(x), ot.Sample(ys[:, None]), cov, basis)
                fitter.setOptimizationBounds(bounds)
                fitter.setOptimizationAlgorithm(_optimizer())
                try:
                    fitter.run()
                except Exception as exc:
                    errors.append(exc)
                    continue
                model = fitter.getResult().getCovarianceModel()
                scale = np.array(model.getScale(), dtype=float)
                if self.estimate_nugget:
                    self._nugget_found[tuple(scale)] = float(model.getNuggetFactor())
                found.append(scale)
        finally:
            ot.Log.Show(flags)
        if not found:
            raise errors[0]
        return found

    # --------------------------------------------------------------- prediction
    def predict(self, u: np.ndarray, *, return_variance: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Mean and (DACE) variance of the surrogate at points ``u`` of shape (m, d)."""
        if self._cond is None:
            raise RuntimeError("KrigingSurrogate.predict called before fit")
        u = np.asarray(u, dtype=float)
        if u.ndim == 1:
            u = u[None, :]
        m = u.shape[0]
        mean = np.empty(m)
        var = np.empty(m) if return_variance else None
        chunk = max(1, int(self.chunk_size))
        starts = range(0, m, chunk)
        scale = self.hyperparameters.scale

        c = self._cond
        # -0.5 * |a - x|^2 = a.x - 0.5 |a|^2 - 0.5 |x|^2 as one BLAS product of augmented matrices
        x_aug = np.hstack([c.x, np.ones((c.x.shape[0], 1)), -0.5 * c.x_sq[:, None]])
        aw = np.column_stack([c.alpha, c.c_inv_f])

        def work(s: int) -> None:
            e = min(s + chunk, m)
            a = u[s:e] / scale
            a_aug = np.hstack([a, -0.5 * np.einsum("ij,ij->i", a, a)[:, None], np.ones((e - s, 1))])
            r = a_aug @ x_aug.T
            np.minimum(r, 0.0, out=r)
            np.exp(r, out=r)
            mw = r @ aw
            f = self._basis(u[s:e])
            mean[s:e] = f @ c.beta + mw[:, 0]
            if var is not None:
                v = r @ c.chol_inv_t
                q = np.einsum("ij,ij->i", v, v)
                var[s:e] = c.sigma2 * np.maximum(1.0 - q + c.trend_variance(f - mw[:, 1:]), 0.0)

        n_threads = self.n_threads or min(4, os.cpu_count() or 1)
        with blas_threads(1):  # parallel over chunks instead (numpy releases the GIL in BLAS and ufuncs)
            if n_threads > 1 and m > 2 * chunk:
                with ThreadPoolExecutor(n_threads) as pool:
                    list(pool.map(work, starts))
            else:
                for s in starts:
                    work(s)
        mean = mean * self._ystd + self._ymean + self._offset_at(u)
        if var is not None:
            var = var * self._ystd**2
        return mean, var

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return self.predict(u, return_variance=False)[0]

    def posterior_covariance(self, u: np.ndarray) -> np.ndarray:
        """Covariance of the Gaussian process at the points ``u`` (m, d) given the training data, that of the
        latent response without the noise: sigma^2 [R(u, u) - r^T C^-1 r + t G^-1 t^T], r the correlations with the
        training points, C = R + nugget I, t = f(u) - r^T C^-1 F, G = F^T C^-1 F (Kriging with the trend estimated;
        its diagonal is :meth:`predict`'s variance). Shape (m, m); m^2 memory, for a sample of a population."""
        if self._cond is None:
            raise RuntimeError("fit first")
        c = self._cond
        u = np.atleast_2d(np.asarray(u, dtype=float))
        a = u / self.hyperparameters.scale
        r = _corr(a, c.x)
        v = r @ c.chol_inv_t
        cov = _corr(a, a)
        cov -= v @ v.T
        cov += c.trend_covariance(self._basis(u) - r @ c.c_inv_f)
        cov *= c.sigma2 * self._ystd**2
        return cov

    def posterior_draws(self, u: np.ndarray, n_draws: int, rng: np.random.Generator) -> np.ndarray:
        """``n_draws`` joint draws of the latent response at the points ``u`` from the Gaussian process given the
        training data (its mean and :meth:`posterior_covariance`), shape (m, n_draws)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        return gaussian_draws(self.predict(u, return_variance=False)[0], self.posterior_covariance(u), n_draws, rng)

    @property
    def training_outputs(self) -> np.ndarray:
        """The outputs the surrogate was fitted to (a copy)."""
        if self._y is None:
            raise RuntimeError("fit first")
        return self._y.copy()

    @property
    def noise_variance(self) -> float:
        """Variance of the noise the fit attributes to the training outputs (output units squared): the relative
        nugget times the process variance (0 up to the stabilising nugget for an interpolating fit)."""
        if self._cond is None:
            raise RuntimeError("fit first")
        return self.hyperparameters.nugget * self._cond.sigma2 * self._ystd**2

    @property
    def noise_sd(self) -> float:
        """Standard deviation of that noise (output units)."""
        return float(np.sqrt(max(self.noise_variance, 0.0)))

    @property
    def process_variance(self) -> float:
        """Variance sigma^2 of the Gaussian process Z (output units squared)."""
        if self._cond is None:
            raise RuntimeError("fit first")
        return self._cond.sigma2 * self._ystd**2

    def leave_one_out(self) -> tuple[np.ndarray, np.ndarray]:
        """Leave-one-out prediction of every training output with the hyperparameters kept, in closed form
        (Dubrule 1983, with the trend re-estimated): with C = R + nugget I and Q = C^-1 - C^-1 F (F^T C^-1 F)^-1
        F^T C^-1, the residual of output i is (Q y)_i / Q_ii = alpha_i / Q_ii and the variance of y_i given the
        others sigma^2 / Q_ii. Returns the predictions (those of a refit without point i) and the variance of the
        predicted mean (that variance less the noise's; with this fit's sigma^2, which a refit would re-estimate)."""
        if self._cond is None:
            raise RuntimeError("fit first")
        c = self._cond
        q_diag = np.einsum("ij,ij->i", c.chol_inv_t, c.chol_inv_t) - c.trend_variance(c.c_inv_f)
        ys = (self._fitted_y - self._ymean) / self._ystd
        mean = (ys - c.alpha / q_diag) * self._ystd + self._ymean + self._offset_at(self._x)
        var = c.sigma2 * np.maximum(1.0 / q_diag - self.hyperparameters.nugget, 0.0) * self._ystd**2
        return mean, var

    # ------------------------------------------------------------- interop
    def to_openturns(self):
        """OpenTURNS ``GaussianProcessRegressionResult`` conditioned on the same data and hyperparameters
        (correlation lengths fixed, not re-optimised); used to cross-check :meth:`predict`."""
        import openturns as ot

        if self._cond is None:
            raise RuntimeError("fit first")
        d = self._x.shape[1]
        ys = (self._fitted_y - self._ymean) / self._ystd
        amplitude = math.sqrt(self._cond.sigma2)
        cov = ot.SquaredExponential(list(map(float, self.hyperparameters.scale)), [amplitude])
        cov.setNuggetFactor(self.hyperparameters.nugget)
        fitter = ot.GaussianProcessFitter(
            ot.Sample(self._x), ot.Sample(ys[:, None]), cov,
            (ot.LinearBasisFactory if self._linear else ot.ConstantBasisFactory)(d).build()
        )
        fitter.setOptimizeParameters(False)
        fitter.run()
        reg = ot.GaussianProcessRegression(fitter.getResult())
        reg.run()
        return reg.getResult()

    def predict_openturns(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mean and variance predicted by OpenTURNS itself (slow; for verification)."""
        import openturns as ot

        res = self.to_openturns()
        s = ot.Sample(np.atleast_2d(np.asarray(u, dtype=float)))
        mean = np.array(res.getMetaModel()(s), dtype=float).ravel()
        var = np.array(ot.GaussianProcessConditionalCovariance(res).getConditionalMarginalVariance(s)).ravel()
        return mean * self._ystd + self._ymean + self._offset_at(np.atleast_2d(u)), var * self._ystd**2


def gaussian_draws(mean: np.ndarray, cov: np.ndarray, n_draws: int, rng: np.random.Generator) -> np.ndarray:
    """``n_draws`` draws of N(mean, cov), shape (m, n_draws): mean + P L z with P L L^T P^T = cov the pivoted Cholesky
    factorisation (LAPACK dpstrf), its columns stopped at the numerical rank r, where the largest remaining pivot
    falls below m eps times the largest diagonal (Higham, Accuracy and Stability of Numerical Algorithms, 10.3).
    After round-off a Kriging's posterior covariance over a population is barely definite or slightly indefinite
    (the default study's: rank 2,845 of m = 3,000), and with few random inputs of low rank (63 with 3): the pivoted
    factor needs no jitter, and costs O(m^2 r)."""
    mean = np.asarray(mean, dtype=float)
    cov = np.asarray(cov, dtype=float)
    m = mean.size
    with blas_threads(1):  # a threaded factor's or product's last bits follow the thread count; the docs promise not
        factor, piv, rank, info = lapack.dpstrf(cov, lower=1)
        if info < 0:
            raise ValueError(f"gaussian_draws: LAPACK dpstrf rejected argument {-info}")
        z = rng.standard_normal((rank, n_draws))
        draws = np.empty((m, n_draws))
        # L z, the pivoted rows first (a triangular product reads the lower triangle only: the factor's upper one
        # holds the input's leftovers), then the rest; scattering the draws, not the m x m factor, to their rows
        draws[piv[:rank] - 1] = blas.dtrmm(1.0, factor[:rank, :rank], z, lower=1)
        if rank < m:
            draws[piv[rank:] - 1] = factor[rank:, :rank] @ z
        draws += mean[:, None]
        return draws


class ShiftedSurrogate:
    """A surrogate minus a constant ``offset``: one level of ``akmcs_multi(levels=...)``, whose levels all
    share one Kriging of the response (a Kriging whose trend holds a constant is shift-equivariant)."""

    def __init__(self, surrogate, offset: float):
        self.surrogate, self.offset = surrogate, float(offset)

    @property
    def hyperparameters(self) -> KrigingHyperparameters:
        return self.surrogate.hyperparameters

    def predict(self, u: np.ndarray, *, return_variance: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Mean minus the offset and the (unchanged) variance at ``u``."""
        mu, var = self.surrogate.predict(u, return_variance=return_variance)
        return mu - self.offset, var

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return self.predict(u, return_variance=False)[0]
