"""Closed-form kinematics and hand-written inverse dynamics of the four-bar and the slider-crank.

Written independently of jointwear.mechanism (vector-loop solutions and per-link Newton-Euler
equations), to check the general multibody kernel.
"""

from __future__ import annotations

import math

import numpy as np


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def four_bar(t, m):
    """Closed-form kinematics of the four-bar config m (FourBarConfig). Returns dict of arrays."""
    l1, l2, l3 = m.crank.length, m.rod.length, m.rocker.length
    c2 = m.rod.length / 2 if m.rod.com_offset is None else m.rod.com_offset
    c3 = m.rocker.length / 2 if m.rocker.com_offset is None else m.rocker.com_offset
    O, C = np.array(m.crank_pivot), np.array(m.rocker_pivot)
    w1 = m.crank_speed
    th = m.crank_angle0 + w1 * t
    A = O + l1 * np.array([math.cos(th), math.sin(th)])
    vA = l1 * w1 * np.array([-math.sin(th), math.cos(th)])
    aA = -l1 * w1 * w1 * np.array([math.cos(th), math.sin(th)])
    d = C - A
    dist = np.hypot(*d)
    a = (l2**2 - l3**2 + dist**2) / (2 * dist)
    h = math.sqrt(l2**2 - a**2)
    u = d / dist
    B = A + a * u + m.assembly_branch * h * np.array([-u[1], u[0]])
    p2 = math.atan2(B[1] - A[1], B[0] - A[0])
    p3 = math.atan2(B[1] - C[1], B[0] - C[0])
    e2 = np.array([math.cos(p2), math.sin(p2)])
    e3 = np.array([math.cos(p3), math.sin(p3)])
    k2 = np.array([-e2[1], e2[0]])
    k3 = np.array([-e3[1], e3[0]])
    # velocity loop: vA + w2 l2 k2 = w3 l3 k3  ->  [l2 k2, -l3 k3] [w2, w3] = -vA  (Cramer's rule)
    M = np.column_stack([l2 * k2, -l3 * k3])
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]

    def solve(rhs):
        return ((rhs[0] * M[1, 1] - M[0, 1] * rhs[1]) / det, (M[0, 0] * rhs[1] - rhs[0] * M[1, 0]) / det)

    w2, w3 = solve(-vA)
    # acceleration loop: aA + al2 l2 k2 - w2^2 l2 e2 = al3 l3 k3 - w3^2 l3 e3
    al2, al3 = solve(-aA + w2**2 * l2 * e2 - w3**2 * l3 * e3)
    G2 = A + c2 * e2
    vG2 = vA + w2 * c2 * k2
    aG2 = aA + al2 * c2 * k2 - w2**2 * c2 * e2
    G3 = C + c3 * e3
    vG3 = w3 * c3 * k3
    aG3 = al3 * c3 * k3 - w3**2 * c3 * e3
    q = np.array([*G2, p2, *G3, p3])
    qd = np.array([*vG2, w2, *vG3, w3])
    qdd = np.array([*aG2, al2, *aG3, al3])
    return {"q": q, "qd": qd, "qdd": qdd, "A": A, "B": B, "C": C, "G2": G2, "G3": G3}


def four_bar_reactions(t, m):
    """Pin forces from per-link Newton-Euler: F_A (on rod by crank), F_B (on rod by rocker), F_C (on rocker by ground)."""
    k = four_bar(t, m)
    g = np.array(m.gravity)
    m2, I2, m3, I3 = m.rod.mass, m.rod.inertia, m.rocker.mass, m.rocker.inertia
    A, B, C, G2, G3 = k["A"], k["B"], k["C"], k["G2"], k["G3"]
    a2, al2, a3, al3 = k["qdd"][0:2], k["qdd"][2], k["qdd"][3:5], k["qdd"][5]
    # unknowns x = [FAx, FAy, FBx, FBy, FCx, FCy]
    E = np.zeros((6, 6))
    r = np.zeros(6)
    E[0, 0] = E[0, 2] = 1.0
    r[0] = m2 * a2[0] - m2 * g[0]
    E[1, 1] = E[1, 3] = 1.0
    r[1] = m2 * a2[1] - m2 * g[1]
    rA, rB = A - G2, B - G2
    E[2, :4] = [-rA[1], rA[0], -rB[1], rB[0]]
    r[2] = I2 * al2
    E[3, 2], E[3, 4] = -1.0, 1.0
    r[3] = m3 * a3[0] - m3 * g[0]
    E[4, 3], E[4, 5] = -1.0, 1.0
    r[4] = m3 * a3[1] - m3 * g[1]
    sB, sC = B - G3, C - G3
    E[5, 2:6] = [sB[1], -sB[0], -sC[1], sC[0]]
    r[5] = I3 * al3 - m.rocker_torque
    x = np.linalg.solve(E, r)
    return x[0:2], x[2:4], x[4:6]


