"""A clearance fit written with its ISO 286 letters (fit = "H7/g6"): its limits, the clearance it sets in a config,
and the fits a design chooses between.

The expected limits are the ISO 286-2 limit deviations of each class, read off its tables (micrometres, exact):
every comparison is to 1e-12 m, i.e. to rounding."""

from __future__ import annotations

import math

import pytest

from jointwear.config import load_config, updated
from jointwear.design import build_controls
from jointwear.design.checks import design_problems
from jointwear.design.settings import DesignSettings, FitOption
from jointwear.schema import ConfigError
from jointwear.study.settings_record import origin, settings_records
from jointwear.uncertainty.tolerances import iso_fit
from jointwear.uncertainty.variables import ClearanceSpec

UM = 1e-6


@pytest.mark.parametrize("fit, size_mm, hole_um, shaft_um", [
    ("H7/g6", 20.0, (0, 21), (-20, -7)),     # 18-30 mm: H7 0/+21, g6 -7/-20
    ("H8/f7", 25.0, (0, 33), (-41, -20)),    # 18-30 mm: H8 0/+33, f7 -20/-41
    ("H9/d9", 25.0, (0, 52), (-117, -65)),   # 18-30 mm: H9 0/+52, d9 -65/-117
    ("H7/h6", 50.0, (0, 25), (-16, 0)),      # 30-50 mm (50 is its upper bound): H7 0/+25, h6 -16/0
    ("F8/h7", 10.0, (13, 35), (-15, 0)),     # 6-10 mm: F8 +13/+35, h7 -15/0
    ("E9/e8", 100.0, (72, 159), (-126, -72)),  # 80-120 mm: E9 +72/+159, e8 -72/-126
    ("H8/f7", 6.0, (0, 18), (-22, -10)),     # 3-6 mm (6 is its upper bound)
    ("H8/f7", 6.01, (0, 22), (-28, -13)),    # just over 6 mm: the 6-10 mm row
    # every other range bound belongs to the range it closes, also when 1e-3 x size rounds above it (18 mm)
    ("H7/h6", 3.0, (0, 10), (-6, 0)),
    ("H7/h6", 10.0, (0, 15), (-9, 0)),
    ("H7/h6", 18.0, (0, 18), (-11, 0)),
    ("H7/h6", 30.0, (0, 21), (-13, 0)),
    ("H7/h6", 80.0, (0, 30), (-19, 0)),
    ("H7/h6", 120.0, (0, 35), (-22, 0)),
])
def test_the_limits_of_a_fit_are_iso_286_2s(fit, size_mm, hole_um, shaft_um):
    f = iso_fit(fit, size_mm * 1e-3)
    assert (f.hole_lower, f.hole_upper) == pytest.approx((hole_um[0] * UM, hole_um[1] * UM), abs=1e-12)
    assert (f.shaft_lower, f.shaft_upper) == pytest.approx((shaft_um[0] * UM, shaft_um[1] * UM), abs=1e-12)
    # radial: half the diametral clearance between the limits, the mean at the middle of both zones
    c_min, c_max = f.clearance_limits
    assert c_min == pytest.approx(0.5 * (hole_um[0] - shaft_um[1]) * UM, abs=1e-12)
    assert c_max == pytest.approx(0.5 * (hole_um[1] - shaft_um[0]) * UM, abs=1e-12)
    assert f.mean_clearance == pytest.approx(0.5 * (c_min + c_max), abs=1e-12)


@pytest.mark.parametrize("fit, size_mm, message", [
    ("H7/k6", 10.0, "only clearance fits are modelled"),
    ("H7/p6", 10.0, "only clearance fits are modelled"),
    ("h7/g6", 10.0, "upper case"),
    ("H7", 10.0, "not written as ISO 286 letters"),
    ("H14/g6", 10.0, "unknown ISO 286 tolerance grade 'IT14'"),
    ("H7/g6", 150.0, "outside the tabulated range"),
    ("H11/c11", 10.0, "'c' gives a clearance fit whose deviations are not tabulated"),  # ISO 286: a-c, cd, ef, fg
    ("C11/h11", 10.0, "'C' gives a clearance fit whose deviations are not tabulated"),
    ("H01/h6", 10.0, "grade IT01 is not tabulated"),  # IT01 is a grade of its own, not IT1
])
def test_a_fit_outside_the_model_is_refused_saying_why(fit, size_mm, message):
    with pytest.raises(ValueError, match=message):
        iso_fit(fit, size_mm * 1e-3)


