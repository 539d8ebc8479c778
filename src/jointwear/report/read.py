"""What the report reads from a study folder: the typed results of :func:`jointwear.load_results`, the series the
dynamics stage writes to ``simulate.npz`` (canonical keys of :meth:`SimulationSummary.save`), and the stages'
PNG and CSV files (listed, and shown where the report has no data to draw a figure itself)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from jointwear.study.results import SimulationSummary, StudyResults, load_results

__all__ = ["StudyOutputs", "JointSeries", "read_outputs", "joint_series"]


@dataclass
class StudyOutputs:
    """A study folder as the report sees it."""

    out_dir: Path
    results: StudyResults
    pngs: dict[str, Path] = field(default_factory=dict)  # stem -> path
    files: list[Path] = field(default_factory=list)

    @property
    def config(self) -> dict:
        """The resolved settings the study wrote (``config.json``, see :mod:`jointwear.study.settings_record`); empty
        when the folder has none."""
        return self.results.config or {}

    @property
    def errors(self) -> dict[str, str]:
        return self.results.errors


@dataclass
class JointSeries:
    """Series of one clearance joint over the simulated cycles (SI units, as ``simulate.npz`` stores them)."""

    name: str
    crank_angle_rad: np.ndarray
    eccentricity_bearing_frame_m: np.ndarray  # (n, 2)
    force_normal_N: np.ndarray


def read_outputs(out_dir: Path | str) -> StudyOutputs:
    """The typed results of the study in ``out_dir`` and its PNG and CSV files."""
    out_dir = Path(out_dir)
    try:
        results = load_results(out_dir)
    except FileNotFoundError:
        if not out_dir.is_dir():
            raise
        results = StudyResults(out_dir)  # nothing of a study yet: the report says what each section misses
    outputs = StudyOutputs(out_dir, results)
    if results.config is not None:
        outputs.files.append(out_dir / "config.json")
    for stage in results.stages:
        outputs.files.append(out_dir / getattr(results, stage).FILE)
    root = out_dir.resolve()
    for folder in (out_dir, out_dir / "data"):
        if folder.is_dir():
            outputs.files += [p for p in sorted(folder.glob("*.csv")) if _inside(p, root)]
            outputs.pngs.update({p.stem: p for p in sorted(folder.glob("*.png")) if _inside(p, root)})
    return outputs


def _inside(path: Path, root: Path) -> bool:
    """Whether ``path`` is a regular file that resolves inside the folder ``root`` (resolved): a symlink planted in
    a received results folder (or a linked ``data`` folder) must not bring a file from elsewhere into the report."""
    resolved = path.resolve()
    return root in resolved.parents and resolved.is_file()


def joint_series(out_dir: Path, sim: SimulationSummary, joint: int = 0) -> JointSeries | None:
    """The series of clearance joint ``joint`` from the stage's ``series_file``; None when the file is absent or
    lacks the joint (a study run with ``figures`` only, or a file from another version)."""
    if not sim.joints or joint >= len(sim.joints):
        return None
    path = (out_dir / sim.series_file).resolve()
    if out_dir.resolve() not in path.parents or not path.is_file():
        return None
    name = str(sim.joints[joint]["name"])
    keys = ("crank_angle_rad", f"{name}_eccentricity_bearing_frame_m", f"{name}_force_normal_N")
    with np.load(path, allow_pickle=False) as z:
        if not all(k in z.files for k in keys):
            return None
        angle, ecc, force = (np.asarray(z[k], dtype=float) for k in keys)
    return JointSeries(name, angle, ecc, force)
