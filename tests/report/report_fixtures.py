"""Realistic synthetic study outputs for the report tests (and for anyone who wants to see a report).

The numbers imitate the flapping-wing study of the reference paper (Jin et al., Drones 2025): wear peaks of
0.0249 mm at 110 deg and 0.0087 mm at 310 deg after 400k cycles, a max wear that grows linearly with the
cycles and scatters normally over the random inputs, reliability R(N) near the paper's. They are made up:
they only exercise the report. Keys follow /work/shared/DESIGN.md plus the optional keys the report reads
(see jointwear.report.html's module docstring).

Run ``python tests/report/report_fixtures.py OUT_DIR`` to write a fixture folder and its report.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy import stats

PAPER_CITATION = (
    "Jin, Y.; Chen, X.; Wang, K.; Jiang, D.; Liu, J.; Pang, H. Uncertainty Control Method for Non-Uniform Wear "
    "of the Driving Mechanism of Flapping Wing Aircraft. Drones 2025, 9(4), 282."
)

ALL = ("simulate", "wear", "reliability", "sensitivity", "config")


def _dump(path: Path, obj) -> None:
    path.write_text(json.dumps(obj, indent=1))


def _wear_profile(n: int = 360, scale: float = 1.0):
    ang = np.arange(n) * 360.0 / n
    d1 = np.minimum(np.abs(ang - 110), 360 - np.abs(ang - 110))
    d2 = np.minimum(np.abs(ang - 310), 360 - np.abs(ang - 310))
    depth = 0.0249 * np.exp(-0.5 * (d1 / 14) ** 2) + 0.0087 * np.exp(-0.5 * (d2 / 11) ** 2) + 2e-4
    return ang, scale * depth


def make_simulate(out: Path, rng: np.random.Generator) -> None:
    crank = np.linspace(0, 2 * 360, 1441)
    phase = np.deg2rad(crank)
    force = 0.029 + 0.012 * np.sin(2 * phase + 0.4) + 0.004 * np.sin(phase) + 0.002 * rng.standard_normal(crank.size)
    force = np.clip(force, 0, None)
    c = 2e-3  # mm
    # journal follows the wall near the rod axis, with small excursions
    t = np.linspace(0, 4 * np.pi, 1441)
    dirn = np.deg2rad(110) + 0.35 * np.sin(t) + np.where(np.sin(t / 2) > 0, 0, np.pi)
    rad = c * (0.995 - 0.03 * np.abs(np.sin(3 * t)))
    # bearing-frame coordinates with angle convention 0 deg = leftmost, clockwise
    x, y = -rad * np.cos(dirn), rad * np.sin(dirn)
    _dump(out / "simulate.json", {
        "contact_force_mean_N": float(force.mean()),
        "contact_force_max_N": float(force.max()),
        "contact_fraction": 0.987,
        "impacts_per_cycle": 2.0,
        "steps_per_cycle": 15210,
        "wall_seconds_per_cycle": 0.0036,
        "cycles": 2,
        "clearance_mm": c,
        "orbit": {"x_mm": x.tolist(), "y_mm": y.tolist()},
        "contact_force": {"crank_angle_deg": crank.tolist(), "force_N": force.tolist()},
    })


def make_wear(out: Path, rng: np.random.Generator, *, csv: bool = True) -> None:
    ang, depth = _wear_profile()
    dirs = np.deg2rad(ang)
    force = 0.006 + 0.03 * (np.exp(-0.5 * ((ang - 110) / 16) ** 2) + 0.4 * np.exp(-0.5 * ((ang - 310) / 12) ** 2))
    slip = 1e-3 * (0.2 + np.exp(-0.5 * ((ang - 115) / 25) ** 2) + 0.5 * np.exp(-0.5 * ((ang - 305) / 20) ** 2))
    area = 2 * 1.128 * np.sqrt(force * 6.4e-5 * 1.5e-11 / 1e-3) * 1e-3 * 1e6  # mm^2
    cyc = np.arange(0, 520_001, 10_000)
    hist = 0.0249 * cyc / 400_000 * (1 + 0.02 * np.sin(cyc / 1e5))
    profile = {"angle_deg": ang.tolist(), "depth_mm": depth.tolist()}
    if not csv:
        profile.update({"contact_force_N": force.tolist(), "slip_mm": slip.tolist(),
                        "contact_area_mm2": area.tolist()})
    _dump(out / "wear.json", {
        "cycles": 400_000,
        "max_wear_mm": float(depth.max()),
        "max_wear_angle_deg": float(ang[np.argmax(depth)]),
        "peaks": [{"angle_deg": 110.0, "depth_mm": float(depth[110])},
                  {"angle_deg": 310.0, "depth_mm": float(depth[310])}],
        "profile": profile,
        "history": {"cycles": cyc.tolist(), "max_wear_mm": hist.tolist()},
        "wall_seconds": 1.21,
        "bearing_radius_mm": 1.002,
        "geometry_mode": "uniform",
    })
    if csv:
        lines = ["# angle on the bearing (0 deg leftmost, clockwise); per crank cycle at 400k cycles",
                 "angle_deg,depth_mm,contact_force_N,slip_mm,contact_area_mm2"]
        lines += [f"{a:.3f},{d:.6e},{f:.6e},{s:.6e},{ar:.6e}" for a, d, f, s, ar in zip(ang, depth, force, slip, area)]
        (out / "wear_profile.csv").write_text("\n".join(lines) + "\n")
    del dirs, rng


def make_reliability(out: Path, rng: np.random.Generator, *, optional: bool = True) -> None:
    cyc = np.arange(300_000, 560_001, 10_000)
    mean = 7.12e-8 * cyc  # mm
    sd = 0.082 * mean
    rel = stats.norm.cdf((0.03 - mean) / sd)
    pf = 1 - rel
    n_mc = 200_000
    cov = np.where(pf > 0, np.sqrt((1 - pf) / (n_mc * np.maximum(pf, 1e-300))), np.nan)
    # life at R = 0.9: solve on the curve
    life = float(np.interp(-0.9, -rel, cyc))
    obj = {
        "curve": {"cycles": cyc.tolist(), "reliability": rel.tolist(),
                  "pf_cov": [None if not math.isfinite(v) else float(v) for v in cov]},
        "life_at_target": {"target": 0.9, "cycles": life, "hours": life / 480 / 60},
        "model_calls": 38,
        "n_mc": n_mc,
        "wall_seconds": 212.4,
        "allowance_mm": 0.03,
        "failed_calls": 0,
        "factors_note": "synthetic",
    }
    if optional:
        hc = [360_000, 400_000, 440_000]
        obj["histograms"] = {"cycles": hc,
                             "max_wear_mm": [(7.12e-8 * c * (1 + 0.082 * rng.standard_normal(4000))).tolist()
                                             for c in hc]}
        calls = np.arange(12, 39)
        target_pf = 1 - float(stats.norm.cdf((0.03 - 7.12e-8 * 400_000) / (0.082 * 7.12e-8 * 400_000)))
        obj["convergence"] = {"n_calls": calls.tolist(),
                              "pf": (target_pf * (1 + 0.6 * np.exp(-(calls - 12) / 5) * np.cos(calls))).tolist(),
                              "cycles": 400_000}
        obj["mean_max_wear_mm"] = {"cycles": hc, "mean": [7.12e-8 * c for c in hc]}
    _dump(out / "reliability.json", obj)


SENS_VARS = [
    # name, label, group, (low, high)
    ("Rj", "journal radius", "tolerance", (0.93, 0.71)),
    ("c", "clearance", "tolerance", (0.996, 0.48)),
    ("l1", "crank length", "tolerance", (0.95, 0.99)),
    ("l2", "rod length", "tolerance", (0.0, 0.0)),
    ("lBC", "rocker length", "tolerance", (0.975, 0.98)),
    ("E_j", "journal Young's modulus", "journal_material", (0.99, 0.95)),
    ("nu_j", "journal Poisson's ratio", "journal_material", (0.979, 0.976)),
    ("k_j", "journal wear coefficient", "journal_material", (0.985, 0.968)),
    ("HB_j", "journal Brinell hardness", "journal_material", (0.62, 0.998)),
    ("E_b", "bearing Young's modulus", "bearing_material", (0.99, 0.962)),
    ("nu_b", "bearing Poisson's ratio", "bearing_material", (0.979, 0.977)),
    ("k_b", "bearing wear coefficient", "bearing_material", (0.998, 0.81)),
    ("HB_b", "bearing Brinell hardness", "bearing_material", (0.41, 0.999)),
]


def make_sensitivity(out: Path, rng: np.random.Generator, *, sobol: bool = True) -> None:
    obj = {
        "cycles": 360_000,
        "factors": [0.8, 1.2],
        "reliability_nominal": 0.978,
        "variables": [{"name": n, "label": lab, "group": g, "reliability_low": lo, "reliability_high": hi}
                      for n, lab, g, (lo, hi) in SENS_VARS],
        "model_calls": 12,
    }
    if sobol:
        st = np.array([0.08, 0.21, 0.01, 0.02, 0.005, 0.03, 0.001, 0.06, 0.19, 0.02, 0.001, 0.12, 0.28])
        obj["sobol"] = {"names": [v[0] for v in SENS_VARS], "S1": (st * 0.93).tolist(), "ST": st.tolist(),
                        "output": "max wear at 360,000 cycles"}
    _dump(out / "sensitivity.json", obj)


def preset_reference(name: str = "jin2025_flapping_wing") -> dict | None:
    """The preset's [reference] as the settings JSON carries it (report units)."""
    from jointwear.config import load_config

    ref = load_config(name).reference
    return None if ref is None else ref.report_dict()


