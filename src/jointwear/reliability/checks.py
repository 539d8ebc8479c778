"""Validation of the reliability methods' numeric options, at the public entry points (messages name the
option and its allowed range)."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["check_positive", "check_positive_int"]


def check_positive_int(name: str, value: Any, minimum: int = 1) -> int:
    """``value`` as an int, or ValueError naming ``name`` when it is not an integer >= ``minimum``.

    An integral float counts (``n=1e5``, as sizes are written in the docs and papers); 1e5 + 0.5 does not."""
    integral_float = isinstance(value, (float, np.floating)) and np.isfinite(value) and float(value).is_integer()
    if isinstance(value, bool) or not (isinstance(value, (int, np.integer)) or integral_float) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def check_positive(name: str, value: Any) -> float:
    """``value`` as a float, or ValueError naming ``name`` when it is not finite and > 0."""
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite number > 0; got {value!r}")
    return v


def check_seed(value: Any) -> int | None:
    """``value`` as an int seed, None (fresh entropy), or ValueError naming ``seed``: the engines derive several
    streams from it (seed x 1000 + j), so a Generator or a string is refused rather than half-used."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ValueError(f"seed must be None or an integer >= 0; got {value!r}")
    return int(value)
