"""Reliability problems with known answers (tests and ``benchmarks/reliability.py``).

Each problem is a :class:`Problem`: a vectorised limit state, its marginals and a reference Pf with the
source of that reference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import integrate, stats
from scipy.special import ndtr

__all__ = ["Problem", "four_branch", "linear", "lognormal_rs", "oscillator", "rastrigin", "four_branch_exact_pf",
           "parabolic", "parabolic_exact_pf", "cubic_parabolic", "archard_wear", "archard_wear_exact_pf"]


@dataclass(frozen=True)
class Problem:
    name: str
    g: Callable[[np.ndarray], np.ndarray]
    marginals: tuple
    pf_ref: float
    ref_source: str
    echard_calls: int | None = None  # AK-MCS+U calls in Echard, Gayton & Lemaire (2011), Struct. Saf. 33
    echard_n_mc: int | None = None  # Monte Carlo population they used


# ------------------------------------------------------------------------------------------ four-branch
def _four_branch(x: np.ndarray, k: float) -> np.ndarray:
    x1, x2 = x[:, 0], x[:, 1]
    a = 3.0 + 0.1 * (x1 - x2) ** 2
    s = (x1 + x2) / math.sqrt(2.0)
    return np.minimum(np.minimum(a - s, a + s), np.minimum((x1 - x2) + k / math.sqrt(2.0), (x2 - x1) + k / math.sqrt(2.0)))


class _FourBranch:  # a class, not a closure, so that it pickles for process executors
    def __init__(self, k: float):
        self.k = k

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return _four_branch(np.asarray(x, dtype=float), self.k)


def four_branch_exact_pf(k: float) -> float:
    """Exact Pf of the four-branch system by 1-D quadrature.

    With v1 = (x1 + x2)/sqrt 2 and v2 = (x1 - x2)/sqrt 2 (independent standard normals), failure is
    |v1| > 3 + 0.2 v2^2 or |v2| > k/2, so Pf = P(|v2| > k/2) + int_{|v2| <= k/2} phi(v2) 2 Phi(-(3 + 0.2 v2^2)) dv2.
    """
    tail = 2.0 * ndtr(-k / 2.0)
    inner, _ = integrate.quad(lambda v: stats.norm.pdf(v) * 2.0 * ndtr(-(3.0 + 0.2 * v * v)), -k / 2, k / 2,
                              epsabs=1e-14, epsrel=1e-12)
    return float(tail + inner)


def four_branch(k: float = 6.0) -> Problem:
    """Four-branch series system (Echard et al. 2011, Sec. 5.1), two standard normal inputs."""
    calls = {6.0: 126, 7.0: 96}.get(float(k))
    return Problem(
        name=f"four_branch_k{k:g}",
        g=_FourBranch(k),
        marginals=(stats.norm(), stats.norm()),
        pf_ref=four_branch_exact_pf(k),
        ref_source="exact, 1-D quadrature in rotated coordinates (four_branch_exact_pf); "
        "Echard 2011 MCS 1e6: 4.416e-3 (k=6), 2.233e-3 (k=7)",
        echard_calls=calls,
        echard_n_mc=1_000_000,
    )


# ------------------------------------------------------------------------------------------ linear
class _Linear:
    def __init__(self, beta: float, d: int):
        self.beta, self.d = beta, d

    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        # inputs N(mu_i, sigma_i) with mu_i = i + 1, sigma_i = 0.5 (i + 1); standardised sum
        mu = np.arange(1, self.d + 1, dtype=float)
        u = (x - mu) / (0.5 * mu)
        return self.beta - u.sum(axis=1) / math.sqrt(self.d)


def linear(beta: float = 3.0, d: int = 2) -> Problem:
    """Linear limit state in d normal inputs of different means/scales: exact Pf = Phi(-beta)."""
    mu = np.arange(1, d + 1, dtype=float)
    return Problem(
        name=f"linear_beta{beta:g}_d{d}",
        g=_Linear(beta, d),
        marginals=tuple(stats.norm(m, 0.5 * m) for m in mu),
        pf_ref=float(ndtr(-beta)),
        ref_source="exact: Phi(-beta)",
    )


# ------------------------------------------------------------------------------------------ lognormal R - S
class _RS:
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return x[:, 0] - x[:, 1]


def lognormal_rs(mean_r: float = 200e6, cov_r: float = 0.1, mean_s: float = 120e6, cov_s: float = 0.2) -> Problem:
    """g = R - S with lognormal R (resistance, Pa) and S (load, Pa). ln R - ln S is normal, so
    Pf = Phi(-(lambda_R - lambda_S) / sqrt(zeta_R^2 + zeta_S^2)) exactly."""

    def ln_params(mean: float, cov: float) -> tuple[float, float]:
        zeta = math.sqrt(math.log(1.0 + cov * cov))
        return math.log(mean) - 0.5 * zeta * zeta, zeta

    lr, zr = ln_params(mean_r, cov_r)
    ls, zs = ln_params(mean_s, cov_s)
    pf = float(ndtr(-(lr - ls) / math.hypot(zr, zs)))
    return Problem(
        name="lognormal_r_minus_s",
        g=_RS(),
        marginals=(stats.lognorm(s=zr, scale=math.exp(lr)), stats.lognorm(s=zs, scale=math.exp(ls))),
        pf_ref=pf,
        ref_source="exact: ln R - ln S normal",
    )


# ------------------------------------------------------------------------------------------ Archard wear
ARCHARD_K0, ARCHARD_H0 = 1e-4, 1.96e9  # wear coefficient (-) and Brinell hardness (Pa) of the bearing
ARCHARD_CYCLES, ARCHARD_DELTA0 = 400_000, 0.03e-3  # cycles, allowable wear (m)
ARCHARD_Q0 = 0.0285e-3 / (ARCHARD_K0 / ARCHARD_H0 * ARCHARD_CYCLES)  # Pa m per cycle: 0.0285 mm at 400k cycles


class _Archard:
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return ARCHARD_DELTA0 - x[:, 0] / x[:, 1] * x[:, 2] * ARCHARD_CYCLES


def archard_wear_exact_pf() -> float:
    """Exact Pf of :func:`archard_wear`: given k and H, failure is q > delta_0 H / (k N), and q is lognormal, so
    Pf = E_{k,H}[Phi(-ln(delta_0 H / (k N q0)) / 0.04)], taken over the two normals by a Gauss-Hermite product rule
    (64 nodes per axis: the integrand is smooth, 32 nodes agree with 64 to 1e-15, and so does scipy's dblquad over
    +-8 sigma)."""
    z, w = np.polynomial.hermite_e.hermegauss(64)
    w = w / math.sqrt(2.0 * math.pi)
    k = ARCHARD_K0 * (1.0 + 0.05 * z)[:, None]
    h = ARCHARD_H0 * (1.0 + 0.05 * z)[None, :]
    tail = ndtr(-np.log(ARCHARD_DELTA0 * h / (k * ARCHARD_CYCLES * ARCHARD_Q0)) / 0.04)
    return float(w @ tail @ w)


def archard_wear() -> Problem:
    """``examples/api_example.py``'s limit state: delta_0 - k / H q N with k ~ N(1e-4, 5 %), H ~ N(1.96 GPa, 5 %) and
    the load term q lognormal (4 %), N = 400,000 cycles; three inputs, Pf about 0.26, a smooth limit state on which a
    Kriging of a dozen points can be sure of itself where it is wrong."""
    return Problem(
        name="archard_wear",
        g=_Archard(),
        marginals=(stats.norm(ARCHARD_K0, 0.05 * ARCHARD_K0), stats.norm(ARCHARD_H0, 0.05 * ARCHARD_H0),
                   stats.lognorm(s=0.04, scale=ARCHARD_Q0)),
        pf_ref=archard_wear_exact_pf(),
        ref_source="exact, Gauss-Hermite quadrature over k and H of the lognormal q's tail (archard_wear_exact_pf)",
    )


# ------------------------------------------------------------------------------------------ oscillator
class _Oscillator:
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        m, c1, c2, r, f1, t1 = (x[:, i] for i in range(6))
        w0 = np.sqrt((c1 + c2) / m)
        return 3.0 * r - np.abs(2.0 * f1 / (m * w0**2) * np.sin(w0 * t1 / 2.0))


# Reference: crude MCS with 1e8 samples, seed 20261121 (benchmarks/reliability.py --reference); COV 5.8e-4.
OSCILLATOR_PF_REF = 2.85626e-2
# Reference: crude MCS with 1e8 samples, seed 20261121; COV 3.6e-4.
RASTRIGIN_PF_REF = 7.296866e-2


def oscillator() -> Problem:
    """Non-linear undamped single-degree-of-freedom oscillator (Echard et al. 2011, Sec. 5.3), 6 normals."""
    margs = (stats.norm(1.0, 0.05), stats.norm(1.0, 0.1), stats.norm(0.1, 0.01), stats.norm(0.5, 0.05),
             stats.norm(1.0, 0.2), stats.norm(1.0, 0.2))
    return Problem(
        name="oscillator",
        g=_Oscillator(),
        marginals=margs,
        pf_ref=OSCILLATOR_PF_REF,
        ref_source="crude MCS 1e8 samples (this repo); Echard 2011 MCS 7e4: 2.850e-2",
        echard_calls=58,
        echard_n_mc=70_000,
    )


class _Rastrigin:
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return 10.0 - np.sum(x * x - 5.0 * np.cos(2.0 * np.pi * x), axis=1)


def rastrigin() -> Problem:
    """Modified Rastrigin function (Echard et al. 2011, Sec. 5.4), two standard normals; non-convex,
    scattered failure domains."""
    return Problem(
        name="rastrigin",
        g=_Rastrigin(),
        marginals=(stats.norm(), stats.norm()),
        pf_ref=RASTRIGIN_PF_REF,
        ref_source="crude MCS 1e8 samples (this repo); Echard 2011 MCS 6e4: 7.34e-2",
        echard_calls=416,
        echard_n_mc=60_000,
    )


# ------------------------------------------------------------------------------------------ small Pf (AK-IS)
class _Parabolic:
    def __init__(self, beta: float, kappa: float):
        self.beta, self.kappa = beta, kappa

    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return self.beta + self.kappa * x[:, 0] ** 2 - x[:, 1]


def parabolic_exact_pf(beta: float, kappa: float) -> float:
    """P[u2 > beta + kappa u1^2] = integral phi(t) Phi(-(beta + kappa t^2)) dt (adaptive quadrature)."""
    val, _ = integrate.quad(lambda t: stats.norm.pdf(t) * ndtr(-(beta + kappa * t * t)), -np.inf, np.inf,
                            epsabs=0.0, epsrel=1e-12, limit=200)
    return float(val)


def parabolic(beta: float = 5.0, kappa: float = 0.1) -> Problem:
    """g = beta + kappa u1^2 - u2, two standard normals: a curved limit state at distance beta (Pf ~ 1e-7 at
    beta = 5), where FORM's Phi(-beta) is off by the curvature (Breitung: a factor 1 / sqrt(1 + 2 kappa beta)).
    The reference is the exact one-dimensional integral."""
    return Problem(
        name=f"parabolic_beta{beta:g}_kappa{kappa:g}",
        g=_Parabolic(beta, kappa),
        marginals=(stats.norm(), stats.norm()),
        pf_ref=parabolic_exact_pf(beta, kappa),
        ref_source="exact: 1-D quadrature of phi(t) Phi(-(beta + kappa t^2))",
    )


class _CubicParabolic:
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return 0.5 * (x[:, 0] - 2.0) ** 2 - 1.5 * (x[:, 1] - 5.0) ** 3 - 3.0


# Reference: importance sampling at the design point (0.788, 3.853) with 1e8 samples (10 x 1e7, seed 1);
# COV 3e-4. FORM gives 4.20e-5.
CUBIC_PARABOLIC_PF_REF = 2.87559e-5


def cubic_parabolic() -> Problem:
    """g = 0.5 (u1 - 2)^2 - 1.5 (u2 - 5)^3 - 3, two standard normals (Echard, Gayton, Lemaire & Relun 2013,
    AK-IS, example 1): small Pf with a strongly non-linear limit state."""
    return Problem(
        name="cubic_parabolic",
        g=_CubicParabolic(),
        marginals=(stats.norm(), stats.norm()),
        pf_ref=CUBIC_PARABOLIC_PF_REF,
        ref_source="importance sampling 1e8 samples at the design point (this repo); FORM 4.20e-5",
    )
