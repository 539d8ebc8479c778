"""Is the wear history converged in its numerical settings on *this* mechanism? (``jointwear converge``)

The nominal wear history is run with the study's wear settings (the baseline) and with each numerical setting
refined by a factor (more recorded and settling cycles per block, shorter blocks, a finer angular grid, tighter
integrator tolerances; in profile mode also the running-in length and the deposit's sub-step), each as several
replicates that differ only in the start phase (the first block's settling, as benchmarks/wear.py does). The
measure is the study's nominal life (the first judged joint to reach its allowance, the limit state of the
reliability stage), or the first judged joint's wear at the history's end when no allowance is set. With several
judged joints each joint's own measure is judged too: a setting that moves a joint which does not govern the nominal
life still moves that joint's R(N), and so the system's.

A refinement's change of the mean is judged against the tolerance with its 95 % interval (Welch's: the Student t
quantile at the Welch-Satterthwaite degrees of freedom times the standard error of the difference of two means; a
few replicates estimate their scatter poorly, and 1.96 standard errors would claim more than 95 %): *converged*
when the interval lies inside +-tolerance, *not converged* when it lies outside, *no change detected* when it holds
zero but reaches past the tolerance, *undecided* otherwise (more replicates tell). A chaotic contact makes every
run another sample of the cycle-to-cycle scatter: the replicates' scatter is reported: the same kind of scatter the
reliability stage's Kriging estimates as noise between its calls.
"""

from __future__ import annotations

import math
import numbers
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from scipy import stats

from jointwear.config import StudyConfig
from jointwear.reliability.results import Z95
from jointwear.schema import ConfigError
from jointwear.study.io import provenance
from jointwear.study.limit_state import limit_state_from_config
from jointwear.study.model_call import quantity_history
from jointwear.study.stage_result import StageResult

#: relative change of the nominal life that counts as converged (the criterion of the wear convergence studies,
#: docs/wear.md)
DEFAULT_TOLERANCE = 0.02
#: start-phase step between replicates (cycles of the first block's settling), as benchmarks/wear.py
REPLICATE_PHASE_STEP = 0.05

REFINEMENT_NAMES = ("record_cycles", "settle_cycles", "block", "n_grid", "tolerance", "profile_smoothing_deg",
                    "profile_substep_cycles")


@dataclass(frozen=True)
class Refinement:
    """One numerical setting refined: its name, what it means, and the WearSettings fields it changes."""

    name: str
    description: str
    update: dict[str, Any]


def refinements(config: StudyConfig, factor: float) -> list[Refinement]:
    """Each numerical wear setting of ``config`` refined by ``factor`` (> 1); the profile-mode settings only in
    profile mode."""
    s, sim = config.wear, config.simulation
    f = float(factor)
    out = [Refinement("record_cycles", "steady cycles recorded per block x factor",
                      {"record_cycles": max(s.record_cycles + 1, int(round(s.record_cycles * f)))}),
           Refinement("settle_cycles", "cycles settled after each geometry update x factor",
                      {"settle_cycles": s.settle_cycles * f if s.settle_cycles > 0 else 1.0})]
    if s.block_rule == "fixed":
        out.append(Refinement("block", "block (cycles between geometry updates) / factor",
                              {"block_cycles": max(1, int(s.block_cycles / f))}))
    else:
        out.append(Refinement("block", "adaptive blocks / factor and their rate tolerance / factor",
                              {"rate_tolerance": s.rate_tolerance / f,
                               "initial_block": max(1, int(s.initial_block / f)),
                               "min_block": max(1, int(s.min_block / f)), "max_block": max(1, int(s.max_block / f))}))
    out.append(Refinement("n_grid", "angular grid cells x factor", {"n_grid": int(round(s.n_grid * f))}))
    rtol = s.rtol if s.rtol is not None else sim.rtol
    atol = s.atol if s.atol is not None else sim.atol
    out.append(Refinement("tolerance", "integrator rtol and atol / factor", {"rtol": rtol / f, "atol": atol / f}))
    if s.geometry_mode == "profile":
        out.append(Refinement("profile_smoothing_deg", "running-in length / factor",
                              {"profile_smoothing_deg": s.profile_smoothing_deg / f}))
        out.append(Refinement("profile_substep_cycles", "deposit sub-step / factor",
                              {"profile_substep_cycles": s.profile_substep_cycles / f}))
    return out


