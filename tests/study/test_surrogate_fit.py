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
