"""jointwear's Python API in a few lines: a preset, a reliability analysis, a figure.

1. Load the default preset (the paper's flapping-wing mechanism) and read a few of its settings.
2. Run AK-MCS on an analytic wear limit state. The reliability engine knows nothing about wear: it takes
   any vectorised g(X) -> array (failure where g < 0) and independent ``scipy.stats`` marginals.
3. Check the answer against plain Monte Carlo and draw the convergence of Pf with the project's figure style.

The limit state is Archard's law in closed form for a bearing that wears at a constant rate:

    max wear after N cycles   h(N) = (k / H) * q * N        q: pressure x sliding per cycle (Pa m)
    limit state               G    = delta_0 - h(N)          delta_0 = 0.03 mm (0.01 x the 3 mm outer diameter)

with the bearing's wear coefficient k, its hardness H and the load term q uncertain. q is chosen so that
the nominal wear after 400,000 cycles is 0.0285 mm, the paper's mean of the max wear.

Run:  python examples/api_example.py [OUT_DIR]     (about 10 s; writes OUT_DIR/api_example_convergence.png)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy import stats

import jointwear.config
import jointwear.reliability
from jointwear.report.figures import convergence_figure
from jointwear.report.style import savefig

DELTA_0 = 0.03e-3  # m, allowable wear
N_CYCLES = 400_000

# 1. the preset ------------------------------------------------------------------------------------------
cfg = jointwear.config.load_config("jin2025_flapping_wing")
joint = cfg.clearance_joints[0]
bearing = joint.bearing_material
print(f"preset {cfg.name}: bearing radius {joint.bearing_radius * 1e3:.3f} mm, "
      f"journal radius {joint.journal_radius * 1e3:.3f} mm, "
      f"bearing k = {bearing.wear_coefficient:.2g}, H = {bearing.hardness / 1e9:.3g} GPa")

# 2. the limit state and its random inputs (SI units) ------------------------------------------------------
k0, H0 = bearing.wear_coefficient, bearing.hardness
q0 = 0.0285e-3 / (k0 / H0 * N_CYCLES)  # Pa m per cycle: nominal wear 0.0285 mm at 400k cycles
marginals = [
    stats.norm(k0, 0.05 * k0),  # wear coefficient k (-)
    stats.norm(H0, 0.05 * H0),  # hardness H (Pa)
    stats.lognorm(s=0.04, scale=q0),  # load term q (Pa m per cycle)
]


def g(x: np.ndarray) -> np.ndarray:
    """Vectorised limit state: x has shape (n, 3) -> (n,) values; failure where g < 0."""
    k, hardness, q = x[:, 0], x[:, 1], x[:, 2]
    return DELTA_0 - k / hardness * q * N_CYCLES


res = jointwear.reliability.akmcs(g, marginals, n_mc=100_000, seed=1)
print(f"AK-MCS: Pf = {res.pf:.4g}, COV = {res.cov:.3f}, R = {1 - res.pf:.4f}, "
      f"{res.n_calls} calls of g (n_mc = {res.n_mc:,})")

# 3. check against plain Monte Carlo and draw the convergence ------------------------------------------------
rng = np.random.default_rng(2)
x_mc = np.column_stack([m.rvs(size=1_000_000, random_state=rng) for m in marginals])
pf_mc = float(np.mean(g(x_mc) < 0))
print(f"plain Monte Carlo (1e6 samples): Pf = {pf_mc:.4g}")
assert abs(res.pf - pf_mc) < 0.1 * pf_mc + 3 * res.cov * res.pf, "AK-MCS and Monte Carlo disagree"

if res.history:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("example-output")
    fig = convergence_figure([h.n_calls for h in res.history], [h.pf for h in res.history],
                             cov=[h.cov for h in res.history])
    print("figure:", savefig(fig, out / "api_example_convergence.png"))
