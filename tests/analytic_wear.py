"""An analytic wear model with the structure of Archard's law, for tests that need the exact R(N).

delta_max(x, N) = RATE * N * (k_b / k_b0) * (H_b0 / H_b) * (1 + 0.05 (c - c0) / 1 um): the wear depth is proportional
to k / H and to the number of cycles, so the exact reliability follows from brute-force Monte Carlo.
"""

import tomllib
from importlib import resources

import numpy as np

RATE = 7.1e-11  # m per cycle at the nominal point: the paper's mean slope (paper-notes: 7.1e-8 mm/cycle)
ALLOWANCE = 3e-5  # the flapping-wing preset's allowance, m


class AnalyticWear:
    """The true-model stand-in: ``(x) -> (wear at each of cycles, "ok")``; ``scale(x)`` and ``life(x)`` in closed
    form."""

    def __init__(self, names, cycles):
        self.i_k, self.i_h, self.i_c = names.index("k_b"), names.index("HB_b"), names.index("c")
        self.cycles = np.asarray(cycles, dtype=float)

    @property
    def inputs(self) -> tuple[int, int, int]:
        """The columns of x the model reads (k_b, HB_b, c)."""
        return self.i_k, self.i_h, self.i_c

    def scale(self, x):
        x = np.atleast_2d(x)
        return (x[:, self.i_k] / 1.2e-3) * (350 * 9.807e6 / x[:, self.i_h]) * (1 + 0.05 * (x[:, self.i_c] - 2e-6) / 1e-6)

    def __call__(self, x):
        return RATE * self.cycles * self.scale(x)[0], "ok"

    def life(self, x):
        return ALLOWANCE / (RATE * self.scale(x))


RATES_TWO_JOINTS = {"A": 1.2e-10, "E": 1.0e-10}  # m per cycle of the six-bar's joints A and E at k = 1e-4


class TwoJointWear:
    """The six-bar's joints A and E, each wearing q_j(x, N) = RATE_j N k_j / 1e-4 with its own random wear
    coefficient (x = (k_A, k_E)); outputs joint after joint. A series system whose life min(N_A, N_E) has a kink."""

    def __init__(self, cycles, rates=None):
        self.cycles = np.asarray(cycles, dtype=float)
        self.rates = dict(RATES_TWO_JOINTS if rates is None else rates)

    def __call__(self, x):
        x = np.atleast_1d(x)
        a = self.rates["A"] * self.cycles * x[0] / 1e-4
        e = self.rates["E"] * self.cycles * x[1] / 1e-4
        return np.concatenate([a, e]), "ok"

    @staticmethod
    def life(x, allowance=ALLOWANCE):
        """N_f = min_j allowance / (RATE_j k_j / 1e-4), for rows x = (k_A, k_E)."""
        x = np.atleast_2d(x)
        return np.minimum(allowance / (RATES_TWO_JOINTS["A"] * x[:, 0] / 1e-4),
                          allowance / (RATES_TWO_JOINTS["E"] * x[:, 1] / 1e-4))


def two_joint_six_bar(reliability: dict | None = None) -> dict:
    """The six-bar preset's config data with only k_A and k_E random (TwoJointWear's inputs), allowance 0.03 mm, a
    curve over 100,000-300,000 cycles (``reliability`` overrides; a None value leaves the key out)."""
    data = tomllib.loads((resources.files("jointwear.presets") / "watt_six_bar_two_clearances.toml").read_text(
        encoding="utf-8"))
    data["uncertainty"] = {"variables": [
        {"name": "k_A", "target": "clearance_joints.A.bearing_material.wear_coefficient", "mean": 1e-4,
         "std": 1e-5, "group": "bearing_material"},
        {"name": "k_E", "target": "clearance_joints.E.bearing_material.wear_coefficient", "mean": 1e-4,
         "std": 1.5e-5, "group": "bearing_material"},
    ]}
    rel = {"allowance_mm": 0.03, "cycles_start": 100_000, "cycles_stop": 300_000, "cycles_step": 50_000,
           **(reliability or {})}
    data["reliability"] = {k: v for k, v in rel.items() if v is not None}
    data.pop("sensitivity", None)
    return data


class NoisyTwoJointWear(TwoJointWear):
    """TwoJointWear whose call scatters as chaotic dynamics does: each joint's wear rate times exp(tau_j eps_j), eps_j
    standard normal and independent, drawn afresh at every call (so its life scatters by tau_j in ln N)."""

    TAUS = (0.15, 0.02)

    def __init__(self, cycles, seed=0):
        super().__init__(cycles)
        self.rng = np.random.default_rng(seed)

    def __call__(self, x):
        a, e = np.split(super().__call__(x)[0], 2)
        eps = self.rng.standard_normal(2)
        return np.concatenate([a * np.exp(self.TAUS[0] * eps[0]), e * np.exp(self.TAUS[1] * eps[1])]), "ok"

    @classmethod
    def survival(cls, x, cycles, eps, allowances=(ALLOWANCE, ALLOWANCE)):
        """Whether each row survives ``cycles`` with its scatter draws ``eps`` (n, 2), each joint with its allowance."""
        x = np.atleast_2d(x)
        life_a = allowances[0] / (RATES_TWO_JOINTS["A"] * x[:, 0] / 1e-4) * np.exp(-cls.TAUS[0] * eps[:, 0])
        life_e = allowances[1] / (RATES_TWO_JOINTS["E"] * x[:, 1] / 1e-4) * np.exp(-cls.TAUS[1] * eps[:, 1])
        return np.minimum(life_a, life_e) > cycles

    @classmethod
    def share_of_a(cls, x, cycles, eps, allowances=(ALLOWANCE, ALLOWANCE)):
        """Joint A's share of the failures at ``cycles``: the failed rows whose A life is the shorter."""
        x = np.atleast_2d(x)
        life_a = allowances[0] / (RATES_TWO_JOINTS["A"] * x[:, 0] / 1e-4) * np.exp(-cls.TAUS[0] * eps[:, 0])
        life_e = allowances[1] / (RATES_TWO_JOINTS["E"] * x[:, 1] / 1e-4) * np.exp(-cls.TAUS[1] * eps[:, 1])
        failed = np.minimum(life_a, life_e) <= cycles
        return float(np.mean(life_a[failed] < life_e[failed]))
