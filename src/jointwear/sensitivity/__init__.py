"""Sensitivity of the reliability and of the wear to every random variable.

* :func:`sobol_indices` - first-order and total Sobol' indices of a vectorised function (usually the
  Kriging surrogate of the max wear) under independent marginals, by SALib's Saltelli/Jansen estimators.
* :func:`reliability_derivatives` - derivatives of Pf with respect to the mean and the standard deviation of
  each normal input (independent or in a Gaussian copula), from one Monte Carlo population (score-function /
  likelihood-ratio estimator); :func:`fill_by_finite_differences` - those of the other inputs, by central
  differences with common random numbers on a failure function of the population; :func:`mean_scores` - the
  score estimator's weights (to apply it to other failure probabilities of the same points, e.g. posterior draws).
* :func:`mean_shift_table` - the paper's one-at-a-time mean shifts (80 % / 120 %), given any function that
  returns the reliability for a list of marginals; :func:`unresolved_pairs` - neighbours of a ranking that the
  surrogate's error does not separate.
"""

from jointwear.sensitivity.derivatives import (
    ReliabilityDerivatives,
    fill_by_finite_differences,
    mean_scores,
    perturbed_column,
    reliability_derivatives,
)
from jointwear.sensitivity.mean_shift import (
    MeanShiftResult,
    mean_shift_table,
    shifted_marginal,
    unresolved_pairs,
)
from jointwear.sensitivity.sobol import SobolResult, sobol_indices

__all__ = [
    "MeanShiftResult",
    "ReliabilityDerivatives",
    "SobolResult",
    "fill_by_finite_differences",
    "mean_scores",
    "mean_shift_table",
    "perturbed_column",
    "reliability_derivatives",
    "shifted_marginal",
    "sobol_indices",
    "unresolved_pairs",
]
