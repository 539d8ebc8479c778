"""Study configuration: pydantic models, TOML loading and built-in presets.

``load_config(source)`` accepts a TOML file path, a preset name (a file
``jointwear/presets/<name>.toml``) or None for the default preset
``jin2025_flapping_wing``.  Every problem becomes a :class:`ConfigError` with one line that
names the field (dotted path) and the allowed range.

Configs are immutable once validated: derive a changed one with :func:`updated`, which validates it again.
Whether a general linkage assembles over a whole cycle is checked after the schema, when the model is built
(:func:`jointwear.mechanism.check_assembly`).

Units: TOML keys may carry a unit suffix (``length_mm``, ``speed_rpm``, ``youngs_modulus_GPa``,
``hardness_HB``, ``angle_deg`` ...; table in :mod:`jointwear.units`).  Models hold SI values
under plain names.  Subclass :class:`SIModel` to get the same behaviour (and ``extra="forbid"``,
NaN/inf rejection) in other sections.

Extending: add a field to :class:`StudyConfig` whose type is an ``SIModel`` defined in the
owning subpackage, e.g. ``wear: WearConfig = Field(default_factory=WearConfig, description=...)``.
"""

from __future__ import annotations

import difflib
import math
import numbers
import os
import re
import stat
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import BaseModel, PrivateAttr, ValidationError, model_validator

from jointwear.contact.settings import (
    ClearanceJointConfig,
    FrictionConfig,
    MaterialConfig,
)
from jointwear.design.settings import (
    CostModel,
    DesignSettings,
    DesignTarget,
    FitControl,
    FitOption,
    MaterialControl,
    MaterialOption,
    PropertyClass,
    PropertyControl,
    ToleranceControl,
)
from jointwear.mechanism.settings import (
    DriverConfig,
    FourBarConfig,
    GeneralBodyConfig,
    GeneralJointConfig,
    GeneralMechanismConfig,
    LinkConfig,
    MechanismConfig,
    SimulationConfig,
    SliderCrankConfig,
)
from jointwear.reference import AcceptanceBand, ReferenceData, ReferenceValue
from jointwear.schema import (
    ConfigError,
    F,
    FieldValueError,
    SIModel,
    field_units,
    item_key,
    path_unit,
    walk_schema,
)
from jointwear.study_settings import (
    ComputeSettings,
    ReliabilitySettings,
    SensitivitySettings,
)
from jointwear.uncertainty.targets import CLEARANCE_SUFFIX, apply_targets, target_error
from jointwear.uncertainty.variables import (
    ClearanceSpec,
    CorrelationSpec,
    RandomVariableSpec,
    UncertaintySettings,
)
from jointwear.units import (
    ANY_UNIT,
    PA_PER_HB,
    SUFFIXES,
    UnitError,
    convert_keys,
    split_unit_key,
    suffix_problem,
    suffix_unit,
    suffixes_of,
    to_si,
)
from jointwear.wear.settings import WearSettings

__all__ = [
    "DEFAULT_PRESET", "ClearanceJointConfig", "ConfigError", "DriverConfig", "FourBarConfig", "FrictionConfig",
    "GeneralBodyConfig", "GeneralJointConfig", "GeneralMechanismConfig", "LinkConfig", "MaterialConfig",
    "MechanismConfig", "SIModel", "SimulationConfig", "SliderCrankConfig", "StudyConfig", "available_presets",
    "config_from_dict", "config_reference_markdown", "load_config", "merge_tables", "updated", "validation_problems",
]

DEFAULT_PRESET = "jin2025_flapping_wing"


# ---------------------------------------------------------------------------------------------
# study
# ---------------------------------------------------------------------------------------------
class StudyConfig(SIModel):
    """A whole study. Later stages add their sections here (wear, uncertainty, reliability, sensitivity, compute)."""

    name: str = F("study", description="Name of the study / preset.")
    citation: str = F("", description="Source of the data (presets are cited data).")
    description: str = F("", description="Free text.")
    mechanism: MechanismConfig = F(
        description="The planar mechanism (type = 'four_bar', 'slider_crank' or 'general').")
    clearance_joints: list[ClearanceJointConfig] = F(
        default_factory=list, description="Revolute joints with clearance (any number)."
    )
    simulation: SimulationConfig = F(default_factory=SimulationConfig, description="Integrator settings.")
    wear: WearSettings = F(default_factory=WearSettings, description="Archard wear and the cycle-block history.")
    uncertainty: UncertaintySettings | None = F(
        None, description="Random inputs (paper Tables 5-6); needed by the reliability and sensitivity stages.")
    reliability: ReliabilitySettings = F(default_factory=ReliabilitySettings, description="Wear reliability (Section 5).")
    sensitivity: SensitivitySettings = F(default_factory=SensitivitySettings, description="Sensitivity (Section 6.2.3).")
    compute: ComputeSettings = F(default_factory=ComputeSettings, description="Where model calls run.")
    reference: ReferenceData | None = F(
        None, description="Cited results of the publication the study reproduces; the report compares with them "
        "only when given (jointwear.reference).")
    design: DesignSettings | None = F(None, description="Uncertainty control: controls, costs and targets (docs/design.md).")
    # the preset, file or folder load_config read (None for a config built in Python): a validated config is read-only,
    # so a Study given it runs what that source says and records the source as if given it
    _origin: str | None = PrivateAttr(None)

    @property
    def origin(self) -> str | None:
        """The preset name, TOML file, results folder or config.json :func:`load_config` read this config from; None
        for a config built in Python (a mapping, or :func:`updated`'s changed copy)."""
        return self._origin

    def __eq__(self, other: object) -> bool:
        """Equal settings, wherever each was read from (pydantic's own comparison counts the origin too)."""
        if not isinstance(other, StudyConfig):
            return NotImplemented
        return self.__dict__ == other.__dict__

    __hash__ = None  # a config holds lists: not hashable, as pydantic's would not be

    @model_validator(mode="before")
    @classmethod
    def _variable_units(cls, data: Any) -> Any:
        """A random variable's mean, std and bounds take suffixes of its target's unit (``mean_HB`` for a
        hardness, never ``std_mm``), and so do the design's specifications of that variable."""
        for where, raw, unit in _suffixed_by_target(data):
            for key in raw:
                split = split_unit_key(key, frozenset(("mean", "std", "lower", "upper")))
                problem = split and suffix_problem(key, split[0], split[1], unit)
                if problem:
                    raise ValueError(f"{where}.{problem} (the unit of its target)")
        return data

    @model_validator(mode="wrap")
    @classmethod
    def _clearance_from_joint(cls, data: Any, handler) -> StudyConfig:
        """A clearance's nominal diameter and mean, when not given, are those of the joint its target names (its
        journal's diameter, its drawn clearance): the defaults must be the user's drawing, not a reference's pin. Each
        clearance keeps which of its settings the joint set (``check`` and the report say so)."""
        if not isinstance(data, dict) or not isinstance(data.get("uncertainty"), dict):
            return handler(data)
        tables = data["uncertainty"].get("clearance")
        if not isinstance(tables, (dict, list)):
            return handler(data)
        filled = [_clearance_defaults(t, data.get("clearance_joints")) if isinstance(t, dict) else (t, {})
                  for t in (tables if isinstance(tables, list) else [tables])]
        config = handler({**data, "uncertainty": {**data["uncertainty"], "clearance": [
            t for t, _ in filled] if isinstance(tables, list) else filled[0][0]}})
        for spec, (_, taken) in zip(config.uncertainty.clearances(), filled):
            spec.set_by_joint(taken)
        return config

    @model_validator(mode="after")
    def _targets_exist(self) -> StudyConfig:
        if self.uncertainty is None:
            return self
        data = self.model_dump()
        for spec in self.uncertainty.all_specs():
            problem = target_error(data, spec.target)
            if problem:
                raise ValueError(f"{self.uncertainty.field_of(spec.name)}.target: {problem}")
            check_display_unit(self.uncertainty.field_of(spec.name), spec)
        return self

    @model_validator(mode="after")
    def _joints_exist(self) -> StudyConfig:
        joints = self.mechanism.revolute_joint_bodies()
        seen = set()
        names = [cj.name for cj in self.clearance_joints]
        for i, cj in enumerate(self.clearance_joints):
            where = f"clearance_joints[{item_key(i, names)}]"
            if cj.joint not in joints:
                allowed = ", ".join(joints)
                raise ValueError(f"{where}.joint: '{cj.joint}' is not a joint that can carry clearance"
                                 f"{_why_no_clearance(self.mechanism, cj.joint)} (allowed: {allowed})")
            if cj.joint in seen:
                raise ValueError(f"{where}.joint: joint '{cj.joint}' given twice")
            seen.add(cj.joint)
            pair = set(joints[cj.joint])
            if {cj.bearing_body, cj.journal_body} != pair:
                raise ValueError(
                    f"{where}: bearing_body/journal_body must be the bodies of joint {cj.joint}: "
                    f"{' and '.join(joints[cj.joint])}"
                )
        return self


