"""Closed-form results of constant-load cases (derived in docs/verification.md; SI units)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from jointwear.contact.laws import contact_stiffness

RIG = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"
JOHNSON = math.sqrt(4.0 / math.pi)


@dataclass(frozen=True)
class Rig:
    """The pendulum rig of tests/wear/rigs/pendulum.toml, read from its config."""

    weight: float  # N
    arm: float  # m, pin centre -> centre of mass
    mass: float
    inertia: float  # about the centre of mass
    omega: float  # crank speed (rad/s)
    crank: float  # crank length (m)
    r_b: float
    r_j: float
    width: float
    hsum: float  # (1 - nu_b^2)/E_b + (1 - nu_j^2)/E_j
    kH_b: float
    mu: float

    @classmethod
    def from_config(cls, cfg) -> "Rig":
        mech = cfg.mechanism
        pend = next(b for b in mech.bodies if b.name == "pendulum")
        crank = next(b for b in mech.bodies if b.name == "crank")
        cj = cfg.clearance_joints[0]
        g = math.hypot(*mech.gravity)
        bm, jm = cj.bearing_material, cj.journal_material
        ax, ay = pend.points["A"]
        return cls(
            weight=pend.mass * g, arm=math.hypot(pend.com[0] - ax, pend.com[1] - ay), mass=pend.mass,
            inertia=pend.inertia, omega=mech.drivers[0].speed,
            crank=math.dist(crank.points["O"], crank.points["A"]), r_b=cj.bearing_radius, r_j=cj.journal_radius,
            width=cj.width, hsum=(1 - bm.poissons_ratio**2) / bm.youngs_modulus
            + (1 - jm.poissons_ratio**2) / jm.youngs_modulus,
            kH_b=bm.wear_coefficient / bm.hardness, mu=cj.friction.mu_d,
        )

    @property
    def clearance(self) -> float:
        return self.r_b - self.r_j

    @property
    def mass_at_pin(self) -> float:
        """The pendulum's mass for a sideways push at the pin, free to turn about its centre of mass:
        1 / m_eff = 1 / m + arm^2 / I."""
        return 1.0 / (1.0 / self.mass + self.arm**2 / self.inertia)

    @property
    def slide_per_rev(self) -> float:
        return 2.0 * math.pi * self.r_j


def friction_circle(rig: Rig) -> tuple[float, float, float]:
    """(phi, N, psi): the contact normal sits atan(mu) from the load line, N = W cos(phi), and the pendulum tilts by
    psi = asin(R_b sin(phi) / arm) so that its weight acts on the line of the contact force."""
    phi = math.atan(rig.mu)
    return phi, rig.weight * math.cos(phi), math.asin(rig.r_b * math.sin(phi) / rig.arm)


def half_width(force: float, r_b: float, r_j: float, hsum: float, width: float) -> float:
    """Johnson's line-contact half-width b = sqrt(4 F R* / (pi L E*)) of a pin in a hole (Contact Mechanics 4.43)."""
    rstar = r_b * r_j / (r_b - r_j)
    return JOHNSON * math.sqrt(force * rstar * hsum / width)


def deposit_per_rev(kH: float, force: float, slide: float, b: float, width: float, pressure: str) -> float:
    """Peak Archard depth laid in one revolution on a stationary patch |s| <= b: uniform p = F / (2 b L), Hertz
    p0 = 2 F / (pi b L)."""
    p0 = force / (2.0 * b * width) if pressure == "uniform" else 2.0 * force / (math.pi * b * width)
    return kH * p0 * slide


def uniform_mode_rate(rig: Rig, h: float, force: float) -> float:
    """Depth per revolution of uniform mode at total depth h: the clearance grows by h (R_b + h/2, R_j - h/2), the
    patch half-width with it, the sliding distance per revolution is 2 pi (R_j - h/2)."""
    rb, rj = rig.r_b + 0.5 * h, rig.r_j - 0.5 * h
    b = half_width(force, rb, rj, rig.hsum, rig.width)
    return deposit_per_rev(rig.kH_b, force, 2.0 * math.pi * rj, b, rig.width, "uniform")


def uniform_mode_euler(rig: Rig, force: float, blocks: np.ndarray) -> np.ndarray:
    """The growth law of uniform mode stepped exactly as the wear history steps it (explicit Euler over blocks)."""
    h = [0.0]
    for dn in blocks:
        h.append(h[-1] + uniform_mode_rate(rig, h[-1], force) * dn)
    return np.asarray(h)


