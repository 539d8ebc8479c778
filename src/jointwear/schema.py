"""Base of every config section: one-line errors, unit-suffixed keys converted to SI, NaN/inf rejected.

Kept apart from :mod:`jointwear.config` so that each stage can define its own section
(``wear.settings``, ``uncertainty.variables``, ``study_settings``) and ``config`` can compose them.
"""

from __future__ import annotations

import functools
import types
import typing
from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from jointwear.units import ANY_UNIT, UnitError, convert_keys, not_a_number, split_unit_key


class ConfigError(ValueError):
    """A configuration problem; ``str(err)`` is one line naming the field and the allowed range.

    ``problems`` lists every problem found (``str`` joins them with '; ').
    """

    def __init__(self, message: str, problems: list[str] | None = None):
        super().__init__(message)
        self.problems = list(problems) if problems else [message]

    @classmethod
    def from_problems(cls, problems: list[str], source: str | None = None) -> ConfigError:
        """One error listing every problem: 'source: p1; p2 [N problems]'."""
        head = f"{source}: " if source else ""
        count = f" [{len(problems)} problems]" if len(problems) > 1 else ""
        return cls(head + "; ".join(problems) + count, problems)


class FieldValueError(ValueError):
    """A bad value of one field, found by a section's own rule: ``message`` says why, and the config boundary shows
    ``value`` as the config wrote it (``std_HB = -7``, not its -6.86e7 Pa; jointwear.config.validation_problems)."""

    def __init__(self, field: str, value: float, message: str):
        super().__init__(f"{message} (got {value:g})")
        self.field, self.value, self.message = field, value, message


def F(default: Any = ..., *, unit: str | None = None, unit_of: str | None = None, description: str, **kw: Any) -> Any:
    """A pydantic Field with its SI unit recorded in the JSON schema (the config reference and the unit-suffix
    check read it). ``unit_of``: the field's unit is set by its context (e.g. "the target"), so any suffix is
    converted and checked there. A field with neither is a plain number and takes no suffix."""
    extra = {"unit": unit} if unit else ({"unit_of": unit_of} if unit_of else None)
    return Field(default, description=description, json_schema_extra=extra, **kw)


@functools.cache
def field_units(model: type[BaseModel]) -> dict[str, str | None]:
    """Each field's SI unit as :func:`F` recorded it (``ANY_UNIT`` for a unit set by the context)."""
    out = {}
    for name, info in model.model_fields.items():
        extra = info.json_schema_extra if isinstance(info.json_schema_extra, dict) else {}
        out[name] = ANY_UNIT if extra.get("unit_of") else extra.get("unit")
    return out


NUMBER_TYPES = (float, int)


@functools.cache
def number_fields(model: type[BaseModel]) -> frozenset[str]:
    """The fields that hold a number or a fixed list of numbers (``float``, ``int | None``, ``tuple[float, float]``,
    ``list[float]``): a string or a boolean there is a slip, not a number to convert."""
    def numeric(annotation: Any) -> bool:
        args = [a for a in typing.get_args(annotation) if a is not type(None) and a is not Ellipsis]
        if typing.get_origin(annotation) in (typing.Union, types.UnionType, list, tuple):
            return bool(args) and all(numeric(a) for a in args)
        return annotation in NUMBER_TYPES
    return frozenset(name for name, info in model.model_fields.items() if numeric(info.annotation))


def number_slips(model: type[BaseModel], data: dict[str, Any]) -> list[str]:
    """'key: a number is expected, not the string '0.9' ...' for each key of ``data`` (unit-suffixed or not) that
    gives a number field a string or a boolean (pydantic's lax mode would read "0.9" as 0.9 and true as 1)."""
    numbers, names = number_fields(model), frozenset(model.model_fields)
    out = []
    for key, value in data.items():
        split = split_unit_key(key, names)
        if (split[0] if split else key) in numbers:
            items = value if isinstance(value, (list, tuple)) else [value]
            slip = next(filter(None, map(not_a_number, items)), None)
            if slip:
                out.append(f"{key}: {slip}")
    return sorted(out)


