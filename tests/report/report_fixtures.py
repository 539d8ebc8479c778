"""Study folders for the report tests, written by the stages' own writers (the typed results' ``save``).

The dynamics and wear results are real: the flapping-wing preset's nominal mechanism, simulated for one cycle
and worn to 400,000 cycles (a few seconds, run once per test session, see ``nominal_run``). The reliability and
sensitivity results are typed results built from made-up numbers near the reference paper's (Jin et al., Drones
2025): the report's logic is what these tests exercise, and a real R(N) costs 60 model calls.

Run ``python tests/report/report_fixtures.py OUT_DIR`` to write a fixture folder and its report.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
from scipy import stats

from jointwear.config import load_config
from jointwear.study.results import ReliabilityCurve, SensitivityResult
from jointwear.study.settings_record import write_settings

PRESET = "jin2025_flapping_wing"
ALL = ("simulate", "wear", "reliability", "sensitivity", "config")
SIMULATE_FILES = ("simulate.json", "simulate.npz", "simulate_joints.csv", "orbit_A.png", "force_A.png")
WEAR_FILES = ("wear.json", "wear_history.csv", "wear_journal_profile.csv", "wear_profile.csv", "wear_polar.png",
              "wear_history.png", "wear_vs_angle.png")


def nominal_run(folder: Path) -> Path:
    """The real dynamics (1 cycle) and wear (400,000 cycles) of the flapping-wing preset, in ``folder``."""
    import jointwear

    study = jointwear.Study(PRESET, out=folder)
    study.simulate(cycles=1)
    study.wear()
    return folder


def reliability_result(*, optional: bool = True) -> ReliabilityCurve:
    """R(N) of a max wear growing as 7.12e-8 mm per cycle with an 8.2 % normal scatter, against 0.03 mm."""
    cyc = np.arange(300_000, 560_001, 10_000, dtype=float)
    mean, allowance = 7.12e-8 * cyc, 0.03
    rel = stats.norm.cdf((allowance - mean) / (0.082 * mean))
    pf = 1 - rel
    n_mc = 200_000
    cov = np.sqrt((1 - pf) / (n_mc * np.maximum(pf, 1e-300)))
    life = float(np.interp(-0.9, -rel, cyc))
    hist_levels = [360_000, 400_000, 440_000]
    rng = np.random.default_rng(7)
    calls = np.arange(12, 39)
    pf400 = float(1 - stats.norm.cdf((allowance - 7.12e-8 * 4e5) / (0.082 * 7.12e-8 * 4e5)))
    return ReliabilityCurve(
        cycles=cyc, reliability=rel, pf=pf, pf_cov=cov, below_floor=np.zeros(cyc.size, bool),
        pf_error=0.2 * pf, target=0.9, life_cycles=life, life_hours=life / 480 / 60, model_calls=38,
        failed_calls=0, n_mc=n_mc, converged=True, wall_seconds=212.4, names=[v[0] for v in SENS_VARS],
        histograms={"cycles": hist_levels, "max_wear_mm": [
            (7.12e-8 * c * (1 + 0.082 * rng.standard_normal(2000))).tolist() for c in hist_levels]}
        if optional else {},
        mean_max_wear_mm={"cycles": hist_levels, "mean": [7.12e-8 * c for c in hist_levels]} if optional else {},
        convergence={"cycles": 400_000, "n_calls": calls.tolist(),
                     "pf": (pf400 * (1 + 0.6 * np.exp(-(calls - 12) / 5) * np.cos(calls))).tolist()}
        if optional else {},
        design_x=np.zeros((0, len(SENS_VARS))), design_wear=np.zeros((0, cyc.size)),
        life_table=[{"target": 0.9, "cycles": life, "hours": life / 480 / 60, "status": "in_curve"}],
        joints=[{"name": "A", "allowance_mm": allowance}], crank_speed_rpm=480.0)


SENS_VARS = [
    # name, label, group, (R at mean x 0.8, R at mean x 1.2)
    ("Rj", "journal radius", "tolerance", (0.93, 0.71)),
    ("c", "radial clearance", "tolerance", (0.996, 0.48)),
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


def sensitivity_result(*, sobol: bool = True, unresolved: list[dict] | None = None) -> SensitivityResult:
    r0 = 0.978
    variables = [{"name": n, "label": lab, "group": g, "reliability_low": lo, "reliability_high": hi}
                 for n, lab, g, (lo, hi) in SENS_VARS]
    swing = {v["name"]: max(abs(v["reliability_low"] - r0), abs(v["reliability_high"] - r0)) for v in variables}
    st = np.array([0.08, 0.21, 0.01, 0.02, 0.005, 0.03, 0.001, 0.06, 0.19, 0.02, 0.001, 0.12, 0.28])
    return SensitivityResult(
        cycles=360_000, factors=[0.8, 1.2], reliability_nominal=r0, variables=variables,
        ranking=sorted(swing, key=lambda n: -swing[n]), ranking_by_group={},
        sobol={"names": [v[0] for v in SENS_VARS], "S1": (st * 0.93).tolist(), "ST": st.tolist(),
               "output": "max wear at 360,000 cycles"} if sobol else {},
        unresolved_pairs=unresolved or [])


def write_config(out: Path, preset: str = PRESET, *, citation: str | None = None) -> None:
    """The settings JSON the study writes (``config.json``) for ``preset``."""
    cfg = load_config(preset)
    if citation is not None:
        cfg = cfg.model_copy(update={"citation": citation})
    write_settings(out, cfg, preset=preset, source="preset")


def make_fixture_dir(out: Path, nominal: Path, which=ALL, *, optional: bool = True, preset: str = PRESET,
                     citation: str | None = None) -> Path:
    """A study folder in ``out`` with the stages in ``which``: the real nominal run's files (from ``nominal``,
    see :func:`nominal_run`) and typed reliability and sensitivity results; the settings JSON of ``preset``
    when "config" is in ``which``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for stage, files in (("simulate", SIMULATE_FILES), ("wear", WEAR_FILES)):
        if stage in which:
            for name in files:
                shutil.copy(Path(nominal) / name, out / name)
    if "reliability" in which:
        reliability_result(optional=optional).save(out)
    if "sensitivity" in which:
        sensitivity_result(sobol=optional).save(out)
    if "config" in which:
        write_config(out, preset, citation=citation)
    return out


if __name__ == "__main__":
    from jointwear.report import build_report

    target = Path(sys.argv[1] if len(sys.argv) > 1 else "report-fixture")
    print(build_report(make_fixture_dir(target, nominal_run(target / "nominal"))))
