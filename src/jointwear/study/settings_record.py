"""The study's resolved settings as recorded in the output folder, ``config.json``: resume, staleness and the
report read it.

Contract (every key optional; the report lists whatever is there)::

    {"name": "my_linkage",                           # the study's name (its config's `name`)
     "preset": "jin2025_flapping_wing" | null,       # preset name, or null for a TOML file
     "source": "preset" | "path/to/study.toml" | "python",   # "python": a StudyConfig or a mapping
     "citation": "...",                              # the preset's citation
     "jointwear_version": "0.1.0", "seed": 2025,     # any other top-level scalars are listed too
     "mechanism": {"type": "crank_rocker", "crank_mm": 6.0, "rod_mm": 38.0, "rocker_mm": 12.0,
                   "pivot_mm": [11.5, 38.0], "branch": 1, "clearance_joint": "A"},
     "settings": [{"name": "clearance_joints[A].friction.mu_d", "value": 0.1, "unit": null,  # an item by its name
                   "source": "<the field's docstring: where the value comes from>",
                   "paper_open": true, "description": "...",
                   "explicit": false,                  # given in the config (true) or a default (false)
                   "derived_from": "fit 'H7/g6'"}, ...],  # only for a value another setting sets
     "allowance_mm": 0.03,                           # the limit state's allowable wear (every joint) and
     "allowances_mm": {"E": 0.04},                   # per-joint overrides, from [reliability]
     "reference": null | {"citation": "...", "label": "Jin et al. 2025", "note": "...",
                          "values": [{"quantity": "reliability", "value": 0.739, "unit": "", "cycles": 400000,
                                      "target_reliability": null, "group": null, "ranking": null,
                                      "source": "Section 6.2.2 and Fig. 21", "note": "",
                                      "band": {"kind": "absolute", "absolute": 0.15, "relative": null,
                                               "lower": null, "upper": null, "justification": "..."}}, ...]}}

``reference`` is the config's ``[reference]`` (:class:`jointwear.reference.ReferenceData`) in report units (mm,
deg, h); the report compares with it, and only with it: without one there is no comparison.

:func:`settings_dump` builds it from the validated pydantic config (and any stage settings models), so each
setting carries the description its field already has; :func:`write_settings` writes it. A field is marked
``paper_open`` when its ``json_schema_extra`` says so, otherwise when its description says the value is not from
the paper (``paper-notes``, ``paper silent``, ``not fixed by the paper``, ``project choice``, ...).
Values are shown in report units: lengths in mm, moduli in GPa / MPa, hardness in HB, speeds in rpm where the
unit is rad/s of a crank; a random variable's numbers (its mean, std and bounds, a design class's of it, a clearance's
mean, minimum and Table 5 std) all in the one unit the random-inputs table gives it (:func:`variable_display`).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from jointwear.config import display_unit, setting_children
from jointwear.schema import item_key
from jointwear.units import scaled, suffix_factor, to_display

__all__ = [
    "is_paper_open",
    "named_paths",
    "origin",
    "random_variables",
    "settings_dump",
    "settings_records",
    "variable_display",
    "write_settings",
]

#: a clearance's own numbers (its distribution's), shown in its display unit; its nominal diameter stays in mm
CLEARANCE_VALUES = ("mean", "minimum", "table5_std")

_OPEN = re.compile(
    r"paper[- ]notes|paper (is )?silent|paper gives no|not (fixed|given|stated) (by|in) the paper|project choice|"
    r"paper leaves|assumed|baseline|not in the paper|no value in the paper|convergence study",
    re.IGNORECASE,
)


def is_paper_open(description: str | None, extra: Mapping | None = None) -> bool:
    """Whether a setting is one the paper leaves open: explicit ``paper_open`` in the field's schema extra,
    else read from its description."""
    if extra and "paper_open" in extra:
        return bool(extra["paper_open"])
    return bool(description and _OPEN.search(description))


def _plain(v: Any) -> Any:
    if isinstance(v, (str, int, float, bool)) or v is None:
        return v
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    if isinstance(v, Path):
        return str(v)
    try:  # numpy scalars
        return v.item()
    except AttributeError:
        return str(v)


def settings_records(model: Any, prefix: str = "", *, explicit: bool = True,
                     variable_units: Mapping[str, tuple[float, str | None]] | None = None,
                     variable: str | None = None, dimension: str | None = None) -> list[dict]:
    """Flatten a pydantic model into ``{"name", "value", "unit", "source", "paper_open", "description",
    "explicit"}``; ``explicit`` is whether the config gave the value (False: a default). A random variable's numbers,
    and a design specification's of it, are shown in that variable's display unit (:func:`variable_display`, as the
    random-inputs table gives them); a reference value's (and its band's) in its quantity's report unit (mm, deg, h:
    ``jointwear.reference.DISPLAY``)."""
    from jointwear.reference import DISPLAY, in_report_unit

    if variable_units is None:
        variable_units = _variable_units(model)
    # this model's own numbers in its variable's display unit: a random variable's, a clearance's
    own = variable_units.get(model.name) if isinstance(getattr(model, "target", None), str) and isinstance(
        getattr(model, "name", None), str) else None
    variable = getattr(model, "variable", None) if isinstance(getattr(model, "variable", None), str) else variable
    dimension = getattr(model, "dimension", None) if isinstance(getattr(model, "dimension", None), str) else dimension
    deeper = {"variable_units": variable_units, "variable": variable, "dimension": dimension}
    out: list[dict] = []
    fields = type(model).model_fields
    given = getattr(model, "model_fields_set", set())
    derived = model.derived_settings() if callable(getattr(model, "derived_settings", None)) else {}
    for name, full, sections in setting_children(model, prefix):
        value, info = getattr(model, name), fields[name]
        here = explicit and name in given
        if sections is not None:
            for section, path, key in sections:  # a table of sections (a material option's by variable) sets it
                out += settings_records(section, path, explicit=here,
                                        **(deeper if key is None else {"variable_units": variable_units,
                                                                       "variable": key}))
            continue
        extra = info.json_schema_extra if isinstance(info.json_schema_extra, Mapping) else {}
        unit = extra.get("unit")
        display = None  # (factor, unit) of a variable's numbers
        if own is not None and (extra.get("unit_of") == "target" or (unit == "m" and name in CLEARANCE_VALUES)):
            display = own
        elif extra.get("unit_of") == "target" and isinstance(getattr(model, "target", None), str):
            unit = display_unit(model.target)  # a variable the config does not list: its target's unit
        elif extra.get("unit_of") == "variable" and variable is not None:
            display = variable_units.get(variable)
        elif name == "hardness" and unit == "Pa":
            unit = "HB"
        if extra.get("unit_of") == "quantity" and dimension in DISPLAY and type(value) in (int, float):
            shown, shown_unit = in_report_unit(value, dimension)  # a reference value: 12.9 h, not 46440 (s)
            shown_unit = shown_unit or None
        elif display is not None:
            shown, shown_unit = scaled(_plain(value), display[0]), display[1] or None
        else:
            shown, shown_unit = to_display(_plain(value), unit)
        desc = info.description or ""
        set_by = derived.get(name) if explicit else None
        out.append({
            "name": full,
            "value": shown,
            "unit": shown_unit,
            "source": extra.get("source") or desc,
            "paper_open": is_paper_open(desc, extra),
            "description": desc if extra.get("source") else "",
            "explicit": here or set_by is not None,
            **({"derived_from": set_by} if set_by else {}),
        })
    return out


def named_paths(records: Sequence[Mapping]) -> list[dict]:
    """``records`` with every list item named as :func:`settings_records` names it (:func:`jointwear.schema.item_key`),
    read off their own ``...[i].name`` records: a config.json written when items went by their index
    ('uncertainty.variables[3].std' -> 'uncertainty.variables[HB_b].std') reads as one written today."""
    lists: dict[str, dict[int, Any]] = {}
    for r in records:
        if m := re.fullmatch(r"(.*)\[(\d+)\]\.name", str(r.get("name", ""))):
            lists.setdefault(m.group(1), {})[int(m.group(2))] = r.get("value")
    keys = {}
    for path, by_index in lists.items():
        names = [by_index.get(i) for i in range(max(by_index) + 1)]
        keys |= {f"{path}[{i}]": f"[{item_key(i, names)}]" for i in by_index}

    def renamed(name: str) -> str:
        out, last = [], 0
        for m in re.finditer(r"\[\d+\]", name):  # each index looked up by the path up to it, as written
            out.append(name[last:m.start()] + keys.get(name[:m.end()], m.group(0)))
            last = m.end()
        return "".join(out) + name[last:]

    return [{**r, "name": renamed(str(r["name"]))} if "name" in r else dict(r) for r in records]


def recorded_settings(source: str | Path) -> list[dict] | None:
    """The settings records a study's folder keeps (``source``: the folder or its ``config.json``), list items named
    as today (:func:`named_paths`); None when ``source`` is neither, or its file cannot be read."""
    path = Path(source)
    path = path / "config.json" if path.is_dir() else path
    if path.suffix != ".json" or not path.is_file():
        return None
    try:
        return named_paths(json.loads(path.read_text(encoding="utf-8"))["settings"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def listed_settings(config: Any, source: str | Path | None = None) -> tuple[list[dict], bool]:
    """:func:`settings_records` of ``config`` and whether ``source`` is a study's folder (or its config.json). For a
    folder, where each value came from is read off its records: the config it keeps sets every value, its records
    know which were defaults; a setting they do not record (the reference's, the study's name) or record without
    ``explicit`` (an old folder) has ``explicit`` None (:func:`origin`: a dash)."""
    records = settings_records(config)
    recorded = None if source is None else recorded_settings(source)
    if recorded is None:
        return records, False
    origins = {r["name"]: {"explicit": r.get("explicit"), "derived_from": r.get("derived_from")}
               for r in recorded if isinstance(r, Mapping) and "name" in r}
    return [{**r, **origins.get(r["name"], {"explicit": None, "derived_from": None})} for r in records], True


def origin(record: Mapping) -> str:
    """Where a setting's value comes from, by its record's ``explicit``: 'the config' or 'jointwear default' (a dash
    for a record written before ``explicit`` was), or what in the config set it ("set by fit 'H7/g6'")."""
    if record.get("derived_from"):
        return f"set by {record['derived_from']}"
    return {True: "the config", False: "jointwear default"}.get(record.get("explicit"), "\u2014")


def variable_display(spec: Any) -> tuple[float, str | None]:
    """(factor from SI, unit) of a random variable's numbers, one for its mean, std and bounds: its own ``unit`` and
    ``scale`` when it gives a unit (a unit keys take as a suffix by its exact factor: the config holds ``scale`` to
    it within 1e-3), else its target's report unit (mm, HB, GPa or MPa by the size of its mean)."""
    if getattr(spec, "unit", ""):
        exact = suffix_factor(spec.unit)
        return (spec.scale if exact is None else 1.0 / exact), spec.unit
    probe = abs(spec.mean) if spec.mean else 1.0
    shown, unit = to_display(probe, display_unit(spec.target))
    return shown / probe, unit


