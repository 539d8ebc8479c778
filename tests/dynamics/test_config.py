"""Config loading, unit suffixes, presets, reference generation."""

import math

import pytest

from jointwear.config import (
    ConfigError,
    available_presets,
    config_from_dict,
    config_reference_markdown,
    load_config,
)
from jointwear.units import PA_PER_HB, convert_keys, split_unit_key


def test_presets_load_with_si_values():
    assert {"jin2025_flapping_wing", "flores_slider_crank"} <= set(available_presets())
    cfg = load_config()  # default preset
    assert cfg.name == "jin2025_flapping_wing" and "Drones" in cfg.citation
    m = cfg.mechanism
    assert m.crank.length == pytest.approx(6e-3) and m.rod.length == pytest.approx(38e-3)
    assert m.rocker_pivot == pytest.approx((11.5e-3, 38e-3))
    assert m.crank_speed == pytest.approx(480 * 2 * math.pi / 60)
    cj = cfg.clearance_joints[0]
    assert cj.clearance == pytest.approx(2e-6)
    assert cj.bearing_material.youngs_modulus == 120e9
    assert cj.bearing_material.hardness == pytest.approx(350 * 9.807e6)  # paper-notes: HB x 9.807e6 Pa
    assert cj.journal_material.wear_coefficient == 2.1e-3
    assert cj.friction.mu_s == 0.15 and cj.friction.v_s == 1e-4
    sc = load_config("flores_slider_crank")
    assert sc.clearance_joints[0].clearance == pytest.approx(0.5e-3)
    assert sc.mechanism.crank_speed == pytest.approx(5000 * 2 * math.pi / 60)


def test_unit_suffixes():
    fields = frozenset({"length", "mu_s", "v_s", "hardness", "speed"})
    assert split_unit_key("length_mm", fields) == ("length", "mm")
    assert split_unit_key("mu_s", fields) is None  # a field, never "mu in seconds"
    assert split_unit_key("v_s_m_s", fields) == ("v_s", "m_s")
    assert convert_keys({"hardness_HB": 2.0}, fields) == {"hardness": 2 * PA_PER_HB}
    assert convert_keys({"speed_rpm": 60.0}, fields)["speed"] == pytest.approx(2 * math.pi)
    with pytest.raises(ValueError, match="given twice"):
        convert_keys({"length": 1.0, "length_mm": 1.0}, fields)


def test_duplicate_and_unknown_keys_are_config_errors():
    cfg = load_config().model_dump()
    cfg["mechanism"]["rod"]["length_mm"] = 38.0  # also given as length
    with pytest.raises(ConfigError, match="mechanism.rod.*given twice"):
        config_from_dict(cfg)
    cfg = load_config().model_dump()
    cfg["mechanism"]["rod"]["lenght"] = 1.0
    with pytest.raises(ConfigError, match="lenght"):
        config_from_dict(cfg)


@pytest.mark.parametrize("section, key, value, message", [
    (("clearance_joints", 0), "width_deg", 8.0,
     r"width_deg: width is in m, and '_deg' is a suffix of rad: use width_m"),
    (("mechanism",), "crank_speed_deg", 300.0, r"crank_speed is in rad/s.*crank_speed_rpm"),
    (("reliability",), "allowance_HB", 0.04, r"allowance is in m, and '_HB' is a suffix of Pa"),
    (("mechanism",), "rocker_torque_N", -0.2, r"rocker_torque is in N m.*rocker_torque_N_m"),
    (("clearance_joints", 0, "friction"), "mu_d_deg", 0.1, r"mu_d is a plain number, without a unit"),
])
def test_a_unit_suffix_of_another_dimension_is_refused(section, key, value, message):
    """A suffix converts only to its field's dimension: `width_deg = 8` was read as a 140 mm width."""
    cfg = load_config().model_dump()
    node = cfg
    for part in section:
        node = node[part]
    plain = key.rsplit("_", 1)[0]
    node.pop(plain, None)
    node[key] = value
    with pytest.raises(ConfigError, match=message):
        config_from_dict(cfg)


