"""The report's sections about the nominal mechanism: its settings, its dynamics and its wear."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from jointwear.study.convergence import half_width
from jointwear.study.limit_state import nominal_lives
from jointwear.study.settings_record import named_paths, origin
from jointwear.study.superseded import SUPERSEDED
from jointwear.wear.angles import angle_text

from . import figures as F
from .alt_text import wear_history_alt, wear_polar_alt
from .markup import Figures, cards, e, format_number, missing, table
from .read import StudyOutputs, joint_series
from .reference_checks import (
    reference_label,
    reference_of,
    reference_values,
    second_peak,
)
from .style import scale_to_unit

__all__ = [
    "allowance_mm",
    "convergence_section",
    "dynamics_section",
    "not_run",
    "settings_section",
    "wear_section",
]


def not_run(out: StudyOutputs, stage: str, what: str) -> str:
    """The notice of a section whose stage has no result: why it could not be read, that its result was moved aside
    (computed with other settings: the latest such folder named), or that it has not run."""
    if stage in out.errors:
        return missing(out.errors[stage])
    moved = sorted(Path(out.out_dir).glob(f"{SUPERSEDED}/*/{stage}.json"))
    if moved:
        where = moved[-1].parent.relative_to(out.out_dir).as_posix()
        return missing(f"No {stage}.json in this folder: {what} has not been run with its current settings; its last "
                       f"result, computed with other settings, was moved to {where}/ (jointwear {stage} runs it "
                       "again).")
    return missing(f"No {stage}.json in this folder: {what} has not been run (jointwear {stage}).")


def allowance_mm(out: StudyOutputs, joint: str | None = None) -> float | None:
    """The allowable wear of ``joint`` (mm; default: the first judged joint): the study's settings first, then the
    stages' own; a judged joint after the first, the stages' per-joint record (the settings hold the first's)."""
    per_joint = joint_allowances(out)
    if joint is not None and str(joint) in per_joint and str(joint) != next(iter(per_joint)):
        return per_joint[str(joint)]
    for value in (out.config.get("allowance_mm"),
                  out.results.wear.limit_mm if out.results.wear is not None else None):
        if value is not None:
            return float(value)
    return None


def joint_allowances(out: StudyOutputs) -> dict[str, float]:
    """Each judged joint's allowable wear (mm) as the reliability stage resolved it (else the wear stage's): the
    settings record one value, the first joint's, beside per-joint allowances."""
    for result in (out.results.reliability, out.results.wear):
        joints = getattr(result, "joints", None) or []
        found = {str(j["name"]): float(j["allowance_mm"]) for j in joints
                 if j.get("name") is not None and j.get("allowance_mm") is not None}
        if found:
            return found
    return {}


def _settings_row(x: dict, value: str | None = None, told: dict[str, str] | None = None) -> tuple:
    """A row of a settings table with its source; ``told``: the descriptions given so far (text -> the setting whose
    row gave it), so that a description given above is not repeated: 'as for <that setting>' where that is shorter."""
    flag = '<span class="pill open">open</span>' if x.get("paper_open") else ""
    source = x.get("source") or "\u2014"
    desc = x.get("description") if x.get("description") != x.get("source") else None
    text = f"{source}\n{desc}" if desc else source
    first = (told or {}).get(text)
    if first is not None and first != x.get("name") and len(f"as for {first}") < len(text):
        src = e(f"as for {first}")
    else:
        if told is not None:
            told.setdefault(text, str(x.get("name")))
        src = e(source) + (f'<div class="desc">{e(desc)}</div>' if desc else "")
    return (e(x.get("name")), e(setting_text(x) if value is None else value), e(_unit_cell(x)), flag, src)


def _unit_cell(x: dict) -> str:
    """A setting's unit, beside a value that has one (not beside a dash: no value, no unit); a setting in degrees by
    its name (``peak_separation_deg``) says so too."""
    if x.get("value") is None or x.get("value") in ({}, []):
        return ""
    return str(x.get("unit") or ("deg" if str(x.get("name", "")).endswith("_deg") else ""))


#: a random input's fields that the Random inputs table shows
_RANDOM_INPUT_FIELDS = ("name", "label", "target", "group", "distribution", "mean", "std", "lower", "upper", "unit")


def in_random_inputs(records: list[dict], variables: list[dict]) -> set[str]:
    """The names of the settings ``uncertainty.variables[X].<field>`` whose values the Random inputs table shows as
    they read here (six digits, one unit; a std scaled by ``uncertainty.std_scale`` is not, so it stays listed; so
    does anything of a variable that table does not list)."""
    rows = {str(v.get("name")): v for v in variables}
    out = set()
    for r in records:
        m = re.fullmatch(r"uncertainty\.variables\[(.+)\]\.(\w+)", str(r.get("name")))
        if not m or m.group(1) not in rows or m.group(2) not in _RANDOM_INPUT_FIELDS:
            continue
        row, field, value = rows[m.group(1)], m.group(2), r.get("value")
        shown = row.get(field)
        if field == "label":
            same = value in ("", shown)  # an empty label is shown as the name
        elif field in ("mean", "std", "lower", "upper") and value is not None:
            same = (isinstance(shown, (int, float)) and str(r.get("unit") or "") == str(row.get("unit") or "")
                    and _entered(value) == _entered(shown))
        else:
            same = value == shown
        if same:
            out.add(str(r["name"]))
    return out


def _number(v: float) -> str:
    """A factor as a reader writes it: 9.807e6, 1e-9."""
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), f"{v:.6g}")


