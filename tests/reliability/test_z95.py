"""One 95 % normal quantile for every 95 % interval: Phi^-1(0.975) to the last bit, not 1.96 (audit 61-J, item 18)."""

from __future__ import annotations

from scipy import stats

from jointwear.reliability import Z95, esc_errors
from jointwear.reliability.results import Z95 as results_z95
from jointwear.study import convergence


def test_z95_is_the_exact_normal_quantile():
    assert Z95 == float(stats.norm.ppf(0.975)) == 1.959963984540054
    assert results_z95 is Z95


def test_the_convergence_check_and_the_esc_bounds_use_it():
    assert convergence.Z95 is Z95 and convergence.t95(float("inf")) == Z95
    assert esc_errors.__defaults__[-1] == Z95
