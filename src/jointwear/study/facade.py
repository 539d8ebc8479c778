"""``jointwear.Study``: one object that runs a whole wear-reliability study of one mechanism.

It owns the config (checked whole before anything runs), the output folder, the executor of model calls,
the evaluation store that makes the study resumable, and the progress display. Every stage returns a typed
result (:mod:`jointwear.study.results`) and writes it to the output folder. The command line is a thin
layer over this class, so a study started from one is continued by the other without repeating a call.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import logging
import math
import numbers
import os
import sqlite3
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, ParamSpec, TypeVar

import numpy as np

from jointwear.compute.executors import scheduler_address, scheduler_argument_accepted
from jointwear.config import StudyConfig, config_from_dict, load_config, restore_given, setting_values, updated
from jointwear.reliability import AllCallsFailedError
from jointwear.schema import ConfigError
from jointwear.study.checks import (
    WEAR_CYCLES_MISSING,
    WEAR_CYCLES_NEEDED,
    check_runs,
    config_problems,
    config_warnings,
    nominal_wear_cycles,
    out_problem,
    random_input_problems,
    scheduler_problem,
    scheduler_unreachable,
)
from jointwear.study.convergence import WearConvergence
from jointwear.study.limit_state import (
    joint_allowance,
    limit_state_from_config,
    limit_state_problems,
    nominal_life_line,
    nominal_life_outside_curve,
)
from jointwear.study.model_call import WearModelCall
from jointwear.study.reliability_results import interval_text, signed_percent
from jointwear.study.results import (
    LATER_STAGE_TYPES,
    STAGE_TYPES,
    ReliabilityCurve,
    SensitivityResult,
    SimulationSummary,
    StudyResults,
    ValidationResult,
    WearSummary,
    load_results,
    results_of_a_study,
)
from jointwear.study.stage_lines import (
    budget_line,
    curve_misses_life_line,
    force_line,
    learning_stop_line,
    life_text,
    linear_trend_hint,
    other_lives_line,
    posterior_error_line,
    posterior_tail_line,
    profile_mode_line,
    ranking_line,
    reused_text,
    simulation_cost_line,
    variance_line,
    wear_line,
)
from jointwear.study.stage_result import same_value
from jointwear.study.superseded import DEPENDS_ON, changed_settings, move_aside, section, stale_stages

#: Tag of the true-model calls in the evaluation store (shared by the CLI and the Python API).
WEAR_MODEL_TAG = "wear_model"
STAGES = ("simulate", "wear", "reliability", "sensitivity")

if TYPE_CHECKING:
    from jointwear.design.results import DesignResult


def design_result_type() -> type[DesignResult]:
    """The design stage's result type, for the readers of a study folder (``LATER_STAGE_TYPES``)."""
    # imported on use: the design package imports the study's modules, and the study package imports this one
    from jointwear.design.results import DesignResult

    return DesignResult


LATER_STAGE_TYPES["design"] = design_result_type

logger = logging.getLogger("jointwear")
LOG_FILE = "jointwear.log"


P = ParamSpec("P")
R = TypeVar("R")


def _quiet(stage: Callable[P, R]) -> Callable[P, R]:
    """Run a stage with warnings kept off the user's screen: every warning left after the numerics handled
    theirs goes to ``out/jointwear.log`` (with where it came from) and to the ``jointwear`` logger at DEBUG."""

    @functools.wraps(stage)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        self = args[0]
        with self._stage_scope(), warnings.catch_warnings(record=True) as caught:  # type: ignore[attr-defined]
            warnings.simplefilter("default")
            try:
                return stage(*args, **kwargs)
            finally:
                self._log_warnings(stage.__name__, caught)  # type: ignore[attr-defined]

    return wrapper


