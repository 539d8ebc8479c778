"""Finished studies side by side: the life at one target reliability with its 95 % interval, whether two lives
differ beyond their errors, the nominal wear and the settings that differ (``jointwear compare``).

Two lives differ beyond their errors when their 95 % intervals (:meth:`ReliabilityCurve.life_interval`) do not
overlap. The intervals cover the error of each study's estimate of R(N), not the wear model's assumptions
(docs/study.md, "How far to trust the life"): two studies that differ in those are compared as they stand.
"""

from __future__ import annotations

import html
import json
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from jointwear.schema import ConfigError
from jointwear.study.io import provenance, write_text_atomic
from jointwear.study.limit_state import intervals_overlap, life_status
from jointwear.study.reliability_results import interval_cells, reliability_target
from jointwear.study.results import StudyResults, load_results
from jointwear.study.stage_result import StageResult, same_value, save_figure
from jointwear.units import in_unit

__all__ = ["StudyComparison", "compare_studies", "life_verdict"]

#: settings that name or describe a study rather than set it
_NOT_SETTINGS = {"name", "citation", "description"}


def life_verdict(low: float | None, high: float | None, base_low: float | None, base_high: float | None) -> str:
    """'longer' or 'shorter' when the interval [low, high] lies wholly above or below the baseline's
    [base_low, base_high], else 'within the errors' (an end that is None reaches as far as it may: give the ends of
    :func:`~jointwear.study.limit_state.interval_reach` to bound one outside its curve by its side)."""
    if intervals_overlap(low, high, base_low, base_high):
        return "within the errors"
    return "shorter" if high is not None and base_low is not None and high < base_low else "longer"