def _variable_units(config: Any) -> dict[str, tuple[float, str | None]]:
    """Each random variable's :func:`variable_display`, the clearances' too, by name, from a study config; empty for
    a section."""
    unc = getattr(config, "uncertainty", None)
    if unc is None or not hasattr(unc, "all_specs"):
        return {}
    return {spec.name: variable_display(spec) for spec in unc.all_specs()}


def _general_mechanism(mech: Any, joints: list) -> dict:
    """A general linkage as drawn (global coordinates at t = 0, mm): what the report's sketch needs."""

    def mm(v) -> list[float]:
        return [float(v[0]) * 1e3, float(v[1]) * 1e3]

    ground = {k: mm(v) for k, v in mech.ground_points.items()}
    bodies = [{"name": b.name, "points_mm": {k: mm(v) for k, v in b.points.items()}, "com_mm": mm(b.com)}
              for b in mech.bodies]
    points = {f"ground.{k}": v for k, v in ground.items()}
    for b in bodies:
        points.update({f"{b['name']}.{k}": v for k, v in b["points_mm"].items()})
    return {
        "type": "general",
        "ground_mm": ground,
        "bodies": bodies,
        "joints": [{"name": j.name, "type": j.type, "at_mm": points.get(j.connects[0]),
                    **({"direction": [float(j.direction[0]), float(j.direction[1])]}
                       if j.type == "prismatic" and j.direction is not None else {})} for j in mech.joints],
        "driven_joints": [d.joint for d in mech.drivers],
        "clearance_joints": [str(cj.joint) if cj.name == cj.joint else f"{cj.name} (at {cj.joint})" for cj in joints],
    }