class Study:
    """A wear-reliability study of one mechanism.

    Parameters
    ----------
    config : str, Path, StudyConfig or mapping
        A preset name, a TOML file, a validated :class:`jointwear.config.StudyConfig`, or the tables of a TOML file
        as a mapping (unit-suffixed keys and ``extends`` as in a file).
    out : str or Path
        Output folder: every stage writes its JSON, CSV tables and figures there, and the evaluation store
        of the model calls (``evaluations.sqlite``). Nothing is written before the config is checked.
    workers : int, optional
        Local worker processes for model calls (default ``compute.workers`` of the config, else all cores;
        1 runs in this process).
    scheduler : str, distributed.Client or LocalCluster, optional
        A Dask cluster for the model calls: its address (``tcp://host:8786``), a client or a cluster object
        (``jointwear.compute.start_local_cluster``). Either argument replaces the config's compute section.
    resume : bool
        Continue the study whose evaluation store is in ``out`` (no call is repeated). Without it an
        existing store with calls in it is an error, unless ``overwrite``.
    overwrite : bool
        Discard an earlier study's evaluation store in ``out``.
    echo : callable, optional
        Receives a one-line summary of each stage and its warnings (default: the ``jointwear`` logger, the
        summaries at INFO level, the warnings at WARNING level, which Python prints when logging is not set up);
        ``echo=print`` shows the summaries in a notebook too.

    Examples
    --------
    >>> study = jointwear.Study("jin2025_flapping_wing", out="results")   # doctest: +SKIP
    >>> rel = study.reliability()                                        # doctest: +SKIP
    >>> rel.life_cycles, rel.reliability                                 # doctest: +SKIP
    """

    def __init__(self, config: str | Path | StudyConfig | Mapping | None = None, out: str | Path = "results", *,
                 workers: int | None = None, scheduler: Any = None, resume: bool = False,
                 overwrite: bool = False, echo: Callable[[str], None] | None = None):
        # a StudyConfig is validated again: its lists are plain lists, which Python code can still change in place
        self.config: StudyConfig = (config_from_dict(config.model_dump(), "config") if isinstance(config, StudyConfig)
                                    else load_config(config))
        if isinstance(config, StudyConfig):  # what the config gave, not every value of its dump
            restore_given(self.config, {name for name, (_, given) in setting_values(config).items() if given})
        # a StudyConfig that load_config read is that source's config (it is read-only): recorded as if given it
        self.source = (config if isinstance(config, (str, Path))
                       else config.origin if isinstance(config, StudyConfig) else None)
        # a preset is named (or the default); a mapping or a config built in Python is not a preset
        named = config if isinstance(config, str) else self.source if isinstance(config, StudyConfig) else None
        self._preset = config is None or (isinstance(named, str) and not named.endswith(".toml")
                                          and not Path(named).exists())
        if isinstance(out, bytes) or not isinstance(out, (str, os.PathLike)) or not str(out):
            raise ConfigError(f"out: must be the output folder, a str or pathlib.Path (got {out!r})")
        self.out = Path(out)
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, numbers.Integral)
                                    or workers < 1):
            raise ConfigError(f"workers: must be a whole number >= 1 (got {workers!r})")
        workers = None if workers is None else int(workers)
        if scheduler is not None and not scheduler_argument_accepted(scheduler):  # checked before anything is written
            raise ConfigError(f"scheduler: must be a Dask scheduler's address (a str such as 'tcp://host:8786'), a "
                              f"distributed.Client or a cluster object (got {scheduler!r})")
        for name, flag in (("resume", resume), ("overwrite", overwrite)):
            if not isinstance(flag, (bool, np.bool_)):  # "false" is truthy: it discarded the store
                raise ConfigError(f"{name}: must be True or False (got {flag!r})")
        if echo is not None and not callable(echo):
            raise ConfigError(f"echo: must be a function given each line the stages tell, or None (got {echo!r})")
        if scheduler is not None and workers is not None:
            raise ConfigError("workers/scheduler: give either local workers or a Dask scheduler, not both")
        if resume and overwrite:
            raise ConfigError("resume/overwrite: give one of them: resume continues the study in the folder, overwrite "
                              "discards its evaluation store")
        # an argument wins over the config's compute section, whichever of the two the config names
        compute = self.config.compute
        given = workers is not None or scheduler is not None
        self.workers = workers if given else compute.workers
        self.scheduler = scheduler if given else compute.scheduler
        # config.json records where the calls run (a resume from the folder connects there), not the config's
        self._compute_run = (compute.model_copy(update={"workers": workers, "scheduler": scheduler_address(scheduler)})
                             if given else None)
        self.resume = bool(resume)
        self.overwrite = bool(overwrite)
        self.echo = echo if echo is not None else logger.info
        # what needs the user's attention reaches them even without an echo: the logger's WARNING level is printed
        # by Python's last-resort handler when nothing else is configured
        self.warn = echo if echo is not None else logger.warning
        self._checked: set[str] = set()
        self._design_told = False
        self._store_opened = False
        self._context = None
        self._reliability: ReliabilityCurve | None = None
        self._depth = 0  # stages running now (one calls another); the folder is released when the last ends
        self._folder_lock = None
        self._report_moved = False  # report.html moved aside with stale results: rebuilt after the next stage
        self._warnings: list[str] = []  # the config's warnings, found (and told) by its first check
        self._scheduler_reached: str | None = None  # the scheduler address that answered
        self._cycles_given = False  # a wear length given to the stage: the config's need not give one

    def __repr__(self) -> str:
        source = f", source={str(self.source)!r}" if self.source is not None else ""
        where = f", scheduler={self.scheduler!r}" if self.scheduler else f", workers={self.workers!r}"
        return f"Study({self.config.name!r}{source}, out={str(self.out)!r}{where})"

    # ----------------------------------------------------------------------------------------- checking
    def check(self, stages: str | Iterable[str] | None = None) -> list[str]:
        """Check the whole config and that the nominal mechanism assembles and runs. Writes nothing.

        Parameters
        ----------
        stages : str or iterable of str, optional
            The stages whose settings are checked: 'simulate', 'wear', 'reliability', 'sensitivity', 'design'
            (default: every stage the config can run, :attr:`stages`).

        Returns
        -------
        list of str
            What is legal but probably not meant; sent to ``echo`` on the study's first check only.

        Raises
        ------
        jointwear.schema.ConfigError
            Every problem found, listed in one message that names each field.
        """
        known = (*STAGES, "design")
        if isinstance(stages, str):
            stages = (stages,)
        if stages is not None and not isinstance(stages, Iterable):
            raise ConfigError(f"stages: a stage name or a list of them (got {stages!r})")
        for stage in [] if stages is None else stages:
            if stage not in known:
                hint = difflib.get_close_matches(str(stage), known, n=1)
                raise ConfigError(f"stages: {stage!r} is not a stage"
                                  + (f" (did you mean {hint[0]!r}?)" if hint else f" (known: {', '.join(known)})"))
        self._check(stages)
        return list(self._warnings)

    def _check(self, stages=None, out: Path | None = None) -> list[str]:
        """:meth:`check`, and with ``out`` whether that folder can be written, before the check that runs the
        mechanism (the first run compiles the kernels: about a minute on a fresh install)."""
        stages = set(self.stages if stages is None else stages)
        if stages <= self._checked:
            return []
        problems = config_problems(self.config, stages | self._checked)
        if "design" in stages | self._checked:
            from jointwear.design import design_problems

            problems += design_problems(self.config)
        if isinstance(self.scheduler, str) and self.scheduler != self.config.compute.scheduler:
            problem = scheduler_problem(self.scheduler)
            if problem:  # the argument's, told as such when alone (not as the config's, as `out` below)
                problem = problem.replace("compute.scheduler", "scheduler")
                if not problems:
                    raise ConfigError(problem)
                problems.append(problem)
        if out is not None and (problem := out_problem(out)):
            if not problems:
                raise ConfigError(problem)
            problems.append(problem)
        if not problems and not self._checked:
            problems += check_runs(self.config) or random_input_problems(self.config)
        if problems:
            raise ConfigError.from_problems(problems, self._source_label)
        found = [] if self._checked else config_warnings(self.config)
        self._warnings += found
        for warning in found:
            if self._cycles_given and warning.startswith(WEAR_CYCLES_NEEDED):
                continue  # the stage was given its length
            self.warn(f"check: warning: {warning}")
        self._checked |= stages
        return found

    @property
    def _source_label(self) -> str:
        """How messages name the config: the file or preset as given, else 'config'."""
        return "config" if self.source is None else str(self.source)

    @property
    def stages(self) -> tuple[str, ...]:
        """The stages this config can run: all four when it has random variables, and `design` when it also has a
        [design] section (so `check` checks that section too; the other stages only warn about its problems)."""
        unc = self.config.uncertainty
        if unc is None or not unc.all_specs():
            return ("simulate", "wear")
        return STAGES + (("design",) if self.config.design is not None else ())

    def _prepare(self, stages, store_reuse: bool | None = None, *, calls: bool = False) -> None:
        """Check the whole config (every rule of every stage it declares, so that a bad config is refused by
        any command), make sure the output folder can be written and, for a stage that makes model calls
        (``store_reuse`` given, or ``calls``), that its scheduler answers and its evaluation store can be opened;
        then record the resolved config. Nothing is written before these checks pass."""
        declared = set(self.stages) - ({"design"} if "design" not in stages else set())
        self._check(set(stages) | declared, out=self.out)
        self._warn_design_problems(stages)
        if store_reuse is not None or calls:
            self._reach_scheduler()
            self._refuse_worker_pool()
        try:
            self.out.mkdir(parents=True, exist_ok=True)
            probe = self.out / ".jointwear-write-test"
            probe.write_text("")
            probe.unlink()
        except OSError as exc:
            raise ConfigError(f"out: cannot write to '{self.out}': {exc.strerror or exc}") from None
        self._hold_folder()  # before the store is judged: a study starting beside this one finds no store yet
        if store_reuse is not None:
            self._refuse_store(store_reuse)
        from jointwear.study.settings_record import settings_dump, write_dump

        source = "preset" if self._preset else "python" if self.source is None else str(self.source)
        ran = (self.config if self._compute_run is None
               else self.config.model_copy(update={"compute": self._compute_run}))
        dump = settings_dump(ran, preset=self.config.name if self._preset else None, source=source)
        self._supersede(dump["settings"])
        write_dump(self.out, dump)

    def _supersede(self, settings: list[dict]) -> None:
        """Move aside the results in ``out`` computed with other values of the settings they depend on than
        ``settings`` (config.json, about to be rewritten, is the only record of them), and say which and why."""
        changed = changed_settings(self.out, settings)
        unrecorded = changed is None  # no readable config.json: the results' settings are unknown, all count as changed
        stale = stale_stages(self.out, [s["name"] for s in settings] if unrecorded else changed)
        if not stale:
            return
        report = ", and report.html" if (self.out / "report.html").is_file() else ""
        self._report_moved = self._report_moved or bool(report)  # the stage that follows builds it again
        where = move_aside(self.out, stale)
        if unrecorded:
            why = "config.json, the record of their settings, is missing or cannot be read"
        else:
            relevant = [name for name in changed if any(section(name) in DEPENDS_ON[stage] for stage in stale)]
            why = (f"they were computed with other settings (changed: {', '.join(relevant[:3])}"
                   f"{f' and {len(relevant) - 3} more' if len(relevant) > 3 else ''})")
        self.warn(f"out: moved the results of {', '.join(stale)} (with their tables and figures{report}) to {where}: "
                  f"{why}, so they count as not run until their stages run again")

    def _hold_folder(self) -> None:
        """Claim ``out`` for this process until its outermost stage ends, so that a second study started in the
        same folder is refused instead of mixing its files and calls with this one's. The operating system's lock
        ends with the process, so a killed study leaves nothing to clean up."""
        if self._folder_lock is not None:
            return
        from filelock import FileLock, Timeout

        lock = FileLock(self.out / ".jointwear.lock", timeout=0, is_singleton=True)
        try:
            lock.acquire()
        except Timeout:
            raise ConfigError(f"out: another jointwear study is working in '{self.out}' (in another process, or in "
                              "another thread of this one); wait for it to end or give this study another output "
                              "folder") from None
        except OSError as exc:  # a folder that exists but may not be written (read-only, immutable)
            raise ConfigError(f"out: cannot write to '{self.out}': {exc.strerror or exc}") from None
        self._folder_lock = lock

    @contextlib.contextmanager
    def _stage_scope(self) -> Iterator[None]:
        """A stage (or a run of stages) in progress: the folder claimed by its first stage is released at the end."""
        self._depth += 1
        try:
            yield
        finally:
            self._depth -= 1
            if self._depth == 0 and self._folder_lock is not None:
                self._folder_lock.release()
                self._folder_lock = None

    def _warn_design_problems(self, stages) -> None:
        """A [design] section that only `design` reads does not stop the other stages (a variation that shifts a
        mean can leave its acceptance limits behind): its problems are told once instead."""
        if "design" in stages or self.config.design is None or self._design_told:
            return
        from jointwear.design import design_problems

        self._design_told = True
        problems = design_problems(self.config)
        if problems:
            self.warn(f"design: {'; '.join(problems)} (only the design stage reads the [design] section: fix it "
                      "before running that stage, or drop the section, e.g. updated(config, {'design': None}))")

    def _log_warnings(self, stage: str, caught) -> None:
        if not caught:
            return
        lines = [f"{stage}: {w.category.__name__}: {w.message} ({w.filename}:{w.lineno})" for w in caught]
        for line in lines:
            logger.debug(line)
        if self.out.is_dir():
            with open(self.out / LOG_FILE, "a", encoding="utf-8") as fh:
                fh.write("\n".join(lines) + "\n")

    def _allowances(self) -> dict[str, float]:
        """The allowance of each judged joint (of every joint whose allowance is known, when the limit state is
        not defined), for the wear figures."""
        if not limit_state_problems(self.config):
            limit = limit_state_from_config(self.config)
            return dict(zip(limit.names, limit.allowances))
        rel = self.config.reliability
        return {cj.name: a for cj in self.config.clearance_joints if (a := joint_allowance(rel, cj)) is not None}

    # ------------------------------------------------------------------------------------------- stages
    @_quiet
    def simulate(self, cycles: int | None = None, settle: int | None = None) -> SimulationSummary:
        """Dynamics of the nominal mechanism with its clearance joints.

        Parameters
        ----------
        cycles : int, optional
            Crank cycles to record (default ``simulation.cycles`` of the config).
        settle : int, optional
            Cycles simulated and discarded first (default ``simulation.settle_cycles``).

        Returns
        -------
        SimulationSummary
            Contact forces, impacts and orbits per clearance joint; also written to ``simulate.json``.
        """
        from jointwear.mechanism import build_model
        from jointwear.mechanism import simulate as run_simulation

        # the arguments are checked by the fields they stand for (simulation.cycles, simulation.settle_cycles): one
        # check, one message naming the field and its range, before anything is written
        given = {path: v for path, v in (("simulation.cycles", cycles), ("simulation.settle_cycles", settle))
                 if v is not None}
        config = updated(self.config, given, source="simulate(cycles, settle)") if given else self.config
        n, settle = config.simulation.cycles, config.simulation.settle_cycles
        self._prepare({"simulate"})
        model = build_model(config)
        run_simulation(model, 0.01, settle_cycles=0)  # compile (or load) the kernels so the timing excludes it
        res = run_simulation(model, n, settle_cycles=settle)
        result = SimulationSummary.from_simulation(res, self.config.name)
        result.save(self.out)
        self.echo(f"simulate: {n} cycle{'' if n == 1 else 's'}, {result.steps_per_cycle:.0f} steps/cycle, "
                  f"{result.wall_seconds_per_cycle * 1e3:.1f} ms/cycle, crank at "
                  f"{config.mechanism.crank_speed * 30.0 / math.pi:,.4g} rpm; "  # signed: a clockwise drive
                  f"mean contact force {force_line(result)}"
                  f" -> {self.out / result.FILE}")
        # a model call runs the history to the curve's last level
        studied = config.uncertainty is not None and not config.reliability.curve_problems()
        call_cycles = max(config.reliability.curve_cycles()) if studied else nominal_wear_cycles(config)
        cost = simulation_cost_line(result.steps_per_cycle, result.wall_seconds_per_cycle,
                                    call_cycles and config.wear.simulated_cycles(call_cycles), call_cycles,
                                    config.reliability.max_calls if studied else None)
        if cost:
            self.echo(f"simulate: {cost}")
        self._tell("simulate", result)
        return result

    @_quiet
    def wear(self, cycles: int | None = None, *, progress: Callable | None = None) -> WearSummary:
        """Non-uniform wear history of the nominal mechanism.

        Parameters
        ----------
        cycles : int, optional
            Crank cycles of the history (default ``wear.cycles`` of the config).
        progress : callable, optional
            Called with the progress of the history (for a progress bar).

        Returns
        -------
        WearSummary
            Wear profiles of bearing and journal and the growth of the deepest wear; also written to
            ``wear.json``.
        """
        from jointwear.mechanism import build_model
        from jointwear.wear import wear_history

        n = self._wear_cycles(cycles)  # refused before anything is written
        self._cycles_given = cycles is not None
        self._prepare({"wear"})
        t0 = time.perf_counter()
        res = wear_history(build_model(self.config), self.config.wear, n, progress=progress)
        result = WearSummary.from_history(res, self.config, self._allowances())
        result.save(self.out)
        asked = result.cycles_requested or result.cycles
        ran = (f"{result.cycles:,} cycles" if result.stopped_at_cycles is None
               else f"{result.stopped_at_cycles:,} of {asked:,} cycles (stopped: worn away)")
        self.echo(f"wear: max bearing wear {wear_line(result)} after {ran} "
                  f"(history {res.wall_seconds:.1f} s, stage {time.perf_counter() - t0:.1f} s) "
                  f"-> {self.out / result.FILE}")
        mode = profile_mode_line(result)
        if mode:
            self.echo(f"wear: {mode}")
        if not nominal_life_outside_curve(self.config, result.joints):  # that warning gives the life itself
            life = nominal_life_line(self.config, result.joints)
            if life:
                self.echo(f"wear: {life}")
        if "reliability" in self.stages and result.stopped_at_cycles is None:
            from jointwear.study.reliability import model_call
            from jointwear.study.sensitivity import far_shift_calls

            budget = budget_line(res.wall_seconds, result.cycles, max(model_call(self.config).cycles),
                                 self.config.reliability.max_calls, far_shift_calls(self.config))
            if budget:
                self.echo(f"wear: {budget}")
        self._tell("wear", result)
        return result

    def _wear_cycles(self, cycles: int | None) -> int:
        """The nominal history's length: the caller's (checked), else the config's (``wear.cycles``, else the
        curve's end)."""
        n = cycles if cycles is not None else nominal_wear_cycles(self.config)
        if n is None:
            raise ConfigError(WEAR_CYCLES_MISSING)
        return _cycles_argument(n)

    @_quiet
    def converge(self, replicates: int = 8, factor: float = 2.0, tolerance: float = 0.02,
                 only: list[str] | None = None, cycles: int | None = None) -> WearConvergence:
        """Whether the nominal wear history is converged in its numerical settings on this mechanism.

        Runs the nominal history with the config's wear settings and with each numerical setting refined by
        ``factor`` (recorded and settling cycles per block, block, angular grid, integrator tolerances; in profile
        mode also the running-in length and the deposit's sub-step), ``replicates`` runs each from other start
        phases, and judges each change of the nominal life against ``tolerance`` with its 95 % interval
        (docs/wear.md, "Is my history converged?").

        Parameters
        ----------
        replicates : int
            Runs per setting (>= 2); a chaotic contact needs more to tell a change from its scatter.
        factor : float
            Refinement factor (> 1) of every setting.
        tolerance : float
            Relative change of the nominal life that counts as converged.
        only : list of str, optional
            The refinements to run (default all): ``record_cycles``, ``settle_cycles``, ``block``, ``n_grid``,
            ``tolerance`` and, in profile mode, ``profile_smoothing_deg`` and ``profile_substep_cycles``.
        cycles : int, optional
            Cycles of each history (default ``wear.cycles``, else the end of the R(N) curve).

        Returns
        -------
        WearConvergence
            Also written to ``wear_convergence.json`` and ``wear_convergence.csv``; each history is kept in
            ``wear_convergence.sqlite`` as it ends, so a check resumes (``overwrite=True`` starts it afresh).
        """
        from jointwear import compute
        from jointwear.study.convergence import (
            STORE_FILE,
            STORE_TAG,
            ConvergenceCall,
            chosen_refinements,
            half_width,
            run_convergence,
        )

        n = self._wear_cycles(cycles)
        chosen_refinements(self.config, replicates, factor, tolerance, only)
        self._prepare({"wear"}, calls=True)
        digest = compute.config_hash(ConvergenceCall(self.config.model_dump()).identity())
        with self._compute(reuse=True, description="histories", store_file=STORE_FILE, digest=digest) as (
                executor, store, progress):
            result = run_convergence(
                self.config, n, replicates=replicates, factor=factor, tolerance=tolerance, only=only,
                threads=executor.threads_per_call, evaluator_factory=lambda call: compute.Evaluator(
                    call, executor, store, timeout=self.config.compute.call_timeout, tag=STORE_TAG,
                    n_outputs=call.n_outputs, progress=progress))
        result.save(self.out)
        what = "nominal life" if result.measure == "life" else "final wear"
        mean = result.baseline["mean"]
        value = f"{mean:,.0f} cycles" if result.measure == "life" else f"{mean * 1e3:.4g} mm"
        self.echo(f"converge: {what} {value}, scatter {100 * result.scatter:.1f} % over {result.replicates} start "
                  f"phases; each setting refined {result.factor:g}x ({result.wall_seconds:.0f} s):")
        for r in result.refinements:
            for joint, _, values, _, verdict in result.subjects(r):
                name = f"  joint {joint}" if joint else r["name"]
                self.echo(f"  {name:<24} {100 * values['change']:+6.1f} % +- {100 * half_width(values):4.1f} %"
                          f"  {verdict}")
        self.echo(f"converge: -> {self.out / result.FILE}")
        for sentence in result.sentences():
            self.warn(f"converge: {sentence}")
        return result

    @_quiet
    def reliability(self) -> ReliabilityCurve:
        """The reliability curve R(N) and the life at each target reliability (AK-MCS on the true wear model).

        Returns
        -------
        ReliabilityCurve
            The curve, the life table and the model calls spent; also written to ``reliability.json``.
        """
        self._prepare({"reliability"}, store_reuse=False)
        with self._session(reuse=False) as ctx:
            return self._learn(ctx)

    def _learn(self, ctx) -> ReliabilityCurve:
        """Run the reliability stage in ``ctx``, write its result and tell it (the same when another stage needs
        it first): the calls made, read back, the life, and what the user must know about the curve."""
        from jointwear.study.reliability import run_reliability

        before = ctx.n_model_calls
        res = run_reliability(ctx, progress=self._progress_callback)
        new = ctx.n_model_calls - before
        recorded = ReliabilityCurve.load_if_present(self.out)
        if new == 0 and recorded is not None and recorded.model_calls == res.model_calls and same_value(
                recorded.reliability, res.reliability):
            res.wall_seconds = recorded.wall_seconds  # a replay of the stored calls: the study's own time
        self._reliability = res
        res.save(self.out)
        life = life_text(res.life_table[0])
        governing = f", governed by joint {res.governing_joint}" if len(res.joints) > 1 else ""
        self.echo(f"reliability: {res.model_calls} model calls{reused_text(new, res.model_calls)}, "
                  f"n_mc = {res.n_mc:,}, life at R = {res.target}: {life}{governing} -> {self.out / res.FILE}")
        if others := other_lives_line(res):
            self.echo(f"reliability: the other targets' lives: {others}")
        self._tell("reliability", res)
        return res

    def _tell(self, stage: str, res) -> None:
        """Warn of what the user must know about ``stage``'s result, whether computed now or kept by a resumed run:
        contacts outside Hertz's range and whirls (simulate); a joint worn away or through, a nominal life off the
        curve, uniform mode outside its range (wear); an unconverged learning, failed or worn-away calls, a poor fit,
        a series system's governing joints, a curve that misses the life (reliability)."""
        sentences: list[str] = []
        if stage == "simulate":
            sentences = res.outside_hertz() + res.whirls()
        elif stage == "wear":
            placed = nominal_life_outside_curve(self.config, res.joints)
            sentences = (res.worn_away() + res.worn_through() + res.outside_hertz() + res.whirls()
                         + ([placed] if placed else [])
                         + res.unjudged_wear(self.config.reliability.quantity))
            if uniform := res.uniform_range_sentence():
                sentences.append(uniform)
        elif stage == "reliability":
            from jointwear.study.reliability import POSTERIOR_POINTS

            missed = curve_misses_life_line(res, WearSummary.load_if_present(self.out))
            sentences = [learning_stop_line(res, self.config.reliability) if not res.converged else None,
                         posterior_error_line(res, self.config.reliability),
                         res.failed_calls_sentence(), res.worn_away_sentence(), res.surrogate_fit_sentence(),
                         res.series_sentence(), missed and missed.rstrip("."),
                         posterior_tail_line(res, POSTERIOR_POINTS)]
        for sentence in sentences:
            if sentence:
                self.warn(f"{stage}: {sentence}")

    @_quiet
    def sensitivity(self) -> SensitivityResult:
        """Sensitivity of the reliability to every variable: mean shifts, Sobol' indices and derivatives.

        Runs (or reads back from the evaluation store) the reliability stage first.

        Returns
        -------
        SensitivityResult
            Also written to ``sensitivity.json``.
        """
        from jointwear.study.sensitivity import coordinate_shift_sentence, far_shift_calls, run_sensitivity

        self._prepare({"reliability", "sensitivity"}, store_reuse=True)
        with self._session(reuse=True) as ctx:
            learned = self._learned(ctx)
            self._progress_phase("sensitivity shifts", far_shift_calls(self.config))  # not the learning's count
            before = ctx.n_model_calls
            sens = run_sensitivity(ctx, learned)
            new = ctx.n_model_calls - before
        sens.save(self.out)
        extra = sens.extra_model_calls
        variance, output = variance_line(sens), sens.sobol.get("output") or "wear"
        self.echo(f"sensitivity: ranking by R at each mean x {sens.factors[0]:g} and x {sens.factors[1]:g} (a change "
                  f"of the nominal design, not of its scatter): {ranking_line(sens)}"
                  f"{f'; by total-effect Sobol index ST of the {output}: {variance}' if variance else ''}"
                  f"{f' ({scatter})' if (scatter := sens.scatter_sentence()) and variance else ''}; "
                  f"{extra} extra model calls{reused_text(new, extra)} "
                  f"-> {self.out / sens.FILE}")
        targets = {s.name: s.target for s in self.config.uncertainty.all_specs()}
        if coordinates := coordinate_shift_sentence(targets, tuple(sens.factors), self.config.mechanism.model_dump()):
            self.warn(f"sensitivity: {coordinates}")
        if unbuilt := sens.unbuilt_shifts_sentence():
            self.warn(f"sensitivity: {unbuilt}")
        if extreme := sens.extreme_shifts_sentence():
            self.warn(f"sensitivity: {extreme}")
        return sens

    @_quiet
    def validate(self, n_samples: int = 2000) -> ValidationResult:
        """Check the R(N) curve against the true wear model sampled directly, and cross-validate the surrogate.

        Runs (or reads back from the store) the reliability stage first. The samples go through the executor
        and the evaluation store, so an interrupted validation resumes. The learnt surrogate is also read on the same
        samples: their difference is its own error (``ValidationResult.paired_difference``, ``paired_ratio`` of the
        life in ``life_table``), a few hundred samples measuring the life's (docs/study.md, "Direct validation").

        Parameters
        ----------
        n_samples : int
            Fresh random samples, one true-model call each.

        Returns
        -------
        ValidationResult
            Also written to ``validation.json``.
        """
        from jointwear.study.validation import run_validation

        if isinstance(n_samples, bool) or not isinstance(n_samples, numbers.Integral) or n_samples < 1:
            # the CLI's --samples is checked by click, so this message is read from Python only
            raise ConfigError(f"n_samples: must be a whole number >= 1 (got {n_samples!r})")
        n_samples = int(n_samples)
        self._prepare({"reliability"}, store_reuse=True)
        before = ValidationResult.load_if_present(self.out)  # after _prepare: one of other settings has moved aside
        with self._session(reuse=True) as ctx:
            learned = self._learned(ctx)
            self._progress_phase("validation samples", n_samples)
            result = run_validation(ctx, learned, n_samples)
        result.save(self.out)
        if before is not None and before.n_samples > n_samples:  # its calls stay in the store: nothing is lost
            self.warn(f"validate: this validation of {n_samples:,} samples replaces one of {before.n_samples:,} in "
                      f"{self.out}; validating again with {before.n_samples:,} reads its calls back from the store")
        agree = sum(result.agreement)
        life = ""
        if result.life_table and result.life_table[0]["cycles"] is not None:
            row = result.life_table[0]
            life = (f", life at R = {row['target']:g}: true model {row['cycles']:,.0f} cycles "
                    f"({interval_text(row['cycles_low'], row['cycles_high'])}), surrogate "
                    f"{'-' if row['surrogate_cycles'] is None else format(row['surrogate_cycles'], ',.0f')}"
                    f"{'' if row['agree'] else ' (the intervals do not overlap)'}")
        elif result.life_table and result.life_table[0].get("note"):
            life = f", life at R = {result.life_table[0]['target']:g}: {result.life_table[0]['note']}"
        if paired := result.paired_life_sentence() or result.unpaired_life_sentence():
            life += f"; {paired}"
        if result.paired:
            life += f"; {result.paired_error_sentence()}"
        joints = "".join(f", joint {j['name']} at {j['levels_agree']}" for j in result.joints if "levels_agree" in j)
        missed = result.disagreement()
        where = f" ({missed})" if missed else ""
        strict = result.differences_at_95()
        strict = f"; {strict}" if strict else ""
        reused = reused_text(result.model_calls, result.n_samples)
        self.echo(f"validate: {result.n_samples:,} true-model samples{reused}, "
                  f"agreement at {agree} of {len(result.agreement)} levels (overlapping 95 % intervals; these samples "
                  f"resolve R to +-{result.resolution:.2g}){where}{strict}"
                  f"{joints}{life}, cross-validation Q2 = "
                  f"{result.cross_validation.get('q2', float('nan')):.3f} -> {self.out / result.FILE}")
        if (check := result.paired_life_allowed()) is not None and check[2] == "beyond":
            self.warn(f"validate: {result.paired_life_sentence()}, beyond what the life's 95 % interval allows "
                      f"({signed_percent(check[0])} to {signed_percent(check[1])}): the life carries more error than "
                      "its interval says (docs/reliability.md, \"The learnt life's spread\")"
                      + (f"; {hint}" if (hint := linear_trend_hint(self.config.reliability.trend)) else ""))
        self._refresh_report()
        return result

    def _refresh_report(self) -> None:
        """Rebuild a report already in the folder (or moved aside with the results a changed setting made stale): it
        would go on without the stage that just wrote its result."""
        if (self.out / "report.html").is_file() or self._report_moved:
            self._report_moved = False
            self.report()

    def report(self) -> Path:
        """Build ``out/report.html`` from the results in the output folder; returns its path."""
        from jointwear.report.html import build_report

        results_of_a_study(self.out, "report")
        path = build_report(self.out)
        self.echo(f"report: {path}")
        return path

    def run(self) -> StudyResults:
        """Every stage end to end, as ``jointwear run``.

        Simulate, wear, then reliability and sensitivity when the config has random variables, then the report.

        Returns
        -------
        StudyResults
            Every stage's typed result, read back from ``out`` as :func:`load_results` gives it (the reliability's
            learning ``engine`` with its surrogates is not written, so it is None here; :meth:`reliability` returns
            it).
        """
        t0 = time.perf_counter()
        stochastic = "reliability" in self.stages
        self._wear_cycles(None)  # a run without a wear length is refused before any stage writes
        self.check(self.stages)
        with self._stage_scope():  # the folder stays this run's between its stages
            if self.out.is_dir():  # a study running there is told as such, not as an earlier run's store
                self._hold_folder()
            if stochastic:
                self._refuse_store(reuse=False)
                self._reach_scheduler()  # before the nominal stages spend their time
            if not self._current("simulate"):
                self.simulate()
            if not self._current("wear"):
                self.wear()
            if stochastic:
                if not self._current("reliability", "sensitivity"):
                    self.reliability()
                    self.sensitivity()
            else:
                self.echo("run: no [uncertainty] section: reliability and sensitivity skipped")
            path = self.report()
        self.echo(f"run: done in {time.perf_counter() - t0:.0f} s -> {path}")
        return load_results(self.out)

    def _current(self, *stages: str) -> bool:
        """Whether a resumed run finds the results of ``stages`` already computed for this config (a result computed
        with other settings is no longer there: :meth:`_supersede`), and says so: a long profile-mode history is not
        run again, nor is the learning replayed from the store to give the curve and the sensitivity it gave."""
        if not self.resume:
            return False
        self._prepare(set(stages))
        found = [self._found(stage) for stage in stages]
        if any(res is None for res in found):
            return False
        for stage, res in zip(stages, found):
            self.echo(f"{stage}: the result for this config is already in {self.out / res.FILE} (resume): not run "
                      "again")
            self._tell(stage, res)
        return True

    def _found(self, stage: str):
        """``stage``'s result in ``out`` if it was computed for this config's cycle counts (None otherwise)."""
        res = STAGE_TYPES[stage].load_if_present(self.out)
        if res is None:
            return None
        if stage == "simulate":
            sim = self.config.simulation
            current = (res.cycles, res.settle_cycles) == (sim.cycles, sim.settle_cycles)
        elif stage == "wear":
            current = (res.cycles_requested or res.cycles) == nominal_wear_cycles(self.config)
        else:
            current = True
        return res if current else None

    def _learned(self, ctx) -> ReliabilityCurve:
        """The reliability result of this study: the one in memory, else learned again from the evaluation store
        (the learning is deterministic, so the stored calls are replayed and no call is repeated) and told as the
        stage tells it when run alone."""
        if self._reliability is None:
            self._learn(ctx)
        return self._reliability

    # --------------------------------------------------------------------------------------- model calls
    def _store_mode(self, reuse: bool) -> dict:
        """How the evaluation store is opened: afresh (``--overwrite``, or a store with no call in it), else resumed
        when asked, once opened in this session, or by a stage that reuses the study's calls (``reuse``)."""
        fresh = not self._store_opened and (self.overwrite or _empty_store(self.out))
        resume = self.resume or self._store_opened or reuse
        return {"resume": resume and not fresh, "overwrite": fresh}

    def _store_message(self, exc: Exception) -> str:
        from jointwear import compute

        if isinstance(exc, compute.ConfigChangedError):
            from jointwear.study.settings_record import settings_dump

            changed = _changed_settings(self.out, settings_dump(self.config)["settings"], of_calls=True)
            named = f" (changed: {', '.join(changed)})" if changed else (
                f" (the {', '.join(WearModelCall.MODEL_SECTIONS)} sections, the random variables' targets or the "
                "curve's cycle counts changed)")
            # the folder leads, as a config file leads its problems: 'out:' read as a stray word before it
            return (f"{self.out}: the evaluation store there holds calls of another wear model{named}. Resume with "
                    "the config they were made with, or use a new output folder (--out; out= in Python); the "
                    "learning, sensitivity, design and report settings may change on resume.")
        return str(exc)

    def _refuse_store(self, reuse: bool) -> None:
        """Refuse, before any stage writes to ``out``, a study whose evaluation store would be refused later."""
        from jointwear import compute
        from jointwear.study.reliability import store_digest

        problem = compute.EvaluationStore.refusal(self.out, store_digest(self.config, self.out),
                                                  **self._store_mode(reuse))
        if problem is not None:
            raise ConfigError(self._store_message(problem))

    @contextlib.contextmanager
    def _compute(self, *, reuse: bool, description: str = "model calls", store_file: str | None = None,
                 digest: str | None = None) -> Iterator:
        """The executor of model calls, an evaluation store and a progress display: (executor, store, progress).
        The store is the study's (``evaluations.sqlite``), or ``store_file`` in the output folder keyed by
        ``digest`` (resumed unless ``overwrite``)."""
        from jointwear import compute
        from jointwear.study.reliability import store_digest

        try:
            if store_file is None:
                store = compute.EvaluationStore.open(self.out, store_digest(self.config, self.out),
                                                     **self._store_mode(reuse))
                self._store_opened = True
            else:
                store = compute.EvaluationStore.open(self.out / store_file, digest, resume=not self.overwrite,
                                                     overwrite=self.overwrite)
        except compute.StoreError as exc:
            if store_file is not None and isinstance(exc, compute.ConfigChangedError):
                raise ConfigError(f"out: {self.out / store_file} holds histories of another wear model (its "
                                  "mechanism, clearance_joints, simulation, wear or limit-state settings changed): "
                                  "start the check afresh with --overwrite (overwrite=True in Python), or use a new "
                                  "output folder") from None
            raise ConfigError(self._store_message(exc)) from None
        try:
            self._reach_scheduler()
        except ConfigError:
            store.close()
            raise
        try:
            executor = compute.make_executor(workers=self.workers, scheduler=self.scheduler)
        except Exception as exc:  # noqa: BLE001 - a bad address or an unreachable cluster is a user error
            store.close()
            raise ConfigError(f"compute: cannot start the executor: {' '.join(str(exc).split())}") from None
        progress = compute.Progress(total=None, description=description)
        try:
            with executor, progress:
                yield executor, store, progress
        except KeyboardInterrupt as exc:  # the command line says this on Ctrl-C; Python shows it under the traceback
            again = ("run the check again to continue from them" if store_file is not None else
                     "run the study again with resume=True (--resume) to continue from them")
            exc.add_note(f"The model calls made so far are kept in {store.path}: {again}.")
            raise
        finally:
            store.close()

    def _refuse_worker_pool(self) -> None:
        """Refuse local worker processes that could not run this process's calls (a script without the
        ``__main__`` guard) before anything is written: the executor would refuse them after the folder was."""
        from jointwear import compute

        workers = self.workers if self.workers is not None else compute.available_cores()
        problem = compute.worker_pool_problem(workers) if self.scheduler is None and workers > 1 else None
        if problem is not None:
            raise ConfigError(f"compute: cannot start the executor: {problem}")

    def _reach_scheduler(self) -> None:
        """Refuse a Dask scheduler that does not answer (in seconds, where distributed waits half a minute); once
        reached, it is not asked again by this study."""
        if self.scheduler is None or self._scheduler_reached == self.scheduler:
            return
        unreachable = scheduler_unreachable(self.scheduler)
        if unreachable:
            raise ConfigError(f"compute: cannot start the executor: {unreachable}")
        self._scheduler_reached = self.scheduler

    @contextlib.contextmanager
    def _session(self, *, reuse: bool) -> Iterator:
        """The study context with its evaluator: executor, evaluation store and progress display."""
        from jointwear import compute
        from jointwear.study.reliability import study_context

        with self._compute(reuse=reuse) as (executor, store, progress):
            self._progress = progress
            ctx = study_context(self.config, lambda call: compute.Evaluator(
                call, executor, store, timeout=self.config.compute.call_timeout, tag=WEAR_MODEL_TAG,
                n_outputs=call.n_outputs, progress=progress), threads=executor.threads_per_call)
            if self._context is not None:
                ctx.evaluator.adopt(self._context.evaluator)
            self._context = ctx
            try:
                yield ctx
            except AllCallsFailedError as exc:
                raise ConfigError(self._all_failed_message(ctx, exc)) from None

    def _all_failed_message(self, ctx, exc: Exception) -> str:
        """One line for a learning whose first model calls all failed: the engine's message knows only its g, the
        store knows why the first call failed (the reason comes first, so the line leads with what to fix)."""
        reasons = list(ctx.call_failures.values())
        if not reasons:
            return f"reliability: every model call of the initial design failed: {' '.join(str(exc).split())}"
        return (f"reliability: every one of the first {len(reasons)} model calls failed, so the study cannot learn; "
                f"the first call's stored reason: {' '.join(reasons[0].split())} (every call's reason is kept in "
                f"{self.out / 'evaluations.sqlite'})")

    def _progress_phase(self, description: str, total: int | None = None) -> None:
        """The progress display starts another phase of model calls (the validation's samples after the learning):
        its counter from 0, its own total, and none of the learning's fields (its Pf, COV, min U and budget)."""
        self._progress.update(description=description, completed=0, total=total,
                              **dict.fromkeys(list(self._progress.fields)))

    def _progress_callback(self, record) -> None:
        cycles = self._context.cycles
        k = self.config.reliability.progress_level(cycles)
        pf = np.atleast_1d(record.pf)
        cov = np.atleast_1d(getattr(record, "cov", np.nan))
        with np.errstate(invalid="ignore"):
            min_u = np.atleast_1d(record.min_u).astype(float)
            min_u = float(np.nanmin(min_u)) if np.isfinite(min_u).any() else float("nan")
        # the bar's total grows batch by batch (the learning may stop before its budget): the budget is said beside
        self._progress.update(**{f"Pf({cycles[k] / 1e3:g}k)": f"{pf[min(k, pf.size - 1)]:.3g}",
                                 "COV": f"{cov[min(k, cov.size - 1)]:.2g}", "min U": f"{min_u:.2f}",
                                 "budget": f"{self.config.reliability.max_calls} calls"})

    # ------------------------------------------------------------------------------------------- design
    @_quiet
    def design(self) -> DesignResult:
        """Uncertainty control (``[design]``): the cheapest controls that reach the target life.

        Finds the cheapest tolerance grades, fit and material specifications that reach the target life at the
        target reliability, the Pareto front of cost against the life at R*, and verifies the choice by its own
        reliability study. Runs (or reads back from the evaluation store) the reliability stage first.

        Returns
        -------
        jointwear.design.DesignResult
            Also written to ``design.json``.
        """
        from jointwear.design import design_problems, run_design
        from jointwear.design.results import choices_text, life_interval_text

        problems = design_problems(self.config)
        if problems:
            raise ConfigError.from_problems(problems, self._source_label)
        self._prepare({"reliability"}, store_reuse=True)
        with self._session(reuse=True) as ctx:
            result = run_design(ctx, self._learned(ctx), echo=self.echo, on_phase=self._progress_phase)
            new = ctx.n_model_calls  # this call's, the reliability stage's when it ran first here too
        result.save(self.out)
        calls = f"{result.model_calls} model calls{reused_text(new, result.model_calls)} -> {self.out / result.FILE}"
        chosen = result.chosen
        if chosen is None:  # none reached the target on the surrogate, or every one that did was refuted
            self.echo(f"design: {result.no_choice_sentence()}; {calls}")
            self._warn_design_trust({})
            if outside := result.target_outside_curve_sentence():  # the nearest's R(N*) is then the less sure
                self.warn(f"design: {outside}")
            self._refresh_report()
            return result
        picks = choices_text(chosen["choices"])
        life = "" if chosen.get("life_at_target_cycles") is None else \
            f", a life of {life_interval_text(chosen)} cycles at R = {result.target_reliability:g}"
        unproven = result.unproven_sentence()  # its verification neither refutes nor proves it
        self.echo(f"design: {picks} (cost {chosen['cost']:.3g}): on the surrogate R = "
                  f"{chosen['reliability_at_target_life']:.4f} +/- {chosen['reliability_error']:.4f} at the target "
                  f"{result.target_life_cycles:,.0f} cycles{life}{'; ' + unproven if unproven else ''}; {calls}")
        self.echo(f"design: {result.change_sentence()}")
        if relative := result.relative_target_sentence():
            self.echo(f"design: {relative}")
        sentence = result.verification_sentence()
        (self.echo if result.verdict() in ("meets", "within_error") else self.warn)(f"design: {sentence}")
        if every := result.every_target_sentence():
            self.warn(f"design: the headline choice does not meet every target; {every}")
        if check := result.every_target_check_sentence():
            met = result.chosen_every_target["verification"]["verdict"] == "meets"
            (self.echo if met else self.warn)(f"design: {check}")
        self._warn_design_trust(chosen)
        for sentence in (result.undecided_sentence(), result.target_outside_curve_sentence()):
            if sentence:
                self.warn(f"design: {sentence}")
        self._refresh_report()
        return result

    def _warn_design_trust(self, chosen: dict) -> None:
        """What the choice rests on that the user must know before buying it: an extrapolated estimate, and
        uniform-mode wear outside its range (as the folder's wear stage found it)."""
        from jointwear.design.results import EXTRAPOLATED_SHARE

        share = chosen.get("outside_design_fraction") or 0.0
        if share > EXTRAPOLATED_SHARE:
            self.warn(f"design: {share:.0%} of the chosen design's population lies outside the inputs the study's "
                      "surrogate learned from: its R(N*) is partly an extrapolation (widen the study's inputs to cover "
                      "it, or keep the verification on)")
        wear = WearSummary.load_if_present(self.out)
        if wear is not None and wear.uniform_out_of_range:
            self.warn(f"design: the choice rests on uniform-mode wear, which the wear stage found outside its range "
                      f"(conformity {wear.conformity:.3g} > 1); rerun the study and the design with "
                      'wear.geometry_mode = "profile" before deciding (docs/wear.md)')


