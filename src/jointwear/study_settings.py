"""Settings of the study stages that join wear and reliability (validated at the config boundary).

Each field that the paper leaves open has a default and says where it comes from. SI units inside
(wear allowance in metres); cycle counts are plain numbers of crank revolutions.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator, model_validator

from jointwear.schema import F, SIModel
from jointwear.wear.settings import MAX_WEAR_CYCLES

#: Upper bounds of the sizes a config asks for, checked when it is loaded (``jointwear check`` fails fast on them
#: instead of allocating): each is far above any real study and below what would exhaust a workstation's memory.
#: A Monte Carlo population holds 8 bytes per random variable per sample (1e8 samples of 8 variables: 6.4 GB).
MAX_MC_SAMPLES = 100_000_000
#: Levels of the R(N) curve (its grid plus the histogram levels): every level holds a Pf estimate over the whole
#: population, and a level count in the millions only builds the grid for minutes (the defaults give 11).
MAX_CURVE_LEVELS = 1_000
#: Saltelli base sample size: the Sobol' design holds N (d + 2) points of d variables (2**20 with 8 variables: 670 MB).
MAX_SOBOL_BASE_SAMPLES = 2**20

LimitStateQuantity = Literal["bearing_max_depth", "journal_max_depth", "clearance_growth"]


class ReliabilitySettings(SIModel):
    """Wear reliability: the limit state G_j = delta_0,j - q_j(x, N) of every judged joint j (paper Section 5).

    With several judged joints the mechanism fails when the first of them fails (a series system):
    N_f(x) = min_j N_f,j(x).
    """

    quantity: LimitStateQuantity = Field(
        "bearing_max_depth",
        description="Wear quantity judged against the allowance: 'bearing_max_depth' (deepest point of the worn "
        "bore, the paper's Eq. 42), 'journal_max_depth' (deepest point of the worn pin), 'clearance_growth' "
        "(radial clearance growth: bearing + journal depth).")
    joints: list[str] | None = Field(
        None, description="Names of the clearance joints judged (any subset); None = every clearance joint. With "
        "several, the mechanism fails when the first of them fails (series system).")
    allowance: float | None = F(
        None, unit="m", description="Wear allowance delta_0 of every judged joint. None = 0.01 D per joint with D "
        "the bearing's outer diameter (the paper's rule, Section 6.2; needs bearing_outer_radius).")
    allowances: dict[str, float] = F(
        default_factory=dict, unit="m",
        description="Per-joint allowance, by clearance-joint name (e.g. allowances_mm = { E = 0.04 }); "
        "overrides `allowance` for the joints it names.")
    allowance_std: float = F(
        0.0, unit="m", description="Standard deviation of a random allowance (Section 5.1 suggests 0.0002-0.0005 "
        "D); 0 = deterministic, as in the paper's results. With several joints one random factor scales every "
        "joint's allowance (delta_0,j x delta_0 / mean).")
    cycles_start: int | None = Field(
        None, description="First cycle count of the R(N) curve (required by the reliability stages).")
    cycles_stop: int | None = Field(
        None, le=MAX_WEAR_CYCLES,
        description="Last cycle count of the R(N) curve (required by the reliability stages). Every model call runs a "
        "wear history to it, and it is the nominal history's default length: at most 10^9, as `wear.cycles` "
        "(`MAX_WEAR_CYCLES`).")
    cycles_step: int | None = Field(
        None, description="Spacing of the R(N) curve; None = (stop - start) / 10. cycles_stop is always a level, so a "
        "step that does not divide the span leaves a shorter last interval (the histogram levels are added too). The "
        "curve has at most 1,000 levels, histogram levels included (each is a Pf estimate over the population).")
    target_reliability: float | list[float] = Field(
        0.9, description="Target reliability, or several (a life table): the life is the first N with "
        "R(N) <= target. The first target is the headline.")
    histogram_cycles: list[int] | None = Field(
        None, description="Cycle counts of the wear distributions (paper Fig. 20); None = three levels inside the "
        "curve (at a quarter, half and three quarters of it, on its grid).")
    progress_cycles: int | None = Field(
        None, description="Curve level followed by the progress line and the convergence record; None = the "
        "middle level of the curve.")
    n_mc: int = Field(
        200_000, le=MAX_MC_SAMPLES,
        description="Initial Monte Carlo population (paper: 100,000; 200,000 gives COV < 5 % down to Pf = 2e-3). At "
        "most 1e8: the population holds 8 bytes per random variable per sample (6.4 GB for 8 variables).")
    n_mc_max: int = Field(
        2_000_000, le=MAX_MC_SAMPLES,
        description="Largest population when the COV check grows it (at most 1e8, as n_mc).")
    n_initial: int = Field(12, description="Latin hypercube initial design size (paper: 20 calls in all).")
    batch_size: int = Field(2, description="Points added per learning iteration (run in parallel).")
    u_threshold: float = Field(2.0, description="Stop learning when min U >= this (paper Eq. 46: 2).")
    stopping: Literal["u", "error"] = Field(
        "error",
        description="Learning stop: 'u' = min U >= u_threshold at every level (the paper's rule); 'error' = the "
        "estimated relative error of every level's Pf from the surrogate's sign uncertainty is below error_tol, "
        "or min U >= u_threshold (project choice: the U rule keeps adding calls near levels with Pf ~ 0.5, where "
        "a population of 1e5 always has points on the limit state).")
    noise: Literal["estimate", "none"] = Field(
        "estimate",
        description="Kriging of a noisy model: 'estimate' fits a nugget (noise variance) by maximum likelihood. The "
        "clearance-joint dynamics is chaotic, so the wear life of one call scatters between nearly equal inputs "
        "(2 % on the flapping wing, 13 % on the six-bar; docs/wear.md); interpolating that scatter stalls the "
        "learning, and R(N) counts it as part of each mechanism's life (docs/reliability.md, 'A noisy model'; project "
        "choice). 'none' = DACE interpolation, as in the paper, with no scatter in R(N).")
    trend: Literal["constant", "archard", "linear"] = Field(
        "constant",
        description="What the Kriging of ln N_f knows before it learns: 'constant' = ordinary Kriging (a constant "
        "trend, as in the paper); 'archard' = Archard's exact scaling of the life in the judged body's wear "
        "coefficient and hardness, -ln(k / k_mean) + ln(H / H_mean), where they are random and one joint is "
        "judged, the Kriging learning the rest; 'linear' = universal Kriging with a linear trend in every input's "
        "normal score, estimated with the process once the design holds two points per coefficient (its lengths "
        "and nugget by the restricted likelihood; with the noise estimated, correlation lengths of at least 1, so "
        "that the rest's scatter is read as noise) (docs/reliability.md, 'The learnt life's spread').")
    error_tol: float = Field(
        0.02, description="Relative Pf error tolerance of the 'error' stopping rule (project choice).")
    hold_iterations: int = Field(
        3, description="The learning stops only when its rule has held on this many successive designs (project "
        "choice: a Kriging of a dozen points can be sure of itself where it is wrong; docs/reliability.md). 1 = stop "
        "on the first design where it holds, as the paper does.")
    surrogate: Literal["per_joint", "system_life"] = Field(
        "per_joint",
        description="With several judged joints: 'per_joint' learns one Kriging of each joint's log life and judges a "
        "sample by the joint that fails first (AK-SYS, Fauriat & Gayton 2014; project choice: each joint's life is "
        "smooth where the system's, their minimum, has a kink); 'system_life' one Kriging of the system's log life. "
        "One judged joint: one Kriging of its log life whichever is set (that joint's life is the system's), and "
        "reliability.json's life_surrogate names what was learnt: 'system_life'.")
    error_abs_tol: float = Field(
        0.01, description="A level also counts as learned when its estimated absolute Pf error is below this "
        "(project choice: 0.01 in R).")
    life_tol: float = Field(
        0.0, description="0 = off (default). Otherwise the learning also stops only when the life at each target "
        "reliability inside the curve is learnt to this relative error, or to half the life's fitted call-to-call "
        "scatter where that is larger: the estimated R error of the two levels around it (error_abs_tol's estimate, "
        "interpolated) over the curve's slope dR / d ln N there; until then the learning adds points at those two "
        "levels. For a model without call-to-call scatter, where the levels' rules alone read the life short: on the "
        "default preset with an analytic wear model whose exact life is known (benchmarks/life_coverage.py, 40 "
        "seeds) the levels' rules stopped at a median 28 calls with the life at R = 0.9 0.40 % (+-0.06 %) short and "
        "its 95 % interval holding the exact life in 36 of 40 seeds; with 0.002, 40 of 40, 0.08 % (+-0.02 %) short, "
        "at a median 36 calls. Not the default: on the default study (the true, chaotic wear model) 0.002 spent the "
        "whole budget of 80 calls without meeting the levels' rules (docs/reliability.md).")
    cov_target: float = Field(0.05, description="Required COV of Pf at every N with Pf > pf_floor (paper: 0.05).")
    pf_floor: float = Field(1e-3, description="Levels with Pf below this need not meet the COV target.")
    max_calls: int = Field(80, description="Budget of true-model calls for the reliability analysis.")
    seed: int = Field(2025, description="Seed of every random draw of the study.")

    @field_validator("u_threshold", "cov_target", "pf_floor", "error_tol", "error_abs_tol")
    @classmethod
    def _positive(cls, value: float, info) -> float:
        if not math.isfinite(value) or value <= 0:
            raise ValueError("must be a positive finite number")
        if info.field_name in ("cov_target", "pf_floor", "error_tol", "error_abs_tol") and value >= 1:
            raise ValueError("must be below 1 (a probability, or a relative error)")
        return value

    @field_validator("target_reliability")
    @classmethod
    def _targets(cls, value: float | list[float]) -> float | list[float]:
        targets = value if isinstance(value, list) else [value]
        if not targets:
            raise ValueError("give at least one target")
        outside = [t for t in targets if not 0 < t < 1]
        if outside:
            raise ValueError(f"must be in (0, 1) (got {outside[0]:g})")
        repeated = [t for i, t in enumerate(targets) if t in targets[:i]]
        if repeated:
            raise ValueError(f"{repeated[0]:g} given twice (each target once: the life table has a row per target)")
        return value

    @field_validator("allowance", "cycles_start", "cycles_step")
    @classmethod
    def _above_zero(cls, value, info):
        if value is not None and not value > 0:
            raise ValueError("must be > 0" + (" m" if info.field_name == "allowance" else ""))
        return value

    @field_validator("life_tol")
    @classmethod
    def _life_tol(cls, value: float) -> float:
        if not 0.0 <= value < 1.0:
            raise ValueError("must be in [0, 1) (a relative error of the life; 0 = off)")
        return value

    @field_validator("allowance_std")
    @classmethod
    def _allowance_std(cls, value: float) -> float:
        if value < 0 or not math.isfinite(value):
            raise ValueError("must be >= 0")
        return value

    @field_validator("n_mc", "n_mc_max", "n_initial", "batch_size", "max_calls", "hold_iterations")
    @classmethod
    def _counts(cls, value: int, info) -> int:
        least = 2 if info.field_name == "n_initial" else 1  # a Kriging needs two points
        if value < least:
            raise ValueError("must be >= 2 (a Kriging needs two points to fit)" if least == 2 else "must be > 0")
        return value

    @model_validator(mode="after")
    def _ranges(self) -> ReliabilitySettings:
        """The rules between fields (each field's own range is its validator's: every one is listed at once)."""
        for name, a in self.allowances.items():
            if not (math.isfinite(a) and a > 0):
                raise ValueError(f"allowances.{name} must be > 0 m (got {a:g})")
        if self.cycles_start is not None and self.cycles_stop is not None and not self.cycles_start < self.cycles_stop:
            raise ValueError(f"need 0 < cycles_start < cycles_stop (got {self.cycles_start}, {self.cycles_stop})")
        if self.n_mc_max < self.n_mc:
            raise ValueError(f"n_mc_max must be >= n_mc (got {self.n_mc_max:,} < {self.n_mc:,})")
        if self.max_calls < self.n_initial:
            raise ValueError(f"max_calls must be >= n_initial (got {self.max_calls} < {self.n_initial}): the "
                             "initial design alone makes n_initial model calls")
        if self.histogram_cycles is not None and any(c <= 0 for c in self.histogram_cycles):
            raise ValueError("histogram_cycles must be positive")
        self._check_level_count()
        return self

    def _check_level_count(self) -> None:
        """The curve's level count bounded (MAX_CURVE_LEVELS), counted without building its grid."""
        hist = len(self.histogram_cycles or [])
        if hist > MAX_CURVE_LEVELS:
            raise ValueError(f"histogram_cycles: {hist:,} levels given, at most {MAX_CURVE_LEVELS:,}")
        if self.cycles_start is None or self.cycles_stop is None:
            return
        grid = len(range(self.cycles_start, self.cycles_stop + 1, self.step())) + 1  # cycles_stop may be off the step
        if grid + hist > MAX_CURVE_LEVELS:
            raise ValueError(
                f"cycles_step: the R(N) curve from cycles_start = {self.cycles_start:,} to cycles_stop = "
                f"{self.cycles_stop:,} on a step of {self.step():,} has about {grid + hist:,} levels (histogram levels "
                f"included), at most {MAX_CURVE_LEVELS:,}: widen cycles_step")

    @property
    def targets(self) -> list[float]:
        """Every target reliability, the headline first."""
        t = self.target_reliability
        return list(t) if isinstance(t, list) else [float(t)]

    def curve_problems(self) -> list[str]:
        """What keeps the R(N) curve from being defined (empty when it is)."""
        problems = []
        if self.cycles_start is None:
            problems.append("reliability.cycles_start: required for the R(N) curve (first cycle count, e.g. 100000)")
        if self.cycles_stop is None:
            problems.append("reliability.cycles_stop: required for the R(N) curve (last cycle count, e.g. 300000)")
        if problems:
            return problems
        grid = self.curve_cycles()
        lo, hi = grid[0], grid[-1]
        if self.histogram_cycles is not None:
            outside = [c for c in self.histogram_cycles if not lo <= c <= hi]
            if outside:
                problems.append(f"reliability.histogram_cycles: {outside} lie outside the curve [{lo}, {hi}]")
        if self.progress_cycles is not None and self.progress_cycles not in grid:
            problems.append(f"reliability.progress_cycles: {self.progress_cycles} is not on the curve grid {grid}")
        return problems

    def step(self) -> int:
        """Spacing of the curve (the configured step, else a tenth of its span)."""
        if self.cycles_step is not None:
            return self.cycles_step
        return max(1, (self.cycles_stop - self.cycles_start) // 10)

    def curve_cycles(self) -> list[int]:
        """The cycle counts of the R(N) curve (start to stop on its step, stop included) and the histogram levels."""
        if self.cycles_start is None or self.cycles_stop is None:
            raise ValueError("reliability.cycles_start and cycles_stop are required for the R(N) curve")
        grid = set(range(self.cycles_start, self.cycles_stop + 1, self.step()))
        grid.add(self.cycles_stop)
        grid.update(c for c in (self.histogram_cycles or []) if self.cycles_start <= c <= self.cycles_stop)
        return sorted(grid)

    def histogram_levels(self) -> list[int]:
        """The wear-distribution levels: the configured ones, else a quarter, half and three quarters of the curve."""
        if self.histogram_cycles is not None:
            return list(self.histogram_cycles)
        grid = self.curve_cycles()
        picks = [grid[min(len(grid) - 1, round(f * (len(grid) - 1)))] for f in (0.25, 0.5, 0.75)]
        return sorted(set(picks))

    def progress_level(self, cycles: list[int]) -> int:
        """Index of the level followed by the progress line (configured, else the middle of the curve)."""
        if self.progress_cycles is not None and self.progress_cycles in cycles:
            return cycles.index(self.progress_cycles)
        return len(cycles) // 2


class SensitivitySettings(SIModel):
    """Sensitivity of the reliability (paper Section 6.2.3) and Sobol' indices of the max wear."""

    cycles: int | None = Field(
        None, description="Cycle count of the sensitivity study, one of the R(N) curve's (paper: 360,000); None = "
        "the curve level whose reliability is nearest the (first) target reliability.")
    factors: tuple[float, float] = Field((0.8, 1.2), description="Mean shifts (paper: 80 % and 120 %).")
    sobol_base_samples: int = Field(
        2048, le=MAX_SOBOL_BASE_SAMPLES,
        description="Saltelli base sample size on the surrogate (power of 2; at most 2**20 = 1,048,576: the Sobol' "
        "design holds N (d + 2) points of d variables, 670 MB for 8 variables).")
    surrogate_shift_limit: float = Field(
        4.0, description="A mean shift up to this many standard deviations is evaluated on the reliability "
        "surrogate (the initial design spans +-5 sigma); a larger one by one true-model call and the separable "
        "scaling rule (docs/study.md). Project choice: the paper does not say how its shifted analyses were run.")

    # each field's own check, so that every problem of the section is listed at once
    @field_validator("cycles")
    @classmethod
    def _cycles(cls, value: int | None) -> int | None:
        if value is not None and value <= 0:
            raise ValueError("must be > 0")
        return value

    @field_validator("factors")
    @classmethod
    def _factors(cls, value):
        if not all(f > 0 and math.isfinite(f) for f in value):
            raise ValueError("must be positive")
        return value

    @field_validator("surrogate_shift_limit")
    @classmethod
    def _shift_limit(cls, value: float) -> float:
        if not (value > 0 and math.isfinite(value)):
            raise ValueError("must be a positive number of standard deviations")
        return value

    @field_validator("sobol_base_samples")
    @classmethod
    def _sobol_base(cls, value: int) -> int:
        if value < 2 or value & (value - 1):
            raise ValueError("must be a power of two")
        return value


class ComputeSettings(SIModel):
    """Where model calls run."""

    workers: int | None = Field(None, description="Local worker processes; None = all cores, 1 = in-process.")
    scheduler: str | None = Field(None, description="Dask scheduler address (tcp://host:8786); None = local.")
    call_timeout: float | None = F(600.0, unit="s", description="Seconds before a model call is abandoned as failed.")

    @field_validator("workers")
    @classmethod
    def _workers(cls, value: int | None) -> int | None:
        if value is not None and value <= 0:
            raise ValueError("workers must be >= 1")
        return value


