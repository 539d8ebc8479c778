"""Settings of the wear model (``config.wear``).

Every choice that the reference paper (Jin et al., Drones 2025, 9, 282, Section 3) leaves open, or states in a
form that cannot be used literally (see the user guide, "The baseline reading of the paper"), is a named field here with
a default and a docstring that says where the default comes from. Units are SI; cycles are crank revolutions.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator, model_validator

from jointwear.schema import F, SIModel

#: sqrt(4/pi) = 1.1284: Johnson's line-contact half-width b = sqrt(4 F R* / (pi L E*)) written as
#: 1.128 sqrt(F R* (h_i + h_j) / L) with 1/E* = h_i + h_j, h = (1 - nu^2) / E (Johnson, Contact Mechanics, Eq. 4.43).
JOHNSON_FACTOR = math.sqrt(4.0 / math.pi)

#: Longest wear history (crank cycles) a config or a caller may ask for, and so the longest block. 10^9 cycles are
#: about 4 years of continuous running at the flapping preset's 480 rpm and 100,000 blocks of the default 10,000
#: cycles (each block integrates about 3 cycles: some 25 minutes of dynamics for one history, and a reliability
#: study runs dozens); a count beyond it is a typo or a unit slip, refused before anything runs.
MAX_WEAR_CYCLES = 1_000_000_000


class WearSettings(SIModel):
    """How the Archard wear of the clearance joints is computed and extrapolated over many cycles (``config.wear``).

    An :class:`jointwear.config.SIModel`: unknown keys, NaN and inf are rejected with the field named.
    """

    geometry_mode: Literal["uniform", "profile"] = Field(
        "uniform",
        description=(
            "How the accumulated wear feeds back into the contact search. 'uniform': the paper's Eqs. 36-37, the "
            "clearance grows uniformly by the wear (R_i += h/2, R_j -= h/2, see `uniform_growth`). 'profile': the "
            "worn bearing and journal profiles R_i(theta) = R_i0 + h_i(theta), R_j(theta) = R_j0 - h_j(theta) are "
            "used by the contact search and the contact stiffness. Default 'uniform': the paper's method, and the "
            "mode that the reproduction targets of Section 6.1.3 refer to (docs/wear.md compares both)."
        ),
    )
    profile_contact: Literal["envelope", "radial"] = Field(
        "envelope",
        description=(
            "Profile mode only: what the contact search is given. 'envelope' (default): the clearance a rigid round "
            "journal can use in each direction, min_k (c0 + h_k) / cos(theta_k - theta) (contact.envelope.admissible_set), "
            "and the wear of each step is laid at the bore point that actually touches (a flank of a pocket narrower "
            "than the journal). 'radial': the raw profiles, c_loc = c0 + h(theta) along the centre line (the "
            "contract's literal reading); a pocket narrower than the journal is then entered radially, which is "
            "unphysical (the journal would cut its flanks) and makes the dynamics stiff (10^6 steps per cycle for "
            "a 10 um pocket, docs/wear.md)."
        ),
    )
    profile_deposit: Literal["distributed", "touch"] = Field(
        "distributed",
        description=(
            "Profile mode only: where each step's wear is laid. 'distributed' (default): on each side, shared over "
            "the cells the other body touches, in proportion to their rigid overlap with it (an elastic foundation "
            "whose patch on a round bore is Johnson's half-width; kernels.share_load): a journal resting in a pocket "
            "worn to its own shape loads the whole worn arc with a cos-shaped pressure, the conformal wear of "
            "Kauzlarich and Williams (2001) that docs/verification.md checks, and a pin under a load fixed on it "
            "wears the bore's shape into itself alike. 'touch': at the single point that touches "
            "(admissible_set's map), spread over the patch and the running-in length (47 % too deep on the "
            "conformal rig)."
        ),
    )
    profile_smoothing_deg: float = Field(
        3.0,
        ge=0.0,
        le=90.0,
        description=(
            "Profile mode only: running-in length (deg). The worn profiles given to the contact search are smoothed "
            "by a periodic Gaussian of this standard deviation, and each block's wear is laid smoothed by it "
            "(distributed deposit; with the 'touch' deposit each step's wear is laid over at least +-sqrt(3) x this "
            "angle); both conserve the worn area. Default 3 deg: on the conformal rig of docs/verification.md halving it "
            "changes the max depth by < 0.1 % (docs/wear.md 'Profile mode on conformal contacts'); 0: "
            "point contacts on the grid, a spiky profile."
        ),
    )
    profile_substep_cycles: float = Field(
        300.0,
        gt=0.0,
        description=(
            "Profile mode, distributed deposit only: most cycles per sub-step in which a block's wear is laid on "
            "each side; each sub-step re-shares the block's recorded loads over the profile as it wears. A block of n cycles takes "
            "max(min(ceil(g n / 2), 16), ceil(n / this)) sub-steps, g the levelling rate of the shares (1/cycle): "
            "the first term resolves a steady conformal load (the rig of docs/verification.md), the second bounds "
            "the sub-step where the levelling is faster than any affordable step (a rotating load). There the "
            "sub-step, not the block, sets how accurately the profile is laid, and too long a sub-step lays it too "
            "shallow: on the flapping wing 300 cycles read the max depth about 2 % shallow at 1.3M cycles and 100 "
            "cycles about 1 %, against sub-steps that resolve the levelling (about 20 cycles; docs/wear.md 'Profile mode on the "
            "flapping wing'; preset jin2025_flapping_wing_profile uses 100). Each sub-step costs about 0.1 ms on a "
            "720-cell grid."
        ),
    )
    uniform_growth: Literal["max_sum", "bearing_max"] = Field(
        "max_sum",
        description=(
            "Uniform mode only: the wear depth h by which the clearance grows (paper Eq. 35-37, 'h is the total "
            "amount of wear'). 'max_sum' (default): max bearing depth + max journal depth, the clearance at the "
            "deepest point, split as R_i += h/2, R_j -= h/2 as in Eqs. 36-37. 'bearing_max': max bearing depth only."
        ),
    )
    n_grid: int = Field(
        720,
        ge=16,
        le=100_000,
        description=(
            "Angular grid points on each body (cell-centred at 2 pi k / n_grid). The wear increment of every step is "
            "spread over the contact patch with exact overlap integration, so the grid only sets the output "
            "resolution. Default 720 (0.5 deg cells): in uniform mode, halving the cells changes the max wear at 400k "
            "cycles by well under 2 %; in profile mode the worn volume moves by < 1 % but the raw max is not "
            "converged (benchmarks/wear.py, docs/wear.md \"Convergence of profile mode\")."
        ),
    )
    cycles: int | None = Field(
        None,
        description=(
            "Number of crank cycles of the nominal wear history (`jointwear wear`, `run`) when the caller does not "
            "give one. Default: the end of the R(N) curve (`reliability.cycles_stop`); a config with neither must "
            "give it. At most 10^9 (`MAX_WEAR_CYCLES`: about 4 years of continuous running at 480 rpm, 100,000 "
            "blocks of the default 10,000 cycles; a larger count is a typo or a unit slip and would run for days)."
        ),
    )
    block_rule: Literal["fixed", "adaptive"] = Field(
        "fixed",
        description=(
            "How many cycles one simulated sample of steady cycles stands for. 'fixed' (default): every block is "
            "`block_cycles` long. 'adaptive': start at `initial_block`, grow by `block_growth` while the bearing's "
            "Archard volume rate changes by less than `rate_tolerance` between blocks, halve when it changes by more "
            "than twice that. Default 'fixed' because the clearance dynamics is chaotic: the wear-rate profile of a "
            "few cycles scatters by 10-25 % at its peak (docs/wear.md), so the accuracy of the final profile is set "
            "by the number of independent samples, which equal blocks maximise; the expected rate itself changes "
            "by only a few % over the whole history."
        ),
    )
    block_cycles: int = Field(
        10_000,
        ge=1,
        le=MAX_WEAR_CYCLES,
        description=(
            "Block size of the 'fixed' rule. Default 10,000 (40 samples to 400k cycles): the run-to-run scatter of "
            "the max wear at 400k cycles is about 4 % (3.9 %, 8 runs at the default rtol 5e-7: "
            "benchmarks/results/wear.json 'convergence'), and halving the block "
            "changes the mean by less than the 2 % acceptance (benchmarks/wear.py, docs/wear.md). At most 10^9, "
            "the longest history (`MAX_WEAR_CYCLES`): a longer block would stand for cycles no history runs."
        ),
    )
    initial_block: int = Field(
        10_000,
        ge=1,
        description="Adaptive rule: first block (cycles). Default 10,000.",
    )
    max_block: int = Field(
        80_000,
        ge=1,
        le=MAX_WEAR_CYCLES,
        description="Adaptive rule: largest block. Default 80,000 (keeps >= 6 history points to 400k cycles). At "
        "most 10^9, the longest history (`MAX_WEAR_CYCLES`); `min_block` and `initial_block` lie below it.",
    )
    min_block: int = Field(2_500, ge=1, description="Adaptive rule: smallest block.")
    block_growth: float = Field(
        2.0,
        ge=1.0,
        description="Adaptive rule: factor by which the block grows when the rate changed by less than the tolerance.",
    )
    rate_tolerance: float = Field(
        0.02,
        gt=0.0,
        description=(
            "Adaptive rule: tolerated relative change of the bearing's Archard volume rate (m^3/cycle) between two "
            "blocks. The volume rate is the smooth measure of how the dynamics changes with the wear (its "
            "cycle-to-cycle scatter is < 2 %; the peak of the profile scatters far more and is not used)."
        ),
    )
    lanes: int = Field(
        2,
        ge=1,
        le=64,
        description=(
            "Independent dynamics chains that simulate alternate blocks concurrently (threads: the integrator "
            "releases the GIL). Block k continues from the end state of block k - lanes and sees the wear of blocks "
            "0 .. k - lanes, i.e. the geometry update lags by lanes - 1 blocks; lane j's first block settles j / lanes "
            "cycle longer (another start phase). The schedule, hence the result, depends on `lanes`, never on the "
            "number of cores. Default 2: a history takes about half the wall time on a 2-core machine for the same "
            "CPU time, and the lag changes the max wear at 400k cycles by less than its sampling scatter "
            "(docs/wear.md 'Lanes'). 1: the sequential loop. The adaptive block rule always runs one lane (its block "
            "sizes depend on the previous block)."
        ),
    )
    settle_cycles_initial: float | None = Field(
        None,
        ge=0.0,
        description=(
            "Cycles simulated and discarded before the first recorded cycles (start from the assembled rest state). "
            "None: the dynamics' own default."
        ),
    )
    settle_cycles: float = Field(
        1.0,
        ge=0.0,
        description=(
            "Cycles simulated and discarded at the start of every later block, which continues from the end state of "
            "the previous block on the updated geometry. Default 1 cycle: the post-update transient of the flapping "
            "preset decays within a fraction of a cycle."
        ),
    )
    record_cycles: int = Field(
        2,
        ge=1,
        description=(
            "Steady cycles recorded per block; the wear rate is their mean. Default 2 (the rate of single cycles "
            "differs by well under 1 % in the flapping preset; 2 averages the impact phase)."
        ),
    )
    pressure: Literal["uniform", "hertz"] = Field(
        "uniform",
        description=(
            "Pressure distribution over the contact patch |s| <= b. 'uniform': p = F_N / A with A = 2 b L, the "
            "paper's Eq. 31-33 (depth dh = (k/H) p ds over the whole patch). 'hertz': the elliptical line-contact "
            "distribution p(s) = 2 F_N / (pi b L) sqrt(1 - s^2/b^2). Both conserve the Archard volume (k/H) F_N ds. "
            "Uniform geometry mode only: profile mode reads the pressure off the worn shape (profile_contact)."
        ),
    )
    half_width_factor: float = Field(
        JOHNSON_FACTOR,
        gt=0.0,
        description=(
            "c in b = c sqrt(F_N R* (h_i + h_j) / L). Default sqrt(4/pi) = 1.128, Johnson's line-contact half-width "
            "b = sqrt(4 F R* / (pi L E*)). The paper's garbled Eq. 32 shows '1.128 x 2 x F_N/L': read as a factor 2 "
            "inside the root (c = 1.128 sqrt(2) = 1.596) when the force is taken per unit half-width; set that value "
            "to reproduce it. With uniform or Hertz spreading the volume does not depend on c; it only sets the "
            "patch width and the reported contact area."
        ),
    )
    track_journal: bool = Field(
        True,
        description="Accumulate the journal's wear on a grid fixed in the journal body (it turns fully against the rod).",
    )
    peak_prominence: float = Field(
        0.05,
        gt=0.0,
        lt=1.0,
        description=(
            "Peak detection on the periodic bearing profile: a local maximum is a peak when its prominence is at least "
            "this fraction of the maximum depth. Default 0.05 (ignores the ripples of the impact phase; keeps the "
            "paper's second peak, 35 % of the first)."
        ),
    )
    peak_separation_deg: float = Field(
        30.0,
        gt=0.0,
        le=180.0,
        description=(
            "Peaks closer than this (deg) are one wear zone; the deeper one is reported. Default 30 deg: the ripples "
            "inside one zone are a few degrees apart, the paper's two zones about 200 deg."
        ),
    )
    rtol: float | None = Field(
        5e-7,
        gt=0.0,
        description=(
            "Integrator relative tolerance of the wear runs; None: the dynamics' default (1e-6). Default 5e-7, half "
            "the dynamics' default, as a margin (about 5-10 % more steps), not for a measured gain: at 400k cycles "
            "the 8-run means at 1e-6, 5e-7 and 2.5e-7 lie within about one standard error (1.5 %) of each other "
            "(docs/wear.md 'Convergence')."
        ),
    )
    atol: float | None = F(
        5e-10, unit="m",
        gt=0.0,
        description="Integrator absolute tolerance on positions; None: the dynamics' default (simulation.atol, "
        "1e-6 mm). Halved with rtol (see rtol).",
    )

    @field_validator("cycles", mode="before")
    @classmethod
    def _cycles_positive(cls, v):
        return check_cycles(v, None) if v is not None else None  # pydantic / ConfigError add the field's path

    @model_validator(mode="after")
    def _blocks_consistent(self):
        if self.min_block > self.max_block:
            raise ValueError(f"min_block ({self.min_block}) must be <= max_block ({self.max_block})")
        if not (self.min_block <= self.initial_block <= self.max_block):
            raise ValueError(
                f"initial_block ({self.initial_block}) must lie in [min_block, max_block] = "
                f"[{self.min_block}, {self.max_block}]"
            )
        return self

    def simulated_cycles(self, cycles: int) -> float | None:
        """Cycles of dynamics a history of ``cycles`` simulates in fixed blocks, each settling ``settle_cycles`` and
        recording ``record_cycles``; None with adaptive blocks, whose number the wear sets."""
        if self.block_rule != "fixed":
            return None
        return math.ceil(cycles / self.block_cycles) * (self.settle_cycles + self.record_cycles)


def check_cycles(value, field: str | None = "cycles") -> int:
    """Validate a cycle count at an API boundary: a finite, positive whole number of at most `MAX_WEAR_CYCLES`.
    Raises ValueError naming `field` (field None: the message starts with "must be", for validators whose caller
    adds the field's path)."""
    prefix = f"{field} " if field else ""
    if isinstance(value, (bool, str)):  # float("1000") would read a string
        raise ValueError(f"{prefix}must be a positive whole number of cycles, got {value!r}")
    too_many = (f"{prefix}must be at most {MAX_WEAR_CYCLES:,} cycles (MAX_WEAR_CYCLES: a "
                f"longer wear history would run for days), got {value!r}")
    try:
        x = float(value)
    except OverflowError:  # an int beyond float's range
        raise ValueError(too_many) from None
    except (TypeError, ValueError):
        raise ValueError(f"{prefix}must be a positive whole number of cycles, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{prefix}must be a finite positive number of cycles, got {value!r}")
    if x > MAX_WEAR_CYCLES:
        raise ValueError(too_many)
    if x <= 0:
        raise ValueError(f"{prefix}must be > 0 cycles, got {value!r}")
    if x != int(x):
        raise ValueError(f"{prefix}must be a whole number of cycles, got {value!r}")
    return int(x)