def t95(dof: float) -> float:
    """The two-sided 95 % quantile of Student's t with ``dof`` degrees of freedom (1.96 as dof -> inf)."""
    return float(stats.t.ppf(0.975, dof)) if math.isfinite(dof) else Z95


def welch_dof(std_a: float, n_a: int, std_b: float, n_b: int) -> float:
    """Welch-Satterthwaite degrees of freedom of the difference of two means (inf when neither scatters)."""
    va, vb = std_a ** 2 / n_a, std_b ** 2 / n_b
    den = (va ** 2 / (n_a - 1) if va else 0.0) + (vb ** 2 / (n_b - 1) if vb else 0.0)
    return (va + vb) ** 2 / den if den > 0.0 else math.inf


def change_verdict(change: float, standard_error: float, tolerance: float, quantile: float = Z95) -> str:
    """The verdict on a relative change with its standard error, from its 95 % interval change +- quantile SE:
    'converged' (inside +-tolerance), 'not converged' (outside it), 'no change detected' (holds 0 but reaches past
    the tolerance: the replicates cannot resolve the tolerance), 'undecided' (neither: a change, of uncertain size
    against the tolerance)."""
    low, high = change - quantile * standard_error, change + quantile * standard_error
    if -tolerance <= low and high <= tolerance:
        return "converged"
    if low > tolerance or high < -tolerance:
        return "not converged"
    if low <= 0.0 <= high:
        return "no change detected"
    return "undecided"


#: how much a verdict says against convergence: a refinement's verdict over the system and its joints is the worst
VERDICT_SEVERITY = {"no wear": 0, "converged": 0, "no change detected": 1, "too few histories": 2, "undecided": 3,
                    "not converged": 4}


def worst_verdict(verdicts: Sequence[str]) -> str:
    """The verdict that says most against convergence (the first of equals)."""
    return max(verdicts, key=VERDICT_SEVERITY.__getitem__)


def replicates_to_resolve(scatter: float, tolerance: float) -> int:
    """Replicates per setting whose 95 % interval of a change is +-tolerance when both settings scatter by
    ``scatter`` (standard deviation / mean): the least n with t_0.975(2n - 2) scatter sqrt(2 / n) <= tolerance."""
    n = max(2, math.ceil(2.0 * (Z95 * scatter / tolerance) ** 2))  # the normal quantile's n: a lower bound
    while _resolution(scatter, n) > tolerance:
        n += 1
    return n