def _why_no_clearance(mechanism: Any, joint: str) -> str:
    """Why a joint of the mechanism cannot carry clearance (': it is prismatic, ...'); '' for a name that is no joint
    of it. A clearance joint is a revolute pin in its bore, and a driver turns its body about an ideal pivot."""
    if joint == "O" and mechanism.type in ("four_bar", "slider_crank"):
        return ": O is the crank's driven pivot, which the constant-speed drive turns about an ideal pin"
    found = next((j for j in getattr(mechanism, "joints", ()) if j.name == joint), None)
    if found is None:
        return ""
    if found.type == "prismatic":
        return (f": {joint} is a prismatic joint (a slider), and a clearance joint is a revolute joint's pin in its "
                "bore")
    driver = next((i for i, d in enumerate(mechanism.drivers) if d.joint == joint), None)
    if driver is not None:
        return (f": {joint} is driven (mechanism.drivers[{driver}].joint), and a driver turns its body about an ideal "
                "pin")
    return ""


def check_display_unit(where: str, spec: RandomVariableSpec) -> None:
    """Refuse a random variable's display unit of another quantity than its target's (a hardness in 'mm'), or
    with a scale that does not convert SI to it."""
    unit = suffix_unit(spec.unit)
    target = target_unit(spec.target)
    if unit is None or target == ANY_UNIT:
        return
    if SUFFIXES[unit][1] != target:
        known = f"its units: {', '.join(suffixes_of(target))}" if target else "a plain number, of no unit"
        raise ValueError(f"{where}.unit: {spec.unit!r} is not a unit of its target {spec.target} ({known})")
    if not math.isclose(spec.scale * SUFFIXES[unit][0], 1.0, rel_tol=1e-3):
        raise ValueError(f"{where}.scale: {spec.scale:g} does not show SI values in {spec.unit!r}, which takes "
                         f"{1.0 / SUFFIXES[unit][0]:.7g}: give that, or leave scale out (the unit sets it)")


def _clearance_defaults(table: dict[str, Any], joints: Any) -> tuple[dict[str, Any], dict[str, str]]:
    """``table`` (a raw clearance table) with ``nominal_diameter`` and ``mean`` (SI) from the clearance joint its
    target names where it gives neither in any unit (a fit sets the mean), and what set each ({'mean': "joint B's
    radii"}); unchanged where the joint is not found (the target's own check reports it)."""
    stems = {stem for key in table for stem in _unit_stems(key)}
    wanted = {"nominal_diameter"} - stems | ({"mean"} - stems if table.get("fit") is None else set())
    target = str(table.get("target") or "")
    keys = _dotted(target).split(".")
    if not wanted or not target.endswith(CLEARANCE_SUFFIX) or len(keys) != 3 or not isinstance(joints, list):
        return table, {}
    joint = next((j for i, j in enumerate(joints) if isinstance(j, dict) and keys[1] in (str(i), j.get("name", "A"))),
                 None)
    try:  # the joint's radii in SI, in whatever unit it gives them (a unit it cannot take: its own check says so)
        radii = convert_keys(joint or {}, frozenset(("journal_radius", "bearing_radius")))
    except UnitError:
        return table, {}
    journal, bearing = radii.get("journal_radius"), radii.get("bearing_radius")
    if not _is_number(journal):
        return table, {}
    out, taken = dict(table), {}
    name = joint.get("name", "A")
    if "nominal_diameter" in wanted:
        out["nominal_diameter"], taken["nominal_diameter"] = 2.0 * journal, f"joint {name}'s journal diameter"
    if "mean" in wanted and _is_number(bearing):
        out["mean"], taken["mean"] = bearing - journal, f"joint {name}'s radii"
    return out, taken


def _dotted(path: str) -> str:
    """``clearance_joints[0].clearance`` (as messages write a path) as ``clearance_joints.0.clearance``."""
    return re.sub(r"\[([^\]]+)\]", r".\1", path)


def target_unit(path: str) -> str | None:
    """The SI unit of a random variable's target (None: a plain number; ``ANY_UNIT``: a path the schema does not
    follow, which the target's own check reports)."""
    return "m" if path.endswith(CLEARANCE_SUFFIX) else path_unit(StudyConfig, path)


