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
    is tested by tests/report (test_figures, the full report, the browser test), the subprocess studies and every
    module that does not use this fixture."""
    from unrendered_figures import unrendered

    from jointwear.report import style

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(style, "to_png_bytes", unrendered)
        yield
