"""Typed results of the reliability stages: the R(N) curve and life table, the sensitivity, and the validation
against the true model; each with ``save(folder)`` (JSON, CSV tables, figures) and ``load(folder)``."""

from __future__ import annotations

import math
import numbers
import warnings
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from jointwear.schema import ConfigError
from jointwear.study.io import provenance
from jointwear.study.limit_state import (
    OUTSIDE_CURVE,
    curve_half_width,
    interval_reach,
    life_at,
    life_interval,
    life_status,
)
from jointwear.study.stage_result import StageResult, save_figure
from jointwear.units import column_name

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["ReliabilityCurve", "SensitivityResult", "SurrogateFit", "ValidationResult", "interval_cells",
           "interval_text", "reliability_target"]


def reliability_target(value: Any, where: str) -> float:
    """``value`` as a float when it is a reliability in (0, 1), else ConfigError naming ``where`` (a target read
    outside that range returned (None, None), and a string ended in numpy's UFuncTypeError)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0.0 < float(value) < 1.0:
        raise ConfigError(f"{where}: a reliability in (0, 1) (got {value!r})")
    return float(value)


def signed_percent(fraction: float) -> str:
    """'-1.4 %', '+0.3 %', '0.0 %' (a fraction to one decimal of a percent; no sign on what rounds to zero)."""
    value = round(100.0 * float(fraction), 1)
    return "0.0 %" if value == 0 else f"{value:+.1f} %"


def interval_text(low: float | None, high: float | None) -> str:
    """'95 % interval 374,429-380,517 cycles'; an end outside the curve is said as such."""
    if low is None and high is None:
        return "95 % interval wider than the curve"
    if low is None:
        return f"95 % interval up to {high:,.0f} cycles (its low end lies before the curve's first cycle count)"
    if high is None:
        return f"95 % interval from {low:,.0f} cycles (its high end lies beyond the curve's last cycle count)"
    return f"95 % interval {low:,.0f}-{high:,.0f} cycles"


def interval_cells(low: float | None, high: float | None, reach: tuple[float, float] | None = None) -> str:
    """'374,429 \u2013 380,517' for a table cell; an end outside the curve said as such (with both outside, ``reach``
    (:meth:`ReliabilityCurve.life_reach`) tells an interval before or beyond the curve from one wider than it)."""
    if low is None and high is None:
        if reach is not None and math.isinf(reach[0]) != math.isinf(reach[1]):
            return "before the curve" if math.isinf(reach[0]) else "beyond the curve"
        return "wider than the curve"
    return (("before the curve" if low is None else f"{low:,.0f}") + " \u2013 "
            + ("beyond the curve" if high is None else f"{high:,.0f}"))


# ------------------------------------------------------------------------------------------------ reliability
@dataclass(frozen=True)
class SurrogateFit:
    """How well the learned life surrogate (the Kriging of ln N_f behind R(N)) explains its own design points,
    from the study's calls alone (no new model call).

    ``q2``: the leave-one-out score 1 - sum (y_i - y_-i)^2 / sum (y_i - mean y)^2 of ln N_f over the ``n_points``
    design points (each predicted by the surrogate without it, hyperparameters kept), ``rmse_log_life`` its root
    mean square residual. ``noise_sd_log_life``: the call-to-call scatter of ln N_f the fit estimated (the nugget:
    reliability.noise = 'estimate'), ``process_sd_log_life`` the spread of the smooth part it explains with the
    inputs; ``relative_nugget`` their variance ratio and ``nugget_at_bound`` whether it sits at the top of the
    range the fit may choose from (the scatter may then be larger than the fit allows). With one Kriging per judged
    joint (``reliability.surrogate = 'per_joint'``) each design point's ln N_f and its prediction are the minimum over
    the joints, the two standard deviations weight each joint's by its share of the design points it governs, and
    the nugget is the largest joint's. ``worst_share``: the share of the leave-one-out squared error that its worst
    point carries, ``worst_life_ratio`` that point's life over the points' median; ``archard_trend_hint``: the
    Kriging learnt a constant trend where ``reliability.trend = "archard"`` would tell it Archard's scaling.
    """

    n_points: int
    q2: float | None
    rmse_log_life: float | None
    noise_sd_log_life: float
    process_sd_log_life: float
    relative_nugget: float
    nugget_at_bound: bool
    worst_share: float | None = None
    worst_life_ratio: float | None = None
    archard_trend_hint: bool = False

    #: Below this Q^2 the inputs explain less of the design points' ln N_f than the model's scatter and the
    #: surrogate's error leave unexplained (the definition of Q^2: half the variance).
    Q2_FLOOR: ClassVar[float] = 0.5
    #: A poor fit whose worst point carries this share of the leave-one-out squared error is that point's
    WORST_SHARE: ClassVar[float] = 0.5
    #: ... and whose life is this many times the points' median (or as much less) is in the inputs' far tail
    FAR_LIFE_RATIO: ClassVar[float] = 10.0

    @classmethod
    def of(cls, surrogate, loo: np.ndarray | None = None, archard_trend_hint: bool = False) -> SurrogateFit:
        """From a fitted :class:`~jointwear.reliability.KrigingSurrogate` of ln N_f; ``loo``: its leave-one-out
        predictions when the caller already has them."""
        y = np.asarray(surrogate.training_outputs, dtype=float)
        if loo is None:
            loo, _ = surrogate.leave_one_out()
        squares = (y - loo) ** 2
        ss_res = float(np.sum(squares))
        ss_tot = float(np.sum((y - y.mean()) ** 2))
        worst = int(np.argmax(squares)) if y.size else None
        parts = getattr(surrogate, "fitted_components", [surrogate])  # a per-joint study's: every joint's Kriging
        return cls(n_points=int(y.size), q2=1.0 - ss_res / ss_tot if ss_tot > 0 else None,
                   rmse_log_life=math.sqrt(ss_res / y.size) if y.size else None,
                   noise_sd_log_life=math.sqrt(surrogate.noise_variance),
                   process_sd_log_life=math.sqrt(surrogate.process_variance),
                   relative_nugget=max(float(p.hyperparameters.nugget) for p in parts),
                   nugget_at_bound=any(p.estimate_nugget and p.hyperparameters.nugget >= 0.99 * max(p.nugget_grid)
                                       for p in parts),
                   worst_share=float(squares[worst] / ss_res) if worst is not None and ss_res > 0 else None,
                   worst_life_ratio=None if worst is None else float(np.exp(y[worst] - np.median(y))),
                   archard_trend_hint=bool(archard_trend_hint))

    @property
    def life_scatter(self) -> float:
        """One standard deviation of a call's life about the smooth surrogate, as a fraction: exp(noise_sd) - 1."""
        return math.expm1(self.noise_sd_log_life)

    @property
    def poor(self) -> bool:
        """Whether the inputs explain less than :attr:`Q2_FLOOR` of the design points' ln N_f."""
        return self.q2 is not None and self.q2 < self.Q2_FLOOR

    @property
    def far_point(self) -> bool:
        """Whether one design point carries ``WORST_SHARE`` or more of the leave-one-out error with a life
        ``FAR_LIFE_RATIO`` times the points' median or more (or as much less): a point in the inputs' far tail."""
        ratio = self.worst_life_ratio
        return (self.worst_share is not None and self.worst_share >= self.WORST_SHARE and bool(ratio)
                and not 1.0 / self.FAR_LIFE_RATIO < ratio < self.FAR_LIFE_RATIO)

    def warning(self) -> str:
        """What a poor fit means for R(N) and what to do (empty when the fit is not poor). A poor Q^2 has causes the
        fit cannot always tell apart (its scatter estimate is itself unsure then): a call's scatter larger than what
        the inputs do, or too few calls for the surrogate to follow them, both told with the numbers; or one point
        in the inputs' far tail (:attr:`far_point`), which a constant trend cannot follow and which bends the
        surrogate elsewhere too, told also above ``Q2_FLOOR`` where Archard's trend would cure it."""
        error = "" if self.rmse_log_life is None else f" (leave-one-out error of ln N_f {self.rmse_log_life:.3g})"
        validate = ("Check the curve against the true model with jointwear validate (docs/study.md, 'How far to trust "
                    "the life')")
        trend = ("with reliability.trend = 'archard' the Kriging is told Archard's scaling of the life in the "
                 "judged body's wear coefficient and hardness, which such a point follows; run again with "
                 "--resume (the calls made are read back; docs/reliability.md, \"The learnt life's spread\")"
                 if self.archard_trend_hint else "more calls near it may let the surrogate follow it: raise "
                 "reliability.max_calls and run again with --resume")
        share = f"{100 * (self.worst_share or 0.0):.0f} %"
        ratio = self.worst_life_ratio or 1.0
        example = " (a wear coefficient near zero lives orders of magnitude longer)" if ratio >= 1.0 else ""
        what = (f"its life is {_times(ratio)} the points' median, a point in the inputs' far tail{example} that the "
                "surrogate cannot follow from the others")
        cure = f"{trend[:1].upper() + trend[1:]}. {validate}"
        if self.poor:
            head = (f"the life surrogate explains little of its {self.n_points} design points (leave-one-out Q^2 = "
                    f"{self.q2:.2f}, below {self.Q2_FLOOR:g}), so R(N) may be too steep or too flat. ")
            if self.far_point:
                return head + f"One design point carries {share} of its leave-one-out error{error}: {what}. {cure}"
            hint = f"; {trend}" if self.archard_trend_hint else ""
            return (head + "Either a call's own scatter is larger than what the random inputs do (the fit puts it at "
                    f"{self.noise_sd_log_life:.3g} in ln N_f, about {100 * self.life_scatter:.2g} % in life, an "
                    "estimate itself unsure on a poor fit), or the surrogate has too few calls to follow the inputs"
                    f"{error}. More calls tell the two apart: raise reliability.max_calls and run again with "
                    "--resume; a Q^2 that stays low is the scatter's, which jointwear converge checks (more cycles "
                    "recorded per block, wear.record_cycles, lower a scatter that comes from sampling few cycles)"
                    f"{hint}. {validate}")
        if self.far_point and self.archard_trend_hint:
            rmse = "" if self.rmse_log_life is None else f", leave-one-out error of ln N_f {self.rmse_log_life:.3g}"
            return (f"one of the life surrogate's {self.n_points} design points carries {share} of its leave-one-out "
                    f"error (Q^2 = {self.q2:.2f}{rmse}): {what}, and it bends the surrogate elsewhere too, so R(N) "
                    f"may be off by more than its error says. {cure}")
        if not self.nugget_at_bound:
            return ""
        return (f"the call-to-call scatter of the life (about {100 * self.life_scatter:.0f} %) sits at the top of the "
                f"range the surrogate's noise estimate may take (relative nugget {self.relative_nugget:g}), so R(N) "
                "may be too steep or too flat. Check the wear history's settings with jointwear converge (more "
                "cycles recorded per block, wear.record_cycles, lower a scatter that comes from sampling few cycles, "
                "not one that comes from the history's path), and the curve against the true model with jointwear "
                "validate (docs/study.md, 'How far to trust the life')")

    def to_json(self) -> dict:
        """The fit's statistics as ``reliability.json`` stores them."""
        return {"n_points": self.n_points, "q2": self.q2, "rmse_log_life": self.rmse_log_life,
                "noise_sd_log_life": self.noise_sd_log_life, "process_sd_log_life": self.process_sd_log_life,
                "relative_nugget": self.relative_nugget, "nugget_at_bound": self.nugget_at_bound,
                "life_scatter": self.life_scatter, "worst_share": self.worst_share,
                "worst_life_ratio": self.worst_life_ratio, "archard_trend_hint": self.archard_trend_hint}

    @classmethod
    def from_json(cls, data: dict | None) -> SurrogateFit | None:
        if not data:
            return None
        return cls(n_points=int(data["n_points"]), q2=data.get("q2"), rmse_log_life=data.get("rmse_log_life"),
                   noise_sd_log_life=float(data["noise_sd_log_life"]),
                   process_sd_log_life=float(data["process_sd_log_life"]),
                   relative_nugget=float(data["relative_nugget"]), nugget_at_bound=bool(data["nugget_at_bound"]),
                   worst_share=data.get("worst_share"), worst_life_ratio=data.get("worst_life_ratio"),
                   archard_trend_hint=bool(data.get("archard_trend_hint", False)))


