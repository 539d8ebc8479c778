"""ISO 286 tolerances and the paper's random variables."""

import math

import pytest

from jointwear.uncertainty.tolerances import (
    clearance_from_fit,
    it_tolerance,
    length_sigma,
)
from jointwear.uncertainty.variables import (
    ClearanceSpec,
    RandomVariableSpec,
    UncertaintySettings,
)


def test_it_grades_at_2_mm_follow_iso_286_1():
    # ISO 286-1:2010 Table 1, nominal sizes up to 3 mm: IT6 = 6 um, IT7 = 10 um.
    assert it_tolerance("IT6", 2e-3) == pytest.approx(6e-6, rel=1e-12)
    assert it_tolerance("it7", 2e-3) == pytest.approx(10e-6, rel=1e-12)
    assert it_tolerance("IT7", 38e-3) == pytest.approx(25e-6, rel=1e-12)  # 30-50 mm row


def test_clearance_sigma_of_the_paper_fit():
    # paper-notes.md: Eq. 40 with IT7/IT6 at 2 mm gives sqrt(10^2 + 6^2)/12 = 0.97 um.
    fit = clearance_from_fit(2e-3, "IT7", "IT6", 2e-6)
    assert fit.std == pytest.approx(math.sqrt(10**2 + 6**2) / 12 * 1e-6, rel=1e-12)


def test_length_sigma_is_a_sixth_of_the_band():
    assert length_sigma(0.144e-3) == pytest.approx(0.024e-3, rel=1e-12)  # Eq. 41
    with pytest.raises(ValueError):
        length_sigma(0.0)


def test_bad_grade_and_size_are_named():
    with pytest.raises(ValueError, match="grade"):
        it_tolerance("IT42", 2e-3)
    with pytest.raises(ValueError, match="nominal size"):
        it_tolerance("IT7", 0.5)


def test_clearance_rules():
    with pytest.raises(ValueError, match="needs its nominal_diameter and mean"):
        _ = ClearanceSpec(target="x").std  # alone: no joint to take them from
    spec = ClearanceSpec(target="x", mean_um=2.0, nominal_diameter_mm=2.0)  # the reference paper's pin
    assert spec.infeasible_probability() == pytest.approx(0.02529, abs=1e-4)  # Phi((0.1-2)/0.97183) from tables
    truncated = spec.frozen()
    assert truncated.ppf(0.0) == pytest.approx(spec.minimum, rel=1e-9)
    printed = ClearanceSpec(target="x", source="table5", mean_um=2.0)
    assert printed.std == 1e-9


def test_a_variable_without_scatter_or_a_uniform_given_bounds_is_told_what_to_write():
    """std = 0 was refused without saying to leave the variable out; a uniform given lower and upper without saying
    how a uniform is given (mean and std: (a + b) / 2 and (b - a) / sqrt(12))."""
    with pytest.raises(ValueError, match=r"must be > 0; leave out a setting that does not scatter"):
        RandomVariableSpec(name="a", target="x", mean=1.0, std=0.0)
    with pytest.raises(ValueError, match=r"mean \(a \+ b\) / 2 and std \(b - a\) / sqrt\(12\)"):
        RandomVariableSpec(name="a", target="x", mean=1.0, std=0.1, distribution="uniform", lower=0.8, upper=1.2)
    with pytest.raises(ValueError) as info:
        RandomVariableSpec(name="a", target="x", mean=1.0, std=0.1, distribution="gumbel", lower=0.8)
    assert "sqrt(12)" not in str(info.value)


def test_variable_validation():
    with pytest.raises(ValueError, match="std"):
        RandomVariableSpec(name="a", target="x", mean=1.0, std=0.0)
    with pytest.raises(ValueError):
        RandomVariableSpec(name="a", target="x", mean=float("nan"), std=1.0)
    with pytest.raises(ValueError, match="duplicate"):
        UncertaintySettings(variables=[RandomVariableSpec(name="a", target="x", mean=1, std=1)] * 2)
    ln = RandomVariableSpec(name="k", target="x", distribution="lognormal", mean=2.0, std=0.5).frozen()
    assert ln.mean() == pytest.approx(2.0, rel=1e-12) and ln.std() == pytest.approx(0.5, rel=1e-12)


def test_a_clearance_takes_its_nominal_diameter_and_mean_from_its_joint():
    """Left out, the nominal diameter and the mean were the reference paper's 2 mm pin and 2 um: a 12 mm H7/g6 pin
    took the tolerances of 2 mm (std 0.97 um instead of 1.76 um), a clearance given by its grades the paper's mean."""
    import tomllib
    from importlib import resources

    from jointwear.config import config_from_dict
    from jointwear.uncertainty.tolerances import clearance_from_fit, iso_fit

    data = tomllib.loads((resources.files("jointwear.presets") / "flores_slider_crank.toml").read_text())
    table = data["uncertainty"]["clearance"]  # bore 10 mm, pin 9.5 mm: a drawn clearance of 0.5 mm
    for key in ("mean_mm", "nominal_diameter_mm"):
        del table[key]
    spec = config_from_dict(data).uncertainty.clearance
    assert spec.nominal_diameter == pytest.approx(19e-3, rel=1e-12) and spec.mean == pytest.approx(0.5e-3, rel=1e-12)
    assert spec.std == clearance_from_fit(19e-3, table["hole_grade"], table["shaft_grade"], 0.5e-3).std
    table.update(fit="H7/g6")
    del table["hole_grade"], table["shaft_grade"]
    spec = config_from_dict(data).uncertainty.clearance
    assert spec.mean == iso_fit("H7/g6", 19e-3).mean_clearance  # the fit's at the pin's own diameter
    table.update(nominal_diameter_mm=2.0)  # given: kept
    assert config_from_dict(data).uncertainty.clearance.mean == iso_fit("H7/g6", 2e-3).mean_clearance
