"""Checks of the ``[design]`` section against the rest of the config (one message per problem, naming the field)."""

from __future__ import annotations

from jointwear.config import StudyConfig, target_display_unit, target_unit
from jointwear.design.settings import FitControl
from jointwear.schema import item_key
from jointwear.study.checks import shown, unbuilt_reason
from jointwear.uncertainty.tolerances import iso_fit, it_tolerance
from jointwear.units import ANY_UNIT


def design_problems(config: StudyConfig) -> list[str]:
    """What keeps ``config.design`` from running (empty when it can)."""
    d = config.design
    if d is None:
        return ["design: the design stage needs a [design] section (targets and controls)"]
    unc = config.uncertainty
    if unc is None or not unc.all_specs():
        return ["design: the design stage needs random variables ([uncertainty] section)"]
    specs = {s.name: s for s in unc.all_specs()}
    problems = []
    controlled: dict[str, str] = {}
    told_twice: set[str] = set()  # variables claim() has named as set twice: the names check below says it once

    def claim(var: str, where: str) -> None:
        if var in controlled:
            problems.append(f"{where}: variable '{var}' is already set by {controlled[var]}")
            told_twice.add(var)
        else:
            controlled[var] = where

    def known(var: str, where: str) -> bool:
        if var not in specs:
            problems.append(f"{where}: '{var}' is not a random variable of [uncertainty] "
                            f"(known: {', '.join(specs)})")
            return False
        return True

    for i, t in enumerate(d.tolerances):
        where = f"design.tolerances[{i}].variable"
        if not known(t.variable, where):
            continue
        if unc.clearance_named(t.variable) is not None:
            problems.append(f"{where}: the clearance is set by a fit ([design.fit]), not by a length grade")
            continue
        unit = target_unit(specs[t.variable].target)
        if unit not in ("m", ANY_UNIT):
            problems.append(f"{where}: '{t.variable}' is not a length (its target is in {unit or 'no unit'}): a "
                            "tolerance grade sets a length's spread; a material property's class goes in "
                            "[[design.properties]]")
            continue
        claim(t.variable, f"design.tolerances[{i}]")
        nominal = t.nominal if t.nominal is not None else abs(specs[t.variable].mean)
        problems += _grade_problems(t.grades, nominal, f"design.tolerances[{i}]")
    fits = d.fits()
    names = [c.name for c in unc.clearances()]
    for i, fit in enumerate(fits):
        where = "design.fit" if isinstance(d.fit, FitControl) else f"design.fit[{i}]"
        fitted = fit.clearance(unc)
        if not names:
            problems.append(f"{where}: the fit needs a random clearance ([uncertainty.clearance])")
        elif fitted is None and fit.variable is None:
            problems.append(f"{where}.variable: the study has several random clearances ({', '.join(names)}); "
                            "name the one this fit sets")
        elif fitted is None:
            problems.append(f"{where}.variable: '{fit.variable}' is not a random clearance of "
                            f"[uncertainty.clearance] (known: {', '.join(names)})")
        else:
            claim(fitted.name, where)
            labels = [f.name for f in fit.options]
            for j, f in enumerate(fit.options):
                option = f"{where}.options[{item_key(j, labels)}]"
                if f.fit is not None:
                    try:
                        mean = iso_fit(f.fit, fitted.nominal_diameter).mean_clearance
                    except ValueError as exc:
                        problems.append(f"{option}.fit: {exc}")
                        continue
                    if not mean > fitted.minimum:
                        problems.append(f"{option}.fit: {f.fit} gives a mean clearance of "
                                        f"{mean * 1e6:g} um, not above the clearance's minimum "
                                        f"({fitted.minimum * 1e6:g} um)")
                else:
                    problems += _grade_problems([f.hole_grade, f.shaft_grade], fitted.nominal_diameter,
                                                option)
    for i, p in enumerate(d.properties):
        where = f"design.properties[{i}].variable"
        if not known(p.variable, where):
            continue
        claim(p.variable, f"design.properties[{i}]")
        labels = [k.name for k in p.classes]
        for j, k in enumerate(p.classes):
            problems += _spec_problems(config, specs[p.variable], k,
                                       f"design.properties[{i}].classes[{item_key(j, labels)}]")
    parts = [m.name for m in d.materials]
    for i, m in enumerate(d.materials):
        material = f"design.materials[{item_key(i, parts)}]"
        for var in sorted({v for o in m.options for v in o.variables} & set(specs)):
            claim(var, material)
        labels = [o.name for o in m.options]
        for j, o in enumerate(m.options):
            for var, ch in o.variables.items():
                where = f"{material}.options[{item_key(j, labels)}].variables.{var}"
                if unc.clearance_named(var) is not None:
                    problems.append(f"{where}: the clearance is set by a fit ([design.fit])")
                elif known(var, where):
                    problems += _spec_problems(config, specs[var], ch, where)
    fitted = [f.clearance(unc) for f in fits]
    # two fits of one clearance are reported above, once
    fit_names = ["fit"] if len(fits) == 1 else list(dict.fromkeys(f"fit {c.name}" for c in fitted if c is not None))
    names = ([t.variable for t in d.tolerances] + fit_names + [p.variable for p in d.properties]
             + [m.name for m in d.materials])
    dup = sorted({n for n in names if names.count(n) > 1} - told_twice)
    if dup:
        problems.append(f"design: control names given twice: {dup} (a material's name must differ from the "
                        "controlled variables and from 'fit')")
    return problems


def _grade_problems(grades, nominal: float, where: str) -> list[str]:
    """Every grade the ISO 286 table cannot give for this nominal size, each message once."""
    out = []
    for grade in grades:
        try:
            it_tolerance(grade, nominal)
        except ValueError as exc:
            if f"{where}: {exc}" not in out:
                out.append(f"{where}: {exc}")
    return out


def _spec_problems(config: StudyConfig, spec, change, where: str) -> list[str]:
    """A property specification the design cannot use: acceptance limits on a variable they cannot truncate or that
    leave out its mean, and a mean at which the model cannot be built (every call of a design with it would fail)."""
    out = []
    if change.mean is not None and (reason := unbuilt_reason(config, [spec.target], [change.mean])) is not None:
        out.append(f"{where}.mean: at {shown(change.mean, spec.target)} the model cannot be built, so every call of "
                   f"a design with it would fail: {reason}")
    truncated = change.lower is not None or change.upper is not None
    if truncated and spec.distribution != "normal":
        out.append(f"{where}: acceptance limits need a normal variable ('{spec.name}' is {spec.distribution})")
    if truncated:
        mean = spec.mean if change.mean is None else change.mean
        if (change.lower is not None and change.lower >= mean) or (change.upper is not None and change.upper <= mean):
            unit = target_display_unit(spec.target)
            unit = f" {unit}" if unit else ""
            limits = " and ".join(f"{v:g}{unit}" for v in (change.lower, change.upper) if v is not None)
            out.append(f"{where}: the acceptance limits ({limits}) must enclose the variable's mean ({mean:g}{unit})")
    return out