def _times(ratio: float) -> str:
    """'690 times' for a ratio above 1, '1/690 of' below it."""
    return f"{ratio:,.3g} times" if ratio >= 1.0 else f"1/{1.0 / ratio:,.3g} of"


@dataclass(repr=False, eq=False)  # StageResult compares by value
class ReliabilityCurve(StageResult):
    """The R(N) curve, the life at each target reliability and the wear distributions of a study.

    Arrays over the curve's ``cycles``: ``reliability``, ``pf``, ``pf_cov`` (coefficient of variation of the
    Monte Carlo estimate of Pf on the surrogate), ``pf_error`` (the surrogate's own absolute error estimate;
    ``pf_error_estimate`` in reliability.json and the CSV: the larger of ESC's and the Kriging's posterior spread,
    docs/reliability.md "The surrogate's error of R(N)"), ``pf_error_esc`` (ESC's part alone, the measure the
    learning stops on; None in results written before it), ``below_floor`` (levels whose COV need not meet the
    target; ``cov_waived_below_pf_floor`` in the JSON). ``life_cycles`` / ``life_hours``: the life at the first
    target (``life_at_target`` in the JSON). ``life_table``: [{``target``, ``cycles``, ``hours``, ``status``,
    ``cycles_low``, ``cycles_high``}]: the life is None where it lies outside the curve, and ``status`` says on
    which side ('in_curve', 'beyond_curve': longer than the curve, 'before_curve': shorter than its first level);
    ``cycles_low`` / ``cycles_high`` bound its 95 % interval (:meth:`life_interval`; None on a side outside the
    curve). ``joints``: each judged joint's allowance and, with several, its own R(N) and its share of the
    system's failures (``governing_share``). ``life_surrogate``: how the life was learnt, 'per_joint' (one Kriging
    per judged joint, several joints) or 'system_life' (one Kriging of the mechanism's log life, which with one
    judged joint is that joint's; results written before the choice existed read as that). ``life_curve``: R(N)
    and its 95 % half-width at 256 or more points over the curve (its levels among them), where :meth:`life` and
    :meth:`life_interval` read the life.

    Units: ``design_x`` are the true-model inputs in SI (columns in the order of ``names``, units in ``units``: a
    hardness in Pa, "" for a plain number),
    ``design_wear`` their wear quantity in m (the first judged joint's) at the history's cycles
    ``design_wear_cycles``, ``design_life`` their life in cycles (the system's; with several judged joints each
    joint's in ``design_joint_lives``, by name);
    ``mean_max_wear_mm`` (``cycles``, ``mean``) and ``histograms`` (``max_wear_mm``) are in mm, as named.

    ``engine``: the learning engine with its surrogates, held only by the result a run returns (it is not written
    to reliability.json, so a result read back by ``load_results`` has None there).
    """

    FILE: ClassVar[str] = "reliability.json"
    ALIGNED: ClassVar[tuple[tuple[str, ...], ...]] = (
        ("cycles", "reliability", "pf", "pf_cov", "below_floor", "pf_error", "pf_error_esc"),)

    cycles: np.ndarray
    reliability: np.ndarray
    pf: np.ndarray
    pf_cov: np.ndarray
    below_floor: np.ndarray
    pf_error: np.ndarray
    target: float
    life_cycles: float | None
    life_hours: float | None
    model_calls: int
    failed_calls: int
    n_mc: int
    converged: bool
    wall_seconds: float
    names: list[str]
    histograms: dict
    mean_max_wear_mm: dict
    convergence: dict
    design_x: np.ndarray
    design_wear: np.ndarray
    life_table: list[dict] = field(default_factory=list)
    design_life: np.ndarray | None = None
    design_joint_lives: dict[str, np.ndarray] | None = None
    design_wear_cycles: np.ndarray | None = None
    quantity: str = "bearing_max_depth"
    joints: list[dict] = field(default_factory=list)
    units: list[str] = field(default_factory=list)
    crank_speed_rpm: float | None = None
    infeasible: dict = field(default_factory=dict)
    learning_stop: str = ""
    surrogate_fit: SurrogateFit | None = None
    pf_error_esc: np.ndarray | None = None
    life_surrogate: str = "system_life"
    life_curve: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=provenance)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})
    engine: Any = field(repr=False, default=None, metadata={"json": False})

    #: a second judged joint governing at least this share of the failures at the life puts the kink of the
    #: series system's life inside the population (project choice)
    SERIES_SHARE: ClassVar[float] = 0.1
    #: fewer expected failures than this in the population leave the Monte Carlo COV of Pf above 0.22 (project choice)
    THIN_TAIL_FAILURES: ClassVar[int] = 20

    @property
    def stopped_by_budget(self) -> bool:
        """Whether the learning ended on its budget of model calls (``reliability.max_calls``)."""
        return "max_calls" in self.learning_stop

    @property
    def stopped_while_confirming(self) -> bool:
        """Whether the budget ended while the learning's rule held but on fewer successive designs than
        ``reliability.hold_iterations`` asks for (:func:`~jointwear.reliability.akmcs`'s message)."""
        return self.stopped_by_budget and "while confirming" in self.learning_stop

    def failed_calls_sentence(self) -> str:
        """What failed model calls mean for the curve (empty when none failed): they count as failures where they
        were drawn but teach the surrogate nothing, so where failures come with high wear R(N) is too high."""
        if not self.failed_calls:
            return ""
        reasons = Counter(str(r) for r in (self.infeasible.get("failure_reasons") or {}).values())
        common = f"; most often: {reasons.most_common(1)[0][0]}" if reasons else ""
        return (f"{self.failed_calls} of {self.model_calls} model calls failed{common}. A failed call counts as a "
                "failure where it was drawn but is left out of the surrogate, so if failures come with high wear the "
                "curve is too high (unconservative): the reasons are in reliability.json (infeasible.failure_reasons)")

    def truncation_sentence(self) -> str:
        """The share of each random clearance's normal below its minimum and what its rule does with it ('' when
        none is): 'truncate' rejects those assemblies, so R(N) is that of the parts accepted; 'fail' counts them as
        failures at every N."""
        parts = []
        for c in self.infeasible.get("clearances") or []:
            share = float(c.get("probability_below_minimum") or 0.0)
            if share <= 0.0:
                continue
            what = ("rejected at assembly, so R(N) is that of the accepted assemblies" if c.get("rule") == "truncate"
                    else "counted as failures at every N")
            parts.append(f"{share * 100:.3g} % of clearance {c['name']}'s normal lies below its minimum "
                         f"({float(c['minimum_clearance_m']) * 1e6:g} um): {what} "
                         f"(infeasible_rule = '{c.get('rule')}')")
        return "; ".join(parts)

    def surrogate_fit_sentence(self) -> str:
        """What a poor life surrogate means and what to do (:meth:`SurrogateFit.warning`; empty when its fit is
        fine or was not recorded)."""
        return "" if self.surrogate_fit is None else self.surrogate_fit.warning()

    def worn_away_sentence(self) -> str:
        """How many model calls wore a joint away (their life ends where the history stopped; empty when none)."""
        n = int(self.infeasible.get("worn_away_calls") or 0)
        if not n:
            return ""
        return (f"{n} of {self.model_calls} model calls wore a joint away within the curve's cycles (docs/wear.md, "
                "'A joint worn away'): a joint worn away has failed whatever the allowance, so their life ends where "
                "their history stopped (within one step of the history's cycles)")

    @property
    def half_width(self) -> np.ndarray:
        """The 95 % half-width of R at each level (:func:`~jointwear.study.limit_state.curve_half_width`)."""
        return curve_half_width(self.pf, self.pf_cov, self.pf_error)

    def _life_curve(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(cycles, R, 95 % half-width) where the life is read: :attr:`life_curve` (the curve between its levels
        too), else, in results written without it, the levels."""
        c = self.life_curve
        if c.get("cycles"):
            return tuple(np.asarray(c[k], dtype=float) for k in ("cycles", "reliability", "half_width_95"))
        return np.asarray(self.cycles, dtype=float), np.asarray(self.reliability, dtype=float), self.half_width

    def fine_curve(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(cycles, R, 95 % half-width) of :attr:`life_curve`, the curve between its levels too; None in results
        written without it."""
        return self._life_curve() if self.life_curve.get("cycles") else None

    def reliability_at(self, cycles: float) -> tuple[float, float]:
        """R at ``cycles`` and its 95 % half-width, read on :attr:`life_curve` as the life is (straight between its
        points); a cycle count outside the curve raises :class:`~jointwear.schema.ConfigError` (R there is not
        estimated: extend reliability.cycles_start or cycles_stop)."""
        n, r, half = self._life_curve()
        if isinstance(cycles, bool) or not isinstance(cycles, numbers.Real) or not n[0] <= cycles <= n[-1]:
            raise ConfigError(f"reliability_at: cycles: a cycle count on the curve, {n[0]:,.0f} to {n[-1]:,.0f} "
                              f"(got {cycles!r})")
        return float(np.interp(cycles, n, r)), float(np.interp(cycles, n, half))

    def hours(self, cycles: float | None) -> float | None:
        """``cycles`` of the crank as hours of running at :attr:`crank_speed_rpm`: N / (60 rpm); None without either."""
        return None if cycles is None or not self.crank_speed_rpm else float(cycles) / (60.0 * self.crank_speed_rpm)

    def life_row(self, target: float | None = None) -> dict | None:
        """The life table's row of ``target`` (default: the first target); None when the table has none."""
        target = self.target if target is None else float(target)
        return next((r for r in self.life_table if abs(float(r["target"]) - target) < 1e-12), None)

    def life(self, target: float | None = None) -> float | None:
        """The life (cycles) at ``target`` (default: the first target): where R(N) falls to it, read on
        :attr:`life_curve` (:func:`~jointwear.study.limit_state.life_at`); None outside the curve, on the side
        :meth:`life_place` tells ('before_curve': lower reliability.cycles_start; 'beyond_curve': extend
        cycles_stop), with :meth:`life_reach` the bound the curve allows. A target outside (0, 1) raises
        :class:`~jointwear.schema.ConfigError`."""
        target = self.target if target is None else reliability_target(target, "life: target")
        self._warn_thin_tail(target)
        cycles, r, _ = self._life_curve()
        return life_at(cycles, r, target)

    def life_place(self, target: float | None = None) -> str:
        """Where the life at ``target`` (default: the first target) lies: 'in_curve', 'before_curve' (R is at or
        below the target at the first level) or 'beyond_curve' (R stays above it to the last level), as the life
        table's ``status`` (:func:`~jointwear.study.limit_state.life_status`)."""
        target = self.target if target is None else reliability_target(target, "life_place: target")
        return life_status(self._life_curve()[1], target)

    def _warn_thin_tail(self, target: float) -> None:
        """A UserWarning when the population's ``n_mc`` samples expect fewer than ``THIN_TAIL_FAILURES`` failures at
        Pf = 1 - ``target``: the life there rests on a handful of failures (the stage's check warns of the
        configured targets; this covers the ones a user reads afterwards)."""
        expected = (1.0 - target) * self.n_mc
        if self.n_mc and expected < self.THIN_TAIL_FAILURES:
            warnings.warn(f"life at R = {target:g}: the {self.n_mc:,} Monte Carlo samples expect about {expected:.2g} "
                          f"failures at Pf = {1.0 - target:.3g} (Monte Carlo COV "
                          f"{math.sqrt(target / expected):.2g}): read life_interval, and for this target run the "
                          f"study with pf_floor <= {1.0 - target:.3g} and n_mc_max >= "
                          f"{math.ceil(self.THIN_TAIL_FAILURES / (1.0 - target)):,}", UserWarning, stacklevel=3)

    def life_interval(self, target: float | None = None) -> tuple[float | None, float | None]:
        """The 95 % interval (cycles) of the life at ``target`` (default: the first target), where the band
        R -/+ its 95 % half-width crosses it (:func:`~jointwear.study.limit_state.life_interval`) on
        :attr:`life_curve`. It is the error of the estimate of R(N) for this wear model, not the scatter of the wear
        model itself. A target outside (0, 1) raises :class:`~jointwear.schema.ConfigError`."""
        target = self.target if target is None else reliability_target(target, "life_interval: target")
        return life_interval(*self._life_curve(), target)

    def life_reach(self, target: float | None = None) -> tuple[float, float]:
        """:meth:`life_interval` with an end outside the curve given as the bound its side allows (the first level,
        the last, or an infinity: :func:`~jointwear.study.limit_state.interval_reach`), for comparing lives."""
        target = self.target if target is None else reliability_target(target, "life_reach: target")
        return interval_reach(*self._life_curve(), target)

    def largest_error(self) -> tuple[float, float] | None:
        """(error, cycles): the surrogate's largest error estimate of R over the curve's levels whose COV counts
        (Pf above ``pf_floor``), and where it is; None when no level has an estimate."""
        k = self._largest_counted(self.pf_error)
        return None if k is None else (float(self.pf_error[k]), float(self.cycles[k]))

    def largest_cov(self) -> float | None:
        """The largest COV of the Monte Carlo estimate of Pf over the levels whose COV counts (Pf above
        ``pf_floor``: a Pf of 1e-5 has a large COV that moves R by nothing)."""
        k = self._largest_counted(self.pf_cov)
        return None if k is None else float(self.pf_cov[k])

    def _largest_counted(self, values) -> int | None:
        """The level of the largest finite value among those above ``pf_floor`` (None when there is none)."""
        values = np.asarray(values, dtype=float)
        counted = np.isfinite(values) & ~np.asarray(self.below_floor, dtype=bool)
        return int(np.flatnonzero(counted)[np.argmax(values[counted])]) if counted.any() else None

    @property
    def governing_joint(self) -> str | None:
        """The judged joint with the largest share of the system's failures at the headline life (or at the
        end of the curve when the target is not reached)."""
        if not self.joints:
            return None
        if len(self.joints) == 1:
            return self.joints[0]["name"]
        shares = self.governing_shares()
        return max(shares, key=shares.get)

    def governing_shares(self) -> dict[str, float]:
        """Each judged joint's share of the system's failures at the headline life (or at the end of the curve
        when the target is not reached), read on :attr:`life_curve` (a result written before the shares were
        kept there: at the nearest level)."""
        n = self.life_cycles if self.life_cycles is not None else float(self.cycles[-1])
        fine = self.life_curve.get("cycles") if self.life_curve else None
        if fine and all("governing_share" in (j.get("curve") or {}) for j in self.joints):
            return {j["name"]: float(np.interp(n, fine, np.nan_to_num(np.asarray(j["curve"]["governing_share"],
                                                                                 dtype=float))))
                    for j in self.joints}
        k = int(np.argmin(np.abs(np.asarray(self.cycles, dtype=float) - n)))
        return {j["name"]: float(np.nan_to_num(np.asarray(j["governing_share"], dtype=float))[k]) for j in self.joints}

    def series_sentence(self) -> str:
        """With several judged joints sharing the failures at the life (a second one governs at least
        :attr:`SERIES_SHARE` of them): the system's life min_j N_f,j has a kink where their lives cross, where the
        surrogate can be confidently wrong and its interval too narrow (docs/study.md). Empty otherwise, and when the
        life was learnt one Kriging per joint, each smooth across the kink."""
        if len(self.joints) < 2 or self.life_surrogate == "per_joint":
            return ""
        shares = sorted(self.governing_shares().items(), key=lambda kv: -kv[1])
        if shares[1][1] < self.SERIES_SHARE:
            return ""
        split = ", ".join(f"{name} {100 * share:.0f} %" for name, share in shares if share > 0)
        return (f"the failures at the life are shared between judged joints ({split}): the mechanism's life, the "
                "smaller of theirs, has a kink where their lives cross, where the surrogate can be confidently wrong "
                "and the life's interval too narrow. Check the curve against the true model with jointwear validate "
                "(docs/study.md, 'How far to trust the life')")

    def to_json(self) -> dict:
        """The result as ``reliability.json`` stores it (the engine is not written)."""
        low, high = self.life_interval()
        return {
            "curve": {"cycles": np.asarray(self.cycles).tolist(), "reliability": np.asarray(self.reliability).tolist(),
                      "pf": np.asarray(self.pf).tolist(), "pf_cov": np.asarray(self.pf_cov).tolist(),
                      "pf_error_estimate": np.asarray(self.pf_error).tolist(),
                      **({} if self.pf_error_esc is None else
                         {"pf_error_esc": np.asarray(self.pf_error_esc).tolist()}),
                      "cov_waived_below_pf_floor": np.asarray(self.below_floor).tolist()},
            "life_at_target": {"target": self.target, "cycles": self.life_cycles, "hours": self.life_hours,
                               "cycles_low": low, "cycles_high": high},
            "life_table": self.life_table,
            "life_curve": self.life_curve,
            "quantity": self.quantity,
            "joints": self.joints,
            "governing_joint": self.governing_joint,
            "allowance_mm": self.joints[0]["allowance_mm"] if self.joints else self.extra.get("allowance_mm"),
            "crank_speed_rpm": self.crank_speed_rpm,
            "model_calls": self.model_calls,
            "failed_calls": self.failed_calls,
            "n_mc": self.n_mc,
            "converged": self.converged,
            "learning_stop": self.learning_stop,
            "life_surrogate": self.life_surrogate,
            "surrogate_fit": None if self.surrogate_fit is None else self.surrogate_fit.to_json(),
            "wall_seconds": self.wall_seconds,
            "variables": self.names,
            "variable_units": self.units,
            "histograms": self.histograms,
            "mean_max_wear_mm": self.mean_max_wear_mm,
            "convergence": self.convergence,
            "design": {"x": np.asarray(self.design_x).tolist(), "wear_m": np.asarray(self.design_wear).tolist(),
                       "wear_cycles": None if self.design_wear_cycles is None
                       else np.asarray(self.design_wear_cycles).tolist(),
                       "life_cycles": None if self.design_life is None else np.asarray(self.design_life).tolist(),
                       "joint_life_cycles": None if self.design_joint_lives is None else
                       {name: np.asarray(v).tolist() for name, v in self.design_joint_lives.items()}},
            "infeasible": self.infeasible,
            "provenance": self.provenance or provenance(),
            **{k: v for k, v in self.extra.items() if k not in _RELIABILITY_KEYS},
        }

    @classmethod
    def from_json(cls, data: dict) -> ReliabilityCurve:
        c = data["curve"]
        life = data.get("life_at_target", {})
        design = data.get("design", {})

        def arr(v):
            return np.asarray([np.nan if x is None else x for x in v], dtype=float)

        return cls(
            cycles=arr(c["cycles"]), reliability=arr(c["reliability"]),
            pf=arr(c["pf"]) if "pf" in c else 1.0 - arr(c["reliability"]),
            pf_cov=arr(c.get("pf_cov", [None] * len(c["cycles"]))),
            below_floor=np.asarray(c.get("cov_waived_below_pf_floor", [False] * len(c["cycles"])), dtype=bool),
            pf_error=arr(c.get("pf_error_estimate", [np.nan] * len(c["cycles"]))),
            pf_error_esc=arr(c["pf_error_esc"]) if "pf_error_esc" in c else None,
            target=life.get("target"), life_cycles=life.get("cycles"), life_hours=life.get("hours"),
            model_calls=data.get("model_calls", 0), failed_calls=data.get("failed_calls", 0),
            n_mc=data.get("n_mc", 0), converged=data.get("converged", False),
            wall_seconds=data.get("wall_seconds", math.nan), names=data.get("variables", []),
            units=data.get("variable_units", []),
            histograms=data.get("histograms", {}), mean_max_wear_mm=data.get("mean_max_wear_mm", {}),
            convergence=data.get("convergence", {}),
            design_x=np.asarray(design.get("x", []), dtype=float),
            design_wear=np.asarray(design.get("wear_m", []), dtype=float),
            design_life=None if design.get("life_cycles") is None else arr(design["life_cycles"]),
            design_joint_lives=None if design.get("joint_life_cycles") is None else
            {name: arr(v) for name, v in design["joint_life_cycles"].items()},
            design_wear_cycles=None if design.get("wear_cycles") is None else arr(design["wear_cycles"]),
            life_table=data.get("life_table", []), quantity=data.get("quantity", "bearing_max_depth"),
            joints=data.get("joints", []), crank_speed_rpm=data.get("crank_speed_rpm"),
            infeasible=data.get("infeasible", {}), learning_stop=data.get("learning_stop", ""),
            surrogate_fit=SurrogateFit.from_json(data.get("surrogate_fit")), provenance=data.get("provenance", {}),
            life_surrogate=data.get("life_surrogate", "system_life"), life_curve=data.get("life_curve", {}),
            extra={k: v for k, v in data.items() if k not in _RELIABILITY_KEYS})

    def joint_curves(self) -> dict[str, tuple[np.ndarray, np.ndarray | None]]:
        """Each judged joint's own R(N) and its 95 % half-width (None in results written without it), with several
        judged joints, on :attr:`life_curve`'s cycles where the result has it (:meth:`fine_curve`), else at the
        levels; empty with one."""
        return {name: (r, half) for name, _cycles, r, half in self._joint_points()}

    def _joint_points(self) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray | None]]:
        """(name, cycles, R, 95 % half-width or None) of each judged joint with several, on :attr:`life_curve`'s
        cycles where the joint has its curve there, else at the levels."""
        if len(self.joints) < 2:
            return []
        fine = self.fine_curve()
        out = []
        for j in self.joints:
            on_fine = "curve" in j and fine is not None
            source = j["curve"] if on_fine else j
            half = source.get("half_width_95")
            out.append((j["name"], fine[0] if on_fine else np.asarray(self.cycles, dtype=float),
                        np.asarray(source["reliability"], dtype=float),
                        None if half is None else np.asarray(half, dtype=float)))
        return out

    def joint_lives(self, target: float | None = None) -> dict[str, tuple[float | None, float | None, float | None]]:
        """Each judged joint's own life at ``target`` (default: the first target), as if it were the only one judged,
        with its 95 % interval: (life, low, high) read on its own R(N) as :meth:`life` reads the system's (None
        outside the curve, or where the result holds no band); empty with one judged joint."""
        target = self.target if target is None else reliability_target(target, "joint_lives: target")
        out = {}
        for name, cycles, r, half in self._joint_points():
            low, high = (None, None) if half is None else life_interval(cycles, r, half, target)
            out[name] = (life_at(cycles, r, target), low, high)
        return out

    def tables(self) -> dict[str, dict[str, Any]]:
        """``reliability_curve`` (R, Pf, its COV and error and R's 95 % half-width at every level; each joint's R
        and share with several), ``life_table`` (the life at each target and its 95 % interval; with several judged
        joints each one's own, :meth:`joint_lives`) and
        ``design_points`` (the true-model calls: inputs in SI, each column named with its unit as a config key,
        ``Rj_m``; the life each gave)."""
        curve = {"cycles": np.asarray(self.cycles, dtype=np.int64), "reliability": self.reliability, "pf": self.pf,
                 "pf_cov": self.pf_cov, "pf_error_estimate": self.pf_error,
                 **({} if self.pf_error_esc is None else {"pf_error_esc": self.pf_error_esc}),
                 "half_width_95": self.half_width}
        for j in self.joints if len(self.joints) > 1 else []:
            curve[f"reliability_{j['name']}"] = j["reliability"]
            if "half_width_95" in j:  # results written before the joints had a band have none
                curve[f"half_width_95_{j['name']}"] = j["half_width_95"]
            curve[f"governing_share_{j['name']}"] = j["governing_share"]
        intervals = [self.life_interval(r["target"]) for r in self.life_table]
        lives = {"target_reliability": [r["target"] for r in self.life_table],
                 "life_cycles": [r["cycles"] for r in self.life_table],
                 "life_hours": [r["hours"] for r in self.life_table],
                 "status": [r.get("status", "") for r in self.life_table],
                 "life_cycles_low": [low for low, _ in intervals],
                 "life_cycles_high": [high for _, high in intervals]}
        per_joint = [self.joint_lives(r["target"]) for r in self.life_table]
        for name in per_joint[0] if per_joint else ():
            for suffix, i in (("", 0), ("_low", 1), ("_high", 2)):
                lives[f"life_cycles_{name}{suffix}"] = [row[name][i] for row in per_joint]
        out = {"reliability_curve": curve, "life_table": lives}
        x = np.atleast_2d(np.asarray(self.design_x, dtype=float))
        if x.size:
            names = self.names[:x.shape[1]]
            units = [*self.units, *[""] * len(names)]  # a result without units (read from an older file): bare names
            cols: dict[str, Any] = {column_name(name, unit): x[:, k]
                                    for k, (name, unit) in enumerate(zip(names, units))}
            if self.design_life is not None:
                cols["life_cycles"] = self.design_life
            for name, lives in (self.design_joint_lives or {}).items():
                cols[f"life_cycles_{name}"] = lives
            out["design_points"] = cols
        return out

    def plot(self) -> Figure:
        """R(N) with its 95 % band, the target and the life with its interval, each judged joint's own curve beside
        (the report's figure): a matplotlib ``Figure``, for a notebook or ``fig.savefig``."""
        from jointwear.report import figures as F

        return F.reliability_curve_figure(
            self.cycles, self.reliability, pf_cov=self.pf_cov, pf_error=self.pf_error, target=self.target,
            life_cycles=self.life_cycles, life_interval=None if self.life_cycles is None else self.life_interval(),
            joints=self.joint_curves() or None, fine=self.fine_curve())

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``reliability.json``, the CSV tables (:meth:`tables`) and the figures."""
        folder = Path(folder)
        self.write_tables(folder)
        if figures:
            from jointwear.report import figures as F

            save_figure(self.plot(), folder / "reliability_curve.png")
            h = self.histograms
            if h.get("cycles"):
                limit = self.joints[0]["allowance_mm"] if self.joints else None
                save_figure(F.wear_histograms_figure(h["cycles"], h["max_wear_mm"], limit_mm=limit),
                         folder / "wear_histograms.png")
            conv = self.convergence
            if conv.get("n_calls"):
                save_figure(F.convergence_figure(conv["n_calls"], conv["pf"], cov=conv.get("cov"),
                                              label=f"Pf at {conv.get('cycles'):,} cycles"),
                         folder / "convergence.png")
        return self.write(folder)  # last: a result whose JSON is there is whole


_RELIABILITY_KEYS = frozenset({
    "curve", "life_at_target", "life_table", "quantity", "joints", "governing_joint", "allowance_mm",
    "crank_speed_rpm", "model_calls", "failed_calls", "n_mc", "converged", "learning_stop", "surrogate_fit",
    "wall_seconds", "life_surrogate", "life_curve",
    "variables", "variable_units", "histograms", "mean_max_wear_mm", "convergence", "design", "infeasible",
    "provenance"})


# ------------------------------------------------------------------------------------------------ sensitivity
def scatter_sentence(sobol: Mapping, floor: float = 0.005) -> str:
    """'the wear's call-to-call scatter holds 7 % of its variance, which no input does: the indices are shares of the
    rest (the surrogate's mean wear), a variable's share of the whole is its index x 0.93'; '' where the scatter's
    share (``sobol['scatter_share']``, sensitivity.json) is below ``floor`` or not recorded."""
    share = sobol.get("scatter_share")
    if share is None or not share >= floor:
        return ""
    return (f"the wear's call-to-call scatter holds {100 * share:.0f} % of its variance, which no input does: the "
            "indices are shares of the rest (the surrogate's mean wear), a variable's share of the whole is its "
            f"index x {1.0 - share:.2g}")


@dataclass(repr=False, eq=False)  # StageResult compares by value
class SensitivityResult(StageResult):
    """How the reliability at ``cycles`` moves with each variable: mean shifts (``variables`` rows with
    ``reliability_low``/``reliability_high`` and their error estimates), the ranking overall and per group
    (``unresolved_pairs``: neighbours the surrogate's error does not separate), Sobol' indices of the wear
    and reliability derivatives. A row's ``dR_dmean`` / ``dR_dstd`` are per SI unit of the variable (its ``unit``, ""
    for a plain number) and its ``elasticity_mean`` is that of R, (mu / R) dR/dmu; ``derivatives`` holds those of Pf
    (``elasticity_mean``: (mu / Pf) dPf/dmu)."""

    FILE: ClassVar[str] = "sensitivity.json"

    cycles: int
    factors: list[float]
    reliability_nominal: float
    variables: list[dict]
    ranking: list[str]
    ranking_by_group: dict
    sobol: dict
    reliability_nominal_error: float | None = None
    unresolved_pairs: list[dict] = field(default_factory=list)
    rules: list[dict] = field(default_factory=list)
    archard_checks: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    extra_model_calls: int = 0
    derivatives: dict = field(default_factory=dict)
    n_population: int = 0
    wall_seconds: float | None = None
    provenance: dict = field(default_factory=provenance)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    @property
    def shifts_move_reliability(self) -> bool:
        """Whether any mean shift changes R at ``cycles``. False where R is 0 or 1 whatever the shift (a level far
        outside the wear's scatter): the ranking then says nothing, only the Sobol' indices of the wear do."""
        r0 = self.reliability_nominal
        return any(abs(v["reliability_low"] - r0) > 0 or abs(v["reliability_high"] - r0) > 0 for v in self.variables)

    def far_shifts(self) -> list[dict]:
        """The rules of the mean shifts too far for the surrogate, read from true-model runs of the shifted nominal
        mechanism (rule ``separable_scaling``)."""
        return [r for r in self.rules if r.get("rule") == "separable_scaling"]

    def unbuilt_shifts(self) -> list[dict]:
        """Those of :meth:`far_shifts` whose shifted mechanism could not be built or run (no wear ratio; their R is
        counted as 0)."""
        return [r for r in self.far_shifts() if r.get("wear_ratio") is None]

    def unbuilt_shifts_sentence(self) -> str:
        """The mean shifts whose shifted nominal mechanism could not be built or run (their R is counted as 0, which
        measures the mechanism's failure to work, not the wear's sensitivity); empty when there are none."""
        failed = self.unbuilt_shifts()
        if not failed:
            return ""

        def why(reason) -> str:  # the model's own words, without the wrapping the rule's record adds
            text = " ".join(str(reason or "").split())
            return text.split("infeasible sample: ", 1)[-1]

        shifts = "; ".join(f"{r['variable']} x {float(r['factor']):g} ({why(r.get('reason'))})" for r in failed)
        return (f"the shifted mechanism could not be built or run for {shifts}: its R is counted as 0, which measures "
                "the mechanism's failure to work, not the wear's sensitivity; read those ranks with that in mind")

    #: a far shift's wear ratio beyond this factor either way: the shifted mechanism moves otherwise
    EXTREME_WEAR_RATIO = 10.0

    def extreme_shifts(self) -> list[dict]:
        """Those of :meth:`far_shifts` whose wear changes more than ``EXTREME_WEAR_RATIO``-fold either way: the
        shifted mechanism moves otherwise (near a dead point, in impacts), a change of design rather than a
        sensitivity."""
        bar = self.EXTREME_WEAR_RATIO
        return [r for r in self.far_shifts() if r.get("wear_ratio") is not None
                and not 1.0 / bar <= float(r["wear_ratio"]) <= bar]

    def extreme_shifts_sentence(self) -> str:
        """:meth:`extreme_shifts` told; empty when there are none."""
        extreme = self.extreme_shifts()
        if not extreme:
            return ""

        def ratio(x: float) -> str:
            return f"{x:,.0f}" if x >= 10 else f"{x:.3g}"

        shifts = "; ".join(f"{r['variable']} x {float(r['factor']):g} (wear x {ratio(float(r['wear_ratio']))})"
                           for r in extreme)
        return (f"the shifted mechanism's wear differs from the nominal's more than {self.EXTREME_WEAR_RATIO:g}-fold "
                f"for {shifts}: it moves otherwise (near a dead point, in impacts), so its R measures that change of "
                "design, not the wear's sensitivity to the variable")

    def variance_ranking(self, floor: float = 0.01) -> list[tuple[str, float]]:
        """The variables whose scatter drives the scatter of the (first judged joint's) wear: (name, total Sobol'
        index) of those with an index of at least ``floor``, largest first; empty without indices. The ranking of the
        mean shifts measures something else: a change of the nominal design, not of a variable's scatter."""
        names, totals = self.sobol.get("names") or [], self.sobol.get("ST") or []
        ranked = [(str(n), float(st)) for n, st in zip(names, totals) if st is not None and float(st) >= floor]
        return sorted(ranked, key=lambda item: -item[1])

    def scatter_sentence(self) -> str:
        """:func:`scatter_sentence` of this result's Sobol' indices."""
        return scatter_sentence(self.sobol)

    @classmethod
    def from_json(cls, data: dict) -> SensitivityResult:
        data = dict(data)
        if "ranking" not in data and "variables" in data and "reliability_nominal" in data:
            r0 = data["reliability_nominal"]
            swing = {v["name"]: max(abs(v["reliability_low"] - r0), abs(v["reliability_high"] - r0))
                     for v in data["variables"]}
            data["ranking"] = sorted(swing, key=lambda n: -swing[n])
        data.setdefault("ranking_by_group", {})
        data.setdefault("sobol", {})
        data.setdefault("factors", [0.8, 1.2])
        return super().from_json(data)

    def _shift_entry(self, name: str, factor: float) -> dict:
        """The record of the reliability with ``name``'s mean x ``factor`` in :attr:`rules` (empty where none is)."""
        return next((r for r in self.rules if r.get("variable") == name
                     and math.isclose(float(r.get("factor", math.nan)), factor, rel_tol=1e-9)), {})

    def shift_rule(self, name: str, factor: float) -> str | None:
        """How the reliability with ``name``'s mean x ``factor`` was read: "surrogate" (on the learnt surrogate),
        "archard_scaling" (the nominal population's lives scaled by Archard's law) or "separable_scaling" (the
        wear ratio of two true-model runs); None where no rule is recorded."""
        return self._shift_entry(name, factor).get("rule")

    def shift_not_run(self, name: str, factor: float) -> bool:
        """Whether the mechanism with ``name``'s mean x ``factor`` could not run (its R = 0 counts it as failing;
        the rule's ``reason`` says why)."""
        return bool(self._shift_entry(name, factor).get("reason"))

    def tables(self) -> dict[str, dict[str, Any]]:
        """``sensitivity``: one row per variable (its unit, the shifted reliabilities with the factor and the rule
        each was read by, R at ``cycles`` unshifted, derivatives, Sobol'; with several judged joints also each
        joint's own Sobol' indices of its wear, ``S1_<joint>`` and ``ST_<joint>``)."""
        keys = ["name", "label", "group", "unit", "reliability_low", "reliability_high", "reliability_low_error",
                "reliability_high_error", "dR_dmean", "dR_dmean_error", "dR_dstd", "elasticity_mean", "S1", "ST"]
        table = {k: [v.get(k) for v in self.variables] for k in keys}
        low, high = (float(f) for f in self.factors)
        n = len(self.variables)
        table |= {"cycles": [self.cycles] * n, "reliability_nominal": [self.reliability_nominal] * n,
                  "factor_low": [low] * n, "factor_high": [high] * n,
                  "rule_low": [self.shift_rule(v["name"], low) for v in self.variables],
                  "rule_high": [self.shift_rule(v["name"], high) for v in self.variables]}
        for joint, indices in (self.sobol.get("by_joint") or {}).items():
            by_name = dict(zip(indices.get("names") or [], zip(indices.get("S1") or [], indices.get("ST") or [])))
            table[f"S1_{joint}"] = [by_name.get(v["name"], (None, None))[0] for v in self.variables]
            table[f"ST_{joint}"] = [by_name.get(v["name"], (None, None))[1] for v in self.variables]
        return {"sensitivity": table}

    def plot(self, variables: list[dict] | None = None, title: str | None = None) -> Figure:
        """The reliability at ``cycles`` with each variable's mean moved by ``factors`` (the tornado), each shifted R
        with its 95 % error and the shifts that could not run hatched: a matplotlib ``Figure``, for a notebook or
        ``fig.savefig``. ``variables``: some of :attr:`variables` (all by default; the report draws one group)."""
        from jointwear.report import figures as F

        v = self.variables if variables is None else variables
        lo, hi = self.factors
        return F.tornado_figure([str(x.get("label") or x["name"]) for x in v], [x["reliability_low"] for x in v],
                                [x["reliability_high"] for x in v], self.reliability_nominal, cycles=self.cycles,
                                title=title, low_label=f"mean \u00d7 {lo:g}", high_label=f"mean \u00d7 {hi:g}",
                                error_low=[x.get("reliability_low_error") or 0.0 for x in v],
                                error_high=[x.get("reliability_high_error") or 0.0 for x in v],
                                not_run_low=[self.shift_not_run(x["name"], lo) for x in v],
                                not_run_high=[self.shift_not_run(x["name"], hi) for x in v])

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``sensitivity.json``, ``sensitivity.csv`` (:meth:`tables`) and the figures."""
        folder = Path(folder)
        self.write_tables(folder)
        if figures:
            from jointwear.report import figures as F

            save_figure(self.plot(), folder / "sensitivity_tornado.png")
            s = self.sobol
            if s.get("names"):
                save_figure(F.sobol_figure(s["names"], s["S1"], s["ST"], S1_conf=s.get("S1_conf"),
                                        ST_conf=s.get("ST_conf"),
                                        output=s.get("output") or f"wear at {self.cycles:,} cycles"),
                         folder / "sensitivity_sobol.png")
        return self.write(folder)  # last: a result whose JSON is there is whole


# ------------------------------------------------------------------------------------------------- validation
@dataclass(repr=False, eq=False)  # StageResult compares by value
class ValidationResult(StageResult):
    """The surrogate's R(N) against the true model sampled directly (``jointwear validate``).

    At every level of the curve: ``reliability_mc`` from ``n_samples`` true-model calls on fresh samples, its
    exact binomial 95 % interval [``ci_low``, ``ci_high``], the surrogate's ``reliability_surrogate`` with its
    error estimate (``surrogate_error``, absolute) and COV, and whether the two agree within their combined
    95 % half-widths (``agreement``: the two intervals overlap; :meth:`differs_at_95` is the stricter 95 % test of
    their difference). ``cross_validation``: leave-one-out predictions of the design points'
    log life against their true values, with Q^2. ``model_calls``: the true-model calls this run made (samples read
    back from the evaluation store are not counted; run metadata, as the wall time: a resumed validation equals an
    uninterrupted one). ``life_table``: at each target of the study, the life read on
    the true model's curve (``cycles``) with the interval where its exact 95 % bounds cross the target
    (``cycles_low``, ``cycles_high``), the surrogate's life and interval (``surrogate_cycles``,
    ``surrogate_cycles_low``, ``surrogate_cycles_high``) and whether the two intervals overlap (``agree``).
    ``joints`` (several judged joints): each joint's own R(N) on the same samples against the study's
    (:func:`jointwear.study.validation.joint_checks`). ``sample_x``: the samples the true model ran on, in SI
    (columns in the order of ``names``, units in ``units``, as the reliability's ``design_x``), and ``sample_life``
    the life each gave in cycles (NaN for a failed call): the direct Monte Carlo itself, for estimators of one's own
    (table ``validation_samples``; results written before they were kept hold None).
    """

    FILE: ClassVar[str] = "validation.json"
    RUN_METADATA: ClassVar[frozenset[str]] = StageResult.RUN_METADATA | {"model_calls"}
    ALIGNED: ClassVar[tuple[tuple[str, ...], ...]] = (
        ("cycles", "reliability_mc", "ci_low", "ci_high", "reliability_surrogate", "surrogate_error", "agreement",
         "paired_reliability_surrogate", "paired_difference_low", "paired_difference_high"),)

    cycles: np.ndarray
    reliability_mc: np.ndarray
    ci_low: np.ndarray
    ci_high: np.ndarray
    reliability_surrogate: np.ndarray
    surrogate_error: np.ndarray
    n_samples: int
    model_calls: int
    wall_seconds: float
    agreement: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    surrogate_cov: np.ndarray = field(default_factory=lambda: np.zeros(0))
    failed_calls: int = 0
    seed: int | None = None
    cross_validation: dict = field(default_factory=dict)
    life_table: list[dict] = field(default_factory=list)
    joints: list[dict] = field(default_factory=list)
    paired_reliability_surrogate: np.ndarray | None = None
    paired_difference_low: np.ndarray | None = None
    paired_difference_high: np.ndarray | None = None
    names: list[str] = field(default_factory=list)
    units: list[str] = field(default_factory=list)
    sample_x: np.ndarray | None = None
    sample_life: np.ndarray | None = None
    provenance: dict = field(default_factory=provenance)
    extra: dict = field(default_factory=dict, repr=False, metadata={"json": False})

    def __post_init__(self) -> None:
        """The curves as arrays (as ReliabilityCurve's), built or read back from JSON (lists with null holes)."""
        self.cycles = np.array(self.cycles, dtype=np.int64)  # copies: never a view of the reliability's arrays
        if self.sample_x is not None:
            self.sample_x = np.array(self.sample_x, dtype=float)
        if self.sample_life is not None:
            self.sample_life = np.array(self.sample_life, dtype=float)
        for name in ("reliability_mc", "ci_low", "ci_high", "reliability_surrogate", "surrogate_error",
                     "surrogate_cov"):
            setattr(self, name, np.array(getattr(self, name), dtype=float))
        for name in ("paired_reliability_surrogate", "paired_difference_low", "paired_difference_high"):
            if getattr(self, name) is not None:
                setattr(self, name, np.array(getattr(self, name), dtype=float))
        self.agreement = np.array(self.agreement, dtype=bool)

    @property
    def paired(self) -> bool:
        """Whether the surrogate was also read on the validation's own samples (a study whose surrogate was in memory:
        ``jointwear validate`` and ``Study.validate`` always)."""
        return self.paired_reliability_surrogate is not None

    def paired_difference(self) -> np.ndarray | None:
        """R of the surrogate on the validation's samples less the true model's on the same samples, at each level:
        the surrogate's own error, without the sampling noise the two share (its 95 % bounds:
        ``paired_difference_low``, ``paired_difference_high``, bootstrap percentiles)."""
        return None if not self.paired else self.paired_reliability_surrogate - self.reliability_mc

    def paired_life_sentence(self, target: float | None = None) -> str:
        """'on the same samples the surrogate's life at R = 0.9 is 374,413 cycles, 1.8 % below the true model's 381,429
        (95 % interval -2.3 % to -1.3 %)' from the life table's paired columns (the first target by default); ''
        without them. The surrogate's life here is read on the validation's samples, not the study's life."""
        rows = [r for r in self.life_table if target is None or r.get("target") == target][:1]
        if not rows or rows[0].get("paired_ratio") is None or rows[0].get("paired_surrogate_cycles") is None:
            return ""
        row = rows[0]
        ratio, low, high = row["paired_ratio"], row.get("paired_ratio_low"), row.get("paired_ratio_high")
        side = "below" if ratio < 0 else "above"
        bounds = ("" if low is None or high is None
                  else f" (95 % interval {signed_percent(low)} to {signed_percent(high)})")
        return (f"on the same samples the surrogate's life at R = {row['target']:g} is "
                f"{row['paired_surrogate_cycles']:,.0f} cycles, {100 * abs(ratio):.1f} % {side} the true model's "
                f"{row['cycles']:,.0f}{bounds}")

    def unpaired_life_sentence(self, target: float | None = None) -> str:
        """Why the paired reading of the life at ``target`` (the first target by default) is missing, where the
        paired curve is there: 'on the same samples the surrogate's life lies before the curve's first level at
        R = 0.9, ...'; '' otherwise (a validation of 100 samples said nothing of it)."""
        rows = [r for r in self.life_table if target is None or r.get("target") == target][:1]
        if not rows or not self.paired or "paired_ratio" not in rows[0] or (  # not tried: too few samples
                rows[0]["paired_ratio"] is not None and rows[0].get("paired_surrogate_cycles") is not None):
            return ""
        where = [OUTSIDE_CURVE.get(life_status(r, rows[0]["target"]), ("",))[0]
                 for r in (self.paired_reliability_surrogate, self.reliability_mc)]
        whose = ("the surrogate's and the true model's lives lie" if where[0] and where[1] else
                 "the surrogate's life lies" if where[0] else "the true model's life lies")
        side = where[0] or where[1]
        return (f"on the same samples {whose} {side} at R = {rows[0]['target']:g}, so the two lives are not compared "
                "(a curve that starts or ends further would compare them)" if side else "")

    def paired_life_allowed(self, target: float | None = None) -> tuple[float, float, str] | None:
        """What the study's life interval allows of the paired ratio (surrogate / true - 1 for a true life anywhere in
        [``surrogate_cycles_low``, ``_high``]: life / high - 1 to life / low - 1), and where the paired ratio's 95 %
        interval lies: 'within' it, 'beyond' it (the life errs by more than its interval says) or 'unresolved'
        (across its edge: these samples cannot tell); None without the numbers."""
        rows = [r for r in self.life_table if target is None or r.get("target") == target][:1]
        keys = ("surrogate_cycles", "surrogate_cycles_low", "surrogate_cycles_high", "paired_ratio_low",
                "paired_ratio_high")
        if not rows or any(rows[0].get(k) is None for k in keys):
            return None
        life, low, high, r_low, r_high = (float(rows[0][k]) for k in keys)
        allowed = (life / high - 1.0, life / low - 1.0)
        verdict = ("beyond" if r_high < allowed[0] or r_low > allowed[1]
                   else "within" if allowed[0] <= r_low and r_high <= allowed[1] else "unresolved")
        return allowed[0], allowed[1], verdict

    def paired_within_error(self) -> np.ndarray | None:
        """Where the paired difference's 95 % interval reaches within the surrogate's own error estimate (+-
        ``surrogate_error``): the error estimate is not refuted there. False where the surrogate errs by more than it
        says."""
        if not self.paired:
            return None
        error = np.nan_to_num(self.surrogate_error, nan=0.0, posinf=1.0)
        return (self.paired_difference_low <= error) & (self.paired_difference_high >= -error)

    def paired_inside_error(self) -> np.ndarray | None:
        """Where the paired difference's whole 95 % interval lies inside +- the surrogate's error estimate: the
        estimate is shown to hold there (:meth:`paired_within_error` asks only that it is not refuted)."""
        if not self.paired:
            return None
        error = np.nan_to_num(self.surrogate_error, nan=0.0, posinf=1.0)
        return (self.paired_difference_low >= -error) & (self.paired_difference_high <= error)

    def paired_verdict(self) -> np.ndarray | None:
        """The paired check's degree at each level, as the report classifies it: 'inside' (the paired difference's
        95 % interval lies within +- the surrogate's error estimate: the estimate holds), 'reaches' (it only
        overlaps +- the estimate: not refuted, not shown) or 'exceeds' (it lies beyond: the surrogate errs by more
        than it says); None unpaired."""
        if not self.paired:
            return None
        return np.where(self.paired_inside_error(), "inside", np.where(self.paired_within_error(), "reaches",
                                                                         "exceeds"))

    def paired_error_ratio(self) -> np.ndarray | None:
        """The absolute difference of surrogate and true model on the same samples over the surrogate's error estimate,
        per level: above 1 the surrogate errs by more than it says (nan where it gives no finite, positive
        estimate)."""
        if not self.paired:
            return None
        error = np.asarray(self.surrogate_error, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.abs(self.paired_difference()) / error
        return np.where(np.isfinite(error) & (error > 0.0), ratio, np.nan)

    def paired_error_sentence(self) -> str:
        """'on the same samples the curve's difference from the true model lies inside its error estimate at 7 of 11
        levels, reaches it at 3 more and exceeds it at 1; the largest is 1.3 times the estimate (at 45,000 cycles)':
        a calibration of the error estimate, told by the three degrees of the paired check; '' unpaired."""
        if not self.paired:
            return ""
        inside, within = self.paired_inside_error(), self.paired_within_error()
        n, n_in, n_within = inside.size, int(inside.sum()), int(within.sum())
        text = (f"on the same samples the curve's difference from the true model lies inside its error estimate at "
                f"{n_in} of {n} levels (its 95 % interval within +- the estimate)")
        if n_within > n_in:
            text += f", reaches it at {n_within - n_in} more"
        if n > n_within:
            text += f", {'and ' if n_within > n_in else ''}exceeds it at {n - n_within}"
        ratio = self.paired_error_ratio()
        if np.isfinite(ratio).any() and np.nanmax(ratio) > 1.0:
            k = int(np.nanargmax(ratio))
            text += f"; the largest is {ratio[k]:.2g} times the estimate (at {self.cycles[k]:,.0f} cycles)"
        return text

    def disagreement(self, shown: int = 3) -> str:
        """'not at 40,000 cycles: true model 0.683 [0.550, 0.797], surrogate 0.499 (its error estimate 0.031)': the
        levels where the true model's interval and the curve's do not overlap (the first ``shown`` of them); ''
        where all agree."""
        missed = [k for k, ok in enumerate(self.agreement) if not ok]
        if not missed:
            return ""

        def error(k):
            e = float(self.surrogate_error[k])
            return f" (its error estimate {e:.3f})" if math.isfinite(e) else ""

        levels = ", ".join(f"{self.cycles[k]:,.0f} cycles: true model {self.reliability_mc[k]:.3f} "
                           f"[{self.ci_low[k]:.3f}, {self.ci_high[k]:.3f}], surrogate "
                           f"{self.reliability_surrogate[k]:.3f}{error(k)}" for k in missed[:shown])
        more = f" and {len(missed) - shown} more" if len(missed) > shown else ""
        return f"not at {levels}{more}"

    @property
    def resolution(self) -> float:
        """The widest 95 % half-width of the direct estimate of R over the levels: differences from the surrogate
        smaller than this cannot be seen with these samples."""
        return max((max(r - lo, hi - r) for r, lo, hi in zip(self.reliability_mc, self.ci_low, self.ci_high)),
                   default=float("nan"))

    @property
    def surrogate_half_width(self) -> np.ndarray:
        """The curve's 95 % half-width at each level as the agreement test reads it: Monte Carlo 1.96 COV Pf plus
        its error estimate (:func:`~jointwear.study.limit_state.curve_half_width`)."""
        r_sur = np.asarray(self.reliability_surrogate, dtype=float)
        cov = self.surrogate_cov if self.surrogate_cov.size == r_sur.size else np.zeros_like(r_sur)
        return curve_half_width(1.0 - r_sur, cov, np.nan_to_num(self.surrogate_error, nan=0.0))

    def differs_at_95(self) -> np.ndarray:
        """Where a 95 % test of the difference rejects the surrogate's R: ``abs(R_true - R_surrogate)`` exceeds the
        root sum of squares of the three 95 % half-widths (the true model's exact interval on the surrogate's side, the
        curve's Monte Carlo 1.96 COV Pf, its error estimate), each error taken as independent. :attr:`agreement`
        asks only that the two intervals overlap, a lenient test (about 99.4 % for two errors of equal width)."""
        r, r_sur = self.reliability_mc, self.reliability_surrogate
        true_half = np.where(r_sur > r, self.ci_high - r, r - self.ci_low)
        cov = self.surrogate_cov if self.surrogate_cov.size == r.size else np.zeros_like(r)
        mc_half = curve_half_width(1.0 - r_sur, cov)  # the curve's Monte Carlo part alone
        error = np.nan_to_num(self.surrogate_error, nan=0.0, posinf=1.0)
        return np.abs(r - r_sur) > np.sqrt(true_half**2 + mc_half**2 + error**2)

    def differences_at_95(self) -> str:
        """'a 95 % test of the difference rejects 950,000 and 1,000,000 cycles' where :meth:`differs_at_95`; ''
        where it rejects none."""
        levels = [f"{c:,.0f}" for c, d in zip(self.cycles, self.differs_at_95()) if d]
        if not levels:
            return ""
        where = levels[0] if len(levels) == 1 else ", ".join(levels[:-1]) + f" and {levels[-1]}"
        return f"a 95 % test of the difference rejects {where} cycles"

    @property
    def all_agree(self) -> bool:
        """Whether the surrogate's R agrees with the direct Monte Carlo's at every level (``agreement``)."""
        return bool(np.all(self.agreement))

    def tables(self) -> dict[str, dict[str, Any]]:
        """``validation`` (the direct Monte Carlo against the surrogate at every level), ``validation_life`` (the
        life at each target on both curves, with their intervals), ``validation_samples`` (each sample's inputs in
        SI, columns named as config keys with their unit, ``Rj_m``, and the life it gave, ``life_cycles``) and, when
        computed, ``cross_validation`` (leave-one-out log lives of the design points)."""
        out = {"validation": {
            "cycles": self.cycles, "reliability_mc": self.reliability_mc, "ci_low": self.ci_low,
            "ci_high": self.ci_high, "reliability_surrogate": self.reliability_surrogate,
            "surrogate_error": self.surrogate_error, "surrogate_half_width_95": self.surrogate_half_width,
            "agreement": self.agreement, "differs_at_95": self.differs_at_95()}}
        if self.paired:
            out["validation"].update({
                "reliability_surrogate_same_samples": self.paired_reliability_surrogate,
                "paired_difference": self.paired_difference(), "paired_difference_low": self.paired_difference_low,
                "paired_difference_high": self.paired_difference_high,
                "paired_within_error": self.paired_within_error(), "paired_verdict": self.paired_verdict()})
        if self.life_table:
            keys = dict.fromkeys(key for row in self.life_table for key in row)  # an untestable row adds its note
            out["validation_life"] = {key: [row.get(key) for row in self.life_table] for key in keys}
        cv = self.cross_validation
        if cv.get("log_life_true"):
            out["cross_validation"] = {"log_life_true": cv["log_life_true"], "log_life_loo": cv["log_life_loo"],
                                       "log_life_loo_sd": cv["log_life_loo_sd"]}
        if self.sample_x is not None and self.sample_life is not None and self.sample_x.ndim == 2:
            out["validation_samples"] = {
                **{column_name(name, unit): self.sample_x[:, k]
                   for k, (name, unit) in enumerate(zip(self.names, [*self.units, *[""] * len(self.names)]))},
                "life_cycles": self.sample_life}
        if self.joints:  # one row per joint and level
            out["validation_joints"] = {
                "joint": [j["name"] for j in self.joints for _ in self.cycles],
                "cycles": np.tile(self.cycles, len(self.joints)),
                **{key: np.concatenate([np.asarray(j[key], dtype=bool if key == "agreement" else float)
                                     for j in self.joints])
                   for key in ("reliability_mc", "ci_low", "ci_high", "reliability_surrogate", "surrogate_half_width",
                               "agreement") if all(key in j for j in self.joints)}}
        return out

    def to_json(self) -> dict:
        """The fields, and the two verdicts' inputs the report shows: the curve's 95 % half-width at each level
        (:attr:`surrogate_half_width`) and the stricter test (:meth:`differs_at_95`); derived, so written fresh."""
        return {**super().to_json(), "surrogate_half_width_95": self.surrogate_half_width.tolist(),
                "differs_at_95": self.differs_at_95().tolist()}

    def plot(self) -> Figure:
        """The surrogate's R(N) with its band against the true model's with its exact interval (the report's figure): a
        matplotlib ``Figure``, for a notebook or ``fig.savefig``."""
        from jointwear.report import figures as F

        return F.validation_figure(self.cycles, self.reliability_mc, self.ci_low, self.ci_high,
                                   self.reliability_surrogate, self.surrogate_half_width, n_samples=self.n_samples)

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``validation.json``, the CSV tables (:meth:`tables`) and the figures."""
        folder = Path(folder)
        self.write_tables(folder)
        cv = self.cross_validation
        if figures:
            from jointwear.report import figures as F

            save_figure(self.plot(), folder / "validation.png")
            if cv.get("log_life_true"):
                save_figure(F.cross_validation_figure(cv["log_life_true"], cv["log_life_loo"], cv["log_life_loo_sd"],
                                                   q2=cv.get("q2")), folder / "cross_validation.png")
        return self.write(folder)  # last: a result whose JSON is there is whole