def _scale_text(x: dict, by_name: dict[str, dict]) -> str:
    """A random input's display scale with what it converts: '1e-09 (Pa -> GPa)', '1.01968e-07 (Pa -> HB; 1 HB =
    9.807e6 Pa)', or that it is unused (without a unit the variable is shown in its target's report unit)."""
    from jointwear.config import target_display_unit

    base = str(x["name"]).removesuffix(".scale")
    unit = (by_name.get(f"{base}.unit") or {}).get("value")
    value = x.get("value")
    if not unit:
        return f"{setting_text(x)} (unused: no display unit)"
    si = target_display_unit(str((by_name.get(f"{base}.target") or {}).get("value", ""))) or "SI"
    note = f"{si} -> {unit}"
    if isinstance(value, (int, float)) and value > 0 and not math.isclose(math.log10(value), round(math.log10(value)),
                                                                         abs_tol=1e-9):
        note += f"; 1 {unit} = {_number(1.0 / value)} {si}"
    return f"{setting_text(x)} ({note})"


def judged_joints(by_name: dict[str, dict]) -> list[str]:
    """The clearance joints the limit state judges, from the settings: ``reliability.joints``, or every one."""
    chosen = (by_name.get("reliability.joints") or {}).get("value")
    if isinstance(chosen, list) and chosen:
        return [str(j) for j in chosen]
    return [str(r.get("value")) for name, r in by_name.items()
            if re.fullmatch(r"clearance_joints\[[^\]]+\]\.name", name)]


def _surrogate_text(x: dict, by_name: dict[str, dict]) -> str:
    """``reliability.surrogate`` with what it learns for this study's judged joints: with one, its life is the
    system's whichever is set (reliability.json's ``life_surrogate``: 'system_life')."""
    n = len(judged_joints(by_name))
    value = x.get("value")
    if value == "per_joint" and n == 1:
        return "per_joint (one judged joint: one Kriging of its life, the system's)"
    if value == "per_joint" and n > 1:
        return f"per_joint ({n} judged joints: one Kriging of each joint's life)"
    if value == "system_life" and n >= 1:
        return f"system_life (one Kriging of the system's life{f', over {n} judged joints' if n > 1 else ''})"
    return setting_text(x)


def settings_value(x: dict, by_name: dict[str, dict]) -> str:
    """A setting's value as the settings tables show it: as entered, a random input's display scale with the units it
    converts between, and the surrogate with what it learns."""
    name = str(x.get("name"))
    if re.fullmatch(r"uncertainty\.variables\[.+\]\.scale", name):
        return _scale_text(x, by_name)
    if name == "reliability.surrogate":
        return _surrogate_text(x, by_name)
    if x.get("value") == "":
        return "(empty)"
    return setting_text(x)


def mean_cell(v: dict) -> str:
    """A random input's mean, and the value drawn at its target where that differs (the nominal stages run the
    drawn one; a shift under 0.1 standard deviations is not warned, but shown here)."""
    mean, drawn = v.get("mean"), v.get("drawn")
    if drawn is None or mean is None or abs(drawn - mean) <= 1e-9 * max(abs(mean), abs(drawn)):
        return _entered(mean)
    return f"{_entered(mean)} (drawn: {_entered(drawn)})"


def _distribution_cell(v: dict) -> str:
    """'normal', or e.g. 'truncated normal, >= 0.1; sampled: mean 2.059, std 0.9106' (bounds and a truncated normal's
    own moments in the row's unit: its mean and std columns are its parent normal's)."""
    text = str(v["distribution"]).replace("_", " ")
    lower, upper = v.get("lower"), v.get("upper")
    if lower is not None and upper is not None:
        text = f"{text}, {_entered(lower)} to {_entered(upper)}"
    elif lower is not None:
        text = f"{text}, >= {_entered(lower)}"
    elif upper is not None:
        text = f"{text}, <= {_entered(upper)}"
    if v["distribution"] == "truncated_normal" and v.get("sampled_mean") is not None:
        text += f"; sampled: mean {format_number(v['sampled_mean'])}, std {format_number(v['sampled_std'])}"
    return text


def setting_text(record: dict) -> str:
    """A setting's value as entered: six significant digits (a length of 18.7805 mm read 18.78 with the report's
    usual four, a list of them 18.780500000000004), and a seed as the integer it is (not 2,025)."""
    value = record.get("value")
    if str(record.get("name", "")).endswith("seed") and isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    return _entered(value)


def _entered(value) -> str:
    """A float to six significant digits without padding (1e-05, 18.7805), anything else as the report shows it."""
    if isinstance(value, float) and math.isfinite(value):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        if len(value) > 8:  # as format_number shortens a long list
            return f"[{', '.join(_entered(v) for v in value[:6])}, \u2026 ({len(value)} values)]"
        return "[" + ", ".join(_entered(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_entered(v)}" for k, v in value.items()) + "}"
    return format_number(value)


