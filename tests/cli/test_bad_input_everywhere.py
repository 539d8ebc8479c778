"""Bad input everywhere: every command, given a malformed config or argument, exits 2 with one line on stderr
that names the field, writes nothing to ``--out`` and prints no traceback.

One malformed value per config section (every field of :class:`jointwear.config.StudyConfig`, the general
mechanism's bodies / joints / drivers, each clearance joint sub-table, each [uncertainty] part), each given to
every command that reads a config; one malformed argument per command. The CLI runs in-process
(``jointwear.cli.main.run``), exactly as the console script does, minus the interpreter start.
"""

from __future__ import annotations

from importlib import resources

import pytest

from jointwear.cli import main as cli
from jointwear.config import StudyConfig


def preset_text(name: str) -> str:
    return (resources.files("jointwear.presets") / f"{name}.toml").read_text(encoding="utf-8")


JIN = preset_text("jin2025_flapping_wing")
WATT = preset_text("watt_six_bar_two_clearances")


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def extend(toml: str, preset: str = "jin2025_flapping_wing") -> str:
    """A config that extends a preset and overrides one table."""
    return f'extends = "{preset}"\n{toml}'


# (section, case id, config text, text the one line must contain: the field's path)
SECTION_CASES = [
    ("name", "name-not-text", edit(JIN, 'name = "jin2025_flapping_wing"', "name = 3"), "name"),
    ("citation", "citation-not-text", extend("citation = [1, 2]"), "citation"),
    ("description", "description-table", extend("description = { a = 1 }"), "description"),
    ("extends", "extends-unknown-preset", 'extends = "no_such_preset"\n', "no_such_preset"),
    ("mechanism", "crank-speed-text", extend('[mechanism]\ncrank_speed_rpm = "fast"'), "mechanism.crank_speed"),
    ("mechanism", "mechanism-type", extend('[mechanism]\ntype = "five_bar"'), "mechanism"),
    ("mechanism", "rod-mass-negative", extend("[mechanism.rod]\nmass_kg = -1.0"), "mechanism.rod.mass"),
    ("mechanism.bodies", "body-mass-zero", edit(WATT, "mass_g = 1.18", "mass_g = 0.0"), "mechanism.bodies"),
    ("mechanism.joints", "joint-unknown-body", edit(WATT, 'connects = ["coupler.A", "crank.A"]',
                                                    'connects = ["coupler.A", "wheel.A"]'), "mechanism.joints"),
    ("mechanism.drivers", "driver-unknown-joint", edit(WATT, 'joint = "O"\nspeed_rpm', 'joint = "Q"\nspeed_rpm'),
     "mechanism.drivers"),
    ("clearance_joints", "restitution-above-1", edit(JIN, "restitution = 0.9", "restitution = 1.5"),
     "clearance_joints[A].restitution"),
    ("clearance_joints.bearing_material", "poisson-0.6", edit(JIN, "poissons_ratio = 0.32", "poissons_ratio = 0.6"),
     "clearance_joints[A].bearing_material.poissons_ratio"),
    ("clearance_joints.journal_material", "hardness-text", edit(JIN, "hardness_HB = 207.0", 'hardness_HB = "hard"'),
     "clearance_joints[A].journal_material.hardness"),
    ("clearance_joints.friction", "friction-speeds", edit(JIN, "v_s_m_s = 1e-4", "v_s_m_s = 1e-2"),
     "clearance_joints[A].friction"),
    ("simulation", "rtol-above-1", extend("[simulation]\nrtol = 2.0"), "simulation.rtol"),
    ("simulation", "integrator-unknown", extend('[simulation]\nmethod = "euler"'), "simulation.method"),
    ("wear", "wear-grid-too-small", extend("[wear]\nn_grid = 3"), "wear.n_grid"),
    ("wear", "wear-cycles-text", extend('[wear]\ncycles = "many"'), "wear.cycles"),
    ("uncertainty", "unknown-key", extend("[uncertainty]\nsamplez = 3"), "uncertainty.samplez"),
    ("uncertainty.clearance", "clearance-grade", edit(JIN, 'hole_grade = "IT7"', 'hole_grade = "IT99"'),
     "uncertainty.clearance"),
    ("uncertainty.variables", "variable-std-zero", edit(JIN, "std_mm = 1e-3", "std_mm = 0.0"),
     "uncertainty.variables"),
    ("uncertainty.correlation", "correlation-not-positive-definite",
     JIN + '\n[uncertainty.correlation]\nvariables = ["Rj", "l1"]\nmatrix = [[1.0, 1.5], [1.5, 1.0]]\n',
     "uncertainty.correlation"),
    ("reliability", "target-reliability", extend("[reliability]\ntarget_reliability = 1.5"),
     "reliability.target_reliability"),
    ("reliability", "cycle-range", extend("[reliability]\ncycles_start = 600000"), "reliability.cycles_start"),
    ("sensitivity", "sobol-not-power-of-2", extend("[sensitivity]\nsobol_base_samples = 1000"),
     "sensitivity.sobol_base_samples"),
    ("compute", "zero-workers", extend("[compute]\nworkers = 0"), "compute.workers"),
    ("compute", "timeout-text", extend('[compute]\ncall_timeout = "soon"'), "compute.call_timeout"),
    ("reference", "reference-band-text", edit(JIN, "value_mm = 0.0249", 'value_mm = "small"'), "reference.values"),
    ("reference", "reference-no-citation", edit(JIN, "[reference]\ncitation = ", "[reference]\ncitatio = "),
     "reference.cit"),
    ("design", "design-grade", edit(JIN, 'grades = ["IT9", "IT10", "IT11"]', 'grades = ["IT9", "ITX"]'),
     "design.tolerances"),
    ("design", "design-target-reliability", edit(JIN, "reliability = 0.9\nlife_factor", "reliability = 1.9\nlife_factor"),
     "design.targets"),
    ("toml", "malformed-toml", JIN.replace("[mechanism]", "[mechanism", 1), "malformed TOML"),
]