def _clearance_name(joints: Sequence) -> dict:
    """The clearance joint's own name, which the results use, where it differs from its mechanism joint's."""
    return {"clearance_joint_name": str(joints[0].name)} if joints and joints[0].name != joints[0].joint else {}


def _mechanism(config: Any) -> dict | None:
    mech = getattr(config, "mechanism", None)
    if mech is not None and getattr(mech, "type", None) == "general":
        return _general_mechanism(mech, getattr(config, "clearance_joints", []) or [])
    if mech is not None and getattr(mech, "type", None) == "slider_crank":
        joints = getattr(config, "clearance_joints", []) or []
        return {"type": "slider_crank", "crank_mm": mech.crank.length * 1e3, "rod_mm": mech.rod.length * 1e3,
                "offset_mm": mech.offset * 1e3, "guide_angle_deg": math.degrees(mech.guide_angle),
                "branch": int(mech.assembly_branch), "clearance_joint": str(joints[0].joint) if joints else "",
                **_clearance_name(joints)}
    if mech is None or getattr(mech, "type", None) != "four_bar":
        return None
    try:
        o = mech.crank_pivot
        c = mech.rocker_pivot
        joints = getattr(config, "clearance_joints", []) or []
        return {
            "type": "crank_rocker",
            "crank_mm": mech.crank.length * 1e3,
            "rod_mm": mech.rod.length * 1e3,
            "rocker_mm": mech.rocker.length * 1e3,
            "pivot_mm": [(c[0] - o[0]) * 1e3, (c[1] - o[1]) * 1e3],
            "branch": int(mech.assembly_branch),
            "clearance_joint": str(joints[0].joint) if joints else "",
            **_clearance_name(joints),
        }
    except AttributeError:
        return None


