"""The mean shift of every distribution family the config builds (``RandomVariableSpec.distribution``, and the
clearance's truncated normal): the mean moves by exactly the factor; positive laws from 0 are scaled (COV kept, no
mass below zero), the others translated (standard deviation kept, bounds moving with them)."""

from __future__ import annotations

import math
import typing

import numpy as np
import pytest
from scipy import stats

from jointwear.sensitivity import shifted_marginal
from jointwear.uncertainty.variables import ClearanceSpec, DistributionName, RandomVariableSpec

FACTORS = (0.8, 1.2)

# a wear coefficient-like variable with 40 % scatter, and bounds where the family takes them
SPECS = {
    "normal": {},
    "lognormal": {},
    "uniform": {},
    "truncated_normal": {"lower": 1.2},
    "weibull": {},
    "gumbel": {},
    "gamma": {},
    "beta": {"lower": 0.5, "upper": 4.0, "std": 0.5},
}
POSITIVE = {"lognormal", "weibull", "gamma"}  # two-parameter laws on (0, inf), built with loc = 0


def frozen(distribution: str, **kwargs):
    settings = {"mean": 2.0, "std": 0.8} | SPECS[distribution] | kwargs
    return RandomVariableSpec(name="k", target="x.k", distribution=distribution, **settings).frozen()


def test_every_config_family_is_covered():
    assert set(SPECS) == set(typing.get_args(DistributionName))


@pytest.mark.parametrize("distribution", sorted(SPECS))
@pytest.mark.parametrize("factor", FACTORS)
def test_shift_multiplies_the_mean_exactly(distribution, factor):
    m = frozen(distribution)
    s = shifted_marginal(m, factor)
    assert s.dist.name == m.dist.name
    assert s.mean() == pytest.approx(factor * m.mean(), rel=1e-12, abs=0.0)


@pytest.mark.parametrize("distribution", sorted(POSITIVE))
@pytest.mark.parametrize("factor", FACTORS)
def test_positive_laws_are_scaled_and_stay_positive(distribution, factor):
    m = frozen(distribution)
    assert m.support()[0] == 0.0 and m.cdf(0.0) == 0.0
    s = shifted_marginal(m, factor)
    assert s.std() == pytest.approx(factor * m.std(), rel=1e-12, abs=0.0)  # COV kept
    assert s.std() / s.mean() == pytest.approx(m.std() / m.mean(), rel=1e-12, abs=0.0)
    assert s.support()[0] == 0.0
    assert s.cdf(0.0) == 0.0  # no mass below zero, exactly
    # the same law as factor x X: quantiles scale
    q = np.array([1e-6, 0.01, 0.5, 0.99])
    np.testing.assert_allclose(s.ppf(q), factor * m.ppf(q), rtol=1e-12)


@pytest.mark.parametrize("distribution", sorted(set(SPECS) - POSITIVE))
@pytest.mark.parametrize("factor", FACTORS)
def test_other_laws_are_translated_with_their_bounds(distribution, factor):
    m = frozen(distribution)
    s = shifted_marginal(m, factor)
    shift = (factor - 1.0) * m.mean()
    assert s.std() == pytest.approx(m.std(), rel=1e-12, abs=0.0)
    low, high = m.support()
    s_low, s_high = s.support()
    for a, b in ((low, s_low), (high, s_high)):
        assert (math.isinf(a) and b == a) or b == pytest.approx(a + shift, rel=1e-12, abs=1e-15)
    q = np.array([1e-6, 0.01, 0.5, 0.99])
    np.testing.assert_allclose(s.ppf(q), m.ppf(q) + shift, rtol=1e-12, atol=1e-15)


def test_truncated_normal_with_both_bounds_and_the_clearance_are_translated():
    both = frozen("truncated_normal", lower=1.2, upper=3.5)
    clearance = ClearanceSpec(target="clearance_joints.0", mean=10e-6, hole_grade="IT7", shaft_grade="IT6",
                              nominal_diameter=2e-3, minimum=8e-6).frozen()  # truncated at its minimum
    assert clearance.dist.name == "truncnorm"
    for m in (both, clearance):
        for factor in FACTORS:
            s = shifted_marginal(m, factor)
            assert s.mean() == pytest.approx(factor * m.mean(), rel=1e-12, abs=0.0)
            assert s.std() == pytest.approx(m.std(), rel=1e-12, abs=0.0)
            low, high = m.support()
            assert s.support()[0] == pytest.approx(low + (factor - 1.0) * m.mean(), rel=1e-12)
            assert math.isinf(high) or s.support()[1] == pytest.approx(high + (factor - 1.0) * m.mean(), rel=1e-12)


@pytest.mark.parametrize("factor", FACTORS)
def test_positive_law_with_an_offset_is_scaled_all_the_same(factor):
    # the config builds none; a law given through the API with loc != 0 is scaled: x -> factor x
    for m in (stats.gamma(6.25, loc=0.3, scale=0.3), stats.weibull_min(2.7, loc=0.5, scale=1.7),
              stats.lognorm(0.39, loc=0.2, scale=1.7)):
        s = shifted_marginal(m, factor)
        assert s.mean() == pytest.approx(factor * m.mean(), rel=1e-12, abs=0.0)
        assert s.std() / s.mean() == pytest.approx(m.std() / m.mean(), rel=1e-12, abs=0.0)
        assert s.support()[0] == pytest.approx(factor * m.support()[0], rel=1e-12)
        assert s.cdf(0.0) == 0.0
