"""Clearance joints: limit of zero clearance, energy conservation, regimes, trace conventions."""


from pathlib import Path

import numpy as np
import pytest

from jointwear.config import ClearanceJointConfig, load_config, updated
from jointwear.contact import ClearanceGeometry
from jointwear.contact.laws import friction_coefficient, hysteresis_factor
from jointwear.mechanism import (
    Body,
    ClearanceJoint,
    MechanismModel,
    SimulationState,
    build_model,
    simulate,
)
from jointwear.mechanism.simulate import trapezoid_weights


def _ideal_mean_reaction(model, joint):
    ri = simulate(model.ideal(), 1, settle_cycles=0, rtol=1e-10, atol=1e-13)
    w = trapezoid_weights(ri.t)
    return float(np.sum(w * np.hypot(*ri.reaction(joint).T)) / w.sum())


@pytest.fixture(scope="module")
def fw_result():
    model = build_model(load_config("jin2025_flapping_wing"))
    return model, simulate(model, 2, settle_cycles=1)


def test_clearance_to_zero_matches_ideal_reaction():
    """c = 1 nm: below the static elastic approach (~5 nm at 30 mN), so the journal never leaves
    the wall and the joint behaves as an ideal pin; frictionless so that the ideal joint is the limit."""
    cfg = load_config("jin2025_flapping_wing")
    cj = cfg.clearance_joints[0]
    cfg = updated(cfg, {"clearance_joints.0.bearing_radius": cj.journal_radius + 1e-9,
                        "clearance_joints.0.friction.law": "none"})
    model = build_model(cfg)
    res = simulate(model, 1, settle_cycles=1)
    tr = res.joints[0]
    ideal = _ideal_mean_reaction(model, "A")
    assert tr.contact_fraction == pytest.approx(1.0)
    # 2 %: issue 2 acceptance (measured 0.2 %)
    assert tr.mean_force == pytest.approx(ideal, rel=0.02)


def test_flapping_wing_nominal(fw_result):
    """Preset: near-continuous contact, mean force close to the ideal mean reaction (29.0 mN here against an
    ideal 28.1 mN; the issue's quick check model gave ~29 mN with the same reading)."""
    model, res = fw_result
    tr = res.joints[0]
    assert tr.contact_fraction > 0.9
    ideal = _ideal_mean_reaction(model, "A")
    assert 0.02 < tr.mean_force < 0.05
    assert tr.mean_force == pytest.approx(ideal, rel=0.05)  # 5 %: the contact vibration adds ~3 % (session 4)
    assert tr.contact_force.max() > tr.mean_force
    assert res.steps_per_cycle > 1000


def test_trace_conventions(fw_result):
    _model, res = fw_result
    tr = res.joints[0]
    assert tr.duration == pytest.approx(res.n_cycles * res.period, rel=1e-12)
    assert np.all(tr.force_normal >= 0.0)
    assert np.all(tr.force_normal[~tr.in_contact] == 0.0)
    assert np.all((tr.theta_bearing >= 0) & (tr.theta_bearing < 2 * np.pi))
    # |e| = clearance + penetration
    np.testing.assert_allclose(np.hypot(*tr.eccentricity.T), tr.clearance_used + tr.penetration, rtol=0, atol=1e-15)
    # theta_bearing is the direction of the eccentricity in the bearing frame
    ang = np.mod(np.arctan2(tr.eccentricity[:, 1], tr.eccentricity[:, 0]), 2 * np.pi)
    d = np.angle(np.exp(1j * (ang - tr.theta_bearing)))
    assert np.max(np.abs(d)) < 1e-9
    # the rod is the bearing body: its global angle is recorded
    i = res.body_names.index("rod")
    np.testing.assert_allclose(tr.bearing_body_angle, res.body_angles[:, i])
    assert res.crank_angle.min() >= 0 and res.crank_angle.max() < 2 * np.pi
    assert tr.joint.bearing_material.youngs_modulus == 120e9
    assert tr.joint.journal_material.hardness == pytest.approx(207 * 9.807e6)


def test_continue_from_state_end(fw_result):
    model, res = fw_result
    res2 = simulate(model, 0.5, settle_cycles=0, state0=res.state_end)
    assert res2.t[0] == pytest.approx(res.t[-1])
    # the state passes through Cartesian coordinates (angles, cos/sin): positions of ~0.04 m come back to a few
    # ulp (~1e-17 m), i.e. ~1e-9 of the ~8 nm penetration and ~2e-9 of the force (F ~ delta^1.5)
    assert res2.joints[0].force_normal[0] == pytest.approx(res.joints[0].force_normal[-1], rel=1e-8)


