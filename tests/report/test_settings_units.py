"""The report's settings tables say what each number is: one unit for a variable's numbers, descriptions that do not
contradict the unit shown, a display scale with what it converts, the random inputs' fields once, the surrogate with
what it learns. Read from the rendered "Study and settings" section (figures made, not rendered)."""

from __future__ import annotations

import html
import json
import re

import pytest

from jointwear.config import available_presets, load_config, updated
from jointwear.report.markup import Figures
from jointwear.report.read import read_outputs
from jointwear.report.study_sections import settings_section
from jointwear.study.settings_record import (
    random_variables,
    settings_records,
    variable_display,
    write_dump,
    write_settings,
)

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read text

EXAMPLES = ["examples/my_linkage.toml", "benchmarks/configs/toggle_press.toml"]


def _section(tmp_path, cfg, preset: str | None = None) -> str:
    write_settings(tmp_path, cfg, preset=preset, source="preset" if preset else None)
    out = read_outputs(tmp_path)
    return settings_section(out, Figures(out.pngs))


def _text(cell: str) -> str:
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", cell)).split())


def _tables(section: str) -> dict[str, list[list[str]]]:
    """Each table's rows (cells as text) by the heading or summary above it, else by its first column's header."""
    out, heading = {}, ""
    for m in re.finditer(r"<h3>(.*?)</h3>|<summary>(.*?)</summary>|<table[^>]*>(.*?)</table>", section, re.DOTALL):
        if m.group(3) is None:
            heading = _text(m.group(1) or m.group(2))
            continue
        first = _text(re.search(r"<th>(.*?)</th>", m.group(3), re.DOTALL).group(1))
        rows = [[_text(c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row, re.DOTALL)]
                for row in re.findall(r"<tr[^>]*>(.*?)</tr>", m.group(3), re.DOTALL)]
        out[heading or first] = [r for r in rows if r]
    return out


def _all_settings(section: str) -> dict[str, list[str]]:
    """The rows of 'All N settings of this study' by setting name: value, unit, then the flag and source or origin."""
    rows = next(rows for heading, rows in _tables(section).items() if re.match(r"All \d+ settings", heading))
    return {r[0]: r[1:] for r in rows}


@pytest.fixture(scope="module")
def default_section(tmp_path_factory) -> str:
    return _section(tmp_path_factory.mktemp("default"), load_config("jin2025_flapping_wing"), "jin2025_flapping_wing")


def test_a_variables_mean_std_and_bounds_share_its_display_unit():
    """E_b's mean and std were listed in GPa, its (empty) lower and upper in MPa; a truncated E_b read its bounds in
    MPa beside a mean in GPa; the clearance's mean was 0.002 mm in the settings and 2 um in Random inputs."""
    cfg = updated("jin2025_flapping_wing", {"uncertainty.variables.E_b.distribution": "truncated_normal",
                                            "uncertainty.variables.E_b.lower_GPa": 0.5,
                                            "uncertainty.variables.E_b.upper_GPa": 150.0})
    rows = {r["name"]: r for r in settings_records(cfg)}
    table = {v["name"]: v for v in random_variables(cfg)}
    for name, v in table.items():
        prefix = f"uncertainty.variables[{name}]"
        for field in ("mean", "std", "lower", "upper"):
            if f"{prefix}.{field}" in rows:
                assert (rows[f"{prefix}.{field}"]["unit"] or "") == v["unit"], (name, field)
    e_b = [rows[f"uncertainty.variables[E_b].{f}"] for f in ("mean", "std", "lower", "upper")]
    assert [(r["value"], r["unit"]) for r in e_b] == [(pytest.approx(120), "GPa"), (pytest.approx(12), "GPa"),
                                                      (pytest.approx(0.5), "GPa"), (pytest.approx(150), "GPa")]
    c = {f: rows[f"uncertainty.clearance.{f}"] for f in ("mean", "minimum", "table5_std", "nominal_diameter")}
    assert [(c[f]["value"], c[f]["unit"]) for f in ("mean", "minimum", "table5_std")] == [
        (pytest.approx(2.0), "um"), (pytest.approx(0.1), "um"), (pytest.approx(1e-3), "um")]
    assert (table["c"]["mean"], table["c"]["lower"], table["c"]["unit"]) == (pytest.approx(2.0), pytest.approx(0.1),
                                                                           "um")
    assert (c["nominal_diameter"]["value"], c["nominal_diameter"]["unit"]) == (pytest.approx(2.0), "mm")  # a size


