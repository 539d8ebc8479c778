"""jointwear.contact: clearance-joint geometry and the normal-force / friction laws."""

from jointwear.contact.geometry import DEFAULT_N_GRID, ClearanceGeometry
from jointwear.contact.laws import FRICTION_CODES, LAW_CODES, contact_stiffness_py

__all__ = ["DEFAULT_N_GRID", "FRICTION_CODES", "LAW_CODES", "ClearanceGeometry", "contact_stiffness_py"]
