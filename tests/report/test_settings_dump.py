"""config.json from a validated config: every setting with its unit, source and paper-open flag."""

from __future__ import annotations

import json

import pytest
from pydantic import BaseModel, Field

from jointwear.report import build_report
from jointwear.report.settings import is_paper_open, settings_dump, write_settings


class _Inner(BaseModel):
    length: float = Field(0.006, description="Crank length (Table 4).", json_schema_extra={"unit": "m"})
    modulus: float = Field(2.11e11, description="Young's modulus (Table 2).", json_schema_extra={"unit": "Pa"})


class _Cfg(BaseModel):
    name: str = "toy"
    citation: str = "A. Author, Journal 2025"
    inner: _Inner = Field(default_factory=_Inner)
    mu: float = Field(0.1, description="Friction; paper gives none, paper-notes baseline.")
    gravity: bool = Field(True, description="Explicit.", json_schema_extra={"paper_open": True})
    speed: float = Field(50.265, description="Crank speed.", json_schema_extra={"unit": "rad/s"})


def test_dump_of_a_pydantic_config(tmp_path):
    d = settings_dump(_Cfg(), seed=3)
    by = {s["name"]: s for s in d["settings"]}
    assert d["preset"] == "toy" and d["citation"].startswith("A. Author") and d["seed"] == 3
    assert "name" not in by and "citation" not in by
    assert by["inner.length"]["value"] == pytest.approx(6.0) and by["inner.length"]["unit"] == "mm"
    assert by["inner.modulus"]["value"] == pytest.approx(211.0) and by["inner.modulus"]["unit"] == "GPa"
    assert by["speed"]["value"] == pytest.approx(480.0, rel=1e-4) and by["speed"]["unit"] == "rpm"
    assert by["mu"]["paper_open"] and by["gravity"]["paper_open"] and not by["inner.length"]["paper_open"]
    assert by["mu"]["source"].startswith("Friction")
    path = write_settings(tmp_path, _Cfg())
    assert json.loads(path.read_text())["settings"]
    page = build_report(tmp_path).read_text()
    assert "Settings the paper leaves open (2)" in page


def test_paper_open_heuristic():
    assert is_paper_open("Static friction coefficient; paper-notes baseline 0.15.")
    assert is_paper_open("Baumgarte alpha (paper Eq. 6, value not given; project choice).")
    assert not is_paper_open("Coefficient of restitution cr (Table 4: 0.9).")
    assert not is_paper_open("anything", {"paper_open": False})


def test_dump_of_the_default_preset():
    config = pytest.importorskip("jointwear.config")
    try:
        cfg = config.load_config("jin2025_flapping_wing")
    except Exception as exc:  # the config stage is another engineer's; report what is missing
        pytest.skip(f"jointwear.config.load_config is not usable yet: {exc}")
    d = settings_dump(cfg)
    assert d["mechanism"]["crank_mm"] == pytest.approx(6.0)
    assert d["mechanism"]["pivot_mm"] == pytest.approx([11.5, 38.0])
    names = [s["name"] for s in d["settings"]]
    assert any("friction.mu_d" in n for n in names)
    assert any(s["paper_open"] for s in d["settings"])
