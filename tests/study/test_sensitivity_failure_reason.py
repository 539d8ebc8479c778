"""A mean shift whose mechanism cannot run is counted as a failure and reported with the reason its model call
recorded (the sensitivity's separable-scaling rule; the report's part is tested in tests/report)."""

from types import SimpleNamespace

import numpy as np

from jointwear.compute import Evaluator
from jointwear.study.sensitivity import failure_reason


def _model(x):
    if x[0] > 1.5:
        return np.array([np.nan]), "mechanism: the drawn points coupler.A and crank.A are 2 mm apart"
    return np.array([x[0] ** 2]), "ok"


def test_failure_reason_reads_the_recorded_reason_without_running_again():
    calls = []

    def counted(x):
        calls.append(x.copy())
        return _model(x)

    ctx = SimpleNamespace(evaluator=Evaluator(counted))
    x_bad, x_good = np.array([2.0]), np.array([1.0])
    assert np.isnan(ctx.evaluator(x_bad[None, :])[0, 0]) and ctx.evaluator(x_good[None, :])[0, 0] == 1.0
    assert failure_reason(ctx, x_bad).endswith("mechanism: the drawn points coupler.A and crank.A are 2 mm apart")
    assert failure_reason(ctx, x_good) == "no reason recorded"  # it did not fail
    assert len(calls) == 2  # both read back, none run again
    assert failure_reason(SimpleNamespace(evaluator=lambda X: X), x_bad) == "no reason recorded"  # a bare callable