def settings_dump(config: Any, *sections: tuple[str, Any], preset: str | None = None, source: str | None = None,
                  **extra: Any) -> dict:
    """The ``config.json`` contract from the validated config and any ``(name, settings_model)`` of the stages.

    ``extra`` top-level scalars (for example ``seed=2025``) are added as given.
    """
    from jointwear import __version__

    name = getattr(config, "name", None)
    settings = [r for r in settings_records(config) if r["name"] not in ("name", "citation", "description")
                and not r["name"].startswith("reference")]
    for sec_name, model in sections:
        if model is not None:
            settings += settings_records(model, sec_name)
    out: dict[str, Any] = {
        "name": name,
        "preset": preset,
        "source": source or ("preset" if preset else "config"),
        "citation": getattr(config, "citation", "") or "",
        "jointwear_version": __version__,
    }
    out.update({k: _plain(v) for k, v in extra.items()})
    mech = _mechanism(config)
    if mech:
        out["mechanism"] = mech
    out.update(_allowances(config))
    out["settings"] = settings
    out["random_variables"] = random_variables(config)
    ref = getattr(config, "reference", None)
    out["reference"] = ref.report_dict() if hasattr(ref, "report_dict") else None
    if hasattr(config, "model_dump"):  # the whole validated config, SI: load_config(folder) gives it back
        out["study_config"] = config.model_dump(mode="json")
    return out


