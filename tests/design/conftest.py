import sys
from pathlib import Path

HERE = Path(__file__).parent
if str(HERE) not in sys.path:  # design_fixtures is a plain module next to the tests (any import mode)
    sys.path.insert(0, str(HERE))
