"""Random-variable settings: every TOML distribution, its validation, and the correlation section."""

import math

import numpy as np
import pytest
from pydantic import ValidationError

from jointwear.uncertainty.variables import RandomVariableSpec, UncertaintySettings, weibull_shape

BOUNDS = {"truncated_normal": {"lower": 1.5}, "beta": {"lower": 0.5, "upper": 4.0}}


@pytest.mark.parametrize("dist", ["normal", "lognormal", "uniform", "weibull", "gumbel", "gamma", "beta"])
def test_mean_and_std_are_those_given(dist):
    spec = RandomVariableSpec(name="a", target="x", distribution=dist, mean=2.0, std=0.3, **BOUNDS.get(dist, {}))
    f = spec.frozen()
    # closed-form moments of each scipy family; the Weibull shape is solved to 1e-14 (brentq xtol/rtol)
    assert f.mean() == pytest.approx(2.0, rel=1e-10)
    assert f.std() == pytest.approx(0.3, rel=1e-10)


def test_bounded_distributions_respect_their_bounds():
    tn = RandomVariableSpec(name="a", target="x", distribution="truncated_normal", mean=2.0, std=0.3,
                            lower=1.8, upper=2.5).frozen()
    assert tn.support() == pytest.approx((1.8, 2.5), abs=1e-15)
    # the parent normal N(2, 0.3) truncated: its median is the normal's quantile of the middle of the mass
    from scipy import stats

    lo, hi = stats.norm.cdf([(1.8 - 2) / 0.3, (2.5 - 2) / 0.3])
    assert tn.median() == pytest.approx(2 + 0.3 * stats.norm.ppf(0.5 * (lo + hi)), rel=1e-12)
    b = RandomVariableSpec(name="b", target="x", distribution="beta", mean=1.0, std=0.5, lower=0.0, upper=4.0).frozen()
    assert b.support() == pytest.approx((0.0, 4.0))


def test_weibull_shape_known_value():
    # k = 1 is the exponential distribution, whose COV is exactly 1; k = 2 (Rayleigh): sqrt(4/pi - 1)
    assert weibull_shape(1.0) == pytest.approx(1.0, rel=1e-10)
    assert weibull_shape(math.sqrt(4 / math.pi - 1)) == pytest.approx(2.0, rel=1e-10)


@pytest.mark.parametrize("kwargs, field", [
    ({"distribution": "beta", "lower": 0.0}, "upper"),
    ({"distribution": "beta", "lower": 0.0, "upper": 1.0}, "mean"),
    ({"distribution": "beta", "lower": 1.0, "upper": 3.0, "std": 2.0}, "std"),
    ({"distribution": "truncated_normal"}, "lower/upper"),
    ({"distribution": "truncated_normal", "lower": 3.0, "upper": 2.5}, "lower"),
    ({"distribution": "normal", "upper": 3.0}, "upper"),
    ({"distribution": "gamma", "mean": -1.0}, "positive mean"),
    ({"distribution": "weibull", "mean": 1.0, "std": 1e-6}, "std / mean"),
    ({"distribution": "normal", "std": 0.0}, "std"),
])
def test_errors_name_the_field(kwargs, field):
    base = {"name": "a", "target": "x", "mean": 2.0, "std": 0.3}
    with pytest.raises(ValidationError, match=field):
        RandomVariableSpec(**{**base, **kwargs})


def _settings(**corr):
    return UncertaintySettings(
        variables=[{"name": n, "target": f"x.{n}", "mean": 1.0, "std": 0.1} for n in ("a", "b", "c2")],
        correlation=corr or None)


def test_correlation_matrix_and_pairs_agree():
    m = _settings(variables=["c2", "a"], matrix=[[1.0, 0.3], [0.3, 1.0]])
    p = _settings(pairs=[["a", "c2", 0.3]])
    expected = np.array([[1.0, 0.0, 0.3], [0.0, 1.0, 0.0], [0.3, 0.0, 1.0]])
    np.testing.assert_array_equal(m.correlation_matrix(), expected)
    np.testing.assert_array_equal(p.correlation_matrix(), expected)
    # names beyond the settings' own (an input the study adds) are independent of the rest
    r = p.correlation_matrix(["a", "b", "c2", "delta_0"])
    assert r.shape == (4, 4) and r[3, 3] == 1.0 and not r[3, :3].any()
    cop = p.copula(["a", "b", "c2", "delta_0"])
    assert cop.getDimension() == 4
    assert np.asarray(cop.getShapeMatrix())[0, 2] == pytest.approx(0.3)
    assert _settings().copula() is None  # no correlation: independent inputs


def test_spearman_measure_is_converted_by_openturns():
    s = _settings(pairs=[["a", "b", 0.5]], measure="spearman")
    # normal copula parameter from a rank correlation: 2 sin(pi rho_s / 6) (exact relation for the normal copula)
    assert np.asarray(s.copula().getShapeMatrix())[0, 1] == pytest.approx(2 * math.sin(math.pi * 0.5 / 6), rel=1e-12)


