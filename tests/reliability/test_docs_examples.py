"""The code blocks of docs/reliability.md run as written (a reader copies them)."""

import re
import tomllib
from pathlib import Path

from jointwear.config import load_config

DOC = Path(__file__).resolve().parents[2] / "docs" / "reliability.md"


def _blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


def test_the_python_blocks_run():
    blocks = _blocks("python")
    assert blocks
    for block in blocks:
        exec(compile(block, str(DOC), "exec"), {})


def test_the_toml_blocks_load_over_a_preset_with_those_variables():
    """The correlation example, and its commented alternative, over a preset that has l1, l2, E_b and HB_b."""
    blocks = _blocks("toml")
    assert blocks
    for block in blocks:
        for text in (block, re.sub(r"(?m)^correlation = .*$", "", block).replace("# correlation =", "correlation =")):
            config = load_config({"extends": "flores_slider_crank", **tomllib.loads(text)})
            assert config.uncertainty.correlation is not None