def test_a_random_variable_takes_the_unit_of_its_target():
    """mean/std/bounds of a variable carry suffixes of its target's dimension: std_mm on a hardness is refused,
    std_HB and std_MPa are the same number."""
    def with_std(key, value):
        cfg = load_config().model_dump()
        var = next(v for v in cfg["uncertainty"]["variables"] if v["target"].endswith("bearing_material.hardness"))
        var.pop("std")
        var[key] = value
        return config_from_dict(cfg), var["name"]

    (a, name), (b, _) = with_std("std_HB", 10.0), with_std("std_MPa", 10.0 * PA_PER_HB / 1e6)
    spec = lambda c: next(v for v in c.uncertainty.variables if v.name == name)  # noqa: E731
    assert spec(a).std == pytest.approx(spec(b).std, rel=1e-12)
    refused = rf"variables\[{name}\]\.std_mm: std is in Pa.*std_HB \(the unit of its target\)"
    with pytest.raises(ConfigError, match=refused):
        with_std("std_mm", 9.0)


@pytest.mark.parametrize("change, message", [
    ({"uncertainty.variables.l1.std_GPa": 1.0}, r"variables\[l1\]\.std_GPa: std is in m, and '_GPa' is a suffix of Pa"),
    ({"uncertainty.variables.k_b.std_HB": 1.0}, r"variables\[k_b\]\.std_HB: std is a plain number"),
    ({"uncertainty.variables.HB_b.mean_mm": 200.0}, r"variables\[HB_b\]\.mean_mm: mean is in Pa"),
])
def test_updated_checks_a_variables_suffix_as_a_file_does(change, message):
    """updated() set `l1.std_GPa = 1` as a 1e9 m crank-length std (a file refused it): it goes through the schema's
    own check by the target's unit now."""
    from jointwear.config import updated

    base = load_config("flores_slider_crank")
    with pytest.raises(ConfigError, match=message):
        updated(base, change)
    hb = {v.name: v for v in updated(base, {"uncertainty.variables.HB_b.std_HB": 10.0}).uncertainty.variables}
    assert hb["HB_b"].std == pytest.approx(10.0 * PA_PER_HB)


@pytest.mark.parametrize("value, got", [
    ({"a": 1}, "(got {'a': 1})"), (None, "(got None)"), ([1, 2], "(got [1, 2])"),
    (list(range(40)), "(got [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16...)"),  # cut at 60 characters
])
def test_a_table_an_array_or_nothing_where_a_number_is_due_is_shown(value, got):
    """'reliability.max_calls: Input should be a valid integer' did not say what was given instead."""
    from jointwear.config import updated

    with pytest.raises(ConfigError, match=r"reliability\.max_calls: Input should be a valid integer \(got "):
        updated(load_config("flores_slider_crank"), {"reliability.max_calls": value})
    try:
        updated(load_config("flores_slider_crank"), {"reliability.max_calls": value})
    except ConfigError as exc:
        assert str(exc).endswith(got), str(exc)


def test_updated_lays_a_mapping_over_its_section_and_replaces_it_with_a_section_object():
    """updated(cfg, {"reliability": {"max_calls": 20}}) reset every other key of the section to its default (the
    curve's cycles, the targets, n_mc), silently; a Study from the same mapping merged it. A mapping is now laid over
    the section as `extends` lays a table, in a list of named tables too; a section object still replaces it."""
    from jointwear.config import updated

    base = load_config("flores_slider_crank")
    new = updated(base, {"reliability": {"max_calls": 20}})
    assert new.reliability == base.reliability.model_copy(update={"max_calls": 20})
    assert base.reliability.cycles_start is not None and base.reliability.target_reliability != [0.9]  # not defaults
    mm = updated(base, {"reliability": {"allowance_mm": 0.05}})  # another unit of a key the section holds
    assert mm.reliability.allowance == pytest.approx(5e-5)
    assert mm.reliability.max_calls == base.reliability.max_calls
    friction = base.clearance_joints[0].friction
    by_item = updated(base, {"clearance_joints.0": {"friction": {"mu_d": 0.012}}})
    assert by_item == updated(base, {"clearance_joints.0.friction.mu_d": 0.012})
    assert by_item.clearance_joints[0].friction == friction.model_copy(update={"mu_d": 0.012})
    whole = updated(base, {"clearance_joints.0.friction": type(friction)(law="none")})
    assert whole.clearance_joints[0].friction == type(friction)(law="none")  # replaced: the defaults of a new one
    with pytest.raises(ConfigError, match=r"clearance_joints\[B\]\.friction\.mu_dd: unknown key.*mu_d"):
        updated(base, {"clearance_joints.0": {"friction": {"mu_dd": 0.2}}})


