"""Random input variables: settings (validated at the config boundary) and frozen distributions.

A variable names a target field of the study config (a dotted path into the SI config, see
``jointwear.study.apply_sample``) and a distribution given by its mean and standard deviation
(SI), plus bounds where the distribution needs them. A clearance (one, or one per clearance joint) is special: its
standard deviation comes either from the paper's Table 5 as printed (1 nm, very likely a units slip) or from an
ISO 286-2 fit, Eq. (40) (0.97 um for IT7/IT6 at 2 mm), and samples at or below a minimum clearance are handled by
a named rule.
Dependence between variables: ``correlation`` (a normal copula, :mod:`jointwear.uncertainty.copulas`).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import (
    Field,
    PrivateAttr,
    SerializerFunctionWrapHandler,
    ValidationError,
    field_validator,
    model_serializer,
    model_validator,
)
from scipy import optimize, special, stats

from jointwear.schema import F, FieldValueError, SIModel
from jointwear.uncertainty.copulas import check_correlation, normal_copula
from jointwear.uncertainty.tolerances import clearance_from_fit, grade_key, iso_fit, it_tolerance
from jointwear.units import suffix_factor

DistributionName = Literal["normal", "lognormal", "uniform", "truncated_normal", "weibull", "gumbel", "gamma", "beta"]

# which of the bound fields each distribution uses ("bounds": at least one of lower/upper; "both": both)
_BOUNDS = {"truncated_normal": "bounds", "beta": "both"}


def weibull_shape(cov: float) -> float:
    """Shape k of a two-parameter Weibull with coefficient of variation ``cov``:
    cov^2 = Gamma(1 + 2/k) / Gamma(1 + 1/k)^2 - 1, decreasing in k (solved by Brent's method on ln k)."""
    def excess(log_k: float) -> float:
        k = math.exp(log_k)
        return math.log(math.expm1(special.gammaln(1 + 2 / k) - 2 * special.gammaln(1 + 1 / k))) - 2 * math.log(cov)

    lo, hi = math.log(0.05), math.log(1e4)  # cov from ~1e5 down to ~1.3e-4
    if not (excess(lo) > 0 > excess(hi)):
        raise ValueError(f"a Weibull variable's std / mean must be in [1.3e-4, 1e5]; got {cov:g}")
    return math.exp(optimize.brentq(excess, lo, hi, xtol=1e-14, rtol=1e-14))


class RandomVariableSpec(SIModel):
    """One random input, given by its mean and standard deviation (SI units) and, where needed, bounds."""

    name: str = Field(description="Short identifier, e.g. 'l2'.")
    label: str = Field("", description="Readable name for reports, e.g. 'rod length'.")
    target: str = Field(description="Dotted path of the SI config field this variable sets.")
    group: Literal["tolerance", "bearing_material", "journal_material", "other"] = Field(
        "other", description="Kind of input: 'tolerance' (a dimension), 'bearing_material', 'journal_material' or "
        "'other'; uncertainty.std_scale and the sensitivity's groups go by it.")
    distribution: DistributionName = Field(
        "normal",
        description="'normal', 'lognormal' (mean > 0), 'uniform' (mean +/- sqrt(3) std), 'truncated_normal' "
        "(the normal N(mean, std) truncated to [lower, upper]; at least one bound), 'weibull' (two-parameter, "
        "mean > 0; shape from std / mean), 'gumbel' (of maxima, right-skewed), 'gamma' (mean > 0), 'beta' "
        "(on [lower, upper], both needed; shapes from mean and std). All 13 paper variables are normal "
        "(Section 4).")
    mean: float = F(unit_of="target", description="Mean (for 'truncated_normal': of the normal before "
                    "truncation).")
    std: float = F(unit_of="target", description="Standard deviation, > 0 (for 'truncated_normal': of the normal "
                   "before truncation).")
    lower: float | None = F(None, unit_of="target", description="Lower bound: 'truncated_normal' and 'beta' only.")
    upper: float | None = F(None, unit_of="target", description="Upper bound: 'truncated_normal' and 'beta' only.")
    unit: str = Field("", description="Display unit for reports (SI value x scale). A unit of the target's "
                      "quantity that keys take as a suffix (mm, um, GPa, MPa, HB, N, ...) sets scale itself.")
    scale: float = Field(1.0, description="Multiply the SI value by this for display; needed only for a unit "
                         "that is not a key suffix (a known unit sets it: 1e3 for mm).")

    @model_validator(mode="before")
    @classmethod
    def _scale_of_unit(cls, data: Any) -> Any:
        """A display unit that keys take as a suffix sets its scale (SI value x scale = value in the unit) where
        none is given (or the default 1, as a written config holds it): alone it displayed SI numbers under its
        name, a 20 mm crank as '0.02 mm'. A scale that does not convert to it is refused by the config
        (``StudyConfig``), after the unit's dimension."""
        if not isinstance(data, dict) or not isinstance(data.get("unit"), str) or data.get("scale", 1.0) != 1.0:
            return data
        factor = suffix_factor(data["unit"])
        return data if factor is None else {**data, "scale": 1.0 / factor}

    @field_validator("mean", "std", "scale")
    @classmethod
    def _finite(cls, value: float) -> float:
        if not math.isfinite(value):
            raise ValueError("must be a finite number")
        return value

    @model_validator(mode="after")
    def _parameters(self) -> RandomVariableSpec:
        name, dist = self.name, self.distribution
        if self.std <= 0:
            hint = "; leave out a setting that does not scatter (the config's value holds)" if self.std == 0 else ""
            raise FieldValueError("std", self.std, f"std of variable {name!r} must be > 0{hint}")
        if dist in ("lognormal", "weibull", "gamma") and self.mean <= 0:
            raise FieldValueError("mean", self.mean, f"{dist} variable {name!r} needs a positive mean")
        needs = _BOUNDS.get(dist)
        for field in ("lower", "upper"):
            if needs is None and getattr(self, field) is not None:
                uniform = ("; a uniform variable between a and b has mean (a + b) / 2 and std (b - a) / sqrt(12)"
                           if dist == "uniform" else "")
                raise ValueError(f"{field} of variable {name!r}: not used by the {dist!r} distribution "
                                 f"(only 'truncated_normal' and 'beta' take bounds){uniform}")
        if needs == "both" and (self.lower is None or self.upper is None):
            missing = "lower" if self.lower is None else "upper"
            raise ValueError(f"{missing} of variable {name!r}: a {dist!r} variable needs both lower and upper")
        if needs == "bounds" and self.lower is None and self.upper is None:
            raise ValueError(f"lower/upper of variable {name!r}: a {dist!r} variable needs at least one bound")
        if self.lower is not None and self.upper is not None and not self.lower < self.upper:
            raise ValueError(f"lower of variable {name!r} must be < upper (got {self.lower:g} >= {self.upper:g})")
        if dist == "truncated_normal":
            lo = -math.inf if self.lower is None else self.lower
            hi = math.inf if self.upper is None else self.upper
            if stats.norm.cdf((hi - self.mean) / self.std) - stats.norm.cdf((lo - self.mean) / self.std) < 1e-12:
                raise ValueError(f"lower/upper of variable {name!r}: [{lo:g}, {hi:g}] holds no probability of "
                                 f"N({self.mean:g}, {self.std:g})")
        if dist == "beta":
            if not self.lower < self.mean < self.upper:
                raise ValueError(f"mean of variable {name!r} must lie between lower and upper "
                                 f"({self.lower:g} < {self.mean:g} < {self.upper:g})")
            if self.std**2 >= (self.mean - self.lower) * (self.upper - self.mean):
                raise ValueError(f"std of beta variable {name!r} must be < sqrt((mean - lower) (upper - mean)) = "
                                 f"{math.sqrt((self.mean - self.lower) * (self.upper - self.mean)):g}")
        if dist == "weibull":
            weibull_shape(self.std / self.mean)
        return self

    def frozen(self):
        """The scipy.stats frozen distribution of this variable (its mean and std are ``mean`` and ``std``,
        except for 'truncated_normal', whose parent normal has them)."""
        mean, std = self.mean, self.std
        dist = self.distribution
        if dist == "normal":
            return stats.norm(loc=mean, scale=std)
        if dist == "lognormal":
            s2 = math.log1p((std / mean) ** 2)
            return stats.lognorm(s=math.sqrt(s2), scale=mean / math.sqrt(1.0 + (std / mean) ** 2))
        if dist == "uniform":
            half = math.sqrt(3.0) * std
            return stats.uniform(loc=mean - half, scale=2.0 * half)
        if dist == "truncated_normal":
            a = -np.inf if self.lower is None else (self.lower - mean) / std
            b = np.inf if self.upper is None else (self.upper - mean) / std
            return stats.truncnorm(a=a, b=b, loc=mean, scale=std)
        if dist == "weibull":
            k = weibull_shape(std / mean)
            return stats.weibull_min(c=k, scale=mean / math.exp(special.gammaln(1.0 + 1.0 / k)))
        if dist == "gumbel":
            beta = std * math.sqrt(6.0) / math.pi  # var = pi^2 beta^2 / 6
            return stats.gumbel_r(loc=mean - np.euler_gamma * beta, scale=beta)  # mean = loc + gamma_E beta
        if dist == "gamma":
            return stats.gamma(a=(mean / std) ** 2, scale=std * std / mean)
        # beta on [lower, upper] by the method of moments
        width = self.upper - self.lower
        m, v = (mean - self.lower) / width, (std / width) ** 2
        common = m * (1.0 - m) / v - 1.0
        return stats.beta(a=m * common, b=(1.0 - m) * common, loc=self.lower, scale=width)


class ClearanceSpec(SIModel):
    """The radial clearance of a clearance joint as a random variable (one table, or one per joint as
    ``[[uncertainty.clearance]]``)."""

    name: str = Field("c", description="The variable's name (in correlations, results and the design's fit); "
                      "each of several clearances needs its own, e.g. 'c_A'.")
    label: str = Field("", description="Readable name for reports; default 'radial clearance', or "
                       "'radial clearance <name>' for one of several, followed by the fit's letters when `fit` is "
                       "given.")
    target: str = Field(description="Dotted path of the clearance in the SI config, e.g. "
                        "'clearance_joints.A.clearance'.")
    mean: float | None = F(None, unit="m", description="Designed radial clearance; set by `fit` when that is given."
                           " Default: the joint's drawn clearance, bearing_radius - journal_radius.")
    fit: str | None = Field(
        None, description="The fit with its ISO 286 letters, bore/pin, e.g. 'H7/g6' (clearance fits: bores D-H on "
        "pins d-h, nominal diameters up to 120 mm). It sets hole_grade, shaft_grade and the mean (the middle of the "
        "fit's limits, ISO 286-2) at nominal_diameter; None = give them yourself.")
    source: Literal["iso286", "table5"] = Field(
        "iso286",
        description="'table5': sigma as printed in Table 5 (1e-6 mm = 1 nm, very likely a units slip); "
        "'iso286': sigma_c = sqrt(T_D^2 + T_d^2)/12, Eq. (40), from the grades below.")
    nominal_diameter: float | None = F(None, unit="m", description="Nominal fit diameter, whose ISO 286 size "
                                       "range sets the tolerances. Default: the diameter of the joint's journal, "
                                       "2 journal_radius (`check` warns when a given one sets other tolerances).")
    hole_grade: str = Field("IT7", description="Bearing bore grade (usual H7 bore; ISO 286-2); set by `fit` when "
                            "that is given.")
    shaft_grade: str = Field("IT6", description="Journal grade (usual h6/g6 shaft; ISO 286-2); set by `fit` when "
                             "that is given.")
    table5_std: float = F(1e-9, unit="m", description="Table 5 as printed: 1e-6 mm (1 nm).")
    minimum: float = F(
        1e-7, unit="m",
        description="Smallest clearance a sample may have. At or below it the fit is an interference or "
        "line-to-line fit that the clearance-joint model does not describe.")
    infeasible_rule: Literal["truncate", "fail"] = Field(
        "truncate",
        description="'truncate': the clearance distribution is truncated at `minimum` (parts that would "
        "interfere are rejected at assembly); 'fail': such samples are kept and counted as failures.")

    #: the settings a `fit` sets
    FIT_SETS: ClassVar[tuple[str, ...]] = ("mean", "hole_grade", "shaft_grade")
    _set_by_joint: dict[str, str] = PrivateAttr(default_factory=dict)

    @field_validator("hole_grade", "shaft_grade")
    @classmethod
    def _known_grade(cls, grade: str) -> str:
        it_tolerance(grade, 1e-3)  # an unknown grade is refused here, where the message can name the field
        return grade

    @model_validator(mode="after")
    def _fit_and_minimum(self) -> ClearanceSpec:
        if self.nominal_diameter is None or self.mean is None and self.fit is None:
            return self  # a study takes them from the target joint (StudyConfig); alone, `std` says to give them
        if self.source == "iso286":
            try:
                it_tolerance(self.hole_grade, self.nominal_diameter)
            except ValueError as exc:  # the grades are known (checked by field): the size is outside the tables
                raise ValueError(f"nominal_diameter: {exc}") from None
        if self.fit is not None:
            self._apply_fit()
        if not self.minimum > 0:
            raise ValueError(f"minimum of the clearance must be > 0 m (got {self.minimum:g})")
        if not self.mean > self.minimum:
            raise ValueError(f"mean of the clearance ({self.mean * 1e6:g} um) must exceed its minimum "
                             f"({self.minimum * 1e6:g} um), the smallest clearance the clearance-joint model "
                             "describes (a unit slip? mean_um, mean_mm)")
        return self

    def _apply_fit(self) -> None:
        """Set the grades and the mean from `fit`; the same values given beside it are accepted, others refused."""
        if self.source != "iso286":
            raise ValueError(f"fit {self.fit!r} sets the spread from its grades (source = 'iso286'), not from Table 5 "
                             "(source = 'table5'): give one of them")
        fit = iso_fit(self.fit, self.nominal_diameter)
        derived = {"hole_grade": fit.hole_grade, "shaft_grade": fit.shaft_grade, "mean": fit.mean_clearance}
        for name, value in derived.items():
            given = getattr(self, name)
            if name in self.model_fields_set and not (math.isclose(given, value, rel_tol=1e-9) if name == "mean"
                                                      else grade_key(given) == value):
                shown = (f"{given * 1e6:g} um" if name == "mean" else repr(given),
                         f"{value * 1e6:g} um" if name == "mean" else repr(value))
                raise ValueError(f"{name} = {shown[0]} contradicts fit {self.fit!r}, which gives {shown[1]} at "
                                 f"{self.nominal_diameter * 1e3:g} mm: give the fit, or the grades and the mean, not "
                                 "both")
            self.__dict__[name] = value  # validated once here: the config is immutable afterwards
        self.__dict__["fit"] = fit.name

    def set_by_joint(self, taken: dict[str, str]) -> None:
        """Record the settings the study took from the target joint (``{'mean': "joint B's radii"}``; the config's
        validation sets them, jointwear.config)."""
        self._set_by_joint = dict(taken)

    def derived_settings(self) -> dict[str, str]:
        """The settings that `fit` or the target joint set, each with what set it (``jointwear check`` and the report
        say so)."""
        by_fit = {} if self.fit is None else dict.fromkeys(self.FIT_SETS, f"fit {self.fit!r}")
        return {**self._set_by_joint, **by_fit}

    @model_serializer(mode="wrap")
    def _without_derived(self, handler: SerializerFunctionWrapHandler) -> dict:
        """A fit's grades and mean, and what the target joint set, are left out of the written config, so that they
        read back from the fit and the joint (and a changed nominal diameter or journal moves them)."""
        data = handler(self)
        if isinstance(data, dict):
            for name in self.derived_settings():
                data.pop(name, None)
        return data

    @property
    def std(self) -> float:
        if self.source == "table5":
            return self.table5_std
        if self.nominal_diameter is None or self.mean is None:
            raise ValueError("a clearance outside a study needs its nominal_diameter and mean (a study takes them "
                             "from the joint its target names)")
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


class CorrelationSpec(SIModel):
    """Correlation between random variables, as a normal (Gaussian) copula.

    Give either ``variables`` and ``matrix`` (the full matrix in that order) or ``pairs`` (only the
    non-zero correlations); variables not named are independent of the others."""

    variables: list[str] = Field(default_factory=list,
                                 description="Names of the correlated variables, in the order of `matrix`.")
    matrix: list[list[float]] | None = Field(
        None, description="Correlation matrix (symmetric, ones on the diagonal, positive definite) of "
        "`variables`, read as `measure`.")
    pairs: list[tuple[str, str, float]] | None = Field(
        None, description="Instead of variables/matrix: [name_a, name_b, correlation] triples.")
    measure: Literal["pearson", "spearman"] = Field(
        "pearson",
        description="'pearson': the normal copula's correlation (Pearson correlation of the normal scores; "
        "of the variables themselves when they are normal); 'spearman': rank correlation, exact for any "
        "marginals (converted by OpenTURNS).")

    @model_validator(mode="after")
    def _shape(self) -> CorrelationSpec:
        if self.pairs is not None:
            if self.matrix is not None or self.variables:
                raise ValueError("give either pairs or variables + matrix, not both")
            seen = set()
            for k, (a, b, r) in enumerate(self.pairs):
                if a == b:
                    raise ValueError(f"pairs[{k}]: a variable paired with itself ({a!r})")
                if frozenset((a, b)) in seen:
                    raise ValueError(f"pairs[{k}]: the pair ({a!r}, {b!r}) is given twice")
                seen.add(frozenset((a, b)))
                if not (math.isfinite(r) and -1.0 < r < 1.0):
                    raise ValueError(f"pairs[{k}]: the correlation must be in (-1, 1); got {r!r}")
            return self
        if self.matrix is None:
            raise ValueError("give variables + matrix, or pairs")
        if len(set(self.variables)) != len(self.variables):
            raise ValueError(f"variables: a name is repeated in {self.variables}")
        if len(self.matrix) != len(self.variables) or any(len(row) != len(self.variables) for row in self.matrix):
            raise ValueError(f"matrix must be {len(self.variables)} x {len(self.variables)}, one row "
                             "and column per name in `variables`")
        check_correlation(self.matrix, "matrix")
        return self

    def names(self) -> list[str]:
        if self.pairs is not None:
            out: list[str] = []
            for a, b, _ in self.pairs:
                out += [n for n in (a, b) if n not in out]
            return out
        return list(self.variables)

    def full_matrix(self, names: list[str]) -> np.ndarray:
        """The correlation matrix over ``names`` (identity for names not correlated here)."""
        pos = {n: i for i, n in enumerate(names)}
        r = np.eye(len(names))
        if self.pairs is not None:
            entries = [(a, b, v) for a, b, v in self.pairs]
        else:
            entries = [(a, b, self.matrix[i][j]) for i, a in enumerate(self.variables)
                       for j, b in enumerate(self.variables) if i != j]
        for a, b, v in entries:
            if a in pos and b in pos:
                r[pos[a], pos[b]] = r[pos[b], pos[a]] = v
        return r


class UncertaintySettings(SIModel):
    """The random inputs of a study (paper Tables 5-6, with the label fix of the user guide's baseline reading)."""

    clearance: ClearanceSpec | list[ClearanceSpec] | None = Field(
        None, description="The radial clearance as an ISO 286 fit: one table, or one per clearance joint "
        "([[uncertainty.clearance]], each with its own name).")
    variables: list[RandomVariableSpec] = Field(default_factory=list)
    correlation: CorrelationSpec | None = Field(
        None,
        description="Correlated variables (a normal copula; independent when absent), e.g. "
        "{ variables = ['l1', 'l2'], matrix = [[1, 0.5], [0.5, 1]] } or { pairs = [['l1', 'l2', 0.5]] }; "
        "a clearance goes by its name ('c' unless named).")
    std_scale: dict[str, float] = Field(
        default_factory=dict,
        description="Factors on the standard deviations, by variable group (tolerance, bearing_material, "
        "journal_material, other) or by variable name (a name wins over its group); e.g. "
        "{ bearing_material = 0.5 } reads a table's spreads as two standard deviations. Alternative readings of "
        "a source's scatter, without restating its variables. A clearance's spread comes from its fit grades "
        "and is not scaled.")

    @model_validator(mode="after")
    def _std_scale(self) -> UncertaintySettings:
        groups = {"tolerance", "bearing_material", "journal_material", "other"}
        names = {v.name for v in self.variables}
        for key, factor in self.std_scale.items():
            if key not in groups and key not in names:
                raise ValueError(f"std_scale.{key}: not a variable group ({', '.join(sorted(groups))}) nor a "
                                 f"variable ({', '.join(sorted(names))})")
            if not (math.isfinite(factor) and factor > 0):
                raise ValueError(f"std_scale.{key}: must be a positive number (got {factor!r})")
        for v in self.variables:  # a scaled spread must still fit its distribution (a beta's bounds, a Weibull's)
            factor = self._scale(v)
            if factor != 1.0:
                try:
                    RandomVariableSpec.model_validate({**v.model_dump(), "std": v.std * factor})
                except ValidationError as exc:
                    key = v.name if v.name in self.std_scale else v.group
                    reason = exc.errors()[0]["msg"].removeprefix("Value error, ")
                    raise ValueError(f"std_scale.{key}: scaled by {factor:g}, variable {v.name!r} is invalid: "
                                     f"{reason}") from None
        return self

    def _scale(self, spec: RandomVariableSpec) -> float:
        return float(self.std_scale.get(spec.name, self.std_scale.get(spec.group, 1.0)))

    def clearances(self) -> list[ClearanceSpec]:
        """The random clearances (none, one, or one per clearance joint)."""
        if self.clearance is None:
            return []
        return list(self.clearance) if isinstance(self.clearance, list) else [self.clearance]

    def field_of(self, name: str) -> str:
        """Where the config gives the random variable ``name``, as messages name it: 'uncertainty.variables[l2]',
        'uncertainty.clearance', or 'uncertainty.clearance[c_A]' for one of several clearances."""
        if self.clearance_named(name) is None:
            return f"uncertainty.variables[{name}]"
        return f"uncertainty.clearance[{name}]" if isinstance(self.clearance, list) else "uncertainty.clearance"

    def clearance_named(self, name: str) -> ClearanceSpec | None:
        """The random clearance called ``name`` (None when no clearance has that name)."""
        return next((c for c in self.clearances() if c.name == name), None)

    def infeasible_probability(self, replace: dict[str, ClearanceSpec] | None = None) -> float:
        """Probability that an assembly has some clearance under the 'fail' rule at or below its minimum (those are
        failures at every N): 1 - prod(1 - p_i) over the 'fail' clearances, the clearances taken as independent;
        ``replace``: clearances by name in place of the configured ones (a design's fit)."""
        keep = 1.0
        for c in self.clearances():
            c = (replace or {}).get(c.name, c)
            if c.infeasible_rule == "fail":
                keep *= 1.0 - c.infeasible_probability()
        return 1.0 - keep

    @model_validator(mode="after")
    def _unique_names(self) -> UncertaintySettings:
        clearances = [c.name for c in self.clearances()]
        if len(clearances) > 1 and len(set(clearances)) < len(clearances):
            repeated = sorted({n for n in clearances if clearances.count(n) > 1})
            parts = [c.target.split(".") for c in self.clearances()]
            hint = ", ".join(f"name = 'c_{p[1]}' for {'.'.join(p)}" for p in parts if len(p) == 3)
            raise ValueError(f"clearance: each clearance needs its own name (given twice: {repeated})"
                             + (f"; e.g. {hint}" if hint else ""))
        names = [v.name for v in self.variables] + clearances
        duplicates = {n for n in names if names.count(n) > 1}
        if duplicates:
            raise ValueError(f"duplicate random variable names: {sorted(duplicates)}")
        specs = self.all_specs()
        for i, spec in enumerate(specs):
            other = next((o for o in specs[:i] if o.target == spec.target), None)
            if other is not None:
                raise ValueError(f"the random variables '{other.name}' and '{spec.name}' both set {spec.target}")
        if self.correlation is not None:
            where = "correlation.pairs" if self.correlation.pairs is not None else "correlation.variables"
            unknown = [n for n in self.correlation.names() if n not in names]
            if unknown:
                raise ValueError(f"{where}: unknown variable(s) {unknown}; known: {names}")
            full = self.correlation.full_matrix(self.names())
            check_correlation(full, "correlation")
            failing = [c.name for c in self.clearances() if c.infeasible_rule == "fail"]
            index = {n: i for i, n in enumerate(self.names())}
            pairs = [(a, b) for i, a in enumerate(failing) for b in failing[i + 1:] if full[index[a], index[b]] != 0]
            if pairs:
                raise ValueError(f"correlation: the clearances {pairs[0][0]!r} and {pairs[0][1]!r} both count an "
                                 "assembly at or below their minimum as failed (infeasible_rule = 'fail'), so they "
                                 "cannot be correlated; use infeasible_rule = 'truncate' on one of them")
            if self.correlation.measure == "spearman":
                normal_copula(full, "spearman", "correlation")
        return self

    def names(self) -> list[str]:
        return [v.name for v in self.all_specs()]

    def all_specs(self) -> list[RandomVariableSpec]:
        """Every variable as a spec (standard deviations scaled by ``std_scale``; not the clearances'), the
        clearances (if any) second as in Table 5."""
        specs = [v if self._scale(v) == 1.0 else v.model_copy(update={"std": v.std * self._scale(v)})
                 for v in self.variables]
        several = len(self.clearances()) > 1
        at = min(1, len(specs))
        # as sampled: 'truncate' draws the normal truncated at the minimum, 'fail' the whole normal
        specs[at:at] = [RandomVariableSpec(
            name=c.name, label=c.label or ("radial clearance " + c.name if several else "radial clearance")
            + (f" ({c.fit})" if c.fit else ""),
            target=c.target, group="tolerance", mean=c.mean, std=c.std, unit="um", scale=1e6,
            **({"distribution": "truncated_normal", "lower": c.minimum} if c.infeasible_rule == "truncate" else {}))
            for c in self.clearances()]
        return specs

    def marginals(self, feasible: bool = False) -> list:
        """Frozen scipy.stats marginals in the order of `names()` (``feasible``: the clearance conditioned on
        exceeding its minimum, whatever the rule)."""
        out = []
        for spec in self.all_specs():
            clearance = self.clearance_named(spec.name)
            if clearance is not None:
                out.append(clearance.feasible() if feasible else clearance.frozen())
            else:
                out.append(spec.frozen())
        return out

    def correlation_matrix(self, names: list[str] | None = None) -> np.ndarray | None:
        """The correlation matrix (as given, in its ``measure``) over ``names`` (default ``names()``; names that
        are not variables, e.g. an extra study input, are independent), or None without correlation."""
        if self.correlation is None:
            return None
        return self.correlation.full_matrix(self.names() if names is None else list(names))

    def copula(self, names: list[str] | None = None) -> Any:
        """The inputs' copula over ``names`` (default ``names()``) as an ``openturns.NormalCopula``, or None for
        independent inputs: pass it as ``copula=`` to the reliability methods and to
        :func:`jointwear.reliability.sample`."""
        r = self.correlation_matrix(names)
        if r is None or np.array_equal(r, np.eye(r.shape[0])):
            return None
        return normal_copula(r, self.correlation.measure, "correlation")
