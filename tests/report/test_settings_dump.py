"""config.json from a validated config: every setting with its unit, source and paper-open flag."""

from __future__ import annotations

import json

import pytest
from pydantic import BaseModel, Field

from jointwear.report import build_report
from jointwear.study.settings_record import is_paper_open, settings_dump, write_settings


class _Inner(BaseModel):
    length: float = Field(0.006, description="Crank length (Table 4).", json_schema_extra={"unit": "m"})
    modulus: float = Field(2.11e11, description="Young's modulus (Table 2).", json_schema_extra={"unit": "Pa"})


class _Cfg(BaseModel):
    name: str = "toy"
    citation: str = "A. Author, Journal 2025"
    inner: _Inner = Field(default_factory=_Inner)
    mu: float = Field(0.1, description="Friction; paper gives none, paper-notes baseline.")
    gravity: bool = Field(True, description="Explicit.", json_schema_extra={"paper_open": True})
    speed: float = Field(50.265, description="Crank speed.", json_schema_extra={"unit": "rad/s"})


def test_dump_of_a_pydantic_config(tmp_path):
    d = settings_dump(_Cfg(), seed=3)
    by = {s["name"]: s for s in d["settings"]}
    assert d["name"] == "toy" and d["preset"] is None and d["source"] == "config"  # a config, not a preset
    assert d["citation"].startswith("A. Author") and d["seed"] == 3
    assert settings_dump(_Cfg(), preset="toy", source="preset")["preset"] == "toy"
    assert "name" not in by and "citation" not in by
    assert by["inner.length"]["value"] == pytest.approx(6.0) and by["inner.length"]["unit"] == "mm"
    assert by["inner.modulus"]["value"] == pytest.approx(211.0) and by["inner.modulus"]["unit"] == "GPa"
    assert by["speed"]["value"] == pytest.approx(480.0, rel=1e-4) and by["speed"]["unit"] == "rpm"
    assert by["mu"]["paper_open"] and by["gravity"]["paper_open"] and not by["inner.length"]["paper_open"]
    assert by["mu"]["source"].startswith("Friction")
    path = write_settings(tmp_path, _Cfg())
    assert json.loads(path.read_text())["settings"]
    page = build_report(tmp_path).read_text()
    # no [reference]: the study's own settings, without the reference's open/closed flags
    assert "Settings of this study (5, 0 given in the config)" in page and "leaves open" not in page
    assert d["reference"] is None


def test_dump_says_which_values_the_config_gives():
    by = {s["name"]: s for s in settings_dump(_Cfg(mu=0.2, inner=_Inner(length=0.01)))["settings"]}
    assert by["mu"]["explicit"] and by["inner.length"]["explicit"]
    assert not by["speed"]["explicit"] and not by["inner.modulus"]["explicit"]


def test_paper_open_heuristic():
    assert is_paper_open("Static friction coefficient; paper-notes baseline 0.15.")
    assert is_paper_open("Baumgarte alpha (paper Eq. 6, value not given; project choice).")
    assert not is_paper_open("Coefficient of restitution cr (Table 4: 0.9).")
    assert not is_paper_open("anything", {"paper_open": False})


def test_dump_of_the_default_preset():
    from jointwear import config

    cfg = config.load_config("jin2025_flapping_wing")
    d = settings_dump(cfg)
    assert d["mechanism"]["crank_mm"] == pytest.approx(6.0)
    assert d["mechanism"]["pivot_mm"] == pytest.approx([11.5, 38.0])
    names = [s["name"] for s in d["settings"]]
    assert any("friction.mu_d" in n for n in names)
    assert any(s["paper_open"] for s in d["settings"])
    # the preset's cited results travel with the settings, in report units, and are not listed as settings
    ref = d["reference"]
    assert ref["label"] == "Jin et al. 2025" and not any(n.startswith("reference") for n in names)
    rel = {v["cycles"]: v for v in ref["values"] if v["quantity"] == "reliability"}
    assert rel[400_000]["value"] == 0.739 and rel[400_000]["band"]["absolute"] == 0.15
    assert all(v["band"]["absolute"] == 0.15 for v in rel.values())  # every level of R(N) in the same band
    assert all(v["source"] for v in ref["values"])
    wear = next(v for v in ref["values"] if v["quantity"] == "nominal_max_wear")
    assert (wear["unit"], wear["value"], wear["band"]["lower"], wear["band"]["upper"]) == ("mm", 0.0249, 0.021, 0.029)
    assert d["allowance_mm"] == pytest.approx(cfg.reliability.allowance * 1e3)


