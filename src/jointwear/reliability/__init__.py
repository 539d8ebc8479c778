"""jointwear.reliability: a reliability engine for any vectorised limit state (it knows nothing about wear).

Failure is g(X) < 0; inputs are independent, given as frozen ``scipy.stats`` marginals. See
``docs/reliability.md`` for the methods, choices, NaN rule and benchmark numbers.
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
]
