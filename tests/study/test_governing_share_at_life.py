"""The governing joint and each joint's share of a series system's failures are read at the life itself, on the life
curve, not at the nearest level of R(N): a user's press with levels 100,000 cycles apart was told joint K took 100 %
of the failures at its life of 532,843 cycles (the share at 500,000), where the joints' own curves gave the other
joint about a third."""

import copy

import numpy as np
import pytest
from test_results import small_reliability_curve

from jointwear.study.reliability import governing_shares_at


def test_shares_by_each_threshold_are_the_fraction_of_failed_samples_whose_shortest_life_is_each_joints():
    rng = np.random.default_rng(3)
    lives = rng.normal([1.0, 1.2], [0.3, 0.1], size=(20_000, 2))
    thresholds = np.array([0.0, 0.8, 1.1, 1.3, -5.0])
    shares = governing_shares_at(lives, thresholds)
    for t, column in zip(thresholds, shares.T):
        failed = lives.min(axis=1) < t
        if not failed.any():
            assert np.all(np.isnan(column))
            continue
        first = np.argmin(lives[failed], axis=1)  # exact: the same counts
        np.testing.assert_allclose(column, [np.mean(first == 0), np.mean(first == 1)], rtol=0, atol=1e-15)
        assert column.sum() == pytest.approx(1.0, abs=1e-15)


def test_the_result_reads_the_shares_at_the_life_between_levels():
    res = small_reliability_curve()
    res.life_curve = {"cycles": [1e5, 1.5e5, 2e5, 3e5], "reliability": [0.99, 0.9, 0.8, 0.3],
                      "half_width_95": [0.01] * 4}
    two = copy.deepcopy(res.joints[0])
    res.joints = [dict(two, name="K", governing_share=[1.0, 1.0, 0.6],
                       curve={"governing_share": [1.0, 0.7, 0.6, 0.5]}),
                  dict(two, name="C", governing_share=[0.0, 0.0, 0.4],
                       curve={"governing_share": [0.0, 0.3, 0.4, 0.5]})]
    res.life_cycles = 1.25e5  # between the curve's points 1e5 and 1.5e5; the nearest level (1e5) gives K 100 %
    assert res.governing_shares() == pytest.approx({"K": 0.85, "C": 0.15}, abs=1e-12)
    legacy = copy.deepcopy(res)  # a result written before the shares were kept on the life curve
    for joint in legacy.joints:
        del joint["curve"]
    assert legacy.governing_shares() == {"K": 1.0, "C": 0.0}