@dataclass(repr=False, eq=False)  # StageResult compares by value
class StudyComparison(StageResult):
    """Several studies at one target reliability ``target``; the first is the baseline.

    ``studies``: one row per study: ``label``, ``folder``, ``geometry_mode``, the life at the target
    (``life_cycles``, ``life_cycles_low``, ``life_cycles_high``: its 95 % interval; ``life_hours``; ``status``:
    'in_curve', 'beyond_curve' or 'before_curve'), ``life_ratio`` (to the baseline's life), ``verdict`` against the
    baseline (:func:`life_verdict`; 'baseline' for the first), ``model_calls``, ``converged``, the nominal
    ``max_wear_mm`` after ``wear_cycles`` (the first joint's; ``max_wear_mm_by_joint``: every joint's),
    ``uniform_out_of_range`` (uniform mode past its range: docs/wear.md) and,
    when the study was validated, ``validation_levels_agreeing`` of its ``validation_levels`` (the curve's levels
    whose 95 % interval overlaps the true model's, sampled directly) and ``validation_levels_passing_95`` (those that
    pass the 95 % test of the difference: :meth:`ValidationResult.differs_at_95`), with its ``validation_samples`` and
    the ``validation_resolution`` in R they give (:attr:`ValidationResult.resolution`), and ``settings_recorded``
    (False for a folder without config.json, whose settings are not compared: :meth:`unrecorded_note`).
    ``differences``: every setting whose value differs between the studies (``name``, ``unit``, ``values`` in the
    order of ``studies``; None where a study has no such setting), in the units of the config files.
    ``curves``: each study's R(N) (``cycles``, ``reliability``, ``half_width``: the 95 % half-width of R).
    """

    FILE: ClassVar[str] = "comparison.json"

    target: float
    studies: list[dict]
    differences: list[dict] = field(default_factory=list)
    curves: list[dict] = field(default_factory=list)
    provenance: dict = field(default_factory=provenance)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    @property
    def labels(self) -> list[str]:
        """Each study's label, in the order given."""
        return [s["label"] for s in self.studies]

    def __repr__(self) -> str:
        """The table of :meth:`markdown` (the field-by-field repr showed ``studies=<list of 2>``)."""
        return f"StudyComparison of {len(self.studies)} studies\n{self.markdown()}"

    def _repr_html_(self) -> str:
        """The comparison's tables in a notebook: the lives, then the settings that differ."""
        from jointwear.report.comparison_page import lives_table, settings_table

        return (f"<p>Life at R = {self.target:g}; the first study, {html.escape(self.labels[0])}, is the "
                f"baseline.</p>{lives_table(self)}{settings_table(self)}")

    def tables(self) -> dict[str, dict[str, Any]]:
        """``comparison`` (one row per study) and ``comparison_settings`` (one row per setting that differs, a
        column per study)."""
        keys = [k for k in self.studies[0] if k != "folder"] + ["folder"] if self.studies else []
        def cell(value):  # a table of numbers as JSON, which a script reads back (a dict's repr it could not)
            return json.dumps(value) if isinstance(value, dict) else value

        out = {"comparison": {k: [cell(s.get(k)) for s in self.studies] for k in keys}}
        settings: dict[str, list] = {"setting": [d["name"] for d in self.differences],
                                     "unit": [d.get("unit") or "" for d in self.differences]}
        for i, label in enumerate(self.labels):
            settings[label] = [_shown(d["values"][i]) for d in self.differences]
        out["comparison_settings"] = settings
        return out

    #: the columns of :meth:`rows`
    COLUMNS: ClassVar[tuple[str, ...]] = ("study", "life (cycles)", "95 % interval", "ratio", "against the baseline",
                                          "max wear (mm)", "model calls", "wear mode", "validated")

    def rows(self) -> list[tuple[str, ...]]:
        """One row of text per study, in the order of :attr:`COLUMNS` (the Markdown and HTML tables)."""
        out = []
        for s in self.studies:
            life = _cycles(s["life_cycles"]) if s["life_cycles"] is not None else s["status"].replace("_", " ")
            ratio = "\u2014" if s["life_ratio"] is None else f"{s['life_ratio']:.3f}"
            by_joint = s.get("max_wear_mm_by_joint") or {}
            wear = ("\u2014" if s["max_wear_mm"] is None
                    else f"{s['max_wear_mm']:.4g} at {s['wear_cycles']:,}" if len(by_joint) < 2
                    else ", ".join(f"{value:.4g} ({name})" for name, value in by_joint.items())
                    + f" at {s['wear_cycles']:,}")
            mode = s["geometry_mode"] or "\u2014"
            if s["uniform_out_of_range"]:
                mode += " (outside its range)"
            elif mode == "uniform" and s["max_wear_mm"] is None:
                mode += " (its range not checked: no wear stage)"
            validated = ("\u2014" if s["validation_levels"] is None
                         else f"{s['validation_levels_agreeing']} of {s['validation_levels']} levels agree "
                              f"({s['validation_levels_passing_95']} by the 95 % test"
                              + (f"; {s['validation_samples']:,} samples resolve R to "
                                 f"\u00b1{s['validation_resolution']:.2g})" if s.get("validation_samples") else ")"))
            calls = str(s["model_calls"]) + ("" if s.get("converged", True) else " (not converged)")
            interval = ("\u2014" if s["life_cycles"] is None
                        else interval_cells(s["life_cycles_low"], s["life_cycles_high"]))
            out.append((s["label"], life, interval, ratio,
                        s["verdict"], wear, calls, mode, validated))
        return out

    def setting_rows(self) -> list[tuple[str, ...]]:
        """One row per setting that differs: its name (with its unit), then its value in each study."""
        return [(d["name"] + (f" ({d['unit']})" if d.get("unit") else ""), *(_shown(v) for v in d["values"]))
                for d in self.differences]

    def markdown(self) -> str:
        """The comparison as Markdown: a table of the studies, then the settings that differ. Every cell is
        escaped (:func:`markdown_cell`): names come from configs and folders that may not be trusted."""
        def row(cells) -> str:
            return "| " + " | ".join(markdown_cell(c) for c in cells) + " |"

        lines = [f"Life at R = {self.target:g}; the first study is the baseline.", "",
                 row(self.COLUMNS), "|---" * len(self.COLUMNS) + "|"]
        lines += [row(r) for r in self.rows()]
        if note := self.wear_mode_note():
            lines += ["", markdown_cell(note)]
        if self.differences:
            lines += ["", row(("setting", *self.labels)), "|---" * (len(self.labels) + 1) + "|"]
            lines += [row(r) for r in self.setting_rows()]
        else:
            lines += ["", "No setting differs between the studies."]
        if note := self.unrecorded_note():
            lines += ["", markdown_cell(note)]
        if note := self.seed_note():
            lines += ["", note]
        return "\n".join(lines)

    def unrecorded_note(self) -> str:
        """The studies whose folder records no settings (no config.json: a result saved on its own), whose
        settings are therefore not compared; '' when every one records them."""
        missing = [s["label"] for s in self.studies if s.get("settings_recorded") is False]
        if not missing:
            return ""
        return (f"{', '.join(missing)} record{'s' if len(missing) == 1 else ''} no settings (no config.json in the "
                "folder: a result saved on its own), so the settings are compared between the others only.")

    def wear_mode_note(self) -> str:
        """Which studies to trust when some ran uniform mode outside its range and others profile mode (the wear
        stage's own verdict, docs/wear.md); '' otherwise."""
        outside = [s["label"] for s in self.studies if s.get("uniform_out_of_range")]
        profile = [s["label"] for s in self.studies if s.get("geometry_mode") == "profile"]
        if not outside or not profile:
            return ""
        return (f"Uniform mode is outside its range in {', '.join(outside)} (the worn surface conforms to the journal, "
                f"docs/wear.md): of these studies, {', '.join(profile)}, in profile mode, "
                f"{'is' if len(profile) == 1 else 'are'} the answer to trust.")

    def seed_note(self) -> str:
        """When the studies differ only in their seeds: a verdict then measures the learning's own scatter, which
        each life interval (the error of one learning's estimate) does not include; '' otherwise."""
        if not self.differences or not all(d["name"].endswith(".seed") for d in self.differences):
            return ""
        return ("These studies differ only in their seeds: their lives differ by the learning's own scatter from "
                "seed to seed, which each life's interval (the error of one learning's estimate) does not include, "
                "so a 'longer' or 'shorter' here says how far that scatter reaches, not that one design lives longer.")

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``comparison.json``, the CSV tables (:meth:`tables`), ``comparison.md``, the figure of the
        curves (``comparison_reliability.png``) and the page ``comparison.html`` (the figure embedded)."""
        from jointwear.report.comparison_page import write_comparison_page

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.write_tables(folder)
        write_text_atomic(folder / "comparison.md", self.markdown() + "\n")
        figure = folder / "comparison_reliability.png"
        if figures:
            from jointwear.report import figures as F

            save_figure(F.comparison_figure(self.curves, self.labels, target=self.target,
                                            lives=[(s["life_cycles"], s["life_cycles_low"], s["life_cycles_high"])
                                                   for s in self.studies]), figure)
        path = self.write(folder)
        write_comparison_page(self, folder / "comparison.html", figure=figure if figures else None)
        return path


def compare_studies(studies: Sequence[Path | str | StudyResults], *, target: float | None = None,
                    labels: Sequence[str] | None = None) -> StudyComparison:
    """Compare finished studies at one target reliability.

    Parameters
    ----------
    studies : sequence of folders (or of :class:`StudyResults` from ``load_results``)
        Two or more study folders with a reliability result; the first is the baseline.
    target : float, optional
        The target reliability, in (0, 1). Default: the baseline's first target.
    labels : sequence of str, optional
        A name for each study. Default: each study's name, or its folder's where names repeat.

    Returns
    -------
    StudyComparison

    Raises
    ------
    ConfigError
        Fewer than two studies, a folder without a reliability result, a target outside (0, 1), or labels that
        do not match the studies one to one.
    """
    if isinstance(studies, (str, Path, StudyResults)):  # a str is a sequence too: 'base' read as folders b, a, s, e
        raise ConfigError(f"compare: studies: a list of two or more study folders, the baseline first (got the single "
                          f"{_one(studies)}; e.g. compare_studies(['base', 'other']))")
    loaded = [s if isinstance(s, StudyResults) else _load(s) for s in studies]
    if len(loaded) < 2:
        raise ConfigError(f"compare: needs two or more study folders (got {len(loaded)})")
    for res in loaded:
        if res.reliability is None:
            why = f" ({res.errors['reliability']})" if "reliability" in res.errors else ""
            raise ConfigError(f"compare: '{res.folder}' has no reliability result{why}: run "
                              f"`jointwear reliability --out {res.folder}` (or `run`) first")
    target = (float(loaded[0].reliability.target) if target is None
              else reliability_target(target, "compare: target"))
    if labels is None:
        labels = _default_labels(loaded)
    elif len(labels) != len(loaded) or len(set(labels)) != len(labels):
        raise ConfigError(f"compare: labels: one distinct label per study ({len(loaded)}; got {list(labels)!r})")
    rows = [_row(res, str(label), float(target)) for res, label in zip(loaded, labels)]
    base = rows[0]
    reach = [res.reliability.life_reach(float(target)) for res in loaded]  # an end outside its curve, bounded
    for i, row in enumerate(rows):
        row["verdict"] = "baseline" if i == 0 else life_verdict(*reach[i], *reach[0])
        row["life_ratio"] = (row["life_cycles"] / base["life_cycles"]
                             if row["life_cycles"] is not None and base["life_cycles"] else None)
    curves = [{"cycles": np.asarray(r.reliability.cycles, dtype=float).tolist(),
               "reliability": np.asarray(r.reliability.reliability, dtype=float).tolist(),
               "half_width": np.asarray(r.reliability.half_width, dtype=float).tolist()} for r in loaded]
    return StudyComparison(target=float(target), studies=rows, differences=_differences(loaded), curves=curves)


def _one(study: Path | str | StudyResults) -> str:
    folder = study.folder if isinstance(study, StudyResults) else study
    return f"folder '{folder}'"


def _load(folder: Path | str) -> StudyResults:
    try:
        return load_results(folder)
    except FileNotFoundError as exc:
        raise ConfigError(f"compare: {exc}") from None


def _default_labels(loaded: list[StudyResults]) -> list[str]:
    """Study names; folder names where names repeat; whole paths where those repeat too."""
    for candidate in ([r.name or r.folder.name for r in loaded], [r.folder.name for r in loaded],
                      [str(r.folder) for r in loaded]):
        if len(set(candidate)) == len(candidate):
            return candidate
    return [f"{i + 1}: {r.folder}" for i, r in enumerate(loaded)]


def _row(res: StudyResults, label: str, target: float) -> dict:
    rel = res.reliability
    life = rel.life(target)
    low, high = rel.life_interval(target)
    hours = rel.hours(life)
    wear = res.wear
    val = res.validation
    return {
        "label": label,
        "geometry_mode": wear.geometry_mode if wear is not None else res.setting("wear.geometry_mode"),
        "life_cycles": life, "life_cycles_low": low, "life_cycles_high": high, "life_hours": hours,
        "status": life_status(rel.reliability, target), "life_ratio": None, "verdict": "",
        "model_calls": int(rel.model_calls), "converged": bool(rel.converged),
        "max_wear_mm": None if wear is None else float(wear.max_wear_mm),
        "max_wear_mm_by_joint": {} if wear is None else {j["name"]: float(j["max_wear_mm"]) for j in wear.joints},
        "wear_cycles": None if wear is None else int(wear.cycles),
        "uniform_out_of_range": bool(wear is not None and wear.uniform_out_of_range),
        "validation_levels_agreeing": None if val is None else int(np.sum(val.agreement)),
        "validation_levels": None if val is None else int(len(val.agreement)),
        "validation_levels_passing_95": None if val is None else int(np.sum(~val.differs_at_95())),
        "validation_samples": None if val is None else int(val.n_samples),
        "validation_resolution": None if val is None else float(val.resolution),
        "settings_recorded": bool((res.config or {}).get("settings")),
        "folder": str(res.folder),
    }


def _differences(loaded: list[StudyResults]) -> list[dict]:
    """The settings (config.json's resolved ``settings``) whose values differ, in the order the first study that
    has each lists them."""
    from jointwear.study.settings_record import named_paths

    per_study = []
    for res in loaded:
        # list items by their names: studies listing their variables in another order compare by name
        per_study.append({s["name"]: s for s in named_paths((res.config or {}).get("settings", []))})
    recorded = [i for i, settings in enumerate(per_study) if settings]  # a folder without config.json: not compared
    names: list[str] = []
    for settings in per_study:
        # where the calls run (compute.workers, .scheduler) does not change a result: serial, local workers and Dask
        # give the same; a call's time-out does (a call it stops counts as a failure of the mechanism)
        names += [n for n in settings if n not in names and n not in _NOT_SETTINGS
                  and (not n.startswith("compute.") or n == "compute.call_timeout")]
    out = []
    for name in names:
        # each study shows a value in the unit that suits its magnitude (0.7 GPa but 700 MPa): one unit for the row
        unit = next((s[name].get("unit") for s in per_study if name in s), None)
        values = [in_unit(s[name]["value"], s[name].get("unit"), unit) if name in s else None for s in per_study]
        known = [values[i] for i in recorded]
        if any(not same_value(known[0], v, rtol=1e-12) for v in known[1:]):  # a value read back through a unit
            out.append({"name": name, "unit": unit, "values": values})
    return out


#: control characters (C0, DEL, C1): a terminal escape sequence (ESC [ ... m, ESC ] ... BEL) starts with one
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
_MARKDOWN_ESCAPES = {"\\": "\\\\", "|": "\\|", "&": "&amp;", "<": "&lt;", ">": "&gt;"}


def markdown_cell(text: Any) -> str:
    """``text`` safe in a Markdown table cell: tabs and line breaks become spaces, other control characters are
    dropped (no terminal escape reaches a terminal that shows the file), ``&``, ``<`` and ``>`` become entities (no
    HTML reaches a Markdown renderer) and backslashes and pipes are backslash-escaped (no cell is split)."""
    text = _CONTROL.sub(lambda m: " " if m.group() in "\t\n\r" else "", str(text))
    return "".join(_MARKDOWN_ESCAPES.get(c, c) for c in text)


def _cycles(value: float | None) -> str:
    return "\u2014" if value is None else f"{value:,.0f}"


def _shown(value: Any) -> str:
    if value is None:
        return "\u2014"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict):  # a table of numbers: {'E': 0.015}, not {'E': 0.015000000000000001}
        return "{" + ", ".join(f"{k!r}: {_shown(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    return str(value)