@dataclass(repr=False, eq=False)
class WearConvergence(StageResult):
    """The nominal wear history's convergence in its numerical settings (``jointwear converge``).

    ``measure``: 'life' (the nominal life, cycles: the first judged joint to reach its allowance, extrapolated
    linearly past the history's end as the reliability stage does) or 'wear' (the first judged joint's wear
    quantity at the history's end, m, when no allowance is set). ``baseline``: the replicates' values, mean,
    standard deviation, ``scatter`` (standard deviation / mean) and ``failed`` (histories that failed, left out).
    Each of ``refinements``: ``name``, ``description``, ``changed`` ({field: [baseline, refined]}), ``values``,
    ``failed``, ``mean``, ``std``, ``change`` (relative change of the mean), ``change_se`` (its standard error),
    ``change_95`` (its 95 % half-width, Welch's) and ``verdict`` (:func:`change_verdict`; 'too few histories' when
    fewer than two of either ran, 'no wear' when the baseline's measure is zero).

    With several judged joints, ``baseline['joints']`` and each refinement's ``joints`` hold the same per joint
    (each joint's own life, or its own wear at the end), the refinement's ``system_verdict`` is the nominal
    measure's own, and its ``verdict`` the worst of them all (:func:`worst_verdict`).
    """

    FILE: ClassVar[str] = "wear_convergence.json"

    measure: str
    unit: str
    cycles: int
    replicates: int
    factor: float
    tolerance: float
    baseline: dict
    refinements: list[dict]
    joints: list[str] = field(default_factory=list)
    quantity: str = ""
    wall_seconds: float = 0.0
    settings: dict = field(default_factory=dict)
    files: list[str] = field(default_factory=list)
    provenance: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    @property
    def scatter(self) -> float:
        """Start-to-start scatter of the baseline: standard deviation / mean of its replicates."""
        return float(self.baseline["scatter"])

    def verdicts(self) -> dict[str, str]:
        """Each refinement's verdict by name."""
        return {r["name"]: r["verdict"] for r in self.refinements}

    def not_converged(self) -> list[str]:
        """The refinements whose change lies outside the tolerance (verdict 'not converged')."""
        return [r["name"] for r in self.refinements if r["verdict"] == "not converged"]

    @property
    def converged(self) -> bool:
        """Whether every refinement's verdict is 'converged'."""
        return all(v == "converged" for v in self.verdicts().values())

    def subjects(self, row: dict) -> list[tuple[str, str, dict, dict, str]]:
        """(joint, what, the row's values, the baseline's, verdict) of the nominal measure (joint '') and of each
        judged joint's own (several joints only)."""
        what = "the nominal life" if self.measure == "life" else "the final wear"
        own = "nominal life" if self.measure == "life" else "final wear"
        joints = row.get("joints") or {}
        base = self.baseline.get("joints") or {}
        return [("", what, row, self.baseline, row.get("system_verdict", row["verdict"]))] + [
            (name, f"joint {name}'s own {own}", j, base.get(name, {}), j["verdict"]) for name, j in joints.items()]

    def governs(self, row: dict, joint: str) -> bool:
        """Whether ``joint``'s own measure is the nominal one in every history of the baseline and of ``row``."""
        own, base = row["joints"][joint], self.baseline["joints"][joint]
        return own["values"] == row["values"] and base["values"] == self.baseline["values"]

    def sentences(self) -> list[str]:
        """A warning for each refinement that is not converged or undecided, saying what to do."""
        out = []
        failed = [(name, r.get("failed", 0)) for name, r in (("baseline", self.baseline),
                                                              *((r["name"], r) for r in self.refinements))]
        if any(n for _, n in failed):
            out.append("histories failed (" + ", ".join(f"{name}: {n} of {self.replicates}" for name, n in failed if n)
                       + "): their reasons are in the study's log and evaluation store; the rest are judged")
        unresolved = []
        for r in self.refinements:
            fields_ = self.changed_text(r, prefix="wear.", sep=", ")
            for joint, what, values, base, verdict in self.subjects(r):
                if joint and self.governs(r, joint):
                    continue  # the nominal measure's sentence says it
                text = (f"with {fields_} {what} moves by {100 * values['change']:+.1f} % "
                        f"(+-{100 * half_width(values):.1f} %, 95 %)")
                if verdict == "not converged":
                    out.append(f"{text}: not converged within {100 * self.tolerance:g} %; refine that setting in "
                               "[wear]")
                elif verdict == "undecided":
                    out.append(f"{text}: whether beyond {100 * self.tolerance:g} % needs more replicates (about "
                               f"{replicates_to_resolve(base.get('scatter', self.scatter), self.tolerance)} for this "
                               "scatter)")
                elif verdict == "no change detected":
                    unresolved.append(base.get("scatter", self.scatter))
        if self.measure == "life":
            first = self.refinements[0] if self.refinements else None
            beyond = [(what, base["mean"]) for joint, what, _, base, _ in (self.subjects(first) if first else [])
                      if base.get("mean", 0.0) > self.cycles and not (joint and self.governs(first, joint))]
            if beyond:
                lives = ", ".join(f"{what} {mean:,.0f}" for what, mean in beyond)
                out.append(f"{lives} cycles lie beyond the histories' end ({self.cycles:,} cycles): extrapolated "
                           "linearly, so this judges the extrapolation's slope; --cycles near the life judges the "
                           "history there")
        if unresolved:
            scatter = max(unresolved)
            out.append(f"the {self.replicates} replicates resolve changes of about "
                       f"+-{100 * _resolution(scatter, self.replicates):.1f} % (95 %), not "
                       f"+-{100 * self.tolerance:g} %: the nominal history scatters by {100 * scatter:.1f} % from "
                       f"start to start; about {replicates_to_resolve(scatter, self.tolerance)} replicates would "
                       "resolve the tolerance")
        return out

    @staticmethod
    def changed_text(row: dict, *, arrow: str = "->", prefix: str = "", sep: str = "; ") -> str:
        """The settings a refinement changed, as text: 'record_cycles 1 -> 2; ...'."""
        return sep.join(f"{prefix}{k} {_fmt(a)} {arrow} {_fmt(b)}" for k, (a, b) in row["changed"].items())

    @property
    def resolution(self) -> float:
        """Half-width of the 95 % interval of a change between two settings that scatter as the baseline."""
        return _resolution(self.scatter, self.replicates)

    def tables(self) -> dict[str, dict[str, list]]:
        """``wear_convergence``: one row per setting (the baseline first) with the mean measure, its change against
        the baseline and that change's 95 % half-width, the verdict, and the same for each judged joint."""
        unit = "cycles" if self.measure == "life" else "mm"
        scale = 1.0 if self.measure == "life" else 1e3
        base_joints = {name: {**j, "change": 0.0, "change_se": 0.0, "change_95": 0.0, "verdict": ""}
                       for name, j in (self.baseline.get("joints") or {}).items()}
        rows = [{"name": "baseline", "description": "the study's wear settings", "changed": {},
                 **self.baseline, "joints": base_joints, "change": 0.0, "change_se": 0.0, "change_95": 0.0,
                 "verdict": ""}]
        rows += self.refinements
        table = {
            "setting": [r["name"] for r in rows],
            "changed": [self.changed_text(r) for r in rows],
            f"mean_{self.measure}_{unit}": [r["mean"] * scale for r in rows],
            f"std_{self.measure}_{unit}": [r["std"] * scale for r in rows],
            "change_pct": [100 * r["change"] for r in rows],
            "change_95_pct": [100 * half_width(r) for r in rows],
            "failed_histories": [r.get("failed", 0) for r in rows],
            "verdict": [r["verdict"] for r in rows],
        }
        for name in self.joints if base_joints else ():
            each = [r["joints"][name] for r in rows]
            table[f"{name}_mean_{self.measure}_{unit}"] = [j["mean"] * scale for j in each]
            table[f"{name}_change_pct"] = [100 * j["change"] for j in each]
            table[f"{name}_change_95_pct"] = [100 * half_width(j) for j in each]
            table[f"{name}_verdict"] = [j["verdict"] for j in each]
        return {"wear_convergence": table}

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``wear_convergence.json`` and ``wear_convergence.csv`` (``figures``: taken as every stage result's
        ``save`` takes it; this stage draws none, the report draws its table)."""
        self.files = [self.FILE, *self.write_tables(folder)]
        return self.write(folder)


def half_width(row: dict) -> float:
    """The half-width of a change's 95 % interval (``change_95``; 1.96 standard errors in a result written before
    it was kept)."""
    return float(row.get("change_95", Z95 * row["change_se"]))


def _resolution(scatter: float, replicates: int) -> float:
    """Half-width of the 95 % interval of a change between two settings of ``replicates`` histories each that
    scatter by ``scatter``: t_0.975(2n - 2) scatter sqrt(2 / n)."""
    return t95(2 * replicates - 2) * scatter * math.sqrt(2.0 / replicates)


def _fmt(value) -> str:
    return f"{value:.4g}" if isinstance(value, float) else f"{value:,}" if isinstance(value, int) else str(value)


def _summary(values: Sequence[float]) -> dict:
    """Mean, standard deviation and scatter of the finite values; ``failed``: the histories that gave none."""
    v = [float(x) for x in values if math.isfinite(x)]
    mean = statistics.fmean(v) if v else math.nan
    std = statistics.stdev(v) if len(v) > 1 else 0.0
    return {"values": v, "failed": len(values) - len(v), "mean": mean, "std": std,
            "scatter": std / abs(mean) if mean else math.nan}


def nominal_measure(config: StudyConfig):
    """(measure, function of a WearResult -> its values, limit state): the nominal life when every judged joint
    has an allowance, else the first judged joint's wear quantity at the history's end. The values are the nominal
    measure followed, with several judged joints, by each joint's own (its life, or its wear at the end)."""
    limit = limit_state_from_config(config)
    several = n_measures(limit) > 1

    def outputs(res) -> tuple[np.ndarray, np.ndarray]:
        by_index = {jw.index: jw for jw in res.joints}
        cycles = by_index[limit.joints[0]].history_cycles
        cycles = cycles[cycles > 0]
        return cycles, np.stack([quantity_history(by_index[j], limit.quantity, cycles) for j in limit.joints])

    if any(a is None for a in limit.allowances):
        def wear_at_end(res) -> np.ndarray:
            _, y = outputs(res)
            ends = y[:, -1]
            return np.concatenate([ends[:1], ends]) if several else ends[:1]
        return "wear", wear_at_end, limit

    def life(res) -> np.ndarray:
        cycles, y = outputs(res)
        lives = limit.joint_lives(cycles, y.reshape(1, -1))[0]
        values = np.concatenate([[lives.min()], lives]) if several else lives[:1]
        return np.minimum(values, float(res.stopped_at)) if res.stopped_at is not None else values
    return "life", life, limit


