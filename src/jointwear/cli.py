"""Command line: ``jointwear <command> [CONFIG] ... --out DIR``, a thin layer over :class:`jointwear.Study`.

CONFIG is a TOML file or a preset name (default ``jin2025_flapping_wing``). Errors in the config or the
arguments end with exit status 2 and one plain line on stderr (no traceback); nothing is written to
``--out`` when the config is bad.
"""

from __future__ import annotations

import inspect
import math
import signal
import sys
from pathlib import Path

import click

from jointwear.schema import ConfigError

#: what every command's help says of its CONFIG argument
CONFIG_HELP = ("CONFIG is a TOML file or a preset name (jointwear presets); without it, the jin2025_flapping_wing "
               "preset.")


def config_argument(f):
    """The optional CONFIG argument, and its meaning at the end of the command's help."""
    f.__doc__ = f"{inspect.cleandoc(f.__doc__ or '')}\n\n{CONFIG_HELP}"
    return click.argument("config", required=False, default=None)(f)
out_option = click.option(
    "--out", "out", type=click.Path(file_okay=False, path_type=Path), default=Path("results"), show_default=True,
    help="Output directory (created if missing).",
)


def compute_options(f):
    """--workers, --scheduler, --resume, --overwrite: where model calls run and what happens to a store."""
    f = click.option("--workers", type=click.IntRange(min=1), default=None,
                     help="Local worker processes for model calls (default: compute.workers, else all cores; "
                          "not with --scheduler).")(f)
    f = click.option("--scheduler", default=None, metavar="ADDRESS",
                     help="Dask scheduler address (tcp://host:8786, or host:8786) to run model calls on a cluster "
                          "(the 'cluster' extra; not with --workers).")(f)
    f = click.option("--resume", is_flag=True,
                     help="Continue the study whose model calls are stored in --out (no call is repeated; not with "
                          "--overwrite).")(f)
    f = click.option("--overwrite", is_flag=True,
                     help="Discard the model calls stored in --out and start afresh (not with --resume).")(f)
    return f


def say(msg: str) -> None:
    """A line on stderr, resolved when it is written: while a live progress line runs, rich has put its own stream
    there and prints the line above the bar (click.echo reached the terminal past it, onto the bar's end)."""
    print(msg, file=sys.stderr, flush=True)


def open_study(config, out, workers=None, scheduler=None, resume=False, overwrite=False):
    from jointwear.study import Study

    return Study(config, out=out, workers=workers, scheduler=scheduler, resume=resume, overwrite=overwrite,
                 echo=say)