def target_display_unit(path: str) -> str | None:
    """A target's SI unit to show beside its numbers: None for a plain number and for a path the schema does not
    follow."""
    unit = target_unit(path)
    return None if unit == ANY_UNIT else unit


def display_unit(target: str) -> str | None:
    """The unit a random variable's numbers are shown in: its target's SI unit, except a hardness, which is
    entered and quoted in HB ("HB" here; :func:`jointwear.units.to_display` converts)."""
    return "HB" if target.rsplit(".", 1)[-1] == "hardness" else target_display_unit(target)


def _suffixed_by_target(data: Any) -> list[tuple[str, dict, str | None]]:
    """(where, raw table, SI unit of the target) of every table whose numbers take their variable's target's unit:
    the random variables, and the design's property classes and material options."""
    if not isinstance(data, Mapping) or not isinstance(data.get("uncertainty"), Mapping):
        return []
    unc = data["uncertainty"]
    units = {}
    clearance = unc.get("clearance")
    for c in [clearance] if isinstance(clearance, Mapping) else clearance if isinstance(clearance, list) else []:
        if isinstance(c, Mapping):
            units[str(c.get("name", "c"))] = "m"
    out = []
    for var in unc.get("variables") or []:
        if isinstance(var, Mapping) and isinstance(var.get("target"), str):
            target = var["target"]
            units[var.get("name")] = target_unit(target)
            out.append((f"uncertainty.variables[{var.get('name')}]", var, units[var.get("name")]))
    design = data.get("design")
    if isinstance(design, Mapping):
        for prop in design.get("properties") or []:
            if isinstance(prop, Mapping) and prop.get("variable") in units:
                for c in prop.get("classes") or []:
                    if isinstance(c, Mapping):
                        out.append((f"design.properties[{prop['variable']}].classes[{c.get('name')}]", c,
                                    units[prop["variable"]]))
        for mat in design.get("materials") or []:
            for opt in (mat.get("options") or []) if isinstance(mat, Mapping) else []:
                specs = opt.get("variables") if isinstance(opt, Mapping) else None
                for name, spec in (specs or {}).items() if isinstance(specs, Mapping) else []:
                    if name in units and isinstance(spec, Mapping):
                        out.append((f"design.materials[{mat.get('name')}].options[{opt.get('name')}].variables.{name}",
                                    spec, units[name]))
    return [(w, raw, u) for w, raw, u in out if u != ANY_UNIT]


# ---------------------------------------------------------------------------------------------
# loading
# ---------------------------------------------------------------------------------------------
def _loc(loc: tuple[Any, ...], data: Any = None) -> str:
    """An error's location as the config's paths write it: ``uncertainty.variables[k_b].std``, a list's item named as
    :func:`jointwear.schema.item_key` names it from ``data`` (as validated), else by its index."""
    out, node = "", data
    for part in loc:
        if isinstance(part, int):
            inside = isinstance(node, list) and 0 <= part < len(node)
            names = [entry.get("name") if isinstance(entry, Mapping) else None for entry in node] if inside else []
            out += f"[{item_key(part, names)}]" if inside else f"[{part}]"
            node = node[part] if inside else None
        elif part in ("four_bar", "slider_crank", "general") and out == "mechanism":
            continue  # discriminated-union tag
        else:
            out += ("." if out else "") + str(part)
            node = node.get(part) if isinstance(node, Mapping) else None
    return out or "config"


def _unit_at(loc: tuple[Any, ...]) -> str | None:
    """The SI unit of the field a validation error points at (an item of a point or list takes its field's); ''
    for a plain number, None where the field or its unit is not known here."""
    found = walk_schema(StudyConfig, loc) if loc else None
    return None if found is None or found[1] == ANY_UNIT else found[1] or ""


def _did_you_mean(loc: tuple[Any, ...]) -> str:
    """' (did you mean mass_g?)' for an unknown key close to a field of its section or to a field with a suffix of
    its unit; '' when none is close."""
    found = walk_schema(StudyConfig, loc[:-1])
    candidates = found[0] if found else []
    if not candidates:
        return ""
    key = str(loc[-1]) if loc else ""
    units = {name: unit for model in candidates for name, unit in field_units(model).items()}
    allowed = {name: list(SUFFIXES) if unit == ANY_UNIT else suffixes_of(unit) for name, unit in units.items() if unit}
    prefix = max((name for name in allowed if key.startswith(name + "_")), key=len, default=None)
    if prefix is not None:  # a field with an unknown unit suffix
        rest = key[len(prefix) + 1:]
        same = [s for s in allowed[prefix] if s.lower() == rest.lower()]
        if same:
            return f" (did you mean {prefix}_{same[0]}? unit suffixes are case-sensitive)"
        return f" (the unit suffixes of {prefix}: {', '.join('_' + s for s in allowed[prefix])})"
    words = set(units) | {f"{name}_{s}" for name, suffixes in allowed.items() for s in suffixes}
    close = difflib.get_close_matches(key, sorted(words), n=1, cutoff=0.75)
    return f" (did you mean {close[0]}?)" if close else ""


#: error types that say the input has another shape than a union's branch (a table where a list is expected ...)
SHAPE_ERRORS = frozenset({"list_type", "tuple_type", "dict_type", "model_type", "model_attributes_type", "set_type",
                          "float_type", "int_type", "string_type", "bool_type", "float_parsing", "int_parsing"})


def _branch_at(loc: tuple[Any, ...]) -> int | None:
    """Where a union's branch tag ('function-after[..., ClearanceSpec]', 'list[...]', 'float') sits in an error's
    location: a key that is no field there but names a type of the union (None when there is none)."""
    for i, key in enumerate(loc):
        found = walk_schema(StudyConfig, loc[:i]) if isinstance(key, str) else None
        models = found[0] if found else []
        if not isinstance(key, str) or any(key in m.model_fields for m in models):
            continue
        if re.fullmatch(r"[\w-]+\[.*\]", key) or key in {m.__name__ for m in models} or key in ("float", "int",
                                                                                                "str", "bool"):
            return i
    return None