def settings_section(out: StudyOutputs, figs: Figures) -> str:
    cfg = out.results.config
    if cfg is None:
        return missing(out.errors.get("config") or "No config.json in this folder: the settings of the study are "
                                                    "not known to the report.")
    parts: list[str] = []
    if cfg.get("citation"):
        what = "the preset" if cfg.get("preset") else "the study's data"
        parts.append(f'<p class="citation"><b>Source of {what}:</b> {e(cfg["citation"])}</p>')
    meta = [(k, format_number(v)) for k, v in cfg.items()
            if k not in ("settings", "mechanism", "citation", "reference") and v is not None
            and not isinstance(v, (dict, list))]
    allowances = joint_allowances(out) or dict(cfg.get("allowances_mm") or {})
    if len(allowances) > 1 and len(set(allowances.values())) > 1:  # config.json records the first joint's alone
        meta = [(k, ", ".join(f"joint {j}: {format_number(a)}" for j, a in allowances.items()) + " (per joint)"
                 if k == "allowance_mm" else v) for k, v in meta]
    parts.append('<div class="grid"><div>')
    if meta:
        parts.append(table(["item", "value"], meta, cls="kv"))
    mech = cfg.get("mechanism")
    if mech and mech.get("type") == "general":
        rows = [("type", "general linkage"),
                ("bodies", ", ".join(b["name"] for b in mech.get("bodies", []))),
                ("joints", ", ".join(f'{j["name"]} ({j.get("type", "revolute")})' for j in mech.get("joints", []))),
                ("driven joints", ", ".join(mech.get("driven_joints", [])) or "\u2014"),
                ("clearance joints", ", ".join(mech.get("clearance_joints", [])) or "\u2014")]
        parts.append(table(["mechanism", "value"], rows, cls="kv"))
    elif mech:
        kinds = {"crank_rocker": "four_bar (a crank-rocker)"}  # as mechanism.type names it, below
        parts.append(table(["mechanism", "value"],
                           [(k, kinds.get(v, v) if k == "type" else format_number(v)) for k, v in mech.items()],
                           cls="kv"))
    parts.append("</div>")
    if mech and all(mech.get(k) is not None for k in ("crank_mm", "rod_mm", "rocker_mm", "pivot_mm")):
        parts.append(figs.draw(lambda: F.mechanism_figure(
            float(mech["crank_mm"]), float(mech["rod_mm"]), float(mech["rocker_mm"]), mech["pivot_mm"],
            branch=int(mech.get("branch", 1) or 1), clearance_joint=str(mech.get("clearance_joint", "A"))),
            "The mechanism at a crank angle of 45 deg, with ghosts over one crank turn; the clearance joint is ringed.",
            png_keys=("mechanism",)))
    elif mech and mech.get("type") == "slider_crank":
        parts.append(figs.draw(lambda: F.slider_crank_figure(
            float(mech["crank_mm"]), float(mech["rod_mm"]), offset_mm=float(mech.get("offset_mm", 0.0)),
            guide_angle_deg=float(mech.get("guide_angle_deg", 0.0)), branch=int(mech.get("branch", 1) or 1),
            clearance_joint=str(mech.get("clearance_joint", "B"))),
            "The mechanism at a crank angle of 45 deg, with ghosts over one crank turn; the clearance joint is ringed.",
            png_keys=("mechanism",)))
    elif mech and mech.get("type") == "general" and mech.get("bodies"):
        parts.append(figs.draw(lambda: F.linkage_figure(mech),
                               "The mechanism as drawn in its config (t = 0): bodies with their centres of mass (+), "
                               "ground points (triangles), the driven and the clearance joints ringed.",
                               png_keys=("mechanism",)))
    else:
        parts.append(figs.draw(None, "Mechanism sketch", png_keys=("mechanism",),
                               missing_text="Mechanism sketch: drawn for four-bar, slider-crank and general linkages."))
    parts.append("</div>")
    joints = clearance_joints_table(cfg.get("settings") or [])
    if joints:
        parts.append("<h3>Clearance joints: geometry and materials</h3>" + joints)
    variables = cfg.get("random_variables") or []
    if variables:
        parts.append(f"<h3>Random inputs ({len(variables)})</h3>")
        parts.append(table(
            ["variable", "name", "group", "distribution", "mean", "std", "COV", "unit", "sets"],
            [(str(v["label"]), str(v["name"]), str(v["group"]).replace("_", " "), _distribution_cell(v),
              mean_cell(v), _entered(v["std"]), format_number(v["cov"]),
              str(v["unit"]), str(v["target"])) for v in variables], cls="settings"))
        parts.append(correlation_part(cfg))
    recs = named_paths(list(cfg.get("settings") or []))  # an old folder's list items by their names, as today
    by_name = {str(x.get("name")): x for x in recs}
    shown_above = in_random_inputs(recs, variables)
    listed = [x for x in recs if str(x.get("name")) not in shown_above]
    otherwise = any(re.fullmatch(r"uncertainty\.variables\[.+\]\.(\w+)", str(x.get("name")))
                    and not str(x.get("name")).endswith(".scale") for x in listed)
    above = (f"<p>Each random input's {', '.join(_RANDOM_INPUT_FIELDS[:-1])} and {_RANDOM_INPUT_FIELDS[-1]} "
             f"({len(shown_above)} settings) are in Random inputs above and not repeated here; listed below are its "
             "display scale" + (" and each value that table shows otherwise (a std there is scaled by "
                                "uncertainty.std_scale)" if otherwise else "") + ".</p>" if shown_above else "")
    ref = reference_of(cfg)
    if ref:
        open_recs = [x for x in recs if x.get("paper_open")]
        told: dict[str, str] = {}
        parts.append(f"<h3>Settings the reference ({e(reference_label(ref))}) leaves open ({len(open_recs)})</h3>")
        parts.append("<p>Each value below is this project's baseline reading of the reference (see the user guide), "
                     "not a number printed in it; the source says where it comes from.</p>")
        if open_recs:
            parts.append(table(["setting", "value", "unit", "", "source"],
                               [_settings_row(x, settings_value(x, by_name), told) for x in open_recs],
                               cls="settings", raw_cols=(0, 1, 2, 3, 4), row_cls=["open"] * len(open_recs)))
        else:
            parts.append(missing("No setting is marked as left open by the reference."))
        told = {}
        parts.append(f"<details><summary>All {len(recs)} settings of this study</summary>{above}")
        parts.append(table(["setting", "value", "unit", "", "source"],
                           [_settings_row(x, settings_value(x, by_name), told) for x in listed],
                           cls="settings", raw_cols=(0, 1, 2, 3, 4),
                           row_cls=["open" if x.get("paper_open") else "" for x in listed]))
        parts.append("</details>")
    else:
        # no reference: the study's own values; where a default comes from is documented in docs/config.md
        rows = [(str(x.get("name")), settings_value(x, by_name), _unit_cell(x), origin(x)) for x in listed]
        n_set = sum(x.get("explicit") is True for x in recs)
        parts.append(f"<h3>Settings of this study ({len(recs)}, {n_set} given in the config)</h3>")
        parts.append("<p>Values not given in the config are jointwear's defaults; <code>jointwear check CONFIG</code> "
                     "prints them and docs/config.md says where each comes from.</p>")
        parts.append(f"<details open><summary>All {len(recs)} settings of this study</summary>{above}")
        parts.append(table(["setting", "value", "unit", "from"], rows, cls="settings"))
        parts.append("</details>")
    parts.append(provenance_part(out))
    return "".join(parts)