@pytest.mark.parametrize("corr, message", [
    ({"variables": ["a", "zz"], "matrix": [[1, 0.2], [0.2, 1]]}, "unknown variable"),
    ({"variables": ["a", "b"], "matrix": [[1, 0.2], [0.3, 1]]}, "symmetric"),
    ({"variables": ["a", "b"], "matrix": [[1, 0.2, 0], [0.2, 1, 0]]}, "2 x 2"),
    ({"variables": ["a", "b"], "matrix": [[2, 0.2], [0.2, 1]]}, "diagonal"),
    ({"pairs": [["a", "b", 1.2]]}, r"pairs\[0\]"),
    ({"pairs": [["a", "a", 0.2]]}, "itself"),
    ({"pairs": [["a", "b", 0.2], ["b", "a", 0.1]]}, "twice"),
    ({"pairs": [["a", "b", 0.9], ["b", "c2", 0.9], ["a", "c2", -0.9]]}, "positive definite"),
    ({"pairs": [["a", "b", 0.2]], "variables": ["a"], "matrix": [[1]]}, "not both"),
])
def test_correlation_errors(corr, message):
    with pytest.raises(ValidationError, match=message):
        _settings(**corr)


def test_toml_config_with_new_distributions_and_correlation():
    import importlib.resources
    import tomllib

    from jointwear.config import config_from_dict

    data = tomllib.loads((importlib.resources.files("jointwear") / "presets" / "jin2025_flapping_wing.toml").read_text())
    var = next(v for v in data["uncertainty"]["variables"] if v["name"] == "l1")
    var.update(distribution="beta", lower_mm=5.99, upper_mm=6.01)  # unit suffixes work for the bounds too
    data["uncertainty"]["correlation"] = {"variables": ["l1", "l2"], "matrix": [[1, 0.5], [0.5, 1]]}
    cfg = config_from_dict(data)
    spec = next(s for s in cfg.uncertainty.all_specs() if s.name == "l1")
    assert spec.lower == pytest.approx(5.99e-3) and spec.upper == pytest.approx(6.01e-3)
    names = cfg.uncertainty.names()
    r = np.asarray(cfg.uncertainty.copula().getShapeMatrix())
    assert r[names.index("l1"), names.index("l2")] == pytest.approx(0.5)
    assert r.shape == (len(names), len(names))


def test_std_scale_reads_a_tables_spreads_another_way():
    from jointwear.config import load_config
    from jointwear.schema import ConfigError

    base, alt = load_config(), load_config("jin2025_flapping_wing_two_sigma")
    for a, b in zip(base.uncertainty.all_specs(), alt.uncertainty.all_specs()):
        factor = 0.5 if a.group in ("bearing_material", "journal_material") else 1.0
        assert b.std == a.std * factor and b.mean == a.mean, a.name  # exact: a product by 0.5 or 1
    data = base.model_dump()
    data["uncertainty"]["std_scale"] = {"no_such_group": 0.5}
    from jointwear.config import config_from_dict

    with pytest.raises(ConfigError, match="std_scale.no_such_group"):
        config_from_dict(data)


def test_a_variation_gives_its_correlation_in_either_form_over_the_base():
    """The slider-crank preset correlates its pin and clearance by pairs; a variation's variables + matrix (in a file
    that extends it, or through updated) was refused as giving both forms."""
    from jointwear.config import load_config, updated

    matrix = [[1.0, 0.5], [0.5, 1.0]]
    extended = load_config({"extends": "flores_slider_crank",
                            "uncertainty": {"correlation": {"variables": ["l1", "l2"], "matrix": matrix}}})
    changed = updated("flores_slider_crank", {"uncertainty.correlation.variables": ["l1", "l2"],
                                              "uncertainty.correlation.matrix": matrix})
    for config in (extended, changed):
        corr = config.uncertainty.correlation
        assert corr.pairs is None and corr.variables == ["l1", "l2"] and corr.matrix == matrix
    # a setting beside the entries keeps them
    spearman = updated("flores_slider_crank", {"uncertainty.correlation.measure": "spearman"}).uncertainty.correlation
    assert spearman.pairs == [("Rj", "c", -0.537)] and spearman.measure == "spearman"


def test_a_spread_scaled_past_its_distribution_is_refused_naming_the_scale():
    """A beta of HB_b 120 +- 12 in [100, 150] scaled by 2.5 (std 30 > sqrt(20 x 30) = 24.5) built a marginal of NaN
    mean, and check blamed the units."""
    from jointwear.config import updated
    from jointwear.schema import ConfigError

    beta = {"distribution": "beta", "mean_HB": 120.0, "std_HB": 12.0, "lower_HB": 100.0, "upper_HB": 150.0}
    base = updated("jin2025_flapping_wing", {f"uncertainty.variables.HB_b.{k}": v for k, v in beta.items()})
    assert updated(base, {"uncertainty.std_scale": {"bearing_material": 2.0}})  # std 24 < 24.5: still a beta
    with pytest.raises(ConfigError, match=r"std_scale.bearing_material: scaled by 2.5, variable 'HB_b' is invalid"):
        updated(base, {"uncertainty.std_scale": {"bearing_material": 2.5}})


def test_a_nominal_diameter_outside_the_tables_is_named():
    from jointwear.config import updated
    from jointwear.schema import ConfigError

    for changes in ({"uncertainty.clearance.nominal_diameter_mm": 200.0},
                    {"uncertainty.clearance.nominal_diameter_mm": 200.0, "uncertainty.clearance.fit": "H7/g6"}):
        with pytest.raises(ConfigError, match=r"uncertainty\.clearance\.nominal_diameter: nominal size 200 mm outside"):
            updated("jin2025_flapping_wing", changes)
