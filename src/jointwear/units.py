"""Unit suffixes of config keys, converted to SI in this one place.

A TOML key may carry a unit suffix: ``length_mm = 6``, ``speed_rpm = 480``,
``youngs_modulus_GPa = 120``, ``hardness_HB = 350``, ``angle_deg = 30``.  The
config models (``jointwear.config.SIModel``) strip the suffix and store the value
in SI under the plain name (``length`` in m, ``speed`` in rad/s, ``youngs_modulus``
in Pa, ``hardness`` in Pa, ``angle`` in rad).  A key is only treated as
``<field>_<suffix>`` when ``<field>`` is a field of the model and the whole key is
not itself a field (so ``mu_s`` stays the static friction coefficient and is never
read as "mu in seconds").

Brinell hardness: ``HB`` is converted with 9.807e6 Pa per HB (1 kgf/mm^2 =
9.80665 N/mm^2, rounded as in the project's paper notes), so that Archard's
``k / H`` has units 1/Pa with k dimensionless.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

#: Pa per Brinell hardness number (kgf/mm^2 -> Pa); baseline reading, user guide.
PA_PER_HB = 9.807e6

#: suffix -> (multiplier to SI, SI unit name). Matching is case-sensitive
#: (``mm`` is not ``Mm``); the longest matching suffix wins.
SUFFIXES: dict[str, tuple[float, str]] = {
    # length
    "m": (1.0, "m"),
    "mm": (1e-3, "m"),
    "um": (1e-6, "m"),
    "nm": (1e-9, "m"),
    "cm": (1e-2, "m"),
    # angle
    "rad": (1.0, "rad"),
    "deg": (math.pi / 180.0, "rad"),
    # angular speed
    "rad_s": (1.0, "rad/s"),
    "rpm": (2.0 * math.pi / 60.0, "rad/s"),
    "deg_s": (math.pi / 180.0, "rad/s"),
    # speed / acceleration
    "m_s": (1.0, "m/s"),
    "mm_s": (1e-3, "m/s"),
    "m_s2": (1.0, "m/s^2"),
    # mass / inertia
    "kg": (1.0, "kg"),
    "g": (1e-3, "kg"),
    "kg_m2": (1.0, "kg m^2"),
    "g_mm2": (1e-9, "kg m^2"),
    # pressure / modulus / hardness
    "Pa": (1.0, "Pa"),
    "kPa": (1e3, "Pa"),
    "MPa": (1e6, "Pa"),
    "GPa": (1e9, "Pa"),
    "HB": (PA_PER_HB, "Pa"),
    # force / torque
    "N": (1.0, "N"),
    "mN": (1e-3, "N"),
    "N_m": (1.0, "N m"),
    "mN_m": (1e-3, "N m"),
    # time
    "s": (1.0, "s"),
    "ms": (1e-3, "s"),
    "us": (1e-6, "s"),
    "h": (3600.0, "s"),
}


#: the unit of a field whose dimension is set by its context (a random variable's mean takes its target's): any
#: suffix is converted here and its dimension is checked where the context is known.
ANY_UNIT = "*"


class UnitError(ValueError):
    """A value that cannot be converted (not a number or a list of numbers), or a suffix of the wrong dimension."""


def si_suffix(unit: str) -> str | None:
    """The key suffix that names an SI unit as itself (``"Pa"`` -> ``"Pa"``, ``"rad/s"`` -> ``"rad_s"``, ``"kg m^2"``
    -> ``"kg_m2"``), for column names such as ``E_b_Pa``; ``""`` for no unit, None for a unit no suffix names."""
    if not unit:
        return ""
    return next((suffix for suffix, (scale, si) in SUFFIXES.items() if si == unit and scale == 1.0), None)


def column_name(name: str, unit: str) -> str:
    """A table column named as a config key would be: ``name_<suffix>`` of the SI unit (``HB_b_Pa``), the bare name for
    a plain number or a unit no suffix names."""
    suffix = si_suffix(unit)
    return f"{name}_{suffix}" if suffix else name


def suffix_unit(unit: str) -> str | None:
    """The suffix of :data:`SUFFIXES` a unit as written names ('mm'; 'µm' as 'um'); None for any other."""
    unit = unit.strip().replace("\u00b5", "u").replace("\u03bc", "u")
    return unit if unit in SUFFIXES else None


def suffix_factor(unit: str) -> float | None:
    """SI per ``unit`` for a unit keys take as a suffix (1e-3 for 'mm', 9.807e6 for 'HB'); None for any other."""
    suffix = suffix_unit(unit)
    return None if suffix is None else SUFFIXES[suffix][0]


def suffixes_of(unit: str) -> list[str]:
    """The suffixes that convert to the SI ``unit``, e.g. ``['m', 'mm', 'um', 'nm', 'cm']`` for 'm'."""
    return [s for s, (_, u) in SUFFIXES.items() if u == unit]


def suffix_problem(key: str, field: str, suffix: str, unit: str | None) -> str | None:
    """Why ``key`` (``<field>_<suffix>``) does not fit a field whose SI unit is ``unit`` (None: a plain number);
    None when it fits."""
    got = SUFFIXES[suffix][1]
    if unit == ANY_UNIT or unit == got:
        return None
    if unit is None:
        return f"{key}: {field} is a plain number, without a unit: write {field} = ..."
    allowed = ", ".join(f"{field}_{s}" for s in suffixes_of(unit)) or f"{field} (in {unit})"
    return f"{key}: {field} is in {unit}, and '_{suffix}' is a suffix of {got}: use {allowed}"


def split_unit_key(key: str, fields: set[str] | frozenset[str]) -> tuple[str, str] | None:
    """Return ``(field, suffix)`` if ``key`` is ``<field>_<suffix>`` for a known field and suffix.

    Returns None if ``key`` is itself a field or no split matches. The longest suffix wins.
    """
    if key in fields:
        return None
    best: tuple[str, str] | None = None
    for suffix in SUFFIXES:
        tail = "_" + suffix
        if key.endswith(tail):
            base = key[: -len(tail)]
            if base in fields and (best is None or len(suffix) > len(best[1])):
                best = (base, suffix)
    return best


def not_a_number(value: Any) -> str | None:
    """'a number is expected, not the string '0.9' ...' for a string or a boolean given as a number, else None."""
    if isinstance(value, str):
        return f"a number is expected, not the string {value!r} (write it without quotes)"
    if isinstance(value, bool):
        return f"a number is expected, not the boolean {str(value).lower()}"
    return None


def to_si(value: Any, suffix: str) -> Any:
    """Multiply a number, or a (nested) list of numbers, by the suffix's factor to SI."""
    factor = SUFFIXES[suffix][0]
    slip = not_a_number(value)
    if slip:
        raise UnitError(slip)
    if isinstance(value, numbers.Real):  # numpy scalars too (np.int64 from np.arange)
        return float(value) * factor
    if isinstance(value, (list, tuple)):
        return [to_si(v, suffix) for v in value]
    if isinstance(value, dict):  # a table of named values, e.g. allowances_mm = { A = 0.03 }
        return {k: to_si(v, suffix) for k, v in value.items()}
    raise UnitError(f"a number is expected, not {type(value).__name__} {value!r}")


