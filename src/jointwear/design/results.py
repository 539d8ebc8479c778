"""The typed result of the design stage (``design.json``, ``design_pareto.csv``, ``design_candidates.csv``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from jointwear.study.io import write_csv
from jointwear.study.stage_result import StageResult


@dataclass(repr=False)
class DesignResult(StageResult):
    """The cheapest controls that reach N* cycles at reliability R*, and the Pareto front of cost vs life at R*.

    ``chosen`` and every ``pareto`` row: ``choices`` (control -> option), ``cost`` (relative), the life at R*
    (``life_at_target_cycles``) and R(N*) (``reliability_at_target_life``) on the study's surrogate, with its
    error bound ``reliability_error`` (the surrogate's ESC bound plus the Monte Carlo 95 % half-width) and the
    share of the candidate's population outside the study design's region (``outside_design_fraction``).
    ``verification``: the chosen design's own AK-MCS study on the true model at N* (``reliability_at_target_life``,
    ``error``, ``model_calls``, ``confirmed``: R + error >= R*). ``model_calls``: the distinct true-model inputs
    the design rests on (study, refinement and verification; ``calls`` splits them). ``targets``: the same for
    every target (the first is the headline). ``chosen_every_target``: with several targets, the cheapest candidate
    that meets all of them at once (its R(N*) and error per target, in their order; None with one target or when
    none does), which a drawing needs; each target's own choice may miss the others.
    """

    FILE: ClassVar[str] = "design.json"

    target_life_cycles: float
    target_reliability: float
    chosen: dict | None
    pareto: list[dict]
    verification: dict | None
    model_calls: int
    wall_seconds: float
    baseline_life_cycles: float | None = None
    life_factor: float | None = None
    targets: list[dict] = field(default_factory=list)
    controls: list[dict] = field(default_factory=list)
    candidates: list[dict] = field(default_factory=list)
    calls: dict = field(default_factory=dict)
    refinement: dict = field(default_factory=dict)
    n_population: int = 0
    n_candidates: int = 0
    provenance: dict = field(default_factory=dict)
    chosen_every_target: dict | None = None

    @property
    def feasible(self) -> bool:
        """Whether some candidate reaches the headline target on the surrogate."""
        return self.chosen is not None

    def undecided_sentence(self) -> str:
        """What candidates left undecided by the refinement mean for the choice (empty when none was left)."""
        n = int((self.refinement or {}).get("undecided_left") or 0)
        if not n:
            return ""
        return (f"the refinement's budget (design.refine_max_calls) ran out with {n} candidate(s) no dearer than the "
                "choice still undecided (their estimate's error spans the target): a cheaper one may meet it; raise "
                "design.refine_max_calls and run again with --resume (resume=True in Python)")

    def save(self, folder: Path | str, *, figures: bool = True) -> Path:
        """Write ``design.json``, the front (``design_pareto.csv``), every candidate (``design_candidates.csv``)
        and the front's figure."""
        folder = Path(folder)
        names = [c["name"] for c in self.controls]
        for rows, name in ((self.pareto, "design_pareto.csv"), (self.candidates, "design_candidates.csv")):
            cols = {n: [r["choices"][n] for r in rows] for n in names}
            for key in ("cost", "life_at_target_cycles", "reliability_at_target_life", "reliability_error",
                        "outside_design_fraction"):
                cols[key] = [r.get(key) for r in rows]
            write_csv(folder / name, cols)
        path = self.write(folder)
        if figures and self.pareto:
            from jointwear.report.design_section import design_pareto_figure
            from jointwear.report.style import savefig

            savefig(design_pareto_figure(self), folder / "design_pareto.png")
        return path
