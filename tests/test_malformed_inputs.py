"""Malformed configs and CLI arguments: each ends with exit status 2 and one plain line, never a traceback.

Every case edits the default preset's TOML text (or the command line) in one place. The CLI runs
in-process (``jointwear.cli.main.run``), exactly as the console script does, minus the interpreter start.
"""

from __future__ import annotations

import re
from importlib import resources
from pathlib import Path

import pytest

from jointwear.cli import main

PRESET = (resources.files("jointwear.presets") / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")


def edit(old: str, new: str, count: int = 1) -> str:
    assert old in PRESET, old
    return PRESET.replace(old, new, count)


def drop_section(header: str) -> str:
    """The preset without one [section] (up to the next header)."""
    pattern = re.compile(r"^\[" + re.escape(header) + r"\][^\n]*\n(?:(?!\[).*\n)*", re.M)
    text, n = pattern.subn("", PRESET)
    assert n == 1
    return text


# (case id, config text or None for the default preset, extra CLI args, text the message must contain)
CONFIG_CASES = [
    ("missing-mechanism", drop_section("mechanism").replace("[mechanism.crank]", "[crank]", 1), [], "mechanism"),
    ("missing-rod", drop_section("mechanism.rod"), [], "rod"),
    ("wrong-type-mass", edit("mass_kg = 8.71e-4", 'mass_kg = "heavy"'), [], "mass"),
    ("nan-mass", edit("mass_kg = 8.71e-4", "mass_kg = nan"), [], "mass"),
    ("negative-mass", edit("mass_kg = 8.71e-4", "mass_kg = -1.0"), [], "mass"),
    ("zero-inertia", edit("inertia_kg_m2 = 1.44e-7", "inertia_kg_m2 = 0.0"), [], "inertia"),
    ("zero-length", edit("length_mm = 38.0", "length_mm = 0.0"), [], "rod"),
    ("zero-clearance", edit("bearing_radius_mm = 1.002", "bearing_radius_mm = 1.0"), [], "journal_radius"),
    ("journal-larger", edit("journal_radius_mm = 1.0 ", "journal_radius_mm = 1.01 "), [], "journal_radius"),
    ("cannot-assemble", edit("length_mm = 38.0", "length_mm = 20.0"), [], "cannot close the loop"),
    ("unknown-key", edit("restitution = 0.9", "restitution = 0.9\nrestitushun = 0.8"), [], "restitushun"),
    ("unknown-unit", edit("width_mm = 1.0", "width_furlong = 1.0"), [], "width"),
    ("restitution-above-1", edit("restitution = 0.9", "restitution = 1.5"), [], "restitution"),
    ("poisson-0.6", edit("poissons_ratio = 0.32", "poissons_ratio = 0.6"), [], "poissons_ratio"),
    ("negative-wear-coefficient", edit("wear_coefficient = 1.2e-3\n", "wear_coefficient = -1.2e-3\n"), [],
     "wear_coefficient"),
    ("zero-hardness", edit("hardness_HB = 350.0", "hardness_HB = 0.0"), [], "hardness"),
    ("unknown-contact-law", edit('contact_law = "lankarani_nikravesh"', 'contact_law = "magic"'), [], "contact_law"),
    ("friction-speeds", edit("v_s_m_s = 1e-4", "v_s_m_s = 1e-2"), [], "v_s"),
    ("bad-bearing-body", edit('bearing_body = "rod"', 'bearing_body = "rocker"'), [], "bearing_body"),
    ("unknown-distribution", edit('name = "l2"', 'name = "l2"\ndistribution = "weibullish"'), [],
     "distribution"),
    ("zero-std", edit("std_mm = 2.4e-2", "std_mm = 0.0"), [], "std"),
    ("bad-target", edit('target = "mechanism.rod.length"', 'target = "mechanism.rod.colour"'), [], "target"),
    ("bad-grade", edit('hole_grade = "IT7"', 'hole_grade = "IT99"'), [], "grade"),
    ("wear-grid-too-small", edit("[wear]\n", "[wear]\nn_grid = 3\n"), [], "n_grid"),
    ("wear-mode", edit("[wear]\n", '[wear]\ngeometry_mode = "banana"\n'), [], "geometry_mode"),
    ("target-reliability", edit("target_reliability = 0.9", "target_reliability = 1.5"), [], "target_reliability"),
    ("cycle-range", edit("cycles_start = 300000", "cycles_start = 600000"), [], "cycles_start"),
    ("sobol-not-power-of-2", edit("[sensitivity]", "[sensitivity]\nsobol_base_samples = 1000"), [],
     "sobol_base_samples"),
    ("zero-workers", PRESET + "\n[compute]\nworkers = 0\n", [], "workers"),
    ("malformed-toml", PRESET.replace("[mechanism]", "[mechanism", 1), [], "malformed TOML"),
    ("code-in-config", PRESET.replace('name = "jin2025_flapping_wing"',
                                      'name = __import__("os").system("echo hacked")', 1), [], "malformed TOML"),
    ("code-as-value", edit("crank_speed_rpm = 480.0", 'crank_speed_rpm = "__import__(\'os\').getcwd()"'), [],
     "crank_speed"),
]


def run_cli(args, capsys):
    status = main.run(args)
    captured = capsys.readouterr()
    return status, captured.err


@pytest.mark.parametrize("case, text, extra, needle", CONFIG_CASES, ids=[c[0] for c in CONFIG_CASES])
def test_malformed_config_exits_2_with_one_line(case, text, extra, needle, tmp_path, capsys):
    path = tmp_path / f"{case}.toml"
    path.write_text(text, encoding="utf-8")
    status, err = run_cli(["simulate", str(path), "--out", str(tmp_path / "out"), *extra], capsys)
    assert status == 2, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert needle.lower() in lines[0].lower(), lines[0]


CLI_CASES = [
    ("unknown-preset", ["simulate", "no_such_preset"], "unknown preset"),
    ("missing-file", ["simulate", "does/not/exist.toml"], "cannot read"),
    ("directory-as-file", ["simulate", "{tmp}/dir.toml"], "cannot read"),
    ("binary-file", ["simulate", "{tmp}/binary.toml"], "utf-8"),
    ("python-file", ["simulate", "{tmp}/evil.toml"], "malformed"),
    ("cycles-zero", ["simulate", "--cycles", "0"], "cycles"),
    ("cycles-not-a-number", ["simulate", "--cycles", "abc"], "cycles"),
    ("cycles-negative-wear", ["wear", "--cycles", "-5"], "cycles"),
    ("unknown-option", ["simulate", "--frobnicate"], "frobnicate"),
    ("unknown-command", ["levitate"], "levitate"),
    ("workers-zero", ["reliability", "--workers", "0"], "workers"),
    ("report-missing-dir", ["report", "{tmp}/nothing_here"], "nothing_here"),
]


@pytest.mark.parametrize("case, args, needle", CLI_CASES, ids=[c[0] for c in CLI_CASES])
def test_malformed_arguments_exit_2_with_one_line(case, args, needle, tmp_path, capsys):
    (tmp_path / "dir.toml").mkdir()
    (tmp_path / "binary.toml").write_bytes(b"\xff\xfe\x00\x81 not text")
    (tmp_path / "evil.toml").write_text("import os\nos.system('echo hacked')\n", encoding="utf-8")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in args]
    if argv[0] != "report" and "--out" not in argv and argv[0] in ("simulate", "wear", "reliability"):
        argv += ["--out", str(tmp_path / "out")]
    status, err = run_cli(argv, capsys)
    assert status == 2, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert needle.lower() in lines[0].lower(), lines[0]


