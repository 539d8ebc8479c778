"""A series system's surrogate: one Kriging per component, the system's response their minimum (AK-SYS).

A series system fails when its first component fails: y(u) = min_j y_j(u). Each y_j is smooth where the system's
response has a kink (where two components' responses cross), and one Kriging of the minimum is confidently wrong
there. AK-SYS (Fauriat & Gayton, Reliab. Eng. Syst. Saf. 123 (2014) 137-144) keeps one Kriging per component and
judges a point by the component with the smallest mean: the system's mean is min_j mu_j and its Kriging variance
that component's, so Echard's U and the ESC error of AK-MCS apply unchanged. One call evaluates every component, so
the components cost no extra call.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ndtr

from .kriging import KrigingSurrogate

__all__ = ["SeriesSurrogate", "series_failure_probability"]


def series_failure_probability(margins, scatter_sds) -> np.ndarray:
    """P(min_j (g_j + e_j) < 0) = 1 - prod_j Phi(g_j / tau_j) for components' margins ``margins[j]`` (any shape,
    one array per component) and independent scatters e_j ~ N(0, tau_j^2); a component with tau_j = 0 survives
    exactly where g_j >= 0, and a NaN margin is a failure."""
    survive: np.ndarray | float = 1.0
    for g, tau in zip(margins, scatter_sds):
        g = np.asarray(g, dtype=float)
        p = ndtr(g / tau) if tau > 0 else (g >= 0).astype(float)
        survive = survive * np.where(np.isnan(g), 0.0, p)
    return np.asarray(1.0 - survive)


def governing(mean: np.ndarray, var: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each row's smallest component mean (n, J) -> (n,) and the variance of the component that attains it."""
    rows, j = np.arange(mean.shape[0]), np.argmin(mean, axis=1)
    return mean[rows, j], var[rows, j]


