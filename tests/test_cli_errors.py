"""Bad input ends `jointwear simulate` with exit status 2 and one line naming the field; no traceback."""

import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest

from jointwear.cli import main_entry

PRESET = (resources.files("jointwear.presets") / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")


def _variant(tmp_path, old, new, name="cfg.toml"):
    assert old in PRESET, old
    p = tmp_path / name
    p.write_text(PRESET.replace(old, new, 1), encoding="utf-8")
    return str(p)


def _run(capsys, args):
    code = main_entry(args)
    err = capsys.readouterr().err
    return code, err


CASES = [
    # (old, new, words expected in the message)
    ("journal_radius_mm = 1.0 ", "journal_radius_mm = 1.002 ", ["clearance_joints[A].journal_radius", "> 0"]),
    ("journal_radius_mm = 1.0 ", "journal_radius_mm = 1.1 ", ["clearance_joints[A].journal_radius", "smaller"]),
    ("bearing_radius_mm = 1.002", "bearing_radius_mm = -1.0", ["clearance_joints[A].bearing_radius", "greater than 0"]),
    ("mass_kg = 8.71e-4", "mass_kg = nan", ["mechanism.rod.mass", "finite"]),
    ("mass_kg = 8.71e-4", "mass_kg = 0.0", ["mechanism.rod.mass", "greater than 0"]),
    ("mass_kg = 8.71e-4", "mass_kg = -1e-3", ["mechanism.rod.mass", "greater than 0"]),
    ("length_mm = 38.0", "length_mm = 20.0", ["mechanism", "rod", "rocker", "cannot close the loop"]),
    ("length_mm = 6.0", "length_mm = 0.0", ["crank.length", "> 0"]),
    ("restitution = 0.9 ", "restitution = 1.5 ", ["clearance_joints[A].restitution", "less than or equal to 1"]),
    ("width_mm = 1.0", "width_mm = 1.0\nwidht_mm = 2.0", ["widht_mm", "unknown key"]),
    ("crank_speed_rpm = 480.0", 'crank_speed_rpm = "fast"', ["mechanism", "crank_speed_rpm"]),
    ('joint = "A"', 'joint = "O"', ["clearance_joints[A].joint", "allowed"]),
    # a GPa value given in Pa (on the tutorial's linkage the journal's preload then failed to assemble: a traceback)
    ("youngs_modulus_GPa = 120.0", "youngs_modulus_Pa = 3.0",
     ["bearing_material.youngs_modulus", "1e+06 Pa", "a unit slip?", "youngs_modulus_GPa"]),
    # and a GPa value given in Pa under a GPa key: 1.2e20 Pa, above any solid (diamond: 1.2e12 Pa)
    ("youngs_modulus_GPa = 120.0", "youngs_modulus_GPa = 120e9",
     ["bearing_material.youngs_modulus", "1.5e+12 Pa", "a unit slip?"]),
    ("hardness_HB = 350.0", "hardness_Pa = 120.0", ["bearing_material.hardness", "1e+06 Pa", "a unit slip?"]),
    # and a hardness in MPa given as if in kPa: 35 TPa, 300 times diamond's, passed and cut the wear a millionfold
    ("hardness_HB = 350.0", "hardness_MPa = 35000000.0", ["bearing_material.hardness", "1.5e+11 Pa", "a unit slip?"]),
    ("wear_coefficient = 1.2e-3", "wear_coefficient = 2.0", ["bearing_material.wear_coefficient", "less than 1"]),
    # a bad value given with a unit suffix is shown as written, then in SI (it was only '-6.8649e+07' for -7 HB)
    ("std_HB = 30.5", "std_HB = -7.0", ["uncertainty.variables[", "must be > 0 (got -7 HB = -6.8649e+07 Pa)"]),
    ("hardness_HB = 350.0", "hardness_HB = -5.0", ["bearing_material.hardness", "(got -5 HB = -4.9035e+07 Pa)"]),
    ("length_mm = 6.0", "length_mm = -6.0", ["crank.length", "(got -6 mm = -0.006 m)"]),
]


@pytest.mark.parametrize("old,new,words", CASES)
def test_bad_config_one_line_exit_2(tmp_path, capsys, old, new, words):
    path = _variant(tmp_path, old, new)
    code, err = _run(capsys, ["simulate", path, "--cycles", "1", "--out", str(tmp_path / "o")])
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert not (tmp_path / "o" / "simulate.json").exists()


def test_unknown_preset(tmp_path, capsys):
    code, err = _run(capsys, ["simulate", "no_such_preset", "--out", str(tmp_path)])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "unknown preset 'no_such_preset'" in err and "jin2025_flapping_wing" in err


def test_missing_file(tmp_path, capsys):
    code, err = _run(capsys, ["simulate", str(tmp_path / "missing.toml"), "--out", str(tmp_path)])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "cannot read file" in err


def test_unreadable_directory(tmp_path, capsys):
    d = tmp_path / "dir.toml"
    d.mkdir()
    code, err = _run(capsys, ["simulate", str(d), "--out", str(tmp_path)])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "cannot read file" in err


def test_malformed_toml(tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text("[mechanism\ntype = 'four_bar'\n", encoding="utf-8")
    code, err = _run(capsys, ["simulate", str(p), "--out", str(tmp_path)])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "malformed TOML" in err


def test_binary_file(tmp_path, capsys):
    p = tmp_path / "bin.toml"
    p.write_bytes(b"\xff\xfe\x00\x01")
    code, err = _run(capsys, ["simulate", str(p), "--out", str(tmp_path)])
    assert code == 2 and "not UTF-8" in err


def test_bad_argument(tmp_path, capsys):
    code, err = _run(capsys, ["simulate", "--cycles", "0", "--out", str(tmp_path)])
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--cycles" in err
    code, err = _run(capsys, ["simulate", "--bogus"])
    assert code == 2 and "--bogus" in err
    for bad, why in (("250.5", "is not a whole number of cycles"), ("5e2x", "is not a number of cycles")):
        code, err = _run(capsys, ["wear", "--cycles", bad, "--out", str(tmp_path)])
        assert code == 2 and f"'{bad}' {why}" in err, err


def test_cycles_are_read_as_the_config_writes_them():
    """The config accepts cycles = 4e5 and 400_000; the command line refused --cycles 4e5."""
    from jointwear.cli import CycleCount

    for text in ("400000", "4e5", "400_000", "4.0e5"):
        assert CycleCount(1).convert(text, None, None) == 400_000
    assert CycleCount(0).convert("0", None, None) == 0


def test_console_script_exit_status(tmp_path):
    """The installed entry point (not only main_entry) maps errors to one line and status 2."""
    path = _variant(tmp_path, "journal_radius_mm = 1.0 ", "journal_radius_mm = 1.1 ")
    code = f"import sys; from jointwear.cli import main; sys.argv=['jointwear','simulate',{path!r}]; main()"
    p = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr
    assert "journal_radius" in p.stderr


@pytest.mark.parametrize("command", ["simulate", "wear", "reliability", "sensitivity", "run"])
def test_bad_config_writes_nothing(tmp_path, capsys, command):
    """Every problem is found before any stage runs, so the output folder is never created."""
    path = _variant(tmp_path, "cycles_start = 300000", "cycles_start = 300000\njoints = [\"Z\"]")
    out = tmp_path / "never"
    code, err = _run(capsys, [command, path, "--out", str(out)])
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "reliability.joints" in err
    assert not out.exists()


def test_all_problems_listed_in_one_line(tmp_path, capsys):
    text = PRESET.replace("mass_kg = 8.71e-4", "mass_kg = -1.0").replace("restitution = 0.9 ", "restitution = 2.0 ")
    p = tmp_path / "two.toml"
    p.write_text(text, encoding="utf-8")
    code, err = _run(capsys, ["check", str(p)])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "mechanism.rod.mass" in err and "clearance_joints[A].restitution" in err and "[2 problems]" in err


def test_zero_crank_speed_exits_2(tmp_path, capsys):
    path = _variant(tmp_path, "crank_speed_rpm = 480.0", "crank_speed_rpm = 0.0")
    code, err = _run(capsys, ["simulate", path, "--out", str(tmp_path / "o")])
    assert code == 2 and "crank_speed" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_unwritable_out_exits_2_before_the_mechanism_runs(tmp_path, capsys, monkeypatch):
    import jointwear.study.facade

    def must_not_run(config):  # the run check compiles the kernels: a minute on a fresh install
        raise AssertionError("the mechanism ran before the output folder was checked")

    monkeypatch.setattr(jointwear.study.facade, "check_runs", must_not_run)
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    code, err = _run(capsys, ["simulate", "--cycles", "1", "--out", str(blocker / "sub")])
    assert code == 2 and err.startswith("error: out:") and len(err.strip().splitlines()) == 1
    assert "is a file, not a folder" in err and not (blocker / "sub").exists()


def test_report_of_a_folder_without_results_exits_2(tmp_path, capsys):
    code, err = _run(capsys, ["report", str(tmp_path)])
    assert code == 2 and "no study results" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "report.html").exists()
    config = tmp_path / "study.toml"  # a config, as the other commands take it (it was "Directory ... is a file")
    config.write_text('extends = "jin2025_flapping_wing"\n', encoding="utf-8")
    code, err = _run(capsys, ["report", str(config)])
    assert code == 2 and "report takes the results folder of a study" in err and "--out DIR" in err


def test_report_takes_its_folder_as_directory_or_as_out_like_every_command(tmp_path, capsys, monkeypatch):
    """`report --out DIR` names the folder as the other commands do; both at once must agree."""
    code, err = _run(capsys, ["report", "--out", str(tmp_path)])
    assert code == 2 and "no study results" in err  # read from --out: the same check as the positional folder
    code, err = _run(capsys, ["report", str(tmp_path), "--out", str(tmp_path / "other")])
    assert code == 2 and "two results directories" in err and len(err.strip().splitlines()) == 1
    # neither: the other commands' default, results (a plain `jointwear report` after `jointwear run`)
    monkeypatch.chdir(tmp_path)
    code, err = _run(capsys, ["report"])
    assert code == 2 and "'results' is not a directory with study results" in err


def test_check_and_presets_and_version(tmp_path, capsys):
    assert main_entry(["check", "jin2025_flapping_wing"]) == 0
    captured = capsys.readouterr()
    assert "mechanism.crank_speed = 480 rpm" in captured.out and "rpm" in captured.out and "valid" in captured.err
    assert main_entry(["presets"]) == 0
    out = capsys.readouterr().out
    assert "jin2025_flapping_wing" in out and "Drones" in out
    with pytest.raises(SystemExit) as exc:
        from jointwear.cli import main

        main(["--version"])
    assert exc.value.code == 0
    assert "jointwear" in capsys.readouterr().out


def test_check_says_whether_each_value_comes_from_the_config_or_is_a_default(capsys):
    """docs/cli.md promised where each value comes from; check printed each field's description instead."""
    assert main_entry(["check", "jin2025_flapping_wing"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "mechanism.crank_speed = 480 rpm    # the config" in lines
    assert "simulation.max_steps = 50000000    # jointwear default: Safety limit on accepted+rejected steps per call." \
        in lines
    assert all(line.split("    # ")[1].startswith(("the config", "jointwear default")) for line in lines)


def test_check_of_a_results_folder_tells_the_defaults_its_config_json_records(tmp_path, capsys):
    """`check <results folder>` marked every setting "the config" (the config kept there sets every value); the
    folder's records say which were defaults: the same origins as checking the preset itself, a dash where they hold
    no record (the reference's values, the study's name)."""
    from jointwear.config import load_config
    from jointwear.study.settings_record import settings_dump, write_dump

    write_dump(tmp_path, settings_dump(load_config("jin2025_flapping_wing"), preset="jin2025_flapping_wing"))
    assert main_entry(["check", "jin2025_flapping_wing"]) == 0
    preset = capsys.readouterr().out.splitlines()
    assert main_entry(["check", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    folder = captured.out.splitlines()
    assert "simulation.max_steps = 50000000    # jointwear default: Safety limit on accepted+rejected steps per call." \
        in folder
    assert "mechanism.crank_speed = 480 rpm    # the config" in folder
    differ = [(a, b) for a, b in zip(folder, preset) if a != b]
    assert len(folder) == len(preset) and differ
    assert all(a.split(" = ")[0].startswith(("reference", "name", "citation", "description")) and "# \u2014" in a
               for a, b in differ), differ[:3]
    assert "config.json records them" in captured.err


def test_a_config_extends_a_preset(tmp_path, capsys):
    from jointwear.config import load_config

    p = tmp_path / "variant.toml"
    p.write_text('extends = "jin2025_flapping_wing"\nname = "variant"\n[reliability]\ncycles_stop = 520000\n'
                 '[mechanism.rod]\nlength_mm = 38.5\n', encoding="utf-8")
    cfg, base = load_config(p), load_config()
    assert cfg.name == "variant" and cfg.reliability.cycles_stop == 520_000
    assert cfg.reliability.cycles_start == base.reliability.cycles_start  # merged, not replaced
    assert cfg.mechanism.rod.length == 0.0385 and cfg.mechanism.rod.mass == base.mechanism.rod.mass
    assert cfg.uncertainty == base.uncertainty
    loop = tmp_path / "loop.toml"
    loop.write_text('extends = "loop.toml"\n', encoding="utf-8")
    code, err = _run(capsys, ["check", str(loop)])
    assert code == 2 and "circular" in err


def test_an_extending_config_changes_one_named_entry_and_a_field_in_another_unit(tmp_path, capsys):
    """``[clearance_joints.B.bearing_material]`` changes the base's joint B only (it was 'Input should be a valid
    list': the whole [[clearance_joints]] entry had to be restated), and ``length_m`` replaces the base's
    ``length_mm`` (it was 'length given twice')."""
    from jointwear.config import load_config

    example = Path(__file__).resolve().parents[1] / "examples" / "my_linkage.toml"
    p = tmp_path / "pom.toml"
    p.write_text(f'extends = "{example.as_posix()}"\nname = "pom"\n[clearance_joints.B.bearing_material]\n'
                 'name = "POM"\nyoungs_modulus_GPa = 3.0\nhardness_MPa = 170.0\nwear_coefficient = 2e-5\n',
                 encoding="utf-8")
    cfg, base = load_config(p), load_config(example)
    (joint,), (base_joint,) = cfg.clearance_joints, base.clearance_joints
    assert (joint.bearing_material.youngs_modulus, joint.bearing_material.hardness) == (3e9, 170e6)
    assert joint.bearing_material.poissons_ratio == base_joint.bearing_material.poissons_ratio  # merged, not replaced
    assert joint.journal_material == base_joint.journal_material and joint.width == base_joint.width
    rod = tmp_path / "rod.toml"
    rod.write_text('extends = "jin2025_flapping_wing"\n[mechanism.rod]\nlength_m = 0.0385\n', encoding="utf-8")
    assert load_config(rod).mechanism.rod.length == 0.0385
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(f'extends = "{example.as_posix()}"\n[clearance_joints.bearing_material]\n'
                     'youngs_modulus_GPa = 3.0\n', encoding="utf-8")
    code, err = _run(capsys, ["check", str(wrong)])
    assert code == 2 and "wrong.toml: clearance_joints: 'bearing_material' names no entry" in err
    assert "[clearance_joints.<name>.<key>]" in err


def test_an_interrupt_says_how_to_continue(tmp_path, capsys, monkeypatch):
    """Ctrl-C printed only 'error: aborted'; the calls made are kept, and the message now says how to go on. The exit
    status is the shell's for SIGINT (130), so a batch script can tell an interrupt from a failed study (1)."""
    import jointwear.study

    def interrupted(self, *args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(jointwear.study.Study, "reliability", interrupted)
    assert main_entry(["reliability", "--out", str(tmp_path)]) == 130
    err = capsys.readouterr().err
    assert "error: aborted" in err and "again with --resume" in err
    # a stage without model calls has no store and no --resume to point to
    monkeypatch.setattr(jointwear.study.Study, "wear", interrupted)
    assert main_entry(["wear", "--out", str(tmp_path)]) == 130
    err = capsys.readouterr().err
    assert "error: aborted" in err and "--resume" not in err


def test_a_bare_command_prints_the_help(capsys):
    # `jointwear` alone squashed its help into one 'error: Usage: ...' line and exited 2
    assert main_entry([]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Usage: jointwear [OPTIONS] COMMAND [ARGS]...") and "Commands:" in out


def test_a_mechanism_that_cannot_start_is_a_problem_naming_the_joints_materials(monkeypatch):
    """The start presses the journals into their bores by their contact law and assembles the rest; when that fails
    (a ValueError from the assembly), check says so in one problem instead of a traceback."""
    import jointwear.mechanism as mechanism
    from jointwear.config import load_config
    from jointwear.study.checks import check_runs

    def cannot_start(*args, **kwargs):
        raise ValueError("assembly did not converge at t = 0 s")

    monkeypatch.setattr(mechanism, "simulate", cannot_start)
    (problem,) = check_runs(load_config("jin2025_flapping_wing"))
    assert "does not start (assembly did not converge at t = 0 s)" in problem
    assert "clearance_joints.A.bearing_material.youngs_modulus = 1.2e+11 Pa" in problem


@pytest.mark.parametrize("command", ["simulate", "wear", "reliability", "run", "converge", "validate", "design"])
def test_every_commands_help_says_what_config_is(capsys, command):
    # a mistyped `simulate --cycles 2e0 FILE` ran the default preset; no help page said CONFIG defaults to it
    from jointwear.cli import CONFIG_HELP

    assert main_entry([command, "--help"]) == 0
    assert " ".join(CONFIG_HELP.split()) in " ".join(capsys.readouterr().out.split())


def test_a_failed_simulation_exits_1_in_one_line(tmp_path, capsys):
    cfg = tmp_path / "few_steps.toml"
    cfg.write_text('extends = "jin2025_flapping_wing"\n[simulation]\nmax_steps = 1000\n', encoding="utf-8")
    assert main_entry(["simulate", str(cfg), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: simulation failed: step budget exhausted") and "\n" not in err


def test_the_help_does_not_load_the_compiled_kernels():
    """`jointwear --help` imported numba (0.3 s of every command's start) to name the simulation's error."""
    code = ("import sys\nfrom jointwear.cli import main_entry\ntry:\n    main_entry(['--help'])\nexcept SystemExit:\n"
            "    pass\nassert 'numba' not in sys.modules, 'numba imported'\n")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


def test_a_subpackage_is_reached_as_an_attribute_of_the_package():
    """After `import jointwear`, `jointwear.study.ReliabilityCurve` raised AttributeError until `jointwear.Study` had
    been touched; the package itself still imports no kernel, and a name it does not have is still refused."""
    code = ("import sys, jointwear\nassert 'numba' not in sys.modules\n"
            "assert jointwear.study.ReliabilityCurve.FILE == 'reliability.json'\n"
            "assert callable(jointwear.reliability.akmcs)\n"
            "try:\n    jointwear.nope\nexcept AttributeError:\n    pass\nelse:\n    raise SystemExit('nope found')\n")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


def test_a_config_saved_with_a_byte_order_mark_loads(tmp_path):
    """Notepad's 'UTF-8 with BOM' gave 'malformed TOML: Invalid statement (at line 1, column 1)'."""
    from jointwear.config import load_config

    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + 'extends = "jin2025_flapping_wing"\nname = "bom"\n'.encode())
    assert load_config(path).name == "bom"
