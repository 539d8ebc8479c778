"""The one angle convention of every wear report (paper Section 6.1.3, the user guide's baseline reading).

Inside the code a profile lives on a grid fixed in its body: theta (rad) counter-clockwise from the body's x axis.
Reports use the paper's convention: the bearing (rod eye) is laid onto global directions at the rod's mean
orientation over a cycle, psi_mean; 0 deg is then the leftmost point (global -x) and the angle grows clockwise:

    global direction  alpha = theta + psi_mean            (CCW from global +x)
    report angle      phi   = (180 deg - alpha) mod 360    (CW from global -x)

so phi = 90 deg is the top of the bearing and phi = 270 deg the bottom. The journal (crank pin) turns a full
revolution, so it has no mean orientation; its profile is reported with psi_mean = 0 (the crank laid along +x).
"""

from __future__ import annotations

import math

import numpy as np


def report_angle_deg(theta_body, mean_orientation: float = 0.0):
    """Body-frame angle(s) theta (rad, CCW from the body x axis) -> report angle (deg, CW from the leftmost point)."""
    phi = np.mod(math.pi - (np.asarray(theta_body, dtype=float) + mean_orientation), 2.0 * math.pi)
    out = np.degrees(phi)
    out = np.where(out >= 360.0, out - 360.0, out)
    return float(out) if np.ndim(out) == 0 else out


def angle_text(phi_deg: float, decimals: int = 0) -> str:
    """A report angle as shown, rounded and wrapped to [0, 360): 359.99 deg at 0 decimals reads "0", not "360"."""
    r = round(float(phi_deg), decimals) % 360.0
    return f"{r + 0.0:.{decimals}f}"  # + 0.0: no "-0"


def body_angle_from_report(phi_deg, mean_orientation: float = 0.0):
    """Inverse of `report_angle_deg`: report angle (deg) -> body-frame angle (rad, in [0, 2 pi))."""
    theta = np.mod(math.pi - np.radians(np.asarray(phi_deg, dtype=float)) - mean_orientation, 2.0 * math.pi)
    return float(theta) if np.ndim(theta) == 0 else theta


def circular_mean(angles, weights=None) -> float:
    """Weighted circular mean (rad, in (-pi, pi]) of angles (rad)."""
    a = np.asarray(angles, dtype=float)
    w = np.ones_like(a) if weights is None else np.asarray(weights, dtype=float)
    return float(math.atan2(np.sum(w * np.sin(a)), np.sum(w * np.cos(a))))
