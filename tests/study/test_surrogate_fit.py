"""The life surrogate's own check (SurrogateFit): its leave-one-out Q^2 and the noise it estimated, from the study's
calls alone; a poor fit warns in the result, the CLI and the report."""

from __future__ import annotations

import numpy as np
import pytest

from jointwear.reliability import KrigingSurrogate
from jointwear.study.reliability_results import SurrogateFit


def _fit(y_of, n=60, d=3, seed=0):
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, d))
    return SurrogateFit.of(KrigingSurrogate(seed=seed, estimate_nugget=True).fit(u, y_of(u, rng)))


def test_a_smooth_response_is_explained():
    # ln N_f smooth in the inputs with 1 % scatter: the inputs explain nearly all of it (Q^2 = 1 - 0.01^2 / var y
    # for a perfect surrogate, var y = 0.29 here) and no warning is given
    fit = _fit(lambda u, rng: 12.0 + 0.5 * u[:, 0] - 0.2 * u[:, 1] ** 2 / 2 + 0.01 * rng.standard_normal(len(u)))
    assert fit.q2 > 0.95
    assert not fit.poor and fit.warning() == ""


def test_scatter_alone_is_not_explained_and_warns():
    # ln N_f = constant + 20 % scatter, the inputs doing nothing: a surrogate cannot predict a left-out point
    # better than the mean (Q^2 <= ~0), and the warning names Q^2, the scatter and what to do
    fit = _fit(lambda u, rng: 12.0 + 0.2 * rng.standard_normal(len(u)))
    assert fit.q2 < SurrogateFit.Q2_FLOOR
    text = fit.warning()
    assert "Q^2" in text and "wear.record_cycles" in text and "jointwear validate" in text
    # it told the scatter as the cause whatever the numbers (a six-bar of 14 calls in 7 inputs, whose design lives
    # spread 15 times the fitted scatter, was sent to converge); the fit cannot tell them apart, more calls can
    assert "raise reliability.max_calls and run again with --resume" in text
    assert f"leave-one-out error of ln N_f {fit.rmse_log_life:.3g}" in text


def test_json_round_trip_and_older_results():
    fit = _fit(lambda u, rng: 12.0 + 0.5 * u[:, 0] + 0.05 * rng.standard_normal(len(u)))
    assert SurrogateFit.from_json(fit.to_json()) == fit
    assert fit.to_json()["life_scatter"] == pytest.approx(np.expm1(fit.noise_sd_log_life))
    assert SurrogateFit.from_json(None) is None  # a reliability.json written before the check


def test_a_point_far_in_the_tail_is_named_as_the_cause_with_the_archard_trend_as_the_cure():
    """A designer's 24 calls followed Archard's law within 2 %, but one initial point at a wear coefficient near zero
    (-5 sigma) lived 450 times the others and the fit's Q^2 read 0.36; the warning blamed a call's scatter or too few
    calls and never named the setting that fixes it (`reliability.trend = "archard"` gave Q^2 = 0.9998). Here ln N_f
    = 14.7 - ln(k / k_mean) + 0.3 u2 with k's COV 20 % and one point at -4.95 sigma (k = 1 % of its mean)."""
    rng = np.random.default_rng(2)
    u = rng.standard_normal((24, 3))
    u[0, 0] = -4.95
    y = 14.7 - np.log(1.0 + 0.2 * u[:, 0]) + 0.3 * u[:, 1] + 0.002 * rng.standard_normal(24)
    surrogate = KrigingSurrogate(seed=2, estimate_nugget=True).fit(u, y)
    fit = SurrogateFit.of(surrogate, archard_trend_hint=True)
    assert fit.poor and fit.worst_share > SurrogateFit.WORST_SHARE
    assert fit.worst_life_ratio == pytest.approx(np.exp(y[0] - np.median(y)), rel=1e-12)
    text = fit.warning()
    assert f"One design point carries {100 * fit.worst_share:.0f} % of its leave-one-out error" in text
    assert f"its life is {fit.worst_life_ratio:,.3g} times the points' median" in text
    assert "reliability.trend = 'archard'" in text and "Either a call's own scatter" not in text
    assert SurrogateFit.from_json(fit.to_json()) == fit
    # without a random wear coefficient or hardness to be told, the cure is more calls
    plain = SurrogateFit.of(surrogate).warning()
    assert "raise reliability.max_calls" in plain and "archard" not in plain
    # a scatter of 0.02 % reads so, not 'about 0 %'
    scattered = SurrogateFit(n_points=24, q2=0.3, rmse_log_life=0.7, noise_sd_log_life=0.000189,
                             process_sd_log_life=0.5, relative_nugget=1e-6, nugget_at_bound=False)
    assert "about 0.019 % in life" in scattered.warning()


def test_a_far_point_is_told_above_the_q2_floor_where_the_archard_trend_cures_it():
    """A verification's Kriging of 16 calls had Q^2 = 0.81 but one point at 35 times the median life carried 91 % of
    its leave-one-out error, and its R(N*) read 0.77 where the design's own study gave 0.90: told where the Archard
    trend would cure it; a point within 10 times the median, or no such cure, stays quiet above the floor."""
    def fit(ratio, hint=True, share=0.91):
        return SurrogateFit(n_points=16, q2=0.81, rmse_log_life=0.527, noise_sd_log_life=1.4e-4,
                            process_sd_log_life=1.44, relative_nugget=1e-8, nugget_at_bound=False,
                            worst_share=share, worst_life_ratio=ratio, archard_trend_hint=hint)

    assert fit(35.1).far_point and not fit(35.1).poor
    assert fit(35.1).warning().startswith("one of the life surrogate's 16 design points carries 91 % of its "
                                          "leave-one-out error (Q^2 = 0.81, leave-one-out error of ln N_f 0.527): "
                                          "its life is 35.1 times the points' median")
    assert "1/20 of the points' median" in fit(0.05).warning()  # a point living far shorter
    assert fit(9.0).warning() == "" and fit(35.1, hint=False).warning() == "" and fit(35.1, share=0.4).warning() == ""