def correlation_pairs(cfg: dict) -> list[tuple[str, str, float]]:
    """The correlated pairs of random inputs the config records ([uncertainty.correlation]: its ``pairs``, or the
    off-diagonal non-zero terms of its ``matrix`` over its ``variables``)."""
    from jointwear.uncertainty.variables import CorrelationSpec

    corr = (((cfg or {}).get("study_config") or {}).get("uncertainty") or {}).get("correlation")
    if not corr:
        return []
    spec = CorrelationSpec.model_validate(corr)  # as the study read it
    names = spec.names()
    matrix = spec.full_matrix(names)
    return [(a, b, float(matrix[i, j])) for i, a in enumerate(names) for j, b in enumerate(names)
            if i < j and matrix[i, j]]


def correlation_part(cfg: dict) -> str:
    """A line under the random inputs' table: the correlated pairs and the measure, or that the inputs are
    independent."""
    pairs = correlation_pairs(cfg)
    if not pairs:
        return "<p>The random inputs are independent (no [uncertainty.correlation]).</p>"
    measure = ((cfg.get("study_config") or {}).get("uncertainty") or {}).get("correlation", {}).get("measure")
    told = ", ".join(f"{a} and {b}: {r:+.3g}" for a, b, r in pairs)
    return (f"<p><b>Correlated inputs</b> ([uncertainty.correlation]{f', {measure}' if measure else ''}): {e(told)}; "
            "the others are independent. The correlation is part of the population the life is computed on.</p>")


_STAGE_NAMES = {"simulate": "simulate", "wear": "wear", "wear_convergence": "converge", "reliability": "reliability",
                "sensitivity": "sensitivity", "validation": "validate", "design": "design"}


def provenance_line(out: StudyOutputs) -> str:
    """'results by jointwear 0.1.0+gf75291d on znver3 (2 CPUs)' from the first result's provenance, saying so where
    the stages' code or CPU differ; '' without a result."""
    records = [getattr(out.results, stage).provenance or {} for stage in out.results.stages
               if getattr(getattr(out.results, stage), "provenance", None)]
    if not records:
        return ""
    keys = {(r.get("jointwear"), (r.get("machine") or {}).get("llvm_host_cpu")) for r in records}
    first = records[0]
    machine = first.get("machine") or {}
    cpus = f" ({machine['cpus']} CPUs)" if machine.get("cpus") else ""
    return (f"results by jointwear {first.get('jointwear', '?')} on {machine.get('llvm_host_cpu') or '?'}{cpus}"
            + ("; the stages differ (see Study and settings)" if len(keys) > 1 else ""))


def provenance_part(out: StudyOutputs) -> str:
    """Which code, machine and seeds produced each result: every stage's recorded provenance (the jointwear
    version with its commit, the CPU the kernels were compiled for, the versions of Python, numpy, scipy, numba
    and openturns, when it was written), the study's seed and the validation's seed and sample count."""
    rows = []
    for stage in out.results.stages:
        prov = getattr(getattr(out.results, stage), "provenance", None) or {}
        if not prov:
            continue
        machine = prov.get("machine") or {}
        cpu = machine.get("llvm_host_cpu") or "\u2014"
        cpu += f", {machine['cpus']} CPUs" if machine.get("cpus") else ""
        versions = ", ".join(f"{k} {prov[k]}" for k in ("python", "numpy", "scipy", "numba", "openturns")
                             if prov.get(k))
        rows.append((_STAGE_NAMES.get(stage, stage), str(prov.get("jointwear") or "\u2014"), cpu, versions or "\u2014",
                     str(prov.get("written_at") or "\u2014").replace("T", " ")))
    if not rows:
        return ""
    seeds = []
    if (seed := out.results.setting("reliability.seed")) is not None:
        seeds.append(f"the study's seed {seed} (reliability.seed)")
    val = out.results.validation
    if val is not None:
        seeds.append(f"the validation's seed {val.seed if val.seed is not None else 'not recorded'} and its "
                     f"{val.n_samples:,} samples")
    return ("<h3>Provenance</h3><p>The code (jointwear's version with its commit), the CPU its kernels were compiled "
            "for and the libraries each result was computed with: results can differ between CPUs and versions."
            + (f" Seeds: {e('; '.join(seeds))}." if seeds else "") + "</p>"
            + table(["stage", "jointwear", "host CPU", "versions", "written"], rows, cls="kv"))