def _matching_branches(errors: list[dict]) -> list[dict]:
    """A union's errors from the branches that fit the input's shape only (a table given for
    ``ClearanceSpec | list[ClearanceSpec]``: not 'Input should be a valid list'), with the branch tags dropped from
    the locations; every branch's when none fits."""
    while True:
        tagged = [(e, i) for e in errors if (i := _branch_at(tuple(e.get("loc", ())))) is not None]
        if not tagged:
            return errors
        err, i = tagged[0]
        prefix = tuple(err["loc"][:i])
        group = [(e, j) for e, j in tagged if j == i and tuple(e["loc"][:i]) == prefix]
        branches: dict[str, list[dict]] = {}
        for e, _ in group:
            branches.setdefault(e["loc"][i], []).append(e)
        fits = {tag for tag, errs in branches.items()
                if not all(len(e["loc"]) == i + 1 and e.get("type") in SHAPE_ERRORS for e in errs)}
        members = {id(e) for e, _ in group}
        if fits:
            errors = [e if id(e) not in members else {**e, "loc": prefix + tuple(e["loc"][i + 1:])}
                      for e in errors if id(e) not in members or e["loc"][i] in fits]
        else:  # no branch takes this shape: one error that lists the shapes they take
            shapes = [e["msg"].removeprefix("Input should be ") for e, _ in group]
            one = {**err, "loc": prefix, "msg": "Input should be " + " or ".join(dict.fromkeys(shapes))}
            errors = [one if e is err else e for e in errors if e is err or id(e) not in members]


def _as_written(table: Any, field: Any) -> str | None:
    """'-7 HB' when ``table`` (a section as the config wrote it) gives ``field`` with a unit suffix, else None."""
    if not isinstance(table, Mapping) or not isinstance(field, str):
        return None
    for key, value in table.items():
        split = split_unit_key(key, frozenset((field,)))
        if split and isinstance(value, (int, float)) and not isinstance(value, bool):
            return f"{value:g} {split[1]}"
    return None


def _table_at(data: Any, loc: tuple[Any, ...]) -> Any:
    """The raw table at an error's location in the data the config was validated from (None where it is not)."""
    node = data
    for key in loc:
        if isinstance(node, Mapping) and key not in node and node.get("type") == key:
            continue  # a discriminated union's tag: the table itself
        try:
            node = node[key]
        except (KeyError, IndexError, TypeError):
            return None
    return node


def _field_of_message(loc: tuple[Any, ...], where: str, msg: str) -> tuple[str, str]:
    """A section's rule that names its field first ('max_calls: ...', 'max_calls must ...') with the field joined to
    the path, as pydantic's own errors write it: ('reliability.max_calls', '...')."""
    named = re.match(r"([a-z_]\w*)((?:\[[^\]]+\]|\.[a-z_]\w*)*)(: | (?=must ))", msg)
    found = walk_schema(StudyConfig, loc) if named else None
    if named and found and any(named[1] in model.model_fields for model in found[0]):
        path = named[1] + named[2]
        return (f"{where}.{path}" if where != "config" else path), msg[named.end():]
    return where, msg


def validation_problems(exc: ValidationError, data: Any = None) -> list[str]:
    """Every problem of a pydantic validation error as 'field.path: message (got value)'; with the ``data`` that
    was validated, a value the config gave with a unit suffix is shown as written, then in SI ('got -7 HB =
    -6.8649e+07 Pa').

    An unknown key usually also causes a "missing" error for the key it misspells: the unknown key is told with the
    key it most likely means, and that key's "missing" is left out. Of a union (one table or a list of tables), only
    the branch that fits the input's shape is reported.
    """
    errors = sorted(_matching_branches(exc.errors()), key=lambda e: e.get("type") != "extra_forbidden")
    hints = {id(e): _did_you_mean(tuple(e.get("loc", ()))) for e in errors if e.get("type") == "extra_forbidden"}
    meant = set()  # (table, field) a misspelt key stands for, in any unit
    for err in errors:
        loc = tuple(err.get("loc", ()))
        guess = re.search(r"did you mean (\w+)\?", hints.get(id(err), ""))
        if guess and loc:
            meant |= {(loc[:-1], stem) for stem in _unit_stems(guess[1])}
    out = []
    for err in errors:
        loc = tuple(err.get("loc", ()))
        if err.get("type") == "missing" and loc and (loc[:-1], loc[-1]) in meant:
            continue
        where = _loc(loc, data)
        msg = err.get("msg", "invalid").removeprefix("Value error, ")
        inp = err.get("input")
        shown = ""
        unit = _unit_at(loc) if isinstance(inp, float) else ""
        written = _as_written(_table_at(data, loc[:-1]), loc[-1]) if isinstance(inp, float) and loc else None
        problem = (err.get("ctx") or {}).get("error")
        if isinstance(problem, FieldValueError):  # a section's rule on one field: its raw table is the input
            written = _as_written(inp, problem.field)
            where, msg, shown = f"{where}.{problem.field}", problem.message, f" (got {problem.value:g})"
            if written:
                shown = f" (got {written} = {problem.value:g} {SUFFIXES[written.split()[1]][1]})"
        elif err.get("type") not in ("missing", "extra_forbidden") and isinstance(inp, (int, float, str)) \
                and not isinstance(inp, bool) and f"got {inp!r}" not in msg:  # a validator that named the value
            shown = f" (got {inp!r}{', SI units' if unit is None else f' {unit}' if unit else ''})"
            if written:  # as written, and in SI where the field's unit is known here
                shown = f" (got {written} = {inp:g}{f' {unit}' if unit else ''})" if unit is not None else (
                    f" (got {written})")
        elif err.get("type", "").endswith(("_type", "_parsing")) and (inp is None or isinstance(inp, (dict, list))):
            # a table, an array or nothing where a value was due: say which (pydantic names only the type it wanted)
            text = repr(inp)
            shown = f" (got {text if len(text) <= 60 else text[:57] + '...'})"
        if err.get("type") == "extra_forbidden":
            msg = "unknown key (not a setting of this section)" + hints[id(err)]
            if loc and loc[0] == "clearance_joints" and str(loc[-1]).split("_")[0] == "clearance":
                # updated() and the random variables' targets take a joint's clearance; a table does not
                msg += ("; a clearance joint's table gives bearing_radius and journal_radius (the clearance is their "
                        "difference)")
        bound = next((v for k, v in (err.get("ctx") or {}).items() if k in ("ge", "gt", "le", "lt")), None)
        if unit == "Pa" and isinstance(bound, (int, float)) and bound:
            shown_bound = str(int(bound)) if float(bound).is_integer() else str(bound)  # as pydantic writes it
            msg = msg.replace(shown_bound, f"{bound:g} Pa")
            if not 1e-2 < abs(inp / bound) < 1e2:  # orders of magnitude off its bound: the unit, most likely
                field = str(err["loc"][-1])
                msg += f", a unit slip? (a suffix gives the unit: {field}_MPa, {field}_GPa)"
        where, msg = _field_of_message(loc, where, msg)
        # a whole-config rule's message starts with the fields it names
        text = (f"{where}: {msg}{shown}" if where != "config" else f"{msg}{shown}").replace("\n", " ")
        if text not in out:
            out.append(text)
    return out