def slider_crank(t, m):
    """Closed-form kinematics of an in-line slider-crank along +x (offset 0, guide angle 0, branch +1)."""
    l1, l2 = m.crank.length, m.rod.length
    c2 = l2 / 2 if m.rod.com_offset is None else m.rod.com_offset
    w = m.crank_speed
    th = m.crank_angle0 + w * t
    A = np.array([l1 * math.cos(th), l1 * math.sin(th)])
    vA = l1 * w * np.array([-math.sin(th), math.cos(th)])
    aA = -l1 * w * w * np.array([math.cos(th), math.sin(th)])
    s, sd, sdd = l1 * math.sin(th), l1 * w * math.cos(th), -l1 * w * w * math.sin(th)
    D = math.sqrt(l2 * l2 - s * s)
    Dd = -s * sd / D
    Ddd = -(sd * sd + s * sdd) / D - s * s * sd * sd / D**3
    xB = l1 * math.cos(th) + D
    vB = -l1 * w * math.sin(th) + Dd
    aB = -l1 * w * w * math.cos(th) + Ddd
    p2 = -math.asin(s / l2)
    w2 = -sd / D
    al2 = -(sdd * D - sd * Dd) / D**2
    e2 = np.array([math.cos(p2), math.sin(p2)])
    k2 = np.array([-e2[1], e2[0]])
    G2 = A + c2 * e2
    vG2 = vA + w2 * c2 * k2
    aG2 = aA + al2 * c2 * k2 - w2**2 * c2 * e2
    q = np.array([*G2, p2, xB, 0.0, 0.0])
    qd = np.array([*vG2, w2, vB, 0.0, 0.0])
    qdd = np.array([*aG2, al2, aB, 0.0, 0.0])
    return {"q": q, "qd": qd, "qdd": qdd, "A": A, "B": np.array([xB, 0.0]), "G2": G2}


def slider_crank_reactions(t, m):
    """F_A (on rod by crank), F_B (on rod by slider), N (on slider by guide, +y) from Newton-Euler."""
    k = slider_crank(t, m)
    g = np.array(m.gravity)
    m2, I2, m3 = m.rod.mass, m.rod.inertia, m.slider.mass
    A, B, G2 = k["A"], k["B"], k["G2"]
    a2, al2, a3 = k["qdd"][0:2], k["qdd"][2], k["qdd"][3:5]
    # slider: m3 a3 = -F_B + (0, N) + m3 g  -> F_B = -m3 a3 + m3 g + (0, N)
    # unknowns x = [FAx, FAy, N]; rod: m2 a2 = F_A + F_B + m2 g ; I2 al2 = rA x F_A + rB x F_B
    E = np.zeros((3, 3))
    r = np.zeros(3)
    FB0 = -m3 * a3 + m3 * g
    E[0, 0] = 1.0
    r[0] = m2 * a2[0] - m2 * g[0] - FB0[0]
    E[1, 1], E[1, 2] = 1.0, 1.0
    r[1] = m2 * a2[1] - m2 * g[1] - FB0[1]
    rA, rB = A - G2, B - G2
    E[2] = [-rA[1], rA[0], rB[0]]
    r[2] = I2 * al2 - cross(rB, FB0)
    x = np.linalg.solve(E, r)
    FA = x[0:2]
    FB = FB0 + np.array([0.0, x[2]])
    return FA, FB, x[2]
