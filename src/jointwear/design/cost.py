"""Relative cost of a tolerance grade from a published tolerance-cost relation.

Two classic forms (both compared by Chase & Greenwood 1988, "Design issues in mechanical tolerance analysis",
Manufacturing Review 1(1):50-59), written with the tolerance relative to a reference tolerance T_ref:

* reciprocal power (Sutherland & Roth 1975): C(T) = a + b (T / T_ref)^-k  (k = 1: the reciprocal model);
* exponential (Speckhart 1972): C(T) = a + b exp(-k (T / T_ref - 1)).

Tighter tolerances cost more under both; at T = T_ref both give a + b.
"""

from __future__ import annotations

import math

from jointwear.design.settings import CostModel, ToleranceControl
from jointwear.uncertainty.tolerances import it_tolerance


def tolerance_cost(tolerance: float, reference: float, model: CostModel) -> float:
    """Relative cost of a tolerance band ``tolerance`` (m) against the reference band ``reference`` (m)."""
    ratio = tolerance / reference
    if model.model == "reciprocal_power":
        return model.a + model.b * ratio ** (-model.k)
    return model.a + model.b * math.exp(-model.k * (ratio - 1.0))


def grade_costs(control: ToleranceControl, nominal: float, model: CostModel) -> list[float]:
    """The cost of every grade of a toleranced length: the user's costs when given, else the cost model with
    its ``reference_grade`` as the reference, or else the loosest listed grade (that grade costs a + b)."""
    if control.costs is not None:
        return [float(c) for c in control.costs]
    bands = [it_tolerance(g, nominal) for g in control.grades]
    reference = it_tolerance(model.reference_grade, nominal) if model.reference_grade is not None else max(bands)
    return [tolerance_cost(t, reference, model) for t in bands]
