"""Typed results of the study stages, each with ``save(folder)`` (JSON, CSV tables, figures) and ``load(folder)``.

Like SciPy's ``OdeResult``: documented fields, units in the names of dimensional quantities. The JSON files
are the contract of docs/user-guide.md, "Commands and outputs" (``simulate.json``, ``wear.json``, ``reliability.json``,
``sensitivity.json``); :func:`load_results` reads a study folder back into these types, which is how the
report and notebooks read results. The reliability stages' results live in
:mod:`jointwear.study.reliability_results` and are re-exported here.
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from jointwear.schema import ConfigError
from jointwear.study.convergence import WearConvergence
from jointwear.study.io import file_labels, provenance, read_json, write_bytes_atomic
from jointwear.study.reliability_results import ReliabilityCurve, SensitivityResult, ValidationResult
from jointwear.study.stage_result import StageResult, save_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["StageResult", "SimulationSummary", "WearSummary", "ReliabilityCurve", "SensitivityResult",
           "ValidationResult", "StudyResults", "STAGE_TYPES", "LATER_STAGE_TYPES", "stage_types", "load_results",
           "results_of_a_study", "NO_STUDY_RESULTS"]


# --------------------------------------------------------------------------------------------------- simulate
def whirl_sentence(joint: str, revolutions: float, force_N: float | None = None) -> str:
    """What a whirling joint means for the results, in one sentence."""
    force = "" if force_N is None else f", mean contact force {force_N:.3g} N"
    return (f"joint {joint} whirls: its contact point runs round the bearing {abs(revolutions):,.0f} times per cycle "
            f"({'backward' if revolutions < 0 else 'forward'}{force}), a friction-driven whirl of the journal in its "
            "bore that the model's equations allow beside the calm motion; the forces and the wear depend on which "
            "of the two the run is in (docs/dynamics.md, 'Friction-driven whirl')")


#: what a contact wider than the Hertz law's range means when the bushing really is soft (no unit slip)
SOFT_CONTACT_NOTE = ("A bushing that really is that soft (a polymer) lies outside what the point-contact law describes "
                     "(no line or conformal law is implemented): its worn volume stands, as it does not depend on the "
                     "contact law, but its depth profile and the life read from it are indicative")


def half_angle_text(degrees: float) -> str:
    """'12.3 deg wide each side', or, for a Hertz half-width past half the bore, that the formula reads it wider
    than the bore (a contact cannot wrap beyond it)."""
    if degrees > 180.0:
        return f"wider than the whole bore (Hertz's half-width reads {degrees:.3g} deg each side)"
    return f"{degrees:.3g} deg wide each side"


@dataclass(repr=False, eq=False)  # StageResult compares by value
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
    driver_torque_mean_N_m: float | None = None
    driver_torque_rms_N_m: float | None = None
    driver_torque_max_N_m: float | None = None
    series_file: str = "simulate.npz"
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    trace: Any = field(default=None, repr=False, metadata={"json": False})
    #: where a loaded result's series are (``simulate.npz`` beside its JSON): :meth:`plot` reads them
    series_path: Path | None = field(default=None, repr=False, metadata={"json": False})

    def outside_hertz_joints(self) -> list[str]:
        """The joints whose contact at its largest normal force is too wide for the Hertz reading of the contact law
        (contact.geometry.HERTZ_HALF_ANGLE_LIMIT; docs/dynamics.md, "Where the contact law holds")."""
        from jointwear.contact.geometry import HERTZ_HALF_ANGLE_LIMIT

        limit = math.degrees(HERTZ_HALF_ANGLE_LIMIT)
        return [j["name"] for j in self.joints if (j.get("contact_half_angle_deg") or 0.0) > limit]

    def outside_hertz(self) -> list[str]:
        """One sentence per joint of :meth:`outside_hertz_joints`."""
        from jointwear.contact.geometry import HERTZ_HALF_ANGLE_LIMIT

        limit = math.degrees(HERTZ_HALF_ANGLE_LIMIT)
        wide = self.outside_hertz_joints()
        return [f"joint {j['name']}'s contact is {half_angle_text(j['contact_half_angle_deg'])} at its largest "
                f"normal force ({j['normal_force_max_N']:.3g} N; Hertz half-width on the unworn radii), more than the "
                f"{limit:.3g} deg to which the Hertz contact law holds: its forces, penetrations (up to "
                f"{j['max_penetration_m'] * 1e6:.3g} um against a clearance of {j['clearance_m'] * 1e6:.3g} um) and "
                "the wear laid on that width are indicative only (docs/dynamics.md, 'Where the contact law holds'). "
                "The width grows as sqrt(load / (width x Young's modulus)): either the load is that large (check the "
                "masses, inertias, crank speed and driving torques; the mean normal force is "
                f"{j.get('contact_force_mean_N') or 0.0:.3g} N), or the contact is too narrow or soft (check "
                f"clearance_joints.{j['name']}.width and its materials' youngs_modulus for a unit slip: width_um for "
                "width_mm, youngs_modulus_MPa for _GPa). " + SOFT_CONTACT_NOTE
                for j in self.joints if j["name"] in wide]

    def whirls(self) -> list[str]:
        """One sentence per joint in a friction-driven whirl (docs/dynamics.md, "Friction-driven whirl")."""
        return [whirl_sentence(j["name"], j["contact_revolutions_per_cycle"], j["contact_force_mean_N"])
                for j in self.joints if j.get("whirl")]

    @classmethod
    def from_simulation(cls, res, name: str = "") -> SimulationSummary:
        from jointwear.contact.geometry import hertz_half_angle
        from jointwear.mechanism import whirl_measure
        from jointwear.mechanism.simulate import trapezoid_weights

        total = res.n_cycles + res.settle_cycles
        joints = []
        for tr in res.joints:
            f = tr.contact_force
            fn_max = float(tr.force_normal.max()) if tr.force_normal.size else 0.0
            revolutions, whirl = whirl_measure(tr, res.n_cycles)
            joints.append({
                "name": tr.name, "bearing_body": tr.bearing_body, "journal_body": tr.journal_body,
                "contact_force_mean_N": tr.mean_force,
                "contact_force_max_N": float(f.max()) if f.size else 0.0,
                "normal_force_mean_N": float(np.sum(tr.dt_weight * tr.force_normal) / tr.duration),
                "contact_fraction": tr.contact_fraction,
                "impacts_per_cycle": tr.n_impacts / res.n_cycles,
                "max_penetration_m": float(tr.penetration.max()),
                "normal_force_max_N": fn_max,
                "contact_half_angle_deg": math.degrees(hertz_half_angle(
                    fn_max, tr.bearing_radius, tr.journal_radius, tr.joint.hsum, tr.joint.width)),
                "clearance_m": tr.clearance_used,
                "stiffness_N_per_m1p5": float(np.median(tr.stiffness)),
                "contact_revolutions_per_cycle": revolutions,
                "whirl": whirl,
            })
        first = joints[0] if joints else {}
        torque = _driver_torque(res)
        if torque is not None:
            w = trapezoid_weights(res.t)
            torque_stats = {"driver_torque_mean_N_m": float(np.sum(w * torque) / np.sum(w)),
                            "driver_torque_rms_N_m": float(np.sqrt(np.sum(w * torque**2) / np.sum(w))),
                            "driver_torque_max_N_m": float(np.max(np.abs(torque)))}
        else:
            torque_stats = {}
        return cls(**torque_stats,
            config=name, cycles=res.n_cycles, settle_cycles=res.settle_cycles, period_s=res.period,
            steps_per_cycle=res.steps_per_cycle,
            wall_seconds_per_cycle=res.wall_seconds / total if total else math.nan,
            wall_seconds=res.wall_seconds, accepted_steps=res.n_steps, rejected_steps=res.n_rejected,
            kernel=res.extra.get("kernel", ""), joints=joints,
            contact_force_mean_N=first.get("contact_force_mean_N"),
            contact_force_max_N=first.get("contact_force_max_N"),
            contact_fraction=first.get("contact_fraction"), impacts_per_cycle=first.get("impacts_per_cycle"),
            provenance=provenance(), trace=res)

    def tables(self) -> dict[str, dict[str, Any]]:
        """``simulate_joints``: one row per clearance joint (forces, contact, penetration, whirl)."""
        keys = [k for k in (self.joints[0] if self.joints else {}) if k not in ("bearing_body", "journal_body")]
        return {"simulate_joints": {k: [j[k] for j in self.joints] for k in keys}}

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``simulate.json``, ``simulate_joints.csv`` (:meth:`tables`), ``simulate.npz`` (series) and the
        figures."""
        folder = Path(folder)
        self.write_tables(folder)
        res = self.trace
        if res is None:
            return self.write(folder)
        data: dict[str, np.ndarray] = {"t_s": res.t, "crank_angle_rad": res.crank_angle,
                                       "body_angles_rad": res.body_angles, "body_names": np.array(res.body_names)}
        torque = _driver_torque(res)
        if torque is not None:
            data["driver_torque_N_m"] = torque
        for tr in res.joints:
            p = f"{tr.name}_"
            data[p + "eccentricity_bearing_frame_m"] = tr.eccentricity
            data[p + "theta_bearing_rad"] = tr.theta_bearing
            data[p + "force_normal_N"] = tr.force_normal
            data[p + "force_tangential_N"] = tr.force_tangential
            data[p + "slip_speed_m_s"] = tr.slip_speed
            data[p + "penetration_m"] = tr.penetration
            data[p + "in_contact"] = tr.in_contact
        buf = io.BytesIO()
        np.savez_compressed(buf, **data)
        write_bytes_atomic(folder / self.series_file, buf.getvalue())
        if figures:
            for tr, label in zip(res.joints, file_labels([tr.name for tr in res.joints])):
                save_figure(self.plot(tr.name, "orbit"), folder / f"orbit_{label}.png")
                save_figure(self.plot(tr.name, "force"), folder / f"force_{label}.png")
        return self.write(folder)  # last: a result whose JSON is there is whole

    @classmethod
    def load(cls, folder: Path | str) -> SimulationSummary:
        """Read ``simulate.json`` back; :meth:`plot` reads the series from ``simulate.npz`` beside it."""
        out = super().load(folder)
        out.series_path = Path(folder) / out.series_file
        return out

    def plot(self, joint: str | None = None, kind: str = "orbit") -> Figure:
        """The journal centre's orbit in the bearing's frame (``kind="orbit"``) or the contact force over the crank
        angle (``kind="force"``) of ``joint`` (default: the first), as the stage draws them: a matplotlib ``Figure``.
        Needs the series: a result computed in this process, or one loaded from a folder with its ``simulate.npz``."""
        from jointwear.report import figures as F

        names = [j["name"] for j in self.joints]
        if joint is not None and joint not in names:
            raise KeyError(f"SimulationSummary has no joint {joint!r}; its joints: {', '.join(names)}")
        if kind not in ("orbit", "force"):
            raise ValueError(f"kind must be 'orbit' or 'force' (got {kind!r})")
        row = self.joints[names.index(joint) if joint is not None else 0]
        name = row["name"]
        if kind == "orbit":
            ecc = self._series(name, "eccentricity_bearing_frame_m")
            return F.orbit_figure(ecc[:, 0] * 1e3, ecc[:, 1] * 1e3, row["clearance_m"] * 1e3,
                                  title=f"Journal centre orbit, joint {name}")
        force = np.hypot(self._series(name, "force_normal_N"), self._series(name, "force_tangential_N"))
        return F.contact_force_figure(np.degrees(self._series(None, "crank_angle_rad")), force,
                                      mean_N=row["contact_force_mean_N"], title=f"Contact force, joint {name}")

    def _series(self, joint: str | None, key: str) -> np.ndarray:
        """One recorded series (``simulate.npz``'s key, a joint's without its prefix) from the trace or the file."""
        if self.trace is not None:
            owner = self.trace if joint is None else next(t for t in self.trace.joints if t.name == joint)
            return getattr(owner, _TRACE_ATTRIBUTES[key])  # only the one asked for (eccentricity: trig per step)
        path = self.series_path
        if path is None or not path.is_file():
            raise ValueError("the simulation's series are not here: plot a result computed in this process, or one "
                             f"loaded from a folder that holds its {self.series_file}")
        with np.load(path) as data:
            return data[key if joint is None else f"{joint}_{key}"]


