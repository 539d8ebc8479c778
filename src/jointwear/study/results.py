"""Typed results of the study stages, each with ``save(folder)`` (JSON, CSV tables, figures) and ``load(folder)``.

Like SciPy's ``OdeResult``: documented fields, units in the names of dimensional quantities. The JSON files
are the contract of DESIGN.md (``simulate.json``, ``wear.json``, ``reliability.json``,
``sensitivity.json``); :func:`load_results` reads a study folder back into these types, which is how the
report and notebooks read results.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from jointwear.study.io import provenance, read_json, write_csv, write_json


class StageResult:
    """Shared save/load of the stage results: the JSON holds every field not marked ``json=False``."""

    FILE: ClassVar[str] = ""

    def to_json(self) -> dict:
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.metadata.get("json", True)}
        for key, value in getattr(self, "extra", {}).items():
            out.setdefault(key, value)
        return out

    @classmethod
    def from_json(cls, data: dict):
        """The result from its JSON; keys this version does not know are kept in ``extra`` (and written back)."""
        kwargs, known = {}, set()
        for f in fields(cls):
            known.add(f.name)
            if not f.metadata.get("json", True):
                continue
            if f.name in data:
                kwargs[f.name] = data[f.name]
            elif f.default is MISSING and f.default_factory is MISSING:
                raise ValueError(f"{cls.FILE}: missing key '{f.name}'")
        if "extra" in known:
            kwargs["extra"] = {k: v for k, v in data.items() if k not in known}
        return cls(**kwargs)

    @classmethod
    def load(cls, folder: Path | str):
        """Read the result back from ``folder / FILE``."""
        return cls.from_json(read_json(Path(folder) / cls.FILE))

    def write(self, folder: Path | str) -> Path:
        payload = self.to_json()
        payload.setdefault("provenance", provenance())
        return write_json(Path(folder) / self.FILE, payload)


def _savefig(fig, path: Path) -> None:
    from jointwear.report.style import savefig

    savefig(fig, path)


# --------------------------------------------------------------------------------------------------- simulate
@dataclass
class SimulationSummary(StageResult):
    """The dynamics of the nominal mechanism over a few crank cycles (``jointwear simulate``).

    Top-level force keys are those of the first clearance joint; ``joints`` has one row per clearance joint
    (``contact_force_mean_N``, ``contact_force_max_N``, ``contact_fraction``, ``impacts_per_cycle``,
    ``max_penetration_m``, ...). ``trace`` (not saved to JSON; its series go to ``simulate.npz``) is the full
    :class:`jointwear.mechanism.SimulationResult` when the result was computed in this process.
    """

    FILE: ClassVar[str] = "simulate.json"

    cycles: int
    config: str = ""
    settle_cycles: float | None = None
    period_s: float | None = None
    steps_per_cycle: float | None = None
    wall_seconds_per_cycle: float | None = None
    wall_seconds: float | None = None
    accepted_steps: int | None = None
    rejected_steps: int | None = None
    kernel: str = ""
    joints: list[dict] = field(default_factory=list)
    contact_force_mean_N: float | None = None
    contact_force_max_N: float | None = None
    contact_fraction: float | None = None
    impacts_per_cycle: float | None = None
    series_file: str = "simulate.npz"
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    trace: Any = field(default=None, repr=False, metadata={"json": False})

    @classmethod
    def from_simulation(cls, res, name: str = "") -> SimulationSummary:
        total = res.n_cycles + res.settle_cycles
        joints = []
        for tr in res.joints:
            f = tr.contact_force
            joints.append({
                "name": tr.name, "bearing_body": tr.bearing_body, "journal_body": tr.journal_body,
                "contact_force_mean_N": tr.mean_force,
                "contact_force_max_N": float(f.max()) if f.size else 0.0,
                "normal_force_mean_N": float(np.sum(tr.dt_weight * tr.force_normal) / tr.duration),
                "contact_fraction": tr.contact_fraction,
                "impacts_per_cycle": tr.n_impacts / res.n_cycles,
                "max_penetration_m": float(tr.penetration.max()),
                "clearance_m": tr.clearance_used,
                "stiffness_N_per_m1p5": float(np.median(tr.stiffness)),
            })
        first = joints[0] if joints else {}
        return cls(
            config=name, cycles=res.n_cycles, settle_cycles=res.settle_cycles, period_s=res.period,
            steps_per_cycle=res.steps_per_cycle,
            wall_seconds_per_cycle=res.wall_seconds / total if total else math.nan,
            wall_seconds=res.wall_seconds, accepted_steps=res.n_steps, rejected_steps=res.n_rejected,
            kernel=res.extra.get("kernel", ""), joints=joints,
            contact_force_mean_N=first.get("contact_force_mean_N"),
            contact_force_max_N=first.get("contact_force_max_N"),
            contact_fraction=first.get("contact_fraction"), impacts_per_cycle=first.get("impacts_per_cycle"),
            provenance=provenance(), trace=res)

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``simulate.json``, ``simulate_joints.csv``, ``simulate.npz`` (series) and the figures."""
        folder = Path(folder)
        path = self.write(folder)
        keys = [k for k in (self.joints[0] if self.joints else {}) if k not in ("bearing_body", "journal_body")]
        write_csv(folder / "simulate_joints.csv", {k: [j[k] for j in self.joints] for k in keys})
        res = self.trace
        if res is None:
            return path
        data: dict[str, np.ndarray] = {"t_s": res.t, "crank_angle_rad": res.crank_angle,
                                       "body_angles_rad": res.body_angles}
        for tr in res.joints:
            p = f"{tr.name}_"
            data[p + "eccentricity_bearing_frame_m"] = tr.eccentricity
            data[p + "theta_bearing_rad"] = tr.theta_bearing
            data[p + "force_normal_N"] = tr.force_normal
            data[p + "force_tangential_N"] = tr.force_tangential
            data[p + "slip_speed_m_s"] = tr.slip_speed
            data[p + "penetration_m"] = tr.penetration
            data[p + "in_contact"] = tr.in_contact
        np.savez_compressed(folder / self.series_file, **data)
        if figures:
            from jointwear.report import figures as F

            for tr in res.joints:
                _savefig(F.orbit_figure(tr.eccentricity[:, 0] * 1e3, tr.eccentricity[:, 1] * 1e3,
                                        tr.clearance_used * 1e3, title=f"Journal centre orbit, joint {tr.name}"),
                         folder / f"orbit_{tr.name}.png")
                _savefig(F.contact_force_figure(np.degrees(res.crank_angle), tr.contact_force,
                                                mean_N=tr.mean_force, title=f"Contact force, joint {tr.name}"),
                         folder / f"force_{tr.name}.png")
        return path


