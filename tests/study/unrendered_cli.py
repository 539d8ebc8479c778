"""``python -m jointwear ...`` with every figure made from the data but not rendered (tests/unrendered_figures.py):
the command line as a subprocess for tests that read its results and text, not its pictures.

    python tests/study/unrendered_cli.py reliability CONFIG --out DIR ...
"""

import sys
from pathlib import Path

if __name__ == "__main__":  # the model calls' worker processes import this file again: nothing to do there
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from unrendered_figures import unrendered

    from jointwear.cli import main
    from jointwear.report import style

    style.to_png_bytes = unrendered
    main()