def _driver_torque(res) -> np.ndarray | None:
    """The driver's torque series of a simulation (SimulationResult.driver_torque), None where it has none (several
    driven bodies, a worn profile); computed once per result."""
    if "driver_torque" not in res.extra:
        try:
            res.extra["driver_torque"] = res.driver_torque
        except ValueError:
            res.extra["driver_torque"] = None
    return res.extra["driver_torque"]


# ------------------------------------------------------------------------------------------------------- wear
#: per-cell columns of a joint's wear profile besides the depth (wear.json ``profile`` and wear_profile.csv)
_PANEL_KEYS = ("contact_force_mean_N", "sliding_mm_per_deg_per_cycle", "contact_area_mean_mm2", "body_angle_deg",
               "contact_time_s_per_cycle", "depth_rate_mm_per_cycle", "depth_growth_mm_per_cycle")


def _profile_panels(jw, order) -> dict[str, list[float]]:
    """Mean contact force, sliding distance per degree of bearing, mean contact area, the cell's angle in the
    bearing body's frame, contact time and depth rate of each bearing cell over the last simulated cycles, and the
    depth each cell gained per cycle over the last block, in the profile's angle order (kept in wear.json, so that a
    folder read back gives the CSV's every column)."""
    d = jw.diagnostics
    cell_deg = 360.0 / jw.theta.size
    growth = {} if jw.last_growth is None else {"depth_growth_mm_per_cycle": (jw.last_growth[order] * 1e3).tolist()}
    return {"contact_force_mean_N": d.force_mean[order].tolist(),
            "sliding_mm_per_deg_per_cycle": (d.slip_distance[order] * 1e3 / cell_deg).tolist(),
            "contact_area_mean_mm2": (d.area_mean[order] * 1e6).tolist(),
            "body_angle_deg": np.degrees(jw.theta[order]).tolist(),
            "contact_time_s_per_cycle": d.contact_time[order].tolist(),
            "depth_rate_mm_per_cycle": (d.bearing[order] * 1e3).tolist()} | growth


