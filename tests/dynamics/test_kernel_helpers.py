"""Small pieces of the step loop and of the result packaging, against their direct forms."""

import math
from pathlib import Path

import numpy as np
import pytest

from jointwear.config import load_config
from jointwear.mechanism import build_model, radau, simulate
from jointwear.mechanism import kernel as K
from jointwear.mechanism.fast import to_cartesian, to_cartesian_point
from jointwear.mechanism.simulate import Runner, wrap_2pi

RIG = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"


@pytest.mark.parametrize("th0", [0.0, 1.0, -2.5, 3.14159, 1234.5678])
def test_crank_rotation_equals_cos_sin(th0):
    """cos/sin of th0 + d by rotation: the Taylor branch (|d| <= 0.05) and the direct branch agree with math.cos/sin
    to rounding (a few ulp of values <= 1: 4e-16 bound; the series' truncation is < 1e-17)."""
    c0, s0 = math.cos(th0), math.sin(th0)
    for d in np.concatenate([np.linspace(-0.05, 0.05, 41), [1e-12, -3e-9, 0.0499999, 0.0500001, 0.3, -1.7]]):
        c, s = K.crank_rotation(c0, s0, d)
        assert abs(c - math.cos(th0 + d)) < 4e-16 * (1 + abs(th0)), (th0, d)
        assert abs(s - math.sin(th0 + d)) < 4e-16 * (1 + abs(th0)), (th0, d)


def test_wrap_2pi_range_and_agreement_with_mod():
    rng = np.random.default_rng(1)
    two_pi = 2 * math.pi
    k = np.arange(-40, 40) * two_pi
    x = np.concatenate([rng.normal(0, 200, 20_000), k, np.nextafter(k, -np.inf), np.nextafter(k, np.inf),
                        [-1e-300, -1e-20, 0.0, -0.0, 1e-20]])
    r = wrap_2pi(x.copy())
    assert r.min() >= 0.0 and r.max() < two_pi
    d = np.abs(r - np.mod(x, two_pi))
    d = np.minimum(d, two_pi - d)  # 0 and 2 pi are the same angle
    assert np.all(d <= 4 * np.spacing(np.maximum(np.abs(x), two_pi)))  # a few ulp of x


def test_end_state_point_conversion_equals_array_form():
    model = build_model(load_config("jin2025_flapping_wing"))
    res = simulate(model, 0.3, settle_cycles=0)
    run = Runner(model, None, 1e-6, 1e-9)
    y = run.to_internal(res.state_end.y)
    ref = {b.name: float(res.state_end.y[3 * i + 2]) + 2 * math.pi for i, b in enumerate(model.free_bodies)}
    q1, qd1, _ = to_cartesian(model, run.lay, y[None, :], None, ref)
    q2, qd2 = to_cartesian_point(model, run.lay, y, ref)
    np.testing.assert_allclose(q2, q1[0], rtol=0, atol=1e-15)  # same formulas, scalar libm vs numpy
    np.testing.assert_allclose(qd2, qd1[0], rtol=1e-13, atol=1e-16)


def test_eccentricity_in_the_bearing_frame():
    """|e| is frame-independent, and its direction in the bearing frame is theta_bearing."""
    model = build_model(load_config("jin2025_flapping_wing"))
    tr = simulate(model, 0.2, settle_cycles=0).joints[0]
    e = tr.eccentricity
    np.testing.assert_allclose(np.hypot(e[:, 0], e[:, 1]), np.hypot(*tr.eccentricity_global.T), rtol=1e-12)
    ang = np.mod(np.arctan2(e[:, 1], e[:, 0]) - tr.theta_bearing + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(ang)) < 1e-9


def test_step_loops_compile_without_reference_counting():
    """The step loops allocate nothing; with numba's reference counting every inlined evaluation costs ~24
    atomic operations, 2x the time per cycle (benchmarks/dynamics.py)."""
    assert K.STEP_LOOP_NRT is False
    for fn in (*K.INTEGRATORS, K.rhs, K.rhs_fourbar_cs, *radau.RADAU_INTEGRATORS, radau.rhs_cartesian_row,
               radau.rhs_natural_fourbar_row):
        assert fn.targetoptions.get("_nrt") is False, fn


