"""Manufacturing tolerances as random variables (paper Section 4.1).

* ISO 286-1 standard tolerance grades IT5-IT11 for nominal sizes up to 120 mm
  (Table 1 of ISO 286-1:2010, values in micrometres).
* Clearance of a hole/shaft fit, Eq. (39)-(40) of Jin et al. (2025):
  c = (D - d) / 2, mu_c = (T_D + T_d + 2 es) / 2 ... with the usual 3-sigma-per-side
  reading sigma_D = T_D / 6, sigma_d = T_d / 6, hence sigma_c = sqrt(T_D^2 + T_d^2) / 12.
* Symmetric length tolerance, Eq. (41): the 6-sigma rule sigma_L = T / 6.

Everything in SI (metres); grade names like ``"IT7"``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

# Upper bounds (mm, inclusive) of the ISO 286-1 nominal size ranges, and the
# standard tolerance in micrometres for each grade in that range.
_SIZE_UPPER_MM = (3, 6, 10, 18, 30, 50, 80, 120)
_IT_UM = {
    "IT5": (4, 5, 6, 8, 9, 11, 13, 15),
    "IT6": (6, 8, 9, 11, 13, 16, 19, 22),
    "IT7": (10, 12, 15, 18, 21, 25, 30, 35),
    "IT8": (14, 18, 22, 27, 33, 39, 46, 54),
    "IT9": (25, 30, 36, 43, 52, 62, 74, 87),
    "IT10": (40, 48, 58, 70, 84, 100, 120, 140),
    "IT11": (60, 75, 90, 110, 130, 160, 190, 220),
}
#: the grades tabulated (nominal sizes up to 120 mm)
IT_GRADES = tuple(_IT_UM)

#: what a fit written with its letters (H8/f7) means here: only the grades set the clearance's spread
FIT_LETTERS = ("fit letters (H, f, g, ...) are not modelled: they set the mean clearance, which is given as the "
               "clearance's mean (mean_um); see docs/tutorial.md, 'The random inputs'")


def it_tolerance(grade: str, nominal_size: float) -> float:
    """Standard tolerance (m) of an ISO 286-1 grade for a nominal size (m)."""
    key = grade.upper().replace(" ", "")
    if key not in _IT_UM:
        lettered = re.fullmatch(r"(?!IT)[A-Z]{1,2}(\d{1,2})", key)  # 'H8', 'f7': a fit's letter and its grade
        hint = f"; the grade is the IT number (IT{lettered[1]}), and {FIT_LETTERS}" if lettered else ""
        raise ValueError(f"unknown ISO 286 tolerance grade {grade!r}; known: {', '.join(_IT_UM)}{hint}")
    size_mm = nominal_size * 1e3
    if not (0.0 < size_mm <= _SIZE_UPPER_MM[-1]):
        raise ValueError(f"nominal size {size_mm:g} mm outside the tabulated range (0, 120] mm")
    for upper, tol in zip(_SIZE_UPPER_MM, _IT_UM[key]):
        if size_mm <= upper:
            return tol * 1e-6
    raise AssertionError("unreachable")


@dataclass(frozen=True)
class FitClearance:
    """Radial clearance of a fit as a normal variable (m)."""

    mean: float
    std: float
    hole_tolerance: float
    shaft_tolerance: float


def clearance_from_fit(nominal_diameter: float, hole_grade: str, shaft_grade: str,
                       mean_clearance: float) -> FitClearance:
    """Radial clearance c = (D - d)/2 of a fit, Eq. (40): sigma_c = sqrt(T_D^2 + T_d^2) / 12.

    The mean is the designed radial clearance (set by the fundamental deviations, which
    the paper does not give); the standard deviation follows from the two grades.
    """
    t_hole = it_tolerance(hole_grade, nominal_diameter)
    t_shaft = it_tolerance(shaft_grade, nominal_diameter)
    return FitClearance(mean=mean_clearance, std=math.hypot(t_hole, t_shaft) / 12.0,
                        hole_tolerance=t_hole, shaft_tolerance=t_shaft)


def length_sigma(tolerance_band: float) -> float:
    """Standard deviation of a length with a symmetric tolerance band T = ES - EI, Eq. (41)."""
    if tolerance_band <= 0:
        raise ValueError("tolerance band must be positive")
    return tolerance_band / 6.0