def n_measures(limit) -> int:
    """How many values a history gives: the nominal measure, and each judged joint's own when there are several."""
    return 1 + len(limit.joints) if len(limit.joints) > 1 else 1


def chosen_refinements(config: StudyConfig, replicates: int, factor: float, tolerance: float,
                       only: Sequence[str] | None = None) -> list[Refinement]:
    """The refinements a convergence check runs, its arguments checked (ConfigError naming the argument)."""
    if isinstance(replicates, bool) or not isinstance(replicates, numbers.Integral) or replicates < 2:
        raise ConfigError(f"replicates: a whole number >= 2 (a change needs their scatter), got {replicates!r}")
    if isinstance(factor, bool) or not (isinstance(factor, numbers.Real) and 1.0 < factor < math.inf):
        raise ConfigError(f"factor: a refinement factor > 1, got {factor!r}")
    if isinstance(tolerance, bool) or not (isinstance(tolerance, numbers.Real) and 0.0 < tolerance < 1.0):
        raise ConfigError(f"tolerance: a relative change in (0, 1), got {tolerance!r}")
    chosen = refinements(config, factor)
    if only:
        unknown = sorted(set(only) - {r.name for r in chosen})
        if unknown:
            raise ConfigError(f"only: unknown or not applicable refinement(s) {', '.join(unknown)}; choose from "
                              f"{', '.join(r.name for r in chosen)}")
        chosen = [r for r in chosen if r.name in set(only)]
    return chosen


