"""AK-MCS on problems with known answers.

Acceptance rule (issue 4): Pf within 3 % of the reference or within 2x the reported COV.
"""

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import Evaluation, akmcs, akmcs_multi, problems


def _accept(pf, cov, ref):
    rel = abs(pf / ref - 1.0)
    # issue 4 acceptance: 3 % of the reference, or 2x the reported coefficient of variation
    assert rel <= max(0.03, 2.0 * cov), f"pf={pf:.5g} ref={ref:.5g} rel={rel:.3%} cov={cov:.3%}"


def test_four_branch_k6():
    p = problems.four_branch(6)
    # reference: exact 4.4573e-3 by quadrature; agrees with the 1e8-sample MCS (4.45e-3)
    assert p.pf_ref == pytest.approx(4.45e-3, rel=3e-3)  # 1e8 MCS has COV 1.5e-3: 2 sigma
    r = akmcs(p.g, p.marginals, n_mc=100_000, seed=3, stopping="u")
    assert r.converged, r.message
    assert r.history[-1].min_u >= 2.0  # the paper's stopping rule held at the end
    assert r.cov < 0.05  # the COV rule held at the end
    _accept(r.pf, r.cov, p.pf_ref)
    # Echard et al. (2011) needed 126 calls with 1e6 candidates; allow that budget
    assert r.n_calls <= 126
    assert r.design_x.shape == (r.n_calls, 2) and r.design_g.shape == (r.n_calls,)
    np.testing.assert_allclose(p.g(r.design_x), r.design_g)


def test_four_branch_k6_default_settings():
    p = problems.four_branch(6)
    r = akmcs(p.g, p.marginals, seed=5)  # default: ESC stop at an estimated 1 % error of Pf
    assert r.converged, r.message
    # the learning stopped on one of the two criteria of stopping="error"
    assert r.error_estimate <= 0.01 or r.details["min_u"] >= 2.0
    assert r.cov < 0.05
    _accept(r.pf, r.cov, p.pf_ref)
    # Echard et al. (2011), AK-MCS+U: 126 calls; the default stop spends far fewer (median 48 in
    # benchmarks/results/reliability.json), so the paper's count is a loose upper bound for one seed
    assert r.n_calls <= 126


def test_linear_beta3_ak_mcs_error_stopping_and_batch():
    p = problems.linear(3.0, 3)
    r = akmcs(p.g, p.marginals, seed=0, stopping="error", batch_size=3)
    assert r.converged, r.message
    assert r.cov < 0.05  # population grown to meet the COV target
    assert r.n_mc > 100_000
    _accept(r.pf, r.cov, p.pf_ref)
    # a linear limit state is learnt with very few points (initial design 12 + a few batches)
    assert r.n_calls <= 40


def test_lognormal_inputs():
    p = problems.lognormal_rs()
    r = akmcs(p.g, p.marginals, seed=1, stopping="error")
    assert r.converged, r.message
    _accept(r.pf, r.cov, p.pf_ref)
    # the design is kept in physical units (Pa), strictly positive
    assert np.all(r.design_x > 0)


def test_multi_levels_share_one_design():
    # g at three "cycle counts": the same model with a threshold that decreases with the level
    shifts = np.array([3.5, 3.0, 2.5])

    def g(x):
        s = (x[:, 0] + x[:, 1]) / np.sqrt(2.0)
        return shifts[None, :] - s[:, None]

    marg = [stats.norm(), stats.norm()]
    seen = []
    r = akmcs_multi(g, marg, seed=0, stopping="error", evaluation=Evaluation(progress=seen.append),
                    pf_floor=1e-3)
    assert r.converged, r.message
    assert r.pf.shape == (3,) and r.cov.shape == (3,)
    ref = stats.norm.sf(shifts)
    for j in range(3):
        if not r.below_floor[j]:
            _accept(r.pf[j], r.cov[j], ref[j])
            assert r.cov[j] < 0.05
    assert np.all(np.diff(r.pf) > 0)  # reliability decreases with the level
    assert r.column_converged.all()
    assert r.design_g.shape == (r.n_calls, 3)
    assert len(seen) == len(r.history) and seen[0].pf.shape == (3,)
    assert len(r.surrogates) == 3


def test_progress_callback_and_history():
    p = problems.linear(2.0, 2)
    recs = []
    r = akmcs(p.g, p.marginals, seed=0, n_mc=20_000, evaluation=Evaluation(progress=recs.append))
    assert recs == r.history
    assert [h.n_calls for h in r.history] == sorted(h.n_calls for h in r.history)
    assert all(np.isfinite(h.pf) for h in r.history)


def _archard_api_example():
    p = problems.archard_wear()
    return list(p.marginals), p.g


def test_the_stop_must_hold_on_successive_designs():
    """A Kriging of a dozen points can be sure of itself where it is wrong: on this 3-input limit state the ESC stop
    holds on the initial design or one batch later while Pf is 3.4 % off (seed 3). Held on three successive designs
    (the default), Pf on the same population is within the requested error_tol of the true g's: the tolerance is the
    one asked for (benchmarks/esc_calibration.py: 30 of 30 seeds within it, 10 of 30 with hold_iterations=1)."""
    marginals, g = _archard_api_example()
    from jointwear.reliability import IsoTransform

    def actual_error(r):
        true_pf = np.mean(g(IsoTransform(marginals).to_x(r.details["population_u"])) < 0)
        return abs(r.pf / true_pf - 1.0)

    once = akmcs(g, marginals, seed=3, hold_iterations=1, keep_population=True)
    held = akmcs(g, marginals, seed=3, keep_population=True)
    assert once.converged and held.converged
    assert actual_error(once) > 0.01  # the case the rule is for: a stop on the first hold misses error_tol
    assert actual_error(held) <= 0.01
    # the rule held on each of the last three designs (each a larger one), and not only there by accident
    designs = sorted({rec.n_calls for rec in held.history})
    assert held.n_calls >= once.n_calls + 2
    last = [max((rec for rec in held.history if rec.n_calls == n), key=lambda rec: rec.iteration) for n in designs[-3:]]
    assert all(rec.error <= 0.01 or rec.min_u >= 2.0 for rec in last)


def test_a_budget_spent_while_confirming_is_not_a_convergence():
    marginals, g = _archard_api_example()
    once = akmcs(g, marginals, seed=3, hold_iterations=1)
    r = akmcs(g, marginals, seed=3, max_calls=once.n_calls + 1)
    assert not r.converged
    assert "while confirming the learning stop" in r.message and f"max_calls={once.n_calls + 1}" in r.message
    with pytest.raises(ValueError, match="hold_iterations"):
        akmcs(g, marginals, hold_iterations=0)


def test_archard_wear_reference_is_its_monte_carlo():
    p = problems.archard_wear()
    x = np.column_stack([m.rvs(size=400_000, random_state=np.random.default_rng(i)) for i, m in enumerate(p.marginals)])
    pf = np.mean(p.g(x) < 0)
    # 4 standard errors of a 4e5-sample Monte Carlo (7e-4 at Pf = 0.26)
    assert abs(pf - p.pf_ref) < 4.0 * np.sqrt(p.pf_ref * (1 - p.pf_ref) / x.shape[0])