def test_a_design_class_is_listed_in_its_variables_unit():
    # a class of E_b: its std of 5 GPa read '5000 MPa' beside a mean of 130 GPa
    cfg = updated("jin2025_flapping_wing", {"design.properties": [
        {"variable": "E_b", "classes": [{"name": "stiff", "cost": 1.0, "mean_GPa": 130.0, "std_GPa": 0.5},
                                        {"name": "plain", "cost": 0.0}]}]})
    rows = {r["name"]: r for r in settings_records(cfg)}
    stiff = [rows[f"design.properties[0].classes[stiff].{f}"] for f in ("mean", "std", "lower")]
    assert [(r["value"], r["unit"]) for r in stiff] == [(pytest.approx(130), "GPa"), (pytest.approx(0.5), "GPa"),
                                                        (None, "GPa")]


# what a description said of a value the report shows in another unit: 'Mean, SI units', 'clearance, m;', 'in SI
# without a unit suffix'
_SAYS_SI = re.compile(r"\bSI units\b|, m[,.;:]|in SI without")


@pytest.mark.parametrize("config", [*available_presets(), *EXAMPLES])
def test_no_description_names_a_unit_other_than_the_one_shown(config):
    cfg = load_config(config)
    said = [(r["name"], r["unit"], r["source"]) for r in settings_records(cfg)
            if r["unit"] and _SAYS_SI.search(r["source"] or "")]
    assert said == []


def test_the_docs_and_the_report_read_the_same_descriptions():
    from jointwear.config import config_reference_markdown

    docs = config_reference_markdown()
    assert "| `mean` | of the target | required | Mean (for 'truncated_normal': of the normal before truncation). |" \
        in docs
    fields = [line for line in docs.split("## Presets")[0].splitlines() if line.startswith("| `")]
    assert [line for line in fields if _SAYS_SI.search(line)] == []  # the unit is in its own column


def test_a_display_scale_says_what_it_converts(default_section):
    rows = _all_settings(default_section)
    assert rows["uncertainty.variables[E_b].scale"][0] == "1e-09 (Pa -> GPa)"
    assert rows["uncertainty.variables[Rj].scale"][0] == "1000 (m -> mm)"
    assert rows["uncertainty.variables[HB_b].scale"][0] == "1.01968e-07 (Pa -> HB; 1 HB = 9.807e6 Pa)"
    assert rows["uncertainty.variables[nu_b].scale"][0] == "1 (unused: no display unit)"


def test_the_random_inputs_fields_are_not_repeated_and_no_value_is_lost(default_section):
    """13 variables x 10 fields repeated what the Random inputs table shows, each with its long description; each
    field's description is now given once, later items say 'as for' the first."""
    tables = _tables(default_section)
    rows = _all_settings(default_section)
    listed = [n for n in rows if n.startswith("uncertainty.variables[")]
    assert listed and all(n.endswith(".scale") for n in listed)
    assert rows["uncertainty.variables[E_b].scale"][-1] == "as for uncertainty.variables[Rj].scale"
    sources = [r[-1] for r in rows.values() if not r[-1].startswith("as for ")]
    assert not [s for s in set(sources) if sources.count(s) > 1 and len(s) > 60]  # each long description once
    # every value of a field left out is in its Random inputs row
    inputs = {r[1]: r for r in tables["Random inputs (13)"]}
    cfg = load_config("jin2025_flapping_wing")
    for spec in cfg.uncertainty.variables:
        label, name, group, distribution, mean, std, _cov, unit, target = inputs[spec.name]
        factor, shown_unit = variable_display(spec)
        assert (label, name, group, distribution, unit, target) == (
            spec.label, spec.name, spec.group.replace("_", " "), spec.distribution, shown_unit or "", spec.target)
        assert (mean.split(" (drawn")[0], std) == (f"{spec.mean * factor:.6g}", f"{spec.std * factor:.6g}")


