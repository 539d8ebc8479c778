"""Fixtures of the report tests: a folder of realistic synthetic study outputs (see report_fixtures.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:  # report_fixtures is a plain module next to the tests (any import mode)
    sys.path.insert(0, str(HERE))

from report_fixtures import make_fixture_dir  # noqa: E402


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory) -> Path:
    """Every stage's output, with all optional keys, the Fig. 17 columns in a CSV."""
    return make_fixture_dir(tmp_path_factory.mktemp("study"))


@pytest.fixture(scope="module")
def full_report(study_dir) -> Path:
    from jointwear.report import build_report

    return build_report(study_dir)
