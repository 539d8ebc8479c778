"""jointwear.design: uncertainty control, the cheapest tolerance grades, fits and material specifications that
make a mechanism reach a target life at a target reliability (docs/design.md).

The settings are imported by :mod:`jointwear.config`; the rest is loaded on first use so that the config does
not import the study.
"""

from importlib import import_module
from typing import TYPE_CHECKING

from jointwear.design.settings import DesignSettings

if TYPE_CHECKING:  # the names type checkers see; at run time __getattr__ imports them on first use
    from jointwear.design.candidates import Candidate, Control, Option, build_controls, enumerate_candidates
    from jointwear.design.checks import design_problems
    from jointwear.design.cost import grade_costs, tolerance_cost
    from jointwear.design.results import DesignResult
    from jointwear.design.search import run_design, verify

_LAZY = {
    "Candidate": "candidates", "Control": "candidates", "Option": "candidates", "build_controls": "candidates",
    "enumerate_candidates": "candidates", "design_problems": "checks", "grade_costs": "cost",
    "tolerance_cost": "cost", "DesignResult": "results", "run_design": "search", "verify": "search",
}

__all__ = ["DesignSettings", "Candidate", "Control", "Option", "build_controls", "enumerate_candidates",
           "design_problems", "grade_costs", "tolerance_cost", "DesignResult", "run_design", "verify"]


def __getattr__(name: str) -> object:
    if name in _LAZY:
        return getattr(import_module(f"jointwear.design.{_LAZY[name]}"), name)
    raise AttributeError(f"module 'jointwear.design' has no attribute {name!r}")


def __dir__() -> list[str]:
    # the lazily imported names too, so that tab completion offers them
    return sorted(set(__all__) | set(globals()))
