"""Monte Carlo, FORM, SORM, subset simulation and importance sampling on exact problems."""

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import (
    form,
    importance_sampling,
    monte_carlo,
    problems,
    sorm,
    subset_simulation,
)


def _accept(pf, cov, ref):
    rel = abs(pf / ref - 1.0)
    # issue 4 acceptance: 3 % of the reference, or 2x the reported coefficient of variation
    assert rel <= max(0.03, 2.0 * cov), f"pf={pf:.5g} ref={ref:.5g} rel={rel:.3%} cov={cov:.3%}"


@pytest.mark.parametrize("beta", [3.0, 5.0])
def test_form_exact_on_linear(beta):
    p = problems.linear(beta, 4)
    r = form(p.g, p.marginals)
    assert r.converged
    # FORM is exact for a linear limit state in normal variables; 1e-6 = the HL-RF tolerance
    assert r.beta == pytest.approx(beta, rel=1e-6)
    assert r.pf == pytest.approx(p.pf_ref, rel=1e-5)
    np.testing.assert_allclose(r.alpha, np.full(4, 0.5), atol=1e-5)  # equal weights 1/sqrt(4)
    s = sorm(p.g, p.marginals, form_result=r)
    np.testing.assert_allclose(s.curvatures, 0.0, atol=1e-4)  # zero curvature, up to FD error h^2
    assert s.pf == pytest.approx(p.pf_ref, rel=1e-3)


def test_beta5_subset_simulation_and_importance_sampling():
    p = problems.linear(5.0, 2)  # exact pf = Phi(-5) = 2.87e-7
    r = subset_simulation(p.g, p.marginals, n_per_level=2000, seed=2)
    assert r.converged
    _accept(r.pf, r.cov, p.pf_ref)
    assert r.n_calls < 20_000  # vs ~1e9 for crude MCS at 5 % COV
    ri = importance_sampling(p.g, p.marginals, n=4000, seed=0)
    _accept(ri.pf, ri.cov, p.pf_ref)


def test_sorm_curvature_and_lognormal_form():
    # paraboloid g = beta - u2 + k/2 u1^2: curvature k; Breitung is the classical asymptotic answer
    beta, kap = 3.0, 0.2

    def g(x):
        return beta - x[:, 1] + 0.5 * kap * x[:, 0] ** 2

    marg = [stats.norm(), stats.norm()]
    s = sorm(g, marg)
    assert s.curvatures == pytest.approx([kap], abs=1e-3)  # central FD with h = 1e-3: O(h^2)
    assert s.pf == pytest.approx(stats.norm.sf(beta) / np.sqrt(1 + beta * kap), rel=1e-3)
    # lognormal R - S: FORM is exact because ln R - ln S is linear in u
    p = problems.lognormal_rs()
    f = form(p.g, p.marginals)
    assert f.pf == pytest.approx(p.pf_ref, rel=1e-4)  # HL-RF tolerance 1e-6 on beta, amplified by dlnPf/dbeta


def test_monte_carlo_lognormal():
    p = problems.lognormal_rs()
    r = monte_carlo(p.g, p.marginals, 200_000, seed=0)
    _accept(r.pf, r.cov, p.pf_ref)
    r2 = monte_carlo(p.g, p.marginals, 10_000, cov_target=0.05, seed=0)
    assert r2.cov < 0.05 and r2.n_calls > 10_000


def test_form_without_a_design_point_gives_no_pf():
    # g = 10 + u1^2 >= 10 everywhere: Pf = 0 and there is no design point; FORM gave Pf = 0.49 with an empty message
    g = lambda x: 10.0 + x[:, 0] ** 2  # noqa: E731
    r = form(g, [stats.norm(), stats.norm()], max_iter=20)
    assert not r.converged and np.isnan(r.pf) and np.isnan(r.beta)
    assert "never reached g = 0" in r.message
    with pytest.raises(ValueError, match="SORM needs FORM's design point"):
        sorm(g, [stats.norm(), stats.norm()], form_result=r)


def test_a_failure_indicator_is_refused():
    # a Kriging of 0/1 values overshoots below 0 and invents failures (it read Pf 2.2e-4 for an event of Pf 0)
    from jointwear.reliability import akmcs

    with pytest.raises(ValueError, match="booleans"):
        akmcs(lambda x: x.sum(axis=1) < 3, [stats.norm(), stats.norm()], seed=1)
    with pytest.raises(ValueError, match="booleans"):
        monte_carlo(lambda x: x.sum(axis=1) < 3, [stats.norm(), stats.norm()], n=1000)


def test_akmcs_says_when_it_found_no_failure_or_stopped_on_min_u_alone():
    from jointwear.reliability import akmcs

    never = akmcs(lambda x: 10.0 + x[:, 0] ** 2, [stats.norm(), stats.norm()], n_mc_max=100_000, seed=1)
    assert never.pf == 0 and not never.converged and "no failure among 100,000 candidates" in never.message
    # a series system whose ESC estimate rose again after the learning's min U stop (seed 4: 0.068 against 0.01)
    both = akmcs(lambda x: np.minimum(2.5 - x[:, 0], 2.5 - x[:, 1]), [stats.norm(), stats.norm()], seed=4)
    if both.converged and both.error_estimate > 0.01:
        assert "above error_tol=0.01" in both.message
    else:
        assert both.message == "converged"


def test_a_seed_or_cov_target_of_the_wrong_kind_is_refused_by_name():
    """akmcs(seed="a") ended in numpy's TypeError and monte_carlo(cov_target=0) in a ZeroDivisionError."""
    from jointwear.reliability import akmcs, monte_carlo

    def g(x):
        return 3.0 - x.sum(axis=1)

    marginals = [stats.norm(), stats.norm()]
    for bad in ("a", -1, 1.5, True, np.random.default_rng(1)):
        with pytest.raises(ValueError, match="^seed must be None or an integer >= 0"):
            akmcs(g, marginals, seed=bad)
    for bad in (0, -1, float("nan")):
        with pytest.raises(ValueError, match="^cov_target must be a finite number > 0"):
            monte_carlo(g, marginals, n=1000, cov_target=bad)
    assert monte_carlo(g, marginals, n=1000, seed=np.int64(3)).pf == monte_carlo(g, marginals, n=1000, seed=3).pf
