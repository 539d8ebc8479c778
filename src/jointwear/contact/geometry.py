"""Geometry of a revolute clearance joint: nominal radii plus uniform or profile wear."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

#: Profile mode: radius (fraction of the nominal radial clearance) with which the corners of the admissible set of
#: journal-centre positions are rounded (jointwear.contact.envelope). A journal resting in a pocket worn to its own
#: shape then rocks in the rounded corner with a tangential stiffness about F / rho instead of chattering across a
#: cusp; 0.2 keeps the steps per cycle as on a round bore (docs/wear.md "Profile mode: cost").
PROFILE_ROUNDING = 0.2

#: default number of points of the angular wear grids
DEFAULT_N_GRID = 360


@dataclass
class ClearanceGeometry:
    """Current geometry of one clearance joint (SI units).

    Local clearance used by the contact search in the direction n (unit vector from the bearing
    centre to the journal centre):

        c_loc = (R_b - R_j) + clearance_growth + (h_b(theta_b) + h_j(theta_j) if use_profile else 0)

    where theta_b / theta_j are the angles of n in the bearing / journal body frames (CCW from the
    body's x axis) and h_b, h_j are interpolated periodically on grids at angles 2 pi k / n_grid by Catmull-Rom
    cubics (C1, so that the contact normal, which follows the profile's slope, does not jump; kernel.profile_at).
    The contact stiffness K is recomputed from the local radii R_i = R_b + h_b + growth/2 and
    R_j = R_j - h_j - growth/2; a side worn nowhere is read as round (model.profile_sides).
    """

    bearing_radius: float
    journal_radius: float
    clearance_growth: float = 0.0
    bearing_wear: np.ndarray = field(default_factory=lambda: np.zeros(DEFAULT_N_GRID))
    journal_wear: np.ndarray = field(default_factory=lambda: np.zeros(DEFAULT_N_GRID))
    use_profile: bool = False

    def __post_init__(self) -> None:
        self.bearing_wear = np.ascontiguousarray(self.bearing_wear, dtype=float)
        self.journal_wear = np.ascontiguousarray(self.journal_wear, dtype=float)
        if self.bearing_wear.ndim != 1 or self.bearing_wear.size < 2:
            raise ValueError("bearing_wear must be a 1-D array with at least 2 points")
        if self.journal_wear.ndim != 1 or self.journal_wear.size < 2:
            raise ValueError("journal_wear must be a 1-D array with at least 2 points")

    @property
    def clearance(self) -> float:
        """Nominal clearance plus uniform growth (m)."""
        return self.bearing_radius - self.journal_radius + self.clearance_growth

    def copy(self) -> ClearanceGeometry:
        return replace(self, bearing_wear=self.bearing_wear.copy(), journal_wear=self.journal_wear.copy())