def test_uniform_profile_equals_clearance_growth():
    """use_profile with h_b = h_j = g/2 everywhere is the same geometry as clearance_growth = g."""
    model = build_model(load_config("jin2025_flapping_wing"))
    g = 0.5e-6
    a = ClearanceGeometry(1.002e-3, 1e-3, clearance_growth=g)
    b = ClearanceGeometry(1.002e-3, 1e-3, 0.0, np.full(360, g / 2), np.full(90, g / 2), use_profile=True)
    ra = simulate(model, 0.25, geometry=[a], settle_cycles=0)
    rb = simulate(model, 0.25, geometry=[b], settle_cycles=0)
    assert ra.joints[0].clearance_used == pytest.approx(2.5e-6)
    np.testing.assert_allclose(ra.joints[0].stiffness, rb.joints[0].stiffness, rtol=1e-12)
    n = min(ra.t.size, rb.t.size, 200)
    np.testing.assert_allclose(ra.joints[0].force_normal[:n], rb.joints[0].force_normal[:n], rtol=1e-6, atol=1e-9)


def test_worn_profile_moves_contact():
    """A local pit on the bearing lets the journal go deeper there (profile read in the bearing frame)."""
    model = build_model(load_config("jin2025_flapping_wing"))
    base = simulate(model, 1, settle_cycles=0)
    tr = base.joints[0]
    prof = np.zeros(360)
    prof[:] = 1e-6  # uniform 1 um bearing wear
    geo = ClearanceGeometry(1.002e-3, 1e-3, 0.0, prof, np.zeros(360), use_profile=True)
    worn = simulate(model, 1, geometry=[geo], settle_cycles=0)
    assert np.median(np.hypot(*worn.joints[0].eccentricity.T)) > np.median(np.hypot(*tr.eccentricity.T)) + 0.9e-6


def _free_journal_model(restitution=1.0, law="lankarani_nikravesh"):
    steel = dict(name="steel", youngs_modulus=207e9, poissons_ratio=0.3, hardness=200 * 9.807e6,
                 wear_coefficient=1e-4)
    ball = Body("journal", 1e-3, 1e-8, {"O": (0.0, 0.0)})
    spec = ClearanceJointConfig(name="J", joint="J", bearing_body="ground", journal_body="journal",
                                bearing_radius=1.1e-3, journal_radius=1.0e-3, width=1e-3, bearing_material=steel,
                                journal_material=steel, contact_law=law, restitution=restitution,
                                friction={"law": "none"})
    cj = ClearanceJoint(spec, bearing_point="O", journal_point="O")
    model = MechanismModel(bodies=[ball], joints=[], clearance_joints=[cj], ground_points={"O": (0.0, 0.0)},
                           gravity=(0.0, 0.0), period_override=1.0, length_ref=1e-3)
    return model


def test_energy_conserved_frictionless_elastic():
    """Free journal in a fixed bearing, cr = 1, no friction, no driver: 10 s with hundreds of impacts."""
    model = _free_journal_model()
    y0 = np.array([0.0, 0.0, 0.0, 0.012, 0.0071, 3.0])
    st = SimulationState(0.0, y0, np.zeros((1, 2)), 0.0)
    res = simulate(model, 10, settle_cycles=0, state0=st, rtol=1e-10, atol=1e-14)
    tr = res.joints[0]
    m, inertia = 1e-3, 1e-8
    ke = 0.5 * m * (res.qd[:, 0] ** 2 + res.qd[:, 1] ** 2) + 0.5 * inertia * res.qd[:, 2] ** 2
    pe = np.where(tr.penetration > 0, tr.stiffness * np.clip(tr.penetration, 0, None) ** 2.5 / 2.5, 0.0)
    e = ke + pe
    assert tr.n_impacts > 300
    # 1e-4 of the kinetic energy: issue 2 acceptance
    drift = np.max(np.abs(e - e[0])) / ke[0]
    print(f"energy drift {drift:.3g} over {tr.n_impacts} impacts, {res.n_steps} steps")
    assert drift < 1e-4


def test_restitution_dissipates():
    model = _free_journal_model(restitution=0.8)
    st = SimulationState(0.0, np.array([0.0, 0.0, 0.0, 0.012, 0.0071, 0.0]), np.zeros((1, 2)), 0.0)
    res = simulate(model, 0.2, settle_cycles=0, state0=st)
    v = np.hypot(res.qd[:, 0], res.qd[:, 1])
    assert res.joints[0].n_impacts >= 2
    assert v[-1] < 0.9 * v[0]