def test_a_std_scaled_by_std_scale_stays_listed(tmp_path):
    cfg = load_config("jin2025_flapping_wing_two_sigma")
    rows = _all_settings(_section(tmp_path, cfg, "jin2025_flapping_wing_two_sigma"))
    assert rows["uncertainty.variables[E_b].std"][:2] == ["12", "GPa"]  # Random inputs shows the scaled 6 GPa
    assert "uncertainty.variables[l1].std" not in rows  # tolerances are not scaled there
    assert "uncertainty.variables[E_b].mean" not in rows


@pytest.mark.parametrize("config, changes, shown", [
    ("jin2025_flapping_wing", {}, "per_joint (one judged joint: one Kriging of its life, the system's)"),
    ("watt_six_bar_two_clearances", {}, "per_joint (2 judged joints: one Kriging of each joint's life)"),
    ("watt_six_bar_two_clearances", {"reliability.joints": ["E"]},
     "per_joint (one judged joint: one Kriging of its life, the system's)"),
    ("watt_six_bar_two_clearances", {"reliability.surrogate": "system_life"},
     "system_life (one Kriging of the system's life, over 2 judged joints)"),
])
def test_the_surrogate_says_what_it_learns(tmp_path, config, changes, shown):
    rows = _all_settings(_section(tmp_path, updated(config, changes)))
    assert rows["reliability.surrogate"][0] == shown


def test_no_description_is_a_dash_and_a_dash_has_no_unit(default_section):
    rows = _all_settings(default_section)
    assert [n for n, r in rows.items() if r[-1] == "\u2014"] == []  # mechanism.type and a variable's group had none
    assert rows["simulation.max_step"][:2] == ["\u2014", ""]  # no value, no unit ('— s')
    assert rows["mechanism.crank.com_offset"][:2] == ["\u2014", ""]
    assert rows["wear.peak_separation_deg"][:2] == ["30", "deg"]  # in degrees by its name, with no unit shown
    assert rows["uncertainty.clearance.label"][0] == "(empty)"
    assert rows["uncertainty.clearance.mean"][:2] == ["2", "um"]  # as Random inputs gives it (it read 0.002 mm)
    mechanism = dict(_tables(default_section)["mechanism"])
    assert mechanism["type"] == "four_bar (a crank-rocker)"  # as mechanism.type names it, not 'crank_rocker'


def test_a_general_linkage_with_two_joints_lists_each_joints_allowance(tmp_path):
    """toggle_press judges K and C against 0.01 D of each bushing: the settings said 'allowance_mm 0.24', the
    first's, until the reliability stage had run."""
    section = _section(tmp_path, load_config("benchmarks/configs/toggle_press.toml"))
    kv = dict(_tables(section)["item"])
    assert kv["allowance_mm"] == "joint K: 0.24, joint C: 0.3 (per joint)"
    rows = _all_settings(section)
    assert rows["reliability.allowances"][:2] == ["{}", ""] and rows["reliability.allowance"][:2] == ["\u2014", ""]
    assert rows["reliability.surrogate"][0] == "per_joint (2 judged joints: one Kriging of each joint's life)"


def test_a_folder_recorded_with_the_former_display_units_finds_no_setting_changed(tmp_path):
    """The clearance's mean was recorded as 0.002 mm and E_b's empty bounds in MPa: a resume compares in SI, so a
    study recorded so moves no result aside."""
    from jointwear.study.settings_record import settings_dump
    from jointwear.study.superseded import changed_settings

    dump = settings_dump(load_config("jin2025_flapping_wing"))
    former = {"uncertainty.clearance.mean": (0.002, "mm"), "uncertainty.clearance.minimum": (1e-4, "mm"),
              "uncertainty.clearance.table5_std": (1e-6, "mm"), "uncertainty.variables[E_b].lower": (None, "MPa")}
    old = [{**r, "value": former[r["name"]][0], "unit": former[r["name"]][1]} if r["name"] in former else r
           for r in dump["settings"]]
    write_dump(tmp_path, {**dump, "settings": old})
    assert json.loads((tmp_path / "config.json").read_text())["settings"] == old
    assert changed_settings(tmp_path, dump["settings"]) == []
