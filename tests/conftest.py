import sys
from pathlib import Path

HERE = Path(__file__).parent
if str(HERE) not in sys.path:  # shared test helpers (analytic_wear) are plain modules in this folder
    sys.path.insert(0, str(HERE))
