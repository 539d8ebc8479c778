"""Cited reference results of a study: the ``[reference]`` section of a config.

A preset that reproduces a publication carries the numbers that publication reports, each with the table,
figure or section it comes from and, optionally, the acceptance band within which the study counts as
reproducing it. The report compares with a reference only when the config declares one; a study without a
``[reference]`` gets a report about itself alone.

Example (TOML)::

    [reference]
    citation = "Jin Y. et al., Drones 2025, 9(4), 282"
    label = "Jin et al. 2025"

    [[reference.values]]
    quantity = "reliability"
    cycles = 400_000
    value = 0.739
    source = "Section 6.2.2 (text beside Fig. 21)"
    band = { absolute = 0.15, justification = "project acceptance: R within 0.15" }

Values carry a unit suffix like every config key (``value_mm``, ``value_deg``, ``value_h``); the quantity fixes
the dimension and a suffix of another dimension is an error. :data:`QUANTITIES` is the vocabulary the report
knows.
"""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import Field, model_validator

from jointwear.schema import F, SIModel
from jointwear.units import SUFFIXES, UnitError, convert_keys

__all__ = ["QUANTITIES", "AcceptanceBand", "ReferenceValue", "ReferenceData"]

Quantity = Literal[
    "nominal_max_wear", "nominal_max_wear_angle", "second_peak_depth", "second_peak_angle", "mean_max_wear",
    "reliability", "life_cycles", "life_hours", "model_calls", "sensitivity_ranking",
]

#: quantity -> (SI dimension of its value, what else it needs, what it means). Dimensions: "m", "rad", "s",
#: "" (a pure number: reliability, cycles, calls) and "ranking" (a list of variable names instead of a value).
QUANTITIES: dict[str, tuple[str, str, str]] = {
    "nominal_max_wear": ("m", "cycles", "max bearing wear depth of the nominal design after `cycles` cycles"),
    "nominal_max_wear_angle": ("rad", "", "angle on the bearing of that max wear (bearing frame)"),
    "second_peak_depth": ("m", "", "depth of the largest wear more than 90 deg from the main peak"),
    "second_peak_angle": ("rad", "", "angle of that second peak"),
    "mean_max_wear": ("m", "cycles", "mean over the random inputs of the max wear after `cycles` cycles"),
    "reliability": ("", "cycles", "reliability R(N) after `cycles` cycles"),
    "life_cycles": ("", "target_reliability", "cycles at which R falls to `target_reliability`"),
    "life_hours": ("s", "target_reliability", "the same life in operating time (value_h)"),
    "model_calls": ("", "", "true-model calls of the reliability analysis"),
    "sensitivity_ranking": ("ranking", "group", "variable names of one group, most influential first"),
}

#: the unit each dimension is shown in, and the factor from SI
DISPLAY = {"m": ("mm", 1e3), "rad": ("deg", 180.0 / math.pi), "s": ("h", 1.0 / 3600.0), "": ("", 1.0)}

_NUMERIC_KEYS = ("value", "absolute", "lower", "upper")


def in_report_unit(x: float | None, dimension: str) -> tuple[float | None, str]:
    """An SI number of ``dimension`` in its report unit (``DISPLAY``): (value, unit); 12 digits kept, so that no
    0.029000000000000005 reaches a listing or the JSON."""
    unit, f = DISPLAY.get(dimension, ("", 1.0))
    return (None if x is None else float(f"{x * f:.12g}")), unit


def _suffix_dimension(key: str, base: str) -> str | None:
    """SI dimension of ``base_<suffix>`` ("" for the plain key), None if ``key`` is not ``base`` + a suffix."""
    if key == base:
        return None
    if key.startswith(base + "_") and key[len(base) + 1:] in SUFFIXES:
        return SUFFIXES[key[len(base) + 1:]][1]
    return None


