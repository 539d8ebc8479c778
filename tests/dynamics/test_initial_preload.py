"""The preloaded start state on a worn bore: initial_state reads the profile as the kernel does, so the kernel finds
the journal pressed in by the static penetration (|R| / K)^(1/n) that the preload intended."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from jointwear.config import load_config
from jointwear.mechanism import build_model
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.kernel import O_DELTA, O_K
from jointwear.mechanism.simulate import Runner

RIG = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"


def test_preload_on_a_worn_bore_gives_the_static_penetration():
    model = build_model(load_config(str(RIG)))
    g0 = model.initial_geometry(n_grid=35)[0]
    # the journal rests at the top of the pendulum's eye, bearing-frame angle pi: midway between two cells of a
    # 35-cell grid, where a linear reading of this curved profile differs from the kernel's Catmull-Rom one by
    # about 0.15 um, 18 % of the static penetration (0.8 um)
    th = 2.0 * np.pi * np.arange(35) / 35
    pocket = 5e-6 * np.cos(2.0 * (th - np.pi)) ** 2
    geom = [dataclasses.replace(g0, use_profile=True, bearing_wear=pocket, journal_wear=np.zeros(35))]
    state = initial_state(model, 0.0, geometry=geom)
    run = Runner(model, geom, 1e-9, 1e-12)
    run.a["cstate"][:] = state.cstate
    run.eval(state.t, run.to_internal(state.y))
    delta = run.w["cout"][0, O_DELTA]

    cj = model.clearance_joints[0]
    q, qd, qdd = model.kinematics(0.0)
    fmag = float(np.hypot(*model.inverse_dynamics(0.0, q, qd, qdd)[cj.name]))
    kst = float(run.w["cout"][0, O_K])  # the stiffness the kernel used at the contact point
    expected = (fmag / kst) ** (1.0 / cj.spec.exponent)
    # the journal lies where the preload put it to the Newton tolerance of the assembly (1e-13 m on 1e-7 m); a
    # linear reading of the profile misplaces it by its interpolation error
    assert abs(delta - expected) < 1e-3 * expected