def convert_keys(data: dict[str, Any], fields: set[str] | frozenset[str],
                 units: dict[str, str | None] | None = None) -> dict[str, Any]:
    """Return a copy of ``data`` with unit-suffixed keys renamed to plain fields, values in SI.

    ``units``: each field's SI unit (None: a plain number; :data:`ANY_UNIT`: set by its context); when given, a
    suffix of another dimension is an error (``width_deg`` for a length). Raises UnitError for that, if a field is
    given twice (e.g. ``length`` and ``length_mm``) or if a value cannot be converted.
    """
    out: dict[str, Any] = {}
    origin: dict[str, str] = {}
    for key, value in data.items():
        split = split_unit_key(key, fields)
        if split is None:
            name, val = key, value
        else:
            name, suffix = split
            problem = None if units is None else suffix_problem(key, name, suffix, units.get(name))
            if problem:
                raise UnitError(problem)
            try:
                val = to_si(value, suffix)
            except UnitError as exc:
                raise UnitError(f"{key}: {exc}") from None
        if name in out:
            raise UnitError(f"{name} given twice (as '{origin[name]}' and '{key}')")
        out[name] = val
        origin[name] = key
    return out


def fmt_mm(x: float) -> str:
    """Format a length in m as mm for messages."""
    return f"{x * 1e3:.6g} mm"


def scaled(value: Any, factor: float) -> Any:
    """A number, or (nested) lists and tables of them, times ``factor``; anything else (a name, a flag, an infinite
    value) as it is."""
    if isinstance(value, dict):  # a table of named values, e.g. the points of a body
        return {k: scaled(x, factor) for k, x in value.items()}
    if isinstance(value, (list, tuple)):
        return [scaled(x, factor) for x in value]
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
        return value * factor
    return value


def in_unit(value: Any, unit: str | None, target: str | None) -> Any:
    """``value`` given in ``unit`` expressed in ``target`` (suffixes of :data:`SUFFIXES` of one dimension; anything
    else as it is)."""
    if unit == target or unit not in SUFFIXES or target not in SUFFIXES or SUFFIXES[unit][1] != SUFFIXES[target][1]:
        return value
    return scaled(value, SUFFIXES[unit][0] / SUFFIXES[target][0])


def to_display(value: Any, unit: str | None) -> tuple[Any, str | None]:
    """An SI value (a number, or lists and tables of them) in the units users read: mm, GPa or MPa, HB (``unit`` =
    "HB": a hardness, entered and quoted in HB), rpm, deg; any other unit as it is."""
    if unit == "m":
        return scaled(value, 1e3), "mm"
    if unit == "Pa":
        mag = max((abs(x) for x in (value if isinstance(value, (list, tuple)) else [value])
                   if isinstance(x, (int, float))), default=0)
        return (scaled(value, 1e-9), "GPa") if mag >= 1e9 else (scaled(value, 1e-6), "MPa")
    if unit == "HB":
        return scaled(value, 1.0 / PA_PER_HB), "HB"
    if unit == "rad/s":
        return scaled(value, 60 / (2 * math.pi)), "rpm"
    if unit == "rad":
        return scaled(value, 180 / math.pi), "deg"
    return value, unit