class SeriesSurrogate:
    """Kriging of each component response of a series system; the system's response is their minimum.

    ``n_components`` Krigings, each fitted on the rows where its own response is finite; ``kriging``: keyword
    arguments of every :class:`KrigingSurrogate`. Component j's seed is ``seed`` * 1000 + j, that of column j of
    ``akmcs_multi``: where one component governs at every design point, its Kriging is the one a single Kriging of
    the system's response would be. A component with fewer than two finite responses (a joint that does not wear
    has a +inf life: it never fails) is not fitted and predicts +inf; ``fitted`` says which are."""

    def __init__(self, n_components: int, seed: int | None = 0, **kriging):
        if n_components < 1:
            raise ValueError(f"n_components must be at least 1; got {n_components}")
        self.components = [KrigingSurrogate(seed=None if seed is None else int(seed) * 1000 + j, **kriging)
                           for j in range(n_components)]
        self.fitted = np.ones(n_components, dtype=bool)
        self._y: np.ndarray | None = None

    def fit(self, x: np.ndarray, y: np.ndarray, *, optimize: bool = True) -> SeriesSurrogate:
        """Fit every component to its column of ``y`` (n, J) on its finite rows; ``optimize=False`` keeps the
        correlation lengths."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        y = np.asarray(y, dtype=float).reshape(x.shape[0], -1)
        if y.shape[1] != len(self.components):
            raise ValueError(f"SeriesSurrogate.fit: y has {y.shape[1]} columns for {len(self.components)} components")
        for j, component in enumerate(self.components):
            ok = np.isfinite(y[:, j])
            self.fitted[j] = ok.sum() >= 2
            if self.fitted[j]:
                component.fit(x[ok], y[ok, j], optimize=optimize)
        if not self.fitted.any():
            raise ValueError("no component has 2 finite responses to fit a Kriging to (a response is +inf where the "
                             "component never fails, NaN where its call failed)")
        self._y = y
        return self

    @property
    def fitted_components(self) -> list[KrigingSurrogate]:
        """The components' Krigings that were fitted (those with a finite response somewhere)."""
        return [c for c, f in zip(self.components, self.fitted) if f]

    def _per_component(self, value, fill):
        """``value(component)`` of every fitted component, ``fill`` for the others."""
        return [value(c) if f else fill for c, f in zip(self.components, self.fitted)]

    def component_predictions(self, u: np.ndarray, *, variance: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Mean and Kriging variance (None with ``variance=False``) of every component at ``u``, each (m, J)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        never = (np.full(u.shape[0], np.inf), np.zeros(u.shape[0]))
        preds = self._per_component(lambda c: c.predict(u, return_variance=variance), never)
        return (np.column_stack([p[0] for p in preds]),
                np.column_stack([p[1] for p in preds]) if variance else None)

    def predict(self, u: np.ndarray, *, return_variance: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """The system's mean min_j mu_j(u) and the Kriging variance of the component that attains it (AK-SYS)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        if not return_variance:
            return self.component_predictions(u, variance=False)[0].min(axis=1), None
        return governing(*self.component_predictions(u))

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return self.predict(u, return_variance=False)[0]

    def posterior_component_draws(self, u: np.ndarray, n_draws: int, rng: np.random.Generator) -> np.ndarray:
        """Joint draws of every component's latent response at ``u`` from its own posterior (the components'
        Krigings are independent), shape (J, m, n_draws)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        never = np.full((u.shape[0], n_draws), np.inf)
        return np.stack(self._per_component(lambda c: c.posterior_draws(u, n_draws, rng), never))

    def posterior_draws(self, u: np.ndarray, n_draws: int, rng: np.random.Generator) -> np.ndarray:
        """Joint draws of the system's latent response at ``u``: the minimum over the components of their
        :meth:`posterior_component_draws`, shape (m, n_draws)."""
        return self.posterior_component_draws(u, n_draws, rng).min(axis=0)

    # ----------------------------------------------------------- a noisy model: each component's own scatter
    @property
    def scatter_sds(self) -> np.ndarray:
        """Each component's call-to-call scatter: its Kriging's noise standard deviation."""
        return np.array(self._per_component(lambda c: c.noise_sd, 0.0))

    def failure_probability(self, u: np.ndarray, thresholds) -> np.ndarray:
        """P(min_j (y_j(u) + e_j) < t_k) at every point and threshold, shape (n, K): each component's mean plus its
        own scatter e_j (:attr:`scatter_sds`), independent from component to component
        (:func:`series_failure_probability`). A single scatter for the system would be wrong where the components
        scatter differently, and where two of them lie near a threshold together (each may fail)."""
        mean = self.component_predictions(u, variance=False)[0]
        t = np.asarray(thresholds, dtype=float).reshape(1, -1)
        return series_failure_probability([mean[:, j:j + 1] - t for j in range(mean.shape[1])], self.scatter_sds)

    def response_draws(self, u: np.ndarray, z: np.ndarray) -> np.ndarray:
        """One draw of the system's noisy response per point: min_j (mu_j(u) + tau_j z_j) for standard normal
        draws ``z`` of shape (n, J)."""
        mean = self.component_predictions(u, variance=False)[0]
        return (mean + np.asarray(z, dtype=float) * self.scatter_sds[None, :]).min(axis=1)

    # ----------------------------------------------------------- what the study's fit report reads
    @property
    def training_outputs(self) -> np.ndarray:
        """The system's response min_j y_j on the rows where every component's is finite."""
        if self._y is None:
            raise RuntimeError("fit first")
        return self._y[self._complete].min(axis=1)

    @property
    def _complete(self) -> np.ndarray:
        """The rows where every fitted component's response is finite."""
        return np.isfinite(self._y[:, self.fitted]).all(axis=1)

    def governing_shares(self) -> np.ndarray:
        """Each component's share of the complete training rows where its response is the smallest."""
        y = self._y[self._complete]
        return np.bincount(np.argmin(y, axis=1), minlength=len(self.components)) / max(y.shape[0], 1)

    def _weighted(self, values) -> float:
        """The mean of per-component values weighted by :meth:`governing_shares`."""
        return float(np.dot(self.governing_shares(), np.asarray(values, dtype=float)))

    @property
    def noise_variance(self) -> float:
        """One number for the call-to-call scatter of the system's response (the study's fit report): each
        component's noise variance weighted by its share of the design points it governs. R(N) takes each
        component's own (:meth:`failure_probability`)."""
        return self._weighted(self._per_component(lambda c: c.noise_variance, 0.0))

    @property
    def noise_sd(self) -> float:
        return math.sqrt(max(self.noise_variance, 0.0))

    @property
    def process_variance(self) -> float:
        """The components' process variances weighted as :attr:`noise_variance`."""
        return self._weighted(self._per_component(lambda c: c.process_variance, 0.0))

    def leave_one_out(self) -> tuple[np.ndarray, np.ndarray]:
        """Leave-one-out prediction of the system's response on the complete rows: the minimum of the components'
        own (:meth:`KrigingSurrogate.leave_one_out`), and the variance of the component that attains it."""
        complete = self._complete
        means, variances = [], []
        for j, c in enumerate(self.components):
            full_mean = np.full(self._y.shape[0], np.inf if not self.fitted[j] else np.nan)
            full_var = np.zeros(self._y.shape[0]) if not self.fitted[j] else np.full(self._y.shape[0], np.nan)
            if self.fitted[j]:
                rows = np.isfinite(self._y[:, j])
                full_mean[rows], full_var[rows] = c.leave_one_out()
            means.append(full_mean[complete])
            variances.append(full_var[complete])
        return governing(np.column_stack(means), np.column_stack(variances))
