"""FORM, SORM, subset simulation and importance sampling cross-checked against OpenTURNS' own implementations
(``ot.FORM``, ``ot.SORM``, ``ot.SubsetSampling``, ``ot.ProbabilitySimulationAlgorithm`` with
``ot.ImportanceSamplingExperiment``) on the reference problems, the same joint law built natively in OpenTURNS."""

import math

import numpy as np
import openturns as ot
import pytest
from scipy import stats

from jointwear.reliability import form, importance_sampling, problems, sorm, subset_simulation
from jointwear.uncertainty.copulas import normal_copula


def _ot_marginal(m):
    if m.dist.name == "norm":
        return ot.Normal(float(m.mean()), float(m.std()))
    if m.dist.name == "lognorm":  # scipy lognorm(s, scale=exp(mu)) = OpenTURNS LogNormal(mu, s)
        s = m.args[0] if m.args else m.kwds["s"]
        return ot.LogNormal(math.log(m.kwds.get("scale", 1.0)), float(s))
    raise NotImplementedError(m.dist.name)


def _ot_event(p, copula=None):
    d = len(p.marginals)
    f = ot.PythonFunction(d, 1, func_sample=lambda X: np.asarray(p.g(np.asarray(X))).reshape(-1, 1))
    ms = [_ot_marginal(m) for m in p.marginals]
    dist = ot.JointDistribution(ms) if copula is None else ot.JointDistribution(ms, copula)
    event = ot.ThresholdEvent(ot.CompositeRandomVector(f, ot.RandomVector(dist)), ot.Less(), 0.0)
    return event, dist


def _solver():
    s = ot.AbdoRackwitz()
    s.setMaximumIterationNumber(200)
    for setter in ("setMaximumAbsoluteError", "setMaximumRelativeError", "setMaximumResidualError",
                   "setMaximumConstraintError"):
        getattr(s, setter)(1e-10)
    return s


OSC_COPULA = np.eye(6)
OSC_COPULA[4, 5] = OSC_COPULA[5, 4] = 0.4  # force amplitude and duration correlated (a made-up dependence)
CASES = {
    "oscillator": (problems.oscillator, None),
    "parabolic": (lambda: problems.parabolic(3.0, 0.1), None),
    "lognormal_rs": (problems.lognormal_rs, None),
    "oscillator_correlated": (problems.oscillator, OSC_COPULA),
}


@pytest.mark.parametrize("case", list(CASES))
def test_form_and_sorm_match_openturns(case):
    make, corr = CASES[case]
    p = make()
    cop = None if corr is None else normal_copula(corr)
    event, dist = _ot_event(p, cop)
    algo = ot.FORM(_solver(), event, dist.getMean())
    algo.run()
    ref = algo.getResult()
    mine = form(p.g, p.marginals, copula=cop)
    # both searches converge to the same design point: ours to a step of 1e-6 (tol) with forward differences
    # of 1e-5 sigma, OpenTURNS to 1e-10; the betas differ by far less than 1e-5 relative
    assert mine.beta == pytest.approx(ref.getHasoferReliabilityIndex(), rel=1e-5)
    sd = np.array([m.std() for m in p.marginals])  # the design points agree to 1e-4 sigma (same tolerances)
    np.testing.assert_allclose(mine.design_point_x, np.asarray(ref.getPhysicalSpaceDesignPoint()), rtol=0,
                               atol=1e-4 * sd.max())
    algo = ot.SORM(_solver(), event, dist.getMean())
    algo.run()
    sref = algo.getResult()
    ms = sorm(p.g, p.marginals, copula=cop)
    # both take finite-difference Hessians at the design point (ours central, h = 1e-3 sigma: O(h^2) = 1e-6
    # relative on the curvatures), so Breitung's and Hohenbichler's Pf agree to 1e-4 relative
    assert ms.pf == pytest.approx(sref.getEventProbabilityBreitung(), rel=1e-4)
    assert ms.details["pf_hohenbichler"] == pytest.approx(sref.getEventProbabilityHohenbichler(), rel=1e-4)


def _agree(pf_a, cov_a, pf_b, cov_b):
    # two independent unbiased estimates of the same Pf: their difference has the standard error
    # sqrt(sd_a^2 + sd_b^2); 4 of them (a false alarm once in ~16,000 runs under normality)
    se = math.hypot(pf_a * cov_a, pf_b * cov_b)
    assert abs(pf_a - pf_b) <= 4 * se, (pf_a, cov_a, pf_b, cov_b)


@pytest.mark.parametrize("case", ["four_branch", "oscillator_correlated", "linear_beta4"])
def test_subset_simulation_matches_openturns(case):
    if case == "four_branch":
        p, cop = problems.four_branch(6), None
    elif case == "linear_beta4":
        p, cop = problems.linear(4.0, 3), None
    else:
        p, cop = problems.oscillator(), normal_copula(OSC_COPULA)
    mine = subset_simulation(p.g, p.marginals, copula=cop, n_per_level=4000, seed=0)
    event, _ = _ot_event(p, cop)
    ot.RandomGenerator.SetSeed(1)
    algo = ot.SubsetSampling(event)
    algo.setMaximumOuterSampling(4000)
    algo.setBlockSize(1)
    algo.run()
    ref = algo.getResult()
    _agree(mine.pf, mine.cov, ref.getProbabilityEstimate(), ref.getCoefficientOfVariation())
    if case != "oscillator_correlated":  # and both agree with the reference value
        _agree(mine.pf, mine.cov, p.pf_ref, 0.0)


@pytest.mark.parametrize("case", ["parabolic", "lognormal_rs", "oscillator_correlated"])
def test_importance_sampling_matches_openturns(case):
    if case == "parabolic":
        p, cop = problems.parabolic(4.0, 0.1), None
    elif case == "lognormal_rs":
        p, cop = problems.lognormal_rs(), None
    else:
        p, cop = problems.oscillator(), normal_copula(OSC_COPULA)
    mine = importance_sampling(p.g, p.marginals, copula=cop, n=20_000, seed=0)
    event, dist = _ot_event(p, cop)
    # OpenTURNS: importance sampling in the standard space, N(u*, I) around the same design point
    std_event = ot.StandardEvent(event)
    d = len(p.marginals)
    instrumental = ot.Normal(ot.Point(mine.design_point_u.tolist()), ot.Point(d, 1.0), ot.CorrelationMatrix(d))
    ot.RandomGenerator.SetSeed(2)
    algo = ot.ProbabilitySimulationAlgorithm(std_event, ot.ImportanceSamplingExperiment(instrumental))
    algo.setMaximumOuterSampling(20_000)
    algo.setBlockSize(1)
    algo.setMaximumCoefficientOfVariation(0.0)
    algo.run()
    ref = algo.getResult()
    _agree(mine.pf, mine.cov, ref.getProbabilityEstimate(), ref.getCoefficientOfVariation())
    if cop is None:
        _agree(mine.pf, mine.cov, p.pf_ref, 0.0)


def test_lognormal_mapping_used_above():
    m = stats.lognorm(0.2, scale=math.exp(1.5))
    o = _ot_marginal(m)
    assert o.getMean()[0] == pytest.approx(m.mean(), rel=1e-12)  # closed-form moments of both
    assert o.getStandardDeviation()[0] == pytest.approx(m.std(), rel=1e-12)
