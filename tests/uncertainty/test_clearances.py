"""Several random clearances, one ISO 286 fit per clearance joint ([[uncertainty.clearance]])."""

import math

import numpy as np
import pytest
from scipy import stats

from jointwear.config import config_from_dict, load_config, updated
from jointwear.design import build_controls, enumerate_candidates
from jointwear.design.checks import design_problems
from jointwear.design.settings import DesignSettings
from jointwear.schema import ConfigError
from jointwear.study.checks import clearance_warnings
from jointwear.study.model_call import apply_sample

SIX_BAR = "watt_six_bar_two_clearances"


def _two_fits(rule_e: str = "truncate", mean_e: float = 20e-6) -> list[dict]:
    return [{"name": "c_A", "target": "clearance_joints.A.clearance", "mean": 20e-6, "nominal_diameter": 4e-3,
             "hole_grade": "IT7", "shaft_grade": "IT6", "minimum": 1e-6},
            {"name": "c_E", "target": "clearance_joints.E.clearance", "mean": mean_e, "nominal_diameter": 4e-3,
             "hole_grade": "IT8", "shaft_grade": "IT7", "minimum": 1e-6, "infeasible_rule": rule_e}]


def _config(**kw):
    data = load_config(SIX_BAR).model_dump()
    data["uncertainty"]["clearance"] = _two_fits(**kw)
    return config_from_dict(data)


def test_each_fit_is_its_own_truncated_variable():
    unc = _config().uncertainty
    names = unc.names()
    # the clearances come second, as the paper's Table 5 places its one clearance
    assert names[:3] == ["l_OA", "c_A", "c_E"]
    specs = {s.name: s for s in unc.all_specs()}
    # Eq. (40), ISO 286-1 at 3-6 mm: IT8 18, IT7 12, IT6 8 um; sigma_c = sqrt(T_D^2 + T_d^2) / 12
    assert specs["c_A"].std == pytest.approx(math.hypot(12e-6, 8e-6) / 12, rel=1e-12)
    assert specs["c_E"].std == pytest.approx(math.hypot(18e-6, 12e-6) / 12, rel=1e-12)
    assert specs["c_E"].label == "radial clearance c_E"
    m = dict(zip(names, unc.marginals(feasible=True)))
    for name in ("c_A", "c_E"):
        assert m[name].cdf(1e-6) == 0.0 and m[name].support()[0] == pytest.approx(1e-6)
        # far above the minimum the truncation leaves the normal: its mean to 1e-12
        assert m[name].mean() == pytest.approx(20e-6, rel=1e-12)


def test_a_sample_sets_every_clearance_joint():
    cfg = _config()
    names = cfg.uncertainty.names()
    x = np.array([s.mean for s in cfg.uncertainty.all_specs()])
    x[names.index("c_A")], x[names.index("c_E")] = 17e-6, 31e-6
    sampled = apply_sample(cfg, [s.target for s in cfg.uncertainty.all_specs()], x)
    joints = {j.name: j for j in sampled.clearance_joints}
    assert joints["A"].bearing_radius - joints["A"].journal_radius == pytest.approx(17e-6, rel=1e-9)
    assert joints["E"].bearing_radius - joints["E"].journal_radius == pytest.approx(31e-6, rel=1e-9)


def test_fail_mass_of_several_clearances_against_direct_sampling():
    # two 'fail' clearances close to their minimum: P(some clearance <= its minimum), independent normals
    cfg = _config(rule_e="fail", mean_e=4e-6)
    unc = updated(cfg, {"uncertainty.clearance.c_A.mean": 3e-6, "uncertainty.clearance.c_A.infeasible_rule": "fail"}
                  ).uncertainty
    p = unc.infeasible_probability()
    rng = np.random.default_rng(7)
    n = 2_000_000
    below = np.zeros(n, dtype=bool)
    for c in unc.clearances():
        below |= rng.normal(c.mean, c.std, n) <= c.minimum
    # binomial standard error of the sampled share; 5 of them
    assert abs(below.mean() - p) < 5 * math.sqrt(p * (1 - p) / n)
    assert 0.02 < p < 0.98  # the check has something to see
    # only 'fail' clearances count
    assert _config().uncertainty.infeasible_probability() == 0.0
    one = _config(rule_e="fail", mean_e=4e-6).uncertainty
    assert one.infeasible_probability() == pytest.approx(one.clearance_named("c_E").infeasible_probability(),
                                                         rel=1e-15)


