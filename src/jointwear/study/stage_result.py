"""The shared base of the typed stage results: JSON save and load, with unknown keys kept in ``extra``."""

from __future__ import annotations

import math
from dataclasses import MISSING, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from jointwear.study.io import check_columns, provenance, read_json, write_csv, write_json

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["StageResult", "same_value", "save_figure", "short_repr"]

_SHORT = 100  # characters of a value shown whole in a result's repr


def short_repr(value: Any) -> str:
    """A value as a result's repr shows it: whole when short, else its shape (a wear profile has 720 cells, an R(N)
    population's design points thousands, and a notebook prints the whole result)."""
    if isinstance(value, np.ndarray):
        if value.size <= 12:
            return np.array2string(value, precision=4, separator=", ", max_line_width=10**6)
        finite = value[np.isfinite(value)] if value.dtype.kind == "f" else value
        span = f", {finite.min():.4g} .. {finite.max():.4g}" if finite.size and value.dtype.kind in "fiu" else ""
        return f"<array {value.shape}{span}>"
    text = repr(value)
    if len(text) <= _SHORT:
        return text
    if isinstance(value, dict):
        keys = ", ".join(map(str, list(value)[:8])) + (", ..." if len(value) > 8 else "")
        return f"<dict of {len(value)}: {keys}>"
    if isinstance(value, (list, tuple)):
        return f"<{type(value).__name__} of {len(value)}>"
    return text[: _SHORT - 3] + "..."


def _nan_holes(value: Any) -> Any:
    """JSON's null back to NaN inside a list of floats (write_json writes NaN as null), so that numpy reads a
    loaded profile as it read the one in memory; other values unchanged."""
    if isinstance(value, dict):
        return {k: _nan_holes(v) for k, v in value.items()}
    if isinstance(value, list):
        if (None in value and any(isinstance(v, float) for v in value)
                and all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in value)):
            return [math.nan if v is None else v for v in value]
        return [_nan_holes(v) for v in value]
    return value