def available_presets() -> list[str]:
    """Names of the built-in presets."""
    files = resources.files("jointwear.presets")
    return sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".toml"))


def non_string_key(tables: Any, path: str = "") -> str:
    """Where a mapping of TOML tables has a key that is not a str ('1 at the top level', "2 in mechanism"), or ''."""
    if isinstance(tables, Mapping):
        for key, value in tables.items():
            if not isinstance(key, str):
                return f"{key!r} in {path}" if path else f"{key!r} at the top level"
            found = non_string_key(value, f"{path}.{key}" if path else key)
            if found:
                return found
    elif isinstance(tables, (list, tuple)):
        for i, item in enumerate(tables):
            found = non_string_key(item, f"{path}[{i}]")
            if found:
                return found
    return ""


def config_from_dict(data: dict[str, Any], source: str = "config") -> StudyConfig:
    """Validate a dict (as parsed from TOML) into a StudyConfig, raising ConfigError."""
    try:
        return StudyConfig.model_validate(data)
    except ValidationError as exc:
        raise ConfigError.from_problems(validation_problems(exc, data), source) from None


def updated(config: StudyConfig, changes: Mapping[str, Any], source: str = "config") -> StudyConfig:
    """A copy of ``config`` with some fields changed, validated again (configs are immutable).

    Parameters
    ----------
    config : StudyConfig, str or Path
        The validated config to start from (unchanged), or a preset name or file to load it from.
    changes : mapping of str to value
        Dotted paths and their new values, e.g. ``{"reliability.n_mc": 50_000,
        "clearance_joints.B.friction.law": "none", "uncertainty.variables.HB_b.std_HB": 6.0}``. A list of
        named tables (bodies, joints, clearance joints, variables; drivers by their joint) is indexed by an item's
        name or by number, as ``clearance_joints.B`` or ``clearance_joints[0]``;
        the last key may carry a unit suffix as in TOML (``allowance_mm``), else the value is in SI. A value may
        be a section: a mapping is laid over it as ``extends`` lays a table (``{"reliability": {"max_calls": 40}}``
        changes that key alone), a section object (an SIModel) replaces it whole. Every path a random variable's
        ``target`` takes works too: a coordinate of a point (``mechanism.ground_points.C.x``; on a general linkage
        its closure tolerance widened by the move, as the study's samples are, so the point's joint partners stay
        where they are drawn and a crank pin moved out makes the crank longer with the rod as drawn) and a clearance
        joint's ``clearance`` (the bearing radius becomes the journal radius plus the value), with a unit suffix too
        (``clearance_joints.B.clearance_um``). These are set after the other changes and the clearances last
        (uncertainty.targets.apply_targets, as for a sample), so a clearance and a journal radius give
        R_i = R_j + c in either order.
    source : str
        Name of the config in messages.

    Returns
    -------
    StudyConfig
        The changed config, checked by the schema like a loaded one.

    Raises
    ------
    ConfigError
        A path that does not exist, or a changed config that the schema rejects (the message names the field).
    """
    if isinstance(config, (str, Path)):
        config = load_config(config)
    if not isinstance(config, StudyConfig):
        raise TypeError(f"updated: config must be a StudyConfig, a preset name or a file (got {type(config).__name__})")
    if not isinstance(changes, Mapping):
        raise TypeError(f"updated: changes must be a mapping of dotted paths to values (got {type(changes).__name__})")
    data = config.model_dump()
    targets: list[tuple[str, float]] = []  # the changes with a random variable's kind of path, set after the others
    changed: dict[int, set[str]] = {}  # id of a table -> the fields the changes set in it
    fitted: list[dict] = []  # the clearance tables given a fit
    correlated: list[dict] = []  # the correlation table, when entries of it are given
    for given, value in changes.items():
        path = _dotted(given)
        *parents, last = path.split(".")
        whole = isinstance(value, BaseModel)  # a section object replaces the table; a mapping is laid over it
        value = value.model_dump() if whole else value
        target = _target_path(data, path, source) if _is_number(value) else None
        if target is not None:  # a random variable's kind of path, perhaps with a unit suffix
            target_path, suffix = target
            targets.append((target_path, to_si(value, suffix) if suffix else value))
            continue
        node: Any = data
        walked: list[str] = []
        try:
            for key in parents:
                node = node[_list_index(node, key)] if isinstance(node, list) else node[key]
                walked.append(key)
            if isinstance(node, list):
                i = _list_index(node, last)
                laid = not whole and isinstance(value, Mapping) and isinstance(node[i], dict)
                node[i] = merge_tables(node[i], dict(value), path) if laid else value
                continue
        except (KeyError, IndexError, ValueError, TypeError):
            raise ConfigError(f"{source}: {path}: no such setting{_missing(node, parents[len(walked)], walked)}") \
                from None
        if not isinstance(node, dict):
            raise ConfigError(f"{source}: {path}: no such setting")
        split = split_unit_key(last, frozenset(node))
        if split is not None:  # the suffixed key replaces the SI one; the validation converts it
            node.pop(split[0])
        if not whole and isinstance(value, Mapping) and (isinstance(node.get(last), dict)
                                                         or _named_entries(node.get(last))):
            # as `extends` lays a table over its base: the keys the mapping does not give keep their values
            node[last] = merge_tables(node, {last: dict(value)}, ".".join(parents))[last]
        else:
            node[last] = value  # an unknown key is reported by the validation
        changed.setdefault(id(node), set()).update(_unit_stems(last))
        if last == "fit" and value is not None and parents[:2] == ["uncertainty", "clearance"]:
            fitted.append(node)
        if parents == ["uncertainty", "correlation"] and last in CORRELATION_ENTRIES:
            correlated.append(node)
    for node in fitted:
        _drop_fit_sets(node, changed[id(node)])
    for node in correlated:
        _drop_correlation_entries(node, changed[id(node)])
    for path, _ in targets:  # a later change may have replaced the table that held a target
        if (problem := target_error(data, path)) is not None:
            raise ConfigError(f"{source}: {problem}")
    apply_targets(data, targets)
    result = config_from_dict(data, source)
    before = setting_values(config)
    restore_given(result, {name for name, (value, _) in setting_values(result).items()
                           if before.get(name, (None, True))[1] or not _same_setting(value, before[name][0])})
    return result


def _same_setting(a: Any, b: Any) -> bool:
    """Whether two values of a setting are equal (a number within round-off of a unit there and back)."""
    if isinstance(a, float) and isinstance(b, (int, float)) and not isinstance(b, bool):
        return math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0) or a == b
    try:
        return bool(a == b)
    except (TypeError, ValueError):
        return False


