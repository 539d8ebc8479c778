"""Fixtures of the report tests: study folders written by the stages' own writers (see report_fixtures.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:  # report_fixtures is a plain module next to the tests (any import mode)
    sys.path.insert(0, str(HERE))

from report_fixtures import make_fixture_dir, nominal_run  # noqa: E402


@pytest.fixture(scope="session")
def nominal(tmp_path_factory) -> Path:
    """The real dynamics and wear of the flapping-wing preset's nominal mechanism (run once per session)."""
    return nominal_run(tmp_path_factory.mktemp("nominal"))


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory, nominal) -> Path:
    """Every stage's output and the settings JSON, with a citation that must be escaped."""
    return make_fixture_dir(tmp_path_factory.mktemp("study"), nominal,
                            citation="Jin et al. Drones 2025, 9, 282. <script>alert('escaped')</script>")


@pytest.fixture(scope="module")
def full_report(study_dir) -> Path:
    from jointwear.report import build_report

    return build_report(study_dir)


@pytest.fixture
def figures_made_not_rendered(request, monkeypatch):
    """For tests that read the report's text: each figure is still made from the study's data (one that cannot be
    made still falls back or says so) but not rendered to PNG, which is about three quarters of a report's time.
    Rendering is tested by the module fixture full_report (built before this function-scoped patch applies),
    test_figures.py and the browser test; a test marked ``rendered`` renders its figures."""
    if request.node.get_closest_marker("rendered"):
        return
    from unrendered_figures import unrendered  # tests/unrendered_figures.py

    from jointwear.report import style

    monkeypatch.setattr(style, "to_png_bytes", unrendered)
