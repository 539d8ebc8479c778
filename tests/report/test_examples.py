"""The examples in examples/ run as a user would run them."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "api_example.py"


def _missing_api() -> str | None:
    """What the example needs from the other stages, if it is not there yet."""
    needs = {"jointwear.reliability": "akmcs", "jointwear.config": "load_config"}
    for module, name in needs.items():
        try:
            mod = importlib.import_module(module)
        except Exception as exc:  # noqa: BLE001
            return f"{module} cannot be imported ({exc})"
        if not hasattr(mod, name):
            return f"{module}.{name} does not exist yet"
    return None


def test_api_example_runs(tmp_path: Path):
    reason = _missing_api()
    if reason:
        pytest.skip(f"examples/api_example.py needs an API that is not there yet: {reason}")
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(EXAMPLE), str(tmp_path)], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    assert "AK-MCS: Pf =" in proc.stdout and "plain Monte Carlo" in proc.stdout
    assert (tmp_path / "api_example_convergence.png").is_file()