def _drop_fit_sets(table: dict[str, Any], keep: set[str]) -> None:
    """A clearance table given a fit: drop the mean and grades the fit sets (ClearanceSpec.FIT_SETS), in any unit,
    except those in ``keep`` (given with the fit, which the schema then checks against it): kept from before, they
    would contradict the new fit."""
    for key in [k for k in table if _unit_stems(k) & set(ClearanceSpec.FIT_SETS) and not _unit_stems(k) & keep]:
        del table[key]


def _drop_correlation_entries(table: dict[str, Any], keep: set[str]) -> None:
    """A correlation table given entries (pairs, or variables and matrix): drop the others (CORRELATION_ENTRIES)
    except those in ``keep``: kept from before, entries of the other form would be refused as giving both forms."""
    for key in CORRELATION_ENTRIES - keep:
        table.pop(key, None)


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _target_path(data: dict[str, Any], path: str, source: str) -> tuple[str, str | None] | None:
    """(target, suffix) when ``path`` is a random variable's kind of target that is not a key of a table (a
    point's coordinate, a clearance joint's ``clearance``), or one with a unit suffix on its last key
    (``clearance_um``); else None: a table's key is set as written, and the schema checks its suffix as in a file
    (a variable's ``std_GPa`` on a length is refused there, by the target's unit)."""
    head, _, last = path.rpartition(".")
    if _is_table_key(data, head, last):
        return None
    if target_error(data, path) is None:
        return path, None
    for suffix in sorted(SUFFIXES, key=len, reverse=True):
        if last.endswith("_" + suffix) and head:
            base = last[: -len(suffix) - 1]
            if _is_table_key(data, head, base):
                return None
            if target_error(data, f"{head}.{base}") is None:
                problem = suffix_problem(last, base, suffix, target_unit(f"{head}.{base}"))
                if problem:
                    raise ConfigError(f"{source}: {head}.{problem}")
                return f"{head}.{base}", suffix
    return None


def _is_table_key(data: dict[str, Any], head: str, key: str) -> bool:
    """Whether ``head`` walks to a table (a dict) that holds ``key``."""
    node: Any = data
    try:
        for part in head.split(".") if head else []:
            node = node[_list_index(node, part)] if isinstance(node, list) else node[part]
    except (KeyError, IndexError, ValueError, TypeError):
        return False
    return isinstance(node, dict) and key in node


def _missing(node: Any, key: str, walked: list[str]) -> str:
    """' (clearance_joints has no item 'X'; its items: B)': what a path's missing key could have been."""
    where = ".".join(walked) or "the config"
    if isinstance(node, list):
        names = [str(item.get("name")) for item in node if isinstance(item, dict) and item.get("name") is not None]
        return f" ({where} has no item '{key}'; its items: {', '.join(names) or f'0 to {len(node) - 1}'})"
    if isinstance(node, dict):
        return f" ({where} has no key '{key}'; its keys: {', '.join(map(str, node))})"
    return ""


def _list_index(items: list, key: str) -> int:
    """The position of ``key`` in a list: a number, or the name of one of its tables (a driver's: its joint)."""
    if key.lstrip("-").isdigit():
        return int(key)
    names = [item.get("name", item.get("joint")) if isinstance(item, dict) else None for item in items]
    if key not in names:
        raise KeyError(key)
    return names.index(key)


def _parse_toml(text: str, source: str) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{source}: malformed TOML: {exc}") from None


#: Largest config file read (a config, or the file its ``extends`` names): real ones are a few kB, and a config
#: is read whole, so a path to a device or a huge file must not be.
MAX_CONFIG_BYTES = 1_000_000
#: Largest config.json read from a results folder (it holds the provenance beside the config: about 130 kB).
MAX_WRITTEN_CONFIG_BYTES = 16_000_000


def _read_config_file(path: Path, what: str = "config", limit: int = MAX_CONFIG_BYTES) -> bytes:
    """The bytes of a config file: a regular file (not a device, FIFO or folder) of at most ``limit`` bytes.
    ``what`` names the field in messages ('config', or 'a.toml: extends')."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # a FIFO must not block the open
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise ConfigError(f"{what}: '{path}' is not a regular file (expected a TOML file)")
            raw = f.read(limit + 1)
    except OSError as exc:
        raise ConfigError(f"{what}: cannot read file '{path}': {exc.strerror or exc}") from None
    if len(raw) > limit:
        raise ConfigError(f"{what}: file '{path}' is larger than {limit:,} bytes, the most a config file may be")
    return raw


def _read_source(source: str | Path, what: str = "config") -> tuple[dict[str, Any], str, Path | None]:
    """The parsed TOML of a preset name or a file, its name for messages and its folder (None for a preset)."""
    text_source = str(source)
    path = Path(text_source)
    is_pathlike = isinstance(source, Path) or text_source.endswith(".toml") or "/" in text_source or "\\" in text_source
    if not is_pathlike and not path.exists():
        names = available_presets()
        if text_source not in names:
            raise ConfigError(
                f"config: unknown preset '{text_source}' and no such file (available presets: {', '.join(names)})"
            )
        text = (resources.files("jointwear.presets") / f"{text_source}.toml").read_text(encoding="utf-8")
        return _parse_toml(text, f"preset {text_source}"), f"preset {text_source}", None
    raw = _read_config_file(path, what)
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark (Windows editors) is not TOML
    except UnicodeDecodeError:
        raise ConfigError(f"{what}: file '{path}' is not UTF-8 text (expected TOML)") from None
    return _parse_toml(text, str(path)), str(path), path.parent


#: a correlation's entries, in either of its two forms: a variation that gives them replaces the base's
CORRELATION_ENTRIES = frozenset(("pairs", "variables", "matrix"))


def merge_tables(base: dict[str, Any], override: dict[str, Any], where: str = "") -> dict[str, Any]:
    """``override`` laid over ``base``: tables merge key by key, anything else (numbers, strings, arrays and
    arrays of tables) replaces the base's value. A key replaces the base's key for the same field in another unit
    (``hardness_MPa`` over ``hardness_HB``), and a table over an array of named tables changes the entries it names
    (``[clearance_joints.B.bearing_material]`` over the base's ``[[clearance_joints]]``). A correlation's entries
    (pairs, or variables and matrix) replace the base's, in whichever form."""
    out = dict(base)
    for key, value in override.items():
        path = f"{where}.{key}" if where else key
        for other in [k for k in out if k != key and _unit_stems(k) & _unit_stems(key)]:
            del out[other]
        if key == "fit" and isinstance(value, str) and where.startswith("uncertainty.clearance"):
            _drop_fit_sets(out, {stem for k in override for stem in _unit_stems(k)})
        if where == "uncertainty" and key == "correlation" and isinstance(value, dict) and isinstance(
                out.get(key), dict) and CORRELATION_ENTRIES & value.keys():
            out[key] = dict(out[key])  # the base's own table stays as it is
            _drop_correlation_entries(out[key], set())
        current = out.get(key)
        if isinstance(value, dict) and isinstance(current, dict):
            out[key] = merge_tables(current, value, path)
        elif isinstance(value, dict) and _named_entries(current):
            out[key] = _merge_named(current, value, path)
        else:
            out[key] = value
    return out


def _unit_stems(key: str) -> set[str]:
    """The field names ``key`` can spell: itself, and its stem before any unit suffix (``length_mm``: length)."""
    return {key} | {key[: -len(s) - 1] for s in SUFFIXES if key.endswith("_" + s) and len(key) > len(s) + 1}


def _named_entries(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) and "name" in v for v in value)


