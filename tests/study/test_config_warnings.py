"""Legal but probably unmeant: a random variable whose mean is far from the value drawn at its target."""

import copy
import math
import sys
from pathlib import Path

import pytest

from jointwear.config import available_presets, load_config, updated
from jointwear.study.checks import MEAN_SHIFT_WARNING_SIGMAS, config_warnings

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


@pytest.mark.parametrize("preset", available_presets())
def test_the_shipped_presets_draw_what_they_sample(preset):
    assert config_warnings(load_config(preset)) == []


def test_a_clearance_mean_far_from_the_drawn_gap_is_warned_with_its_distance():
    base = load_config()
    spec = base.uncertainty.clearance
    sigmas = MEAN_SHIFT_WARNING_SIGMAS + 1.0
    shifted = updated(base, {"uncertainty.clearance.mean": spec.mean + sigmas * spec.std})
    (warning,) = config_warnings(shifted)
    # in the units users read (mm for a length), as check lists the settings
    assert (f"the mean of 'c' ({(spec.mean + sigmas * spec.std) * 1e3:.6g} mm) is {sigmas:,.2g} standard deviations"
            in warning)
    inside = updated(base, {"uncertainty.clearance.mean": spec.mean + 0.5 * MEAN_SHIFT_WARNING_SIGMAS * spec.std})
    assert config_warnings(inside) == []


def test_a_nominal_material_changed_alone_is_warned():
    """A 20 % larger bearing wear coefficient in the material changed the wear stage's answer and left R(N) exactly
    the same (the random variable k_b kept its mean), and check said nothing."""
    base = load_config()
    spec = next(s for s in base.uncertainty.all_specs() if s.name == "k_b")
    changed = updated(base, {spec.target: spec.mean * 1.2})
    (warning,) = config_warnings(changed)
    assert "the mean of 'k_b'" in warning and "R(N) does not follow a change of the drawn value alone" in warning


@pytest.mark.parametrize("path, value, where", [
    # a hardness class given without its suffix: 120 Pa, not 120 HB (shown in HB, as check lists a hardness)
    ("design.properties.0.classes.2.mean", 120.0,
     f"design.properties[HB_b].classes[hard]: its mean ({120.0 / 9.807e6:.6g} HB) is"),
    # a fit's clearance in mm where um was meant: 531 times the study's
    ("design.fit.options.1.mean", 2e-3, "design.fit.options[H6/g5]: its mean (2 mm) is 1e+03 times"),
])
def test_a_design_specification_orders_of_magnitude_off_is_warned(path, value, where):
    """A unit slip in [design] passed check and design silently; a real alternative differs by a factor of a few."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "design"))
    from design_fixtures import DESIGN

    base = updated(load_config(), {"design": DESIGN})
    assert config_warnings(base) == []  # 390 HB against 350: a real alternative
    keys = path.split(".")
    design = copy.deepcopy(DESIGN)
    node = design
    for key in keys[1:-1]:
        node = node[int(key)] if key.isdigit() else node[key]
    node.pop(keys[-1] + "_HB", None)
    node[keys[-1]] = value
    (warning,) = config_warnings(updated(load_config(), {"design": design}))
    assert warning.startswith(where) and "a unit slip?" in warning


def test_a_design_specification_beyond_the_studys_population_is_warned():
    """A POM option against a bronze study (hardness and k about 8 study standard deviations away) was rejected by
    the design on an extrapolated R(N*) of 0.03 where its own study gave 0.97; nothing said it lay outside."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "design"))
    from design_fixtures import DESIGN

    from jointwear.study.checks import population_reach

    base = updated(load_config(), {"design": DESIGN})
    spec = next(s for s in base.uncertainty.all_specs() if s.name == "HB_b")
    reach = population_reach(base.reliability.n_mc)
    design = copy.deepcopy(DESIGN)
    cls = design["properties"][0]["classes"][2]
    cls.pop("mean_HB", None)
    for sigmas, warned in ((reach - 0.2, False), (reach + 0.2, True), (8.0, True)):
        cls["mean"] = spec.mean - sigmas * spec.std
        found = [w for w in config_warnings(updated(load_config(), {"design": design})) if "population of" in w]
        assert bool(found) is warned, (sigmas, found)
    assert "lies 8 of the study's standard deviations" in found[0] and "docs/design.md" in found[0]


