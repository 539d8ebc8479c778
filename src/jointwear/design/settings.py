"""The ``[design]`` config section: the controls a designer can buy, what they cost, and the target.

A control is one decision with a few options: the ISO 286 grade of a toleranced length, the fit of a clearance
joint, the specification class of a material property (its mean and spread, or acceptance limits that truncate
its distribution), or a whole candidate material (a set of property classes bought together). One option of
every control makes a candidate design; the design stage finds the cheapest candidate whose life at the target
reliability reaches the target life (:mod:`jointwear.design.search`).

Cross-references to the ``[uncertainty]`` section (a control's variable must be a random variable there) are
checked by :func:`jointwear.design.checks.design_problems`, which needs the whole config.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

from pydantic import Field, field_validator, model_validator

from jointwear.schema import F, SIModel
from jointwear.study_settings import MAX_MC_SAMPLES
from jointwear.uncertainty.tolerances import IT_GRADES, grade_key, iso_fit, it_tolerance

#: largest population per candidate, as reliability.n_mc
MAX_POPULATION = MAX_MC_SAMPLES
#: most combinations enumerated: each costs a Monte Carlo estimate of its R(N*) on the surrogate
MAX_CANDIDATES = 10_000_000

if TYPE_CHECKING:
    from jointwear.uncertainty.variables import ClearanceSpec, UncertaintySettings


def _grade_name(grade: str) -> str:
    """:func:`~jointwear.uncertainty.tolerances.grade_key`; raises ValueError naming the known grades."""
    key = grade_key(grade)
    it_tolerance(key, 1e-3)  # raises for an unknown grade
    return key


class CostModel(SIModel):
    """Relative manufacturing cost of a tolerance T (a grade's ISO 286-1 tolerance at the nominal size).

    ``reciprocal_power``: C(T) = a + b (T / T_ref)^-k, the reciprocal-power tolerance-cost model (Sutherland &
    Roth 1975; one of the models compared by Chase & Greenwood 1988, Manufacturing Review 1(1):50-59; k = 1 is
    the plain reciprocal model). ``exponential``: C(T) = a + b exp(-k (T / T_ref - 1)), the exponential model of
    Speckhart 1972 (J. Eng. Ind. 94(2):447-453) written relative to T_ref. T_ref is the tolerance of the loosest
    grade a control lists, so that grade costs a + b. The coefficients depend on the process; the defaults
    (a = 0, b = 1, k = 1) give costs relative to the loosest grade, to be replaced by a shop's own fit.
    """

    model: Literal["reciprocal_power", "exponential"] = Field(
        "reciprocal_power", description="Tolerance-cost relation (Chase & Greenwood 1988 compare both).")
    a: float = Field(0.0, description="Fixed cost per dimension (set-up), relative units (>= 0).")
    b: float = Field(1.0, description="Cost scale at the reference tolerance, relative units (> 0).")
    k: float = Field(1.0, description="Exponent (reciprocal power) or rate (exponential), > 0.")
    reference_grade: str | None = Field(
        None, description="ISO 286 grade whose tolerance is T_ref (it costs a + b) for every toleranced length, e.g. "
        "'IT11'. None: each control's loosest listed grade, so that a grade's cost changes with the grades listed "
        "beside it, while fit and material costs are absolute.")

    @field_validator("reference_grade")
    @classmethod
    def _known_grade(cls, grade: str | None) -> str | None:
        if grade is not None:
            it_tolerance(grade, 1e-3)  # an unknown grade is refused here, where the message names the field
        return grade

    @model_validator(mode="after")
    def _ranges(self) -> CostModel:
        if self.a < 0:
            raise ValueError(f"a must be >= 0 (got {self.a:g})")
        if self.b <= 0:
            raise ValueError(f"b must be > 0 (got {self.b:g})")
        if self.k <= 0:
            raise ValueError(f"k must be > 0 (got {self.k:g})")
        return self


class ToleranceControl(SIModel):
    """The ISO 286 grade of one toleranced length (a random variable of ``[uncertainty]``): sigma = IT / 6."""

    variable: str = Field(description="Name of the random variable (a length, e.g. 'l2').")
    grades: list[str] = Field(description="Candidate ISO 286-1 grades, e.g. ['IT9', 'IT10', 'IT11'].")
    nominal: float | None = F(None, unit="m", description="Nominal size for the IT table; None = the "
                              "variable's mean.")
    costs: list[float] | None = Field(
        None, description="Relative cost of each grade (same order); None = the [design.cost_model] relation. A "
        "tighter grade may not cost less than a looser one (equal costs are accepted).")

    @field_validator("grades")
    @classmethod
    def _grades(cls, grades: list[str]) -> list[str]:
        if not grades:
            raise ValueError("give at least one grade")
        names = [grade_key(g) for g in grades]
        unknown = [g for g, name in zip(grades, names) if name not in IT_GRADES]
        if unknown:
            raise ValueError(f"unknown ISO 286 tolerance grades {unknown}; known: {', '.join(IT_GRADES)} (the table "
                             "covers nominal sizes up to 120 mm)")
        if len(set(names)) != len(names):
            raise ValueError(f"grades given twice: {names}")
        return names

    @model_validator(mode="after")
    def _costs(self) -> ToleranceControl:
        if self.costs is not None:
            if len(self.costs) != len(self.grades):
                raise ValueError(f"costs: {len(self.costs)} costs for {len(self.grades)} grades")
            negative = [f"{g} costs {c:g}" for g, c in zip(self.grades, self.costs) if c < 0]
            if negative:
                raise ValueError(f"costs: {', '.join(negative)}, must be >= 0")
            inverted = _inverted(list(zip(self.grades, self.costs)), lambda g, h: _rank(g) < _rank(h))
            if inverted:
                raise ValueError(f"costs: a tighter grade costs less than a looser one ({inverted}), which no "
                                 "tolerance-cost relation gives (costs listed in another order than the grades?); "
                                 "give a tighter grade a cost at least the looser one's")
        if self.nominal is not None and not self.nominal > 0:
            raise ValueError(f"nominal must be > 0 m (got {self.nominal:g})")
        return self


class FitOption(SIModel):
    """One fit of the clearance joint and its cost: its ISO 286 letters (``fit = "H8/f7"``, which set both grades and
    the mean clearance at the clearance's nominal diameter), or its two grades (sigma_c from ISO 286-2, Eq. 40)."""

    name: str | None = Field(None, description="Label; default the fit's letters, e.g. 'H7/g6'.")
    fit: str | None = Field(None, description="The fit with its ISO 286 letters, bore/pin, e.g. 'H8/f7': sets the "
                            "grades and the mean clearance (the middle of the fit's limits) at the clearance's nominal "
                            "diameter. None = give hole_grade and shaft_grade.")
    hole_grade: str | None = Field(None, description="Bore grade, e.g. 'IT7' (without `fit`).")
    shaft_grade: str | None = Field(None, description="Pin grade, e.g. 'IT6' (without `fit`).")
    mean: float | None = F(None, unit="m", description="Designed mean radial clearance, without `fit`; None = the "
                           "study's.")
    cost: float = Field(description="Relative cost (user-given; >= 0). Of two fits given by their grades with the "
                        "same mean, the tighter (neither grade looser) may not cost less.")

    @field_validator("hole_grade", "shaft_grade")
    @classmethod
    def _grade(cls, grade: str | None) -> str | None:
        return None if grade is None else _grade_name(grade)

    @model_validator(mode="after")
    def _check(self) -> FitOption:
        if self.cost < 0:
            raise ValueError(f"cost must be >= 0 (got {self.cost:g})")
        if self.mean is not None and not self.mean > 0:
            raise ValueError(f"mean must be > 0 m (got {self.mean:g})")
        if self.fit is not None:
            fit = iso_fit(self.fit, 1e-3)  # the letters checked here, the size by design.checks
            # grades that agree with the letters are accepted, as [uncertainty.clearance] accepts them
            given = [k for k in ("hole_grade", "shaft_grade") if getattr(self, k) not in (None, getattr(fit, k))]
            given += ["mean"] if self.mean is not None else []  # it follows from the letters at the joint's size
            if given:
                raise ValueError(f"fit {self.fit!r} sets {', '.join(given)}: give the fit, or the grades (and the "
                                 "mean), not both")
            self.__dict__["fit"] = fit.name
        elif self.hole_grade is None or self.shaft_grade is None:
            raise ValueError("give the fit's letters (fit = 'H7/g6') or both hole_grade and shaft_grade")
        if self.name is None:
            self.__dict__["name"] = self.fit or f"{self.hole_grade}/{self.shaft_grade}"
        return self

    def applied_to(self, clearance: ClearanceSpec) -> ClearanceSpec:
        """The study's random clearance under this fit (validated as a config's clearance is)."""
        from jointwear.uncertainty.variables import ClearanceSpec

        data = clearance.model_dump()
        for derived in ClearanceSpec.FIT_SETS:
            data.pop(derived, None)
        data["source"] = "iso286"
        if self.fit is not None:
            data["fit"] = self.fit
        else:
            data.update(fit=None, hole_grade=self.hole_grade, shaft_grade=self.shaft_grade,
                        mean=self.mean if self.mean is not None else clearance.mean)
        return ClearanceSpec.model_validate(data)


class FitControl(SIModel):
    """The fit of one of the study's random clearances (``[uncertainty.clearance]``)."""

    variable: str | None = Field(None, description="Name of the clearance this fit sets; None = the study's only "
                                 "random clearance.")
    options: list[FitOption] = Field(description="Candidate fits.")

    def clearance(self, uncertainty: UncertaintySettings | None) -> ClearanceSpec | None:
        """The random clearance this fit sets (None when there is none to set: see design.checks)."""
        clearances = [] if uncertainty is None else uncertainty.clearances()
        if self.variable is None:
            return clearances[0] if len(clearances) == 1 else None
        return next((c for c in clearances if c.name == self.variable), None)

    @field_validator("options")
    @classmethod
    def _some(cls, options: list[FitOption]) -> list[FitOption]:
        if not options:
            raise ValueError("give at least one fit")
        _unique([o.name for o in options])
        # fits by their letters move the mean clearance with the grades, so only fits by grades with one mean compare
        graded = [(o, o.cost) for o in options if o.fit is None]
        inverted = _inverted(graded, _tighter_fit)
        if inverted:
            raise ValueError(f"cost: a fit tighter in its grades (with the same mean) costs less than a looser one "
                             f"({inverted}); give the tighter fit a cost at least the looser one's")
        return options


class PropertySpec(SIModel):
    """A specification of one random material property: its mean and standard deviation (None = the study's)
    and optional acceptance limits that truncate the (normal) distribution (parts outside are rejected)."""

    mean: float | None = F(None, unit_of="variable", description="Mean; None = the study's. Entered with a key "
                           "suffix of its variable's quantity (mean_HB, mean_GPa, ...) or in SI.")
    std: float | None = F(None, unit_of="variable", description="Standard deviation (> 0); None = the study's. "
                          "Entered as `mean` is (std_HB, ...).")
    lower: float | None = F(None, unit_of="variable", description="Lower acceptance limit (truncates the "
                            "distribution).")
    upper: float | None = F(None, unit_of="variable", description="Upper acceptance limit (truncates the "
                            "distribution).")

    @model_validator(mode="after")
    def _check(self) -> PropertySpec:
        if self.std is not None and not self.std > 0:
            raise ValueError(f"std must be > 0 (got {self.std:g})")
        if self.lower is not None and self.upper is not None and not self.lower < self.upper:
            raise ValueError(f"need lower < upper (got {self.lower:g}, {self.upper:g})")
        return self


class PropertyClass(PropertySpec):
    """One specification class of a property, with its relative cost."""

    name: str = Field(description="Label, e.g. 'standard', 'screened'.")
    cost: float = Field(description="Relative cost (user-given; >= 0).")

    @field_validator("cost")
    @classmethod
    def _cost(cls, cost: float) -> float:
        if cost < 0:
            raise ValueError("must be >= 0")  # the config boundary adds the value as written ("(got -1.0)")
        return cost


class PropertyControl(SIModel):
    """The specification class of one material property (a random variable, e.g. 'HB_b' or 'k_b')."""

    variable: str = Field(description="Name of the random variable.")
    classes: list[PropertyClass] = Field(description="Candidate specification classes.")

    @field_validator("classes")
    @classmethod
    def _some(cls, classes: list[PropertyClass]) -> list[PropertyClass]:
        if not classes:
            raise ValueError("give at least one class")
        _unique([c.name for c in classes])
        return classes


class MaterialOption(SIModel):
    """A candidate material: the specifications of several properties bought together, with its cost."""

    name: str = Field(description="Label, e.g. 'Ti-6Al-4V'.")
    cost: float = Field(description="Relative cost (user-given; >= 0).")
    variables: dict[str, PropertySpec] = Field(
        description="Property specifications by random-variable name, e.g. { HB_b = { mean_HB = 380, std_HB = 20 } }.")

    @model_validator(mode="after")
    def _check(self) -> MaterialOption:
        if self.cost < 0:
            raise ValueError(f"cost must be >= 0 (got {self.cost:g})")
        if not self.variables:
            raise ValueError("variables: give at least one property")
        return self


class MaterialControl(SIModel):
    """A choice between candidate materials of one part."""

    name: str = Field(description="The part, e.g. 'bearing'.")
    options: list[MaterialOption] = Field(description="Candidate materials.")

    @field_validator("options")
    @classmethod
    def _some(cls, options: list[MaterialOption]) -> list[MaterialOption]:
        if not options:
            raise ValueError("give at least one material")
        _unique([o.name for o in options])
        return options


class DesignTarget(SIModel):
    """A target: the life N* to reach at reliability R* (absolute, or a factor of the study's life at R*)."""

    reliability: float = Field(description="Target reliability R*, in (0, 1).")
    life_cycles: float | None = Field(None, description="Target life N*, cycles.")
    life_factor: float | None = Field(
        None, description="Target life as a multiple of the study's life at R* (e.g. 1.2: 20 % above today's).")

    @model_validator(mode="after")
    def _check(self) -> DesignTarget:
        if not 0 < self.reliability < 1:
            raise ValueError(f"reliability must be in (0, 1) (got {self.reliability:g})")
        if (self.life_cycles is None) == (self.life_factor is None):
            raise ValueError("give exactly one of life_cycles and life_factor")
        for name in ("life_cycles", "life_factor"):
            v = getattr(self, name)
            if v is not None and not v > 0:
                raise ValueError(f"{name} must be > 0 (got {v:g})")
        return self


class DesignSettings(SIModel):
    """Uncertainty control: the cheapest controls that reach a target life at a target reliability."""

    targets: list[DesignTarget] = Field(description="Targets (the first is the headline; several allowed).")
    tolerances: list[ToleranceControl] = Field(default_factory=list, description="Grades of toleranced lengths.")
    fit: FitControl | list[FitControl] | None = Field(
        None, description="Fits of a clearance joint, or of several ([[design.fit]], each naming its `variable`).")
    properties: list[PropertyControl] = Field(default_factory=list, description="Material property classes.")
    materials: list[MaterialControl] = Field(default_factory=list, description="Candidate materials.")
    cost_model: CostModel = Field(default_factory=CostModel, description="Tolerance-cost relation for grades.")
    n_population: int = Field(
        50_000, le=MAX_POPULATION,
        description="Monte Carlo population per candidate on the surrogate (common random numbers: the "
        "same standard-normal draws for every candidate, so candidates differ only by their distributions). At most "
        "1e8, as reliability.n_mc (8 bytes per random variable per sample).")
    max_candidates: int = Field(
        100_000, le=MAX_CANDIDATES,
        description="Largest number of combinations enumerated; at most 1e7 (each is a Monte Carlo estimate over "
        "n_population samples).")
    refine_max_calls: int = Field(
        40, description="Budget of refinement points, each a true-model call where the surrogate must be refined for a "
        "candidate (a point the evaluation store already holds counts too).")
    batch_size: int = Field(2, description="Refinement points per iteration (run in parallel).")
    verify: bool = Field(True, description="Verify the chosen design with its own reliability study.")
    verification_max_calls: int = Field(80, description="Budget of true-model calls of a verification study (all "
                                        "of them together: verification_total_max_calls).")
    verification_stopping: Literal["u", "error"] = Field(
        "u", description="Learning stop of the verification study: 'u' (the paper's rule, min U >= 2, else the "
        "budget) keeps learning near the limit state at N*; 'error' stops once the ESC error bound is below the "
        "study's tolerance, which a Kriging fitted on its initial design alone can meet too early (project choice).")
    require: Literal["not_refuted", "proven"] = Field(
        "not_refuted", description="The decision rule for the headline choice. 'not_refuted': the cheapest candidate "
        "that meets the target on the surrogate and that its verification does not refute (a verdict 'within_error' "
        "stands, told as not proven). 'proven': the cheapest candidate whose verification meets the target beyond its "
        "error bound; a verdict 'within_error' passes to the next point of the Pareto front, each verified in turn "
        "within verification_total_max_calls, and no such candidate leaves no choice (docs/design.md, 'Requiring a "
        "proven choice').")
    verification_total_max_calls: int | None = Field(
        None, description="Budget of true-model calls of all the verifications together (each at most "
        "verification_max_calls). None = verification_max_calls under require = 'not_refuted' (the rounds after a "
        "refuted choice share it), 3 x verification_max_calls under require = 'proven' (up to three front points "
        "on a model whose verification runs to its budget).")
    verify_every_target: bool = Field(
        True, description="With several targets: verify the cheapest design that meets them all at once "
        "(chosen_every_target, what a drawing needs) with its own reliability study at every target's N*, on a budget "
        "of verification_max_calls of its own (the headline choice's verification checks the first target only).")
    seed: int = Field(0, description="Seed of the candidates' population and the refinement.")

    @field_validator("targets")
    @classmethod
    def _targets(cls, targets: list[DesignTarget]) -> list[DesignTarget]:
        if not targets:
            raise ValueError("give at least one target")
        return targets

    @field_validator("n_population")
    @classmethod
    def _population(cls, value: int) -> int:
        if value < MIN_POPULATION:
            raise ValueError(f"must be >= {MIN_POPULATION:,} (got {value:,}): a candidate's R(N*) is the share of its "
                             "population that survives, and fewer samples cannot tell a reliability of 0.9 from 0.95")
        return value

    @field_validator("max_candidates", "batch_size", "refine_max_calls", "verification_max_calls")
    @classmethod
    def _counts(cls, value: int, info) -> int:  # each its own check: every problem of the section at once
        least = 1 if info.field_name in ("max_candidates", "batch_size") else 0
        if value < least:
            raise ValueError(f"must be >= {least}")
        return value

    @field_validator("verification_total_max_calls")
    @classmethod
    def _total(cls, value: int | None) -> int | None:
        if value is not None and value < 0:
            raise ValueError("must be >= 0 (or omitted: a multiple of verification_max_calls)")
        return value

    @property
    def verification_budget(self) -> int:
        """The true-model calls all the verifications may spend together (verification_total_max_calls resolved)."""
        if self.verification_total_max_calls is not None:
            return self.verification_total_max_calls
        return self.verification_max_calls * (PROVEN_ROUNDS if self.require == "proven" else 1)

    @model_validator(mode="after")
    def _check(self) -> DesignSettings:
        if self.require == "proven" and (not self.verify or not self.verification_max_calls
                                         or not self.verification_budget):
            off = ("verify = false" if not self.verify else "verification_max_calls = 0"
                   if not self.verification_max_calls else "verification_total_max_calls = 0")
            raise ValueError(f"require: 'proven' needs the verification on the true model, and {off} turns it off "
                             "(or keep require = 'not_refuted')")
        if not (self.tolerances or self.fit or self.properties or self.materials):
            raise ValueError("name at least one control (tolerances, fit, properties or materials)")
        n = 1
        for size in self.option_counts():
            n *= size
        if n > self.max_candidates:
            raise ValueError(f"{n} combinations exceed max_candidates = {self.max_candidates}")
        return self

    def fits(self) -> list[FitControl]:
        """The fit controls (none, one, or one per clearance)."""
        if self.fit is None:
            return []
        return list(self.fit) if isinstance(self.fit, list) else [self.fit]

    def option_counts(self) -> list[int]:
        """Number of options of every control, in the order of the candidate enumeration."""
        return ([len(t.grades) for t in self.tolerances] + [len(f.options) for f in self.fits()]
                + [len(p.classes) for p in self.properties] + [len(m.options) for m in self.materials])


#: verifications the default budget of require = 'proven' allows when each runs to its verification_max_calls
PROVEN_ROUNDS = 3
#: smallest population per candidate: the exact 95 % interval of R = 0.9 from 1,000 samples is about +/- 0.02
MIN_POPULATION = 1_000


def _rank(grade: str) -> int:
    return IT_GRADES.index(grade)


def _tighter_fit(a: FitOption, b: FitOption) -> bool:
    """Whether fit ``a`` is tighter than ``b``: the same mean, neither grade looser and one tighter."""
    if a.mean != b.mean:
        return False
    pairs = [(_rank(a.hole_grade), _rank(b.hole_grade)), (_rank(a.shaft_grade), _rank(b.shaft_grade))]
    return all(x <= y for x, y in pairs) and any(x < y for x, y in pairs)


def _inverted(priced: list[tuple], tighter) -> str:
    """Every pair of ``priced`` (option, cost) where the option ``tighter`` than the other costs strictly less, as
    'IT9 at 1 < IT11 at 3'; '' when none."""
    def label(option) -> str:
        return option if isinstance(option, str) else option.name

    return ", ".join(f"{label(a)} at {ca:g} < {label(b)} at {cb:g}"
                     for a, ca in priced for b, cb in priced if tighter(a, b) and ca < cb)


def _unique(names: list[str]) -> None:
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ValueError(f"names given twice: {dup}")