def _merge_named(entries: list[dict], changes: dict[str, Any], where: str) -> list[dict]:
    """The array of named tables ``entries`` with the entries ``changes`` names changed (each a table)."""
    names = [str(v["name"]) for v in entries]
    unknown = [k for k in changes if k not in names]
    if unknown:
        raise ConfigError(f"{where}: {', '.join(repr(k) for k in unknown)} names no entry of the base's {where} "
                          f"(its entries: {', '.join(names)}); change one with [{where}.<name>.<key>], or give the "
                          f"whole list with [[{where}]]")
    bad = [k for k, v in changes.items() if not isinstance(v, dict)]
    if bad:
        raise ConfigError(f"{where}.{bad[0]}: expected a table of the entry's keys")
    return [merge_tables(v, changes[str(v["name"])], f"{where}.{v['name']}") if str(v["name"]) in changes else v
            for v in entries]


def _resolve(source: str | Path, chain: tuple[str, ...] = (), what: str = "config") -> tuple[dict[str, Any], str]:
    """The TOML data of ``source`` with its ``extends`` chain resolved (a preset name, or a path relative to the
    extending file); ``what`` names the field that gave ``source`` in messages."""
    data, name, folder = _read_source(source, what)
    return _extended(data, name, folder, chain), name


def _extended(data: dict[str, Any], name: str, folder: Path | None, chain: tuple[str, ...] = ()) -> dict[str, Any]:
    """``data`` laid over the config its ``extends`` names (a preset name, or a path relative to ``folder``)."""
    if name in chain:
        raise ConfigError(f"{name}: extends: circular ({' -> '.join(chain + (name,))})")
    base = data.pop("extends", None)
    if base is None:
        return data
    if not isinstance(base, str):
        raise ConfigError(f"{name}: extends: expected a preset name or a TOML path (got {base!r})")
    if folder is not None and (base.endswith(".toml") or "/" in base) and not Path(base).is_absolute():
        base = str(folder / base)
    base_data, _ = _resolve(base, chain + (name,), f"{name}: extends")
    try:
        return merge_tables(base_data, data)
    except ConfigError as exc:
        raise ConfigError(f"{name}: {exc}") from None


def load_config(source: str | Path | None = None) -> StudyConfig:
    """Load and validate a study config.

    A file may start from another config with ``extends = "<preset name or TOML path>"``: its tables are laid
    over the base's key by key (arrays, including arrays of tables, replace the base's; a key in another unit
    replaces the base's; ``[clearance_joints.B.bearing_material]`` changes the base's joint named B).

    Parameters
    ----------
    source : str, Path, StudyConfig, mapping or None
        A TOML file, a preset name (:func:`available_presets`), a config already validated (returned as is), the
        tables of a TOML file as a mapping (unit-suffixed keys and ``extends`` as in a file), a study's output
        folder or its ``config.json`` (the config that study ran), or None for the default preset
        ``jin2025_flapping_wing``.

    Returns
    -------
    StudyConfig
        The whole config in SI units.

    Raises
    ------
    jointwear.schema.ConfigError
        The file cannot be read or is not valid; the message names every field at fault.
    """
    if source is None:
        source = DEFAULT_PRESET
    if isinstance(source, StudyConfig):
        return source
    if isinstance(source, Mapping):  # the tables of a TOML file, e.g. built in a notebook
        bad = non_string_key(source)
        if bad:
            raise ConfigError(f"config: every key of the tables must be a str, as in a TOML file ({bad})")
        return config_from_dict(_extended(dict(source), "config", None), "config")
    if not isinstance(source, (str, Path)):
        raise ConfigError(f"config: expected a preset name, a TOML path, a StudyConfig or a mapping of TOML tables "
                          f"(got {type(source).__name__})")
    written = Path(source) / "config.json"
    if written.is_file():  # a study's output folder
        config = _written_config(written)
    elif Path(source).suffix == ".json":
        config = _written_config(Path(source))
    else:
        config = config_from_dict(*_resolve(source))
    config._origin = str(source)
    return config


def _written_config(path: Path) -> StudyConfig:
    """The config a study wrote to its folder (config.json's ``study_config``, SI units)."""
    import json

    raw = _read_config_file(path, limit=MAX_WRITTEN_CONFIG_BYTES)
    try:
        data = json.loads(raw.decode("utf-8"))
    except ValueError as exc:
        raise ConfigError(f"config: cannot read '{path}': {exc}") from None
    if not isinstance(data, dict) or "study_config" not in data:
        raise ConfigError(f"config: '{path}' holds no study config (a results folder's config.json written by "
                          "jointwear 0.x before the study config was kept there, or not a config.json)")
    config = config_from_dict(data["study_config"], str(path))
    settings = data.get("settings")
    if isinstance(settings, list) and settings and all(isinstance(r, dict) and "explicit" in r for r in settings):
        # the values the study's own config gave, as config.json records them: every value of study_config would
        # otherwise count as given, and a study run again from the folder would call its defaults the config's
        restore_given(config, {str(r.get("name")) for r in settings if r.get("explicit")})
    return config


def setting_children(model: BaseModel, prefix: str = ""):
    """Each field of ``model``: (its name, its setting's name as config.json and config errors write it, the sections
    under it or None for a value). A section is (model, its name, the key of a table of sections or None): a list's
    item goes by its name (``clearance_joints[A]``, :func:`jointwear.schema.item_key`), a table's by its key."""
    for name in type(model).model_fields:
        value = getattr(model, name)
        full = f"{prefix}.{name}" if prefix else name
        if isinstance(value, BaseModel):
            yield name, full, [(value, full, None)]
        elif isinstance(value, (list, tuple)) and value and all(isinstance(v, BaseModel) for v in value):
            names = [getattr(v, "name", None) for v in value]
            yield name, full, [(v, f"{full}[{item_key(i, names)}]", None) for i, v in enumerate(value)]
        elif isinstance(value, Mapping) and value and all(isinstance(v, BaseModel) for v in value.values()):
            yield name, full, [(v, f"{full}.{key}", str(key)) for key, v in value.items()]
        else:
            yield name, full, None