# ------------------------------------------------------------------------------------------------------- wear
@dataclass
class WearSummary(StageResult):
    """The wear history of the nominal mechanism (``jointwear wear``).

    Top-level keys are those of the first clearance joint (DESIGN.md): ``max_wear_mm``,
    ``max_wear_angle_deg``, ``peaks`` [{``angle_deg``, ``depth_mm``}], ``profile`` {``angle_deg``,
    ``depth_mm``}, ``history`` {``cycles``, ``max_wear_mm``}; ``joints`` has the same for every joint plus the
    journal's wear, the clearance growth, the Archard volumes and the wear-rate diagnostics.
    ``conformity`` (joint 0) is the half worn arc of a bore worn to the journal's shape over the contact's
    half-angle on the unworn bore; ``uniform_mode_valid`` is False when it exceeds 1 for any joint, where only
    ``geometry_mode = "profile"`` describes the contact (docs/wear.md).
    ``history_result`` (not saved) is the full :class:`jointwear.wear.WearResult`.
    """

    FILE: ClassVar[str] = "wear.json"

    cycles: int
    max_wear_mm: float
    max_wear_angle_deg: float | None = None
    peaks: list[dict] = field(default_factory=list)
    profile: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    journal: dict = field(default_factory=dict)
    wall_seconds: float | None = None
    joints: list[dict] = field(default_factory=list)
    simulation_seconds: float = 0.0
    n_simulated_cycles: float = 0.0
    n_blocks: int = 0
    blocks: list[dict] = field(default_factory=list)
    angle_convention: str = ("bearing (rod) frame laid at the rod's mean orientation; 0 deg = leftmost point, "
                             "clockwise")
    settings: dict = field(default_factory=dict)
    geometry_mode: str = "uniform"
    limit_mm: float | None = None
    conformity: float | None = None
    uniform_mode_valid: bool | None = None
    files: list[str] = field(default_factory=list)
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    history_result: Any = field(default=None, repr=False, metadata={"json": False})

    @classmethod
    def from_history(cls, res, config=None, allowances_m: dict[str, float] | None = None) -> WearSummary:
        """Summarise a :class:`jointwear.wear.WearResult` of ``config`` (allowances by joint name, m)."""
        from jointwear.wear.angles import report_angle_deg
        from jointwear.wear.results import conservation_error

        allowances_m = allowances_m or {}
        joints = []
        for jw in res.joints:
            name = str(config.clearance_joints[jw.index].name) if config is not None else f"joint{jw.index}"
            ang = jw.angle_deg
            o = np.argsort(ang)
            jang = report_angle_deg(jw.theta, 0.0)
            jo = np.argsort(jang)
            eb, ej = conservation_error(jw)
            a = allowances_m.get(name)
            joints.append({
                "name": name,
                "max_wear_mm": jw.max_bearing_wear * 1e3,
                "max_wear_angle_deg": jw.max_wear_angle_deg,
                "peaks": [{"angle_deg": p["angle_deg"], "depth_mm": p["depth"] * 1e3} for p in jw.peaks],
                "profile": {"angle_deg": ang[o].tolist(), "depth_mm": (jw.bearing_wear[o] * 1e3).tolist()},
                "history": {"cycles": jw.history_cycles.astype(int).tolist(),
                            "max_wear_mm": (jw.history_max_bearing * 1e3).tolist(),
                            "max_journal_wear_mm": (jw.history_max_journal * 1e3).tolist(),
                            "clearance_growth_mm": (jw.history_clearance_growth * 1e3).tolist()},
                "journal": {"max_wear_mm": float(jw.journal_wear.max() * 1e3),
                            "mean_wear_mm": float(jw.journal_wear.mean() * 1e3),
                            "angle_convention": "journal frame laid along +x; 0 deg leftmost, clockwise",
                            "profile": {"angle_deg": jang[jo].tolist(),
                                        "depth_mm": (jw.journal_wear[jo] * 1e3).tolist()}},
                "bearing_radius_mm": jw.bearing_radius * 1e3,
                "allowance_mm": None if a is None else a * 1e3,
                "rod_mean_orientation_deg": math.degrees(jw.mean_orientation),
                "archard_volume_mm3": {"bearing": jw.volume_bearing * 1e9, "journal": jw.volume_journal * 1e9},
                "conservation_rel_error": {"bearing": eb, "journal": ej},
                "wear_rate_initial_mm_per_cycle": float(jw.first_rate.bearing.max() * 1e3),
                "wear_rate_final_mm_per_cycle": float(jw.diagnostics.bearing.max() * 1e3),
                "max_half_width_um": jw.diagnostics.max_half_width * 1e6,
                "conformity": jw.conformity,
                "uniform_mode_valid": jw.uniform_mode_valid,
            })
        j0 = joints[0]
        return cls(
            cycles=res.n_cycles, max_wear_mm=j0["max_wear_mm"], max_wear_angle_deg=j0["max_wear_angle_deg"],
            peaks=j0["peaks"], profile=j0["profile"],
            history={"cycles": j0["history"]["cycles"], "max_wear_mm": j0["history"]["max_wear_mm"]},
            journal=j0["journal"], wall_seconds=res.wall_seconds, joints=joints,
            simulation_seconds=res.sim_seconds, n_simulated_cycles=res.n_simulated_cycles,
            n_blocks=len(res.blocks),
            blocks=[{"start": b.start, "size": b.size, "peak_rate_mm_per_cycle": b.peak_rate * 1e3,
                     "rate_change": None if math.isnan(b.rate_change) else b.rate_change} for b in res.blocks],
            settings=res.settings.model_dump(mode="json"), geometry_mode=res.settings.geometry_mode,
            limit_mm=j0["allowance_mm"], conformity=j0["conformity"],
            uniform_mode_valid=all(j["uniform_mode_valid"] for j in joints), provenance=provenance(),
            history_result=res)

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``wear.json``, the profile and history CSV tables of every joint and the figures."""
        folder = Path(folder)
        res = self.history_result
        files: list[str] = []
        for k, joint in enumerate(self.joints):
            sfx = "" if k == 0 else f"_{k}"
            h = joint["history"]
            files.append(write_csv(folder / f"wear_history{sfx}.csv", {
                "cycles": h["cycles"], "max_bearing_wear_mm": h["max_wear_mm"],
                "max_journal_wear_mm": h["max_journal_wear_mm"], "clearance_growth_mm": h["clearance_growth_mm"],
            }).name)
            jp = joint["journal"]["profile"]
            files.append(write_csv(folder / f"wear_journal_profile{sfx}.csv",
                                   {"angle_deg": jp["angle_deg"], "journal_depth_mm": jp["depth_mm"]}).name)
            cols = {"angle_deg": joint["profile"]["angle_deg"], "bearing_depth_mm": joint["profile"]["depth_mm"]}
            panels = {}
            if res is not None:
                jw = res.joints[k]
                d = jw.diagnostics
                o = np.argsort(jw.angle_deg)
                cell = 360.0 / jw.theta.size
                panels = {"contact_force_N": d.force_mean[o], "slip_mm": d.slip_distance[o] * 1e3 / cell,
                          "contact_area_mm2": d.area_mean[o] * 1e6}
                cols.update({"body_angle_deg": np.degrees(jw.theta[o]), "contact_force_mean_N": d.force_mean[o],
                             "sliding_mm_per_deg_per_cycle": panels["slip_mm"],
                             "contact_area_mean_mm2": panels["contact_area_mm2"],
                             "contact_time_s_per_cycle": d.contact_time[o],
                             "depth_rate_mm_per_cycle": d.bearing[o] * 1e3})
            files.append(write_csv(folder / f"wear_profile{sfx}.csv", cols).name)
            if figures:
                from jointwear.report import figures as F

                prof = joint["profile"]
                _savefig(F.wear_polar_figure(prof["angle_deg"], prof["depth_mm"],
                                             radius_mm=joint.get("bearing_radius_mm"), peaks=joint["peaks"],
                                             cycles=self.cycles, title=f"Worn bearing, joint {joint['name']}"),
                         folder / f"wear_polar{sfx}.png")
                if panels:
                    _savefig(F.wear_panels_figure(prof["angle_deg"], prof["depth_mm"], slip_mm=panels["slip_mm"],
                                                  contact_force_N=panels["contact_force_N"],
                                                  contact_area_mm2=panels["contact_area_mm2"], cycles=self.cycles,
                                                  slip_unit="mm/deg per cycle"),
                             folder / f"wear_vs_angle{sfx}.png")
                _savefig(F.wear_history_figure(h["cycles"], h["max_wear_mm"], limit_mm=joint.get("allowance_mm")),
                         folder / f"wear_history{sfx}.png")
                files += [f"wear_polar{sfx}.png", f"wear_history{sfx}.png"] + (
                    [f"wear_vs_angle{sfx}.png"] if panels else [])
        self.files = files
        return self.write(folder)


# ------------------------------------------------------------------------------------------------ reliability
@dataclass
class ReliabilityResult(StageResult):
    """The R(N) curve, the life at each target reliability and the wear distributions of a study.

    Arrays over the curve's ``cycles``: ``reliability``, ``pf``, ``pf_cov`` (coefficient of variation of the
    Monte Carlo estimate of Pf on the surrogate), ``pf_error`` (the surrogate's own absolute error estimate),
    ``below_floor`` (levels whose COV need not meet the target). ``life_table``: [{``target``, ``cycles``,
    ``hours``, ``status``}]: the life is None where it lies outside the curve, and ``status`` says on which side
    ('in_curve', 'beyond_curve': longer than the curve, 'before_curve': shorter than its first level). ``joints``: each judged joint's
    allowance and, with several, its own R(N) and its share of the system's failures (``governing_share``).
    """

    FILE: ClassVar[str] = "reliability.json"

    cycles: np.ndarray
    reliability: np.ndarray
    pf: np.ndarray
    pf_cov: np.ndarray
    below_floor: np.ndarray
    pf_error: np.ndarray
    target: float
    life_cycles: float | None
    life_hours: float | None
    model_calls: int
    failed_calls: int
    n_mc: int
    converged: bool
    wall_seconds: float
    names: list[str]
    histograms: dict
    mean_max_wear: dict
    convergence: dict
    design_x: np.ndarray
    design_wear: np.ndarray
    life_table: list[dict] = field(default_factory=list)
    design_life: np.ndarray | None = None
    quantity: str = "bearing_max_depth"
    joints: list[dict] = field(default_factory=list)
    crank_speed_rpm: float | None = None
    infeasible: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    engine: Any = field(repr=False, default=None, metadata={"json": False})

    @property
    def governing_joint(self) -> str | None:
        """The judged joint with the largest share of the system's failures at the headline life (or at the
        end of the curve when the target is not reached)."""
        if not self.joints:
            return None
        if len(self.joints) == 1:
            return self.joints[0]["name"]
        n = self.life_cycles if self.life_cycles is not None else float(self.cycles[-1])
        k = int(np.argmin(np.abs(np.asarray(self.cycles, dtype=float) - n)))
        shares = [np.nan_to_num(np.asarray(j["governing_share"], dtype=float))[k] for j in self.joints]
        return self.joints[int(np.argmax(shares))]["name"]

    def to_json(self) -> dict:
        return {
            "curve": {"cycles": np.asarray(self.cycles).tolist(), "reliability": np.asarray(self.reliability).tolist(),
                      "pf": np.asarray(self.pf).tolist(), "pf_cov": np.asarray(self.pf_cov).tolist(),
                      "pf_error_estimate": np.asarray(self.pf_error).tolist(),
                      "cov_waived_below_pf_floor": np.asarray(self.below_floor).tolist()},
            "life_at_target": {"target": self.target, "cycles": self.life_cycles, "hours": self.life_hours},
            "life_table": self.life_table,
            "quantity": self.quantity,
            "joints": self.joints,
            "governing_joint": self.governing_joint,
            "allowance_mm": self.joints[0]["allowance_mm"] if self.joints else self.extra.get("allowance_mm"),
            "crank_speed_rpm": self.crank_speed_rpm,
            "model_calls": self.model_calls,
            "failed_calls": self.failed_calls,
            "n_mc": self.n_mc,
            "converged": self.converged,
            "wall_seconds": self.wall_seconds,
            "variables": self.names,
            "histograms": self.histograms,
            "mean_max_wear_mm": self.mean_max_wear,
            "convergence": self.convergence,
            "design": {"x": np.asarray(self.design_x).tolist(), "wear_m": np.asarray(self.design_wear).tolist(),
                       "life_cycles": None if self.design_life is None else np.asarray(self.design_life).tolist()},
            "infeasible": self.infeasible,
            "provenance": self.provenance or provenance(),
            **{k: v for k, v in self.extra.items() if k not in _RELIABILITY_KEYS},
        }

    @classmethod
    def from_json(cls, data: dict) -> ReliabilityResult:
        c = data["curve"]
        life = data.get("life_at_target", {})
        design = data.get("design", {})

        def arr(v):
            return np.asarray([np.nan if x is None else x for x in v], dtype=float)

        return cls(
            cycles=arr(c["cycles"]), reliability=arr(c["reliability"]),
            pf=arr(c["pf"]) if "pf" in c else 1.0 - arr(c["reliability"]),
            pf_cov=arr(c.get("pf_cov", [None] * len(c["cycles"]))),
            below_floor=np.asarray(c.get("cov_waived_below_pf_floor", [False] * len(c["cycles"])), dtype=bool),
            pf_error=arr(c.get("pf_error_estimate", [np.nan] * len(c["cycles"]))),
            target=life.get("target"), life_cycles=life.get("cycles"), life_hours=life.get("hours"),
            model_calls=data.get("model_calls", 0), failed_calls=data.get("failed_calls", 0),
            n_mc=data.get("n_mc", 0), converged=data.get("converged", False),
            wall_seconds=data.get("wall_seconds", math.nan), names=data.get("variables", []),
            histograms=data.get("histograms", {}), mean_max_wear=data.get("mean_max_wear_mm", {}),
            convergence=data.get("convergence", {}),
            design_x=np.asarray(design.get("x", []), dtype=float),
            design_wear=np.asarray(design.get("wear_m", []), dtype=float),
            design_life=None if design.get("life_cycles") is None else arr(design["life_cycles"]),
            life_table=data.get("life_table", []), quantity=data.get("quantity", "bearing_max_depth"),
            joints=data.get("joints", []), crank_speed_rpm=data.get("crank_speed_rpm"),
            infeasible=data.get("infeasible", {}), provenance=data.get("provenance", {}),
            extra={k: v for k, v in data.items() if k not in _RELIABILITY_KEYS})

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``reliability.json``, the CSV tables (curve, life table, design points) and the figures."""
        folder = Path(folder)
        curve = {"cycles": np.asarray(self.cycles, dtype=float), "reliability": self.reliability, "pf": self.pf,
                 "pf_cov": self.pf_cov, "pf_error_estimate": self.pf_error}
        for j in self.joints if len(self.joints) > 1 else []:
            curve[f"reliability_{j['name']}"] = j["reliability"]
            curve[f"governing_share_{j['name']}"] = j["governing_share"]
        write_csv(folder / "reliability_curve.csv", curve)
        write_csv(folder / "life_table.csv", {
            "target_reliability": [r["target"] for r in self.life_table],
            "life_cycles": [r["cycles"] for r in self.life_table],
            "life_hours": [r["hours"] for r in self.life_table],
            "status": [r.get("status", "") for r in self.life_table]})
        x = np.atleast_2d(np.asarray(self.design_x, dtype=float))
        if x.size:
            cols: dict[str, Any] = {name: x[:, k] for k, name in enumerate(self.names[:x.shape[1]])}
            if self.design_life is not None:
                cols["life_cycles"] = self.design_life
            write_csv(folder / "design_points.csv", cols)
        path = self.write(folder)
        if figures:
            from jointwear.report import figures as F

            _savefig(F.reliability_curve_figure(self.cycles, self.reliability, pf_cov=self.pf_cov, target=self.target,
                                                life_cycles=self.life_cycles), folder / "reliability_curve.png")
            h = self.histograms
            if h.get("cycles"):
                limit = self.joints[0]["allowance_mm"] if self.joints else None
                _savefig(F.wear_histograms_figure(h["cycles"], h["max_wear_mm"], limit_mm=limit),
                         folder / "wear_histograms.png")
            conv = self.convergence
            if conv.get("n_calls"):
                _savefig(F.convergence_figure(conv["n_calls"], conv["pf"], cov=conv.get("cov"),
                                              label=f"Pf at {conv.get('cycles'):,} cycles"),
                         folder / "convergence.png")
        return path


