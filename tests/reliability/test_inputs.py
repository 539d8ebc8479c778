"""Bad input, the NaN rule, determinism, executors and the evaluation store."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from scipy import stats

from jointwear.reliability import (
    Evaluation,
    LimitStateCaller,
    akmcs,
    monte_carlo,
    problems,
    subset_simulation,
)

NORM2 = [stats.norm(), stats.norm()]


def _lin(x):
    return 2.5 - (x[:, 0] + x[:, 1]) / np.sqrt(2.0)


def test_unfrozen_distribution():
    with pytest.raises(ValueError, match=r"marginals\[1\] is the unfrozen distribution scipy.stats.norm"):
        akmcs(_lin, [stats.norm(), stats.norm])


def test_not_a_distribution_and_not_a_sequence():
    with pytest.raises(ValueError, match=r"marginals\[0\] is a float"):
        akmcs(_lin, [1.0, stats.norm()])
    with pytest.raises(ValueError, match="sequence"):
        akmcs(_lin, stats.norm())


def test_wrong_shape():
    with pytest.raises(ValueError, match=r"g returned an array of shape \(12, 2\)"):
        akmcs(lambda x: np.column_stack([x[:, 0], x[:, 1]]), NORM2, n_initial=12)
    with pytest.raises(ValueError, match=r"shape \(\)"):
        monte_carlo(lambda x: 1.0, NORM2, 100)


def test_dimension_mismatch():
    def g3(x):  # a model of three inputs
        return 3.0 - x[:, 0] - x[:, 1] - x[:, 2]

    with pytest.raises(ValueError, match=r"2 marginals given"):
        akmcs(g3, NORM2)
    with pytest.raises(ValueError, match="u0 has 3 components"):
        from jointwear.reliability import form

        form(_lin, NORM2, u0=[0, 0, 0])


def test_all_nan_raises_and_nan_policy_raise():
    from jointwear.reliability import AllCallsFailedError

    # a typed error, so that a caller that knows its model (the study) can say why its calls failed
    with pytest.raises(AllCallsFailedError, match="NaN"):
        akmcs(lambda x: np.full(len(x), np.nan), NORM2)
    with pytest.raises(AllCallsFailedError, match="first batch"):
        monte_carlo(lambda x: np.full(len(x), np.nan), NORM2, 100)
    with pytest.raises(ValueError, match="nan_policy='raise'"):
        akmcs(lambda x: np.where(x[:, 0] > 1, np.nan, _lin(x)), NORM2, evaluation=Evaluation(nan_policy="raise"))


def test_nan_counts_as_failure_never_safe():
    # the model fails (NaN) in a region that is *safe* in truth: the rule must count those calls as failures
    def g(x):
        out = _lin(x)
        out[(x[:, 0] < -3.0)] = np.nan
        return out

    r = monte_carlo(g, NORM2, 200_000, seed=0, keep_design=True)
    exact = stats.norm.sf(2.5) + stats.norm.cdf(-3.0)  # union is ~disjoint: overlap ~1e-9
    assert r.pf == pytest.approx(exact, rel=3 * r.cov)  # 3 sigma of the MC estimate
    assert r.n_failed_calls == int(np.count_nonzero(r.design_x[:, 0] < -3.0))
    ra = akmcs(g, NORM2, seed=0, n_mc=50_000, stopping="error")
    assert ra.pf >= stats.norm.sf(2.5) * 0.9  # never "safe": NaN points add to pf, not subtract
    assert ra.n_failed_calls == int(np.count_nonzero(~np.isfinite(ra.design_g)))
    assert all("non-finite" in v for v in ra.failure_reasons.values())


def test_exceptions_in_model_calls_are_failed_calls():
    def g(x):
        if np.any(x[:, 0] > 4.0):
            raise RuntimeError("integrator cannot proceed")
        return _lin(x)

    r = subset_simulation(g, NORM2, n_per_level=500, seed=0)
    assert np.isfinite(r.pf)
    reasons = set(r.failure_reasons.values())
    assert not reasons or reasons == {"RuntimeError: integrator cannot proceed"}


def test_determinism():
    p = problems.four_branch(6)
    kw = dict(n_mc=30_000, seed=11, stopping="error", batch_size=2)
    a = akmcs(p.g, p.marginals, **kw)
    b = akmcs(p.g, p.marginals, **kw)
    assert a.pf == b.pf and a.n_calls == b.n_calls
    np.testing.assert_array_equal(a.design_x, b.design_x)
    s1 = subset_simulation(_lin, NORM2, n_per_level=500, seed=5)
    s2 = subset_simulation(_lin, NORM2, n_per_level=500, seed=5)
    assert s1.pf == s2.pf


def test_executor_store_and_caller_give_same_result(tmp_path):
    from jointwear.compute import EvaluationStore, Evaluator

    p = problems.linear(2.0, 2)
    base = akmcs(p.g, p.marginals, n_mc=20_000, seed=4)
    seen = []
    with ThreadPoolExecutor(2) as pool:
        r = akmcs(p.g, p.marginals, n_mc=20_000, seed=4,
                  evaluation=Evaluation(executor=pool, on_evaluate=lambda x, g, why: seen.append(len(x))))
    assert r.pf == base.pf and r.n_calls == base.n_calls and sum(seen) == r.n_calls
    # the cache of model calls is compute's evaluator: g through it is stored, and a rerun on the filled
    # store calls the model zero times and reproduces the run (resumability)
    row_model = lambda x: p.g(x[None, :])
    with EvaluationStore.open(tmp_path, "linear") as store:
        first = Evaluator(row_model, store=store)
        r1 = akmcs(first, p.marginals, n_mc=20_000, seed=4)
        assert first.n_model_calls == r1.n_calls
    with EvaluationStore.open(tmp_path, "linear", resume=True) as store:
        again = Evaluator(row_model, store=store)
        shared = LimitStateCaller(again, 2)
        r2 = akmcs(again, p.marginals, n_mc=20_000, seed=4, evaluation=Evaluation(caller=shared))
    assert again.n_model_calls == 0 and shared.n_calls == r2.n_calls and r1.pf == r2.pf == base.pf
    np.testing.assert_array_equal(r2.design_x, base.design_x)


def test_bad_options():
    with pytest.raises(ValueError, match="stopping"):
        akmcs(_lin, NORM2, stopping="maybe")
    with pytest.raises(ValueError, match="batch_size"):
        akmcs(_lin, NORM2, batch_size=0)
    with pytest.raises(ValueError, match="executor"):
        akmcs(_lin, NORM2, evaluation=Evaluation(executor=object()))
    with pytest.raises(ValueError, match="nan_policy"):
        Evaluation(nan_policy="ignore")
    with pytest.raises(ValueError, match="evaluation"):
        akmcs(_lin, NORM2, evaluation={"executor": None})


def test_process_pool_executor_batch():
    # model calls in worker processes (the default executor of the compute layer); batches of 3 run in parallel
    from concurrent.futures import ProcessPoolExecutor

    p = problems.four_branch(6)
    with ProcessPoolExecutor(2) as pool:
        r = akmcs(p.g, p.marginals, n_mc=20_000, seed=2, batch_size=3, stopping="error",
                  evaluation=Evaluation(executor=pool))
    base = akmcs(p.g, p.marginals, n_mc=20_000, seed=2, batch_size=3, stopping="error")
    assert r.pf == base.pf and r.n_calls == base.n_calls  # same algorithm, different place of the calls


def test_sizes_take_an_integral_float_as_the_docs_write_them():
    """docs/reliability.md writes `n=1e5`, `n_mc=1e5`: they were refused ('n must be an integer >= 2; got 100000.0')."""
    from jointwear.reliability import importance_sampling, sample

    assert monte_carlo(_lin, NORM2, n=2e3, batch=1e3).n_mc == 2000
    assert sample(NORM2, 1e2, seed=0).shape == (100, 2)
    assert importance_sampling(_lin, NORM2, n=1e3).n_calls >= 1000  # plus the FORM calls
    for bad in (2500.5, float("nan"), float("inf"), True, "1000"):
        with pytest.raises(ValueError, match=r"n must be an integer >= 2"):
            monte_carlo(_lin, NORM2, n=bad)
    with pytest.raises(ValueError, match=r"n must be an integer >= 0; got 10.5"):
        sample(NORM2, 10.5)