@pytest.mark.parametrize("section, key, value, message", [
    (("reliability",), "target_reliability", "0.9",
     r"reliability\.target_reliability: a number is expected, not the string '0.9' \(write it without quotes\)"),
    (("reliability",), "target_reliability", [0.9, "0.5"], r"target_reliability: .*not the string '0.5'"),
    (("compute",), "workers", True, r"compute\.workers: a number is expected, not the boolean true"),
    (("mechanism",), "rocker_pivot", [0.0115, "38e-3"], r"mechanism\.rocker_pivot: .*not the string '38e-3'"),
])
def test_a_quoted_number_or_a_boolean_is_not_read_as_a_number(section, key, value, message):
    """pydantic's lax mode read `target_reliability = "0.9"` as 0.9 and `workers = true` as 1 without a word."""
    cfg = load_config().model_dump()
    node = cfg
    for part in section:
        node = node[part]
    node[key] = value
    with pytest.raises(ConfigError, match=message):
        config_from_dict(cfg)


def test_numpy_scalars_take_unit_suffixes():
    """A sweep over np.arange gives np.int64: it was refused as 'expected a number with unit 'rpm', got int64'."""
    import numpy as np

    from jointwear.config import updated

    speeds = [updated(load_config(), {"mechanism.crank_speed_rpm": v}).mechanism.crank_speed
              for v in (np.int64(480), np.int32(480), np.float32(480.0), 480)]
    assert speeds == [pytest.approx(480 * 2 * math.pi / 60, rel=1e-15)] * 4


def test_a_quoted_number_in_a_file_is_refused_with_the_others(tmp_path):
    """Every quoted number of a section is named at once, a unit-suffixed one included."""
    path = tmp_path / "quoted.toml"
    path.write_text('extends = "jin2025_flapping_wing"\n[reliability]\nmax_calls = "30"\nallowance_mm = "0.05"\n')
    with pytest.raises(ConfigError) as err:
        load_config(path)
    text = str(err.value)
    assert "max_calls: a number is expected, not the string '30'" in text
    assert "allowance" in text and "'0.05'" in text


@pytest.mark.parametrize("section, key, hint", [
    (("mechanism", "rod"), "mass_gr", "the unit suffixes of mass: _kg, _g"),
    (("mechanism",), "crank_speed_RPM", "did you mean crank_speed_rpm? unit suffixes are case-sensitive"),
    (("clearance_joints", 0), "bearing_raduis_mm", "did you mean bearing_radius_mm?"),
    ((), "sensitivty", "did you mean sensitivity?"),
])
def test_an_unknown_key_names_what_was_meant(section, key, hint):
    cfg = load_config().model_dump()
    node = cfg
    for part in section:
        node = node[part]
    node[key] = 1.0
    with pytest.raises(ConfigError) as err:
        config_from_dict(cfg)
    assert f"{key}: unknown key (not a setting of this section) ({hint})" in str(err.value)


def test_a_misspelt_required_key_is_one_problem_not_two():
    """A typo in a required key (`targt`) was told twice: the unknown key, and 'target: Field required'."""
    data = load_config().model_dump()
    variable = data["uncertainty"]["variables"][0]
    variable["targt"] = variable.pop("target")
    with pytest.raises(ConfigError) as err:
        config_from_dict(data)
    assert str(err.value).endswith(f"uncertainty.variables[{variable['name']}].targt: unknown key (not a setting of "
                                   "this section) (did you mean target?)"), err.value
    joint = load_config().model_dump()
    joint["clearance_joints"][0]["jornal_radius_mm"] = 1.0  # with a unit suffix: the same
    joint["clearance_joints"][0].pop("journal_radius")
    assert "Field required" not in str(pytest.raises(ConfigError, config_from_dict, joint).value)
    unlike = load_config().model_dump()  # a key like no field: the missing one is still told
    unlike["clearance_joints"][0]["zzz"] = unlike["clearance_joints"][0].pop("journal_radius")
    assert "clearance_joints[A].journal_radius: Field required" in str(
        pytest.raises(ConfigError, config_from_dict, unlike).value)


