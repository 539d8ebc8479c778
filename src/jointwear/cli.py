"""Command line: ``jointwear <command> [CONFIG] ... --out DIR``.

Each command is a small function registered on the ``main`` group; CONFIG is a TOML file or a
preset name (default ``jin2025_flapping_wing``).  Errors in the config or the arguments end with
exit status 2 and one plain line on stderr (no traceback).

Adding a command (other stages)::

    @main.command()
    @config_argument
    @out_option
    def wear(config, out):
        cfg = load_cli_config(config)
        ...
        write_json(out, "wear.json", payload)
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import click
import numpy as np

from jointwear.config import ConfigError, load_config

config_argument = click.argument("config", required=False, default=None)
out_option = click.option(
    "--out", "out", type=click.Path(file_okay=False, path_type=Path), default=Path("results"), show_default=True,
    help="Output directory (created if missing).",
)


class CLIError(click.ClickException):
    """A user-facing error: one line, exit status 2."""

    exit_code = 2


def load_cli_config(config: str | None):
    """Load the config named on the command line (ConfigError propagates to a one-line exit 2)."""
    return load_config(config)


def _json_default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o).__name__)


def write_json(out: Path, name: str, payload: dict) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    path.write_text(json.dumps(payload, indent=2, default=_json_default, allow_nan=True) + "\n", encoding="utf-8")
    return path


class JointwearGroup(click.Group):
    """A click group whose ``main()`` maps config/usage errors to one line on stderr and exit status 2."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):  # type: ignore[override]
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        sys.exit(self.run(args, prog_name or "jointwear"))

    def run(self, args: list[str] | None = None, prog_name: str = "jointwear") -> int:
        from jointwear.mechanism.simulate import SimulationError

        try:
            rv = super().main(args=args, prog_name=prog_name, standalone_mode=False)
        except ConfigError as exc:
            click.echo(f"error: {_one_line(str(exc))}", err=True)
            return 2
        except click.exceptions.Abort:
            click.echo("error: aborted", err=True)
            return 1
        except click.UsageError as exc:
            click.echo(f"error: {_one_line(exc.format_message())}", err=True)
            return 2
        except click.ClickException as exc:
            click.echo(f"error: {_one_line(exc.format_message())}", err=True)
            return exc.exit_code if exc.exit_code else 2
        except SimulationError as exc:
            click.echo(f"error: simulation failed: {_one_line(str(exc))}", err=True)
            return 1
        return rv if isinstance(rv, int) else 0


def _one_line(msg: str) -> str:
    return " ".join(msg.split())


@click.group(cls=JointwearGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="jointwear")
def main() -> None:
    """jointwear: non-uniform wear of revolute clearance joints and wear reliability of planar mechanisms."""



@main.command()
@config_argument
@click.option("--cycles", type=click.IntRange(min=1), default=None,
              help="Crank cycles to record (default: simulation.cycles of the config).")
@click.option("--settle", type=click.IntRange(min=0), default=None,
              help="Cycles to settle before recording (default: simulation.settle_cycles).")
@out_option
def simulate(config: str | None, cycles: int | None, settle: int | None, out: Path) -> None:
    """Simulate the mechanism with its clearance joints; write simulate.json, simulate.npz and figures."""
    from jointwear.mechanism import build_model
    from jointwear.mechanism import simulate as run_simulation

    cfg = load_cli_config(config)
    model = build_model(cfg)
    n = cycles if cycles is not None else cfg.simulation.cycles
    run_simulation(model, 0.01, settle_cycles=0)  # load/compile the kernels so timings exclude it
    res = run_simulation(model, n, settle_cycles=settle)
    payload = simulate_summary(res, cfg.name)
    write_json(out, "simulate.json", payload)
    _write_series(out, res)
    _plot(out, res)
    j = payload
    click.echo(
        f"simulate: {n} cycles, {j['steps_per_cycle']:.0f} steps/cycle, {j['wall_seconds_per_cycle'] * 1e3:.1f} ms/cycle; "
        f"mean contact force {j.get('contact_force_mean_N', float('nan')):.4g} N -> {out / 'simulate.json'}"
    )


