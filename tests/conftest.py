import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent
if str(HERE) not in sys.path:  # shared test helpers (analytic_wear) are plain modules in this folder
    sys.path.insert(0, str(HERE))


@pytest.fixture(scope="module")
def figures_unrendered():
    """For a module whose tests read results and text, not pictures (module fixtures included, if they come after
    it): each figure is still made from the data (one that cannot be made fails or falls back as it would) but not
    rendered to PNG, most of a stage's or a report's figure time; the PNG files hold a 3x2 placeholder. Rendering
    is tested by tests/report (test_figures, the full report, the browser test), the example scripts run as a user
    runs them and every module that does not use this fixture (tests/study/unrendered_cli.py: the CLI unrendered)."""
    from unrendered_figures import unrendered

    from jointwear.report import style

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(style, "to_png_bytes", unrendered)
        yield


#: the files that take longest on a cold suite on 2 cores (each over 18 s, ``--durations=0`` summed per file), longest
#: first. xdist hands each worker whole files in collection order: starting with these (longest processing time first)
#: leaves short files for the end, so the workers finish together instead of one running a long file alone.
LONGEST_FIRST = (
    "tests/study/test_study_resume.py", "tests/study/test_examples_own_mechanism.py",
    "tests/study/test_stage_reruns.py", "tests/study/test_study_analytic.py", "tests/study/test_config_warnings.py",
    "tests/study/test_limit_state.py", "tests/dynamics/test_general_linkage.py", "tests/study/test_study_api.py",
    "tests/dynamics/test_tree_kernel.py", "tests/report/test_report_html.py",
    "tests/verification/test_conformal_wear.py", "tests/dynamics/test_radau.py", "tests/dynamics/test_tree_slider.py",
    "tests/test_cli_errors.py",
    "tests/design/test_design_analytic.py", "tests/compute/test_compute_dask.py", "tests/study/test_convergence.py",
    "tests/study/test_validation.py", "tests/design/test_design_refuted.py",
)


def pytest_collection_modifyitems(items):
    """The files of LONGEST_FIRST first, in its order; every other test keeps its place (a stable sort)."""
    rank = {path: k for k, path in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(LONGEST_FIRST)))
