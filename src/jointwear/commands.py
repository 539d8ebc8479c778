"""Study commands of the command line: wear, reliability, sensitivity, report, run.

Registered on the ``jointwear`` group by :func:`register` (called from :mod:`jointwear.cli`). Each is a
thin layer over the Python API: load the config, run the stage, write its JSON and figures to ``--out``.
"""

from __future__ import annotations

import contextlib
import math
import time
from pathlib import Path

import click
import numpy as np

from jointwear.config import ConfigError

WEAR_MODEL_TAG = "wear_model"


def _compute_options(f):
    f = click.option("--workers", type=click.IntRange(min=1), default=None,
                     help="Local worker processes for model calls (default: compute.workers, else all cores).")(f)
    f = click.option("--scheduler", default=None, metavar="ADDRESS",
                     help="Dask scheduler address (tcp://host:8786) to run model calls on a cluster.")(f)
    f = click.option("--resume", is_flag=True, help="Resume an interrupted study in --out (no call is repeated).")(f)
    f = click.option("--overwrite", is_flag=True, help="Discard an earlier study's evaluation store in --out.")(f)
    return f


def _say(msg: str) -> None:
    click.echo(msg, err=True)


@contextlib.contextmanager
def open_study(cfg, out: Path, *, workers, scheduler, resume: bool, overwrite: bool, reuse: bool = False):
    """The study context with its evaluator: executor, evaluation store and progress display."""
    from jointwear import compute
    from jointwear.study import study_context

    out.mkdir(parents=True, exist_ok=True)
    workers = workers if workers is not None else cfg.compute.workers
    scheduler = scheduler if scheduler is not None else cfg.compute.scheduler
    digest = compute.config_hash(cfg.model_dump(mode="json"))
    try:
        store = compute.EvaluationStore.open(out, digest, resume=resume or reuse, overwrite=overwrite)
    except compute.StoreError as exc:
        raise ConfigError(str(exc)) from None
    try:
        executor = compute.make_executor(workers=workers, scheduler=scheduler)
    except Exception as exc:  # noqa: BLE001 - a bad address or an unreachable cluster is a user error
        store.close()
        raise ConfigError(f"compute: cannot start the executor: {' '.join(str(exc).split())}") from None
    progress = compute.Progress(total=None, description="model calls")
    try:
        with executor, progress:
            ctx = study_context(cfg, lambda call: compute.Evaluator(
                call, executor, store, timeout=cfg.compute.call_timeout, tag=WEAR_MODEL_TAG,
                n_outputs=len(call.cycles), progress=progress))
            yield ctx, progress, store
    finally:
        store.close()


def _progress_callback(progress, cycles):
    from jointwear.study import reference_level

    ref = reference_level(cycles)

    def on_iteration(rec):
        pf = np.atleast_1d(rec.pf)
        cov = np.atleast_1d(getattr(rec, "cov", np.nan))
        progress.update(**{"Pf(400k)": f"{pf[min(ref, pf.size - 1)]:.3g}",
                           "COV": f"{cov[min(ref, cov.size - 1)]:.2g}",
                           "min U": f"{float(np.nanmin(np.atleast_1d(rec.min_u))):.2f}"})
    return on_iteration


def do_reliability(cfg, out: Path, **opts):
    from jointwear.study import run_reliability

    with open_study(cfg, out, **opts) as (ctx, progress, _store):
        res = run_reliability(ctx, progress=_progress_callback(progress, ctx.cycles))
        write_reliability(res, cfg, out)
        return ctx, res


def write_reliability(res, cfg, out: Path) -> None:
    from jointwear.cli import write_json
    from jointwear.report import figures
    from jointwear.report.html import PAPER
    from jointwear.report.style import savefig

    payload = res.as_json()
    payload["allowance_mm"] = cfg.reliability.allowance * 1e3
    payload["crank_speed_rpm"] = abs(cfg.mechanism.crank_speed) * 60 / (2 * math.pi)
    write_json(out, "reliability.json", payload)
    savefig(figures.reliability_curve_figure(res.cycles, res.reliability, pf_cov=res.pf_cov, target=res.target,
                                             life_cycles=res.life_cycles, paper=PAPER["reliability"],
                                             paper_life=PAPER["life_cycles"]),
            out / "reliability_curve.png")
    h = res.histograms
    savefig(figures.wear_histograms_figure(h["cycles"], h["max_wear_mm"], limit_mm=cfg.reliability.allowance * 1e3,
                                           paper_means=PAPER["mean_max_wear_mm"]),
            out / "wear_histograms.png")
    conv = res.convergence
    if conv["n_calls"]:
        savefig(figures.convergence_figure(conv["n_calls"], conv["pf"], cov=conv.get("cov"),
                                           label=f"Pf at {conv.get('cycles', 400_000):,} cycles"),
                out / "convergence.png")
    life = "not reached in the curve" if res.life_cycles is None else (
        f"{res.life_cycles:,.0f} cycles = {res.life_hours:.2f} h")
    _say(f"reliability: {res.model_calls} model calls, n_mc = {res.n_mc:,}, life at R = {res.target}: {life} "
         f"-> {out / 'reliability.json'}")