_RELIABILITY_KEYS = frozenset({
    "curve", "life_at_target", "life_table", "quantity", "joints", "governing_joint", "allowance_mm",
    "crank_speed_rpm", "model_calls", "failed_calls", "n_mc", "converged", "wall_seconds", "variables",
    "histograms", "mean_max_wear_mm", "convergence", "design", "infeasible", "provenance"})


# ------------------------------------------------------------------------------------------------ sensitivity
@dataclass
class SensitivityResult(StageResult):
    """How the reliability at ``cycles`` moves with each variable: mean shifts (``variables`` rows with
    ``reliability_low``/``reliability_high`` and their error estimates), the ranking overall and per group
    (``unresolved_pairs``: neighbours the surrogate's error does not separate), Sobol' indices of the wear
    and reliability derivatives."""

    FILE: ClassVar[str] = "sensitivity.json"

    cycles: int
    factors: list[float]
    reliability_nominal: float
    variables: list[dict]
    ranking: list[str]
    ranking_by_group: dict
    sobol: dict
    reliability_nominal_error: float | None = None
    unresolved_pairs: list[dict] = field(default_factory=list)
    rules: list[dict] = field(default_factory=list)
    archard_checks: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    extra_model_calls: int = 0
    derivatives: dict = field(default_factory=dict)
    n_population: int = 0
    wall_seconds: float | None = None
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    @classmethod
    def from_json(cls, data: dict) -> SensitivityResult:
        data = dict(data)
        if "ranking" not in data and "variables" in data and "reliability_nominal" in data:
            r0 = data["reliability_nominal"]
            swing = {v["name"]: max(abs(v["reliability_low"] - r0), abs(v["reliability_high"] - r0))
                     for v in data["variables"]}
            data["ranking"] = sorted(swing, key=lambda n: -swing[n])
        data.setdefault("ranking_by_group", {})
        data.setdefault("sobol", {})
        data.setdefault("factors", [0.8, 1.2])
        return super().from_json(data)

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``sensitivity.json``, ``sensitivity.csv`` (one row per variable) and the figures."""
        folder = Path(folder)
        keys = ["name", "label", "group", "reliability_low", "reliability_high", "reliability_low_error",
                "reliability_high_error", "dR_dmean", "dR_dstd", "elasticity_mean", "S1", "ST"]
        write_csv(folder / "sensitivity.csv", {k: [v.get(k) for v in self.variables] for k in keys})
        path = self.write(folder)
        if figures:
            from jointwear.report import figures as F

            v = self.variables
            lo, hi = self.factors
            _savefig(F.tornado_figure([x["label"] for x in v], [x["reliability_low"] for x in v],
                                      [x["reliability_high"] for x in v], self.reliability_nominal,
                                      cycles=self.cycles, low_label=f"mean \u00d7 {lo:g}",
                                      high_label=f"mean \u00d7 {hi:g}"), folder / "sensitivity_tornado.png")
            s = self.sobol
            _savefig(F.sobol_figure(s["names"], s["S1"], s["ST"], S1_conf=s.get("S1_conf"), ST_conf=s.get("ST_conf"),
                                    output=f"wear at {self.cycles:,} cycles"), folder / "sensitivity_sobol.png")
        return path


# ------------------------------------------------------------------------------------------------- validation
@dataclass
class ValidationResult(StageResult):
    """The surrogate's R(N) against the true model sampled directly (``jointwear validate``).

    At every level of the curve: ``reliability_mc`` from ``n_samples`` true-model calls on fresh samples, its
    exact binomial 95 % interval [``ci_low``, ``ci_high``], the surrogate's ``reliability_surrogate`` with its
    error estimate (``surrogate_error``, absolute) and COV, and whether the two agree within their combined
    95 % half-widths (``agreement``). ``cross_validation``: leave-one-out predictions of the design points'
    log life against their true values, with Q^2.
    """

    FILE: ClassVar[str] = "validation.json"

    cycles: list[int]
    reliability_mc: list[float]
    ci_low: list[float]
    ci_high: list[float]
    reliability_surrogate: list[float]
    surrogate_error: list[float]
    n_samples: int
    model_calls: int
    wall_seconds: float
    agreement: list[bool] = field(default_factory=list)
    surrogate_cov: list[float] = field(default_factory=list)
    failed_calls: int = 0
    seed: int | None = None
    cross_validation: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    @property
    def all_agree(self) -> bool:
        return all(self.agreement)

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``validation.json``, ``validation.csv``, ``cross_validation.csv`` and the figures."""
        folder = Path(folder)
        write_csv(folder / "validation.csv", {
            "cycles": self.cycles, "reliability_mc": self.reliability_mc, "ci_low": self.ci_low,
            "ci_high": self.ci_high, "reliability_surrogate": self.reliability_surrogate,
            "surrogate_error": self.surrogate_error, "agreement": self.agreement})
        cv = self.cross_validation
        if cv.get("log_life_true"):
            write_csv(folder / "cross_validation.csv", {
                "log_life_true": cv["log_life_true"], "log_life_loo": cv["log_life_loo"],
                "log_life_loo_sd": cv["log_life_loo_sd"]})
        path = self.write(folder)
        if figures:
            from jointwear.report import figures as F

            _savefig(F.validation_figure(self.cycles, self.reliability_mc, self.ci_low, self.ci_high,
                                         self.reliability_surrogate, self.surrogate_error,
                                         n_samples=self.n_samples), folder / "validation.png")
            if cv.get("log_life_true"):
                _savefig(F.cross_validation_figure(cv["log_life_true"], cv["log_life_loo"], cv["log_life_loo_sd"],
                                                   q2=cv.get("q2")), folder / "cross_validation.png")
        return path


