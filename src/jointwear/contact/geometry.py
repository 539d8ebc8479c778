"""Geometry of a revolute clearance joint: nominal radii plus uniform or profile wear."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

#: Profile mode: radius (fraction of the nominal radial clearance) with which the corners of the admissible set of
#: journal-centre positions are rounded (jointwear.contact.envelope). A journal resting in a pocket worn to its own
#: shape then rocks in the rounded corner with a tangential stiffness about F / rho instead of chattering across a
#: cusp; 0.2 keeps the steps per cycle as on a round bore (docs/wear.md "Profile mode: cost").
PROFILE_ROUNDING = 0.2

#: Largest contact half-angle b / R_b (rad) at which the Hertz reading of a joint's contact is trusted: Hertz's
#: theory takes the gap as a parabola and the bodies as half-spaces (Johnson, Contact Mechanics, 1985, Sect. 4.1); the
#: gap of a pin in a bore, c (1 - cos theta), departs from the parabola c theta^2 / 2 by theta^2 / 12, 0.75 % here,
#: and a contact of 17 deg is no longer small against the bodies. Past it (soft bushings, heavy loads) the forces,
#: penetrations and the wear laid on the half-width are indicative only (docs/dynamics.md).
HERTZ_HALF_ANGLE_LIMIT = 0.3


def hertz_half_angle(force: float, bearing_radius: float, journal_radius: float, hsum: float, width: float) -> float:
    """Contact half-angle b / R_b (rad) of Johnson's line contact under the normal force (N): b = sqrt(4 F R* hsum /
    (pi L)), R* = R_b R_j / (R_b - R_j), hsum = sum of (1 - nu^2) / E (Johnson 1985, Eq. 4.43)."""
    r_star = bearing_radius * journal_radius / (bearing_radius - journal_radius)
    return float(np.sqrt(4.0 * max(force, 0.0) * r_star * hsum / (np.pi * width)) / bearing_radius)


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
