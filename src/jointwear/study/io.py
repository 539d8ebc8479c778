"""Writing results: strict JSON (no NaN or Infinity: null, with the reason beside it), CSV tables, provenance."""

from __future__ import annotations

import csv
import datetime as _dt
import io
import json
import math
import numbers
import os
import platform
import re
import secrets
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


def write_bytes_atomic(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file renamed over it: a process killed while writing leaves
    the old file or the new one, never half of one (a study's records are read back on resume). The temporary file
    is created anew under a random name (O_EXCL, permissions from the umask as for any new file) and the rename
    replaces a link at ``path``: a symlink planted in a received folder is never written through."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f"{path.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def write_text_atomic(path: Path, text: str) -> Path:
    """Write ``text`` (UTF-8, newlines as given) to ``path`` as :func:`write_bytes_atomic` does."""
    return write_bytes_atomic(path, text.encode("utf-8"))


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


#: first characters that make a spreadsheet read a text cell as a formula (OWASP, "CSV injection")
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")


def csv_cell(value: Any) -> Any:
    """One CSV cell: a float in 10 significant digits, None empty, a number as it is, and a text whose first
    character a spreadsheet reads as a formula (``= + - @``, tab, carriage return) prefixed with a single quote,
    the standard neutralisation (a variable named ``=HYPERLINK(...)`` is written ``'=HYPERLINK(...)``). Only text
    is changed: a negative number, or a text that reads as one (``-1.5``), stays a number."""
    if value is None:
        return ""
    if isinstance(value, (float, np.floating)):
        return f"{value:.10g}"
    if isinstance(value, (bool, np.bool_, numbers.Number)):
        return value
    text = str(value)
    if text.startswith(FORMULA_STARTS):
        try:
            float(text)
        except ValueError:
            return "'" + text
    return text


def check_columns(table: str, columns: Mapping[str, Sequence]) -> None:
    """Raise a ValueError naming ``table`` and its columns' lengths when they differ (a CSV row per index would
    otherwise be cut at the shortest column without a word)."""
    lengths = {name: len(column) for name, column in columns.items()}
    if len(set(lengths.values())) > 1:
        listed = ", ".join(f"{name} {n}" for name, n in lengths.items())
        raise ValueError(f"{table}: columns of different lengths ({listed}); were some of its arrays changed after "
                         "it was computed?")


def write_csv(path: Path, columns: Mapping[str, Sequence]) -> Path:
    """Write equal-length columns as a CSV table (header = the column names, units in the names); every cell as
    :func:`csv_cell` writes it (text that a spreadsheet would run as a formula is neutralised)."""
    check_columns(Path(path).name, columns)
    names = list(columns)
    cols = [list(columns[n]) for n in names]
    buf = io.StringIO(newline="")
    w = csv.writer(buf)
    w.writerow([csv_cell(n) for n in names])
    for row in zip(*cols):
        w.writerow([csv_cell(v) for v in row])
    return write_text_atomic(path, buf.getvalue())


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
        "machine": {"platform": platform.platform(), "processor": platform.machine(), "llvm_host_cpu": cpu,
                    "cpus": os.cpu_count()},
    }


def provenance() -> dict:
    """The versions of jointwear and its numerical dependencies, the machine, and the time of writing."""
    out = dict(_static_provenance())
    out["written_at"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    return out
