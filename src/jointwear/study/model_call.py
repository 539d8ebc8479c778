"""The true model of a study: a sample of the random inputs -> the wear histories of the judged joints.

A call builds the sampled mechanism, runs its wear history and reads the limit state's wear quantity of
each judged joint at the history's cycle counts. Samples that cannot be built return NaN with the reason
(the reliability engine counts them as failures of the mechanism and reports them).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from jointwear.config import StudyConfig, config_from_dict
from jointwear.schema import ConfigError
from jointwear.uncertainty.targets import apply_targets, target_error
from jointwear.wear.results import history_at


def apply_sample(base: StudyConfig | dict, targets: Sequence[str], x: Sequence[float]) -> StudyConfig:
    """A copy of the config with each target field set to the sample value (SI).

    A target ``clearance_joints.<i>.clearance`` sets the bearing radius to journal radius + c after all
    other targets (so a sampled journal radius and a sampled clearance combine as R_i = R_j + c).
    A target that moves a drawn point of a general linkage moves it away from its joint partner's point: the
    drawing's closure tolerance admits that move on top of the drawing's own gaps (the drawing was checked on the
    base config), and the assembly closes the loop with every other link as drawn (or says why it cannot).
    Raises ConfigError when ``x`` and ``targets`` differ in length or the sample gives an invalid config (whether a
    general linkage assembles is checked when the model is built).
    """
    if len(x) != len(targets):  # zip would drop the surplus silently
        raise ConfigError(f"uncertainty: a sample of {len(x)} values for {len(targets)} targets")
    data = base.model_dump() if isinstance(base, StudyConfig) else copy.deepcopy(base)
    for path in targets:
        problem = target_error(data, path)
        if problem:
            raise ConfigError(f"uncertainty: target {problem}")
    apply_targets(data, zip(targets, x))
    return config_from_dict(data, source="sample")


#: The wear (m) a call reports at the cycle counts after its history stopped with a joint worn away
#: (wear.history.used_up): larger than any allowance, so that the life ends at the stop (within one cycle step of
#: the curve) instead of running on along an extrapolated history of a joint that is gone.
WORN_AWAY_WEAR = 1.0


def quantity_history(joint_wear, quantity: str, cycles) -> np.ndarray:
    """The wear quantity (m) of one joint's history at ``cycles`` (:func:`~jointwear.wear.results.history_at`)."""
    if quantity == "bearing_max_depth":
        return np.asarray(joint_wear.max_wear_at(np.asarray(cycles, dtype=float)), dtype=float)
    series = {"journal_max_depth": joint_wear.history_max_journal,
              "clearance_growth": joint_wear.history_max_bearing + joint_wear.history_max_journal}[quantity]
    return history_at(joint_wear.history_cycles, series, cycles)


@dataclass
class WearModelCall:
    """One true-model call: sample x -> the wear quantity (m) of every judged joint at each of ``cycles``,
    concatenated joint after joint (shape J * H).

    A plain picklable object so that worker processes and Dask workers can run it. ``threads``: most threads
    of one wear history (its lanes; None: the cores of the process that runs it); the result does not depend on it.
    """

    MODEL_SECTIONS: ClassVar[tuple[str, ...]] = ("mechanism", "clearance_joints", "simulation", "wear")
    #: the other settings a call's identity depends on (the history's cycle counts, the judged joints, their
    #: quantity; and every random variable's target), as config.json names them
    CALL_SETTINGS: ClassVar[tuple[str, ...]] = ("reliability.cycles_start", "reliability.cycles_stop",
                                                "reliability.cycles_step", "reliability.histogram_cycles",
                                                "reliability.joints", "reliability.quantity")

    #: settings of the model sections that only the simulate and wear stages read (how long they run, which peaks
    #: they report): a call runs to the curve's last level and returns depths, so its store survives a change of them
    STAGE_ONLY: ClassVar[frozenset[str]] = frozenset(
        {"simulation.cycles", "wear.cycles", "wear.peak_prominence", "wear.peak_separation_deg"})

    base: dict
    targets: list[str]
    cycles: list[int]
    joints: list[int] = field(default_factory=lambda: [0])
    quantity: str = "bearing_max_depth"
    threads: int | None = None

    @property
    def n_outputs(self) -> int:
        return len(self.cycles) * len(self.joints)

    def identity(self, *, former: bool = False) -> dict:
        """What the outputs of a call depend on besides x: the config's model sections (``MODEL_SECTIONS``, but
        ``STAGE_ONLY``), the targets, the cycle counts, the joints and the quantity. Not ``threads``, nor the study's
        learning, sensitivity, design or report settings: its hash keys the evaluation store, so a study resumed with
        a larger budget reads back every call it made. ``former``: with the ``STAGE_ONLY`` settings, as stores were
        keyed before they left it (their calls are the same)."""
        model = {k: self.base[k] if former or not isinstance(self.base[k], dict) else
                 {f: v for f, v in self.base[k].items() if f"{k}.{f}" not in self.STAGE_ONLY}
                 for k in self.MODEL_SECTIONS}
        return {"model": model, "targets": list(self.targets), "cycles": list(self.cycles),
                "joints": list(self.joints), "quantity": self.quantity}

    @classmethod
    def depends_on(cls, name: str) -> bool:
        """Whether the calls' identity (the evaluation store's key) depends on the setting ``name``, as config.json
        names it ('wear.block_cycles', 'uncertainty.variables[0].target')."""
        if name in cls.STAGE_ONLY:
            return False
        return (name.split(".")[0].split("[")[0] in cls.MODEL_SECTIONS or name in cls.CALL_SETTINGS
                or (name.startswith("uncertainty.") and name.endswith(".target")))

    def __call__(self, x: np.ndarray):
        from jointwear.mechanism import build_model
        from jointwear.wear import wear_history

        try:
            cfg = apply_sample(self.base, self.targets, x)
            model = build_model(cfg)  # the assembly check of a general linkage
        except ConfigError as exc:  # the sample's own config names itself 'sample:' already
            return np.full(self.n_outputs, np.nan), f"infeasible sample: {str(exc).removeprefix('sample: ')}"
        res = wear_history(model, cfg.wear, max(self.cycles), threads=self.threads)
        gone = np.asarray(self.cycles, dtype=float) > (np.inf if res.stopped_at is None else res.stopped_at)
        return np.concatenate([np.where(gone, WORN_AWAY_WEAR, quantity_history(res.joints[j], self.quantity,
                                                                                self.cycles))
                               for j in self.joints]), "ok"