#: a clearance joint's settings shown per part (bearing, journal), with their heading
_PART_COLUMNS = (("body", "body"), ("material.name", "material"), ("material.youngs_modulus", "Young's modulus"),
                 ("material.poissons_ratio", "Poisson's ratio"), ("material.hardness", "hardness"),
                 ("material.wear_coefficient", "wear coefficient k"), ("radius", "radius"))


def clearance_joints_table(records: list[dict]) -> str:
    """The nominal geometry and the materials of each clearance joint, bearing and journal side by side in a row each,
    from the study's settings records ('' when it has none): the numbers a designer checks first, which were only in
    the list of every setting."""
    records = named_paths(records)  # a folder written when items went by their index reads as one written today
    by_name = {str(r.get("name")): r for r in records}
    joints = [name.removesuffix(".name") for name in by_name
              if name.startswith("clearance_joints[") and name.endswith("].name") and name.count(".") == 1]
    rows, units = [], {}
    for joint in joints:
        width = by_name.get(f"{joint}.width")
        for part in ("bearing", "journal"):
            cells = []
            for key, _heading in _PART_COLUMNS:
                record = by_name.get(f"{joint}.{part}_{key}")
                units.setdefault(key, (record or {}).get("unit"))
                cells.append(setting_text(record) if record is not None else "\u2014")
            rows.append((str(by_name[f"{joint}.name"]["value"]), part, *cells,
                         setting_text(width) if width and part == "bearing" else ""))  # the joint's, once
            units.setdefault("width", (width or {}).get("unit"))
    if not rows:
        return ""
    headings = [heading + (f" ({units[key]})" if units.get(key) else "")
                for key, heading in (*_PART_COLUMNS, ("width", "width"))]
    return table(["joint", "part", *headings], rows, cls="settings")


def warning(title: str, sentence: str) -> str:
    """A warning paragraph: a bold title, then the sentence capitalised."""
    return f'<p class="warn"><strong>{e(title)}</strong> {e(sentence[:1].upper() + sentence[1:])}.</p>'


def dynamics_section(out: StudyOutputs, figs: Figures) -> str:
    sim = out.results.simulate
    if sim is None:
        return not_run(out, "simulate", "the dynamics stage")

    # one prefix for both forces, set by the peak: 29 mN on the flapping wing, 203 N on a pump
    raw = [sim.contact_force_mean_N, sim.contact_force_max_N]
    scaled, force_unit = scale_to_unit([math.nan if v is None else v for v in raw], "N")
    mean_force, peak_force = ("\u2014" if v is None else f"{x:.4g} {force_unit}" for v, x in zip(raw, scaled))

    first = f" (joint {sim.joints[0]['name']})" if len(sim.joints) > 1 else ""
    parts = [warning("Outside the contact law's range.", sentence) for sentence in sim.outside_hertz()]
    parts += [warning("Friction-driven whirl.", sentence) for sentence in sim.whirls()]
    parts += [cards([
        ("mean contact force" + first, mean_force, None),
        ("peak contact force" + first, peak_force, None),
        ("contact fraction", format_number(sim.contact_fraction, 3), "share of the cycle in contact"),
        ("impacts per cycle", format_number(sim.impacts_per_cycle, 3), None),
        ("steps per cycle", format_number(sim.steps_per_cycle), "over the recorded cycles"),
        ("wall time per cycle", "\u2014" if sim.wall_seconds_per_cycle is None
         else f"{sim.wall_seconds_per_cycle * 1e3:.3g} ms", None),
    ])]
    parts.append(table(["other result", "value"], [
        ("kernel", sim.kernel or "\u2014"), ("cycles simulated", format_number(sim.cycles)),
        ("settling cycles", format_number(sim.settle_cycles)), ("crank period (s)", format_number(sim.period_s)),
        ("accepted / rejected steps (settling included)",
         f"{format_number(sim.accepted_steps)} / {format_number(sim.rejected_steps)}"),
        ("clearance joints", ", ".join(str(j["name"]) for j in sim.joints) or "\u2014")], cls="kv"))
    if len(sim.joints) > 1:
        parts.append(joints_dynamics_table(sim.joints))
    series = joint_series(out.out_dir, sim)
    name = series.name if series is not None else ""
    clearance = sim.joints[0]["clearance_m"] * 1e3 if sim.joints else None
    parts.append('<div class="grid">')
    parts.append(figs.draw(
        None if series is None else (lambda: F.orbit_figure(series.eccentricity_bearing_frame_m[:, 0] * 1e3,
                                                            series.eccentricity_bearing_frame_m[:, 1] * 1e3,
                                                            clearance)),
        f"Journal centre orbit of joint {name} relative to the bearing centre, in the frame of the bearing body; "
        "dashed: the clearance circle.", png_keys=joint_png_keys(("orbit",), name),
        missing_text=f"Journal orbit: no series file ({sim.series_file})."))
    parts.append(figs.draw(
        None if series is None else (lambda: F.contact_force_figure(np.degrees(series.crank_angle_rad),
                                                                    series.force_normal_N,
                                                                    mean_N=sim.contact_force_mean_N)),
        f"Normal contact force in clearance joint {name} against the crank angle"
        + (f", the {format_number(sim.cycles)} recorded cycles overlaid (after {format_number(sim.settle_cycles)} "
           f"settling cycle{'' if sim.settle_cycles == 1 else 's'}); their spread is the contact's cycle-to-cycle "
           "variation"
           if sim.cycles and sim.cycles > 1 else "") + ".",
        png_keys=joint_png_keys(("contact_force", "force"), name),
        missing_text=f"Contact force: no series file ({sim.series_file})."))
    parts.append("</div>")
    return "".join(parts)