def same_value(a: Any, b: Any, *, rtol: float = 0.0) -> bool:
    """Equality of result values, arrays by value and NaN equal to NaN (a loaded result keeps its NaN holes);
    floats within ``rtol`` of each other count as equal (0: exactly)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if rtol and a.shape == b.shape and a.dtype.kind == b.dtype.kind == "f":
            return bool(np.allclose(a, b, rtol=rtol, atol=0.0, equal_nan=True))
        try:
            return bool(np.array_equal(a, b, equal_nan=True))
        except TypeError:  # not numbers: NaN cannot occur
            return bool(np.array_equal(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same_value(a[k], b[k], rtol=rtol) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same_value(x, y, rtol=rtol) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float):
        if math.isnan(a) and math.isnan(b):
            return True
        return a == b or abs(a - b) <= rtol * max(abs(a), abs(b))
    return bool(a == b)


class StageResult:
    """Shared save/load of the stage results: the JSON holds every field not marked ``json=False``."""

    FILE: ClassVar[str] = ""
    #: fields that record how a run went, not what it found: equality ignores them
    RUN_METADATA: ClassVar[frozenset[str]] = frozenset(
        {"wall_seconds", "wall_seconds_per_cycle", "simulation_seconds", "provenance"})
    #: groups of array fields that run along one axis (the curve's levels...): checked before anything is saved
    ALIGNED: ClassVar[tuple[tuple[str, ...], ...]] = ()
    __hash__ = None  # mutable, compared by value

    def __eq__(self, other: object) -> bool:
        """Field by field, arrays by value (the dataclass comparison raised 'the truth value of an array is
        ambiguous'). Run metadata (``RUN_METADATA``: wall times, provenance with its time of writing) and fields
        kept out of the JSON (the learning engine) are not compared, so the same curve computed twice is equal."""
        if type(other) is not type(self):
            return NotImplemented
        return all(same_value(getattr(self, f.name), getattr(other, f.name))
                   for f in fields(self) if f.metadata.get("json", True) and f.name not in self.RUN_METADATA)

    def __repr__(self) -> str:
        """One line per field, long values summarised (``short_repr``); subclasses are dataclasses with repr=False."""
        rows = [f"    {f.name}={short_repr(getattr(self, f.name))}," for f in fields(self) if f.repr]
        return "\n".join([f"{type(self).__name__}(", *rows, ")"])

    def to_json(self) -> dict:
        """The fields written to the stage's JSON file (a field with ``metadata={"json": False}`` is not)."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.metadata.get("json", True)}
        for key, value in getattr(self, "extra", {}).items():
            out.setdefault(key, value)
        return out

    @classmethod
    def from_json(cls, data: dict):
        """The result from its JSON; keys this version does not know are kept in ``extra`` (and written back)."""
        kwargs, known = {}, set()
        for f in fields(cls):
            known.add(f.name)
            if not f.metadata.get("json", True):
                continue
            if f.name in data:
                kwargs[f.name] = _nan_holes(data[f.name])
            elif f.default is MISSING and f.default_factory is MISSING:
                raise ValueError(f"{cls.FILE}: missing key '{f.name}'")
        if "extra" in known:
            kwargs["extra"] = {k: v for k, v in data.items() if k not in known}
        return cls(**kwargs)

    @classmethod
    def load(cls, folder: Path | str):
        """Read the result back from ``folder / FILE``."""
        return cls.from_json(read_json(Path(folder) / cls.FILE))

    @classmethod
    def load_if_present(cls, folder: Path | str):
        """The result in ``folder``, or None where the stage has not written it there or it cannot be read."""
        try:
            return cls.load(folder)
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def tables(self) -> dict[str, dict[str, Any]]:
        """The stage's tables by file stem (``save`` writes each as ``<stem>.csv``): equal-length columns by name,
        units in the names."""
        return {}

    def frame(self, table: str | None = None) -> pd.DataFrame:
        """One of :meth:`tables` as a pandas DataFrame (the first when ``table`` is None), as its CSV file holds it."""
        import pandas as pd

        tables = self.tables()
        if table is None and tables:
            table = next(iter(tables))
        if table not in tables:
            raise KeyError(f"{type(self).__name__} has no table {table!r}; its tables: {', '.join(tables) or 'none'}")
        return pd.DataFrame({name: np.asarray(column) for name, column in tables[table].items()})

    def check_lengths(self) -> None:
        """Raise a ValueError naming the fields of an ``ALIGNED`` group whose lengths differ (None: not held)."""
        for group in self.ALIGNED:
            lengths = {name: len(value) for name in group if (value := getattr(self, name)) is not None}
            if len(set(lengths.values())) > 1:
                listed = ", ".join(f"{name} {n}" for name, n in lengths.items())
                raise ValueError(f"{type(self).__name__}: {', '.join(lengths)} run along one axis but their lengths "
                                 f"differ ({listed}); were some of its arrays changed after it was computed?")

    def write_tables(self, folder: Path | str) -> list[str]:
        """Write every table as ``<stem>.csv`` in ``folder``; the file names. The result's arrays and every table
        are checked before any is written: a result whose arrays disagree in length writes nothing."""
        self.check_lengths()
        tables = self.tables()
        for stem, columns in tables.items():
            check_columns(f"{type(self).__name__} table '{stem}'", columns)
        return [write_csv(Path(folder) / f"{stem}.csv", columns).name for stem, columns in tables.items()]

    def write(self, folder: Path | str) -> Path:
        """Write the stage's JSON file (``FILE``) in ``folder``, with this machine's provenance when the result has
        none; its path."""
        payload = self.to_json()
        if not payload.get("provenance"):  # a result built without its machine's record gets this one's
            payload["provenance"] = provenance()
            if hasattr(self, "provenance"):  # and the result returned says what its file says
                self.provenance = payload["provenance"]
        return write_json(Path(folder) / self.FILE, payload)


def save_figure(fig, path: Path) -> None:
    """Write a figure with the project's style (PNG)."""
    from jointwear.report.style import savefig

    savefig(fig, path)
