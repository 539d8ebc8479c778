"""`jointwear wear`: run the wear history and write wear.json, CSV data and figures.

The command-line wiring lives in jointwear/cli.py (owned by the dynamics/lead); it calls `wear_command`.
Millimetres and degrees exist only here and in plots.py (output edge).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from .angles import report_angle_deg
from .history import WearResult, conservation_error, wear_history
from .settings import WearSettings, check_cycles

MM = 1e3  # m -> mm


def settings_from_config(config) -> WearSettings:
    s = getattr(config, "wear", None)
    if isinstance(s, WearSettings):
        return s
    if isinstance(s, dict):
        return WearSettings.model_validate(s)
    return WearSettings()


def _joint_name(config, i: int) -> str:
    try:
        return str(config.clearance_joints[i].name)
    except Exception:  # noqa: BLE001
        return f"joint{i}"


def result_summary(res: WearResult, config=None) -> dict:
    """The JSON-ready summary of a wear history (DESIGN.md keys for joint 0, plus every joint)."""
    joints = []
    for jw in res.joints:
        ang = jw.angle_deg
        o = np.argsort(ang)
        jang = report_angle_deg(jw.theta, 0.0)
        jo = np.argsort(jang)
        eb, ej = conservation_error(jw)
        joints.append({
            "name": _joint_name(config, jw.index),
            "max_wear_mm": jw.max_bearing_wear * MM,
            "max_wear_angle_deg": jw.max_wear_angle_deg,
            "peaks": [{"angle_deg": p["angle_deg"], "depth_mm": p["depth"] * MM} for p in jw.peaks],
            "profile": {"angle_deg": ang[o].tolist(), "depth_mm": (jw.bearing_wear[o] * MM).tolist()},
            "history": {"cycles": jw.history_cycles.astype(int).tolist(),
                        "max_wear_mm": (jw.history_max_bearing * MM).tolist(),
                        "max_journal_wear_mm": (jw.history_max_journal * MM).tolist(),
                        "clearance_growth_mm": (jw.history_clearance_growth * MM).tolist()},
            "journal": {"max_wear_mm": float(jw.journal_wear.max() * MM),
                        "mean_wear_mm": float(jw.journal_wear.mean() * MM),
                        "angle_convention": "journal (crank) frame laid along +x; 0 deg leftmost, clockwise",
                        "profile": {"angle_deg": jang[jo].tolist(), "depth_mm": (jw.journal_wear[jo] * MM).tolist()}},
            "rod_mean_orientation_deg": math.degrees(jw.mean_orientation),
            "archard_volume_mm3": {"bearing": jw.volume_bearing * 1e9, "journal": jw.volume_journal * 1e9},
            "conservation_rel_error": {"bearing": eb, "journal": ej},
            "wear_rate_initial_mm_per_cycle": float(jw.first_rate.bearing.max() * MM),
            "wear_rate_final_mm_per_cycle": float(jw.diagnostics.bearing.max() * MM),
            "max_half_width_um": jw.diagnostics.max_half_width * 1e6,
        })
    j0 = joints[0]
    out = {
        "cycles": res.n_cycles,
        "max_wear_mm": j0["max_wear_mm"],
        "max_wear_angle_deg": j0["max_wear_angle_deg"],
        "peaks": j0["peaks"],
        "profile": j0["profile"],
        "history": {"cycles": j0["history"]["cycles"], "max_wear_mm": j0["history"]["max_wear_mm"]},
        "journal": j0["journal"],
        "wall_seconds": res.wall_seconds,
        "simulation_seconds": res.sim_seconds,
        "n_simulated_cycles": res.n_simulated_cycles,
        "n_blocks": len(res.blocks),
        "blocks": [{"start": b.start, "size": b.size, "peak_rate_mm_per_cycle": b.peak_rate * MM,
                    "rate_change": None if math.isnan(b.rate_change) else b.rate_change} for b in res.blocks],
        "angle_convention": "bearing (rod) frame laid at the rod's mean orientation; 0 deg = leftmost point, clockwise",
        "settings": res.settings.model_dump(mode="json"),
        "joints": joints,
    }
    return out


def _write_csv(path: Path, header: list[str], cols: list) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for row in zip(*cols):
            w.writerow([f"{v:.10g}" if isinstance(v, (float, np.floating)) else v for v in row])


def write_outputs(res: WearResult, out_dir, config=None, figures: bool = True) -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = result_summary(res, config)
    files = []
    for jw in res.joints:
        sfx = "" if jw.index == 0 else f"_{jw.index}"
        d = jw.diagnostics
        ang = jw.angle_deg
        o = np.argsort(ang)
        cell = 360.0 / jw.theta.size
        p = out / f"wear_profile{sfx}.csv"
        _write_csv(p, ["angle_deg", "bearing_depth_mm", "body_angle_deg", "contact_force_mean_N",
                       "sliding_mm_per_deg_per_cycle", "contact_area_mean_mm2", "contact_time_s_per_cycle",
                       "depth_rate_mm_per_cycle"],
                   [ang[o], jw.bearing_wear[o] * MM, np.degrees(jw.theta[o]), d.force_mean[o],
                    d.slip_distance[o] * MM / cell, d.area_mean[o] * 1e6, d.contact_time[o], d.bearing[o] * MM])
        jang = report_angle_deg(jw.theta, 0.0)
        jo = np.argsort(jang)
        p2 = out / f"wear_journal_profile{sfx}.csv"
        _write_csv(p2, ["angle_deg", "journal_depth_mm", "body_angle_deg"],
                   [jang[jo], jw.journal_wear[jo] * MM, np.degrees(jw.theta[jo])])
        p3 = out / f"wear_history{sfx}.csv"
        _write_csv(p3, ["cycles", "max_bearing_wear_mm", "max_journal_wear_mm", "clearance_growth_mm"],
                   [jw.history_cycles.astype(int), jw.history_max_bearing * MM, jw.history_max_journal * MM,
                    jw.history_clearance_growth * MM])
        files += [p.name, p2.name, p3.name]
        if figures:
            from . import plots

            allowance = None
            try:
                allowance = 0.01 * 2.0 * float(config.clearance_joints[jw.index].bearing_outer_radius)
            except Exception:  # noqa: BLE001
                pass
            fac = plots.polar_profile(res, out / f"wear_polar{sfx}.png", jw.index)
            plots.angle_panels(res, out / f"wear_vs_angle{sfx}.png", jw.index)
            plots.history_plot(res, out / f"wear_history{sfx}.png", jw.index, allowance)
            plots.journal_profile_plot(res, out / f"wear_journal{sfx}.png", jw.index)
            files += [f"wear_polar{sfx}.png", f"wear_vs_angle{sfx}.png", f"wear_history{sfx}.png",
                      f"wear_journal{sfx}.png"]
            summary["joints"][jw.index]["polar_exaggeration"] = fac
    summary["files"] = files
    with open(out / "wear.json", "w") as f:
        json.dump(summary, f, indent=1)
    return summary


def wear_command(config, cycles=None, out_dir=".", *, figures: bool = True, progress=None) -> dict:
    """Run the wear history of `config` (a StudyConfig, preset name, TOML path or None) and write the outputs.

    cycles: crank cycles (default config.wear.cycles); must be a finite whole number > 0 (ValueError naming
    "cycles" otherwise). Writes out_dir/wear.json, wear_profile.csv, wear_journal_profile.csv, wear_history.csv
    and the figures; returns the wear.json dictionary.
    """
    from jointwear.config import load_config

    if config is None or isinstance(config, (str, Path)):
        config = load_config(config)
    settings = settings_from_config(config)
    n = check_cycles(cycles if cycles is not None else settings.cycles, "cycles")
    from jointwear.mechanism import build_model

    model = build_model(config)
    res = wear_history(model, settings, n, progress=progress)
    return write_outputs(res, out_dir, config, figures=figures)
