"""Candidate designs: every control's options as changes of input distributions, and their combinations.

A control's option changes the distributions of one or more random variables and nothing else: the wear
model depends on the sampled values, not on the distributions, so every candidate is the same true model under
other input distributions. The rules:

* a length at grade IT g: normal with the same mean and sigma = IT(g, nominal) / 6 (ISO 286-1 tolerance read
  as 6 sigma, Eq. 41 of Jin et al. 2025; :func:`jointwear.uncertainty.tolerances.length_sigma`);
* a fit: the clearance's sigma = sqrt(T_D^2 + T_d^2) / 12 from the bore and pin grades (Eq. 40,
  :func:`jointwear.uncertainty.tolerances.clearance_from_fit`), truncated at the minimum clearance as in the
  study;
* a property class: the given mean and standard deviation (the study's where not given); acceptance limits
  truncate the normal distribution (parts outside the limits are rejected at inspection).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from jointwear.config import StudyConfig
from jointwear.design.cost import grade_costs
from jointwear.design.settings import DesignSettings, PropertySpec
from jointwear.uncertainty.tolerances import it_tolerance, length_sigma
from jointwear.uncertainty.variables import ClearanceSpec, RandomVariableSpec, UncertaintySettings


@dataclass
class Option:
    """One option of a control: its label, cost and the distributions it sets (by variable name)."""

    name: str
    cost: float
    marginals: dict
    described: dict = field(default_factory=dict)  # per variable: mean, std, lower, upper (SI)
    clearance: ClearanceSpec | None = None  # the clearance this option sets (fits only)


@dataclass
class Control:
    """A decision (``kind``: 'tolerance', 'fit', 'property' or 'material') and its options."""

    name: str
    kind: str
    options: list[Option]

    def to_json(self) -> dict:
        return {"name": self.name, "kind": self.kind,
                "options": [{"name": o.name, "cost": o.cost, "distributions": o.described} for o in self.options]}


def spec_marginal(spec: RandomVariableSpec, change: PropertySpec | None = None):
    """The frozen distribution of ``spec`` with ``change``'s mean/std and acceptance limits applied."""
    if change is not None and (change.mean is not None or change.std is not None):
        spec = spec.model_copy(update={k: v for k, v in (("mean", change.mean), ("std", change.std)) if v is not None})
    if change is None or (change.lower is None and change.upper is None):
        return spec.frozen()
    lo = -float("inf") if change.lower is None else (change.lower - spec.mean) / spec.std
    hi = float("inf") if change.upper is None else (change.upper - spec.mean) / spec.std
    return stats.truncnorm(a=lo, b=hi, loc=spec.mean, scale=spec.std)


def _described(spec: RandomVariableSpec, change: PropertySpec | None = None) -> dict:
    mean = spec.mean if change is None or change.mean is None else change.mean
    std = spec.std if change is None or change.std is None else change.std
    return {"mean": mean, "std": std, "lower": None if change is None else change.lower,
            "upper": None if change is None else change.upper}


def build_controls(config: StudyConfig, settings: DesignSettings | None = None) -> list[Control]:
    """The controls of ``settings`` (default ``config.design``) as options over the study's random variables
    (the config is assumed checked by :func:`jointwear.design.checks.design_problems`)."""
    settings = settings if settings is not None else config.design
    unc = config.uncertainty
    specs = {s.name: s for s in unc.all_specs()}
    controls: list[Control] = []
    for t in settings.tolerances:
        spec = specs[t.variable]
        nominal = t.nominal if t.nominal is not None else abs(spec.mean)
        costs = grade_costs(t, nominal, settings.cost_model)
        options = []
        for grade, cost in zip(t.grades, costs):
            sigma = length_sigma(it_tolerance(grade, nominal))
            changed = spec.model_copy(update={"std": sigma})
            options.append(Option(grade, cost, {t.variable: changed.frozen()},
                                  {t.variable: _described(changed)}))
        controls.append(Control(t.variable, "tolerance", options))
    fits = settings.fits()
    for fit in fits:
        options = []
        fitted = fit.clearance(unc)
        for f in fit.options:
            c = f.applied_to(fitted)
            options.append(Option(f.name, f.cost, {c.name: c.feasible()},
                                  {c.name: {"mean": c.mean, "std": c.std, "lower": c.minimum, "upper": None,
                                            "hole_grade": c.hole_grade, "shaft_grade": c.shaft_grade}},
                                  clearance=c))
        controls.append(Control("fit" if len(fits) == 1 else f"fit {fitted.name}", "fit", options))
    for p in settings.properties:
        spec = specs[p.variable]
        options = [Option(k.name, k.cost, {p.variable: spec_marginal(spec, k)}, {p.variable: _described(spec, k)})
                   for k in p.classes]
        controls.append(Control(p.variable, "property", options))
    for m in settings.materials:
        options = [Option(o.name, o.cost, {v: spec_marginal(specs[v], ch) for v, ch in o.variables.items()},
                          {v: _described(specs[v], ch) for v, ch in o.variables.items()}) for o in m.options]
        controls.append(Control(m.name, "material", options))
    return controls


