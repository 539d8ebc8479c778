"""Random input variables: settings (validated at the config boundary) and frozen distributions.

A variable names a target field of the study config (a dotted path into the SI config, see
``jointwear.study.apply_sample``) and a distribution given by its mean and standard deviation
(SI). The clearance is special: its standard deviation comes either from the paper's Table 5 as
printed (1 nm, very likely a units slip) or from an ISO 286-2 fit, Eq. (40) (0.97 um for IT7/IT6
at 2 mm), and samples at or below a minimum clearance are handled by a named rule.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import Field, field_validator, model_validator
from scipy import stats

from jointwear.schema import SIModel
from jointwear.uncertainty.tolerances import clearance_from_fit

DistributionName = Literal["normal", "lognormal", "uniform"]


class RandomVariableSpec(SIModel):
    """One independent random input."""

    name: str = Field(description="Short identifier, e.g. 'l2'.")
    label: str = Field("", description="Readable name for reports, e.g. 'rod length'.")
    target: str = Field(description="Dotted path of the SI config field this variable sets.")
    group: Literal["tolerance", "bearing_material", "journal_material", "other"] = "other"
    distribution: DistributionName = Field("normal", description="All 13 paper variables are normal (Section 4).")
    mean: float = Field(description="Mean, SI units.")
    std: float = Field(description="Standard deviation, SI units (> 0).")
    unit: str = Field("", description="Display unit for reports (SI value x scale).")
    scale: float = Field(1.0, description="Multiply the SI value by this for display (e.g. 1e3 for mm).")

    @field_validator("mean", "std", "scale")
    @classmethod
    def _finite(cls, value: float) -> float:
        if not math.isfinite(value):
            raise ValueError("must be a finite number")
        return value

    @model_validator(mode="after")
    def _positive_std(self) -> RandomVariableSpec:
        if self.std <= 0:
            raise ValueError(f"std of variable {self.name!r} must be > 0 (got {self.std:g})")
        if self.distribution == "lognormal" and self.mean <= 0:
            raise ValueError(f"lognormal variable {self.name!r} needs a positive mean")
        return self

    def frozen(self):
        """The scipy.stats frozen distribution of this variable."""
        if self.distribution == "normal":
            return stats.norm(loc=self.mean, scale=self.std)
        if self.distribution == "lognormal":
            s2 = math.log1p((self.std / self.mean) ** 2)
            return stats.lognorm(s=math.sqrt(s2), scale=self.mean / math.sqrt(1.0 + (self.std / self.mean) ** 2))
        half = math.sqrt(3.0) * self.std
        return stats.uniform(loc=self.mean - half, scale=2.0 * half)


class ClearanceSpec(SIModel):
    """The radial clearance of the clearance joint as a random variable."""

    target: str = Field(description="Dotted path of the clearance in the SI config.")
    mean: float = Field(2e-6, description="Designed radial clearance, m (Table 2: 1.002 mm - 1 mm).")
    source: Literal["iso286", "table5"] = Field(
        "iso286",
        description="'table5': sigma as printed in Table 5 (1e-6 mm = 1 nm, very likely a units slip); "
        "'iso286': sigma_c = sqrt(T_D^2 + T_d^2)/12, Eq. (40), from the grades below.")
    nominal_diameter: float = Field(2e-3, description="Nominal fit diameter, m (journal diameter 2 mm).")
    hole_grade: str = Field("IT7", description="Bearing bore grade (usual H7 bore; ISO 286-2).")
    shaft_grade: str = Field("IT6", description="Journal grade (usual h6/g6 shaft; ISO 286-2).")
    table5_std: float = Field(1e-9, description="Table 5 as printed: 1e-6 mm.")
    minimum: float = Field(
        1e-7,
        description="Smallest clearance a sample may have, m. At or below it the fit is an interference or "
        "line-to-line fit that the clearance-joint model does not describe.")
    infeasible_rule: Literal["truncate", "fail"] = Field(
        "truncate",
        description="'truncate': the clearance distribution is truncated at `minimum` (parts that would "
        "interfere are rejected at assembly); 'fail': such samples are kept and counted as failures.")

    @property
    def std(self) -> float:
        if self.source == "table5":
            return self.table5_std
        return clearance_from_fit(self.nominal_diameter, self.hole_grade, self.shaft_grade, self.mean).std

    def frozen(self):
        """The clearance as sampled: truncated at `minimum` ('truncate'), or the full normal ('fail')."""
        if self.infeasible_rule == "truncate":
            return self.feasible()
        return stats.norm(loc=self.mean, scale=self.std)

    def feasible(self):
        """The clearance given that it exceeds `minimum`: the normal truncated there."""
        a = (self.minimum - self.mean) / self.std
        return stats.truncnorm(a=a, b=np.inf, loc=self.mean, scale=self.std)

    def infeasible_probability(self) -> float:
        """Probability that an untruncated normal clearance falls at or below `minimum`."""
        return float(stats.norm.cdf((self.minimum - self.mean) / self.std))


class UncertaintySettings(SIModel):
    """The random inputs of a study (paper Tables 5-6, with the label fix of paper-notes.md)."""

    clearance: ClearanceSpec | None = None
    variables: list[RandomVariableSpec] = Field(default_factory=list)

    @model_validator(mode="after")
    def _unique_names(self) -> UncertaintySettings:
        names = [v.name for v in self.variables] + (["c"] if self.clearance else [])
        duplicates = {n for n in names if names.count(n) > 1}
        if duplicates:
            raise ValueError(f"duplicate random variable names: {sorted(duplicates)}")
        return self

    def names(self) -> list[str]:
        return [v.name for v in self.all_specs()]

    def all_specs(self) -> list[RandomVariableSpec]:
        """Every variable as a spec, the clearance (if any) second as in Table 5."""
        specs = list(self.variables)
        if self.clearance is not None:
            c = self.clearance
            specs.insert(min(1, len(specs)), RandomVariableSpec(
                name="c", label="radial clearance", target=c.target, group="tolerance",
                mean=c.mean, std=c.std, unit="um", scale=1e6))
        return specs

    def marginals(self, feasible: bool = False) -> list:
        """Frozen scipy.stats marginals in the order of `names()` (``feasible``: the clearance conditioned on
        exceeding its minimum, whatever the rule)."""
        out = []
        for spec in self.all_specs():
            if spec.name == "c" and self.clearance is not None:
                out.append(self.clearance.feasible() if feasible else self.clearance.frozen())
            else:
                out.append(spec.frozen())
        return out