def test_there_are_at_least_thirty_cases():
    assert len(CONFIG_CASES) + len(CLI_CASES) >= 30


def test_wear_without_cycles_or_curve_names_the_field(tmp_path, capsys):
    """No paper default for the wear history: a config with neither [wear] cycles nor an R(N) curve is refused."""
    text = (Path(__file__).resolve().parents[1] / "examples" / "my_linkage.toml").read_text()
    text = text.split("[uncertainty.clearance]")[0].replace("cycles = 600000", "")
    cfg = tmp_path / "no_cycles.toml"
    cfg.write_text(text)
    out = tmp_path / "out"
    code, err = run_cli(["wear", str(cfg), "--out", str(out)], capsys)
    assert code == 2 and "wear.cycles" in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


def test_a_value_the_validator_names_is_not_repeated(tmp_path, capsys):
    """'wear.cycles: must be a whole number of cycles, got 400000.5 (got 400000.5)': the generic '(got ...)' repeated
    what the validator had already said."""
    cfg = tmp_path / "frac.toml"
    cfg.write_text('extends = "flores_slider_crank"\n[wear]\ncycles = 400000.5\n')
    code, err = run_cli(["check", str(cfg)], capsys)
    assert code == 2 and err.strip().endswith("wear.cycles: must be a whole number of cycles, got 400000.5"), err