def make_config(out: Path, *, reference: bool = True) -> None:
    S = []

    def s(name, value, unit, source, open_=False, description=""):
        S.append({"name": name, "value": value, "unit": unit, "source": source, "paper_open": open_,
                  "description": description})

    s("mechanism.crank_length", 6.0, "mm", "Table 4")
    s("mechanism.rod_length", 38.0, "mm", "Table 4")
    s("mechanism.rocker_length", 12.0, "mm", "Table 4")
    s("mechanism.rocker_pivot", [11.5, 38.0], "mm", "Table 4")
    s("mechanism.crank_speed", 480.0, "rpm", "Section 6.1.1")
    s("mechanism.assembly_branch", 1, None, "paper-notes.md: branch whose peaks match 110/310 deg", True)
    s("mechanism.gravity", True, None, "paper-notes.md: paper silent; baseline on (-y)", True)
    s("mechanism.external_load", "none", None, "paper-notes.md: the paper lists no aerodynamic load", True)
    s("joint.journal_radius", 1.0, "mm", "Table 2")
    s("joint.bearing_radius", 1.002, "mm", "Table 2")
    s("joint.width", 1.0, "mm", "Table 2")
    s("contact.law", "lankarani_nikravesh", None, "Section 2.4.1")
    s("contact.restitution", 0.9, None, "Section 2.4.1")
    s("contact.impact_speed_floor", 1e-4, "m/s", "paper-notes.md (avoids D -> infinity)", True)
    s("friction.mu_dynamic", 0.1, None, "paper-notes.md (Eq. 19 garbled, no values)", True)
    s("friction.mu_static", 0.15, None, "paper-notes.md (Eq. 19 garbled, no values)", True)
    s("wear.coefficient_reading", "dimensionless k, H = HB x 9.807e6 Pa", None,
      "paper-notes.md: only reading that reproduces the magnitude", True)
    s("wear.geometry_mode", "uniform", None, "paper Eqs. 36-37 (profile mode offered)", True)
    s("wear.block_cycles", 10_000, "cycles", "convergence study, docs", True)
    s("uncertainty.clearance_sigma", 0.97, "um", "ISO 286-2 IT7/IT6 via Eq. 40 (Table 5 prints 1 nm)", True)
    s("reliability.allowable_wear", 0.03, "mm", "Section 5.1: 0.01 D, D = 3 mm")
    s("reliability.target", 0.9, None, "Section 6.2")
    s("reliability.u_stop", 2.0, None, "Section 5.2")
    s("reliability.cov_max", 0.05, None, "Section 5.2")
    _dump(out / "config.json", {
        "preset": "jin2025_flapping_wing",
        "citation": PAPER_CITATION + " <script>alert('escaped')</script>",
        "source": "preset",
        "jointwear_version": "0.1.0",
        "seed": 12345,
        "mechanism": {"type": "crank_rocker", "crank_mm": 6.0, "rod_mm": 38.0, "rocker_mm": 12.0,
                      "pivot_mm": [11.5, 38.0], "branch": 1, "clearance_joint": "A"},
        "settings": S,
        "allowance_mm": 0.03,
        "reference": preset_reference() if reference else None,
    })


def make_fixture_dir(out: Path, which=ALL, *, seed: int = 7, optional: bool = True, csv: bool = True,
                     reference: bool = True) -> Path:
    """Write the JSON (and CSV) files of a synthetic study into ``out``; ``which`` picks the stages (a config.json
    with the flapping-wing preset's [reference] is always written unless ``reference`` is False and "config" is
    not in ``which``: the comparison needs the reference from the study's settings)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    if "simulate" in which:
        make_simulate(out, rng)
    if "wear" in which:
        make_wear(out, rng, csv=csv)
    if "reliability" in which:
        make_reliability(out, rng, optional=optional)
    if "sensitivity" in which:
        make_sensitivity(out, rng, sobol=optional)
    if "config" in which:
        make_config(out, reference=reference)
    elif reference:
        _dump(out / "config.json", {"preset": "jin2025_flapping_wing", "reference": preset_reference()})
    return out


if __name__ == "__main__":
    target = Path(sys.argv[1] if len(sys.argv) > 1 else "report-fixture")
    make_fixture_dir(target)
    from jointwear.report import build_report

    print(build_report(target))