CONFIG_COMMANDS = ["simulate", "wear", "converge", "reliability", "sensitivity", "validate", "run", "check",
                   "design"]
ALL_COMMANDS = [*CONFIG_COMMANDS, "report", "presets", "compare"]


def run_cli(argv, capsys):
    status = cli.run(argv)
    return status, capsys.readouterr()


def names_field(line: str, path: str) -> bool:
    """The line names the field: the parts of its dotted path appear in order ('mechanism: rod.mass' counts)."""
    pos, low = 0, line.lower()
    for part in path.lower().split("."):
        pos = low.find(part, pos)
        if pos < 0:
            return False
        pos += len(part)
    return True


def assert_one_line_error(status, captured, needle):
    err = captured.err
    assert status == 2, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err + captured.out
    assert lines[0].startswith("error: "), lines[0]
    assert names_field(lines[0], needle), (needle, lines[0])


def test_every_section_of_the_config_has_a_case():
    """A new top-level section of StudyConfig must come with its malformed-input case here."""
    covered = {section.split(".")[0] for section, *_ in SECTION_CASES}
    assert set(StudyConfig.model_fields) <= covered, set(StudyConfig.model_fields) - covered


def test_every_command_is_covered():
    assert set(ALL_COMMANDS) == set(cli.commands)


@pytest.mark.parametrize("command", CONFIG_COMMANDS)
@pytest.mark.parametrize("section, case, text, needle", SECTION_CASES, ids=[c[1] for c in SECTION_CASES])
def test_malformed_config_section(command, section, case, text, needle, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # so that anything written to the working directory is seen too
    path = tmp_path / f"{case}.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    argv = [command, str(path)] + ([] if command == "check" else ["--out", str(out)])
    status, captured = run_cli(argv, capsys)
    assert_one_line_error(status, captured, needle)
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # nothing else written, not even in cwd


# one malformed argument per command: (command, argv after the command, needle)
ARGUMENT_CASES = [
    ("simulate", ["--cycles", "0"], "--cycles"),
    ("simulate", ["--settle", "-1"], "--settle"),
    ("wear", ["--cycles", "abc"], "--cycles"),
    ("converge", ["--replicates", "1"], "--replicates"),
    ("converge", ["--only", "bogus"], "only"),
    ("reliability", ["--workers", "0"], "--workers"),
    ("sensitivity", ["--workers", "two"], "--workers"),
    ("validate", ["--samples", "0"], "--samples"),
    ("run", ["--frobnicate"], "--frobnicate"),
    ("design", ["--workers", "1", "--scheduler", "tcp://localhost:1"], "workers/scheduler"),
    ("check", [], "config"),  # CONFIG is required
    ("check", ["no_such_preset"], "no_such_preset"),
    ("report", ["{tmp}/nothing_here"], "nothing_here"),
    ("report", [], "directory"),
    ("presets", ["extra"], "extra"),
    ("compare", ["{tmp}/nothing_here", "{tmp}/nor_here"], "nothing_here"),
    ("compare", ["{tmp}/a", "{tmp}/b", "--target", "1.5"], "--target"),
    ("simulate", ["{tmp}/missing.toml"], "missing.toml"),
]


@pytest.mark.parametrize("command, args, needle", ARGUMENT_CASES,
                         ids=[f"{c}-{'-'.join(a) or 'none'}".replace("{tmp}/", "") for c, a, _ in ARGUMENT_CASES])
def test_malformed_argument(command, args, needle, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    argv = [command, *(a.replace("{tmp}", str(tmp_path)) for a in args)]
    if command in CONFIG_COMMANDS and command != "check":
        argv += ["--out", str(out)]
    status, captured = run_cli(argv, capsys)
    assert_one_line_error(status, captured, needle)
    assert list(tmp_path.iterdir()) == []


def test_every_command_has_an_argument_case():
    assert {c for c, *_ in ARGUMENT_CASES} == set(ALL_COMMANDS)


def test_report_of_unreadable_results_names_the_file(tmp_path, capsys):
    """The report's 'config' is the results folder: a corrupt stage file is named, nothing is written."""
    (tmp_path / "wear.json").write_text("{not json", encoding="utf-8")
    status, captured = run_cli(["report", str(tmp_path)], capsys)
    assert_one_line_error(status, captured, "wear.json")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wear.json"]
