"""Writing results: strict JSON (no NaN or Infinity: null, with the reason beside it), CSV tables, provenance."""

from __future__ import annotations

import csv
import datetime as _dt
import json
import math
import os
import platform
import re
from collections import Counter
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np


def strict(obj: Any) -> Any:
    """A JSON-ready copy: numpy to Python, non-finite floats to None (strict parsers refuse NaN/Infinity)."""
    if isinstance(obj, Mapping):
        return {str(k): strict(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [strict(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return strict(obj.tolist())
    if isinstance(obj, np.generic):
        return strict(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, Path):
        return str(obj)
    return obj


def write_text_atomic(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file renamed over it: a process killed while writing leaves
    the old file or the new one, never half of one (a study's records are read back on resume)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    return path


def write_json(path: Path, payload: Mapping) -> Path:
    """Write ``payload`` as strict, indented JSON (NaN and infinities become null), atomically."""
    return write_text_atomic(path, json.dumps(strict(payload), indent=1, allow_nan=False) + "\n")


def read_json(path: Path) -> dict:
    obj = json.loads(Path(path).read_text(encoding="utf-8"))
    if not isinstance(obj, dict):
        raise ValueError(f"{path}: expected a JSON object")
    return obj


def file_labels(names: Sequence[str]) -> list[str]:
    """Each name as part of a file name: characters other than letters, digits, '.', '-' and '_' become '_' (a joint
    named 'crank pin/rod' -> 'crank_pin_rod'); where two names give the same label, also in another case ('A' and
    'a': one file on macOS and Windows), each gets its position appended."""
    labels = [re.sub(r"[^A-Za-z0-9._-]", "_", str(name)) or "_" for name in names]
    counts = Counter(label.casefold() for label in labels)
    return [f"{label}_{k}" if counts[label.casefold()] > 1 else label for k, label in enumerate(labels)]


def write_csv(path: Path, columns: Mapping[str, Sequence]) -> Path:
    """Write equal-length columns as a CSV table (header = the column names, units in the names)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(columns)
    cols = [list(columns[n]) for n in names]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for row in zip(*cols):
            w.writerow(["" if v is None else (f"{v:.10g}" if isinstance(v, (float, np.floating)) else v)
                        for v in row])
    return path


@lru_cache(maxsize=1)
def _static_provenance() -> dict:
    from importlib.metadata import PackageNotFoundError, version

    def v(name: str) -> str | None:
        try:
            return version(name)
        except PackageNotFoundError:
            return None

    try:
        import llvmlite.binding as llvm

        cpu = llvm.get_host_cpu_name()
    except Exception:  # noqa: BLE001 - provenance is best effort
        cpu = None
    from jointwear.compute.store import code_version

    return {
        "jointwear": code_version(),  # with the git commit when run from a checkout: which code wrote the result
        "python": platform.python_version(),
        "numpy": v("numpy"), "scipy": v("scipy"), "numba": v("numba"), "openturns": v("openturns"),
        "machine": {"platform": platform.platform(), "processor": platform.machine(), "llvm_host_cpu": cpu},
    }


def provenance() -> dict:
    """The versions of jointwear and its numerical dependencies, the machine, and the time of writing."""
    out = dict(_static_provenance())
    out["written_at"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    return out
