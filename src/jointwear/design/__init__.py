"""jointwear.design: uncertainty control, the cheapest tolerance grades, fits and material specifications that
make a mechanism reach a target life at a target reliability (docs/design.md).

The settings are imported by :mod:`jointwear.config`; the rest is loaded on first use so that the config does
not import the study.
"""

from importlib import import_module

from jointwear.design.settings import DesignSettings

_LAZY = {
    "Candidate": "candidates", "Control": "candidates", "Option": "candidates", "build_controls": "candidates",
    "enumerate_candidates": "candidates", "design_problems": "checks", "grade_costs": "cost",
    "tolerance_cost": "cost", "DesignResult": "results", "run_design": "search", "verify": "search",
}

__all__ = ["DesignSettings", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(import_module(f"jointwear.design.{_LAZY[name]}"), name)
    raise AttributeError(f"module 'jointwear.design' has no attribute {name!r}")
