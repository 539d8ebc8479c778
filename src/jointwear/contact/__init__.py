"""jointwear.contact: clearance-joint geometry and the normal-force / friction laws."""

from jointwear.contact.geometry import DEFAULT_N_GRID, ClearanceGeometry
from jointwear.contact.laws import FRICTION_CODES, LAW_CODES, contact_stiffness_py

__all__ = ["ClearanceGeometry", "DEFAULT_N_GRID", "LAW_CODES", "FRICTION_CODES", "contact_stiffness_py"]