def config_models(annotation: Any) -> list[type[BaseModel]]:
    """The config models an annotation holds directly or as a union (``A | B | None``)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    if typing.get_origin(annotation) in (typing.Union, types.UnionType, typing.Annotated):
        return [m for a in typing.get_args(annotation) for m in config_models(a)]
    return []


def item_key(index: int, names: Sequence[str | None]) -> str:
    """How a path names item ``index`` of a list whose items go by ``names``: by its name where no other item has it
    (``joints[B]``, as :func:`jointwear.config.updated` reads a path), else by its index (``joints[1]``). A name that
    reads as an index or holds a path's separators (``.``, ``[``, ``]``: a material 'St 37.2') goes by its index too."""
    name = names[index]
    plain = isinstance(name, str) and name and not name.lstrip("-").isdigit() and not any(c in name for c in ".[]")
    return name if plain and names.count(name) == 1 else str(index)


def walk_schema(model: type[BaseModel], keys) -> tuple[list[type[BaseModel]], str | None] | None:
    """Follow ``keys`` (a dotted target split at its dots, or a validation error's location) through the config
    schema from ``model``: the models the last key leads to and the SI unit of the last field passed; None where a
    key names no field. The key after a list or table of sections is an item's index or name; a discriminated
    union's tag is passed over; inside a point, a list or a table of numbers the field's unit holds."""
    candidates, unit, items = [model], None, None
    for key in keys:
        if items is not None:  # this key is the item's index or name
            candidates, items = items, None
            continue
        if not candidates:
            continue
        tagged = [m for m in candidates
                  if "type" in m.model_fields and key in typing.get_args(m.model_fields["type"].annotation)]
        if tagged:
            candidates = tagged
            continue
        owner = next((m for m in candidates if key in m.model_fields), None)
        if owner is None:
            return None
        annotation = owner.model_fields[key].annotation
        unit = field_units(owner)[key]
        candidates = config_models(annotation)
        if not candidates:
            items = [m for a in typing.get_args(annotation) for m in config_models(a)] or None
    return candidates, unit


def path_unit(model: type[BaseModel], path: str) -> str | None:
    """The SI unit of the config field a dotted path (a random variable's ``target``) ends in, from the schema;
    an item of a table, a list of numbers or a point has its field's unit. ``ANY_UNIT`` where the walk cannot
    follow the path (the target's own check reports that)."""
    found = walk_schema(model, path.split("."))
    return ANY_UNIT if found is None else found[1]


class SIModel(BaseModel):
    """Base of every config section: unknown keys rejected, NaN/inf rejected, unit suffixes to SI, immutable once
    validated (a changed config is a new, validated one: jointwear.config.updated)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, validate_default=True, frozen=True)

    def __setattr__(self, name: str, value: Any) -> None:
        if name in type(self).model_fields:  # pydantic's own "Instance is frozen" does not say what to do instead
            raise AttributeError(
                f"a validated config is read-only ({type(self).__name__}.{name} cannot be set): make a changed, "
                f"validated copy with jointwear.updated(config, {{'<path>.{name}': value}}), the path as `jointwear "
                "check` lists it, e.g. updated(config, {'wear.block_cycles': 500}) or "
                "updated(config, {'uncertainty.variables.HB_b.std_HB': 20})"
            )
        super().__setattr__(name, value)

    @model_validator(mode="before")
    @classmethod
    def _unit_suffixes(cls, data: Any) -> Any:
        if isinstance(data, dict):
            slips = number_slips(cls, data)
            if slips:
                raise ValueError("; ".join(slips))
            try:
                return convert_keys(data, frozenset(cls.model_fields), field_units(cls))
            except UnitError as exc:
                raise ValueError(str(exc)) from None
        return data