def test_a_clearance_given_by_its_fit_takes_the_grades_the_mean_and_the_spread():
    c = ClearanceSpec(target="x", fit="H8 / f7", nominal_diameter_mm=6.0)
    # H8/f7 at 6 mm: 10-40 um diametral, so 12.5 um radial at the middle; IT8 = 18, IT7 = 12 um: Eq. (40)
    assert (c.fit, c.hole_grade, c.shaft_grade) == ("H8/f7", "IT8", "IT7")
    assert c.mean == pytest.approx(12.5 * UM, abs=1e-12)
    assert c.std == pytest.approx(math.hypot(18, 12) / 12 * UM, rel=1e-12)
    # the written config carries the fit, not what it sets: read back, and at another size, it is derived again
    data = c.model_dump()
    assert data["fit"] == "H8/f7" and not {"mean", "hole_grade", "shaft_grade"} & set(data)
    assert ClearanceSpec.model_validate(data) == c
    wider = ClearanceSpec.model_validate({**data, "nominal_diameter": 25e-3})
    assert wider.mean == pytest.approx(23.5 * UM, abs=1e-12)  # H8/f7 at 25 mm: 20-74 um
    # the same values given beside the fit are accepted; others are refused, naming both
    assert ClearanceSpec(target="x", fit="H8/f7", nominal_diameter_mm=6.0, mean_um=12.5, hole_grade="it8") == c
    for given, message in [({"mean_um": 20.0}, "mean = 20 um contradicts fit 'H8/f7', which gives 12.5 um"),
                           ({"shaft_grade": "IT6"}, "shaft_grade = 'IT6' contradicts fit 'H8/f7', which gives 'IT7'"),
                           ({"source": "table5"}, "not from Table 5")]:
        with pytest.raises(ValueError, match=message):
            ClearanceSpec(target="x", fit="H8/f7", nominal_diameter_mm=6.0, **given)


def test_a_study_config_takes_a_fit_and_a_change_of_size_moves_its_mean():
    base = load_config("jin2025_flapping_wing")
    # a fit given in a change replaces the preset's own mean and grades (it sets them); one given beside it is checked
    with pytest.raises(ConfigError, match=r"uncertainty\.clearance: mean = 2 um contradicts fit 'H7/g6'"):
        updated(base, {"uncertainty.clearance.fit": "H7/g6", "uncertainty.clearance.mean_um": 2.0})
    cfg = updated(base, {"uncertainty.clearance.fit": "H7/g6"})
    data = base.uncertainty.clearance.model_dump()
    data.pop("mean")
    assert updated(base, {"uncertainty.clearance": {**data, "fit": "H7/g6"}}) == cfg
    assert cfg.uncertainty.clearance.mean == pytest.approx(5 * UM, abs=1e-12)  # H7/g6 at 2 mm: 2-18 um diametral
    assert "radial clearance (H7/g6)" in [s.label for s in cfg.uncertainty.all_specs()]  # as the report names it
    # `jointwear check` and the report's settings table say where each value comes from
    records = {r["name"]: r for r in settings_records(cfg)}
    assert [origin(records[f"uncertainty.clearance.{k}"]) for k in ("fit", "mean", "hole_grade", "minimum")] == [
        "the config", "set by fit 'H7/g6'", "set by fit 'H7/g6'", "the config"]
    moved = updated(cfg, {"uncertainty.clearance.nominal_diameter_mm": 4.0})
    assert moved.uncertainty.clearance.mean == pytest.approx(7 * UM, abs=1e-12)  # 3-6 mm: 4-24 um
    freed = updated(cfg, {"uncertainty.clearance.fit": None, "uncertainty.clearance.mean_um": 3.0,
                          "uncertainty.clearance.hole_grade": "IT8"})
    assert (freed.uncertainty.clearance.fit, freed.uncertainty.clearance.mean) == (None, 3 * UM)


def test_a_design_chooses_between_fits_given_by_their_letters():
    cfg = load_config("jin2025_flapping_wing")  # one random clearance at 2 mm, IT7/IT6 and a mean of 2 um
    design = DesignSettings.model_validate({
        "targets": [{"reliability": 0.9, "life_factor": 1.2}],
        "fit": {"options": [{"fit": "H7/h6", "cost": 1.0},
                            {"fit": "H9/d9", "cost": 0.0},
                            {"name": "own", "hole_grade": "IT8", "shaft_grade": "IT7", "cost": 0.5}]}})
    assert [o.name for o in design.fit.options] == ["H7/h6", "H9/d9", "own"]
    cfg = updated(cfg, {"design": design})
    assert design_problems(cfg) == []
    (control,) = build_controls(cfg)
    h6, d9, own = (o.clearance for o in control.options)
    assert h6.mean == pytest.approx(4 * UM, abs=1e-12)  # at 2 mm: H7 0/+10, h6 -6/0
    assert d9.mean == pytest.approx(22.5 * UM, abs=1e-12)  # H9 0/+25, d9 -20/-45
    assert d9.std == pytest.approx(math.hypot(25, 25) / 12 * UM, rel=1e-12)
    assert (own.fit, own.hole_grade, own.mean) == (None, "IT8", cfg.uncertainty.clearance.mean)  # the study's mean
    # a fit's letters with other grades, and a fit the table has no row for at the clearance's size, are refused
    # (grades that agree with the letters are accepted, as [uncertainty.clearance] accepts them)
    with pytest.raises(ValueError, match="give the fit, or the grades"):
        FitOption(fit="H7/g6", hole_grade="IT8", cost=0.0)
    assert FitOption(fit="H7/g6", hole_grade="IT7", cost=0.0).hole_grade == "IT7"
    big = updated(cfg, {"uncertainty.clearance.nominal_diameter_mm": 150.0,  # Table 5's spread needs no grade
                        "uncertainty.clearance.source": "table5"})
    assert any("design.fit.options[H7/h6].fit: fit 'H7/h6': nominal size 150 mm outside the tabulated range" in p
               for p in design_problems(big))
