"""jointwear.compute: where model calls run, and the evaluation store that makes studies resumable.

A service for the stages; it imports none of them.

- :func:`make_executor`: local processes (default, all cores), in-process serial (``workers=1``) or a
  Dask distributed cluster (``scheduler="tcp://host:8786"``); :func:`start_local_cluster` for tests.
- :class:`Evaluator`: a model ``f(x) -> (outputs, status)`` over a batch of rows, with time-outs,
  failures recorded (never raised), timing, and reuse of stored calls.
- :class:`EvaluationStore`: SQLite file in the output folder; resume, refuse a changed config.
- :class:`Progress`: rich progress display (calls done / total, Pf, COV, time left).

See docs/compute.md.
"""

from .evaluator import BatchResult, Evaluator, run_call
from .executors import (
    DaskExecutor,
    LocalExecutor,
    SerialExecutor,
    available_cores,
    make_executor,
    start_local_cluster,
    worker_pool_problem,
)
from .progress import Progress
from .store import (
    CallRecord,
    ConfigChangedError,
    EvaluationStore,
    StoreError,
    StoreExistsError,
    StoreStats,
    code_version,
    config_hash,
    row_key,
)

__all__ = [
    "BatchResult",
    "CallRecord",
    "ConfigChangedError",
    "DaskExecutor",
    "EvaluationStore",
    "Evaluator",
    "LocalExecutor",
    "Progress",
    "SerialExecutor",
    "StoreError",
    "StoreExistsError",
    "StoreStats",
    "available_cores",
    "code_version",
    "config_hash",
    "make_executor",
    "row_key",
    "run_call",
    "start_local_cluster",
    "worker_pool_problem",
]