def joint_png_keys(keys: tuple[str, ...], joint: str | None) -> tuple[str, ...]:
    """The stage files a figure of ``joint`` drawn here stands for: its own (``orbit_K``) before any of the kind, so
    that a second joint's file (``orbit_C``, sorting first) is not taken for it and stays in the appendix."""
    return (*(f"{key}_{joint}".lower() for key in keys), *keys) if joint else keys  # stems are matched lower-case


def joints_dynamics_table(joints: list[dict]) -> str:
    """Every clearance joint's contact over the recorded cycles (a mechanism with several)."""
    rows = [(str(j["name"]), f"{j.get('bearing_body', '')} / {j.get('journal_body', '')}",
             format_number(j.get("contact_force_mean_N")), format_number(j.get("contact_force_max_N")),
             format_number(j.get("contact_fraction"), 3), format_number(j.get("impacts_per_cycle"), 3),
             format_number(None if j.get("max_penetration_m") is None else j["max_penetration_m"] * 1e6),
             format_number(None if j.get("clearance_m") is None else j["clearance_m"] * 1e6)) for j in joints]
    return "<h3>Every clearance joint</h3>" + table(
        ["joint", "bearing / journal", "mean contact force (N)", "peak contact force (N)", "contact fraction",
         "impacts per cycle", "max penetration (\u00b5m)", "clearance (\u00b5m)"], rows, cls="num")


def joints_wear_table(joints: list[dict]) -> str:
    """Every clearance joint's wear at the end of the history (a mechanism with several)."""
    rows = [(str(j["name"]), format_number(j.get("max_wear_mm")),
             "\u2014" if j.get("max_wear_angle_deg") is None else angle_text(j["max_wear_angle_deg"], 1),
             format_number((j.get("journal") or {}).get("max_wear_mm")), format_number(j.get("allowance_mm")),
             format_number(j.get("conformity"), 3)) for j in joints]
    return "<h3>Every clearance joint</h3>" + table(
        ["joint", "max bearing wear (mm)", "at angle (deg)", "journal max wear (mm)", "allowance (mm)",
         "conformity"], rows, cls="num")


_UNIFORM_WARNING = (
    '<p class="warn"><strong>Uniform mode is outside its range here.</strong> The worn pocket is wider than the '
    "contact patch (conformity {conformity} &gt; 1): the journal fits into its own wear, the pressure spreads and "
    "the depth grows more slowly than uniform mode assumes: its depths are too deep and the lives from them too "
    "short, by a factor only a profile-mode study tells (its interval does not include this error). Run the "
    'study with <code>wear.geometry_mode = "profile"</code>, whose wear follows the pocket (docs/wear.md).</p>')


