"""The user guide's config reference is the one generated from the current config schema."""

from __future__ import annotations

from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "user-guide.md"


def test_config_reference_is_up_to_date():
    pytest.importorskip("jointwear.config")
    from jointwear.report.config_reference import update

    assert update(GUIDE, check=True), (
        "docs/user-guide.md: the config reference is out of date with the config schema; regenerate it with "
        "`python -m jointwear.report.config_reference docs/user-guide.md`")


def test_generated_reference_lists_every_top_level_section():
    from jointwear.config import StudyConfig
    from jointwear.report.config_reference import config_reference_markdown

    text = config_reference_markdown()
    for name in StudyConfig.model_fields:
        assert f"| `{name}` |" in text
