"""Base of every config section: one-line errors, unit-suffixed keys converted to SI, NaN/inf rejected.

Kept apart from :mod:`jointwear.config` so that each stage can define its own section
(``wear.settings``, ``uncertainty.variables``, ``study_settings``) and ``config`` can compose them.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from jointwear.units import UnitError, convert_keys


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


def F(default: Any = ..., *, unit: str | None = None, description: str, **kw: Any) -> Any:
    """A pydantic Field with a unit recorded in the JSON schema (used by the config reference)."""
    extra = {"unit": unit} if unit else None
    return Field(default, description=description, json_schema_extra=extra, **kw)


class SIModel(BaseModel):
    """Base of every config section: unknown keys rejected, NaN/inf rejected, unit suffixes to SI, immutable once
    validated (a changed config is a new, validated one: jointwear.config.updated)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, validate_default=True, frozen=True)

    @model_validator(mode="before")
    @classmethod
    def _unit_suffixes(cls, data: Any) -> Any:
        if isinstance(data, dict):
            try:
                return convert_keys(data, frozenset(cls.model_fields))
            except UnitError as exc:
                raise ValueError(str(exc)) from None
        return data