def test_dormand_prince_tableau_satisfies_the_order_conditions():
    """Row sums equal c; b of order 5 and the embedded b - e of order 4 (the 17 rooted-tree conditions up to order 5,
    Hairer, Norsett & Wanner I, Table II.2.2); exact rational conditions, so rounding level (1e-14)."""
    a, c, e = K.DP_A, K.DP_C, K.DP_E
    assert np.max(np.abs(a.sum(axis=1) - c)) < 1e-14
    assert c[5] == c[6] == 1.0  # the step loop evaluates stages 5 and 6 at t + h

    def conditions(b):
        ac = a @ c
        return [b.sum() - 1, b @ c - 1 / 2, b @ c**2 - 1 / 3, b @ ac - 1 / 6, b @ c**3 - 1 / 4, b @ (c * ac) - 1 / 8,
                b @ (a @ c**2) - 1 / 12, b @ (a @ ac) - 1 / 24, b @ c**4 - 1 / 5, b @ (c**2 * ac) - 1 / 10,
                b @ ac**2 - 1 / 20, b @ (c * (a @ c**2)) - 1 / 15, b @ (a @ c**3) - 1 / 20, b @ (c * (a @ ac)) - 1 / 30,
                b @ (a @ (c * ac)) - 1 / 40, b @ (a @ (a @ c**2)) - 1 / 60, b @ (a @ (a @ ac)) - 1 / 120]

    b = a[6]  # FSAL: the last row holds the weights
    assert max(abs(x) for x in conditions(b)) < 1e-14
    low = conditions(b - e)
    assert max(abs(x) for x in low[:8]) < 1e-14
    assert max(abs(x) for x in low[8:]) > 1e-6  # the embedded formula is of order 4, not 5