def test_the_random_inputs_are_listed_in_their_targets_units():
    """Each random variable in report units: its own display unit when it gives one (the preset's HB), else its
    target's (a modulus in GPa, not 1.1e11), a hardness in HB; the mean, std and bounds with one prefix."""
    from jointwear import config

    cfg = config.load_config("jin2025_flapping_wing")
    rows = {r["name"]: r for r in settings_dump(cfg)["random_variables"]}
    assert [r for r in rows] == [s.name for s in cfg.uncertainty.all_specs()]
    assert (rows["l2"]["unit"], rows["l2"]["mean"]) == ("mm", pytest.approx(38.0))
    spec = next(s for s in cfg.uncertainty.variables if s.name == "HB_b")
    assert rows["HB_b"]["unit"] == spec.unit and rows["HB_b"]["mean"] == pytest.approx(spec.mean * spec.scale)
    plain = config.updated(cfg, {"uncertainty.variables.HB_b.unit": "", "uncertainty.variables.HB_b.scale": 1.0})
    hb = next(r for r in settings_dump(plain)["random_variables"] if r["name"] == "HB_b")
    # a hardness without its own display unit in HB, as it is entered and quoted (it read 1.177 GPa; 9.807e6 Pa/HB)
    assert (hb["unit"], hb["mean"]) == ("HB", pytest.approx(spec.mean / 9.807e6))
    e_b = next(r for r in settings_dump(plain)["random_variables"] if r["name"] == "E_b")
    assert e_b["unit"] == "GPa"
    assert hb["std"] / hb["mean"] == pytest.approx(spec.std / spec.mean) == pytest.approx(hb["cov"])


def test_a_design_specification_is_listed_field_by_field_in_its_variables_unit():
    """`check` printed a material option's specifications as a raw SI dump ("{'HB_b': 'mean=1176840000.0 ...'}");
    each field is now a row, in the unit of its variable's target (a hardness in HB, as entered)."""
    from jointwear.config import load_config
    from jointwear.study.settings_record import settings_records

    cfg = load_config()  # its [design] has a "hardened" class of HB_b: mean_HB = 390
    k = next(i for i, p in enumerate(cfg.design.properties) if p.variable == "HB_b")
    rows = {r["name"]: r for r in settings_records(cfg)}
    row = rows[f"design.properties[{k}].classes[hardened].mean"]
    assert row["unit"] == "HB" and row["value"] == pytest.approx(390, rel=1e-12)
    assert not any(isinstance(r["value"], str) and "mean=" in r["value"] for r in rows.values())


def test_a_setting_is_shown_as_entered():
    """The settings table showed a seed as 2,025, a point of a body as 18.780500000000004 and a length of 18.7805 mm
    as 18.78."""
    from jointwear.report.study_sections import setting_text

    assert setting_text({"name": "reliability.seed", "value": 2025}) == "2025"
    assert setting_text({"name": "reliability.n_mc", "value": 238_691}) == "238,691"
    assert setting_text({"name": "mechanism.bodies[1].points", "value": {"B": [18.780500000000004, -2.5]}}) \
        == "{B: [18.7805, -2.5]}"
    assert setting_text({"name": "clearance_joints[0].bearing_radius", "value": 18.7805}) == "18.7805"
    assert setting_text({"name": "reliability.pf_floor", "value": 1e-3}) == "0.001"