def random_variables(config: Any) -> list[dict]:
    """The study's random inputs in report units: ``name``, ``label``, ``group``, ``distribution``, ``target``,
    ``mean``, ``std``, ``cov`` (std / |mean|), ``lower``, ``upper``, ``unit``, ``drawn`` (the value the config
    draws at the target, which the nominal stages run; None where it cannot be read), and ``sampled_mean``,
    ``sampled_std`` (the moments of what is drawn: a truncated normal's mean and std are its parent normal's). The
    unit is the variable's own display unit (``unit`` and ``scale``) when it gives one, else its target's, shown as
    the settings are (mm, MPa, ...)."""
    from jointwear.uncertainty.targets import target_error, target_value

    unc = getattr(config, "uncertainty", None)
    if unc is None or not hasattr(unc, "all_specs"):
        return []
    data = config.model_dump() if hasattr(config, "model_dump") else {}
    rows = []
    for spec in unc.all_specs():
        factor, unit = variable_display(spec)

        def conv(v: float | None) -> float | None:
            return None if v is None else v * factor

        rows.append({"name": spec.name, "label": spec.label or spec.name, "group": spec.group,
                     "distribution": spec.distribution, "target": spec.target, "mean": conv(spec.mean),
                     "std": conv(spec.std), "cov": spec.std / abs(spec.mean) if spec.mean else None,
                     "lower": conv(spec.lower), "upper": conv(spec.upper), "unit": unit or "",
                     "drawn": None if not data or target_error(data, spec.target) else conv(target_value(data,
                                                                                                       spec.target)),
                     **sampled_moments(spec, conv)})
    return rows


def sampled_moments(spec, conv) -> dict:
    """``sampled_mean``, ``sampled_std`` of a variable as drawn, converted by ``conv``: a truncated normal's own (its
    ``mean`` and ``std`` are its parent normal's: the flapping wing's clearance, 2 um and 0.97 um, is drawn with
    2.06 um and 0.91 um), every other distribution's ``mean`` and ``std``."""
    if spec.distribution != "truncated_normal":
        return {"sampled_mean": conv(spec.mean), "sampled_std": conv(spec.std)}
    drawn = spec.frozen()
    return {"sampled_mean": conv(float(drawn.mean())), "sampled_std": conv(float(drawn.std()))}


def _allowances(config: Any) -> dict:
    """The limit state's allowable wear in mm: ``allowance_mm`` of the first judged joint (the one the report's
    wear figures show) and ``allowances_mm`` of every judged joint, by name, as the study resolves them."""
    try:
        from jointwear.study.limit_state import limit_state_from_config

        limit = limit_state_from_config(config)
    except Exception:  # not a StudyConfig, or a limit state the study itself will reject with its own message
        return {}
    names = list(getattr(limit, "names", []) or [])
    # a joint without an allowance (no [reliability] allowance, no bushing wall) has none to report
    allowances = [float(f"{float(a) * 1e3:.12g}") if a is not None else math.nan
                  for a in getattr(limit, "allowances", ())]
    if not allowances:
        return {}
    out: dict[str, Any] = {"allowance_mm": allowances[0]} if math.isfinite(allowances[0]) else {}
    if len(names) == len(allowances) and any(math.isfinite(a) for a in allowances):
        out["allowances_mm"] = {n: a for n, a in zip(names, allowances) if math.isfinite(a)}
    return out


def write_settings(out_dir: Path | str, config: Any, *sections: tuple[str, Any], filename: str = "config.json",
                   **kw: Any) -> Path:
    """Write :func:`settings_dump` to ``out_dir / "config.json"``; returns the path."""
    return write_dump(out_dir, settings_dump(config, *sections, **kw), filename=filename)


def write_dump(out_dir: Path | str, dump: dict, *, filename: str = "config.json") -> Path:
    """Write a :func:`settings_dump` already made to ``out_dir / filename``; returns the path."""
    from jointwear.study.io import write_text_atomic

    return write_text_atomic(Path(out_dir) / filename, json.dumps(dump, indent=1, default=str))