def _benchmark_module():
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "dynamics.py"
    spec = importlib.util.spec_from_file_location("benchmark_dynamics", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("preset,worn,fast", [("jin2025_flapping_wing", False, None), ("jin2025_flapping_wing", True, None),
                                              ("watt_six_bar_two_clearances", True, None),
                                              ("watt_six_bar_two_clearances", True, False)])
def test_python_source_of_the_kernels_equals_the_compiled_kernels(preset, worn, fast):
    """benchmarks/dynamics.py compares with scipy on the kernels' own Python source (numba bypassed); that source
    must run and give the compiled kernel's derivatives (and would catch a compiled function the bypass misses:
    numba refuses a Python function as an argument). States along a trajectory, in contact, worn profiles or not.
    Tolerance: the compiled four-bar kernel reassociates and contracts to FMA (kernel.FASTMATH), i.e. a few ulp per
    operation, which the 2x2 constraint solve and the contact stiffness amplify; 1e-9 of the largest derivative
    component leaves a margin of >1e3 over what was measured (<1e-12)."""
    import dataclasses

    bench = _benchmark_module()
    model = build_model(load_config(preset))
    geom = model.initial_geometry()
    if worn:
        n = geom[0].bearing_wear.size
        th = 2 * np.pi * np.arange(n) / n
        geom = [dataclasses.replace(g, bearing_wear=2e-6 * np.maximum(0, np.cos(th - 2.2)) ** 2,
                                    journal_wear=1e-6 * np.maximum(0, np.cos(th + 1.0)) ** 2, use_profile=True)
                for g in geom]
    res = simulate(model, 0.05, geometry=geom, settle_cycles=0, fast=fast)
    run = Runner(model, geom, 1e-6, 1e-9, fast)
    assert run.mode == {("jin2025_flapping_wing", None): 1, ("watt_six_bar_two_clearances", None): 2}.get((preset, fast), 0)
    a = run._args()
    states = [run.to_internal(np.concatenate([res.q[i], res.qd[i]])) for i in range(0, res.t.size, res.t.size // 7)]
    assert np.any(res.joints[0].in_contact)
    for t, y in zip(res.t[::res.t.size // 7], states):
        out = []
        for bypass in (False, True):
            dy = np.zeros((7, run.ny))
            with bench.numba_bypassed() if bypass else _nothing():
                assert hasattr(K.clearance_contact, "py_func") is not bypass  # compiled, or its Python source
                # compiled: the copies the record's evaluation calls (the same source, compiled on their own, cached
                # by the simulation above; the inlined originals compiled alone cost ~24 s here)
                fourbar, tree = (K.rhs_fourbar, K.rhs_tree) if bypass else (K.rhs_fourbar_called, K.rhs_tree_called)
                if run.mode == 1:
                    fourbar(t, y[None, :], 0, dy, 0, a[3], a[5], *a[6:12], a[18], a[20])
                elif run.mode == 2:  # tree kernel: base cos/sin at (t, y), then the evaluation there
                    K.tree_base(t, y, a[4], a[3], a[12], a[13], a[14])
                    tree(t, 0.0, y, y, dy, 0, *a[0:11], *a[12:21])
                else:
                    K.rhs(t, y, dy, 0, *a)
            out.append(dy[0])
        assert hasattr(K.rhs, "py_func") and hasattr(K.rhs_fourbar, "py_func")  # restored on exit
        # the tree kernel rebuilds the positions through the joint chain, so its rounding (~1e-17 m of ~50 mm links,
        # FMA-contracted when compiled) reaches the ~25 nm penetration: ~5e-10 of the contact force (measured 2e-10),
        # which the near-balance of contact force and load on the light output amplifies to 1.7e-8 of the largest
        # derivative (measured): 1e-7
        tol = 1e-7 if run.mode == 2 else 1e-9
        np.testing.assert_allclose(out[1], out[0], rtol=0, atol=tol * np.max(np.abs(out[0])))


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def test_profile_sides_read_only_worn_sides():
    """kernel_arrays marks the sides whose profile the contact reads: none on a round joint, the worn ones in profile
    mode, and the bearing's (zero) profile when nothing is worn yet."""
    import dataclasses

    from jointwear.mechanism.model import profile_sides

    g = build_model(load_config(str(RIG))).initial_geometry()[0]
    worn = np.linspace(0.0, 1e-6, g.bearing_wear.size)
    assert profile_sides(g) == 0
    assert profile_sides(dataclasses.replace(g, bearing_wear=worn)) == 0  # uniform mode reads no profile
    cases = {(False, False): K.PROF_BEARING, (True, False): K.PROF_BEARING, (False, True): K.PROF_JOURNAL,
             (True, True): K.PROF_BEARING | K.PROF_JOURNAL}
    for (b, j), bits in cases.items():
        gg = dataclasses.replace(g, use_profile=True, bearing_wear=worn if b else 0 * worn,
                                 journal_wear=worn if j else 0 * worn)
        assert profile_sides(gg) == bits, (b, j)


def test_skipping_a_round_side_is_exact():
    """A side whose profile is zero everywhere contributes exactly 0 to the local clearance and to the normal's slope,
    so reading it or not gives bit-identical derivatives (general kernel, states along a worn-bearing trajectory of
    the pendulum rig)."""
    import dataclasses

    from jointwear.mechanism.model import profile_sides

    model = build_model(load_config(str(RIG)))
    g = model.initial_geometry()[0]
    n = g.bearing_wear.size
    th = 2 * np.pi * np.arange(n) / n
    geom = [dataclasses.replace(g, use_profile=True, bearing_wear=2e-5 * np.maximum(0.0, -np.cos(th)) ** 2)]
    assert profile_sides(geom[0]) == K.PROF_BEARING
    res = simulate(model, 0.05, geometry=geom, settle_cycles=0, fast=False)
    assert np.all(res.joints[0].in_contact)
    run = Runner(model, geom, 1e-6, 1e-9, False)
    a = run._args()
    cint = a[6]
    for i in range(0, res.t.size, max(1, res.t.size // 5)):
        y = run.to_internal(np.concatenate([res.q[i], res.qd[i]]))
        out = []
        for bits in (K.PROF_BEARING, K.PROF_BEARING | K.PROF_JOURNAL):
            cint[0, K.CI_PROF] = bits
            dy = np.zeros((7, run.ny))
            K.rhs(res.t[i], y, dy, 0, *a)
            out.append(dy[0].copy())
        np.testing.assert_array_equal(out[0], out[1])


def test_cartesian_rhs_satisfies_the_baumgarte_stabilised_constraint():
    """The general kernel's accelerations satisfy J qdd = gamma - 2 alpha Phidot - beta^2 Phi (kernel.py docstring;
    gamma = -rest) at a state off the constraint manifold (Phi ~ 1e-6 m, Phidot ~ 1e-2 m/s); guards a damping term
    alpha Phidot (off by ~1 here). Tolerance: rounding of the block LDL^T solve, a few ulp of the largest product
    |J| |qdd| summed per row (measured < 1e-16 of it); 1e-10 of that scale."""
    model = build_model(load_config("watt_six_bar_two_clearances"))
    geom = model.initial_geometry()
    res = simulate(model, 0.02, geometry=geom, settle_cycles=0, fast=False)
    run = Runner(model, geom, 1e-6, 1e-9, False)
    assert run.mode == 0  # the Cartesian kernel K.rhs
    a = run._args()
    nq = 3 * a[0]
    i = res.t.size // 2
    y = run.to_internal(np.concatenate([res.q[i], res.qd[i]])).copy()
    rng = np.random.default_rng(1)
    y[:nq] += 1e-6 * rng.standard_normal(nq)
    y[nq:] += 1e-2 * rng.standard_normal(nq)
    dy = np.zeros((7, run.ny))
    K.rhs(res.t[i], y, dy, 0, *a)
    alpha, beta = a[11]
    phi, phid, rest, jac = a[13], a[14], a[15], a[16]
    assert np.max(np.abs(phi)) > 1e-7 and np.max(np.abs(alpha * phid)) > 0.1  # the stabilisation terms matter
    qdd = dy[0, nq:2 * nq]
    scale = np.max(np.abs(jac) @ np.abs(qdd))
    np.testing.assert_allclose(jac @ qdd, -rest - 2.0 * alpha * phid - beta ** 2 * phi, rtol=0, atol=1e-10 * scale)
