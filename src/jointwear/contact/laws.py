"""Normal-force and friction laws of a revolute clearance joint (compiled scalar kernels).

Normal force (paper Section 2.4.1): F_N = K d^n (1 + chi * v_n), d = penetration, v_n = d(d)/dt,
with the hysteresis factor chi chosen by the law code:

=====  ======================  ======================================  ==========================
code   name                    chi                                     source
=====  ======================  ======================================  ==========================
0      lankarani_nikravesh     3 (1 - cr^2) / (4 v0)                   Lankarani & Nikravesh 1990
1      flores                  8 (1 - cr) / (5 cr v0)                  Flores et al. 2011
2      hunt_crossley           3 (1 - cr) / (2 v0)                     Hunt & Crossley 1975
=====  ======================  ======================================  ==========================

v0 is the normal approach speed at the start of the contact, floored by v0_min.  The force is
clipped at zero (no adhesion during restitution).

Stiffness (paper Eq. 17 as corrected in the user guide's baseline reading):
K = 4 / (3 (h_i + h_j)) * sqrt(R_i R_j / (R_i - R_j)), h_k = (1 - nu_k^2) / E_k.

Friction (paper Section 2.4.2, Eq. 19; Ambrosio 2003 modified Coulomb law in the continuous
cubic-blend form used e.g. by Bai & Zhao 2012): the friction force on the journal along the
tangent t is F_T = -mu(v_t) F_N, with the odd function

    mu(v) = mu_d sgn(v)                                                  |v| > v_d
    mu(v) = [mu_d + (mu_s - mu_d) x^2 (3 - 2 x)] sgn(v), x = (v_d - |v|)/(v_d - v_s)   v_s <= |v| <= v_d
    mu(v) = mu_s (2 y^2 (3 - 2 y) - 1),  y = (v + v_s) / (2 v_s)         |v| < v_s

which is continuous with continuous slope at |v| = v_d, rises to mu_s at |v| = v_s and passes
through zero at v = 0 (no discontinuity at stick).
"""

from __future__ import annotations

import math

from numba import njit

LAW_CODES = {"lankarani_nikravesh": 0, "flores": 1, "hunt_crossley": 2}
FRICTION_CODES = {"none": 0, "ambrosio": 1}


@njit(cache=True, inline="always")
def contact_stiffness(hsum: float, r_i: float, r_j: float) -> float:
    """Generalized stiffness K = 4 / (3 hsum) * sqrt(R_i R_j / (R_i - R_j)) (N/m^n) of a pin of radius R_j in a hole
    of radius R_i, hsum = h_i + h_j (compliance); Lankarani & Nikravesh 1990, paper Eq. 17 as corrected in the
    baseline reading. Compiled for the kernels, and called as it is from Python."""
    return 4.0 / (3.0 * hsum) * math.sqrt(r_i * r_j / (r_i - r_j))


@njit(cache=True, inline="always")
def hysteresis_factor(law: int, cr: float, v0: float) -> float:
    """chi in F_N = K d^n (1 + chi v_n), 1/(m/s)."""
    if law == 0:
        return 3.0 * (1.0 - cr * cr) / (4.0 * v0)
    elif law == 1:
        return 8.0 * (1.0 - cr) / (5.0 * cr * v0)
    else:
        return 3.0 * (1.0 - cr) / (2.0 * v0)


@njit(cache=True, inline="always")
def normal_force(law: int, k: float, nexp: float, delta: float, vn: float, cr: float, v0: float) -> float:
    """Normal contact force (>= 0) for penetration delta > 0 and penetration rate vn."""
    if nexp == 1.5:
        dn = delta * math.sqrt(delta)
    else:
        dn = delta ** nexp
    f = k * dn * (1.0 + hysteresis_factor(law, cr, v0) * vn)
    return max(0.0, f)


@njit(cache=True, inline="always")
def friction_coefficient(v: float, mu_d: float, mu_s: float, v_s: float, v_d: float) -> float:
    """Signed friction coefficient mu(v) of the modified Coulomb law (odd in v)."""
    av = abs(v)
    if av > v_d:
        return mu_d if v > 0.0 else -mu_d
    if av >= v_s:
        x = (v_d - av) / (v_d - v_s)
        m = mu_d + (mu_s - mu_d) * x * x * (3.0 - 2.0 * x)
        return m if v > 0.0 else -m
    y = (v + v_s) / (2.0 * v_s)
    return mu_s * (2.0 * y * y * (3.0 - 2.0 * y) - 1.0)


def compliance(youngs_modulus: float, poissons_ratio: float) -> float:
    """Compliance h = (1 - nu^2) / E of a body's material (1/Pa), the term of K and of the Hertz half-width."""
    return (1.0 - poissons_ratio**2) / youngs_modulus


def contact_stiffness_py(e_i: float, nu_i: float, e_j: float, nu_j: float, r_i: float, r_j: float) -> float:
    """K from materials and radii: contact_stiffness(compliance(E_i, nu_i) + compliance(E_j, nu_j), R_i, R_j)."""
    return contact_stiffness(compliance(e_i, nu_i) + compliance(e_j, nu_j), r_i, r_j)