def _last_slope_mm(cycles: np.ndarray, depth_m: np.ndarray) -> float | None:
    """Growth of a depth history over its last segment, mm per cycle (None with fewer than two points)."""
    n, d = np.asarray(cycles, dtype=float), np.asarray(depth_m, dtype=float)
    if n.size < 2 or n[-1] == n[-2]:
        return None
    return float((d[-1] - d[-2]) / (n[-1] - n[-2]) * 1e3)


@dataclass(repr=False, eq=False)  # StageResult compares by value
class WearSummary(StageResult):
    """The wear history of the nominal mechanism (``jointwear wear``).

    Top-level keys are those of the first clearance joint (the JSON contract): ``max_wear_mm``,
    ``max_wear_angle_deg``, ``peaks`` [{``angle_deg``, ``depth_mm``}], ``profile`` {``angle_deg``,
    ``depth_mm``}, ``history`` {``cycles``, ``max_wear_mm``}; ``joints`` has the same for every joint plus the
    journal's wear, the clearance growth, the Archard volumes and the wear-rate diagnostics.
    ``conformity`` (joint 0) is the half worn arc of a bore worn to the journal's shape over the contact's
    half-angle on the unworn bore (a joint's ``contact_half_width_um``: Johnson's half-width at the first block's mean
    force; ``max_half_width_um`` is the largest in the last block's recorded cycles); ``uniform_mode_valid`` is
    False when it exceeds 1 for any joint, where only ``geometry_mode = "profile"`` describes the contact
    (docs/wear.md). ``limit_mm`` is the first joint's allowance; each joint's own is its ``allowance_mm``, and its
    ``nominal_life_cycles`` the cycles at which its ``quantity`` (the limit state's) reaches that allowance within
    the history (None where it stays below it, or has no allowance).
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
    angle_convention: str = ("the bearing body's frame laid at its mean orientation; 0 deg = leftmost point, "
                             "clockwise")
    settings: dict = field(default_factory=dict)
    geometry_mode: str = "uniform"
    limit_mm: float | None = None
    quantity: str | None = None  # the limit state's, which the joints' nominal lives are read in
    conformity: float | None = None
    uniform_mode_valid: bool | None = None
    stopped_at_cycles: int | None = None  # ``cycles`` then holds these, the history's end, and
    cycles_requested: int | None = None  # this what was asked
    stop_reason: str | None = None
    files: list[str] = field(default_factory=list)
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    history_result: Any = field(default=None, repr=False, metadata={"json": False})

    @classmethod
    def from_history(cls, res, config=None, allowances_m: dict[str, float] | None = None) -> WearSummary:
        """Summarise a :class:`jointwear.wear.WearResult` of ``config`` (allowances by joint name, m; each joint's
        nominal life is read in ``config.reliability.quantity``, the bearing's max depth without a config)."""
        from jointwear.study.limit_state import life_within_history
        from jointwear.wear.angles import report_angle_deg
        from jointwear.wear.results import conservation_error

        allowances_m = allowances_m or {}
        quantity = config.reliability.quantity if config is not None else "bearing_max_depth"
        joints = []
        for jw in res.joints:
            name = str(config.clearance_joints[jw.index].name) if config is not None else f"joint{jw.index}"
            ang = jw.angle_deg
            o = np.argsort(ang)
            jang = report_angle_deg(jw.theta, 0.0)
            jo = np.argsort(jang)
            eb, ej = conservation_error(jw)
            a = allowances_m.get(name)
            cj = config.clearance_joints[jw.index] if config is not None else None
            outer = None if cj is None else cj.bearing_outer_radius
            wall = None if outer is None else outer - cj.bearing_radius
            joints.append({
                "name": name,
                "max_wear_mm": jw.max_bearing_wear * 1e3,
                "max_wear_angle_deg": jw.max_wear_angle_deg,
                "peaks": [{"angle_deg": p["angle_deg"], "depth_mm": p["depth"] * 1e3} for p in jw.peaks],
                "profile": {"angle_deg": ang[o].tolist(), "depth_mm": (jw.bearing_wear[o] * 1e3).tolist(),
                            **_profile_panels(jw, o)},
                "history": {"cycles": jw.history_cycles.astype(int).tolist(),
                            "max_wear_mm": (jw.history_max_bearing * 1e3).tolist(),
                            "max_journal_wear_mm": (jw.history_max_journal * 1e3).tolist(),
                            # profile mode grows no clearance in the dynamics: the limit state's measure instead
                            "clearance_growth_mm": ((jw.history_max_bearing + jw.history_max_journal
                                                     if res.settings.geometry_mode == "profile"
                                                     else jw.history_clearance_growth) * 1e3).tolist()},
                "journal": {"max_wear_mm": float(jw.journal_wear.max() * 1e3),
                            "mean_wear_mm": float(jw.journal_wear.mean() * 1e3),
                            "angle_convention": "journal frame laid along +x; 0 deg leftmost, clockwise",
                            "profile": {"angle_deg": jang[jo].tolist(),
                                        "depth_mm": (jw.journal_wear[jo] * 1e3).tolist()}},
                "bearing_radius_mm": jw.bearing_radius * 1e3,
                "bearing_wall_mm": None if wall is None else wall * 1e3,
                "allowance_mm": None if a is None else a * 1e3,
                "bearing_mean_orientation_deg": math.degrees(jw.mean_orientation),
                "rod_mean_orientation_deg": math.degrees(jw.mean_orientation),  # its name in earlier files
                "archard_volume_mm3": {"bearing": jw.volume_bearing * 1e9, "journal": jw.volume_journal * 1e9},
                "conservation_rel_error": {"bearing": eb, "journal": ej},
                # the peak of one block's wear-rate profile (the touching point's rate, which in profile mode moves
                # round a conformal pocket); the deepest point's growth is max_depth_growth_mm_per_cycle
                "wear_rate_initial_mm_per_cycle": float(jw.first_rate.bearing.max() * 1e3),
                "wear_rate_final_mm_per_cycle": float(jw.diagnostics.bearing.max() * 1e3),
                "max_depth_growth_mm_per_cycle": _last_slope_mm(jw.history_cycles, jw.history_max_bearing),
                # the largest over the last block's recorded cycles (a wide unworn contact narrows as it wears in);
                # the first block's, at its mean force on the unworn radii, is what the conformity is measured on
                "max_half_width_um": jw.diagnostics.max_half_width * 1e6,
                "contact_half_width_um": jw.contact_half_width * 1e6,
                "conformity": jw.conformity,
                "uniform_mode_valid": jw.uniform_mode_valid,
            })
            row = joints[-1]  # what the wear stage prints, kept: the judged quantity's crossing of the allowance
            row["nominal_life_cycles"] = life_within_history(row["history"], row["allowance_mm"], quantity)
        j0 = joints[0]
        return cls(
            cycles=res.n_cycles if res.stopped_at is None else res.stopped_at, max_wear_mm=j0["max_wear_mm"],
            max_wear_angle_deg=j0["max_wear_angle_deg"],
            peaks=j0["peaks"], profile=j0["profile"],
            history={"cycles": j0["history"]["cycles"], "max_wear_mm": j0["history"]["max_wear_mm"]},
            journal=j0["journal"], wall_seconds=res.wall_seconds, joints=joints,
            simulation_seconds=res.sim_seconds, n_simulated_cycles=res.n_simulated_cycles,
            n_blocks=len(res.blocks),
            blocks=[{"start": b.start, "size": b.size, "peak_rate_mm_per_cycle": b.peak_rate * 1e3,
                     "rate_change": None if math.isnan(b.rate_change) else b.rate_change,
                     "contact_revolutions_per_cycle": list(b.contact_revolutions),
                     "whirl": [joints[i]["name"] for i, w in enumerate(b.whirl) if w]} for b in res.blocks],
            settings=res.settings.model_dump(mode="json"), geometry_mode=res.settings.geometry_mode,
            limit_mm=j0["allowance_mm"], quantity=quantity, conformity=j0["conformity"],
            uniform_mode_valid=all(j["uniform_mode_valid"] for j in joints), stopped_at_cycles=res.stopped_at,
            cycles_requested=res.n_cycles, stop_reason=res.stop_reason, provenance=provenance(), history_result=res)

    def worn_away(self) -> list[str]:
        """The sentence saying that the history stopped early because a joint was worn away, if it did."""
        if self.stopped_at_cycles is None:
            return []
        asked = self.cycles_requested or self.cycles
        return [f"the history stopped at {self.stopped_at_cycles:,} of {asked:,} cycles because {self.stop_reason}: "
                "the joint is worn away, which the wear model does not describe (docs/wear.md, 'A joint worn away')"]

    def whirls(self) -> list[str]:
        """One sentence per joint that whirled in some blocks of the history (docs/dynamics.md, "Friction-driven
        whirl"): its wear is spread round the bore there, so the depth depends on how many blocks whirled."""
        out = []
        for k, j in enumerate(self.joints):
            spun = [b for b in self.blocks if j["name"] in (b.get("whirl") or [])]
            if spun:
                most = max((b["contact_revolutions_per_cycle"][k] for b in spun), key=abs)
                cycles = sum(b["size"] for b in spun)
                out.append(f"{whirl_sentence(j['name'], most)}; here in {len(spun)} of {len(self.blocks)} blocks "
                           f"({cycles:,} of {self.cycles:,} cycles)")
        return out

    @property
    def uniform_out_of_range(self) -> bool:
        """Whether the history ran in uniform mode where the worn pocket outgrew the contact patch (conformity > 1),
        so that profile mode's answer is the one to trust (docs/wear.md)."""
        return self.geometry_mode == "uniform" and self.uniform_mode_valid is False

    def uniform_range_sentence(self) -> str:
        """What to do when uniform mode ran outside its range (:attr:`uniform_out_of_range`), with each joint's
        conformity past 1 when there are several; '' otherwise."""
        if not self.uniform_out_of_range:
            return ""
        conformity = (f"conformity {self.conformity:.3g}" if len(self.joints) < 2 else "conformity " + ", ".join(
            f"{j['conformity']:.3g} at joint {j['name']}" for j in self.joints if j.get("uniform_mode_valid") is False))
        return (f"uniform mode is outside its range here ({conformity} > 1: the journal fits into its own wear); "
                'wear.geometry_mode = "profile" follows it (docs/wear.md)')

    def outside_hertz(self, skip: Collection[str] = ()) -> list[str]:
        """One sentence per joint whose contact, at the largest force of the history's last recorded cycles, is too
        wide for the Hertz reading of the contact law (Johnson's half-width on the current radii; the dynamics stage
        says the same of its own cycles: docs/dynamics.md, "Where the contact law holds"); ``skip``: joints already
        told of."""
        from jointwear.contact.geometry import HERTZ_HALF_ANGLE_LIMIT
        from jointwear.wear.settings import JOHNSON_FACTOR

        factor = float(self.settings.get("half_width_factor") or JOHNSON_FACTOR)
        own = not math.isclose(factor, JOHNSON_FACTOR, rel_tol=1e-9)
        out = []
        for j in self.joints:
            if j["name"] in skip:
                continue
            radius_um = (j.get("bearing_radius_mm") or 0.0) * 1e3
            width = j.get("max_half_width_um") or 0.0
            if radius_um > 0.0 and width / radius_um > HERTZ_HALF_ANGLE_LIMIT:
                # a factor of one's own, not the material, may make it so wide: said first, with Johnson's width
                why = (f"It is read with wear.half_width_factor = {factor:g}, {factor / JOHNSON_FACTOR:.3g} times "
                       f"Johnson's {JOHNSON_FACTOR:.4g}, which gives {width * JOHNSON_FACTOR / factor:.4g} um: check "
                       "that setting first. " if own else "")
                out.append(f"joint {j['name']}'s contact is {half_angle_text(math.degrees(width / radius_um))} "
                           f"in the history's last recorded cycles (Johnson's half-width {width:.4g} um on a "
                           f"{radius_um / 1e3:.4g} mm bore), more than the {math.degrees(HERTZ_HALF_ANGLE_LIMIT):.3g} "
                           f"deg to which the Hertz contact law holds. {why}{SOFT_CONTACT_NOTE}")
        return out

    def worn_through(self) -> list[str]:
        """One sentence per joint whose bearing wear is deeper than its bushing wall (bearing_outer_radius -
        bearing_radius): a worn-through bushing, which the wear model does not describe."""
        return [f"joint {j['name']}'s bearing wear ({j['max_wear_mm']:.3g} mm) is deeper than its wall "
                f"({j['bearing_wall_mm']:.3g} mm, bearing_outer_radius - bearing_radius): the bushing is worn through "
                f"within {self.cycles:,} cycles, which the wear model does not describe"
                for j in self.joints
                if j.get("bearing_wall_mm") is not None and j["max_wear_mm"] > j["bearing_wall_mm"]]

    def unjudged_wear(self, quantity: str) -> list[str]:
        """One sentence per joint whose part that the limit state ``quantity`` does not judge wears past the joint's
        allowance: a journal deeper than the allowance under 'bearing_max_depth', a bearing under
        'journal_max_depth' ('clearance_growth' judges both)."""
        other = {"bearing_max_depth": ("journal", "journal_max_depth"),
                 "journal_max_depth": ("bearing", "bearing_max_depth")}.get(quantity)
        if other is None:
            return []
        part, setting = other
        out = []
        for j in self.joints:
            allowance = j.get("allowance_mm")
            depth = (j.get("journal") or {}).get("max_wear_mm") if part == "journal" else j.get("max_wear_mm")
            if allowance and depth is not None and depth > allowance:
                out.append(f"joint {j['name']}'s {part} wears {depth:.3g} mm within {self.cycles:,} cycles, past the "
                           f"allowance of {allowance:.3g} mm, which the limit state does not judge "
                           f"(reliability.quantity = '{quantity}'); '{setting}' or 'clearance_growth' would")
        return out

    def _suffixes(self) -> list[str]:
        """Each joint's file-name suffix: none for a single joint, else its name made safe for a file name."""
        if len(self.joints) == 1:
            return [""]
        return [f"_{label}" for label in file_labels([joint["name"] for joint in self.joints])]

    def tables(self) -> dict[str, dict[str, Any]]:
        """Per joint: ``wear_history`` (the maximum depths and the clearance growth against cycles),
        ``wear_journal_profile`` and ``wear_profile`` (depth and the per-cycle contact quantities round the bearing);
        with several joints each name ends in the joint's (``wear_profile_A``)."""
        out: dict[str, dict[str, Any]] = {}
        for joint, sfx in zip(self.joints, self._suffixes()):
            h = joint["history"]
            out[f"wear_history{sfx}"] = {
                "cycles": h["cycles"], "max_bearing_wear_mm": h["max_wear_mm"],
                "max_journal_wear_mm": h["max_journal_wear_mm"], "clearance_growth_mm": h["clearance_growth_mm"]}
            jp = joint["journal"]["profile"]
            out[f"wear_journal_profile{sfx}"] = {"angle_deg": jp["angle_deg"], "journal_depth_mm": jp["depth_mm"]}
            prof = joint["profile"]
            cols = {"angle_deg": prof["angle_deg"], "bearing_depth_mm": prof["depth_mm"],
                    **{key: prof[key] for key in _PANEL_KEYS if key in prof}}
            out[f"wear_profile{sfx}"] = cols
        return out

    def plot(self, joint: str | None = None) -> Figure:
        """The worn bearing of ``joint`` (default: the first) in polar form, its depth exaggerated, with its peaks: a
        matplotlib ``Figure``, for a notebook or ``fig.savefig``."""
        from jointwear.report import figures as F

        names = [j["name"] for j in self.joints]
        if joint is not None and joint not in names:
            raise KeyError(f"WearSummary has no joint {joint!r}; its joints: {', '.join(names)}")
        row = self.joints[names.index(joint) if joint is not None else 0]
        prof = row["profile"]
        return F.wear_polar_figure(prof["angle_deg"], prof["depth_mm"], radius_mm=row.get("bearing_radius_mm"),
                                   peaks=row["peaks"], cycles=self.cycles, title=f"Worn bearing, joint {row['name']}")

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``wear.json``, the CSV tables of every joint (:meth:`tables`) and the figures (with several joints,
        each joint's files end in its name: ``wear_profile_A.csv``)."""
        folder = Path(folder)
        files = self.write_tables(folder)
        if figures:
            from jointwear.report import figures as F

            for joint, sfx in zip(self.joints, self._suffixes()):
                h, prof = joint["history"], joint["profile"]
                named = joint["name"] if len(self.joints) > 1 else None  # the figure's title names it
                save_figure(self.plot(joint["name"]), folder / f"wear_polar{sfx}.png")
                panels = "contact_force_mean_N" in prof
                if panels:
                    save_figure(F.wear_panels_figure(prof["angle_deg"], prof["depth_mm"],
                                                  slip_mm=prof["sliding_mm_per_deg_per_cycle"],
                                                  contact_force_N=prof["contact_force_mean_N"],
                                                  contact_area_mm2=prof["contact_area_mean_mm2"], cycles=self.cycles,
                                                  slip_unit="mm/deg per cycle", slip_quantity="sliding distance",
                                                  joint=named),
                             folder / f"wear_vs_angle{sfx}.png")
                save_figure(F.wear_history_figure(h["cycles"], h["max_wear_mm"], limit_mm=joint.get("allowance_mm"),
                                                  joint=named),
                         folder / f"wear_history{sfx}.png")
                files += [f"wear_polar{sfx}.png", f"wear_history{sfx}.png"] + (
                    [f"wear_vs_angle{sfx}.png"] if panels else [])
        self.files = files
        return self.write(folder)


# ---------------------------------------------------------------------------------------------------- loading
@dataclass(repr=False)
class StudyResults:
    """Every stage result found in a study folder (None where a stage has not run) and the resolved config."""

    folder: Path
    config: dict | None = None
    simulate: SimulationSummary | None = None
    wear: WearSummary | None = None
    reliability: ReliabilityCurve | None = None
    sensitivity: SensitivityResult | None = None
    validation: ValidationResult | None = None
    design: StageResult | None = None  # the design stage's DesignResult
    wear_convergence: WearConvergence | None = None
    errors: dict[str, str] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (f"StudyResults(folder={str(self.folder)!r}, name={self.name!r}, stages={self.stages}"
                + (f", errors={self.errors}" if self.errors else "") + ")")

    @property
    def name(self) -> str | None:
        """The study's name, from its ``config.json`` (None when the folder has none)."""
        return (self.config or {}).get("name")

    def setting(self, name: str) -> Any:
        """The value ``config.json`` records for a setting, in its recorded units (None when it records none)."""
        return next((s.get("value") for s in (self.config or {}).get("settings", []) if s.get("name") == name), None)

    @property
    def stages(self) -> list[str]:
        """The stages with a result in the folder."""
        return [s for s in ("simulate", "wear", "wear_convergence", "reliability", "sensitivity", "validation",
                          "design")
                if getattr(self, s) is not None]


STAGE_TYPES: dict[str, type] = {"simulate": SimulationSummary, "wear": WearSummary,
                                "wear_convergence": WearConvergence, "reliability": ReliabilityCurve,
                                "sensitivity": SensitivityResult, "validation": ValidationResult}

#: the result types of the stages built on the study (the design stage), each by a function that imports it: filled
#: by the layer above both (:mod:`jointwear.study.facade`), so that reading a folder imports none of their packages
LATER_STAGE_TYPES: dict[str, Callable[[], type[StageResult]]] = {}


def stage_types() -> dict[str, type[StageResult]]:
    """Every stage's result type by stage name, in the study's order: ``STAGE_TYPES``, then the later stages'."""
    return {**STAGE_TYPES, **{stage: result_type() for stage, result_type in LATER_STAGE_TYPES.items()}}


def load_results(folder: Path | str) -> StudyResults:
    """Read the typed results of a study back from its output folder.

    Parameters
    ----------
    folder : str or Path
        The ``--out`` folder of a study.

    Returns
    -------
    StudyResults
        One typed result per stage; a stage whose file is missing is None, one whose file cannot be read is
        None with the reason in ``errors``.

    Raises
    ------
    FileNotFoundError
        ``folder`` is not a directory, or holds neither ``config.json`` nor any stage's file (a mistyped folder, or
        the folder above a study's, would otherwise read as a study with no results); the message names the
        subfolders that hold studies.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(f"no study folder '{folder}'")
    types = stage_types()
    files = ("config.json", *(cls.FILE for cls in types.values()))
    if not any((folder / name).is_file() for name in files):
        inside = sorted(p.name for p in folder.iterdir() if p.is_dir() and any((p / f).is_file() for f in files))
        raise FileNotFoundError(
            f"'{folder}' holds no study results (none of {', '.join(files)})"
            + (f"; these folders in it do: {', '.join(inside[:10])}{', ...' if len(inside) > 10 else ''}"
               if inside else ""))
    out = StudyResults(folder)
    cfg = folder / "config.json"
    if cfg.is_file():
        try:
            out.config = read_json(cfg)
        except (OSError, ValueError) as exc:
            out.errors["config"] = f"config.json could not be read: {exc}"
    for stage, cls in types.items():
        path = folder / cls.FILE
        if not path.is_file():
            continue
        try:
            setattr(out, stage, cls.load(folder))
        except (OSError, ValueError, KeyError, TypeError, OverflowError) as exc:  # 1e300 where a count is due
            out.errors[stage] = f"{cls.FILE} could not be read: {exc}"
    return out


#: the trace's attribute behind each series of simulate.npz that SimulationSummary.plot draws (a joint's: unprefixed)
_TRACE_ATTRIBUTES = {"crank_angle_rad": "crank_angle", "t_s": "t", "eccentricity_bearing_frame_m": "eccentricity",
                     "force_normal_N": "force_normal", "force_tangential_N": "force_tangential"}


#: what a command that needs a stage's result says of a folder without one
NO_STUDY_RESULTS = "has no study results (simulate.json, wear.json, reliability.json or sensitivity.json)"


def results_of_a_study(folder: Path | str, what: str) -> StudyResults:
    """:func:`load_results` for a command (``what``) that needs at least one stage's result: a ConfigError otherwise,
    the same from the command line and from Python (the subfolders that hold studies named when ``folder`` is the
    one above them)."""
    try:
        results = load_results(folder)
    except FileNotFoundError as exc:
        raise ConfigError(f"{what}: {exc}" if Path(folder).is_dir() else f"{what}: '{folder}' {NO_STUDY_RESULTS}") \
            from None
    if not results.stages:
        raise ConfigError(f"{what}: '{folder}' {NO_STUDY_RESULTS}")
    return results
