"""The study joins random inputs, the true model and the reliability engine correctly.

The wear model is replaced by an analytic law with the structure of Archard's (wear depth proportional
to k / H and to the number of cycles), so the exact R(N) is known by brute-force Monte Carlo.
"""

import json

import numpy as np
import pytest
from analytic_wear import RATE, AnalyticWear

from jointwear import compute
from jointwear.config import load_config, updated
from jointwear.study import life_at, population, run_reliability, study_context
from jointwear.study.io import strict
from jointwear.study.limit_state import curve_cycles

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


@pytest.fixture(scope="module")
def study():
    # a deterministic model: the engine's own accuracy settings (relative ESC error 2 %, absolute 0.2 %)
    cfg = updated(load_config(), {
        "reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [380_000, 420_000], "reliability.n_mc": 50_000,
        "reliability.noise": "none", "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002, "reliability.max_calls": 120})
    holder = {}

    def factory(call):
        holder["model"] = AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
        return compute.Evaluator(holder["model"], None, None, n_outputs=len(call.cycles))

    ctx = study_context(cfg, factory)
    return cfg, ctx, run_reliability(ctx), holder["model"]


def test_reliability_curve_matches_brute_force_monte_carlo(study):
    cfg, ctx, res, model = study
    x = population(ctx.marginals, 1_000_000, seed=99)
    wear = RATE * model.scale(x)[:, None] * res.cycles[None, :]
    pf_ref = np.mean(wear > cfg.reliability.allowance, axis=0)
    se_ref = np.sqrt(pf_ref * (1 - pf_ref) / len(x))
    for k in range(len(res.cycles)):
        if pf_ref[k] < 1e-3:
            continue
        # Tolerance: the reliability engine's acceptance (issue 4): within 3 % of the reference or within
        # 2x the reported COV, plus 3 standard errors of the 1e6-sample reference itself.
        tol = max(0.03 * pf_ref[k], 2 * res.pf_cov[k] * res.pf[k]) + 3 * se_ref[k]
        assert abs(res.pf[k] - pf_ref[k]) < tol, (res.cycles[k], res.pf[k], pf_ref[k])
    assert res.model_calls <= cfg.reliability.max_calls
    assert np.all(np.diff(res.reliability) <= 1e-12)  # wear grows with N, so R(N) cannot increase


def test_life_and_histograms_are_consistent(study):
    cfg, ctx, res, model = study
    life = res.life(cfg.reliability.target_reliability)
    assert life == res.life_cycles
    # the life's 95 % interval (the band R -/+ (1.96 COV Pf + surrogate error) crossing the target, on the curve
    # between its levels) holds the life of the brute-force curve read at the same points
    fine = np.asarray(res.life_curve["cycles"])
    np.testing.assert_array_equal(fine, curve_cycles(res.cycles))
    x = population(ctx.marginals, 1_000_000, seed=99)
    rate = np.sort(RATE * model.scale(x))  # wear RATE scale N > a when RATE scale > a / N: one sort for every N
    pf_ref = 1.0 - np.searchsorted(rate, cfg.reliability.allowance / fine, side="right") / rate.size
    low, high = res.life_interval()
    assert low <= life_at(fine, 1.0 - pf_ref, cfg.reliability.target_reliability) <= high, (low, high)
    assert res.life_table[0]["cycles_low"] == low and res.life_table[0]["cycles_high"] == high
    # every level's error estimate is finite, and the results read back from their JSON give the same interval
    assert np.all(np.isfinite(res.pf_error))
    back = type(res).from_json(json.loads(json.dumps(strict(res.to_json()), allow_nan=False)))
    assert back.life_interval() == (low, high)
    # Mean max wear from the surrogate vs the exact mean RATE * N * E[scale] (Monte Carlo, 1e6 samples).
    x = population(ctx.marginals, 1_000_000, seed=5)
    exact = RATE * model.scale(x).mean() * np.asarray(res.mean_max_wear_mm["cycles"]) * 1e3
    # 1 % : the surrogate's error on a smooth 3-variable product over the population, well above MC noise
    np.testing.assert_allclose(res.mean_max_wear_mm["mean"], exact, rtol=1e-2)
    assert res.histograms["cycles"] == [380_000, 420_000]
    # the speed as entered: 480 rpm came back through rad/s as 479.99999999999994
    assert cfg.mechanism.crank_speed * 60 / (2 * np.pi) != 480.0 and res.crank_speed_rpm == 480.0
    # the design points' wear comes with the cycles it is at (it had no cycle axis): the analytic wear RATE * N * scale
    np.testing.assert_array_equal(res.design_wear_cycles, ctx.history_cycles)
    scale = model.scale(res.design_x)[:, None]
    np.testing.assert_allclose(res.design_wear, RATE * scale * np.asarray(ctx.history_cycles)[None, :], rtol=1e-12)
    # one model for both: P(wear > allowance) of the histograms is 1 - R(N) up to the Monte Carlo noise of two
    # populations (4 standard errors of their difference)
    n_h, n_mc = res.histograms["n_population"], res.n_mc
    for p_hist, p_curve in zip(res.histograms["exceedance"], res.histograms["one_minus_reliability"]):
        se = np.sqrt(p_curve * (1 - p_curve) * (1 / n_h + 1 / n_mc))
        assert abs(p_hist - p_curve) <= 4 * se + 1e-12, (p_hist, p_curve)


def test_life_at_interpolates():
    assert life_at([1, 2, 3], [1.0, 0.95, 0.85], 0.9) == pytest.approx(2.5)  # exact linear interpolation
    assert life_at([1, 2], [1.0, 0.95], 0.9) is None  # beyond the curve
    assert life_at([1, 2], [0.85, 0.5], 0.9) is None  # before the curve


def _analytic_study(cfg, executor=None):
    holder = {}

    def factory(call):
        holder["model"] = AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
        return compute.Evaluator(holder["model"], executor, None, n_outputs=len(call.cycles))

    ctx = study_context(cfg, factory)
    return ctx, run_reliability(ctx), holder["model"]


def _small_config():
    return updated(load_config(), {
        "reliability.cycles_start": 360_000, "reliability.cycles_stop": 440_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [400_000], "reliability.n_mc": 20_000, "reliability.max_calls": 30})


@pytest.fixture(scope="module")
def small_serial():
    """The small study run serially, the reference of the parallel, Dask and 'fail' rule runs (deterministic)."""
    return _analytic_study(_small_config())


def test_random_allowance_enters_as_a_variable():
    # Section 5.1: delta_0 ~ N(0.01 D, 0.0005 D). Exact R(N) by brute force with the allowance sampled too.
    cfg = updated(_small_config(), {"reliability.allowance_std": 0.0005 * 3e-3, "reliability.noise": "none", "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002})
    ctx, res, model = _analytic_study(cfg)
    assert ctx.names[-1] == "delta_0" and len(ctx.marginals) == 14
    x = population(ctx.marginals, 1_000_000, seed=11)
    wear = RATE * model.scale(x[:, :-1])[:, None] * res.cycles[None, :]
    pf_ref = np.mean(wear > x[:, -1:], axis=0)
    for k in range(len(res.cycles)):
        # the engine's acceptance (issue 4): 3 % of the reference or 2x the reported COV, + 3 reference s.e.
        tol = max(0.03 * pf_ref[k], 2 * res.pf_cov[k] * res.pf[k]) + 3 * np.sqrt(pf_ref[k] * (1 - pf_ref[k]) / 1e6)
        assert abs(res.pf[k] - pf_ref[k]) < tol


def test_same_result_serially_and_with_two_local_workers(small_serial):
    from jointwear.compute import make_executor

    cfg = _small_config()
    _, serial, _ = small_serial
    with make_executor(workers=2) as ex:
        _, parallel, _ = _analytic_study(cfg, ex)
    assert parallel.model_calls == serial.model_calls
    np.testing.assert_array_equal(parallel.reliability, serial.reliability)  # bit-identical by design


def test_same_result_on_a_dask_cluster(small_serial):
    from jointwear.compute import make_executor, start_local_cluster

    cfg = _small_config()
    _, serial, _ = small_serial
    cluster = start_local_cluster(n_workers=2)
    try:
        with make_executor(scheduler=cluster) as ex:
            _, on_dask, _ = _analytic_study(cfg, ex)
    finally:
        cluster.close()
    assert on_dask.model_calls == serial.model_calls
    np.testing.assert_array_equal(on_dask.reliability, serial.reliability)


def test_fail_rule_adds_the_infeasible_probability(small_serial):
    # 'fail': Pf = P(c <= c_min) + P(c > c_min) Pf(feasible); 'truncate': Pf(feasible). Same learning (the
    # learning always runs on the feasible samples), so the relation holds to rounding.
    cfg = _small_config()
    assert cfg.uncertainty.clearance.infeasible_rule == "truncate"
    _, truncated, _ = small_serial
    cfg = updated(cfg, {"uncertainty.clearance.infeasible_rule": "fail"})
    _, failing, _ = _analytic_study(cfg)
    p_inf = cfg.uncertainty.clearance.infeasible_probability()
    np.testing.assert_allclose(failing.pf, p_inf + (1 - p_inf) * truncated.pf, rtol=1e-12, atol=1e-15)
    assert failing.infeasible["clearances"][0]["rule"] == "fail"
    assert failing.infeasible["probability_failed_at_assembly"] == pytest.approx(p_inf, rel=1e-12)  # 1 - (1 - p)


@pytest.fixture(scope="module")
def small_sensitivity():
    """The small deterministic study's sensitivity at 400k cycles (mean shifts of 0.8 and 1.2)."""
    from jointwear.study import run_sensitivity

    cfg = updated(_small_config(), {"reliability.noise": "none", "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002, "sensitivity.cycles": 400_000,
                                    "sensitivity.sobol_base_samples": 256})
    ctx, res, model = _analytic_study(cfg)
    return cfg, ctx, model, run_sensitivity(ctx, res)


def test_sensitivity_mean_shifts_against_brute_force(small_sensitivity):
    # Mean shifts of the analytic wear model at 400k cycles: k_b (a 2-sigma shift, on the surrogate) and the
    # rod length l2 (hundreds of sigma, separable scaling: the analytic wear does not depend on l2, so its
    # reliability must stay the nominal one). Exact values by brute-force Monte Carlo.
    from jointwear.sensitivity import shifted_marginal

    cfg, ctx, model, sens = small_sensitivity
    by_name = {v["name"]: v for v in sens.variables}
    i = ctx.names.index("k_b")
    for factor, key in ((0.8, "reliability_low"), (1.2, "reliability_high")):
        marg = list(ctx.marginals)
        marg[i] = shifted_marginal(marg[i], factor)
        x = population(marg, 400_000, seed=21)
        exact = np.mean(RATE * model.scale(x) * 400_000 <= cfg.reliability.allowance)
        # 0.02: the learning's absolute error tolerance (0.002) on the nominal population, plus the surrogate's
        # extrapolation toward the 2-sigma-shifted tail and Monte Carlo error (~0.001)
        assert abs(by_name["k_b"][key] - exact) < 0.02, (factor, by_name["k_b"][key], exact)
    rules = {(r["variable"], round(r["factor"], 3)): r for r in sens.rules}
    assert rules[("l2", 0.8)]["rule"] == "separable_scaling"
    # a deterministic model (noise "none"): the wear ratio's two calls do not scatter, so its error is the surrogate's
    far = rules[("l2", 0.8)]
    assert far["error_wear_ratio"] == 0.0 and far["error_estimate"] == far["error_surrogate"] > 0
    assert rules[("k_b", 1.2)]["rule"] == "surrogate"
    assert by_name["l2"]["reliability_high"] == pytest.approx(sens.reliability_nominal, abs=1e-12)
    assert sens.ranking[0] in ("k_b", "HB_b")  # the only variables with a 10 % scatter in the model
    # the elasticity of R, (mu / R) dR/dmu, against a central difference of the exact R (+-2 %, common random
    # numbers; +-5 % gives the same to 1 %): it was labelled so but held -(mu / Pf) dPf/dmu, 1.9x this one here.
    # 10 %: three standard errors of the score-function estimate (0.7 % each) and the surrogate's boundary, which
    # the learning places to 0.002 in Pf, not in its slope (measured: 4 %)
    r = []
    for factor in (0.98, 1.02, 1.0):
        marg = list(ctx.marginals)
        marg[i] = shifted_marginal(marg[i], factor)
        x = population(marg, 400_000, seed=21)
        r.append(np.mean(RATE * model.scale(x) * 400_000 <= cfg.reliability.allowance))
    assert by_name["k_b"]["elasticity_mean"] == pytest.approx((r[1] - r[0]) / (0.04 * r[2]), rel=0.10)
    # a slope's 95 % error counts the surrogate's own (the estimator's spread over the Kriging's posterior): with the
    # Monte Carlo error alone, three of the ten inputs the analytic wear does not read (l2, nu_j, k_j: exact slope 0)
    # had resolved slopes, |dR/dmu| > 1.96 SE (measured: -162 against 154, and likewise); the three it reads are
    # resolved
    for v in sens.variables:
        assert (abs(v["dR_dmean"]) > v["dR_dmean_error"]) == (v["name"] in ("k_b", "HB_b", "c")), v


def test_archard_shifts_check_the_surrogate_and_the_clearance_keeps_its_floor():
    # The analytic wear is exactly proportional to k_b / H_b, so Archard's exact shift must agree with the
    # surrogate-based one within the check's own tolerance (each reading's error, never below the learning's requested
    # accuracy, plus Monte Carlo noise). Shifts of +-10 % (about 1 sigma of k_b and H_b) keep both readings where the
    # surrogate was learned: the Archard reading needs the life at 400k x 1.1^(+-1), inside the 320k-480k curve.
    # Over 12 seeds the largest |difference| / tolerance was 0.35 (with +-20 % shifts and a 320k-560k curve it
    # reached 1.05, where the surrogate's own reading was truly off: the check is meant to flag that).
    from jointwear.study import run_sensitivity
    from jointwear.study.sensitivity import physical_marginal
    from jointwear.sensitivity import shifted_marginal

    cfg = updated(_small_config(), {"reliability.noise": "none", "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002,
                                    "reliability.cycles_start": 320_000, "reliability.cycles_stop": 480_000,
                                    "reliability.max_calls": 60, "sensitivity.cycles": 400_000,
                                    "sensitivity.factors": (0.9, 1.1), "sensitivity.sobol_base_samples": 256})
    ctx, res, _ = _analytic_study(cfg)
    sens = run_sensitivity(ctx, res)
    checked = {(c["variable"], round(c["factor"], 3)) for c in sens.archard_checks}
    assert checked == {("k_b", 0.9), ("k_b", 1.1), ("HB_b", 0.9), ("HB_b", 1.1)}
    assert all(c["consistent"] is True for c in sens.archard_checks), sens.archard_checks
    # the table reports Archard's scaling for the judged body's k and H, the surrogate's direct reading for the rest
    rows = {v["name"]: v for v in sens.variables}
    for c in sens.archard_checks:
        side = "reliability_low" if c["factor"] < 1.0 else "reliability_high"
        assert rows[c["variable"]][side] == c["reliability_archard"]
    assert {r["rule"] for r in sens.rules if r["variable"] in ("k_b", "HB_b")} == {"archard_scaling"}
    # sensitivity.csv says which rule read each shift, at which factor (it gave the reliabilities alone)
    table = sens.tables()["sensitivity"]
    assert table["factor_low"] == [0.9] * len(ctx.names) and table["factor_high"] == [1.1] * len(ctx.names)
    recorded = {(r["variable"], round(r["factor"], 6)): r["rule"] for r in sens.rules}
    cells = {(name, f): rule for name, low, high in zip(table["name"], table["rule_low"], table["rule_high"])
             for f, rule in ((0.9, low), (1.1, high))}
    assert cells == recorded
    assert cells[("k_b", 0.9)] == "archard_scaling" and cells[("E_b", 1.1)] == "surrogate"
    assert cells[("Rj", 0.9)] == "separable_scaling"  # +-10 % of a radius: many of its tolerance's sigmas
    assert set(table["reliability_nominal"]) == {sens.reliability_nominal} and set(table["cycles"]) == {400_000}
    i = ctx.names.index("c")
    low = physical_marginal(ctx, i, shifted_marginal(ctx.marginals[i], 0.8))
    # the shifted clearance is still truncated at the configured minimum: no sample below it
    assert low.ppf(0.0) == pytest.approx(cfg.uncertainty.clearance.minimum, rel=1e-9)
    assert low.mean() < ctx.marginals[i].mean()


def test_archard_check_is_not_made_outside_the_learned_curve(small_sensitivity):
    # +-20 % shifts of k_b and H_b move the Archard reading's limit state to 400k x 1.2^(+-1) and 400k x 0.8^(+-1)
    # (320k to 500k cycles), all outside a 360k-440k curve, where the surrogate was never learned: not checked, and said
    cfg, _, _, sens = small_sensitivity
    assert cfg.sensitivity.factors == (0.8, 1.2) and cfg.reliability.curve_cycles() == [360_000, 400_000, 440_000]
    checks = sens.archard_checks
    assert len(checks) == 4
    for c in checks:
        assert c["consistent"] is None and "outside the learned curve" in c["note"]
        assert not 360_000 <= c["life_level_needed"] <= 440_000


class _WornAwayAbove(AnalyticWear):
    """The analytic wear model whose calls fail above a wear coefficient, as a worn-away pin's did."""

    def __init__(self, names, cycles, k_max):
        super().__init__(names, cycles)
        self.k_max = k_max

    def __call__(self, x):
        if x[self.i_k] > self.k_max:
            raise ValueError("math domain error")
        return super().__call__(x)


def test_a_failed_call_keeps_the_models_own_reason_and_is_counted():
    """The engine sees a failed call's NaN only; the study keeps what the model said (it reported 'g returned a
    non-finite value' for every worn-away pin)."""
    cfg = _small_config()
    k = cfg.uncertainty.all_specs()[[s.name for s in cfg.uncertainty.all_specs()].index("k_b")]
    ctx = study_context(cfg, lambda call: compute.Evaluator(
        _WornAwayAbove([s.name for s in cfg.uncertainty.all_specs()], call.cycles, k.mean + 1.5 * k.std), None,
        None, n_outputs=len(call.cycles)))
    res = run_reliability(ctx)
    reasons = res.infeasible["failure_reasons"]
    assert res.failed_calls == len(reasons) > 0
    assert all("math domain error" in r for r in reasons.values()), reasons
    assert f"{res.failed_calls} of {res.model_calls} model calls failed" in res.failed_calls_sentence()


class ScatteredWear(AnalyticWear):
    """The analytic wear times exp(s z(x)), z(x) a standard normal drawn from the bits of x: a deterministic model
    whose life scatters from one input to the next like a chaotic contact's (docs/reliability.md, 'A noisy
    model'). Its exact R(N) draws z independently of x."""

    def __init__(self, names, cycles, s):
        super().__init__(names, cycles)
        self.s = s

    def z(self, x):
        import hashlib

        rows = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
        return np.array([np.random.default_rng(int.from_bytes(hashlib.blake2b(r.tobytes(), digest_size=8).digest(),
                                                              "little")).standard_normal() for r in rows])

    def __call__(self, x):
        return RATE * self.cycles * self.scale(x)[0] * np.exp(self.s * self.z(x)[0]), "ok"


def test_the_curve_integrates_the_life_scatter():
    # the scatter (13 % in ln N) is as large as the inputs' own (k_b and H_b: ~13 %): a curve that read the
    # Kriging's mean alone would be far too steep (0.992 against the exact 0.963 at its first level)
    s = 0.13
    cfg = updated(load_config(), {
        "reliability.cycles_start": 300_000, "reliability.cycles_stop": 520_000, "reliability.cycles_step": 40_000,
        "reliability.histogram_cycles": [380_000, 420_000], "reliability.n_mc": 50_000, "reliability.max_calls": 60})
    holder = {}

    def factory(call):
        holder["model"] = ScatteredWear([v.name for v in cfg.uncertainty.all_specs()], call.cycles, s)
        return compute.Evaluator(holder["model"], None, None, n_outputs=len(call.cycles))

    ctx = study_context(cfg, factory)
    res = run_reliability(ctx)
    model = holder["model"]
    # the Kriging's noise is the scatter: 60 noisy points estimate a variance to ~18 % (sqrt(2 / 60)), so its
    # standard deviation to ~9 %; 25 % is about 3 of those
    assert res.engine.noise_sd == pytest.approx(s, rel=0.25)
    x = population(ctx.marginals, 400_000, seed=99)
    z = np.random.default_rng(5).standard_normal(x.shape[0])
    wear = RATE * (model.scale(x) * np.exp(s * z))[:, None] * res.cycles[None, :]
    r_exact = 1.0 - np.mean(wear > cfg.reliability.allowance, axis=0)
    se = np.sqrt(r_exact * (1.0 - r_exact) / x.shape[0])
    # at every level the exact curve lies in the curve's own 95 % band, up to 3 standard errors of the reference
    assert np.all(np.abs(res.reliability - r_exact) <= res.half_width + 3 * se), (res.reliability, r_exact)
    # the surrogate's part of that band is the larger of ESC's count and the Kriging's posterior spread; on a curve
    # that integrates a scatter this large the posterior spread sets it somewhere (ESC counts only the points near
    # the sign change)
    assert np.all(res.pf_error >= res.pf_error_esc) and np.any(res.pf_error > res.pf_error_esc)
    low, high = res.life_interval()
    assert low <= life_at(res.cycles, r_exact, cfg.reliability.target_reliability) <= high
    # the histograms' wear carries the same scatter: P(wear > allowance) is 1 - R(N) up to the Monte Carlo noise
    # of two populations (4 standard errors of their difference)
    n_h, n_mc = res.histograms["n_population"], res.n_mc
    for p_hist, p_curve in zip(res.histograms["exceedance"], res.histograms["one_minus_reliability"]):
        assert abs(p_hist - p_curve) <= 4 * np.sqrt(p_curve * (1 - p_curve) * (1 / n_h + 1 / n_mc)) + 1e-12


def test_one_judged_joint_learns_the_system_life_and_the_config_and_docs_say_so(study):
    """reliability.json said 'system_life' while the config said 'per_joint' and its description 'the same either
    way': with one joint the JSON names what was learnt, and the setting's description and the docs say that."""
    from pathlib import Path

    from jointwear.study_settings import ReliabilitySettings

    cfg, _ctx, res, _model = study
    assert len(res.joints) == 1 and cfg.reliability.surrogate == "per_joint"
    assert res.life_surrogate == res.to_json()["life_surrogate"] == "system_life"
    said = "life_surrogate names what was learnt: 'system_life'"
    assert said in ReliabilitySettings.model_fields["surrogate"].description
    docs = Path(__file__).resolve().parents[2] / "docs"
    assert "`system_life` with one judged joint" in (docs / "user-guide.md").read_text(encoding="utf-8")
    assert "`life_surrogate` says `\"system_life\"`" in (docs / "reliability.md").read_text(encoding="utf-8")
