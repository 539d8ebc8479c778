"""Settings of the study stages that join wear and reliability (validated at the config boundary).

Each field that the paper leaves open has a default and says where it comes from. SI units inside
(wear allowance in metres); cycle counts are plain numbers of crank revolutions.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator, model_validator

from jointwear.schema import SIModel


class ReliabilitySettings(SIModel):
    """Wear reliability: limit state G = delta_0 - delta_max(x, N) (paper Section 5)."""

    allowance: float = Field(
        3e-5, description="Wear allowance delta_0, m: 0.01 D with D = 3 mm, the bearing's outer diameter "
        "(Section 6.2).")
    allowance_std: float = Field(
        0.0, description="Standard deviation of a random allowance, m (Section 5.1 suggests 0.0002-0.0005 D); "
        "0 = deterministic, as in the paper's results.")
    cycles_start: int = Field(300_000, description="First cycle count of the R(N) curve.")
    cycles_stop: int = Field(560_000, description="Last cycle count of the R(N) curve (paper: up to 520k).")
    cycles_step: int = Field(20_000, description="Spacing of the R(N) curve; 20k hits 360k/400k/420k/440k/520k.")
    target_reliability: float = Field(0.9, description="Acceptable reliability for the life (paper: 0.9).")
    histogram_cycles: list[int] = Field([360_000, 400_000, 440_000], description="Paper Fig. 20.")
    n_mc: int = Field(
        200_000, description="Initial Monte Carlo population (paper: 100,000; 200,000 gives COV < 5 % down to Pf = 2e-3).")
    n_mc_max: int = Field(2_000_000, description="Largest population when the COV check grows it.")
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
        "clearance-joint dynamics is chaotic, so the wear life of one call scatters by ~0.5 % between nearly equal "
        "inputs (docs/wear.md); interpolating that scatter stalls the learning (project choice). 'none' = DACE "
        "interpolation, as in the paper.")
    error_tol: float = Field(0.02, description="Relative Pf error tolerance of the 'error' stopping rule (project choice).")
    error_abs_tol: float = Field(
        0.01, description="A level also counts as learned when its estimated absolute Pf error is below this "
        "(project choice: 0.01 in R, well inside the 0.15 agreement band with the paper).")
    cov_target: float = Field(0.05, description="Required COV of Pf at every N with Pf > pf_floor (paper: 0.05).")
    pf_floor: float = Field(1e-3, description="Levels with Pf below this need not meet the COV target.")
    max_calls: int = Field(
        60, description="Budget of true-model calls for the reliability analysis (issue goal: <= 60 for the whole curve).")
    seed: int = Field(2025, description="Seed of every random draw of the study.")

    @field_validator("allowance", "target_reliability", "u_threshold", "cov_target", "pf_floor")
    @classmethod
    def _positive(cls, value: float, info) -> float:
        if not math.isfinite(value) or value <= 0:
            raise ValueError(f"{info.field_name} must be a positive finite number")
        return value

    @model_validator(mode="after")
    def _ranges(self) -> ReliabilitySettings:
        if not 0 < self.target_reliability < 1:
            raise ValueError("target_reliability must be in (0, 1)")
        if self.allowance_std < 0 or not math.isfinite(self.allowance_std):
            raise ValueError("allowance_std must be >= 0")
        if not 0 < self.cycles_start < self.cycles_stop:
            raise ValueError("need 0 < cycles_start < cycles_stop")
        if self.cycles_step <= 0:
            raise ValueError("cycles_step must be > 0")
        for name in ("n_mc", "n_mc_max", "n_initial", "batch_size", "max_calls"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0")
        if self.n_mc_max < self.n_mc:
            raise ValueError("n_mc_max must be >= n_mc")
        if any(c <= 0 for c in self.histogram_cycles):
            raise ValueError("histogram_cycles must be positive")
        return self

    def curve_cycles(self) -> list[int]:
        """The cycle counts of the R(N) curve, including every histogram level."""
        grid = set(range(self.cycles_start, self.cycles_stop + 1, self.cycles_step))
        grid.update(self.histogram_cycles)
        return sorted(grid)


class SensitivitySettings(SIModel):
    """Sensitivity of the reliability (paper Section 6.2.3) and Sobol' indices of the max wear."""

    cycles: int = Field(360_000, description="Cycle count of the sensitivity study (paper: 360,000).")
    factors: tuple[float, float] = Field((0.8, 1.2), description="Mean shifts (paper: 80 % and 120 %).")
    sobol_base_samples: int = Field(2048, description="Saltelli base sample size on the surrogate (power of 2).")
    surrogate_shift_limit: float = Field(
        4.0, description="A mean shift up to this many standard deviations is evaluated on the reliability "
        "surrogate (the initial design spans +-5 sigma); a larger one by one true-model call and the separable "
        "scaling rule (docs/study.md). Project choice: the paper does not say how its shifted analyses were run.")

    @model_validator(mode="after")
    def _check(self) -> SensitivitySettings:
        if self.cycles <= 0:
            raise ValueError("cycles must be > 0")
        if not all(f > 0 and math.isfinite(f) for f in self.factors):
            raise ValueError("factors must be positive")
        if not (self.surrogate_shift_limit > 0 and math.isfinite(self.surrogate_shift_limit)):
            raise ValueError("surrogate_shift_limit must be a positive number of standard deviations")
        n = self.sobol_base_samples
        if n < 2 or n & (n - 1):
            raise ValueError("sobol_base_samples must be a power of two")
        return self


class ComputeSettings(SIModel):
    """Where model calls run."""

    workers: int | None = Field(None, description="Local worker processes; None = all cores, 1 = in-process.")
    scheduler: str | None = Field(None, description="Dask scheduler address (tcp://host:8786); None = local.")
    call_timeout: float | None = Field(600.0, description="Seconds before a model call is abandoned as failed.")

    @field_validator("workers")
    @classmethod
    def _workers(cls, value: int | None) -> int | None:
        if value is not None and value <= 0:
            raise ValueError("workers must be >= 1")
        return value