def _check_suffixes(data: dict, dimension: str, where: str) -> None:
    """A unit suffix must match the quantity's dimension: ``value_deg`` for a wear depth is an error."""
    for key in data:
        for base in _NUMERIC_KEYS:
            dim = _suffix_dimension(key, base)
            if dim is None:
                continue
            want = {"m": "m", "rad": "rad", "s": "s"}.get(dimension)
            if want is None or dim != want:
                allowed = {"m": "_mm, _um or _m", "rad": "_deg or _rad", "s": "_h or _s"}.get(
                    dimension, "no unit suffix (a plain number)")
                what = {"m": "a length", "rad": "an angle", "s": "a time"}.get(dimension, "a plain number")
                raise ValueError(f"{where}{key}: the quantity is {what}: "
                                 f"use {base} with {allowed}")


class AcceptanceBand(SIModel):
    """Within what a study's number counts as reproducing the reference's: one kind per band.

    ``absolute``: |ours - reference| <= absolute (angles: the shorter way round the circle); ``relative``:
    |ours - reference| <= relative x |reference|; ``lower`` / ``upper``: ours inside [lower, upper] (either may be
    left open); ``same_order``: a sensitivity ranking in the same order (a different order is reported, never a
    failure: the surrogate's error often cannot separate neighbours). Values in SI, or with a unit suffix
    (``absolute_deg``, ``lower_mm``).
    """

    absolute: float | None = F(None, gt=0, unit_of="quantity",
                               description="Largest absolute difference (SI, or with a unit suffix).")
    relative: float | None = Field(None, gt=0, description="Largest relative difference, a fraction (0.15 = 15 %).")
    lower: float | None = F(None, unit_of="quantity",
                            description="Smallest accepted value (SI, or with a unit suffix).")
    upper: float | None = F(None, unit_of="quantity",
                            description="Largest accepted value (SI, or with a unit suffix).")
    same_order: bool = Field(False, description="Rankings only: the same order as the reference.")
    justification: str = Field(min_length=1, description="Why this band (required): where the tolerance comes from.")

    @model_validator(mode="after")
    def _one_kind(self) -> AcceptanceBand:
        kinds = [k for k, on in (("absolute", self.absolute is not None), ("relative", self.relative is not None),
                                 ("lower/upper", self.lower is not None or self.upper is not None),
                                 ("same_order", self.same_order)) if on]
        if len(kinds) != 1:
            raise ValueError("give exactly one kind of band: absolute, relative, lower/upper or same_order "
                             f"(got {', '.join(kinds) or 'none'})")
        if self.lower is not None and self.upper is not None and not self.lower < self.upper:
            raise ValueError(f"lower ({self.lower:g}) must be smaller than upper ({self.upper:g}), SI units")
        return self

    @property
    def kind(self) -> str:
        if self.absolute is not None:
            return "absolute"
        if self.relative is not None:
            return "relative"
        return "same_order" if self.same_order else "interval"