def test_a_clearance_in_a_joints_table_says_how_the_table_gives_it():
    """updated(config, {'clearance_joints.B.clearance_mm': 0.4}) works; the same key in a table was only 'unknown'."""
    cfg = load_config().model_dump()
    cfg["clearance_joints"][0]["clearance_mm"] = 0.4
    with pytest.raises(ConfigError, match="clearance_mm: unknown key .*; a clearance joint's table gives "
                                          "bearing_radius and journal_radius"):
        config_from_dict(cfg)


def test_config_reference_markdown():
    md = config_reference_markdown()
    for key in ("assembly_branch", "v0_min", "baumgarte_alpha", "jin2025_flapping_wing", "hardness"):
        assert key in md
    for section in ("## wear", "## uncertainty", "## reliability", "## sensitivity", "## compute"):
        assert section in md
    # the validators' bounds are told (n_grid < 16 was refused by a rule the reference did not give)
    (row,) = [line for line in md.splitlines() if line.startswith("| `n_grid` |")]
    assert row.endswith("Allowed: >= 16, <= 100000. |")
    (row,) = [line for line in md.splitlines() if line.startswith("| `restitution` |")]
    assert row.endswith("Allowed: > 0, <= 1. |")


def test_docs_config_md_is_the_generated_reference():
    from pathlib import Path

    doc = Path(__file__).resolve().parents[2] / "docs" / "config.md"
    assert doc.read_text(encoding="utf-8") == config_reference_markdown(), (
        "docs/config.md is out of date: python -c 'import jointwear.config as c; "
        "print(c.config_reference_markdown(), end=\"\")' > docs/config.md")


def test_a_mapping_of_toml_tables_is_a_config_as_its_file_is(tmp_path):
    """From a notebook: the tables of a TOML file as a dict, unit suffixes and `extends` included, give the config the
    file gives; anything else is refused naming what is accepted."""
    import tomllib

    text = 'extends = "jin2025_flapping_wing"\n[reliability]\nallowance_mm = 0.02\n'
    path = tmp_path / "variant.toml"
    path.write_text(text, encoding="utf-8")
    from_file = load_config(path)
    from_mapping = load_config(tomllib.loads(text))
    assert from_mapping == from_file and from_mapping.reliability.allowance == pytest.approx(2e-5)
    with pytest.raises(ConfigError, match="expected a preset name, a TOML path, a StudyConfig or a mapping"):
        load_config(42)
    with pytest.raises(ConfigError, match="allowance_furlong: unknown key"):
        load_config({"extends": "jin2025_flapping_wing", "reliability": {"allowance_furlong": 1}})


def test_a_bad_value_is_echoed_with_its_si_unit_and_a_whole_config_rule_names_its_field_first():
    cfg = load_config().model_dump()
    cfg["clearance_joints"][0]["width"] = -0.008
    with pytest.raises(ConfigError, match=r"clearance_joints\[A\]\.width: .*\(got -0\.008 m\)"):
        config_from_dict(cfg, "my.toml")
    cfg = load_config().model_dump()
    cfg["clearance_joints"][0]["joint"] = "Z"
    with pytest.raises(ConfigError) as err:
        config_from_dict(cfg, "my.toml")
    assert str(err.value).startswith("my.toml: clearance_joints[A].joint: 'Z' is not a joint")


def test_a_path_in_a_message_names_a_list_item_and_its_field_as_updated_reads_them():
    """A named variable's bad std was told as `uncertainty.variables[4]`, and a section's own rule as
    `reliability: max_calls`: both now as the paths `updated` and the docs write."""
    from jointwear.config import updated

    cfg = load_config()
    name = cfg.uncertainty.variables[4].name
    with pytest.raises(ConfigError) as err:
        updated(cfg, {f"uncertainty.variables[{name}].std": 0.0})
    assert f"uncertainty.variables[{name}].std: " in str(err.value), err.value
    with pytest.raises(ConfigError, match=r"config: reliability\.max_calls: must be > 0 \(got -1\)"):
        updated(cfg, {"reliability.max_calls": -1})
    data = cfg.model_dump()
    data["uncertainty"]["variables"][5]["name"] = name  # a name given twice: the index tells which
    data["uncertainty"]["variables"][5]["std"] = -1.0
    problems = str(pytest.raises(ConfigError, config_from_dict, data).value)
    assert "uncertainty.variables[5].std" in problems, problems


