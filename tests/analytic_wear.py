"""An analytic wear model with the structure of Archard's law, for tests that need the exact R(N).

delta_max(x, N) = RATE * N * (k_b / k_b0) * (H_b0 / H_b) * (1 + 0.05 (c - c0) / 1 um): the wear depth is proportional
to k / H and to the number of cycles, so the exact reliability follows from brute-force Monte Carlo.
"""

import numpy as np

RATE = 7.1e-11  # m per cycle at the nominal point: the paper's mean slope (paper-notes: 7.1e-8 mm/cycle)
ALLOWANCE = 3e-5  # the flapping-wing preset's allowance, m


class AnalyticWear:
    """The true-model stand-in: ``(x) -> (wear at each of cycles, "ok")``; ``scale(x)`` and ``life(x)`` in closed
    form."""

    def __init__(self, names, cycles):
        self.i_k, self.i_h, self.i_c = names.index("k_b"), names.index("HB_b"), names.index("c")
        self.cycles = np.asarray(cycles, dtype=float)

    def scale(self, x):
        x = np.atleast_2d(x)
        return (x[:, self.i_k] / 1.2e-3) * (350 * 9.807e6 / x[:, self.i_h]) * (1 + 0.05 * (x[:, self.i_c] - 2e-6) / 1e-6)

    def __call__(self, x):
        return RATE * self.cycles * self.scale(x)[0], "ok"

    def life(self, x):
        return ALLOWANCE / (RATE * self.scale(x))