def _changed_settings(out: Path, settings: list[dict], *, of_calls: bool = False) -> list[str]:
    """The settings of the wear model (``WearModelCall.MODEL_SECTIONS``; ``of_calls``: every setting the model
    calls' identity depends on, ``WearModelCall.depends_on``) whose values differ from those recorded in
    ``out/config.json`` by an earlier study (empty when there is none, or it had this model)."""
    changed = changed_settings(out, settings) or []
    model = tuple(WearModelCall.MODEL_SECTIONS)
    return [name for name in changed if (WearModelCall.depends_on(name) if of_calls else section(name) in model)]


def _empty_store(out: Path) -> bool:
    """Whether ``out`` holds an evaluation store with no call in it (a study stopped before its first call:
    nothing to lose by reopening it)."""
    from jointwear.compute.store import read_only_uri

    db = out / "evaluations.sqlite"
    if not db.exists():
        return False
    try:
        with contextlib.closing(sqlite3.connect(read_only_uri(db), uri=True, timeout=5)) as con:
            return int(con.execute("select count(*) from calls").fetchone()[0]) == 0
    except sqlite3.Error:
        return False


def _cycles_argument(value) -> int:
    """A stage's cycle count checked (:func:`~jointwear.wear.settings.check_cycles`): its problem is a ConfigError,
    as every check at the boundary."""
    from jointwear.wear.settings import check_cycles

    try:
        return check_cycles(value, "cycles")
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
