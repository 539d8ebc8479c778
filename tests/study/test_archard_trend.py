"""reliability.trend = "archard": the Kriging of ln N_f is told Archard's exact scaling in the judged body's k and H."""

import numpy as np
import pytest
from analytic_wear import RATE, AnalyticWear

from jointwear import compute
from jointwear.config import load_config, updated
from jointwear.study import population, run_reliability, study_context

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def _context(cfg, factory=None):
    return study_context(cfg, factory or (lambda call: compute.Evaluator(lambda x: None, None, None, n_outputs=1)))


def test_trend_is_archards_scaling_of_the_judged_bodys_k_and_h():
    from jointwear.study.reliability import life_trend

    ctx = _context(updated(load_config(), {"reliability.trend": "archard"}))
    x = population(ctx.marginals, 1000, seed=1)
    k, h = ctx.names.index("k_b"), ctx.names.index("HB_b")
    k_mean, h_mean = ctx.marginals[k].mean(), ctx.marginals[h].mean()
    # life proportional to H / k (wear depth k / H x the same history): exact
    np.testing.assert_allclose(life_trend(ctx)(x), np.log(x[:, h] / h_mean) - np.log(x[:, k] / k_mean), rtol=1e-12)
    assert life_trend(_context(load_config())) is None  # the default: ordinary Kriging
    # two judged joints learnt one Kriging each: no single body's k and H scale the system's life
    six = load_config("watt_six_bar_two_clearances")
    assert life_trend(_context(updated(six, {"reliability.trend": "archard"}))) is None


@pytest.mark.parametrize("seed", [1, 2])
def test_analytic_life_with_the_trend(seed):
    # the analytic Archard-type model (tests/analytic_wear.py): told k and H, the Kriging learns ln(1 + 0.05 dc) alone
    cfg = updated(load_config(), {
        "reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [380_000], "reliability.trend": "archard", "reliability.seed": seed})
    holder = {}

    def factory(call):
        holder["model"] = AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
        return compute.Evaluator(holder["model"], None, None, n_outputs=len(call.cycles))

    ctx = _context(cfg, factory)
    res = run_reliability(ctx)
    x = population(ctx.marginals, 2_000_000, seed=10_000 + seed)
    exact = float(np.quantile(cfg.reliability.allowance / (RATE * holder["model"].scale(x)), 0.1))
    low, high = res.life_interval()
    assert low <= exact <= high, (low, exact, high)
    # Tolerance 0.5 %: benchmarks/life_coverage.py (40 seeds) measured a mean error of -0.02 % and a spread of 0.09 %
    # with the trend, against -0.45 % and 0.45 % without it; the 2e6-sample reference's own error is about 0.03 %
    assert abs(res.life() / exact - 1) < 5e-3


def test_check_says_where_the_trend_changes_nothing():
    from jointwear.study.checks import config_warnings

    base = load_config()
    assert not [w for w in config_warnings(updated(base, {"reliability.trend": "archard"})) if "trend" in w]
    six = updated(load_config("watt_six_bar_two_clearances"), {"reliability.trend": "archard"})
    assert any("reliability.trend" in w and "one judged joint (judged: A, E)" in w for w in config_warnings(six))
    growth = updated(base, {"reliability.trend": "archard", "reliability.quantity": "clearance_growth"})
    assert any("reliability.trend" in w and "'clearance_growth'" in w for w in config_warnings(growth))
    fixed = [v for v in base.model_dump()["uncertainty"]["variables"] if v["name"] not in ("k_b", "HB_b")]
    no_random = updated(base, {"reliability.trend": "archard", "uncertainty.variables": fixed})
    assert any("reliability.trend" in w and "no random variable targets clearance_joints.A.bearing_material"
               in w for w in config_warnings(no_random))
