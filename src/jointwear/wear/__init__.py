"""jointwear.wear: Archard wear of revolute clearance joints on angular grids, and the cycle-block history.

Public API::

    from jointwear.wear import WearSettings, wear_history, WearResult
    res = wear_history(model, WearSettings(), 400_000)
    res.max_wear_at(360_000)        # m, any N from one call
"""

from .angles import report_angle_deg
from .cycle import CycleWear, cycle_wear
from .history import wear_history
from .results import JointWear, WearResult
from .settings import WearSettings

__all__ = ["WearSettings", "wear_history", "WearResult", "JointWear", "CycleWear", "cycle_wear", "report_angle_deg"]