@pytest.mark.parametrize("change,words", [
    (lambda f: f[1].update(name="c_A"), ["each clearance needs its own name", "'c_E' for clearance_joints.E"]),
    (lambda f: f[1].update(target="clearance_joints.A.clearance"), ["'c_A' and 'c_E' both set"]),
    (lambda f: f[1].update(target="clearance_joints.Q.clearance"), ["uncertainty.clearance[c_E].target"]),
])
def test_a_wrong_list_names_the_field(change, words):
    data = load_config(SIX_BAR).model_dump()
    fits = _two_fits()
    change(fits)
    data["uncertainty"]["clearance"] = fits
    with pytest.raises(ConfigError) as err:
        config_from_dict(data)
    for w in words:
        assert w in str(err.value)


def test_two_failing_clearances_cannot_be_correlated():
    data = _config(rule_e="fail").model_dump()
    data["uncertainty"]["clearance"][0]["infeasible_rule"] = "fail"
    data["uncertainty"]["correlation"] = {"pairs": [["c_A", "c_E", 0.5]]}
    with pytest.raises(ConfigError, match="'c_A' and 'c_E' both count an assembly"):
        config_from_dict(data)
    data["uncertainty"]["clearance"][0]["infeasible_rule"] = "truncate"
    assert config_from_dict(data).uncertainty.copula() is not None


def test_truncation_warning_names_the_clearance():
    cfg = updated(_config(), {"uncertainty.clearance.c_E.mean": 1.5e-6})
    (warning,) = clearance_warnings(cfg)
    assert warning.startswith("uncertainty.clearance[c_E]: ")


def _design(fit: dict) -> DesignSettings:
    return DesignSettings.model_validate({"targets": [{"reliability": 0.9, "life_factor": 1.2}], "fit": fit})


def test_the_design_fit_sets_the_clearance_it_names():
    options = [{"name": "loose", "hole_grade": "IT9", "shaft_grade": "IT8", "cost": 0.0},
               {"name": "tight", "hole_grade": "IT6", "shaft_grade": "IT5", "cost": 1.0, "mean": 2e-6}]
    cfg = updated(_config(rule_e="fail"), {"design": _design({"options": options})})
    assert design_problems(cfg) == ["design.fit.variable: the study has several random clearances (c_A, c_E); "
                                    "name the one this fit sets"]
    cfg = updated(cfg, {"design": _design({"variable": "c_B", "options": options})})
    assert "design.fit.variable: 'c_B' is not a random clearance" in design_problems(cfg)[0]
    cfg = updated(cfg, {"design": _design({"variable": "c_A", "options": options})})
    assert design_problems(cfg) == []
    loose, tight = build_controls(cfg)[0].options
    unc = cfg.uncertainty
    # ISO 286-1 at 3-6 mm: IT9 30, IT8 18, IT6 8, IT5 5 um
    assert loose.described["c_A"]["std"] == pytest.approx(math.hypot(30e-6, 18e-6) / 12, rel=1e-12)
    assert set(tight.marginals) == {"c_A"}
    # c_A keeps its 'truncate' rule; E's 'fail' mass counts whatever A's fit
    p_e = cfg.uncertainty.clearance_named("c_E").infeasible_probability()
    assert unc.infeasible_probability(replace={"c_A": loose.clearance}) == pytest.approx(p_e, rel=1e-12)
    # with c_A failing too, each option combines both: 1 - (1 - p_A)(1 - p_E)
    cfg = updated(cfg, {"uncertainty.clearance.c_A.infeasible_rule": "fail"})
    controls = build_controls(cfg)
    tight = next(c for c in enumerate_candidates(controls) if c.choices(controls)["fit"] == "tight")
    c = stats.norm(2e-6, math.hypot(8e-6, 5e-6) / 12)
    assert tight.infeasible_probability(controls, cfg.uncertainty) == pytest.approx(
        1 - (1 - c.cdf(1e-6)) * (1 - p_e), rel=1e-12)