def test_a_verification_budget_below_its_initial_design_is_warned():
    """verification_max_calls = 12 on the 13 inputs of the default study cut the verification's 2d + 2 = 28-point
    initial design to 12 and gave 'meets R* beyond its error' from that Kriging (80 calls: 0.956 +- 0.005 against
    its 0.946 +- 0.033); 3 calls read R = 1.0000 +- 0.34. Nothing said so."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "design"))
    from design_fixtures import DESIGN

    for calls, warned in ((27, True), (28, False)):
        cfg = updated(load_config(), {"design": DESIGN | {"verification_max_calls": calls}})
        found = [w for w in config_warnings(cfg) if w.startswith("design.verification_max_calls")]
        assert bool(found) is warned, (calls, found)
    twelve = config_warnings(updated(load_config(), {"design": DESIGN | {"verification_max_calls": 12}}))
    assert any("fewer than the verification's initial design of 2d + 2 = 28 points (d = 13 random inputs)" in w
               for w in twelve)


def test_a_design_target_outside_the_curve_is_warned():
    """A target of 100 cycles beside a curve from 1.5M passed `check` without a word (docs/design.md promised it):
    the study's learning refines the surrogate only about its curve's levels (300k-560k on the default study)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "design"))
    from design_fixtures import DESIGN

    for life, side in ((100.0, "before"), (299_999.0, "before"), (300_000.0, None), (560_000.0, None),
                       (900_000.0, "beyond")):
        cfg = updated(load_config(), {"design": DESIGN | {"targets": [{"reliability": 0.9, "life_cycles": life}]}})
        found = [w for w in config_warnings(cfg) if w.startswith("design.targets[0].life_cycles")]
        assert bool(found) is (side is not None), (life, found)
        if side:
            assert f"cycles lies {side} the R(N) curve (300,000-560,000 cycles)" in found[0], found
    factor = updated(load_config(), {"design": DESIGN | {"targets": [{"reliability": 0.9, "life_factor": 5.0}]}})
    assert not [w for w in config_warnings(factor) if w.startswith("design.targets")]  # known only after the study


def test_a_clearance_mean_at_or_below_its_minimum_is_refused_naming_the_field():
    """A mean of -5 um passed check, and the truncation at the minimum then sampled clearances of 0.1-0.9 um."""
    from jointwear.schema import ConfigError

    with pytest.raises(ConfigError, match=r"uncertainty\.clearance.*mean of the clearance \(-5 um\) must exceed its "
                                          r"minimum \(0\.1 um\)"):
        updated(load_config(), {"uncertainty.clearance.mean_um": -5.0})


def test_a_clearance_mostly_truncated_at_its_minimum_is_warned_with_the_mean_it_samples():
    """The truncated normal's mean mu + sigma phi(a) / (1 - Phi(a)), a = (minimum - mu) / sigma (exact)."""
    from scipy.stats import norm

    from jointwear.study.checks import TRUNCATED_MEAN_SHIFT_WARNING

    base = load_config()
    narrow = updated(base, {"uncertainty.clearance.mean_um": 0.6})
    spec = narrow.uncertainty.clearance
    a = (spec.minimum - spec.mean) / spec.std
    sampled = spec.mean + spec.std * norm.pdf(a) / norm.sf(a)
    assert sampled - spec.mean > TRUNCATED_MEAN_SHIFT_WARNING * spec.mean  # the case is meant to warn
    # (the drawn gap stays 2 um: that shift of the mean is warned beside, as its own warning)
    (warning,) = [w for w in config_warnings(narrow) if w.startswith("uncertainty.clearance:")]
    assert warning.startswith(f"uncertainty.clearance: {norm.cdf(a):.1%} of the clearance's normal")
    assert f"their mean is {sampled * 1e6:.4g} um, not the designed 0.6 um" in warning
    failing = updated(narrow, {"uncertainty.clearance.infeasible_rule": "fail"})
    assert [w for w in config_warnings(failing) if w.startswith("uncertainty.clearance:")] == []


@pytest.mark.parametrize("changes, unread", [
    ({"wear.profile_smoothing_deg": 6.0}, "wear.profile_smoothing_deg: read only with geometry_mode = 'profile'"),
    ({"wear.geometry_mode": "profile", "wear.profile_deposit": "touch", "wear.profile_substep_cycles": 50.0},
     "wear.profile_substep_cycles: read only with profile_deposit = 'distributed'"),
    ({"wear.geometry_mode": "profile", "wear.uniform_growth": "bearing_max"},
     "wear.uniform_growth: read only with geometry_mode = 'uniform'"),
    ({"wear.geometry_mode": "profile", "wear.pressure": "hertz"},
     "wear.pressure: read only with geometry_mode = 'uniform'"),
    ({"wear.geometry_mode": "profile", "wear.profile_substep_cycles": 50.0}, None),
])
def test_a_wear_setting_its_mode_does_not_read_is_warned(changes, unread):
    """profile_smoothing_deg in uniform mode, profile_substep_cycles with the touch deposit, and the pressure in profile
    mode (which gave bit-identical profiles with either) passed silently."""
    warnings = config_warnings(updated(load_config(), changes))
    if unread is None:
        assert warnings == []
        return
    (warning,) = warnings
    assert warning.startswith(unread) and warning.endswith("so the setting changes nothing")


