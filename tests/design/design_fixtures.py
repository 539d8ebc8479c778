"""An analytic wear model and a small design problem whose exact answer is known by brute force."""

import numpy as np
from analytic_wear import AnalyticWear

from jointwear import compute
from jointwear.config import load_config, updated
from jointwear.design.settings import DesignSettings
from jointwear.study import study_context

DESIGN = {
    "targets": [{"reliability": 0.9, "life_cycles": 400_000}],
    "tolerances": [{"variable": "l2", "grades": ["IT9", "IT10", "IT11"]}],
    "fit": {"options": [{"name": "H7/g6", "hole_grade": "IT7", "shaft_grade": "IT6", "cost": 0.0},
                        {"name": "H6/g5", "hole_grade": "IT6", "shaft_grade": "IT5", "cost": 0.5}]},
    "properties": [
        {"variable": "HB_b", "classes": [
            {"name": "standard", "cost": 0.0},
            {"name": "screened", "std_HB": 15.0, "lower_HB": 320.0, "cost": 0.8},
            {"name": "hard", "mean_HB": 390.0, "cost": 1.2}]},
        {"variable": "k_b", "classes": [
            {"name": "standard", "cost": 0.0},
            {"name": "screened", "std": 0.6e-4, "upper": 1.3e-3, "cost": 0.7},
            {"name": "coated", "mean": 1.0e-3, "std": 1.0e-4, "cost": 1.5}]},
    ],
    "n_population": 50_000, "refine_max_calls": 30, "verification_max_calls": 60,
    # a deterministic model (noise = 'none'): the ESC bound is calibrated, so the verification may stop on it
    "verification_stopping": "error",
}


def analytic_config(design=None):
    # a deterministic model: the engine's own accuracy settings (relative ESC error 2 %, absolute 0.2 %)
    return updated(load_config(), {
        "reliability.cycles_start": 340_000, "reliability.cycles_stop": 480_000, "reliability.cycles_step": 20_000,
        "reliability.histogram_cycles": [380_000, 420_000], "reliability.n_mc": 50_000, "reliability.max_calls": 80,
        "reliability.noise": "none", "reliability.error_tol": 0.02, "reliability.error_abs_tol": 0.002,
        "design": DesignSettings.model_validate(design if design is not None else DESIGN)})


def analytic_context(cfg):
    holder = {}

    def factory(call):
        holder["model"] = AnalyticWear([s.name for s in cfg.uncertainty.all_specs()], call.cycles)
        return compute.Evaluator(holder["model"], None, None, n_outputs=len(call.cycles))

    ctx = study_context(cfg, factory)
    return ctx, holder["model"]


def exact_reliabilities(ctx, model, controls, candidates, life, n=1_000_000, seed=7):
    """R(N*) of every candidate by brute-force Monte Carlo on the analytic model (same draws for all). The inputs are
    independent, so each column is transformed once per distinct marginal and shared by the candidates using it."""
    from jointwear.reliability import IsoTransform

    z = np.random.default_rng(seed).standard_normal((n, len(ctx.names)))
    if ctx.copula is not None:
        iso = [IsoTransform(c.marginals(controls, ctx.names, ctx.marginals)) for c in candidates]
        return np.array([float(np.mean(model.life(t.to_x(z)) > life)) for t in iso])
    columns: dict = {}  # (column, id of its marginal) -> (marginal, values); keeping the marginal keeps its id unique
    out = []
    x = np.zeros_like(z)  # only the columns the model reads are filled
    for cand in candidates:
        for i, m in enumerate(cand.marginals(controls, ctx.names, ctx.marginals)):
            if i not in model.inputs:
                continue
            key = (i, id(m))
            if key not in columns:
                columns[key] = (m, IsoTransform([m]).to_x(z[:, [i]])[:, 0])
            x[:, i] = columns[key][1]
        out.append(float(np.mean(model.life(x) > life)))
    return np.array(out)


__all__ = ["AnalyticWear", "analytic_config", "analytic_context", "exact_reliabilities"]


class FixedPopulationSpace:
    """A candidate space whose every candidate (and today's design) has the same population: ``n`` points at the
    origin of ``dim`` inputs, with the life-scatter draw ``scatter`` (n,) per point (zeros by default)."""

    def __init__(self, n, dim=1, scatter=None):
        self.u = np.zeros((n, dim))
        self.scatter = np.zeros(n) if scatter is None else np.asarray(scatter, dtype=float)

    def population(self, cand):
        return self.u, self.u

    def infeasible_probability(self, cand):
        return 0.0