def test_a_random_inputs_mean_beside_the_value_drawn_at_its_target():
    # the preset's E_j samples around Table 6's 210 GPa while the nominal mechanism runs Table 2's 211 GPa: a shift of
    # under 0.1 standard deviations, not warned, and the report's random inputs showed 210 with nothing beside it
    from jointwear.config import load_config
    from jointwear.report.study_sections import mean_cell
    from jointwear.study.settings_record import random_variables

    rows = {v["name"]: v for v in random_variables(load_config("jin2025_flapping_wing"))}
    assert (rows["E_j"]["mean"], rows["E_j"]["drawn"], rows["E_j"]["unit"]) == (210.0, 211.0, "GPa")
    assert mean_cell(rows["E_j"]) == "210 (drawn: 211)"
    assert [n for n, v in rows.items() if "drawn" in mean_cell(v)] == ["E_j"]


def test_a_truncated_inputs_own_moments_are_given_beside_its_parent_normals():
    """The flapping wing's clearance was given as 2.0 um, std 0.97 um: its parent normal's, while the truncated normal
    drawn (at 0.1 um) has 2.059 and 0.911 um. Exact: a normal truncated below at a = (lower - mu) / s has mean
    mu + s lam and variance s^2 (1 + a lam - lam^2), lam = phi(a) / (1 - Phi(a)) (Johnson, Kotz & Balakrishnan)."""
    import math

    from scipy.stats import norm

    from jointwear.config import load_config
    from jointwear.report.study_sections import _distribution_cell
    from jointwear.study.settings_record import random_variables

    rows = {v["name"]: v for v in random_variables(load_config("jin2025_flapping_wing"))}
    c = rows["c"]
    mu, s = c["mean"], c["std"]
    a = (c["lower"] - mu) / s
    lam = norm.pdf(a) / norm.sf(a)
    assert c["sampled_mean"] == pytest.approx(mu + s * lam, rel=1e-12)
    assert c["sampled_std"] == pytest.approx(s * math.sqrt(1 + a * lam - lam**2), rel=1e-12)
    assert (round(c["sampled_mean"], 3), round(c["sampled_std"], 3)) == (2.059, 0.911)  # the audit's values
    assert (rows["l2"]["sampled_mean"], rows["l2"]["sampled_std"]) == (rows["l2"]["mean"], rows["l2"]["std"])
    assert _distribution_cell(c).endswith("; sampled: mean 2.059, std 0.9106")


class _Item(BaseModel):
    name: str
    width: float = Field(0.01, json_schema_extra={"unit": "m"})


class _Listed(BaseModel):
    items: list[_Item]


def test_a_lists_items_are_named_as_config_errors_and_updated_name_them():
    """Each item by its name where it is unique and reads as one path step (as jointwear.config.updated reads a path
    and config errors write it); by its index where two share a name or it holds a '.', '[' or ']'."""
    from jointwear.study.settings_record import settings_records

    names = ["A", "St 37.2", "B", "B", "7", "x]"]
    listed = _Listed(items=[_Item(name=n) for n in names])
    recs = [r["name"] for r in settings_records(listed) if r["name"].endswith("width")]
    assert recs == ["items[A].width", "items[1].width", "items[2].width", "items[3].width", "items[4].width",
                    "items[5].width"]


def test_a_config_json_written_with_indices_reads_as_one_written_with_names(tmp_path):
    """A study folder recorded before list items went by their names: the same config finds no setting changed (no
    result is moved aside on resume), and a changed one is named by its item's name."""
    import re

    from jointwear.config import load_config, updated
    from jointwear.study.settings_record import named_paths, write_dump
    from jointwear.study.superseded import changed_settings

    cfg = load_config("watt_six_bar_two_clearances")
    dump = settings_dump(cfg)
    order = {"clearance_joints": [j.name for j in cfg.clearance_joints],
             "uncertainty.variables": [v.name for v in cfg.uncertainty.variables],
             "mechanism.joints": [j.name for j in cfg.mechanism.joints],
             "mechanism.bodies": [b.name for b in cfg.mechanism.bodies]}

    def by_index(name: str) -> str:
        for path, names in order.items():
            name = re.sub(rf"^{re.escape(path)}\[([^\]]+)\]", lambda m: f"{path}[{names.index(m.group(1))}]", name)
        return name

    old = {**dump, "settings": [{**r, "name": by_index(r["name"])} for r in dump["settings"]]}
    assert "clearance_joints[1].width" in {r["name"] for r in old["settings"]}  # the old spelling, written
    assert named_paths(old["settings"]) == dump["settings"]
    write_dump(tmp_path, old)
    assert changed_settings(tmp_path, dump["settings"]) == []
    wider = settings_dump(updated(cfg, {"clearance_joints[E].width_mm": 9.0}))["settings"]
    assert changed_settings(tmp_path, wider) == ["clearance_joints[E].width"]