#: the file of the check's evaluation store in the output folder (apart from the study's evaluations.sqlite, so
#: that neither refuses nor discards the other's calls)
STORE_FILE = "wear_convergence.sqlite"
#: the tag of its histories in that store
STORE_TAG = "wear_convergence"


@dataclass
class ConvergenceCall:
    """One history of the check, a plain picklable object so that worker processes and Dask workers can run it:
    the input row (refinement code, factor, replicate k, cycles) -> (the measure,). Code -1 is the baseline, else
    the index of the refinement in :data:`REFINEMENT_NAMES`; replicate k starts from the phase settle0 + 0.05 k."""

    base: dict
    threads: int | None = None

    def identity(self) -> dict:
        """What a history's measure depends on besides its row: the model sections of the config and the limit
        state (the key of the check's evaluation store)."""
        from jointwear.study.model_call import WearModelCall

        rel = self.base.get("reliability") or {}
        identity = {"model": {k: self.base[k] for k in WearModelCall.MODEL_SECTIONS},
                    "limit": {k: rel.get(k) for k in ("quantity", "joints", "allowance", "allowances")}}
        if self.n_outputs > 1:
            identity["outputs"] = "system and each joint"  # a store of the system's measure alone is not this one
        return identity

    @property
    def n_outputs(self) -> int:
        """The values a history gives (:func:`n_measures`), as the evaluator stores them."""
        from jointwear.config import config_from_dict

        return n_measures(limit_state_from_config(config_from_dict(self.base, source="convergence")))

    def settings(self, config: StudyConfig, x) -> Any:
        """The WearSettings of the row ``x``."""
        code, factor, k = int(x[0]), float(x[1]), int(x[2])
        update = {} if code < 0 else next(r.update for r in refinements(config, factor)
                                          if r.name == REFINEMENT_NAMES[code])
        s = config.wear
        settle0 = s.settle_cycles_initial if s.settle_cycles_initial is not None else config.simulation.settle_cycles
        return s.model_copy(update={**update, "settle_cycles_initial": settle0 + REPLICATE_PHASE_STEP * k})

    def __call__(self, x: np.ndarray):
        from jointwear.config import config_from_dict
        from jointwear.mechanism import build_model
        from jointwear.wear import wear_history

        config = config_from_dict(self.base, source="convergence")
        _, value_of, _ = nominal_measure(config)
        res = wear_history(build_model(config), self.settings(config, x), int(x[3]), threads=self.threads)
        return np.asarray(value_of(res), dtype=float), "ok"


