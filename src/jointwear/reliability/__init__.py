"""jointwear.reliability: a reliability engine for any vectorised limit state (it knows nothing about wear).

Failure is g(X) < 0; inputs are given as marginals (frozen ``scipy.stats``, scipy's new distribution objects or
OpenTURNS distributions) and, for dependent inputs, an OpenTURNS copula or a correlation matrix
(:mod:`.inputs`). See ``docs/reliability.md`` for the methods, choices, NaN rule and benchmark numbers.
"""

from . import problems
from ._core import (
    Evaluator,
    IsoTransform,
    IterationRecord,
    MultiReliabilityResult,
    ReliabilityResult,
    check_marginals,
)
from .akis import akis
from .inputs import Marginal, as_marginal, check_copula, sample
from .akmcs import akmcs, akmcs_multi, esc_absolute_error, esc_error
from .kriging import KrigingSurrogate, blas_threads
from .methods import form, importance_sampling, monte_carlo, sorm, subset_simulation

__all__ = [
    "akis",
    "akmcs",
    "akmcs_multi",
    "esc_absolute_error",
    "esc_error",
    "monte_carlo",
    "form",
    "sorm",
    "subset_simulation",
    "importance_sampling",
    "problems",
    "blas_threads",
    "KrigingSurrogate",
    "Evaluator",
    "IsoTransform",
    "IterationRecord",
    "ReliabilityResult",
    "MultiReliabilityResult",
    "check_marginals",
    "check_copula",
    "Marginal",
    "as_marginal",
    "sample",
]
