"""`check` warns of a fit control whose clearance the study correlates with another input: the fit's options set the
clearance's spread only, while the correlated pin radius keeps its spread and coefficient (a design lead's audit
found the slider-crank preset's corr(R_j, c) = -0.537, set from its IT8/IT7 fit, kept for an IT9/IT8 option)."""

from jointwear.config import load_config, updated
from jointwear.study.checks import design_warnings

FIT = {"options": [{"name": "IT9/IT8", "hole_grade": "IT9", "shaft_grade": "IT8", "cost": 0.0},
                   {"name": "IT8/IT7", "hole_grade": "IT8", "shaft_grade": "IT7", "cost": 0.2}]}
DESIGN = {"targets": [{"reliability": 0.9, "life_cycles": 40_000}], "fit": FIT}


def _warnings(changes):
    return [w for w in design_warnings(updated(load_config("flores_slider_crank"), {"design": DESIGN, **changes}))
            if "correlated" in w]


def test_a_fit_of_a_correlated_clearance_is_warned_of_naming_the_partner_and_its_coefficient():
    (warning,) = _warnings({})
    assert warning.startswith("design.fit:") and "'Rj' (-0.537)" in warning and "'c'" in warning


def test_without_the_correlation_there_is_nothing_to_warn_of():
    assert _warnings({"uncertainty.correlation": None}) == []
