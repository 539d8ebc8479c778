"""Sizes and files an untrusted config asks for are bounded at the boundary: `check` fails fast, naming the field."""

from __future__ import annotations

import resource
from importlib import resources

import pytest

from jointwear.cli import main
from jointwear.config import load_config
from jointwear.schema import ConfigError

PRESET = (resources.files("jointwear.presets") / "jin2025_flapping_wing.toml").read_text(encoding="utf-8")


def edit(old: str, new: str) -> str:
    assert old in PRESET, old
    return PRESET.replace(old, new, 1)


def _address_space() -> int:
    """The process's address space now (bytes): the cap is 2 GB above it, whatever the tests before reserved."""
    try:
        for line in open("/proc/self/status", encoding="ascii"):
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def check(tmp_path, text: str, capsys) -> tuple[int, str]:
    """`jointwear check` of ``text`` under a 2 GB address-space cap (an unbounded size would fail on memory, not on
    the config check): its exit status and its message."""
    path = tmp_path / "c.toml"
    path.write_text(text, encoding="utf-8")
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = 2 * 1024**3 + _address_space()
    resource.setrlimit(resource.RLIMIT_AS, (cap if hard == resource.RLIM_INFINITY else min(cap, hard), hard))
    try:
        code = main.run(["check", str(path)])
    except Exception as exc:  # MemoryError or any traceback: the check did not fail fast
        pytest.fail(f"check raised {type(exc).__name__}: {exc}")
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
    return code, capsys.readouterr().err


SIZE_CASES = [
    ("curve-levels", edit("cycles_stop = 560000\ncycles_step = 20000",
                          "cycles_stop = 1_000_000_000\ncycles_step = 1"),
     "cycles_step"),
    ("n_mc", edit("[reliability]", "[reliability]\nn_mc = 1_000_000_000_000\nn_mc_max = 1_000_000_000_000"),
     "reliability.n_mc"),
    ("sobol", edit("[sensitivity]", "[sensitivity]\nsobol_base_samples = 1_099_511_627_776"),
     "sensitivity.sobol_base_samples"),
    ("simulation-cycles", edit("cycles = 2\n", "cycles = 1_000_000_000_000\n"), "simulation.cycles"),
    ("settle-cycles", edit("settle_cycles = 1 ", "settle_cycles = 1_000_000_000_000 "), "simulation.settle_cycles"),
    ("wear-cycles", edit("cycles = 400_000 ", "cycles = 1e300 "), "wear.cycles: must be at most 1,000,000,000"),
    ("wear-cycles-int", edit("cycles = 400_000 ", "cycles = 1_000_000_001 "), "wear.cycles"),
    ("block-cycles", edit("[wear]\n", "[wear]\nblock_cycles = 1_000_000_000_000\n"), "wear.block_cycles"),
    ("max-block", edit("[wear]\n", "[wear]\nmax_block = 1_000_000_000_000\n"), "wear.max_block"),
    ("curve-stop", edit("cycles_stop = 560000", "cycles_stop = 1_000_000_000_000"), "reliability.cycles_stop"),
]


@pytest.mark.parametrize("text, field", [c[1:] for c in SIZE_CASES], ids=[c[0] for c in SIZE_CASES])
def test_check_bounds_every_size(tmp_path, capsys, text, field):
    code, err = check(tmp_path, text, capsys)
    assert code == 2 and field in err and "Traceback" not in err, err


def test_histogram_levels_are_bounded():
    hist = list(range(360_000, 360_000 + 5_000))
    with pytest.raises(ConfigError, match="histogram_cycles: 5,000 levels given, at most 1,000"):
        load_config({"extends": "jin2025_flapping_wing", "reliability": {"histogram_cycles": hist}})


def test_bounds_leave_real_studies_alone():
    cfg = load_config({"extends": "jin2025_flapping_wing", "reliability": {"n_mc": 10**8, "n_mc_max": 10**8},
                       "sensitivity": {"sobol_base_samples": 2**20}, "simulation": {"cycles": 100}})
    assert cfg.reliability.n_mc == 10**8 and cfg.sensitivity.sobol_base_samples == 2**20


def test_wear_bounds_leave_long_histories_alone():
    cfg = load_config({"extends": "jin2025_flapping_wing", "wear": {"cycles": 10**9, "block_cycles": 10**9,
                                                                     "max_block": 10**9},
                       "reliability": {"cycles_stop": 10**9, "cycles_step": 10**7}})
    assert cfg.wear.cycles == cfg.wear.block_cycles == cfg.reliability.cycles_stop == 10**9


@pytest.mark.parametrize("cycles", [10**12, 10**400, 1e300], ids=["1e12", "int-1e400", "float-1e300"])
def test_wear_cycles_argument_is_bounded(tmp_path, cycles):
    """The history length a caller gives is bounded as wear.cycles is, before anything runs or is written."""
    import jointwear

    study = jointwear.Study("jin2025_flapping_wing", out=tmp_path / "out", workers=1)
    with pytest.raises(ConfigError, match="cycles must be at most 1,000,000,000 cycles"):
        study.wear(cycles=cycles)
    assert not (tmp_path / "out" / "wear.json").exists()


@pytest.mark.parametrize("kwargs, field, most", [({"cycles": 10**12}, "simulation.cycles", "100"),
                                                ({"cycles": 2, "settle": 10**12}, "simulation.settle_cycles", "10000")])
def test_simulate_arguments_are_bounded_by_their_fields(tmp_path, kwargs, field, most):
    """simulate(cycles=, settle=) is checked by the settings fields it stands for (one bound, one message), before
    anything is written."""
    import jointwear

    with pytest.raises(ConfigError, match=rf"simulate\(cycles, settle\): {field}: Input should be less than or "
                                          rf"equal to {most}"):
        jointwear.Study("jin2025_flapping_wing", out=tmp_path / "out", workers=1).simulate(**kwargs)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_design_candidates_are_bounded():
    with pytest.raises(ConfigError, match="max_candidates"):
        load_config({"extends": "jin2025_flapping_wing", "design": {"max_candidates": 10**12}})