# ---------------------------------------------------------------------------------------------------- loading
@dataclass
class StudyResults:
    """Every stage result found in a study folder (None where a stage has not run) and the resolved config."""

    folder: Path
    config: dict | None = None
    simulate: SimulationSummary | None = None
    wear: WearSummary | None = None
    reliability: ReliabilityResult | None = None
    sensitivity: SensitivityResult | None = None
    validation: ValidationResult | None = None
    errors: dict[str, str] = field(default_factory=dict)

    @property
    def stages(self) -> list[str]:
        """The stages with a result in the folder."""
        return [s for s in ("simulate", "wear", "reliability", "sensitivity", "validation")
                if getattr(self, s) is not None]


STAGE_TYPES: dict[str, type] = {"simulate": SimulationSummary, "wear": WearSummary,
                                "reliability": ReliabilityResult, "sensitivity": SensitivityResult,
                                "validation": ValidationResult}


def load_results(folder: Path | str) -> StudyResults:
    """The typed results of the study in ``folder``; a stage whose file is missing is None, one whose file
    cannot be read is None with the reason in ``errors``."""
    folder = Path(folder)
    out = StudyResults(folder)
    cfg = folder / "config.json"
    if cfg.is_file():
        try:
            out.config = read_json(cfg)
        except (OSError, ValueError) as exc:
            out.errors["config"] = f"config.json could not be read: {exc}"
    for stage, cls in STAGE_TYPES.items():
        path = folder / cls.FILE
        if not path.is_file():
            continue
        try:
            setattr(out, stage, cls.load(folder))
        except (OSError, ValueError, KeyError, TypeError) as exc:
            out.errors[stage] = f"{cls.FILE} could not be read: {exc}"
    return out
