"""jointwear.reliability: a reliability engine for any vectorised limit state (it knows nothing about wear).

Failure is g(X) < 0; inputs are given as marginals (frozen ``scipy.stats``, scipy's new distribution objects
or OpenTURNS distributions) and, for dependent inputs, an OpenTURNS copula or a correlation matrix
(:mod:`.inputs`). How g is called (executor, cache, callbacks, NaN policy) is one :class:`Evaluation` that
every method takes. See ``docs/reliability.md`` for the methods, choices, NaN rule and benchmark numbers.
"""

from . import problems
from .akis import akis
from .akmcs import akmcs, akmcs_multi
from .evaluation import AllCallsFailedError, Evaluation, LimitStateCaller
from .inputs import (
    IsoTransform,
    Marginal,
    as_marginal,
    check_copula,
    check_marginals,
    sample,
)
from .kriging import KrigingSurrogate, ShiftedSurrogate, blas_threads
from .learning import esc_absolute_error, esc_error, esc_errors
from .methods import form, importance_sampling, monte_carlo, sorm, subset_simulation
from .results import (
    Z95,
    IterationRecord,
    MultiReliabilityResult,
    ReliabilityResult,
    cov_population,
    failure_probability,
    failure_spread,
    population_size,
    posterior_failure_spread,
)
from .system import SeriesSurrogate

__all__ = [
    "AllCallsFailedError",
    "Evaluation",
    "IsoTransform",
    "IterationRecord",
    "KrigingSurrogate",
    "LimitStateCaller",
    "Marginal",
    "MultiReliabilityResult",
    "ReliabilityResult",
    "SeriesSurrogate",
    "ShiftedSurrogate",
    "Z95",
    "akis",
    "akmcs",
    "akmcs_multi",
    "as_marginal",
    "blas_threads",
    "check_copula",
    "check_marginals",
    "esc_absolute_error",
    "esc_error",
    "esc_errors",
    "failure_probability",
    "failure_spread",
    "form",
    "importance_sampling",
    "monte_carlo",
    "cov_population",
    "population_size",
    "posterior_failure_spread",
    "problems",
    "sample",
    "sorm",
    "subset_simulation",
]