def test_the_spec_of_a_clearance_says_how_it_is_sampled():
    # 'truncate': the spec is the truncated normal the study samples; 'fail': the whole normal
    unc = _config(rule_e="fail").uncertainty
    specs = {s.name: s for s in unc.all_specs()}
    assert (specs["c_A"].distribution, specs["c_A"].lower) == ("truncated_normal", 1e-6)
    x = np.linspace(0.5e-6, 30e-6, 7)
    np.testing.assert_allclose(specs["c_A"].frozen().cdf(x), unc.clearance_named("c_A").frozen().cdf(x),
                               rtol=1e-12, atol=1e-300)
    assert (specs["c_E"].distribution, specs["c_E"].lower) == ("normal", None)


def test_one_design_fit_per_clearance_combines_their_failed_assemblies():
    fit_a = {"variable": "c_A", "options": [
        {"name": "A loose", "hole_grade": "IT8", "shaft_grade": "IT7", "cost": 0.0},
        {"name": "A tight", "hole_grade": "IT6", "shaft_grade": "IT5", "cost": 1.0, "mean": 3e-6}]}
    fit_e = {"variable": "c_E", "options": [
        {"name": "E loose", "hole_grade": "IT8", "shaft_grade": "IT7", "cost": 0.0, "mean": 3e-6},
        {"name": "E tight", "hole_grade": "IT6", "shaft_grade": "IT5", "cost": 1.0}]}
    cfg = updated(_config(rule_e="fail"), {"uncertainty.clearance.c_A.infeasible_rule": "fail",
                                           "design": _design([fit_a, fit_e])})
    assert design_problems(cfg) == []
    controls = build_controls(cfg)
    assert [c.name for c in controls] == ["fit c_A", "fit c_E"]
    # ISO 286-1 at 3-6 mm: IT8 18, IT7 12, IT6 8, IT5 5 um; each clearance N(mean, sigma_c) below 1 um
    def p(mean, t_hole, t_shaft):
        return stats.norm(mean, math.hypot(t_hole, t_shaft) / 12).cdf(1e-6)

    expected = {("A loose", "E loose"): (p(20e-6, 18e-6, 12e-6), p(3e-6, 18e-6, 12e-6)),
                ("A tight", "E loose"): (p(3e-6, 8e-6, 5e-6), p(3e-6, 18e-6, 12e-6)),
                ("A loose", "E tight"): (p(20e-6, 18e-6, 12e-6), p(20e-6, 8e-6, 5e-6)),
                ("A tight", "E tight"): (p(3e-6, 8e-6, 5e-6), p(20e-6, 8e-6, 5e-6))}
    for cand in enumerate_candidates(controls):
        pa, pe = expected[tuple(cand.choices(controls).values())]
        assert cand.infeasible_probability(controls, cfg.uncertainty) == pytest.approx(1 - (1 - pa) * (1 - pe),
                                                                                      rel=1e-12)
    # two fits of one clearance
    twice = updated(cfg, {"design": _design([fit_a, {**fit_e, "variable": "c_A"}])})
    assert design_problems(twice) == ["design.fit[1]: variable 'c_A' is already set by design.fit[0]"]


def test_a_fit_given_over_a_config_with_grades_and_a_mean_replaces_them(tmp_path):
    """A sweep over fits could not start from a config that gives the grades and the mean: updated() and a file that
    extends it kept them, and the fit was refused as contradicting them. H7/e7 at the 4 mm pin: hole 0/+12 um,
    shaft -20/-32 um (ISO 286-2, 3-6 mm), a radial clearance of (20 + 44) / 4 = 16 um."""
    from pathlib import Path

    example = Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml"
    base = load_config(example)
    assert base.uncertainty.clearance.fit is None and base.uncertainty.clearance.mean == pytest.approx(20e-6)
    fitted = updated(base, {"uncertainty.clearance.fit": "H7/e7"})
    clearance = fitted.uncertainty.clearance
    assert (clearance.fit, clearance.hole_grade, clearance.shaft_grade) == ("H7/e7", "IT7", "IT7")
    assert clearance.mean == pytest.approx(16e-6)
    # a mean given with the fit is still checked against it
    with pytest.raises(ConfigError, match="contradicts fit 'H7/e7'"):
        updated(base, {"uncertainty.clearance.fit": "H7/e7", "uncertainty.clearance.mean_um": 5.0})
    # and a file that extends the example takes the fit the same way
    path = tmp_path / "fit.toml"
    path.write_text(f'extends = "{example.as_posix()}"\n\n[uncertainty.clearance]\nfit = "H7/e7"\n', encoding="utf-8")
    assert load_config(path).uncertainty.clearance == clearance