@pytest.mark.parametrize("factor, warned", [(100.0, True), (0.5, True), (1.596, False), (2.2, False)])
def test_a_half_width_factor_far_from_johnsons_is_warned(factor, warned):
    """A factor of 100 passed check and the wear stage blamed the material for the patch it made; the paper's reading
    (1.596, 1.41 times Johnson's) and anything within 2 times either way pass quietly."""
    from jointwear.wear.settings import JOHNSON_FACTOR

    warnings = [w for w in config_warnings(updated(load_config(), {"wear.half_width_factor": factor}))
                if w.startswith("wear.half_width_factor")]
    assert bool(warnings) == warned
    if warned:
        assert f"is {factor / JOHNSON_FACTOR:.3g} times Johnson's" in warnings[0]
    # the same without an uncertainty section (a wear-only config)
    rig = load_config(str(Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"))
    assert bool([w for w in config_warnings(updated(rig, {"wear.half_width_factor": factor}))
                 if w.startswith("wear.half_width_factor")]) == warned


def test_an_allowance_the_joint_cannot_be_checked_against_and_many_clearances_deep_is_warned():
    """flores_slider_crank gives no bearing wall: `allowance_mm = 5` on its 0.5 mm clearance passed check without a
    word (with a wall, an allowance at or beyond it is refused)."""
    from jointwear.study.checks import ALLOWANCE_CLEARANCE_WARNING

    base = load_config("flores_slider_crank")
    clearance = base.clearance_joints[0].clearance
    (warning,) = config_warnings(updated(base, {"reliability.allowance_mm": 5.0}))
    assert warning.startswith("reliability.allowance: 5 mm for joint B is 10 times its clearance (0.5 mm)")
    assert "clearance_joints.B.bearing_outer_radius" in warning
    assert config_warnings(updated(base, {"reliability.allowance": 0.9 * ALLOWANCE_CLEARANCE_WARNING * clearance})) == []
    walled = updated(base, {"clearance_joints.B.bearing_outer_radius_mm": 20.0, "reliability.allowance_mm": 5.0})
    assert config_warnings(walled) == []  # checked against its 10 mm wall instead, and within it


def test_a_budget_that_cannot_confirm_the_stop_is_warned():
    """max_calls = 14 with n_initial = 12 and batches of 2: the stop, held first on the initial design, needs two more
    designs (16 calls) to be confirmed, so the learning could only end on its budget."""
    base = load_config("jin2025_flapping_wing")
    tight = updated(base, {"reliability.max_calls": 14})
    (warning,) = [w for w in config_warnings(tight) if w.startswith("reliability.max_calls")]
    assert "needs at least 16" in warning and "hold_iterations = 3" in warning
    assert not [w for w in config_warnings(updated(base, {"reliability.max_calls": 16})) if "max_calls" in w]
    assert not [w for w in config_warnings(updated(tight, {"reliability.hold_iterations": 2})) if "max_calls" in w]


def test_a_hardness_is_told_in_hb_as_it_is_given():
    """The warning gave a hardness entered as mean_HB in Pa ('8.8263e+09 Pa'), while check lists it in HB."""
    base = load_config()
    spec = next(s for s in base.uncertainty.all_specs() if s.target.endswith("bearing_material.hardness"))
    index = [v.name for v in base.uncertainty.variables].index(spec.name)
    shifted = updated(base, {f"uncertainty.variables[{index}].mean_HB": 900.0})
    (warning,) = [w for w in config_warnings(shifted) if f"the mean of '{spec.name}'" in w]
    assert f"the mean of '{spec.name}' (900 HB) is" in warning
    drawn = base.clearance_joints[0].bearing_material.hardness
    assert f"drawn at its target {spec.target} ({drawn / 9.807e6:.6g} HB)" in warning and " Pa" not in warning


@pytest.mark.parametrize("moved_mm, warned", [(1.0, True), (0.005, False)])
def test_a_drawn_gap_the_assembly_closes_is_warned(tmp_path, moved_mm, warned):
    """A point drawn 1.5 mm off its partner passed check silently (the assembly closes gaps up to closure_tolerance,
    5 % of the median link size: 1.3 mm on this linkage of 26 mm) and changed the link; a drawing rounded to 0.01 mm
    must not be warned (GAP_WARNING, 1e-3 of the link size: 0.026 mm here)."""
    text = (Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml").read_text(encoding="utf-8")
    drawn = 'points_mm = { C = [35.0, 20.0], B = [18.7805, 39.0244] }'
    assert drawn in text
    path = tmp_path / "moved.toml"
    path.write_text(text.replace(drawn, f'points_mm = {{ C = [35.0, 20.0], B = [{18.7805 - moved_mm}, 39.0244] }}'),
                    encoding="utf-8")
    warnings = [w for w in config_warnings(load_config(path)) if w.startswith("mechanism.joints[")]
    if warned:
        assert warnings == ["mechanism.joints[B].connects: the drawn points rocker.B and coupler.B of revolute joint "
                            "'B' are 1 mm apart; the assembly closes the gap, so the links it joins are up to that "
                            "much off the drawing: draw the two points at the same place unless that is meant"]
    else:
        assert warnings == []


def test_a_mass_in_kg_where_g_was_meant_is_warned(tmp_path):
    """'mass = 4.71' (kg) for the coupler's 4.71 g passed every check: the simulation ran 15x slower with a radius of
    gyration of 0.37 mm on a 40 mm link. sqrt(I / m) = sqrt(628 g mm^2 / 4710 g) = 0.365 mm, 0.0091 of its size
    (39.96 mm), below the 0.02 a link's material allows; as drawn it is 0.29, a uniform bar's."""
    text = (Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml").read_text(encoding="utf-8")
    assert "mass_g = 4.71\n" in text
    path = tmp_path / "kg.toml"
    path.write_text(text.replace("mass_g = 4.71\n", "mass = 4.71\n"), encoding="utf-8")
    (warning,) = [w for w in config_warnings(load_config(path)) if w.startswith("mechanism.bodies[")]
    size = math.hypot(18.7805 - 10.0, 39.0244)
    assert warning == (f"mechanism.bodies[coupler]: its mass (4710 g) and inertia (628 g mm^2) give a radius of "
                       f"gyration of {math.sqrt(628 / 4710):.3g} mm, {math.sqrt(628 / 4710) / size:.2g} times its "
                       f"size ({size:.3g} mm; a uniform bar has 0.29): a unit slip? (a suffix gives the unit: mass_g, "
                       "inertia_g_mm2)")
    drawn = load_config(Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml")
    assert not [w for w in config_warnings(drawn) if w.startswith("mechanism.bodies[")]


def test_a_fit_given_by_its_letters_far_from_the_study_is_warned(tmp_path):
    """docs/design.md promises a warning for a fit whose mean lies beyond the population's reach; a fit given by its
    letters (its mean set by the ISO limits) was skipped, and the design chose H7/g6 on an extrapolation. H7/g6 at
    the example's 4 mm pin gives 7 um (ISO 286-2: hole 0/+12, shaft -4/-12 um, radial (4 + 24) / 4), 10.8 of the
    study's standard deviations below its 20 um."""
    example = Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml"
    path = tmp_path / "design.toml"
    path.write_text(f'extends = "{example.as_posix()}"\n[[design.targets]]\nreliability = 0.9\nlife_factor = 1.1\n'
                    '[[design.fit.options]]\nname = "IT7/IT6"\nhole_grade = "IT7"\nshaft_grade = "IT6"\ncost = 0.0\n'
                    '[[design.fit.options]]\nfit = "H7/g6"\ncost = 0.3\n', encoding="utf-8")
    cfg = load_config(path)
    (warning,) = [w for w in config_warnings(cfg) if w.startswith("design.fit.options[H7/g6]")]
    sigmas = (cfg.uncertainty.clearance.mean - 7e-6) / cfg.uncertainty.clearance.std
    assert warning.startswith(f"design.fit.options[H7/g6]: its mean (0.007 mm) lies {sigmas:.3g} of the study's "
                              "standard deviations from its mean of 'c' (0.02 mm)")


def test_a_config_without_a_wear_length_checks_and_takes_the_callers(tmp_path):
    """The tutorial's first stage (a mechanism and its clearance joints, no [wear] cycles and no R(N) curve) could
    not be checked, simulated or worn, even with --cycles: the wear length was a problem of every command."""
    from jointwear.cli import main_entry
    from jointwear.schema import ConfigError
    from jointwear.study import Study

    rig = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"
    cfg = load_config(rig)
    assert cfg.uncertainty is None and cfg.wear.cycles is None
    (warning,) = [w for w in Study(cfg, out=tmp_path / "c").check() if w.startswith("wear.cycles")]
    assert "the wear stage will need the number of cycles" in warning and "--cycles N" in warning
    for stage in ("wear", "run"):  # refused before anything is written
        with pytest.raises(ConfigError, match=r"^wear\.cycles: give the number of cycles"):
            getattr(Study(cfg, out=tmp_path / stage, echo=lambda s: None), stage)()
        assert not (tmp_path / stage).exists()
    assert main_entry(["wear", str(rig), "--cycles", "500", "--out", str(tmp_path / "cli")]) == 0
    assert (tmp_path / "cli" / "wear.json").is_file()


def test_a_block_as_long_as_the_history_is_warned():
    """block_cycles = 5,000,000 on the pump's 2,000,000-cycle history ran one straight block (its nominal life 4.5 %
    off the converged one) and converge's halved block, still longer than the history, read 'converged'."""
    base = load_config(Path(__file__).resolve().parents[2] / "examples" / "piston_pump.toml")
    n = base.wear.cycles or base.reliability.cycles_stop
    assert not [w for w in config_warnings(base) if w.startswith("wear.block_cycles")]
    (warning,) = [w for w in config_warnings(updated(base, {"wear.block_cycles": n}))
                  if w.startswith("wear.block_cycles")]
    assert warning.startswith(f"wear.block_cycles: {n:,} cycles is at least the nominal history's {n:,}")
    shorter = updated(base, {"wear.block_cycles": n - 1})
    assert not [w for w in config_warnings(shorter) if w.startswith("wear.block_cycles")]


def test_blocks_so_short_that_every_call_simulates_hours_are_warned():
    """block_cycles = 100 on the pump's 2,000,000-cycle history: 20,000 blocks of 3 simulated cycles each, minutes of
    dynamics per model call (hours over a study's calls), passed check in silence. The bound: 10,000 simulated cycles
    per history."""
    from jointwear.study.checks import LONG_HISTORY_SIMULATED_CYCLES

    base = load_config(Path(__file__).resolve().parents[2] / "examples" / "piston_pump.toml")
    n, per_block = base.wear.cycles or base.reliability.cycles_stop, base.wear.settle_cycles + base.wear.record_cycles
    (warning,) = [w for w in config_warnings(updated(base, {"wear.block_cycles": 100})) if w.startswith("wear.block")]
    assert warning.startswith(f"wear.block_cycles: 100 cycles makes the nominal history of {n:,} cycles "
                              f"{n // 100:,} blocks, which simulate {n // 100 * per_block:,.0f} cycles of dynamics")
    assert "minutes a call" in warning and "jointwear converge" in warning
    at_bound = math.ceil(n / (LONG_HISTORY_SIMULATED_CYCLES // per_block))  # a block short enough to stay quiet
    assert not [w for w in config_warnings(updated(base, {"wear.block_cycles": at_bound}))
                if w.startswith("wear.block_cycles")]


def test_a_general_linkage_left_free_by_a_missing_joint_is_warned():
    """A rocker-slider without its slider's prismatic joint passed check and simulated another mechanism; a pendulum
    (a body meant to swing under its load) gets the same warning, which says so."""
    from pathlib import Path

    from jointwear.study.checks import mobility_warnings

    rigs = Path(__file__).resolve().parents[1] / "wear" / "rigs"
    (warning,) = mobility_warnings(load_config(rigs / "pendulum.toml"))
    assert "keeps 1 degree of freedom after its drivers" in warning and "a joint is missing" in warning
    assert "`jointwear converge` measures that scatter" in warning  # uniform mode's depth depends on the start there
    assert mobility_warnings(load_config("watt_six_bar_two_clearances")) == []  # 3 x 5 - 2 x 7 - 1 driver = 0


@pytest.mark.parametrize("bearing_mm, warned", [(35.0, True), (5.5, True), (5.4, False), (5.025, False)])
def test_a_clearance_that_is_a_large_share_of_the_journal_radius_is_warned(bearing_mm, warned):
    """A 30 mm clearance (a bore of 35 mm radius on a 5 mm pin, larger than the crank) and one of 80 % of the radius
    passed check, and the linkage strayed 28 deg from its crank with ordinary-looking forces; 10 % of the radius is the
    bound (the rig's 0.5 % and 8.5 % pass, as Flores' benchmark's 5.3 % does)."""
    from jointwear.study.checks import clearance_size_warnings

    rig = load_config(str(Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"))
    loose = updated(rig, {"clearance_joints[A].bearing_radius_mm": bearing_mm,
                          "clearance_joints[A].bearing_outer_radius_mm": 2 * bearing_mm})
    warnings = clearance_size_warnings(loose)
    assert bool(warnings) == warned
    if warned:
        c = bearing_mm * 1e-3 - 4.975e-3
        assert warnings[0].startswith(f"clearance_joints.A: the radial clearance, {c * 1e3:.4g} mm")
        assert f"is {100 * c / 4.975e-3:.3g} % of the journal radius" in warnings[0]
        assert warnings[0] in config_warnings(loose)


@pytest.mark.parametrize("rocker_mm, warned", [(8.5, True), (12.0, False)])
def test_a_four_bar_whose_transmission_angle_leaves_30_to_150_deg_is_warned(rocker_mm, warned):
    """A near-limit linkage ran without a word at peaks of 1.4 kN. Exact: the flapping wing's crank 6, rod 38 mm and
    pivots 39.70 mm apart put the distance from crank pin to rocker pivot in [d - 6, d + 6]; with a rocker of 8.5 mm
    the law of cosines gives 152.4 deg at d + 6 (warned), with the preset's 12 mm 60.3-123.3 deg (quiet)."""
    import math

    from jointwear.study.checks import transmission_range, transmission_warnings

    cfg = updated(load_config(), {"mechanism.rocker.length_mm": rocker_mm})
    d = math.hypot(11.5, 38.0)
    angles = [math.degrees(math.acos((38.0**2 + rocker_mm**2 - ac**2) / (2 * 38.0 * rocker_mm)))
              for ac in (d - 6, d + 6)]
    assert transmission_range(cfg.mechanism) == pytest.approx((min(angles), max(angles)), rel=1e-9)
    warnings = transmission_warnings(cfg)
    assert bool(warnings) == warned
    if warned:
        assert warnings[0].startswith(f"mechanism: the transmission angle ranges over {min(angles):.3g}-"
                                      f"{max(angles):.3g} deg") and max(angles) > 150


def test_gravity_in_mm_per_s2_is_warned():
    from jointwear.study.checks import gravity_warnings

    base = load_config("watt_six_bar_two_clearances")
    assert gravity_warnings(base) == []
    (warning,) = gravity_warnings(updated(base, {"mechanism.gravity": (0.0, -9806.65)}))
    assert warning.startswith("mechanism.gravity: 9,806.65 m/s^2 is 1,000 g (a unit slip?")


def test_a_coordinates_mean_shift_is_said_to_depend_on_the_origin():
    """A rocker arm toleranced as its point D.y (55 mm from the origin) ranked first: x 1.2 moved D by 11 mm, 44 % of
    the arm C-D, and the rank would change with the origin."""
    from jointwear.study.sensitivity import coordinate_shift_sentence

    targets = {"arm": "mechanism.bodies.rocker.points.D.y", "c": "clearance_joints.B.clearance",
               "pivot": "mechanism.ground_points.C.x", "l1": "mechanism.crank.length"}
    assert coordinate_shift_sentence(targets, (0.8, 1.2)).startswith("arm and pivot are coordinates of the drawing: "
                                                                     "each mean x 0.8 / x 1.2 moves its point")
    assert coordinate_shift_sentence({"l1": "mechanism.crank.length"}, (0.8, 1.2)) == ""
    # a coordinate that scales a link is no origin's choice: the example's crank O-A is drawn from O = (0, 0) along
    # x, so A.x x 0.8 is the crank at 80 % (a designer's audit read the note on such a crank); its rocker's B.y and
    # its ground pivot C = (35, 20) mm are not on such an axis
    from jointwear.config import load_config as load

    mech = load(Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml").model_dump()["mechanism"]
    drawn = {"l_crank": "mechanism.bodies.crank.points.A.x", "arm": "mechanism.bodies.rocker.points.B.y",
             "pivot": "mechanism.ground_points.C.x"}
    assert coordinate_shift_sentence(drawn, (0.8, 1.2), mech).startswith("arm and pivot are coordinates")
    assert coordinate_shift_sentence({"l_crank": drawn["l_crank"]}, (0.8, 1.2), mech) == ""


@pytest.mark.parametrize("changes, warned", [
    ({}, None),                                                            # the pump's 8 mm pin at 8 mm
    ({"uncertainty.clearance.nominal_diameter": 2e-3}, "std 1.46 um"),     # the paper's 2 mm on an 8 mm pin
    ({"uncertainty.clearance.nominal_diameter": 8.5e-3}, None),            # same ISO 286 size range (6-10 mm)
])
def test_a_fit_taken_at_another_diameter_than_its_journals_is_warned(changes, warned):
    # ISO 286-2: IT7/IT6 are 15/9 um at 6-10 mm, 10/6 um at 1-3 mm: sigma_c = sqrt(T_D^2 + T_d^2) / 12 = 1.46 / 0.97 um
    pump = load_config(str(Path(__file__).resolve().parents[2] / "examples" / "piston_pump.toml"))
    notes = [w for w in config_warnings(updated(pump, changes)) if "nominal_diameter" in w]
    if warned is None:
        assert notes == []
    else:
        (note,) = notes
        assert "while the journal of clearance_joints.B is 8 mm in diameter" in note and warned in note
        assert "set nominal_diameter_mm = 8" in note


@pytest.mark.parametrize("old, new, start, words", [
    # the bushing's radii in metres under plain keys: a 4 m pin on a 40 mm linkage
    ("journal_radius_mm = 2.0", "journal_radius = 2.0", "clearance_joints[B]:", ["journal_radius 2,000 mm"]),
    # the coupler's centre of mass 10x off its drawing: hypot(143.90 - 18.78, 195.12 - 39.02) = 200.1 mm from its
    # nearer point B, on a 40 mm bar
    ("com_mm = [14.3902, 19.5122]", "com_mm = [143.902, 195.122]", "mechanism.bodies[coupler].com:",
     ["200.1 mm from the nearest of the body's points", "(40 mm)"]),
    # a 3 um bushing on a 4 mm pin (width / diameter 0.00075; pin joints run 0.25-2): it passed check, and the wear
    # stage reported tens of millimetres of wear without naming the width
    ("width_mm = 3.0", "width_um = 3.0", "clearance_joints[B]: width 0.003 mm", ["width_mm"]),
    # the pin, bore and wall 1000x too small: a 2 um pin on a 40 mm linkage
    ("journal_radius_mm = 2.0", "journal_radius_um = 2.0", "clearance_joints[B]: journal_radius 0.002 mm",
     ["less than 0.0001 of the mechanism's largest link"]),
])
def test_lengths_out_of_scale_with_the_drawing_are_warned(tmp_path, old, new, start, words):
    text = (Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml").read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "slip.toml"
    text = text.replace(old, new)
    for unit in ("", "_um"):  # keep the joint legal: the bore and the wall in the same unit
        if f"journal_radius{unit} = 2.0" in text:
            text = (text.replace("bearing_radius_mm = 2.02", f"bearing_radius{unit} = 2.02")
                    .replace("bearing_outer_radius_mm = 3.0", f"bearing_outer_radius{unit} = 3.0"))
    path.write_text(text, encoding="utf-8")
    (warning,) = [w for w in config_warnings(load_config(path)) if w.startswith(start)]
    assert all(word in warning for word in words), warning


def test_a_mechanism_that_does_not_run_names_the_unit_slip_first(tmp_path, monkeypatch):
    # an inertia in kg m^2 under a plain key (628 for 628 g mm^2) exhausts the step budget after 40 s: the error
    # stopped `check` before its warnings, so the gyration radius that says why was never shown
    import jointwear.mechanism as mechanism
    from jointwear.study.checks import check_runs

    def exhausted(*args, **kwargs):
        raise mechanism.SimulationError("step budget exhausted at t = 9.2e-06 s")

    monkeypatch.setattr(mechanism, "simulate", exhausted)
    text = (Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml").read_text(encoding="utf-8")
    path = tmp_path / "inertia.toml"
    path.write_text(text.replace("inertia_g_mm2 = 628.0", "inertia = 628.0"), encoding="utf-8")
    (problem,) = check_runs(load_config(path))
    assert "does not run: step budget exhausted" in problem
    assert "; check first mechanism.bodies[coupler]: its mass (4.71 g) and inertia (6.28e+11 g mm^2)" in problem
    drawn = load_config(Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml")
    assert "check first" not in check_runs(drawn)[0]


def test_a_nominal_history_that_ends_before_the_curve_is_warned():
    # the six-bar preset's wear.cycles (450k) inherited under a curve moved to 800k-2M: the nominal wear was that of
    # 450k cycles and the nominal life an extrapolation, in silence
    six = load_config("watt_six_bar_two_clearances")
    assert not [w for w in config_warnings(six) if w.startswith("wear.cycles")]
    moved = updated(six, {"reliability.cycles_start": 800_000, "reliability.cycles_stop": 2_000_000,
                          "reliability.cycles_step": 200_000, "reliability.histogram_cycles": [1_200_000],
                          "sensitivity.cycles": 1_200_000})
    (warning,) = [w for w in config_warnings(moved) if w.startswith("wear.cycles")]
    assert "ends at 450,000 cycles, before the R(N) curve's first level (800,000)" in warning
    assert "set wear.cycles = 2,000,000" in warning


def test_a_pin_radius_drawn_apart_from_a_clearance_that_holds_its_scatter_is_warned():
    """c = (D - d) / 2 already holds the pin's scatter: with R_j independent of c, the bore R_j + c scattered by
    3.70 um in the slider-crank instead of its IT8 grade's 2.75 um (33 um / 12)."""
    import numpy as np

    from jointwear.reliability import sample

    base = load_config("flores_slider_crank")
    independent = updated(base, {"uncertainty.correlation": None})
    (warning,) = config_warnings(independent)
    assert "bore radius R_j + c scatters by 3.7 um, not the hole grade's 2.75 um" in warning
    rho = float(warning.rsplit(", ", 1)[1].rstrip("]"))
    assert rho == pytest.approx(-1.75 / 3.2596, abs=1e-3)
    # the correlation it gives draws the bore with the hole grade's spread (4e5 samples: std to about 0.2 %)
    unc = updated(base, {"uncertainty.correlation": {"pairs": [["Rj", "c", rho]]}}).uncertainty
    x = sample(unc.marginals(), 400_000, seed=1, copula=unc.copula())
    names = unc.names()
    bore = x[:, names.index("Rj")] + x[:, names.index("c")]
    assert np.std(bore) == pytest.approx(33e-6 / 12, rel=0.01)


def test_a_target_the_curve_cannot_estimate_to_its_cov_is_warned_with_the_settings_it_needs():
    """R = 0.9999 with the defaults: Pf = 1e-4 lies below pf_floor = 1e-3, where the COV target is waived, and check
    said nothing; the user found the settings by hand."""
    base = load_config()
    (warning,) = config_warnings(updated(base, {"reliability.target_reliability": [0.9, 0.9999]}))
    cov = math.sqrt((1 - 1e-4) / (1e-4 * base.reliability.n_mc))  # COV^2 = (1 - Pf) / (n Pf) at the first population
    assert warning.startswith("reliability.target_reliability: the life at R = 0.9999 reads the curve at Pf = 0.0001")
    assert f"COV may reach {cov:.2g}" in warning and "n_mc_max >= 3,999,600" in warning
    tuned = {"reliability.target_reliability": [0.9, 0.9999], "reliability.pf_floor": 1e-4,
             "reliability.n_mc_max": 4_000_000}
    assert config_warnings(updated(base, tuned)) == []
    assert config_warnings(updated(base, {"reliability.target_reliability": 0.999})) == []  # 399,600 samples suffice
    # a target no population the config takes can read to its COV: the advice stays one the config takes (it said
    # 'n_mc_max >= 399,999,600', which the schema then refused); 1e8 samples read Pf = 1e-6 to a COV of 0.1
    (deep,) = config_warnings(updated(base, {"reliability.target_reliability": [0.9, 0.999999]}))
    assert "n_mc_max = 100,000,000 (the largest population, which reads it to a COV of 0.1;" in deep
    updated(base, {"reliability.target_reliability": [0.9, 0.999999], "reliability.pf_floor": 1e-6,
                   "reliability.n_mc_max": 100_000_000})


def test_every_reliability_setting_out_of_its_range_is_listed_at_once():
    """Only a section's first problem was told (max_calls = -3 beside target_reliability = 1.5 said nothing of the
    calls); n_initial = 1 passed every check and ended in the engine's traceback after the folder was written; a
    negative error tolerance, a COV target of 500 % and a probability floor of 2 passed without a word."""
    from jointwear.schema import ConfigError

    with pytest.raises(ConfigError) as err:
        updated(load_config(), {"reliability.max_calls": -3, "reliability.target_reliability": 1.5,
                                "reliability.n_initial": 1, "reliability.error_tol": -0.1,
                                "reliability.cov_target": 5.0, "reliability.pf_floor": 2.0})
    assert sorted(p.split(":")[0] for p in err.value.problems) == [
        "reliability.cov_target", "reliability.error_tol", "reliability.max_calls", "reliability.n_initial",
        "reliability.pf_floor", "reliability.target_reliability"]
    assert "reliability.n_initial: must be >= 2 (a Kriging needs two points to fit) (got 1)" in err.value.problems
    # the sensitivity and design sections too (each told its first problem only)
    with pytest.raises(ConfigError) as err:
        updated(load_config(), {"sensitivity.sobol_base_samples": 100, "sensitivity.surrogate_shift_limit": -1,
                                "design.refine_max_calls": -1, "design.verification_max_calls": -1})
    assert sorted(p.split(":")[0] for p in err.value.problems) == [
        "design.refine_max_calls", "design.verification_max_calls", "sensitivity.sobol_base_samples",
        "sensitivity.surrogate_shift_limit"]


def test_an_allowance_past_the_wall_is_refused_for_the_wear_stage_alone():
    """Without an [uncertainty] section (stages simulate, wear) an allowance of 0.0202 mm on a 0.008 mm wall passed
    check, though docs/cli.md says it is refused; the wear stage then drew an allowance the bushing cannot reach."""
    from jointwear.study.checks import config_problems

    base = load_config("jin2025_flapping_wing").model_copy(update={"uncertainty": None})
    walled = updated(base, {"clearance_joints.A.bearing_outer_radius_mm": 1.01, "reliability.allowance_mm": 0.0202})
    (problem,) = config_problems(walled, {"simulate", "wear"})
    assert problem.startswith("reliability.allowance: 0.0202 mm for joint A is not less than its bearing wall")
    assert config_problems(walled, {"simulate"}) == []
    assert config_problems(updated(walled, {"reliability.allowance_mm": 0.005}), {"simulate", "wear"}) == []


def test_a_static_friction_below_the_sliding_one_is_warned():
    """mu_d = 0.6 given alone kept the default mu_s = 0.15 in silence: friction then rises with the slip speed."""
    from jointwear.study.checks import friction_warnings

    base = load_config("jin2025_flapping_wing")
    (warning,) = friction_warnings(updated(base, {"clearance_joints.A.friction.mu_d": 0.6}))
    assert warning.startswith("clearance_joints.A.friction.mu_s: 0.15 is below mu_d = 0.6")
    assert warning in config_warnings(updated(base, {"clearance_joints.A.friction.mu_d": 0.6}))
    assert friction_warnings(base) == []
    assert friction_warnings(updated(base, {"clearance_joints.A.friction.mu_d": 0.6,
                                            "clearance_joints.A.friction.law": "none"})) == []
    # a sliding coefficient of 5 (a percentage or a typo) passed in silence; dry metals slide at 0.1-0.8
    high = friction_warnings(updated(base, {"clearance_joints.A.friction.mu_d": 5.0,
                                            "clearance_joints.A.friction.mu_s": 5.0}))
    assert high == ["clearance_joints.A.friction.mu_d: 5 is above 1, beyond a sliding friction coefficient of dry "
                    "metals (0.1-0.8); a percentage or a typo?"]
    assert friction_warnings(updated(base, {"clearance_joints.A.friction.mu_d": 1.0,
                                            "clearance_joints.A.friction.mu_s": 1.0})) == []


def test_a_contact_exponent_other_than_hertzs_is_refused_by_name():
    """exponent = 3 with Hertz's K (N/m^1.5) sank the reference pin 79 um into its 2 um clearance, in silence."""
    from jointwear.schema import ConfigError

    base = load_config("jin2025_flapping_wing")
    for bad in (1.0, 3.0, 1.4):
        with pytest.raises(ConfigError, match=r"exponent: must be 1.5: the contact stiffness K is Hertz's"):
            updated(base, {"clearance_joints.A.exponent": bad})
    assert updated(base, {"clearance_joints.A.exponent": 1.5}) == base


def test_a_standard_deviation_read_as_si_by_a_missing_suffix_is_warned():
    """`updated(cfg, {"uncertainty.variables[E_b].std": 12})` meant 12 GPa and set 12 Pa (a number without a suffix
    is SI): the modulus stopped varying, silently. A standard deviation below 1e-6 of its mean is warned; every
    preset's variables (the narrowest: a 1 um journal tolerance on 1 mm, 1e-3) are not."""
    from jointwear.study.checks import TINY_SCATTER, scatter_warnings

    base = load_config()
    slipped = updated(base, {"uncertainty.variables[E_b].std": 12.0, "uncertainty.variables[HB_b].std": 30.5})
    warnings = scatter_warnings(slipped)
    assert [w.split(":")[0] for w in warnings] == ["uncertainty.variables[E_b]", "uncertainty.variables[HB_b]"]
    assert "its standard deviation, 12 Pa, is 1e-10 of its mean (120 GPa)" in warnings[0]
    assert warnings[0] in config_warnings(slipped)
    above_the_bar = updated(base, {"uncertainty.variables[E_b].std_GPa": 1.01 * 120.0 * TINY_SCATTER})
    assert scatter_warnings(above_the_bar) == []
    for preset in available_presets():
        assert scatter_warnings(load_config(preset)) == [], preset
