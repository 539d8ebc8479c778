"""The random inputs of the engine: marginals from any well-kept library, an optional copula, the
iso-probabilistic transform to standard-normal space and sampling.

Accepted marginals (one per input, continuous, univariate):

* frozen ``scipy.stats`` distributions (``stats.norm(1, 2)``, ``stats.lognorm(0.1, scale=2e11)``...);
* scipy's new distribution objects (``stats.Normal(mu=1, sigma=2)``, ``stats.make_distribution(...)(...)``,
  shifted/scaled/truncated ones);
* OpenTURNS univariate distributions (``ot.Normal(1, 2)``, ``ot.Gumbel(...)``...).

Dependence: ``copula=None`` (independent inputs), any OpenTURNS copula of the right dimension
(``ot.NormalCopula``, ``ot.ClaytonCopula``...), or a correlation matrix, read as the correlation of a normal
copula (:func:`jointwear.uncertainty.copulas.normal_copula`, ``measure="pearson"``).

The transform for dependent inputs is OpenTURNS' iso-probabilistic transform of the copula: every input is
first mapped to its normal score z_i = Phi^-1(F_i(x_i)) (exactly as for independent inputs), then the
transform of ``ot.JointDistribution([N(0, 1)] * d, copula)`` takes z to independent standard normals
(Nataf for elliptical copulas, Rosenblatt otherwise). Both transforms depend on the marginals only through
F_i(x_i), so this is OpenTURNS' transform of the joint distribution of x itself, with the marginals' tails
kept exact (``isf``/``sf`` above the median).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy import stats
from scipy.special import ndtr, ndtri

from .checks import check_positive_int

__all__ = ["Marginal", "as_marginal", "check_marginals", "check_copula", "IsoTransform", "sample"]


def _is_scipy_frozen(m: Any) -> bool:
    return isinstance(getattr(m, "dist", None), (stats.rv_continuous, stats.rv_discrete)) and callable(
        getattr(m, "ppf", None))


def _is_scipy_new(m: Any) -> bool:
    return all(callable(getattr(m, a, None)) for a in ("icdf", "iccdf", "cdf", "ccdf", "sample", "standard_deviation"))


def _is_openturns(m: Any) -> bool:
    try:
        import openturns as ot
    except ImportError:  # pragma: no cover - a declared dependency
        return False
    return isinstance(m, (ot.Distribution, ot.DistributionImplementation))


def _ot_column(sample: Any) -> np.ndarray:
    return np.asarray(sample, dtype=float).reshape(-1)


class Marginal:
    """One input distribution seen through the few methods the engine needs.

    Wraps a frozen ``scipy.stats`` distribution (its own methods are called, so results are those of scipy
    exactly), a new-style scipy distribution (``cdf``/``ccdf``/``icdf``/``iccdf``/``sample``) or an OpenTURNS
    distribution (``computeCDF``/``computeComplementaryCDF``/``computeQuantile``; random draws by inversion
    of a numpy uniform, so that the numpy seed decides them, not OpenTURNS' global generator).
    """

    def __init__(self, dist: Any):
        self.dist = dist
        if _is_scipy_frozen(dist):
            self.kind = "scipy"
            self.name = dist.dist.name
            normal = self.name == "norm"
        elif _is_openturns(dist):
            self.kind = "openturns"
            impl = dist.getImplementation() if hasattr(dist, "getImplementation") else dist
            self.name = impl.getClassName()
            normal = self.name == "Normal"
        elif _is_scipy_new(dist):
            self.kind = "scipy_new"
            self.name = type(dist).__name__
            normal = isinstance(dist, stats.Normal)
        else:
            raise TypeError(f"{type(dist).__name__} is not a supported distribution")
        # normal marginals are mapped exactly by mu + sigma u
        self.affine = (float(self.mean()), float(self.std())) if normal else None

    # -- probabilities
    def cdf(self, x: np.ndarray) -> np.ndarray:
        if self.kind == "scipy":
            return self.dist.cdf(x)
        if self.kind == "scipy_new":
            return np.asarray(self.dist.cdf(x), dtype=float)
        return _ot_column(self.dist.computeCDF(np.asarray(x, dtype=float).reshape(-1, 1)))

    def sf(self, x: np.ndarray) -> np.ndarray:
        if self.kind == "scipy":
            return self.dist.sf(x)
        if self.kind == "scipy_new":
            return np.asarray(self.dist.ccdf(x), dtype=float)
        return _ot_column(self.dist.computeComplementaryCDF(np.asarray(x, dtype=float).reshape(-1, 1)))

    def ppf(self, p: np.ndarray) -> np.ndarray:
        if self.kind == "scipy":
            return self.dist.ppf(p)
        if self.kind == "scipy_new":
            return np.asarray(self.dist.icdf(p), dtype=float)
        return _ot_column(self.dist.computeQuantile(np.asarray(p, dtype=float).reshape(-1)))

    def isf(self, q: np.ndarray) -> np.ndarray:
        if self.kind == "scipy":
            return self.dist.isf(q)
        if self.kind == "scipy_new":
            return np.asarray(self.dist.iccdf(q), dtype=float)
        return _ot_column(self.dist.computeQuantile(np.asarray(q, dtype=float).reshape(-1), True))

    # -- moments and draws
    def mean(self) -> float:
        if self.kind == "openturns":
            return float(self.dist.getMean()[0])
        return float(self.dist.mean())

    def std(self) -> float:
        if self.kind == "scipy":
            return float(self.dist.std())
        if self.kind == "scipy_new":
            return float(self.dist.standard_deviation())
        return float(self.dist.getStandardDeviation()[0])

    def rvs(self, n: int, rng: np.random.Generator) -> np.ndarray:
        if self.kind == "scipy":
            return self.dist.rvs(size=n, random_state=rng)
        if self.kind == "scipy_new":
            return np.asarray(self.dist.sample(n, rng=rng), dtype=float)
        return self.ppf(rng.random(n))

    # -- standard-normal score z = Phi^-1(F(x)) and back (tails through sf/isf: no round-off at |z| = 8)
    def to_normal(self, x: np.ndarray) -> np.ndarray:
        if self.affine is not None:
            mu, sd = self.affine
            return (x - mu) / sd
        xs = np.atleast_1d(np.asarray(x, dtype=float))
        p = np.asarray(self.cdf(xs), dtype=float)
        z = ndtri(np.clip(p, 1e-300, 1.0))
        upper = p >= 0.5  # the upper tail through sf, computed there only
        if np.any(upper):
            z[upper] = -ndtri(np.clip(np.asarray(self.sf(xs[upper]), dtype=float), 1e-300, 1.0))
        return z.reshape(np.shape(x))

    def from_normal(self, z: np.ndarray) -> np.ndarray:
        if self.affine is not None:
            mu, sd = self.affine
            return mu + sd * z
        lo = z < 0
        x = np.empty_like(z)
        if lo.any():
            x[lo] = self.ppf(ndtr(z[lo]))
        if (~lo).any():
            x[~lo] = self.isf(ndtr(-z[~lo]))
        return x


def as_marginal(dist: Any) -> Marginal:
    """The :class:`Marginal` adapter of any accepted distribution (a ``Marginal`` is returned as is)."""
    return dist if isinstance(dist, Marginal) else Marginal(dist)


def check_marginals(marginals: Any) -> list:
    """Validate a sequence of continuous univariate distributions (see the module docstring for the kinds
    accepted); returns them as a list, unchanged. Errors name the position and what is wrong."""
    one = _is_scipy_frozen(marginals) or _is_openturns(marginals) or _is_scipy_new(marginals)
    if one or not isinstance(marginals, Sequence) or isinstance(marginals, (str, bytes)):
        raise ValueError(
            "marginals must be a sequence (list or tuple) of distributions (frozen scipy.stats, scipy's new "
            f"distribution objects or OpenTURNS), one per input variable; got {type(marginals).__name__}"
        )
    if len(marginals) == 0:
        raise ValueError("marginals is empty: give one distribution per input variable")
    out = []
    for i, m in enumerate(marginals):
        if isinstance(m, Marginal):
            m = m.dist
        if isinstance(m, (stats.rv_continuous, stats.rv_discrete)):
            raise ValueError(
                f"marginals[{i}] is the unfrozen distribution scipy.stats.{m.name}; freeze it with its "
                f"parameters, e.g. scipy.stats.{m.name}(loc=..., scale=...)"
            )
        if _is_scipy_frozen(m):
            if isinstance(m.dist, stats.rv_discrete):
                raise ValueError(f"marginals[{i}] ({m.dist.name}) is discrete; only continuous marginals are supported")
        elif _is_openturns(m):
            if m.getDimension() != 1:
                raise ValueError(f"marginals[{i}] is a {m.getDimension()}-dimensional OpenTURNS distribution; give "
                                 "one univariate marginal per input and the dependence as `copula`")
            if not m.isContinuous():
                raise ValueError(f"marginals[{i}] ({m.getClassName()}) is not continuous; only continuous marginals "
                                 "are supported")
        elif _is_scipy_new(m):
            # scipy exposes no public base class for its discrete distributions: recognise them by name
            if any(c.__name__ == "DiscreteDistribution" for c in type(m).__mro__):
                raise ValueError(f"marginals[{i}] ({type(m).__name__}) is discrete; only continuous marginals "
                                 "are supported")
        else:
            raise ValueError(f"marginals[{i}] is a {type(m).__name__}, not a distribution (frozen scipy.stats, "
                             "scipy's new distribution objects or OpenTURNS)")
        a = as_marginal(m)
        sd = a.std()
        if not (np.isfinite(sd) and sd > 0):
            why = (" (scipy gives NaN for parameters outside a distribution's domain, e.g. scale <= 0, and for a law "
                   "without a variance, such as the Cauchy)" if np.isnan(sd) else "")
            raise ValueError(f"marginals[{i}] ({a.name}) has standard deviation {sd}; it must be finite and > 0{why}")
        out.append(m)
    return out


def check_copula(copula: Any, dim: int) -> Any:
    """None for independent inputs, else an OpenTURNS copula of dimension ``dim``.

    ``copula``: None, an OpenTURNS copula, or a correlation matrix (array-like, the normal copula's
    correlation, see :func:`jointwear.uncertainty.copulas.normal_copula`). An independent copula gives None,
    so that independent inputs always take the exact per-marginal transform.
    """
    if copula is None:
        return None
    import openturns as ot

    if not isinstance(copula, (ot.Distribution, ot.DistributionImplementation)):
        from jointwear.uncertainty.copulas import normal_copula

        try:
            copula = normal_copula(np.asarray(copula, dtype=float))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"copula: {exc}") from None
    if not copula.isCopula():
        raise ValueError(f"copula must be an OpenTURNS copula (e.g. ot.NormalCopula) or a correlation matrix; "
                         f"got the distribution {copula.getClassName()}")
    if copula.getDimension() != dim:
        raise ValueError(f"copula has dimension {copula.getDimension()} but there are {dim} marginals")
    if copula.hasIndependentCopula():
        return None
    return copula


class IsoTransform:
    """Inputs x <-> independent standard normals u.

    Independent inputs: x_i = F_i^-1(Phi(u_i)), per marginal (normal marginals exactly mu + sigma u; tails
    through the survival functions, so u = +/-8 maps without round-off). Dependent inputs (``copula``): the
    normal scores z_i = Phi^-1(F_i(x_i)) go through OpenTURNS' iso-probabilistic transform of the copula
    (module docstring).

    Parameters
    ----------
    marginals:
        One distribution per input (any kind :func:`check_marginals` accepts).
    copula:
        None, an OpenTURNS copula or a correlation matrix (:func:`check_copula`).
    """

    def __init__(self, marginals: Sequence, copula: Any = None):
        self.marginals = list(marginals)
        self.dim = len(self.marginals)
        self._m = [as_marginal(m) for m in self.marginals]
        self.copula = check_copula(copula, self.dim)
        self._to_u = self._to_z = None
        if self.copula is not None:
            import openturns as ot

            joint = ot.JointDistribution([ot.Normal()] * self.dim, self.copula)
            self._to_u = joint.getIsoProbabilisticTransformation()
            self._to_z = joint.getInverseIsoProbabilisticTransformation()

    @property
    def independent(self) -> bool:
        return self.copula is None

    def to_x(self, u: np.ndarray) -> np.ndarray:
        """Physical points from standard-normal points (rows)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        z = u if self._to_z is None else self._ot_map(self._to_z, u)
        x = np.empty_like(z)
        for i, m in enumerate(self._m):
            x[:, i] = m.from_normal(z[:, i])
        return x

    def normal_score(self, i: int, values: np.ndarray) -> np.ndarray:
        """Phi^-1(F_i(values)) of input i alone: its column of :meth:`to_u` when the inputs are independent (a
        population with one column changed is mapped by that column only)."""
        return self._m[i].to_normal(np.asarray(values, dtype=float))

    def to_u(self, x: np.ndarray) -> np.ndarray:
        """Standard-normal points from physical points (rows)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        z = np.empty_like(x)
        for i, m in enumerate(self._m):
            z[:, i] = m.to_normal(x[:, i])
        if self._to_u is None:
            return z
        return self._ot_map(self._to_u, z)

    @staticmethod
    def _ot_map(fn, a: np.ndarray) -> np.ndarray:
        import openturns as ot

        if a.shape[0] == 0:
            return a.copy()
        return np.asarray(fn(ot.Sample(a)), dtype=float).reshape(a.shape)


def sample(marginals: Sequence, n: int, seed: Any = None, copula: Any = None) -> np.ndarray:
    """``n`` random input points (physical space), shape (n, d).

    Independent inputs: column i is ``marginals[i]``'s own sampler with one ``numpy.random.default_rng(seed)``
    shared in order (for frozen scipy marginals ``m.rvs(size=n, random_state=rng)``). Dependent inputs:
    u ~ N(0, I) from that generator, mapped by :class:`IsoTransform` (OpenTURNS' transform of the copula).
    """
    marginals = check_marginals(marginals)
    n = check_positive_int("n", n, 0)
    rng = np.random.default_rng(seed)
    cop = check_copula(copula, len(marginals))
    if cop is None:
        return np.column_stack([as_marginal(m).rvs(n, rng) for m in marginals])
    return IsoTransform(marginals, cop).to_x(rng.standard_normal((n, len(marginals))))