@dataclass(frozen=True)
class Candidate:
    """One combination: the index of the chosen option of every control."""

    picks: tuple[int, ...]

    def choices(self, controls: list[Control]) -> dict[str, str]:
        return {c.name: c.options[i].name for c, i in zip(controls, self.picks)}

    def cost(self, controls: list[Control]) -> float:
        return float(sum(c.options[i].cost for c, i in zip(controls, self.picks)))

    def options(self, controls: list[Control]) -> list[Option]:
        return [c.options[i] for c, i in zip(controls, self.picks)]

    def marginals(self, controls: list[Control], names: list[str], base: list) -> list:
        """The candidate's input distributions in the study's variable order (the study's where no control
        sets them)."""
        out = list(base)
        for option in self.options(controls):
            for var, dist in option.marginals.items():
                out[names.index(var)] = dist
        return out

    def infeasible_probability(self, controls: list[Control], uncertainty: UncertaintySettings) -> float:
        """Probability of an assembly with a clearance at or below its minimum under the 'fail' rule, each
        clearance as this candidate's fits set it (the study's where no fit does)."""
        chosen = {o.clearance.name: o.clearance for o in self.options(controls) if o.clearance is not None}
        return uncertainty.infeasible_probability(replace=chosen)

    def distributions(self, controls: list[Control]) -> dict:
        out: dict = {}
        for option in self.options(controls):
            out.update(option.described)
        return out


#: Largest relative difference of mean, standard deviation and support at which an option is read as the study's own
#: distribution: a value written to two significant figures (8.7 um for IT9's 8.67 um); neighbouring ISO grades
#: differ by 60 %.
SAME_DISTRIBUTION_RTOL = 0.05


def _distance(a, b) -> float:
    """The largest relative difference of two frozen distributions' mean, standard deviation and support ends."""
    left = np.array([a.mean(), a.std(), *a.support()], dtype=float)
    right = np.array([b.mean(), b.std(), *b.support()], dtype=float)
    same = left == right  # the infinite ends of two untruncated distributions
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(left - right) / np.maximum(np.abs(left), np.abs(right))
    return float(np.max(np.where(same, 0.0, np.nan_to_num(rel, nan=np.inf))))


def today_picks(controls: list[Control], uncertainty: UncertaintySettings) -> list[int | None]:
    """For every control, the option nearest the study's own distributions within ``SAME_DISTRIBUTION_RTOL``
    (None when no option is)."""
    study = {s.name: s.frozen() for s in uncertainty.all_specs()}
    study.update({c.name: c.feasible() for c in uncertainty.clearances()})
    picks = []
    for control in controls:
        distance = [max(_distance(d, study[v]) for v, d in o.marginals.items()) for o in control.options]
        best = int(np.argmin(distance))
        picks.append(best if distance[best] <= SAME_DISTRIBUTION_RTOL else None)
    return picks


def today_candidate(controls: list[Control], uncertainty: UncertaintySettings) -> tuple[Candidate | None, list[str]]:
    """Today's design among the candidates (:func:`today_picks`). Returns (that candidate, []) or (None, the controls
    none of whose options sets the study's distributions)."""
    picks = today_picks(controls, uncertainty)
    unmatched = [c.name for c, p in zip(controls, picks) if p is None]
    return (None, unmatched) if unmatched else (Candidate(tuple(picks)), [])


def changes_from(cand: Candidate, picks: list[int | None]) -> int:
    """How many controls ``cand`` sets otherwise than ``picks`` (today's; a control today's design matches no option
    of counts as a change for every candidate)."""
    return sum(p != t for p, t in zip(cand.picks, picks))


def enumerate_candidates(controls: list[Control]) -> Iterator[Candidate]:
    """Every combination of one option per control."""
    for picks in itertools.product(*[range(len(c.options)) for c in controls]):
        yield Candidate(tuple(picks))
