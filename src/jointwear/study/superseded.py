"""Results computed with other settings than their folder records now: moved aside, so none is shown as current.

A study folder records one config, ``config.json``, which every stage rewrites with the settings it runs with; the
report, :func:`jointwear.load_results` and :func:`jointwear.compare_studies` read every result in the folder as
computed with those settings. So before a stage rewrites it, each result that depends on a setting that changed (a
validation of the old curve after ``reliability.allowance`` changed; every result after a wear-model setting
changed) is moved to ``superseded/<time>/`` with its tables and figures (and the report built from it).
"""

from __future__ import annotations

import datetime as _dt
import json
import re
import shutil
from pathlib import Path
from typing import Any

from jointwear.study.model_call import WearModelCall
from jointwear.study.results import stage_types
from jointwear.study.stage_result import same_value

__all__ = ["DEPENDS_ON", "SUPERSEDED", "changed_settings", "move_aside", "result_files", "section", "stale_stages"]

SUPERSEDED = "superseded"
_MODEL = WearModelCall.MODEL_SECTIONS
_RELIABILITY = (*_MODEL, "uncertainty", "reliability")
#: the config sections (the first part of a config.json setting name) each stage's result depends on: its own and
#: those of what it is built from (sensitivity, validation and design are read off the reliability curve)
DEPENDS_ON: dict[str, tuple[str, ...]] = {
    "simulate": ("mechanism", "clearance_joints", "simulation"),
    "wear": _MODEL,
    "wear_convergence": _MODEL,
    "reliability": _RELIABILITY,
    "sensitivity": (*_RELIABILITY, "sensitivity"),
    "validation": _RELIABILITY,
    "design": (*_RELIABILITY, "design"),
}
#: settings of a section a stage depends on that the stage does not read: the dynamics reads no wear property
NOT_READ_BY: dict[str, re.Pattern] = {"simulate": re.compile(r"_material\.(wear_coefficient|hardness)$")}
#: settings no stage computes with, only the report shows: a random input's label, a material's name (a renamed
#: label moved every result aside, to be read back from the store); the sensitivity records the labels it drew with
DISPLAY_ONLY = re.compile(r"^uncertainty\..*\.label$|_material\.name$")
LABELS_RECORDED_BY = ("sensitivity",)
# the figures each stage's save() draws (its JSON, tables and ``files`` are read off the result itself)
_FIGURES: dict[str, tuple[str, ...]] = {
    "simulate": ("orbit_*.png", "force_*.png"),
    "reliability": ("reliability_curve.png", "wear_histograms.png", "convergence.png"),
    "sensitivity": ("sensitivity_tornado.png", "sensitivity_sobol.png"),
    "validation": ("validation.png", "cross_validation.png"),
    "design": ("design_pareto.png",),
}


def section(name: str) -> str:
    """The config section of a config.json setting name: 'clearance_joints[0].bearing_radius' -> 'clearance_joints'."""
    return name.split(".")[0].split("[")[0]


def _in_si(value: Any, unit: str | None) -> Any:
    """A recorded setting in SI, so that a folder written with other display units (a hardness once shown in GPa,
    now in HB) compares by value."""
    from jointwear.units import SUFFIXES, UnitError, to_si

    if not unit or unit not in SUFFIXES:
        return value
    try:
        return to_si(value, unit)
    except UnitError:
        return value


def changed_settings(folder: Path, settings: list[dict]) -> list[str] | None:
    """The settings (config.json records: ``name``, ``value``, ``unit``) whose values differ from those
    ``folder/config.json`` records, in the order of ``settings`` then the recorded ones; None when the folder records
    no config (or one that cannot be read)."""
    from jointwear.study.settings_record import named_paths, recorded_settings

    # list items by their names, also in a folder written when they went by their index
    recorded = recorded_settings(folder) if Path(folder).is_dir() else None
    if recorded is None:
        return None
    try:
        before = {r["name"]: _in_si(r.get("value"), r.get("unit")) for r in recorded}
    except (ValueError, KeyError, TypeError):
        return None
    now = {r["name"]: _in_si(json.loads(json.dumps(r.get("value"), default=str)), r.get("unit"))
           for r in named_paths(settings)}
    names = list(now) + [name for name in before if name not in now]
    return [name for name in names  # rtol: a display unit there and back
            if not same_value(now.get(name), before.get(name), rtol=1e-12)]


def stale_stages(folder: Path, changed: list[str]) -> list[str]:
    """The stages with a result in ``folder`` that depend on a setting in ``changed``, in the order of the study."""
    def reads(stage: str, name: str) -> bool:
        ignored = NOT_READ_BY.get(stage)
        shown_only = DISPLAY_ONLY.search(name) and stage not in LABELS_RECORDED_BY
        return (section(name) in DEPENDS_ON[stage] and not shown_only
                and not (ignored is not None and ignored.search(name)))

    types = stage_types()
    return [stage for stage in DEPENDS_ON
            if any(reads(stage, name) for name in changed) and (Path(folder) / types[stage].FILE).is_file()]


def result_files(folder: Path, stage: str) -> list[Path]:
    """The files of ``stage``'s result in ``folder``: its JSON, its tables, its figures and series."""
    folder = Path(folder)
    cls = stage_types()[stage]
    names = {cls.FILE}
    result = cls.load_if_present(folder)
    if result is not None:
        names |= {f"{stem}.csv" for stem in result.tables()}
        names |= {str(n) for n in [*(getattr(result, "files", None) or []), getattr(result, "series_file", None)]
                  if n and Path(str(n)).name == str(n)}  # names in the folder only, never a path out of it
    paths = {folder / name for name in names} | {p for pattern in _FIGURES.get(stage, ()) for p in folder.glob(pattern)}
    return sorted(p for p in paths if p.is_file())


def move_aside(folder: Path, stages: list[str]) -> Path:
    """Move the files of ``stages``' results, and ``report.html`` (built from them), to a new
    ``folder/superseded/<UTC time>/`` with a copy of ``config.json`` (the settings they ran with, which the stage
    about to run rewrites); returns that folder."""
    folder = Path(folder)
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    dest = folder / SUPERSEDED / stamp
    k = 1
    while dest.exists():  # two moves within a second keep both
        k += 1
        dest = folder / SUPERSEDED / f"{stamp}-{k}"
    dest.mkdir(parents=True)
    files = [p for stage in stages for p in result_files(folder, stage)]
    for path in [*files, folder / "report.html"]:
        if path.is_file():
            path.replace(dest / path.name)
    if (folder / "config.json").is_file():  # the settings the moved results ran with, for load_results and compare
        shutil.copy2(folder / "config.json", dest / "config.json")
    return dest