def setting_values(model: BaseModel, prefix: str = "", given: bool = True) -> dict[str, tuple[Any, bool]]:
    """Every setting of ``model`` by its name as config.json names it (``clearance_joints[A].width``): its value and
    whether the config gave it (its field and every section above it set, pydantic's ``model_fields_set``)."""
    out: dict[str, tuple[Any, bool]] = {}
    for name, full, sections in setting_children(model, prefix):
        here = given and name in model.model_fields_set
        if sections is None:
            out[full] = (getattr(model, name), here)
        else:
            for section, path, _ in sections:
                out.update(setting_values(section, path, here))
    return out


def restore_given(model: BaseModel, given: set[str], prefix: str = "") -> bool:
    """Leave in ``model``'s set fields (pydantic's ``model_fields_set``, what the config gave) only those whose
    settings, named as config.json names them, are in ``given``: a config validated again from a whole dump (a
    results folder's, a variation's) would otherwise count every default as given. Whether any is."""
    kept = False
    for name, full, sections in setting_children(model, prefix):
        here = (full in given if sections is None
                else any([restore_given(section, given, path) for section, path, _ in sections]))
        if not here:
            model.__pydantic_fields_set__.discard(name)
        kept = kept or here
    return kept


# ---------------------------------------------------------------------------------------------
# reference documentation
# ---------------------------------------------------------------------------------------------
def field_bounds(finfo) -> str:
    """A field's numeric bounds as the validator holds them ('>= 16', '> 0, <= 1'; '' without any), in SI."""
    symbols = {"ge": ">=", "gt": ">", "le": "<=", "lt": "<"}
    parts = [f"{symbols[name]} {getattr(m, name):g}" for m in finfo.metadata for name in symbols
             if isinstance(getattr(m, name, None), (int, float))]
    return ", ".join(parts)


def config_reference_markdown() -> str:
    """Markdown reference of every config section and field, generated from the pydantic models."""
    lines = [
        "# Configuration reference",
        "",
        "Generated by `jointwear.config.config_reference_markdown()`. Values are SI; a TOML key may carry a",
        "unit suffix (`length_mm`, `crank_speed_rpm`, `youngs_modulus_GPa`, `hardness_HB`, `crank_angle0_deg`, ...)",
        "that is converted to SI on load. Unknown keys are errors.",
        "",
        "A suffix must convert to its field's unit (the column *unit (SI)* below): `width_deg` is refused, and so is a",
        "suffix on a plain number. A random variable's `mean`, `std`, `lower` and `upper` take the unit of its",
        "`target` (`mean_HB` for a hardness, `std_um` for a length), and a reference value that of its quantity.",
        "Suffixes are case-sensitive.",
        "",
        "| SI unit | suffixes |",
        "|---|---|",
        *(f"| {u} | {', '.join(f'`_{s}`' for s in suffixes_of(u))} |"
          for u in dict.fromkeys(u for _, u in SUFFIXES.values())),
        "",
        f"`_HB` is Brinell hardness at {PA_PER_HB:g} Pa per HB (1 kgf/mm^2).",
        "",
    ]
    sections: list[tuple[str, type[BaseModel]]] = [
        ("(top level)", StudyConfig),
        ("mechanism (type = \"four_bar\")", FourBarConfig),
        ("mechanism (type = \"slider_crank\")", SliderCrankConfig),
        ("mechanism.crank / rod / rocker / slider", LinkConfig),
        ("mechanism (type = \"general\")", GeneralMechanismConfig),
        ("[[mechanism.bodies]] (general)", GeneralBodyConfig),
        ("[[mechanism.joints]] (general)", GeneralJointConfig),
        ("[[mechanism.drivers]] (general)", DriverConfig),
        ("[[clearance_joints]]", ClearanceJointConfig),
        ("clearance_joints.bearing_material / journal_material", MaterialConfig),
        ("clearance_joints.friction", FrictionConfig),
        ("simulation", SimulationConfig),
        ("wear", WearSettings),
        ("uncertainty", UncertaintySettings),
        ("uncertainty.clearance", ClearanceSpec),
        ("[[uncertainty.variables]]", RandomVariableSpec),
        ("uncertainty.correlation", CorrelationSpec),
        ("reliability", ReliabilitySettings),
        ("sensitivity", SensitivitySettings),
        ("compute", ComputeSettings),
        ("reference", ReferenceData),
        ("[[reference.values]]", ReferenceValue),
        ("reference.values.band", AcceptanceBand),
        ("design", DesignSettings),
        ("[[design.targets]]", DesignTarget),
        ("[[design.tolerances]]", ToleranceControl),
        ("design.fit (or [[design.fit]])", FitControl),
        ("[[design.fit.options]]", FitOption),
        ("[[design.properties]]", PropertyControl),
        ("[[design.properties.classes]]", PropertyClass),
        ("[[design.materials]]", MaterialControl),
        ("[[design.materials.options]]", MaterialOption),
        ("design.cost_model", CostModel),
    ]
    for title, model in sections:
        summary = " ".join((model.__doc__ or "").strip().split("\n\n")[0].split())  # the first paragraph, whole
        lines += [f"## {title}", "", summary, "",
                  "| key | unit (SI) | default | description |", "|---|---|---|---|"]
        for fname, finfo in model.model_fields.items():
            extra = finfo.json_schema_extra if isinstance(finfo.json_schema_extra, dict) else {}
            extra = extra or {}
            unit = extra.get("unit") or (f"of the {extra['unit_of']}" if extra.get("unit_of") else "")
            if finfo.is_required():
                default = "required"
            elif finfo.default_factory is not None:
                default = "(section)"
            else:
                default = f"`{finfo.default!r}`"
            desc = (finfo.description or "").replace("|", "\\|")
            bounds = field_bounds(finfo)
            if bounds:
                desc = f"{desc} Allowed: {bounds}."
            lines.append(f"| `{fname}` | {unit} | {default} | {desc} |")
        lines.append("")
    lines += ["## Presets", ""]
    for name in available_presets():
        cfg = load_config(name)
        lines.append(f"- `{name}`: {cfg.description} Source: {cfg.citation}")
    lines.append("")
    return "\n".join(lines)
