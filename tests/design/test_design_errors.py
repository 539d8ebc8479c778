"""A bad [design] section ends `jointwear design` with exit status 2 and one line naming the field."""

from importlib import resources

import pytest

from jointwear.cli import main_entry


def _preset_text() -> str:
    return (resources.files("jointwear") / "presets" / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")


@pytest.mark.parametrize("extra,words", [
    ('\n[[design.targets]]\nreliability = 1.5\nlife_factor = 1.2\n', ["design.targets", "reliability"]),
    ('\n[[design.tolerances]]\nvariable = "l1"\ngrades = ["IT42"]\n', ["design.tolerances", "IT42"]),
    ('\n[[design.properties]]\nvariable = "nope"\nclasses = [{ name = "a", cost = 1.0 }]\n',
     ["design.properties[2].variable", "nope"]),
    ('\n[[design.properties]]\nvariable = "l1"\nclasses = [{ name = "a", cost = 1.0 }]\n'
     '\n[[design.tolerances]]\nvariable = "l1"\ngrades = ["IT8"]\n', ["l1", "already set"]),
    # every unknown grade at once (only the first was named), and the table's reach
    ('\n[[design.tolerances]]\nvariable = "l1"\ngrades = ["IT19", "H7", "IT01", "IT9"]\n',
     ["grades ['IT19', 'H7', 'IT01']", "up to 120 mm"]),
    # a grade on a hardness: "nominal size 8.8263e+11 mm outside the tabulated range" before
    ('\n[[design.tolerances]]\nvariable = "E_j"\ngrades = ["IT8"]\n',
     ["'E_j' is not a length (its target is in Pa)", "[[design.properties]]"]),
    # costs listed loosest first in mind: the tightest grade was the cheapest, in silence
    ('\n[[design.tolerances]]\nvariable = "l1"\ngrades = ["IT9", "IT11"]\ncosts = [1.0, 3.0]\n',
     ["design.tolerances[2].costs:", "a tighter grade costs less", "IT9 at 1 < IT11 at 3"]),
    # a class's mean the model cannot take: it passed `check`, was chosen as the cheapest and every call of its
    # verification failed (a designer's typo, a negative wear coefficient)
    ('\n[[design.properties]]\nvariable = "E_b"\nclasses = [{ name = "typo", mean_GPa = -110.0, cost = 0.1 }]\n',
     ["design.properties[2].classes[typo].mean: at -110 GPa the model cannot be built", "young"]),
    # a negative cost: 'got' said twice ('cost must be >= 0 (got -1) (got -1.0)'), and a grade's not named
    ('\n[[design.properties]]\nvariable = "E_b"\nclasses = [{ name = "screened", cost = -1.0 }]\n',
     ["design.properties[2].classes[screened].cost: must be >= 0 (got -1.0)"]),
    ('\n[[design.tolerances]]\nvariable = "l1"\ngrades = ["IT9", "IT11"]\ncosts = [1.0, -3.0]\n',
     ["design.tolerances[2].costs: IT11 costs -3, must be >= 0"]),
])
def test_bad_design_section_exits_2_with_one_line(tmp_path, capsys, extra, words):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(_preset_text() + extra, encoding="utf-8")
    out = tmp_path / "out"
    code = main_entry(["design", str(cfg), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and err.startswith("error:") and "Traceback" not in err
    for w in words:
        assert w in err, err
    assert not (out / "design.json").exists()


def test_design_without_a_design_section_exits_2(tmp_path, capsys):
    text = _preset_text()
    cfg = tmp_path / "nodesign.toml"
    cfg.write_text(text[:text.index("\n[design]")], encoding="utf-8")
    assert main_entry(["design", str(cfg), "--out", str(tmp_path / "out")]) == 2
    assert "[design]" in capsys.readouterr().err


def test_check_checks_the_design_section_too(tmp_path, capsys):
    """`jointwear check` on a config with a [design] section checks it: a misspelt variable there used to pass
    `check` and fail only `jointwear design`."""
    cfg = tmp_path / "bad.toml"
    extra = '\n[[design.properties]]\nvariable = "nope"\nclasses = [{ name = "a", cost = 1.0 }]\n'
    cfg.write_text(_preset_text() + extra, encoding="utf-8")
    assert main_entry(["check", str(cfg)]) == 2
    assert "design.properties[2].variable" in capsys.readouterr().err