def wear_section(out: StudyOutputs, figs: Figures) -> str:
    wear = out.results.wear
    if wear is None:
        return not_run(out, "wear", "the wear stage")
    parts: list[str] = []
    if wear.uniform_out_of_range:
        parts.append(_UNIFORM_WARNING.format(conformity=e(format_number(wear.conformity, 3))))
    parts += [warning("Worn away.", s) for s in wear.worn_away()]
    parts += [warning("Worn through.", s) for s in wear.worn_through()]
    quantity = out.results.setting("reliability.quantity") or "bearing_max_depth"
    parts += [warning("Worn past the allowance where it is not judged.", s) for s in wear.unjudged_wear(quantity)]
    parts += [warning("Friction-driven whirl.", s) for s in wear.whirls()]
    sp = second_peak(wear)
    floor = float(wear.settings.get("peak_prominence", 0.05)) * (wear.max_wear_mm or 0.0)
    if sp is not None and not sp[1] >= floor:  # what is left far from the main peak is not a wear zone of its own
        second = ("none", "a single wear zone")
    else:
        second = ("\u2014", None) if sp is None else (f"{sp[1]:.4g} mm", f"at {angle_text(sp[0])} deg")
    first = f" (joint {wear.joints[0]['name']})" if len(wear.joints) > 1 else ""
    items = [
        ("cycles of the history", format_number(wear.cycles), simulated_note(wear)),
        ("max bearing wear" + first, f"{format_number(wear.max_wear_mm)} mm", None),
        ("at angle", f"{angle_text(wear.max_wear_angle_deg, 1)} deg", "0 deg = leftmost, clockwise"),
        ("second peak", *second),
        ("wall time", "\u2014" if wear.wall_seconds is None else f"{wear.wall_seconds:.3g} s",
         "of the history; the stage also builds the model and draws its figures"),
        ("geometry mode", wear.geometry_mode, None),
    ]
    life = nominal_life_card(wear, quantity, first)
    if life is not None:
        items.append(life)
    if wear.journal.get("max_wear_mm") is not None:
        items.append(("journal max wear", f"{wear.journal['max_wear_mm']:.4g} mm", "over the pin's circumference"))
    if wear.conformity is not None and math.isfinite(wear.conformity):
        items.append(("conformity", format_number(wear.conformity, 3),
                      "worn arc / contact patch; profile mode follows the worn shape at any value: the answer to trust"
                      if wear.geometry_mode == "profile" else "worn arc / contact patch; up to 1 uniform mode's "
                      "depths are fair, above it too deep"))
    parts.append(cards(items))
    if len(wear.joints) > 1:
        parts.append(joints_wear_table(wear.joints))
    prof = wear.profile
    head = str(wear.joints[0]["name"]) if wear.joints else None  # the joint the profile and history are of
    ang, depth = np.asarray(prof["angle_deg"], dtype=float), np.asarray(prof["depth_mm"], dtype=float)
    radius = wear.joints[0].get("bearing_radius_mm") if wear.joints else None
    parts.append('<div class="grid">')
    parts.append(figs.draw(
        None if ang.size == 0 else (lambda: F.wear_polar_figure(ang, depth, radius_mm=radius, peaks=wear.peaks,
                                                                cycles=wear.cycles)),
        "Bearing wear profile over the initial circle" + (f" of joint {wear.joints[0]['name']}" if first else "")
        + "; the radial exaggeration factor is written on the figure.",
        png_keys=joint_png_keys(("polar",), head), missing_text="Polar wear profile: the wear result has no profile.",
        alt=wear_polar_alt(ang, depth)))
    several = len(wear.joints) > 1
    for j in wear.joints[1:]:
        jp = j.get("profile") or {}
        jang, jdepth = (np.asarray(jp.get(k, []), dtype=float) for k in ("angle_deg", "depth_mm"))
        parts.append(figs.draw(
            None if jang.size == 0 else (lambda j=j, jang=jang, jdepth=jdepth: F.wear_polar_figure(
                jang, jdepth, radius_mm=j.get("bearing_radius_mm"), peaks=j.get("peaks"), cycles=wear.cycles,
                title=f"Bearing wear profile of joint {j['name']} after {wear.cycles:,.0f} cycles")),
            f"Bearing wear profile of joint {j['name']} over the initial circle.", alt=wear_polar_alt(jang, jdepth),
            png_keys=(f"polar_{j['name']}".lower(),),
            missing_text=f"Polar wear profile of joint {j['name']}: not in this wear result."))
    rel = out.results.reliability
    mean_all = rel.mean_max_wear_mm if rel is not None else {}
    # the mean is the first judged joint's (the histograms name it), which need not be the first clearance joint
    mean_joint = str((rel.histograms or {}).get("joint") or head) if rel is not None else head
    mean = mean_all if mean_joint == head else {}
    limit = allowance_mm(out)
    ref = reference_of(out.config)
    label = reference_label(ref)
    ref_mean = {float(v["cycles"]): float(v["value"]) for v in reference_values(ref, "mean_max_wear")}
    nominal = next(((float(v["cycles"]), float(v["value"])) for v in reference_values(ref, "nominal_max_wear")), None)
    parts.append(figs.draw(
        lambda: F.wear_history_figure(wear.history["cycles"], wear.history["max_wear_mm"], limit_mm=limit,
                                      mean_cycles=mean.get("cycles"), mean_max_wear_mm=mean.get("mean"),
                                      reference_mean=ref_mean or None, reference_nominal=nominal,
                                      reference_label=label, joint=head if several else None),
        _history_caption(head if several else None, bool(mean.get("mean")),
                         label if ref_mean or nominal else None, limit),
        png_keys=joint_png_keys(("history",), head),
        alt=wear_history_alt(wear.history["cycles"], wear.history["max_wear_mm"], limit)))
    for j in wear.joints[1:]:  # each joint's own history, standing for its stage file (wear_history_C.png)
        h = j.get("history") or {}
        jlimit = j.get("allowance_mm")
        jmean = mean_all if mean_joint == str(j["name"]) else {}
        parts.append(figs.draw(
            (lambda h=h, j=j, jlimit=jlimit, jmean=jmean: F.wear_history_figure(
                h["cycles"], h["max_wear_mm"], limit_mm=jlimit, mean_cycles=jmean.get("cycles"),
                mean_max_wear_mm=jmean.get("mean"), joint=str(j["name"]))) if h.get("cycles") else None,
            _history_caption(str(j["name"]), bool(jmean.get("mean")), None, jlimit),
            png_keys=(f"history_{j['name']}".lower(),),
            alt=wear_history_alt(h.get("cycles", []), h.get("max_wear_mm", []), jlimit),
            missing_text=f"Wear history of joint {j['name']}: not in this wear result."))
    parts.append("</div>")
    for j in wear.joints or [{"profile": prof}]:
        parts.append(_panels(figs, wear, j, str(j["name"]) if several else None))
    if wear.peaks:
        parts.append("<h3>Wear peaks</h3>")
        parts.append(table(["angle (deg)", "depth (mm)"], [(angle_text(p["angle_deg"], 1),
                                                            format_number(p["depth_mm"])) for p in wear.peaks],
                           cls="kv"))
    return "".join(parts)


def simulated_note(wear) -> str | None:
    """How many of the history's cycles were simulated as dynamics, and what a fraction of a cycle is ('84.5 of them
    simulated ...: each of the 28 wear blocks settles 1 and records 2 cycles; the half: ...'); None where all
    were."""
    n = wear.n_simulated_cycles
    if not n or n >= wear.cycles:
        return None
    settle, record = (wear.settings.get(k) for k in ("settle_cycles", "record_cycles"))
    text = f"{format_number(n)} of them simulated as dynamics"
    if wear.n_blocks and settle is not None and record is not None:
        text += (f": each of the {wear.n_blocks:,} wear blocks settles {float(settle):g} and records "
                 f"{float(record):g} crank cycles")
    if n != int(n):  # wear/history.py: a second lane's first block settles lane / lanes of a cycle longer
        text += ("; the fraction is a second chain of blocks started part of a cycle later, at another phase "
                 "(wear.lanes)")
    return text + "; the cycles between carry the recorded wear rates"