class JointwearGroup(click.Group):
    """A click group whose ``main()`` maps config/usage errors to one line on stderr and exit status 2."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):  # type: ignore[override]
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        # a batch scheduler ends a job with SIGTERM: stop as on Ctrl-C (the workers ended, the resume hint told)
        signal.signal(signal.SIGTERM, _terminated)
        for stream in (sys.stdout, sys.stderr):  # a dash or a degree sign must not end a run on a cp437 console
            if hasattr(stream, "reconfigure"):
                stream.reconfigure(errors="replace")
        sys.exit(self.run(args, prog_name or "jointwear"))

    def run(self, args: list[str] | None = None, prog_name: str = "jointwear") -> int:
        given = list(sys.argv[1:] if args is None else args)

        def resume_hint() -> str:
            if next((a for a in given if not a.startswith("-")), None) not in RESUMABLE:
                return ""
            return (" (the model calls made so far are kept in the output folder's evaluation store: run the same "
                    "command again with --resume to continue it)")

        try:
            rv = super().main(args=given, prog_name=prog_name, standalone_mode=False)
        except ConfigError as exc:
            click.echo(f"error: {one_line(str(exc))}", err=True)
            return 2
        except click.exceptions.Abort:
            click.echo(f"error: aborted{resume_hint()}", err=True)
            return 128 + (signal.SIGTERM if _TERMINATED else signal.SIGINT)  # the shell's convention: 143, 130
        except click.exceptions.NoArgsIsHelpError as exc:  # bare `jointwear`: the help, as `jointwear --help`
            click.echo(exc.ctx.get_help())
            return 0
        except click.UsageError as exc:
            click.echo(f"error: {one_line(exc.format_message())}", err=True)
            return 2
        except click.ClickException as exc:
            click.echo(f"error: {one_line(exc.format_message())}", err=True)
            return exc.exit_code if exc.exit_code else 2
        except RuntimeError as exc:
            # imported here: it loads numba (0.3 s of every command's start)
            from jointwear.mechanism.results import SimulationError

            if not isinstance(exc, SimulationError):
                raise
            click.echo(f"error: simulation failed: {one_line(str(exc))}", err=True)
            return 1
        except BaseException as exc:  # a lost Dask scheduler or a worker of another version (see ClusterError)
            from jointwear.compute.executors import ClusterError  # here: importing it loads numpy

            if not isinstance(exc, ClusterError):
                raise
            click.echo(f"error: {one_line(str(exc))}{resume_hint()}", err=True)
            return 2
        return rv if isinstance(rv, int) else 0


_TERMINATED = False
#: the commands that keep their model calls in a store and take --resume
RESUMABLE = frozenset({"run", "reliability", "sensitivity", "validate", "design", "converge"})


def _terminated(signum, frame) -> None:
    """SIGTERM: end as a Ctrl-C does (click turns the KeyboardInterrupt into Abort), with exit status 143."""
    global _TERMINATED
    _TERMINATED = True
    raise KeyboardInterrupt


def one_line(msg: str) -> str:
    return " ".join(msg.split())


def _versions(ctx, _param, value) -> None:
    if not value or ctx.resilient_parsing:
        return
    from jointwear.study.io import provenance

    p = provenance()
    deps = ", ".join(f"{k} {p[k]}" for k in ("numpy", "scipy", "numba", "openturns") if p.get(k))
    click.echo(f"jointwear {p['jointwear']} (Python {p['python']}; {deps})")
    ctx.exit()


@click.group(cls=JointwearGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--version", is_flag=True, expose_value=False, is_eager=True, callback=_versions,
              help="Show the versions of jointwear and its numerical dependencies, and exit.")
def main() -> None:
    """jointwear: non-uniform wear of revolute clearance joints and wear reliability of planar mechanisms."""


class CycleCount(click.ParamType):
    """A whole number of cycles, also written as a TOML config may write it: 4e5, 400_000."""

    name = "cycles"

    def __init__(self, minimum: int) -> None:
        self.minimum = minimum

    def convert(self, value, param, ctx) -> int:
        if isinstance(value, int) and not isinstance(value, bool):
            n = value
        else:
            try:
                x = float(str(value).replace("_", ""))
            except ValueError:
                self.fail(f"{value!r} is not a number of cycles", param, ctx)
            if not math.isfinite(x) or x != int(x):
                self.fail(f"{value!r} is not a whole number of cycles", param, ctx)
            n = int(x)
        if n < self.minimum:
            self.fail(f"{value!r} is below {self.minimum}", param, ctx)
        return n


@main.command()
@config_argument
@click.option("--cycles", type=CycleCount(1), default=None,
              help="Crank cycles to record (default: simulation.cycles of the config).")
@click.option("--settle", type=CycleCount(0), default=None,
              help="Cycles to settle before recording (default: simulation.settle_cycles).")
@out_option
def simulate(config: str | None, cycles: int | None, settle: int | None, out: Path) -> None:
    """Simulate the mechanism with its clearance joints; write simulate.json, simulate_joints.csv,
    simulate.npz and figures."""
    open_study(config, out).simulate(cycles=cycles, settle=settle)


@main.command()
@config_argument
@click.option("--cycles", type=CycleCount(1), default=None,
              help="Crank cycles of the wear history (default: wear.cycles of the config, else the end of its "
                   "R(N) curve).")
@out_option
def wear(config, cycles, out):
    """Non-uniform wear of the clearance joints over many cycles; write wear.json, CSV tables and figures."""
    open_study(config, out).wear(cycles)


@main.command()
@config_argument
@click.option("--replicates", type=click.IntRange(min=2), default=8, show_default=True,
              help="Histories per setting, each from another start phase.")
@click.option("--factor", type=click.FloatRange(min=1.0, min_open=True), default=2.0, show_default=True,
              help="Refinement factor of every setting.")
@click.option("--tolerance", type=click.FloatRange(min=0.0, max=1.0, min_open=True, max_open=True), default=0.02,
              show_default=True, help="Relative change of the nominal life that counts as converged.")
@click.option("--only", "only", multiple=True,
              help="A refinement to run (repeatable or comma separated; default all): record_cycles, "
                   "settle_cycles, block, n_grid, tolerance; in profile mode also profile_smoothing_deg, "
                   "profile_substep_cycles.")
@click.option("--cycles", type=CycleCount(1), default=None,
              help="Cycles of each history [default: wear.cycles, else the end of the R(N) curve].")
@compute_options
@out_option
def converge(config, replicates, factor, tolerance, only, cycles, workers, scheduler, resume, overwrite, out):
    """Whether the nominal wear history is converged in its numerical settings (each refined, with replicates);
    write wear_convergence.json and wear_convergence.csv. Its histories go through the executor and an evaluation
    store of their own (wear_convergence.sqlite), always continued (an interrupted check resumes without --resume;
    --overwrite starts it afresh)."""
    chosen = [name.strip() for item in only for name in item.split(",") if name.strip()]
    open_study(config, out, workers, scheduler, resume, overwrite).converge(replicates, factor, tolerance,
                                                                          chosen or None, cycles)


@main.command()
@config_argument
@compute_options
@out_option
def reliability(config, workers, scheduler, resume, overwrite, out):
    """Wear reliability R(N) and the life at the target reliability (AK-MCS); write reliability.json."""
    open_study(config, out, workers, scheduler, resume, overwrite).reliability()


@main.command()
@config_argument
@compute_options
@out_option
def sensitivity(config, workers, scheduler, resume, overwrite, out):
    """Reliability sensitivity to every variable (mean shifts, Sobol', derivatives); write sensitivity.json,
    sensitivity.csv and figures.

    Re-uses the evaluations of a reliability study in the same --out folder (no --resume needed).
    """
    open_study(config, out, workers, scheduler, resume, overwrite).sensitivity()


@main.command()
@config_argument
@click.option("--samples", type=click.IntRange(min=1), default=2000, show_default=True,
              help="Fresh random samples, one true-model call each.")
@compute_options
@out_option
def validate(config, samples, workers, scheduler, resume, overwrite, out):
    """Check the R(N) curve against the true wear model sampled directly; write validation.json, its CSV tables
    and figures.

    Re-uses the evaluations of a reliability study in the same --out folder (no --resume needed).
    """
    open_study(config, out, workers, scheduler, resume, overwrite).validate(n_samples=samples)


@main.command()
@click.argument("directory", type=click.Path(path_type=Path), required=False)
@click.option("--out", "out", type=click.Path(path_type=Path), default=None,
              help="The results folder, as the other commands name it (same as DIRECTORY; default: results).")
def report(directory, out):
    """Build DIRECTORY/report.html from the results of a study (DIRECTORY or --out DIR)."""
    from jointwear.report.html import build_report
    from jointwear.study.results import results_of_a_study

    if directory is None and out is None:
        out = Path("results")  # the other commands' default --out
    if directory is not None and out is not None and directory.resolve() != out.resolve():
        raise ConfigError(f"report: two results directories, '{directory}' and --out '{out}': give one")
    directory = directory if directory is not None else out
    if directory.is_file():  # a config given as the other commands take it
        raise ConfigError(f"report: '{directory}' is a file; report takes the results folder of a study (the --out "
                          "of the command that ran it): jointwear report --out DIR")
    if not directory.is_dir():
        raise ConfigError(f"report: '{directory}' is not a directory with study results")
    results_of_a_study(directory, "report")
    say(f"report: {build_report(directory)}")


@main.command()
@config_argument
@compute_options
@out_option
def run(config, workers, scheduler, resume, overwrite, out):
    """The whole study end to end: simulate, wear, reliability, sensitivity, report."""
    open_study(config, out, workers, scheduler, resume, overwrite).run()


@main.command()
@click.argument("directories", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--target", type=click.FloatRange(min=0.0, max=1.0, min_open=True, max_open=True), default=None,
              help="Target reliability (default: the first study's first target).")
@click.option("--label", "labels", multiple=True,
              help="A name for each study, in order, each its own (repeat the option once per study; default: "
                   "the studies' names).")
@click.option("--out", "out", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Also write comparison.json, its CSV tables, comparison.md, the figure and comparison.html here.")
def compare(directories, target, labels, out):
    """Compare two or more finished studies (their results folders; the first is the baseline): the life at the
    target with its 95 % interval, whether it differs beyond the errors, the nominal wear and the settings that
    differ."""
    import warnings

    from jointwear.study import compare_studies

    with warnings.catch_warnings(record=True) as caught:  # said as the stages say theirs, not as Python's
        warnings.simplefilter("always")
        result = compare_studies(list(directories), target=target, labels=list(labels) or None)
    for message in dict.fromkeys(" ".join(str(w.message).split()) for w in caught):
        say(f"compare: warning: {message}")
    click.echo(result.markdown())
    if out is not None:
        say(f"compare: {result.save(out)}")


@main.command()
@click.argument("config", required=True)
def check(config):
    """Check CONFIG whole (every section and cross-section rule, the nominal mechanism runs) and print every
    setting resolved, with its unit and where its value comes from: the config, or jointwear's default (and where
    that default comes from)."""
    from jointwear.study import Study
    from jointwear.study.settings_record import listed_settings, origin

    study = Study(config, out=Path("."), echo=lambda line: None)  # its warnings are printed last, below
    found = study.check()
    records, from_folder = listed_settings(study.config, config)
    for rec in records:
        value = rec["value"]
        unit = f" {rec['unit']}" if rec["unit"] and value is not None else ""  # 'None', not 'None HB'
        source = " ".join(str(rec["source"]).split())
        shown = f"{value:.6g}" if isinstance(value, float) else repr(value)
        note = f"{origin(rec)}: {source}" if source and not rec["explicit"] else origin(rec)
        click.echo(f"{rec['name']} = {shown}{unit}    # {note}")
    if from_folder:
        say(f"check: '# jointwear default' and '# the config' as {config}'s config.json records them; '\u2014': a "
            "setting it does not record (the reference's values, the study's name)")
    if extends := _extends(config):
        say(f"check: '# the config' marks the values of {config} and of the config it extends ({extends})")
    for warning in found:
        say(f"check: warning: {warning}")
    checks = "; converge and validate run on it too" if "reliability" in study.stages else "; converge runs on it too"
    say(f"check: {config} is a valid study config for the stages {', '.join(study.stages)}{checks}")


def _extends(config: str) -> str | None:
    """The ``extends`` of a TOML file given by its path (None for a preset, a folder, or no extends)."""
    import tomllib

    path = Path(config)
    if path.suffix != ".toml" or not path.is_file():
        return None
    try:
        with path.open("rb") as f:
            base = tomllib.load(f).get("extends")
    except (OSError, tomllib.TOMLDecodeError):
        return None
    return base if isinstance(base, str) else None


@main.command()
def presets():
    """List the built-in presets with their citations."""
    from jointwear.config import available_presets, load_config

    for name in available_presets():
        cfg = load_config(name)
        click.echo(f"{name}\n    {cfg.description}\n    source: {cfg.citation}")


@main.command()
@config_argument
@compute_options
@out_option
def design(config, workers, scheduler, resume, overwrite, out):
    """The cheapest controls (grades, fit, material specifications) that reach the [design] target life at the
    target reliability, the Pareto front of cost vs life, and the choice verified; write design.json.

    Re-uses the evaluations of a reliability study in the same --out folder (no --resume needed).
    """
    open_study(config, out, workers, scheduler, resume, overwrite).design()

def main_entry(argv: list[str] | None = None) -> int:
    """Run the CLI in-process and return the exit status (used by tests)."""
    return main.run(argv)