def uniform_mode_ode(rig: Rig, force: float, n: np.ndarray) -> np.ndarray:
    """The same law integrated exactly (dh/dn = uniform_mode_rate)."""
    sol = solve_ivp(lambda _, y: [uniform_mode_rate(rig, y[0], force)], (0.0, float(np.max(n))), [0.0],
                    rtol=1e-10, atol=1e-16, dense_output=True)
    return sol.sol(np.asarray(n, dtype=float))[0]


def conformal_wear(rig: Rig, force: float, n: float) -> dict:
    """Conformal wear of a radially loaded journal bearing by a hard journal (Kauzlarich and Williams 2001, Sec. 4;
    docs/verification.md): the journal, displaced by d along its contact line, has worn the bore to its own shape,
    h(theta) = d cos(theta) - c0 over |theta| < theta_m = acos(c0 / d). Local Archard wear with the cos pressure of
    a conformal contact gives dd/dn = (k/H) N s_rev / (R L (theta_m + sin theta_m cos theta_m)). Returns the max depth
    d - c0, the worn arc 2 theta_m (rad) and the worn area 2 R (d sin theta_m - c0 theta_m) (m^2, thin layer)."""
    c0, r = rig.clearance, rig.r_b

    def rate(_, y):
        t = math.acos(min(1.0, c0 / y[0]))
        return [rig.kH_b * force * rig.slide_per_rev / (r * rig.width * max(t + math.sin(t) * math.cos(t), 1e-12))]

    sol = solve_ivp(rate, (0.0, n), [c0 * (1.0 + 1e-9)], rtol=1e-10, atol=1e-18)
    d = float(sol.y[0, -1])
    t = math.acos(c0 / d)
    return {"depth": d - c0, "arc": 2.0 * t, "area": 2.0 * r * (d * math.sin(t) - c0 * t)}


def hertz_approach(force: float, r_b: float, r_j: float, hsum: float) -> float:
    """The contact law's static penetration delta = (F / K)^(1/n), n = 3/2, K the law's stiffness."""
    return (force / contact_stiffness(hsum, r_b, r_j)) ** (2.0 / 3.0)


def rocking_hz(force: float, radius: float, mass: float) -> float:
    """Frequency (Hz) of a mass pressed by ``force`` onto a path of ``radius``: omega^2 = N / (radius m), a pendulum
    of length ``radius`` in the field N (restoring force N s / radius for a tangential offset s)."""
    return math.sqrt(force / (radius * mass)) / (2.0 * math.pi)


def rocking_frequency(rig: Rig, force: float, growth: float = 0.0) -> float:
    """Frequency (Hz) of the pendulum's eye rocking on the pin along the bore: the eye's centre rides the circle of
    radius e = c0 + growth + delta about the pin's centre with the pendulum's mass at the pin (Rig.mass_at_pin);
    omega^2 = N / (e m_eff)."""
    rb, rj = rig.r_b + 0.5 * growth, rig.r_j - 0.5 * growth
    return rocking_hz(force, rb - rj + hertz_approach(force, rb, rj, rig.hsum), rig.mass_at_pin)


def spectral_peak(t: np.ndarray, x: np.ndarray, above: float) -> float:
    """Frequency (Hz) of the largest spectral peak of x(t) above `above` Hz: resampled evenly, a quintic trend (the
    crank's 1 Hz motion) removed, Hann window, zero-padded 16-fold (bins of 1 / (16 T) for a record of length T)."""
    tu = np.linspace(t[0], t[-1], 2**16)
    xu = np.interp(tu, t, x)
    xu -= np.polyval(np.polyfit(tu, xu, 5), tu)
    spec = np.abs(np.fft.rfft(xu * np.hanning(xu.size), 2**20))
    freq = np.fft.rfftfreq(2**20, tu[1] - tu[0])
    spec[freq < above] = 0.0
    return float(freq[np.argmax(spec)])


def mirrored_config(rig_config):
    """The rig mirrored: the eye on the crank, the pin on the pendulum, so that the load stays fixed on the pin and
    turns round the bore; only the pin wears (k/H = 1e-14 m^2/N, the rig's bearing's). To first order in c0 / R the
    pin wears the bore's shape into itself as the rig's bore wears the pin's (docs/verification.md, case 5)."""
    data = rig_config.model_dump(mode="python")
    cj = data["clearance_joints"][0]
    cj["bearing_body"], cj["journal_body"] = cj["journal_body"], cj["bearing_body"]
    kb = cj["bearing_material"]["wear_coefficient"]
    cj["bearing_material"]["wear_coefficient"], cj["journal_material"]["wear_coefficient"] = 0.0, kb
    return type(rig_config).model_validate(data)