def test_a_reference_value_is_listed_in_its_quantitys_report_unit():
    """`check` listed the reference's values in raw SI without a unit: 2.49e-05 (a wear depth in m), 1.91986 (an
    angle in rad), 46440 (a life of 12.9 h in s). They are listed in mm, deg and h, as config.json's `reference`
    gives them; plain quantities (a reliability, a cycle count) stay plain."""
    from jointwear.config import load_config
    from jointwear.study.settings_record import settings_records

    cfg = load_config()
    rows = {r["name"]: r for r in settings_records(cfg)}
    values = cfg.reference.values
    listed = {v.quantity: rows[f"reference.values[{i}].value"] for i, v in enumerate(values) if v.value is not None}
    shown = {quantity: (row["value"], row["unit"]) for quantity, row in listed.items()}
    assert shown["nominal_max_wear"] == (pytest.approx(0.0249), "mm")
    assert shown["nominal_max_wear_angle"] == (pytest.approx(110.0), "deg")
    assert shown["life_hours"] == (pytest.approx(12.9), "h")
    assert shown["reliability"][1] is None
    k = next(i for i, v in enumerate(values) if v.quantity == "nominal_max_wear_angle")
    band = rows[f"reference.values[{k}].band.absolute"]
    assert (band["value"], band["unit"]) == (pytest.approx(20.0), "deg")


def test_a_random_inputs_display_unit_sets_its_own_scale():
    # a designer wrote unit = "mm" / "HB" without scale (as the examples showed the pair): the random-inputs table
    # read '0.02 mm +- 3.5e-06 mm' for a 20 mm crank and '882,630,000 HB' for a bronze of 90 HB
    from jointwear.config import updated
    from jointwear.study.checks import config_warnings
    from jointwear.study.settings_record import random_variables

    base = updated("examples/my_linkage.toml", {})
    assert {v.name: v.unit for v in base.uncertainty.variables if v.unit} == {"l_crank": "mm", "HB_b": "HB"}
    rows = {v["name"]: v for v in random_variables(base)}
    assert (rows["l_crank"]["mean"], rows["l_crank"]["std"]) == pytest.approx((10.0, 0.0037), rel=1e-12)
    assert rows["HB_b"]["mean"] == pytest.approx(120.0, rel=1e-12)  # the HB's own scale, 1 / units.PA_PER_HB
    # a unit the keys do not take leaves scale to the user, and check says the SI numbers would show under it
    odd = updated(base, {"uncertainty.variables.HB_b.unit": "kgf/mm2", "uncertainty.variables.HB_b.scale": 1.0})
    assert {v["name"]: v for v in random_variables(odd)}["HB_b"]["mean"] == pytest.approx(120.0 * 9.807e6)
    assert any(w.startswith("uncertainty.variables[HB_b].unit: 'kgf/mm2' is not a unit jointwear converts")
               for w in config_warnings(odd))
    assert not any(".unit:" in w for w in config_warnings(base))


@pytest.mark.parametrize("changes, message", [
    ({"uncertainty.variables.HB_b.unit": "mm"},
     "uncertainty.variables[HB_b].unit: 'mm' is not a unit of its target clearance_joints.B.bearing_material.hardness "
     "(its units: Pa, kPa, MPa, GPa, HB)"),
    ({"uncertainty.variables.l_crank.scale": 1e6},
     "uncertainty.variables[l_crank].scale: 1e+06 does not show SI values in 'mm', which takes 1000: give that, or "
     "leave scale out (the unit sets it)"),
])
def test_a_display_unit_of_another_quantity_or_scale_is_refused_naming_the_field(changes, message):
    from jointwear.config import updated
    from jointwear.schema import ConfigError

    with pytest.raises(ConfigError) as err:
        updated("examples/my_linkage.toml", changes)
    assert message in str(err.value)