def test_slider_crank_regimes():
    """Flores benchmark: free flight, impacts and following of the bearing wall; slider acceleration spikes."""
    cfg = load_config("flores_slider_crank")
    model = build_model(cfg)
    # 4 cycles: the motion is not periodic (cycles range from continuous following to 13 impacts)
    res = simulate(model, 4, settle_cycles=1)
    ideal = simulate(model.ideal(), 1, settle_cycles=0)
    tr = res.joints[0]
    free_flight = 1.0 - tr.contact_fraction
    assert free_flight > 0.02  # measured 0.03-0.25 per cycle
    assert tr.n_impacts >= 4  # measured 0-14 per cycle
    # following: a contact phase lasting more than 10 % of a cycle
    longest, start = 0.0, None
    for i, c in enumerate(tr.in_contact):
        if c and start is None:
            start = i
        elif not c and start is not None:
            longest = max(longest, tr.t[i] - tr.t[start])
            start = None
    assert longest > 0.1 * res.period
    a = np.abs(res.body_acceleration("slider")[:, 0])
    a_ideal = np.abs(ideal.body_acceleration("slider")[:, 0])
    assert a.max() > 3.0 * a_ideal.max()  # measured ~10x (Flores et al. 2006 show spikes of this order)
    # spikes coincide with contact
    assert tr.in_contact[np.argmax(a)]


def test_contact_law_switch():
    assert hysteresis_factor(0, 0.9, 1.0) == pytest.approx(3 * (1 - 0.81) / 4)
    assert hysteresis_factor(1, 0.9, 1.0) == pytest.approx(8 * 0.1 / (5 * 0.9))
    assert hysteresis_factor(2, 0.9, 1.0) == pytest.approx(3 * 0.1 / 2)
    cfg = updated(load_config("jin2025_flapping_wing"), {"clearance_joints.0.contact_law": "flores"})
    res = simulate(build_model(cfg), 1, settle_cycles=1)
    # same mean load path: the law changes only the damping (chi 0.178/v0 vs 0.1425/v0 at cr = 0.9)
    assert 0.028 < res.joints[0].mean_force < 0.036


def test_friction_law_shape():
    mu_d, mu_s, vs, vd = 0.1, 0.15, 1e-4, 1e-3
    f = lambda v: friction_coefficient(v, mu_d, mu_s, vs, vd)
    assert f(0.0) == 0.0
    assert f(vs) == pytest.approx(mu_s) and f(-vs) == pytest.approx(-mu_s)
    assert f(vd) == pytest.approx(mu_d) and f(1.0) == mu_d and f(-1.0) == -mu_d
    v = np.linspace(-2e-3, 2e-3, 4001)
    mu = np.array([f(x) for x in v])
    # continuous: steepest slope is 3 mu_s / (2 v_s) = 2250 s/m at v = 0, times the grid step 1e-6 m/s
    assert np.max(np.abs(np.diff(mu))) < 2.3e-3
    np.testing.assert_allclose(mu, -mu[::-1], atol=1e-15)  # odd


