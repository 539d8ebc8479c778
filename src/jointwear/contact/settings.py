"""Settings of a clearance joint (``[[clearance_joints]]``): radii, width, materials, contact and friction laws.

SI values under plain names; TOML keys may carry a unit suffix (jointwear.units). The mechanism model holds these
validated objects as they are (jointwear.mechanism.model.ClearanceJoint).
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import field_validator, model_validator

from jointwear.contact.laws import compliance, contact_stiffness_py
from jointwear.schema import F, SIModel
from jointwear.units import fmt_mm


class MaterialConfig(SIModel):
    """Elastic and wear properties of one body of a clearance joint."""

    name: str = F("", description="Material name, for reports only.")
    youngs_modulus: float = F(
        unit="Pa", ge=1e6, le=1.5e12,
        description="Young's modulus E (key e.g. youngs_modulus_GPa), from 1 MPa (a soft rubber) to 1.5 TPa (above "
        "diamond's 1.2 TPa): a value outside is a unit slip.",
    )
    poissons_ratio: float = F(gt=-1.0, lt=0.5, description="Poisson's ratio nu, in (-1, 0.5).")
    hardness: float = F(
        unit="Pa", ge=1e6, le=1.5e11,
        description="Hardness H used by Archard's law (key hardness_HB: Brinell number x 9.807e6 Pa; baseline "
        "reading), from 1 MPa (PTFE's is about 30 MPa) to 150 GPa (above diamond's 100 GPa or so): a value outside "
        "is a unit slip.",
    )
    wear_coefficient: float = F(
        ge=0, lt=1, description="Dimensionless Archard wear coefficient k, 0 <= k < 1 (Archard's law, "
        "dV = k F ds / H): a probability per asperity encounter, about 1e-2 for dry mild steel at most; 0 for a side that "
        "does not wear. From a handbook's specific wear rate K in mm^3/(N m): k = K x 1e-9 x H in Pa (k / H is K in "
        "m^2/N), e.g. POM on steel, K = 2e-6 at H = 170 MPa: k = 3.4e-7.",
    )

    @property
    def h(self) -> float:
        """Compliance (1 - nu^2) / E (1/Pa): :func:`jointwear.contact.laws.compliance`."""
        return compliance(self.youngs_modulus, self.poissons_ratio)


class FrictionConfig(SIModel):
    """Modified Coulomb friction of Ambrosio (2003) in the continuous cubic-blend form (docs/dynamics.md)."""

    law: Literal["ambrosio", "none"] = F("ambrosio", description="'ambrosio' (modified Coulomb) or 'none' (frictionless).")
    mu_d: float = F(0.1, ge=0, description="Dynamic (sliding) friction coefficient; paper gives none, baseline reading 0.1.")
    mu_s: float = F(0.15, ge=0, description="Static friction coefficient; baseline reading 0.15.")
    v_s: float = F(1e-4, unit="m/s", gt=0, description="Static-friction critical slip speed; baseline reading 1e-4 m/s.")
    v_d: float = F(1e-3, unit="m/s", gt=0, description="Speed above which friction is purely dynamic; baseline reading 1e-3 m/s.")

    @model_validator(mode="after")
    def _speeds(self) -> FrictionConfig:
        if not self.v_s < self.v_d:
            raise ValueError(f"v_s ({self.v_s:g} m/s) must be smaller than v_d ({self.v_d:g} m/s)")
        return self


class ClearanceJointConfig(SIModel):
    """A revolute joint with radial clearance: a journal (pin) inside a bearing (eye)."""

    name: str = F("A", description="Name of the clearance joint (reports, traces).")
    joint: str = F(
        description="Name of the mechanism's revolute joint that carries the clearance (four_bar: A, B, C; "
        "slider_crank: A, B; general: any revolute joint that is not a driver's). Joint O (the driven crank "
        "pivot) cannot carry clearance."
    )
    bearing_body: str = F(description="Body carrying the bearing (the hole); one of the two bodies of `joint`.")
    journal_body: str = F(description="Body carrying the journal (the pin); the other body of `joint`.")
    bearing_radius: float = F(unit="m", gt=0, description="Inner radius R_i of the bearing.")
    journal_radius: float = F(unit="m", gt=0, description="Radius R_j of the journal; must be < bearing_radius.")
    bearing_outer_radius: float | None = F(
        None, unit="m", gt=0,
        description="Outer radius of the bearing; the wear allowance 0.01 D uses its diameter.",
    )
    width: float = F(unit="m", gt=0, description="Axial width L of the contact.")
    bearing_material: MaterialConfig = F(description="Bearing material.")
    journal_material: MaterialConfig = F(description="Journal material.")
    contact_law: Literal["lankarani_nikravesh", "flores", "hunt_crossley"] = F(
        "lankarani_nikravesh",
        description="Normal force law: 'lankarani_nikravesh' (paper Eq. 16-18, D = 3K(1-cr^2)d^n/(4 v0)), "
        "'flores' (Flores et al. 2011, D = 8K(1-cr)d^n/(5 cr v0)), 'hunt_crossley' (D = 3K(1-cr)d^n/(2 v0)).",
    )
    exponent: float = F(1.5, gt=0, description="Force exponent n of K d^n; 1.5 (Hertz, paper Eq. 16), the only value "
                        "consistent with the stiffness K, which is Hertz's in N/m^1.5 from the materials and radii.")
    restitution: float = F(
        0.9, gt=0, le=1,
        description="Coefficient of restitution cr the damping of the contact law is built from. Each law matches it "
        "to first order in 1 - cr only: one impact delivers 0.913 at cr = 0.9 with 'lankarani_nikravesh', 0.909 with "
        "'hunt_crossley' and 0.894 with 'flores' (docs/verification.md, case 6).",
    )
    v0_min: float = F(
        1e-4, unit="m/s", gt=0,
        description="Floor on the impact speed v0 in the damping term; paper silent, baseline reading 1e-4 m/s.",
    )
    friction: FrictionConfig = F(default_factory=FrictionConfig, description="Friction law parameters.")

    @field_validator("exponent")
    @classmethod
    def _hertz_exponent(cls, v: float) -> float:
        # another n with Hertz's K in N/m^1.5 has no units: n = 3 sank the reference pin 79 um into a 2 um clearance
        if v != 1.5:
            raise ValueError("must be 1.5: the contact stiffness K is Hertz's, in N/m^1.5 from the "
                             "materials and radii (docs/dynamics.md), so K d^n with another exponent has no consistent "
                             "units; jointwear takes no stiffness of its own")
        return v

    @field_validator("journal_radius")
    @classmethod
    def _journal_smaller(cls, v: float, info: Any) -> float:
        rb = info.data.get("bearing_radius")
        if rb is not None and not v < rb:
            raise ValueError(
                f"journal radius {fmt_mm(v)} must be smaller than bearing_radius {fmt_mm(rb)} "
                f"(clearance = bearing_radius - journal_radius = {fmt_mm(rb - v)} must be > 0)"
            )
        return v

    @model_validator(mode="after")
    def _outer(self) -> ClearanceJointConfig:
        if self.bearing_outer_radius is not None and not self.bearing_outer_radius > self.bearing_radius:
            raise ValueError(
                f"bearing_outer_radius {fmt_mm(self.bearing_outer_radius)} must exceed bearing_radius "
                f"{fmt_mm(self.bearing_radius)}"
            )
        if self.bearing_body == self.journal_body:
            raise ValueError("bearing_body and journal_body must differ")
        return self

    @property
    def clearance(self) -> float:
        """Radial clearance c = R_i - R_j (m)."""
        return self.bearing_radius - self.journal_radius


    @property
    def hsum(self) -> float:
        """Sum of the two bodies' compliances h = (1 - nu^2) / E (1/Pa)."""
        return self.bearing_material.h + self.journal_material.h

    @property
    def stiffness(self) -> float:
        """Nominal contact stiffness K of the unworn joint (N/m^n)."""
        bm, jm = self.bearing_material, self.journal_material
        return contact_stiffness_py(bm.youngs_modulus, bm.poissons_ratio, jm.youngs_modulus, jm.poissons_ratio,
                                    self.bearing_radius, self.journal_radius)