def test_a_clearance_the_joint_sets_is_listed_as_set_by_it_and_follows_the_joint():
    """`check` listed a clearance's nominal diameter and mean that the study took from its joint as 'the config', and
    an updated journal left the nominal diameter at the old pin's (the ISO 286 tolerances of another size)."""
    from jointwear.config import updated
    from jointwear.study.settings_record import origin, settings_records

    data = load_config().model_dump()
    for key in ("nominal_diameter", "mean"):
        data["uncertainty"]["clearance"].pop(key)
    cfg = config_from_dict(data)
    joint = cfg.clearance_joints[0]
    spec = cfg.uncertainty.clearance
    assert spec.nominal_diameter == 2.0 * joint.journal_radius and spec.mean == joint.clearance
    shown = {r["name"]: origin(r) for r in settings_records(cfg)}
    assert shown["uncertainty.clearance.nominal_diameter"] == "set by joint A's journal diameter"
    assert shown["uncertainty.clearance.mean"] == "set by joint A's radii"
    assert shown["uncertainty.clearance.hole_grade"] == "the config"
    bigger = updated(cfg, {"clearance_joints.A.journal_radius_mm": 1.5, "clearance_joints.A.bearing_radius_mm": 1.503,
                           "clearance_joints.A.bearing_outer_radius_mm": 3.0})
    assert bigger.uncertainty.clearance.nominal_diameter == pytest.approx(3e-3)
    assert bigger.uncertainty.clearance.mean == pytest.approx(3e-6)
    assert config_from_dict(cfg.model_dump()) == cfg  # written without them, read back the same
    # given in the config, they are the config's
    given = {r["name"]: origin(r) for r in settings_records(load_config())}
    assert given["uncertainty.clearance.nominal_diameter"] == "the config"


def test_a_cross_section_problem_names_the_file(tmp_path, capsys):
    """The study's cross-section rules name the file they read, as the schema's do (they said 'config')."""
    from jointwear.cli import main_entry

    path = tmp_path / "mine.toml"
    path.write_text('extends = "jin2025_flapping_wing"\n[sensitivity]\ncycles = 123\n', encoding="utf-8")
    assert main_entry(["check", str(path)]) == 2
    assert f"error: {path}: sensitivity.cycles: 123 is not one of the R(N) curve's" in capsys.readouterr().err


def test_a_budget_below_the_initial_design_is_refused_by_the_schema():
    """max_calls < n_initial passed `check` and failed inside the learning, after the store was written."""
    from jointwear.config import updated

    with pytest.raises(ConfigError, match=r"reliability.max_calls: must be >= n_initial \(got 10 < 12\)"):
        updated(load_config(), {"reliability.max_calls": 10})
    assert updated(load_config(), {"reliability.max_calls": 10, "reliability.n_initial": 10}).reliability.max_calls == 10


def test_a_target_reliability_given_twice_is_refused_by_name():
    """`target_reliability = [0.9, 0.9]` passed check: the life table had the same row twice."""
    from jointwear.config import updated

    with pytest.raises(ConfigError, match=r"reliability.target_reliability: 0.9 given twice"):
        updated(load_config(), {"reliability.target_reliability": [0.9, 0.5, 0.9]})
    assert updated(load_config(), {"reliability.target_reliability": [0.9, 0.5]}).reliability.targets == [0.9, 0.5]


def test_check_says_that_the_config_marks_inherited_values_too(tmp_path, capsys):
    # a file that extends another: its settings printed '# the config' for the base's values, which the file never
    # wrote (a preset's wear.cycles, inherited, was taken for the user's own)
    from pathlib import Path

    from jointwear.cli import main_entry

    rig = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"
    path = tmp_path / "rig.toml"
    path.write_text(f'extends = "{rig.as_posix()}"\n\n[wear]\ncycles = 1000\n', encoding="utf-8")
    assert main_entry(["check", str(path)]) == 0
    err = capsys.readouterr().err
    assert f"'# the config' marks the values of {path} and of the config it extends ({rig.as_posix()})" in err