def run_convergence(config: StudyConfig, cycles: int, *, replicates: int = 8, factor: float = 2.0,
                    tolerance: float = DEFAULT_TOLERANCE, only: Sequence[str] | None = None, threads: int | None = None,
                    evaluator_factory: Callable[[ConvergenceCall], Callable] | None = None) -> WearConvergence:
    """The nominal history to ``cycles`` with the config's wear settings and with each refinement, ``replicates``
    runs each (start phases settle0 + 0.05 k); ``only``: the refinements to run (names of
    :data:`REFINEMENT_NAMES`). ``evaluator_factory(call)`` returns what evaluates the rows, X (n, 4) -> Y (n, 1)
    with NaN for a failed history (a :class:`jointwear.compute.Evaluator`: workers, store, progress); default:
    one after the other in this process. ``threads``: most threads of one history (its lanes)."""
    chosen = chosen_refinements(config, replicates, factor, tolerance, only)
    measure, _, limit = nominal_measure(config)
    call = ConvergenceCall(config.model_dump(), threads)
    evaluate = evaluator_factory(call) if evaluator_factory is not None else (
        lambda X: np.array([call(x)[0] for x in X]))
    codes = [-1] + [REFINEMENT_NAMES.index(r.name) for r in chosen]
    # the baseline's rows carry factor 1 (it refines nothing), so a check with another factor reads them back
    X = np.array([[c, float(factor) if c >= 0 else 1.0, k, int(cycles)] for c in codes for k in range(replicates)],
                 dtype=float)
    t0 = time.perf_counter()
    width = n_measures(limit)
    Y = np.asarray(evaluate(X), dtype=float).reshape(len(codes), replicates, width)
    names = list(limit.names) if width > 1 else []
    base = _summary(Y[0, :, 0])
    if names:
        base["joints"] = {name: _summary(Y[0, :, 1 + j]) for j, name in enumerate(names)}
    rows = []
    s = config.wear
    for r, values in zip(chosen, Y[1:]):
        row = _changed(values[:, 0], base, tolerance)
        if names:
            row["joints"] = {name: _changed(values[:, 1 + j], base["joints"][name], tolerance)
                             for j, name in enumerate(names)}
            row["system_verdict"] = row["verdict"]
            row["verdict"] = worst_verdict([row["verdict"], *(j["verdict"] for j in row["joints"].values())])
        rows.append({"name": r.name, "description": r.description,
                     "changed": {k: [getattr(s, k) if getattr(s, k) is not None else _resolved(config, k), v]
                                 for k, v in r.update.items()}, **row})
    return WearConvergence(measure=measure, unit="cycles" if measure == "life" else "m", cycles=int(cycles),
                           replicates=replicates, factor=float(factor), tolerance=float(tolerance), baseline=base,
                           refinements=rows, joints=list(limit.names), quantity=limit.quantity,
                           wall_seconds=time.perf_counter() - t0, settings=s.model_dump(mode="json"),
                           provenance=provenance())


def _changed(values: np.ndarray, base: dict, tolerance: float) -> dict:
    """A refined setting's values against the baseline's summary: their summary, the relative change of the mean,
    its standard error and the verdict."""
    row = _summary(values)
    row.pop("scatter")
    n_b, n_r = len(base["values"]), len(row["values"])
    if n_b < 2 or n_r < 2:
        change, se, q, verdict = math.nan, math.nan, math.nan, "too few histories"
    elif base["mean"] == 0.0:  # a joint that never wears: no relative change
        change, se, q, verdict = math.nan, math.nan, math.nan, "no wear"
    else:
        change = row["mean"] / base["mean"] - 1.0
        se = math.sqrt(row["std"] ** 2 / n_r + base["std"] ** 2 / n_b) / abs(base["mean"])
        q = t95(welch_dof(row["std"], n_r, base["std"], n_b))
        verdict = change_verdict(change, se, tolerance, q)
    return {**row, "change": change, "change_se": se, "change_95": q * se, "verdict": verdict}


def _resolved(config: StudyConfig, name: str):
    """A wear setting left to the simulation's (rtol, atol) as the history uses it."""
    return getattr(config.simulation, name)
