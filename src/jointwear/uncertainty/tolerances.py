"""Manufacturing tolerances as random variables (paper Section 4.1).

* ISO 286-1 standard tolerance grades IT5-IT11 for nominal sizes up to 120 mm
  (Table 1 of ISO 286-1:2010, values in micrometres).
* Clearance of a hole/shaft fit, Eq. (39)-(40) of Jin et al. (2025):
  c = (D - d) / 2, mu_c = (T_D + T_d - 2 es) / 4 for an H bore (EI = 0) on a pin of upper deviation es <= 0, with
  the usual 3-sigma-per-side
  reading sigma_D = T_D / 6, sigma_d = T_d / 6, hence sigma_c = sqrt(T_D^2 + T_d^2) / 12.
* Symmetric length tolerance, Eq. (41): the 6-sigma rule sigma_L = T / 6.
* A clearance fit written with its letters (``"H7/g6"``): the fundamental deviations of ISO 286-2 for holes D-H and
  shafts d-h up to 120 mm give the limits of the bore and the pin, hence the mean clearance.

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

# Fundamental deviation of the shafts d-h (upper deviation es = -value, um) over the same size ranges, ISO 286-2
# Tables 19-21; a hole D-H has the opposite lower deviation EI = +value (ISO 286-1, the general rule for A-H).
_CLEARANCE_DEVIATION_UM = {
    "d": (20, 30, 40, 50, 65, 80, 100, 120),
    "e": (14, 20, 25, 32, 40, 50, 60, 72),
    "f": (6, 10, 13, 16, 20, 25, 30, 36),
    "g": (2, 4, 5, 6, 7, 9, 10, 12),
    "h": (0, 0, 0, 0, 0, 0, 0, 0),
}
#: the fit letters modelled: clearance fits, holes D-H on shafts d-h
FIT_LETTERS = tuple(_CLEARANCE_DEVIATION_UM)
#: ISO 286 clearance-fit letters not tabulated here (their deviations grow faster with the size; larger clearances)
UNTABULATED_CLEARANCE_LETTERS = ("a", "b", "c", "cd", "ef", "fg")


def _size_range(nominal_size: float) -> int:
    """Index of the ISO 286-1 size range (over one bound, up to and including the next) of a size in m."""
    size_mm = round(nominal_size * 1e3, 9)  # 18 mm given in mm arrives as 18.000000000000004 mm, over the bound
    if not (0.0 < size_mm <= _SIZE_UPPER_MM[-1]):
        raise ValueError(f"nominal size {size_mm:g} mm outside the tabulated range (0, 120] mm")
    return next(i for i, upper in enumerate(_SIZE_UPPER_MM) if size_mm <= upper)


def grade_key(grade: str) -> str:
    """Normalised ISO 286 grade name ('it 7' -> 'IT7'), as the tables name it."""
    return str(grade).upper().replace(" ", "")


def it_tolerance(grade: str, nominal_size: float) -> float:
    """Standard tolerance (m) of an ISO 286-1 grade for a nominal size (m)."""
    key = grade_key(grade)
    if key not in _IT_UM:
        lettered = re.fullmatch(r"(?!IT)[A-Z]{1,2}(\d{1,2})", key)  # 'H8', 'f7': a fit's letter and its grade
        hint = (f"; the grade is the IT number (IT{lettered[1]}); a fit with its letters is written as the "
                "clearance's fit (fit = \"H8/f7\")") if lettered else ""
        raise ValueError(f"unknown ISO 286 tolerance grade {grade!r}; known: {', '.join(_IT_UM)}{hint}")
    return _IT_UM[key][_size_range(nominal_size)] * 1e-6


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


@dataclass(frozen=True)
class IsoFit:
    """A clearance fit of ISO 286 written with its letters, at one nominal diameter (limit deviations in m)."""

    name: str
    hole_grade: str
    shaft_grade: str
    hole_lower: float
    hole_upper: float
    shaft_lower: float
    shaft_upper: float

    @property
    def mean_clearance(self) -> float:
        """Mean radial clearance (m): half the difference of the bore's and the pin's mid-limit diameters."""
        return 0.25 * (self.hole_lower + self.hole_upper - self.shaft_lower - self.shaft_upper)

    @property
    def clearance_limits(self) -> tuple[float, float]:
        """Smallest and largest radial clearance (m) of parts within their limits."""
        return 0.5 * (self.hole_lower - self.shaft_upper), 0.5 * (self.hole_upper - self.shaft_lower)


def iso_fit(fit: str, nominal_diameter: float) -> IsoFit:
    """The limits of a hole-and-shaft fit written as ``"H7/g6"`` (hole letter and grade / shaft letter and grade).

    ISO 286-2: hole D-H with lower deviation EI = +a, upper EI + IT; shaft d-h with upper deviation es = -a, lower
    es - IT; a the fundamental deviation of the letter for the size range. Only clearance fits are modelled (a pin
    that could interfere with its bore is outside the clearance-joint model)."""
    text = str(fit).replace(" ", "")
    m = re.fullmatch(r"([A-Za-z]{1,2})(\d{1,2})/([A-Za-z]{1,2})(\d{1,2})", text)
    if m is None:
        raise ValueError(f"fit {fit!r} is not written as ISO 286 letters and grades, e.g. 'H7/g6' (bore/pin)")
    hole, hole_it, shaft, shaft_it = m[1], m[2], m[3], m[4]
    known = ", ".join(FIT_LETTERS)
    if hole != hole.upper() or shaft != shaft.lower():
        raise ValueError(f"fit {fit!r}: the bore's letter is upper case and the pin's lower case, e.g. 'H7/g6'")
    for letter in (hole, shaft):
        if letter.lower() in UNTABULATED_CLEARANCE_LETTERS:
            raise ValueError(f"fit {fit!r}: the letter {letter!r} gives a clearance fit whose deviations are not "
                             f"tabulated here (bores {known.upper()} on pins {known} are); give the clearance by its "
                             "grades and its mean instead")
        if letter.lower() not in FIT_LETTERS:
            raise ValueError(f"fit {fit!r}: only clearance fits are modelled, bores {known.upper()} on pins {known} "
                             f"('{letter}' gives a transition or interference fit, which has no clearance to wear)")
    for digits in (hole_it, shaft_it):
        if digits.startswith("0"):  # IT01 and IT0 are grades of their own, not IT1
            raise ValueError(f"fit {fit!r}: grade IT{digits} is not tabulated; known: {', '.join(IT_GRADES)}")
    hole_grade, shaft_grade = f"IT{int(hole_it)}", f"IT{int(shaft_it)}"
    try:
        t_hole, t_shaft = it_tolerance(hole_grade, nominal_diameter), it_tolerance(shaft_grade, nominal_diameter)
    except ValueError as exc:
        raise ValueError(f"fit {fit!r}: {exc}") from None
    k = _size_range(nominal_diameter)
    ei_hole = _CLEARANCE_DEVIATION_UM[hole.lower()][k] * 1e-6
    es_shaft = -_CLEARANCE_DEVIATION_UM[shaft][k] * 1e-6
    return IsoFit(name=f"{hole}{int(hole_it)}/{shaft}{int(shaft_it)}", hole_grade=hole_grade, shaft_grade=shaft_grade,
                  hole_lower=ei_hole, hole_upper=ei_hole + t_hole, shaft_lower=es_shaft - t_shaft,
                  shaft_upper=es_shaft)


def length_sigma(tolerance_band: float) -> float:
    """Standard deviation of a length with a symmetric tolerance band T = ES - EI, Eq. (41)."""
    if tolerance_band <= 0:
        raise ValueError("tolerance band must be positive")
    return tolerance_band / 6.0
