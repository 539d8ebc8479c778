"""The tolerance-cost relations against their published forms, and the grade costs built from them."""

import math

import pytest

from jointwear.design.cost import grade_costs, tolerance_cost
from jointwear.design.settings import CostModel, ToleranceControl
from jointwear.uncertainty.tolerances import it_tolerance


@pytest.mark.parametrize("a,b,k", [(0.0, 1.0, 1.0), (0.3, 2.0, 1.5), (1.0, 0.5, 0.7)])
def test_reciprocal_power_is_a_plus_b_over_t_to_the_k(a, b, k):
    # Published form (Sutherland & Roth 1975; Chase & Greenwood 1988): C(T) = A + B T^-k, with T in units of T_ref
    model = CostModel(model="reciprocal_power", a=a, b=b, k=k)
    for t, ref in ((10e-6, 40e-6), (25e-6, 25e-6), (160e-6, 100e-6)):
        assert tolerance_cost(t, ref, model) == pytest.approx(a + b * (t / ref) ** (-k), rel=1e-14)


def test_exponential_is_a_plus_b_exp():
    # Published form (Speckhart 1972): C(T) = A e^{-B T}; here a + b exp(-k (T / T_ref - 1)), equal at T = T_ref
    model = CostModel(model="exponential", a=0.2, b=1.0, k=2.0)
    assert tolerance_cost(50e-6, 50e-6, model) == pytest.approx(1.2, rel=1e-14)
    assert tolerance_cost(25e-6, 50e-6, model) == pytest.approx(0.2 + math.exp(1.0), rel=1e-14)


def test_grade_costs_use_the_loosest_grade_as_reference_and_grow_when_tighter():
    control = ToleranceControl(variable="l2", grades=["IT9", "IT10", "IT11"])
    costs = grade_costs(control, 38e-3, CostModel())
    # ISO 286-1 at 38 mm (30-50 mm row): IT9 62 um, IT10 100 um, IT11 160 um; reciprocal model, k = 1
    assert costs == pytest.approx([160 / 62, 160 / 100, 1.0], rel=1e-12)
    assert costs[0] > costs[1] > costs[2]


def test_user_costs_override_the_model():
    control = ToleranceControl(variable="l2", grades=["IT9", "IT11"], costs=[3.0, 1.0])
    assert grade_costs(control, 38e-3, CostModel()) == [3.0, 1.0]


def test_bad_cost_model_is_refused():
    with pytest.raises(ValueError, match="k must be > 0"):
        CostModel(k=0.0)
    with pytest.raises(ValueError, match="costs"):
        ToleranceControl(variable="l2", grades=["IT9", "IT11"], costs=[1.0])
    assert it_tolerance("IT9", 38e-3) == pytest.approx(62e-6)


def test_a_reference_grade_makes_a_grades_cost_independent_of_the_list():
    """Scaled to the loosest listed grade, IT9 cost 2.558 beside IT7/IT11 and 1.0 beside IT7 alone, while fit and
    material costs stayed absolute; a fixed reference grade gives IT9 one cost (ISO 286-1 at 15 mm: IT9 43 um,
    IT11 110 um; reciprocal model: 110 / 43)."""
    model = CostModel(reference_grade="IT11")
    wide = grade_costs(ToleranceControl(variable="l1", grades=["IT7", "IT9", "IT11"]), 15e-3, model)
    narrow = grade_costs(ToleranceControl(variable="l1", grades=["IT7", "IT9"]), 15e-3, model)
    assert wide[:2] == narrow and wide[1] == pytest.approx(110 / 43, rel=1e-12) and wide[2] == pytest.approx(1.0)
    loosest = grade_costs(ToleranceControl(variable="l1", grades=["IT7", "IT9"]), 15e-3, CostModel())
    assert loosest[1] == pytest.approx(1.0)  # without a reference: the list's loosest grade
    with pytest.raises(ValueError, match="reference_grade"):
        CostModel(reference_grade="IT99")


@pytest.mark.parametrize("grades, costs, pairs", [
    (["IT9", "IT10", "IT11"], [1.0, 2.0, 3.0], "IT9 at 1 < IT10 at 2, IT9 at 1 < IT11 at 3, IT10 at 2 < IT11 at 3"),
    (["IT11", "IT8", "IT10"], [1.0, 2.0, 2.5], "IT8 at 2 < IT10 at 2.5"),  # in any order of the list
])
def test_a_tighter_grade_costing_less_is_refused_naming_the_grades(grades, costs, pairs):
    """costs = [1, 2, 3] for IT9, IT10, IT11 (listed loosest first in mind) was accepted: IT9 then cost least of all
    and the design bought it, in silence."""
    from jointwear.config import load_config, updated
    from jointwear.schema import ConfigError

    with pytest.raises(ConfigError, match=rf"design\.tolerances\[0\]\.costs: a tighter grade costs less than a looser "
                                          rf"one \({pairs}\)"):
        updated(load_config(), {"design.tolerances": [{"variable": "l2", "grades": grades, "costs": costs}]})


def test_equal_or_rising_grade_costs_are_accepted():
    for costs in ([1.0, 1.0, 1.0], [3.0, 2.0, 1.0], [2.0, 2.0, 1.0]):
        assert ToleranceControl(variable="l2", grades=["IT9", "IT10", "IT11"], costs=costs).costs == costs


def test_a_fit_tighter_in_its_grades_costing_less_is_refused():
    from jointwear.design.settings import FitControl

    def fit(hole, shaft, cost, **extra):
        return {"hole_grade": hole, "shaft_grade": shaft, "cost": cost, **extra}

    with pytest.raises(ValueError, match=r"cost: a fit tighter in its grades \(with the same mean\) costs less than a "
                                         r"looser one \(IT7/IT6 at 0.1 < IT8/IT7 at 0.3, IT7/IT6 at 0.1 < IT7/IT7 at "
                                         r"0.2, IT7/IT7 at 0.2 < IT8/IT7 at 0.3\)"):
        FitControl(options=[fit("IT8", "IT7", 0.3), fit("IT7", "IT6", 0.1), fit("IT7", "IT7", 0.2)])
    # not comparable: another mean clearance, grades crossed (tighter bore, looser pin), or letters (their mean moves)
    FitControl(options=[fit("IT8", "IT7", 0.3, mean=4e-6), fit("IT7", "IT6", 0.1)])
    FitControl(options=[fit("IT6", "IT8", 0.1), fit("IT8", "IT6", 0.3)])
    FitControl(options=[{"fit": "H7/g6", "cost": 0.1}, {"fit": "H8/f7", "cost": 0.3}])
