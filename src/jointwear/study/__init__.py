"""The study: joins the wear model, the random variables, the limit state and the reliability engine for one
mechanism, behind one object (:class:`Study`), with typed results that :func:`load_results` reads back."""

from jointwear.study.comparison import StudyComparison, compare_studies
from jointwear.study.convergence import WearConvergence, run_convergence
from jointwear.study.facade import WEAR_MODEL_TAG, Study
from jointwear.study.limit_state import LimitState, life_at, life_from_history, limit_state_from_config
from jointwear.study.model_call import WearModelCall, apply_sample
from jointwear.study.reliability import (
    StudyContext,
    WearSurrogates,
    cycles_to_hours,
    population,
    run_reliability,
    study_context,
)
from jointwear.study.results import (
    ReliabilityCurve,
    SensitivityResult,
    SimulationSummary,
    StudyResults,
    ValidationResult,
    WearSummary,
    load_results,
)
from jointwear.study.sensitivity import run_sensitivity

__all__ = [
    "WEAR_MODEL_TAG", "LimitState", "ReliabilityCurve", "SensitivityResult", "SimulationSummary", "Study",
    "StudyComparison", "StudyContext", "StudyResults", "ValidationResult", "WearConvergence", "WearModelCall",
    "WearSummary", "WearSurrogates", "apply_sample", "compare_studies", "cycles_to_hours", "life_at",
    "life_from_history", "limit_state_from_config", "load_results", "population", "run_convergence",
    "run_reliability", "run_sensitivity", "study_context",
]


def __getattr__(name: str):
    """``ReliabilityResult``: the former name of :class:`ReliabilityCurve` (the engines' result keeps that name)."""
    if name == "ReliabilityResult":
        import warnings

        warnings.warn("jointwear.study.ReliabilityResult is now ReliabilityCurve (jointwear.reliability's "
                      "ReliabilityResult is the engines' result)", DeprecationWarning, stacklevel=2)
        return ReliabilityCurve
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