def _history_caption(joint: str | None, mean: bool, reference: str | None, limit: float | None) -> str:
    """The caption of a joint's wear history figure."""
    return ("Max bearing wear" + (f" of joint {joint}" if joint else "") + " against cycles: the nominal design"
            + (", the mean over the random inputs (read from the life surrogate as allowance \u00d7 N / N_f(x): "
               "linear in N by construction, exact at the allowance)" if mean else "")
            + (f", the values of the reference ({reference})" if reference else "")
            + (f" and the configured allowance ({limit:g} mm, dashed)." if limit is not None else "."))


def _panels(figs: Figures, wear, joint: dict, name: str | None) -> str:
    """Sliding, force, area and wear depth against the bearing angle of one joint (``name``: said in the caption
    and title with several joints), standing for that joint's stage file."""
    prof = joint.get("profile") or {}
    keys = joint_png_keys(("fig17", "panels", "vs_angle"), str(joint.get("name")) if joint.get("name") else None)
    of = f" of joint {name}" if name else ""
    if "contact_force_mean_N" not in prof:
        return figs.draw(None, f"Wear{of} against the angle", png_keys=keys,
                         missing_text=f"Wear{of} against the angle (sliding, force, area): not in this wear result.")
    return figs.draw(lambda: F.wear_panels_figure(
        np.asarray(prof["angle_deg"], dtype=float), np.asarray(prof["depth_mm"], dtype=float), cycles=wear.cycles,
        slip_mm=prof["sliding_mm_per_deg_per_cycle"], slip_unit="mm/deg per cycle", slip_quantity="sliding distance",
        contact_force_N=prof["contact_force_mean_N"], contact_area_mm2=prof["contact_area_mean_mm2"], joint=name),
        f"Sliding distance, mean contact force, mean contact area and bearing wear depth{of} against the angle on "
        "the bearing.", png_keys=keys, wide=True)


def nominal_life_card(wear, quantity: str, first: str):
    """The card of the cycles at which the nominal history reaches the first joint's allowance in the limit state's
    measure ``quantity`` (None without an allowance, or where the history stops growing)."""
    joint = wear.joints[0] if wear.joints else {}
    allowance = joint.get("allowance_mm")
    if allowance is None:
        return None
    life = nominal_lives([joint], {str(joint.get("name")): allowance}, str(quantity)).get(str(joint.get("name")))
    if life is None or not math.isfinite(life):
        return None
    how = "extrapolated linearly past the history's end" if life > wear.cycles else "read off the history"
    return ("nominal life" + first, f"{format_number(life)} cycles", f"to the allowance of {allowance:.3g} mm; {how}")


def convergence_section(out: StudyOutputs) -> str:
    """The nominal history's convergence in its numerical settings (``jointwear converge``)."""
    conv = out.results.wear_convergence
    life = conv.measure == "life"
    scale, unit = (1.0, "cycles") if life else (1e3, "mm")
    what = "nominal life" if life else "final wear"
    head = cards([
        (what, f"{format_number(conv.baseline['mean'] * scale)} {unit}",
         f"mean of {conv.replicates} histories from other start phases"),
        ("start-to-start scatter", f"{100 * conv.scatter:.1f} %", "standard deviation / mean of those histories"),
        ("resolution", f"\u00b1{100 * conv.resolution:.1f} %",
         f"95 % interval of a change with {conv.replicates} replicates (tolerance \u00b1{100 * conv.tolerance:g} %)"),
    ])
    rows = []
    several = bool(conv.baseline.get("joints"))
    for r in conv.refinements:
        row = [r["name"], conv.changed_text(r, arrow="\u2192"), format_number(r["mean"] * scale),
               f"{100 * r['change']:+.1f} % \u00b1 {100 * half_width(r):.1f} %"]
        if several:
            row += [r.get("system_verdict", r["verdict"]), "; ".join(
                f"{joint} {100 * j['change']:+.1f} % \u00b1 {100 * half_width(j):.1f} % {verdict}"
                for joint, _, j, _, verdict in conv.subjects(r)[1:])]
        rows.append(row + [r["verdict"]])
    heads = ["setting", "refined", f"{what} ({unit})", "change (95 %)"]
    heads += [f"{what} verdict", "each joint's own (95 %)"] if several else []
    body = table(heads + ["verdict"], rows)
    lead = (f"<p>The nominal history to {conv.cycles:,} cycles with the study's wear settings and with each "
            f"numerical setting refined {conv.factor:g}x, {conv.replicates} histories each. A change is "
            "<em>converged</em> when its 95 % interval lies inside the tolerance, <em>not converged</em> when it "
            "lies outside, <em>no change detected</em> when it holds zero but the replicates cannot resolve the "
            "tolerance, <em>undecided</em> otherwise. A refinement that changes nothing at one factor may still "
            "matter at a larger one (docs/wear.md, \u201cIs my history converged?\u201d)."
            + (" With several judged joints each joint's own measure is judged too, and a setting's verdict is the "
               "worst of them: a joint that does not govern the nominal life still sets its share of R(N)."
               if several else "") + "</p>")
    warns = "".join(warning("Convergence:", s) for s in conv.sentences())
    return head + warns + lead + body