class ReferenceValue(SIModel):
    """One number (or ranking) that the reference reports, with where it comes from."""

    quantity: Quantity = Field(description="What the number is; one of QUANTITIES (the report's vocabulary).")
    value: float | None = F(
        None, unit_of="quantity",
        description="The reported value, SI or with a unit suffix matching the quantity (value_mm, "
        "value_deg, value_h; reliability, cycles and calls are plain numbers).")
    ranking: list[str] | None = Field(
        None, description="sensitivity_ranking only: variable names ([[uncertainty.variables]] name, a "
        "clearance's name: 'c' unless named), most influential first.")
    group: str | None = Field(
        None, description="sensitivity_ranking only: the variables' group (tolerance, bearing_material, ...).")
    cycles: int | None = Field(None, gt=0, description="Cycle count N of an 'at N cycles' quantity.")
    target_reliability: float | None = Field(
        None, gt=0, lt=1, description="life_cycles / life_hours: the reliability the life is taken at.")
    source: str = Field(min_length=1, description="Table, figure or section of the publication (required).")
    note: str = Field("", description="How the number was read (typos fixed, values read off a figure, ...).")
    band: AcceptanceBand | None = Field(None, description="Acceptance band; none: the number is only reported.")

    @model_validator(mode="before")
    @classmethod
    def _unit_suffixes(cls, data: Any) -> Any:
        # replaces SIModel's converter so that a suffix of the wrong dimension is caught before conversion
        if not isinstance(data, dict):
            return data
        q = data.get("quantity")
        if q in QUANTITIES:
            dim = QUANTITIES[q][0]
            _check_suffixes(data, dim, "")
            if isinstance(data.get("band"), dict):
                _check_suffixes(data["band"], dim, "band.")
        try:
            return convert_keys(data, frozenset(cls.model_fields))
        except UnitError as exc:
            raise ValueError(str(exc)) from None

    @model_validator(mode="after")
    def _complete(self) -> ReferenceValue:
        dim, needs, _ = QUANTITIES[self.quantity]
        if dim == "ranking":
            if not self.ranking or not self.group:
                raise ValueError("sensitivity_ranking needs `ranking` (variable names) and `group`")
            if self.value is not None:
                raise ValueError("sensitivity_ranking takes `ranking`, not `value`")
            if self.band is not None and self.band.kind != "same_order":
                raise ValueError("a ranking's band can only be `same_order = true`")
        else:
            if self.value is None:
                raise ValueError(f"{self.quantity} needs a `value`")
            if self.ranking is not None:
                raise ValueError(f"`ranking` is for sensitivity_ranking, not {self.quantity}")
            if self.band is not None and self.band.kind == "same_order":
                raise ValueError("`same_order` is a band for rankings only")
        if needs == "cycles" and self.cycles is None:
            raise ValueError(f"{self.quantity} needs `cycles` (the N it is reported at)")
        if needs == "target_reliability" and self.target_reliability is None:
            raise ValueError(f"{self.quantity} needs `target_reliability`")
        return self

    @property
    def dimension(self) -> str:
        return QUANTITIES[self.quantity][0]

    def report_dict(self) -> dict:
        """The value and band in report units (mm, deg, h), as plain data for the settings JSON."""
        unit = in_report_unit(None, self.dimension)[1]

        def shown(x):
            return in_report_unit(x, self.dimension)[0]

        out: dict[str, Any] = {
            "quantity": self.quantity, "value": shown(self.value), "unit": unit, "cycles": self.cycles,
            "target_reliability": self.target_reliability, "group": self.group, "ranking": self.ranking,
            "source": self.source, "note": self.note, "band": None,
        }
        if self.band is not None:
            b = self.band
            out["band"] = {"kind": b.kind, "absolute": shown(b.absolute), "relative": b.relative,
                           "lower": shown(b.lower), "upper": shown(b.upper), "justification": b.justification}
        return out


class ReferenceData(SIModel):
    """Results of a publication that the study reproduces (``[reference]``), each value cited."""

    citation: str = Field(min_length=1, description="Full citation of the publication the values come from.")
    label: str = Field(
        "reference", min_length=1,
        description="Short name on figures and in tables, e.g. 'Jin et al. 2025'. Default 'reference'.")
    note: str = Field("", description="Anything a reader needs about how the values were read.")
    values: list[ReferenceValue] = Field(min_length=1, description="The reported values ([[reference.values]]).")

    def report_dict(self) -> dict:
        """Plain data for the settings JSON (key ``reference``): values and bands in report units."""
        return {"citation": self.citation, "label": self.label, "note": self.note,
                "values": [v.report_dict() for v in self.values]}

    def series(self, quantity: str) -> dict[int, float]:
        """{cycles: value in report units} of an 'at N cycles' quantity, for the figures' reference points
        (``reliability``, ``mean_max_wear`` in mm, ``nominal_max_wear`` in mm); empty when not declared."""
        return {int(v.cycles): v.report_dict()["value"] for v in self.values
                if v.quantity == quantity and v.cycles is not None}

    def life(self, target_reliability: float) -> float | None:
        """The reference's life (cycles) at ``target_reliability``, or None."""
        return next((v.value for v in self.values if v.quantity == "life_cycles"
                     and v.target_reliability is not None and abs(v.target_reliability - target_reliability) < 1e-12),
                    None)