def do_sensitivity(cfg, out: Path, ctx, res) -> dict:
    from jointwear.cli import write_json
    from jointwear.report import figures
    from jointwear.report.style import savefig
    from jointwear.study import run_sensitivity

    sens = run_sensitivity(ctx, res)
    write_json(out, "sensitivity.json", sens)
    v = sens["variables"]
    lo, hi = sens["factors"]
    savefig(figures.tornado_figure([x["label"] for x in v], [x["reliability_low"] for x in v],
                                   [x["reliability_high"] for x in v], sens["reliability_nominal"],
                                   cycles=sens["cycles"], low_label=f"mean \u00d7 {lo:g}",
                                   high_label=f"mean \u00d7 {hi:g}"), out / "sensitivity_tornado.png")
    s = sens["sobol"]
    savefig(figures.sobol_figure(s["names"], s["S1"], s["ST"], S1_conf=s["S1_conf"], ST_conf=s["ST_conf"],
                                 output=f"max wear at {sens['cycles']:,} cycles"), out / "sensitivity_sobol.png")
    _say(f"sensitivity: ranking {_ranking_line(sens)}; {sens['extra_model_calls']} extra model calls "
         f"-> {out / 'sensitivity.json'}")
    return sens


def _ranking_line(sens: dict) -> str:
    """Per group, the variables by their effect on R, '~' between neighbours the surrogate's error does not
    separate: 'tolerance: l2 ~ lBC > l1 | bearing_material: k_b ~ HB_b > ...'."""
    ties = {(p["first"], p["second"]) for p in sens.get("unresolved_pairs", [])}
    parts = []
    for group, names in sens["ranking_by_group"].items():
        text = names[0] if names else ""
        for a, b in zip(names, names[1:]):
            text += (" ~ " if (a, b) in ties else " > ") + b
        parts.append(f"{group}: {text}")
    return " | ".join(parts)


def do_wear(cfg, cycles, out: Path) -> dict:
    from jointwear.wear.cli import wear_command

    t0 = time.perf_counter()
    summary = wear_command(cfg, cycles, out)
    _say(f"wear: max bearing wear {summary.get('max_wear_mm', float('nan')):.4f} mm at "
         f"{summary.get('max_wear_angle_deg', float('nan')):.0f} deg after {summary.get('cycles')} cycles "
         f"({time.perf_counter() - t0:.1f} s) -> {out / 'wear.json'}")
    return summary


def do_reliability_and_sensitivity(cfg, out: Path, **opts) -> None:
    from jointwear.study import run_reliability

    with open_study(cfg, out, **opts) as (ctx, progress, _store):
        res = run_reliability(ctx, progress=_progress_callback(progress, ctx.cycles))
        write_reliability(res, cfg, out)
        do_sensitivity(cfg, out, ctx, res)


def register(main: click.Group) -> None:
    """Add the study commands to the ``jointwear`` group."""
    from jointwear.cli import config_argument, load_cli_config, out_option

    @main.command()
    @config_argument
    @click.option("--cycles", type=click.IntRange(min=1), default=None,
                  help="Crank cycles of the wear history (default: wear.cycles of the config, 400,000).")
    @out_option
    def wear(config, cycles, out):
        """Non-uniform wear of the clearance joints over many cycles; write wear.json, data and figures."""
        do_wear(load_cli_config(config), cycles, out)

    @main.command()
    @config_argument
    @_compute_options
    @out_option
    def reliability(config, workers, scheduler, resume, overwrite, out):
        """Wear reliability R(N) and the life at the target reliability (AK-MCS); write reliability.json."""
        cfg = load_cli_config(config)
        do_reliability(cfg, out, workers=workers, scheduler=scheduler, resume=resume, overwrite=overwrite)

    @main.command()
    @config_argument
    @_compute_options
    @out_option
    def sensitivity(config, workers, scheduler, resume, overwrite, out):
        """Reliability sensitivity to every variable (mean shifts, Sobol', derivatives); write sensitivity.json.

        Re-uses the evaluations of a reliability study in the same --out folder.
        """
        cfg = load_cli_config(config)
        do_reliability_and_sensitivity(cfg, out, workers=workers, scheduler=scheduler, resume=resume,
                                       overwrite=overwrite, reuse=not overwrite)

    @main.command()
    @click.argument("directory", type=click.Path(file_okay=False, path_type=Path))
    def report(directory):
        """Build DIRECTORY/report.html from the JSON and figures of a study."""
        from jointwear.report.html import build_report

        if not directory.is_dir():
            raise ConfigError(f"report: '{directory}' is not a directory with study results")
        path = build_report(directory)
        _say(f"report: {path}")

    @main.command()
    @config_argument
    @_compute_options
    @out_option
    def run(config, workers, scheduler, resume, overwrite, out):
        """The whole study end to end: simulate, wear, reliability, sensitivity, report."""
        from jointwear.cli import simulate as simulate_cmd
        from jointwear.report.html import build_report
        from jointwear.report.settings import write_settings

        cfg = load_cli_config(config)
        t0 = time.perf_counter()
        out.mkdir(parents=True, exist_ok=True)
        write_settings(out, cfg, preset=cfg.name if config is None or not str(config).endswith(".toml") else None,
                       source=str(config) if config else "preset")
        ctx_click = click.get_current_context()
        ctx_click.invoke(simulate_cmd, config=config, cycles=None, settle=None, out=out)
        do_wear(cfg, cfg.wear.cycles, out)
        do_reliability_and_sensitivity(cfg, out, workers=workers, scheduler=scheduler, resume=resume,
                                       overwrite=overwrite)
        path = build_report(out)
        _say(f"run: done in {time.perf_counter() - t0:.0f} s -> {path}")
