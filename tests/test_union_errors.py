"""A mistake inside a field that takes one table or a list of tables ([uncertainty.clearance]) leaked pydantic's
union internals: 'uncertainty.clearance.function-after[_above_minimum(), ClearanceSpec].hole_grade: ...;
uncertainty.clearance.list[function-after[...]]: Input should be a valid list [2 problems]'."""

from importlib import resources

import pytest

from jointwear.cli import main_entry

PRESET = (resources.files("jointwear.presets") / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")


@pytest.mark.parametrize("old, new, expected", [
    ('hole_grade = "IT7"', 'hole_grade = "H7"',
     "uncertainty.clearance.hole_grade: unknown ISO 286 tolerance grade 'H7'; known: IT5, IT6, IT7, IT8, IT9, IT10, "
     "IT11; the grade is the IT number (IT7); a fit with its letters is written as the clearance's fit "
     "(fit = \"H8/f7\")"),
    ('hole_grade = "IT7"\nshaft_grade = "IT6"', 'fit = "H7/g6"',  # beside the preset's mean of 2 um
     "uncertainty.clearance: mean = 2 um contradicts fit 'H7/g6', which gives 5 um at 2 mm: give the fit, or the "
     "grades and the mean, not both"),
    ('hole_grade = "IT7"\nshaft_grade = "IT6"', 'fit = "H7/k6"',
     "uncertainty.clearance: fit 'H7/k6': only clearance fits are modelled, bores D, E, F, G, H on pins d, e, f, g, h"),
    ('target = "clearance_joints.0.clearance"\n', "", "uncertainty.clearance.target: Field required"),
])
def test_a_mistake_in_the_clearance_table_is_one_problem_on_its_field(tmp_path, capsys, old, new, expected):
    assert old in PRESET
    path = tmp_path / "slip.toml"
    path.write_text(PRESET.replace(old, new, 1), encoding="utf-8")
    assert main_entry(["check", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"error: {path}: {expected}"), line
    assert "[" not in line.split(": ")[1] and "problems]" not in line and "valid list" not in line


def test_a_shape_no_branch_takes_is_one_problem_naming_both_shapes(tmp_path, capsys):
    path = tmp_path / "shape.toml"
    path.write_text(PRESET.replace("target_reliability = ", "target_reliability = { a = 1 } # ", 1), encoding="utf-8")
    assert main_entry(["check", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.endswith("reliability.target_reliability: Input should be a valid number or a valid list "
                         "(got {'a': 1})"), line