def test_configs_are_frozen_and_updated_revalidates():
    """A validated config cannot be changed in place; a changed copy (config.updated) is validated again."""
    from jointwear.config import ConfigError

    cfg = load_config("jin2025_flapping_wing")
    with pytest.raises(AttributeError, match=r"^a validated config is read-only \(ClearanceJointConfig.journal_radius "
                                             r"cannot be set\): make a changed, validated copy with "
                                             r"jointwear.updated\(config, \{'<path>.journal_radius'"):
        cfg.clearance_joints[0].journal_radius = 1.003e-3
    assert cfg.clearance_joints[0].journal_radius == 1e-3
    with pytest.raises(ConfigError, match="rod .* and rocker .* cannot close the loop"):
        updated(cfg, {"mechanism.rocker_pivot": (0.0115, 0.08)})
    # the sensitivity's rod x 0.8: Grashof's sum named with the lengths of the preset (6, 38 x 0.8, 12, 39.702 mm)
    with pytest.raises(ConfigError, match=r"shortest \+ longest, here 45.702 mm, stays below the other two, here "
                                          r"42.4 mm"):
        updated(cfg, {"mechanism.rod.length": 0.8 * cfg.mechanism.rod.length})
    with pytest.raises(ConfigError, match=r"clearance_joints\[A\].journal_radius"):
        updated(cfg, {"clearance_joints.0.journal_radius": 1.003e-3})
    with pytest.raises(ConfigError, match="no such setting"):
        updated(cfg, {"clearance_joints.3.journal_radius": 1e-3})
    # named items and TOML's unit suffixes, as in a variable's target; the suffixed key replaces the SI one
    own = load_config(Path(__file__).parents[2] / "examples" / "my_linkage.toml")
    changed = updated(own, {"clearance_joints.B.friction.mu_d": 0.2, "reliability.allowance_mm": 0.004,
                            "uncertainty.variables.HB_b.std_HB": 6.0, "mechanism.bodies.crank.mass_g": 2.0})
    assert changed.clearance_joints[0].friction.mu_d == 0.2 and changed.reliability.allowance == pytest.approx(4e-6)
    hb = next(v for v in changed.uncertainty.variables if v.name == "HB_b")
    assert hb.std == pytest.approx(6.0 * 9.807e6) and changed.mechanism.bodies[0].mass == pytest.approx(2e-3)
    with pytest.raises(ConfigError, match=r"clearance_joints.Z.friction.mu_d: no such setting \(clearance_joints has "
                       r"no item 'Z'; its items: B\)"):
        updated(own, {"clearance_joints.Z.friction.mu_d": 0.2})
    # every path a target takes: a point's coordinate, a joint's derived clearance
    moved = updated(own, {"mechanism.bodies.crank.points.A.y": 1e-4, "clearance_joints.B.clearance": 3e-6})
    assert moved.mechanism.bodies[0].points["A"] == (own.mechanism.bodies[0].points["A"][0], 1e-4)
    cj = moved.clearance_joints[0]
    assert cj.journal_radius == own.clearance_joints[0].journal_radius
    assert cj.bearing_radius - cj.journal_radius == pytest.approx(3e-6, rel=1e-9)
    # ... with a unit suffix too, and from a preset name (both were refused)
    suffixed = updated(own, {"mechanism.bodies.crank.points.A.y_mm": 0.1, "clearance_joints.B.clearance_um": 3.0})
    assert suffixed.mechanism.bodies[0].points["A"] == pytest.approx(moved.mechanism.bodies[0].points["A"], rel=1e-12)
    assert suffixed.clearance_joints[0].bearing_radius == pytest.approx(cj.bearing_radius, rel=1e-12)
    with pytest.raises(ConfigError, match=r"clearance_joints.B.clearance_deg: clearance is in m"):
        updated(own, {"clearance_joints.B.clearance_deg": 3.0})
    assert updated("jin2025_flapping_wing", {"reliability.n_mc": 1000}).reliability.n_mc == 1000
    with pytest.raises(TypeError, match="changes must be a mapping"):
        updated(cfg, [("reliability.n_mc", 1000)])


@pytest.mark.parametrize("amp", [0.0, 2e-6, 2e-5])
def test_energy_conserved_with_worn_profile(amp):
    """Worn (non-circular) bearing, cr = 1, frictionless: the normal force derives from the potential
    K delta^(n+1)/(n+1) of delta = |e| - c_loc(theta), so energy is conserved through impacts."""
    model = _free_journal_model()
    th = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    geo = [ClearanceGeometry(1.1e-3, 1e-3, 0.0, amp * (1 + np.cos(2 * th)), np.zeros(720), use_profile=True)]
    st = SimulationState(0.0, np.array([0.0, 0.0, 0.0, 0.012, 0.0071, 3.0]), np.zeros((1, 2)), 0.0)
    res = simulate(model, 2, geometry=geo, settle_cycles=0, state0=st, rtol=1e-10, atol=1e-14)
    tr = res.joints[0]
    ke = 0.5e-3 * (res.qd[:, 0] ** 2 + res.qd[:, 1] ** 2) + 0.5e-8 * res.qd[:, 2] ** 2
    assert tr.n_impacts > 100
    # kinetic energy after 2 s of impacts: 3e-4 (the stiffness K follows the local radii, which the
    # potential ignores, so each impact gains or loses up to dK/K ~ 10 % of its small elastic share; the sum
    # depends on where the >100 impacts land: measured 2e-6 at 2 um, and at 20 um of profile amplitude 3e-5 with
    # linear and 1.4e-4 with the C1 (Catmull-Rom) interpolation of the profile)
    assert abs(ke[-1] - ke[0]) / ke[0] < 3e-4


def test_model_and_result_pickle():
    """Models and results cross process boundaries (compute stage)."""
    import pickle

    model = build_model(load_config("jin2025_flapping_wing"))
    res = simulate(model, 0.05, settle_cycles=0)
    res2 = pickle.loads(pickle.dumps(res))
    np.testing.assert_array_equal(res2.q, res.q)
    np.testing.assert_array_equal(res2.joints[0].force_normal, res.joints[0].force_normal)
    model2 = pickle.loads(pickle.dumps(model))
    np.testing.assert_allclose(model2.kinematics(0.01)[0], model.kinematics(0.01)[0])