def simulate_summary(res, name: str = "") -> dict:
    """The simulate.json payload (top-level keys for the first clearance joint, plus a `joints` list)."""
    total_cycles = res.n_cycles + res.settle_cycles
    joints = []
    for tr in res.joints:
        f = tr.contact_force
        joints.append({
            "name": tr.name,
            "bearing_body": tr.bearing_body,
            "journal_body": tr.journal_body,
            "contact_force_mean_N": tr.mean_force,
            "contact_force_max_N": float(f.max()) if f.size else 0.0,
            "normal_force_mean_N": float(np.sum(tr.dt_weight * tr.force_normal) / tr.duration),
            "contact_fraction": tr.contact_fraction,
            "impacts_per_cycle": tr.n_impacts / res.n_cycles,
            "max_penetration_m": float(tr.penetration.max()),
            "clearance_m": tr.clearance_used,
            "stiffness_N_per_m1p5": float(np.median(tr.stiffness)),
        })
    payload: dict[str, Any] = {"config": name, "cycles": res.n_cycles, "settle_cycles": res.settle_cycles,
                               "period_s": res.period}
    if joints:
        first = joints[0]
        for k in ("contact_force_mean_N", "contact_force_max_N", "contact_fraction", "impacts_per_cycle"):
            payload[k] = first[k]
    payload["steps_per_cycle"] = res.steps_per_cycle
    payload["wall_seconds_per_cycle"] = res.wall_seconds / total_cycles if total_cycles else math.nan
    payload["wall_seconds"] = res.wall_seconds
    payload["accepted_steps"] = res.n_steps
    payload["rejected_steps"] = res.n_rejected
    payload["joints"] = joints
    payload["kernel"] = res.extra.get("kernel", "")
    payload["series_file"] = "simulate.npz"
    return payload


def _write_series(out: Path, res) -> None:
    data: dict[str, np.ndarray] = {"t_s": res.t, "crank_angle_rad": res.crank_angle, "body_angles_rad": res.body_angles}
    for tr in res.joints:
        p = f"{tr.name}_"
        data[p + "eccentricity_bearing_frame_m"] = tr.eccentricity
        data[p + "theta_bearing_rad"] = tr.theta_bearing
        data[p + "force_normal_N"] = tr.force_normal
        data[p + "force_tangential_N"] = tr.force_tangential
        data[p + "slip_speed_m_s"] = tr.slip_speed
        data[p + "penetration_m"] = tr.penetration
        data[p + "in_contact"] = tr.in_contact
    np.savez_compressed(out / "simulate.npz", **data)


def _plot(out: Path, res) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for tr in res.joints:
        fig, ax = plt.subplots(figsize=(5, 5))
        c = tr.clearance_used
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(c * 1e6 * np.cos(th), c * 1e6 * np.sin(th), "k--", lw=0.8, label="clearance circle")
        ax.plot(tr.eccentricity[:, 0] * 1e6, tr.eccentricity[:, 1] * 1e6, lw=0.8, label="journal centre")
        ax.set_aspect("equal")
        ax.set_xlabel("eccentricity along bearing-body x (um)")
        ax.set_ylabel("eccentricity along bearing-body y (um)")
        ax.set_title(f"Journal orbit, joint {tr.name} (bearing frame)")
        ax.legend(loc="upper right", fontsize=8)
        fig.tight_layout()
        fig.savefig(out / f"orbit_{tr.name}.png", dpi=120)
        plt.close(fig)
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(np.degrees(res.crank_angle), tr.contact_force * 1e3, ".", ms=1)
        ax.set_xlabel("crank angle (deg)")
        ax.set_ylabel("contact force (mN)")
        ax.set_xlim(0, 360)
        ax.set_title(f"Contact force vs crank angle, joint {tr.name}")
        fig.tight_layout()
        fig.savefig(out / f"force_{tr.name}.png", dpi=120)
        plt.close(fig)


def main_entry(argv: list[str] | None = None) -> int:
    """Run the CLI in-process and return the exit status (used by tests)."""
    return main.run(argv)


# the study commands (wear, reliability, sensitivity, report, run) live in jointwear.commands
from jointwear.commands import register as _register_study_commands  # noqa: E402

_register_study_commands(main)
