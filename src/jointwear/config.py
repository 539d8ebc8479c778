"""Study configuration: pydantic models, TOML loading and built-in presets.

``load_config(source)`` accepts a TOML file path, a preset name (a file
``jointwear/presets/<name>.toml``) or None for the default preset
``jin2025_flapping_wing``.  Every problem becomes a :class:`ConfigError` with one line that
names the field (dotted path) and the allowed range.

Units: TOML keys may carry a unit suffix (``length_mm``, ``speed_rpm``, ``youngs_modulus_GPa``,
``hardness_HB``, ``angle_deg`` ...; table in :mod:`jointwear.units`).  Models hold SI values
under plain names.  Subclass :class:`SIModel` to get the same behaviour (and ``extra="forbid"``,
NaN/inf rejection) in other sections.

Extending: add a field to :class:`StudyConfig` whose type is an ``SIModel`` defined in the
owning subpackage, e.g. ``wear: WearConfig = Field(default_factory=WearConfig, description=...)``.
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from jointwear.reference import AcceptanceBand, ReferenceData, ReferenceValue
from jointwear.design.settings import DesignSettings
from jointwear.schema import ConfigError, F, SIModel
from jointwear.study_settings import (
    ComputeSettings,
    ReliabilitySettings,
    SensitivitySettings,
)
from jointwear.uncertainty.targets import target_error
from jointwear.uncertainty.variables import (
    ClearanceSpec,
    CorrelationSpec,
    RandomVariableSpec,
    UncertaintySettings,
)
from jointwear.units import fmt_mm
from jointwear.wear.settings import WearSettings

DEFAULT_PRESET = "jin2025_flapping_wing"


Vec2 = tuple[float, float]


# ---------------------------------------------------------------------------------------------
# materials, friction, clearance joints
# ---------------------------------------------------------------------------------------------
class MaterialConfig(SIModel):
    """Elastic and wear properties of one body of a clearance joint."""

    name: str = F("", description="Material name, for reports only.")
    youngs_modulus: float = F(unit="Pa", gt=0, description="Young's modulus E (key e.g. youngs_modulus_GPa).")
    poissons_ratio: float = F(gt=-1.0, lt=0.5, description="Poisson's ratio nu, in (-1, 0.5).")
    hardness: float = F(
        unit="Pa", gt=0,
        description="Hardness H used by Archard's law (key hardness_HB: Brinell number x 9.807e6 Pa; paper-notes).",
    )
    wear_coefficient: float = F(
        ge=0, description="Dimensionless Archard wear coefficient k (paper Eq. 29; paper-notes reading of Table 2).",
    )


class FrictionConfig(SIModel):
    """Modified Coulomb friction of Ambrosio (2003) in the continuous cubic-blend form (docs/dynamics.md)."""

    law: Literal["ambrosio", "none"] = F("ambrosio", description="'ambrosio' (modified Coulomb) or 'none' (frictionless).")
    mu_d: float = F(0.1, ge=0, description="Dynamic (sliding) friction coefficient; paper gives none, paper-notes baseline 0.1.")
    mu_s: float = F(0.15, ge=0, description="Static friction coefficient; paper-notes baseline 0.15.")
    v_s: float = F(1e-4, unit="m/s", gt=0, description="Static-friction critical slip speed; paper-notes baseline 1e-4 m/s.")
    v_d: float = F(1e-3, unit="m/s", gt=0, description="Speed above which friction is purely dynamic; paper-notes baseline 1e-3 m/s.")

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
    bearing_radius: float = F(unit="m", gt=0, description="Inner radius R_i of the bearing (paper Table 2: 1.002 mm).")
    journal_radius: float = F(unit="m", gt=0, description="Radius R_j of the journal; must be < bearing_radius.")
    bearing_outer_radius: float | None = F(
        None, unit="m", gt=0,
        description="Outer radius of the bearing (Table 2: 1.5 mm); the wear allowance 0.01 D uses its diameter.",
    )
    width: float = F(unit="m", gt=0, description="Axial width L of the contact (Table 4: 1 mm).")
    bearing_material: MaterialConfig = F(description="Bearing material.")
    journal_material: MaterialConfig = F(description="Journal material.")
    contact_law: Literal["lankarani_nikravesh", "flores", "hunt_crossley"] = F(
        "lankarani_nikravesh",
        description="Normal force law: 'lankarani_nikravesh' (paper Eq. 16-18, D = 3K(1-cr^2)d^n/(4 v0)), "
        "'flores' (Flores et al. 2011, D = 8K(1-cr)d^n/(5 cr v0)), 'hunt_crossley' (D = 3K(1-cr)d^n/(2 v0)).",
    )
    exponent: float = F(1.5, gt=0, description="Force exponent n of K d^n; 1.5 (Hertz, paper Eq. 16).")
    restitution: float = F(0.9, gt=0, le=1, description="Coefficient of restitution cr (Table 4: 0.9).")
    v0_min: float = F(
        1e-4, unit="m/s", gt=0,
        description="Floor on the impact speed v0 in the damping term; paper silent, paper-notes suggests 1e-4 m/s.",
    )
    friction: FrictionConfig = F(default_factory=FrictionConfig, description="Friction law parameters.")

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


# ---------------------------------------------------------------------------------------------
# mechanisms
# ---------------------------------------------------------------------------------------------
class LinkConfig(SIModel):
    """A rigid link between two joints (or a slider block)."""

    length: float = F(0.0, unit="m", ge=0, description="Distance between the link's two joints (0 for a slider block).")
    mass: float = F(unit="kg", gt=0, description="Mass.")
    inertia: float = F(unit="kg m^2", gt=0, description="Moment of inertia about the centre of mass.")
    com_offset: float | None = F(
        None, unit="m",
        description="Distance of the centre of mass from the link's first joint along the link "
        "(crank: from O; rod: from A; rocker: from C). Default: length / 2.",
    )


def _com(link: LinkConfig) -> float:
    return link.length / 2 if link.com_offset is None else link.com_offset


def _nonzero_crank_speed(v: float) -> float:
    if v == 0.0:
        raise ValueError("crank_speed must not be 0 (the crank turns once per cycle)")
    return v


def _positive_length(link: LinkConfig, where: str) -> None:
    if not link.length > 0:
        raise ValueError(f"{where}.length must be > 0 (got {fmt_mm(link.length)})")


class FourBarConfig(SIModel):
    """Crank-rocker four-bar O-A-B-C: crank OA driven at constant speed, rod AB, rocker CB.

    Body frames: origin at the centre of mass, x axis along the link from its first joint to the
    second (crank O->A, rod A->B, rocker C->B).
    """

    type: Literal["four_bar"] = "four_bar"
    crank_pivot: Vec2 = F((0.0, 0.0), unit="m", description="Ground pivot O of the crank (Fig. 14: origin).")
    rocker_pivot: Vec2 = F(unit="m", description="Ground pivot C of the rocker (Table 4: (11.5, 38) mm).")
    crank: LinkConfig = F(description="Crank OA (Table 3). Its mass does not matter while its speed is imposed.")
    rod: LinkConfig = F(description="Connecting rod AB (Table 3).")
    rocker: LinkConfig = F(
        description="Rocker CB: length = l_BC (Table 4); com_offset from C (paper-notes baseline: uniform 27 mm bar, "
        "C at one end, com 13.5 mm from C)."
    )
    crank_speed: float = F(
        unit="rad/s", description="Constant crank speed, positive counter-clockwise (480 rpm, Section 6.1.1)."
    )
    crank_angle0: float = F(0.0, unit="rad", description="Crank angle at t = 0, from +x, CCW.")
    assembly_branch: Literal[1, -1] = F(
        1,
        description="+1: joint B lies to the left of the directed line from crank pin A to rocker pivot C "
        "((C-A) x (B-A) > 0); -1: to the right. The paper does not fix it (paper-notes).",
    )
    gravity: Vec2 = F(
        (0.0, -9.80665), unit="m/s^2", description="Gravity vector; paper silent, paper-notes baseline (0, -g)."
    )
    rocker_torque: float = F(
        0.0, unit="N m", description="Constant external torque on the rocker (CCW positive); paper gives no load."
    )
    rod_force: Vec2 = F((0.0, 0.0), unit="N", description="Constant external force on the rod at its centre of mass.")

    _nonzero_speed = field_validator("crank_speed")(classmethod(lambda cls, v: _nonzero_crank_speed(v)))

    @model_validator(mode="after")
    def _closure(self) -> FourBarConfig:
        for name in ("crank", "rod", "rocker"):
            _positive_length(getattr(self, name), name)
        l1, l2, l3 = self.crank.length, self.rod.length, self.rocker.length
        d = math.hypot(self.rocker_pivot[0] - self.crank_pivot[0], self.rocker_pivot[1] - self.crank_pivot[1])
        lo, hi = d - l1, d + l1  # range of |AC| over a full crank turn
        need_lo, need_hi = abs(l2 - l3), l2 + l3
        if not (lo > need_lo and hi < need_hi and d > l1):
            raise ValueError(
                f"links rod ({fmt_mm(l2)}) and rocker ({fmt_mm(l3)}) cannot close the loop for every crank angle: "
                f"the distance from crank pin A to rocker pivot C ranges over [{fmt_mm(max(lo, 0))}, {fmt_mm(hi)}] "
                f"(crank {fmt_mm(l1)}, pivots {fmt_mm(d)} apart) but must stay strictly inside "
                f"[{fmt_mm(need_lo)}, {fmt_mm(need_hi)}]"
            )
        return self


class SliderCrankConfig(SIModel):
    """Slider-crank O-A-B: crank OA driven at constant speed, rod AB, slider at B on a straight guide.

    Body frames: origin at the centre of mass, x along O->A (crank), A->B (rod), the guide (slider).
    """

    type: Literal["slider_crank"] = "slider_crank"
    crank_pivot: Vec2 = F((0.0, 0.0), unit="m", description="Ground pivot O of the crank.")
    crank: LinkConfig = F(description="Crank OA.")
    rod: LinkConfig = F(description="Connecting rod AB.")
    slider: LinkConfig = F(description="Slider block (length ignored; its centre of mass is at B).")
    crank_speed: float = F(unit="rad/s", description="Constant crank speed, positive counter-clockwise.")
    crank_angle0: float = F(0.0, unit="rad", description="Crank angle at t = 0, from +x, CCW.")
    offset: float = F(0.0, unit="m", description="Offset of the slider guide line from O, along the guide's normal.")
    guide_angle: float = F(0.0, unit="rad", description="Direction of the slider guide, from +x, CCW.")
    assembly_branch: Literal[1, -1] = F(
        1, description="+1: slider on the positive guide direction side of the crank pin; -1: the other side."
    )
    gravity: Vec2 = F((0.0, 0.0), unit="m/s^2", description="Gravity vector (Flores et al. 2006 benchmark: none).")

    _nonzero_speed = field_validator("crank_speed")(classmethod(lambda cls, v: _nonzero_crank_speed(v)))

    @model_validator(mode="after")
    def _closure(self) -> SliderCrankConfig:
        for name in ("crank", "rod"):
            _positive_length(getattr(self, name), name)
        l1, l2 = self.crank.length, self.rod.length
        if not l2 > l1 + abs(self.offset):
            raise ValueError(
                f"links crank ({fmt_mm(l1)}) and rod ({fmt_mm(l2)}) cannot close the loop for every crank angle: "
                f"the rod must be longer than crank + |offset| = {fmt_mm(l1 + abs(self.offset))}"
            )
        return self



# ---------------------------------------------------------------------------------------------
# general planar linkage
# ---------------------------------------------------------------------------------------------
def _convert_point_tables(data: Any, fields: frozenset[str], table_fields: tuple[str, ...]) -> Any:
    """Unit suffix on a table of named points (``points_mm = {A = [6, 0]}``): convert every value to SI."""
    if not isinstance(data, dict):
        return data
    from jointwear.units import UnitError, split_unit_key, to_si

    out = dict(data)
    for key, value in data.items():
        split = split_unit_key(key, fields)
        if split is None or split[0] not in table_fields or not isinstance(value, dict):
            continue
        name, suffix = split
        if name in data:
            raise ValueError(f"{name} given twice (as '{name}' and '{key}')")
        try:
            out[name] = {k: to_si(v, suffix) for k, v in value.items()}
        except UnitError as exc:
            raise ValueError(f"{key}: {exc}") from None
        del out[key]
    return out


class GeneralBodyConfig(SIModel):
    """A rigid body of a general linkage, drawn in GLOBAL coordinates at the assembly configuration.

    Body-frame coordinates are derived: origin at the centre of mass ``com``, x axis along ``axis``
    (from its first point to its second) or, without ``axis``, along the global x axis of the drawing.
    """

    name: str = F(description="Name of the body (unique; 'ground' is reserved).")
    mass: float = F(unit="kg", gt=0, description="Mass.")
    inertia: float = F(unit="kg m^2", gt=0, description="Moment of inertia about the centre of mass.")
    com: Vec2 = F(unit="m", description="Centre of mass, global coordinates at the assembly configuration (the drawing).")
    points: dict[str, Vec2] = F(
        unit="m",
        description="Named points (joint centres), global coordinates at the assembly configuration, "
        "e.g. points_mm = {A = [6, 0], B = [-0.5, 37.4]}.",
    )
    axis: tuple[str, str] | None = F(
        None,
        description="Two of the body's points defining its x axis (first -> second); sets the frame in which "
        "bearing angles are reported. Default: the global x axis of the drawing.",
    )
    force: Vec2 = F((0.0, 0.0), unit="N", description="Constant external force at the centre of mass.")
    torque: float = F(0.0, unit="N m", description="Constant external torque (CCW positive).")

    @model_validator(mode="before")
    @classmethod
    def _point_units(cls, data: Any) -> Any:
        return _convert_point_tables(data, frozenset(cls.model_fields), ("points",))

    @model_validator(mode="after")
    def _check(self) -> GeneralBodyConfig:
        if self.name == "ground":
            raise ValueError("name: 'ground' is reserved for the fixed frame (use ground_points)")
        if not self.points:
            raise ValueError(f"points: body '{self.name}' has no points")
        for k in self.points:
            if not k or "." in k:
                raise ValueError(f"points: point name {k!r} of body '{self.name}' must be non-empty without '.'")
        if self.axis is not None:
            a, b = self.axis
            for p in (a, b):
                if p not in self.points:
                    raise ValueError(f"axis: '{p}' is not a point of body '{self.name}' "
                                     f"(points: {', '.join(self.points)})")
            pa, pb = self.points[a], self.points[b]
            if math.hypot(pb[0] - pa[0], pb[1] - pa[1]) == 0.0:
                raise ValueError(f"axis: points '{a}' and '{b}' of body '{self.name}' coincide")
        return self


class GeneralJointConfig(SIModel):
    """An ideal joint of a general linkage between two body points (or a body point and a ground point)."""

    name: str = F(description="Name of the joint (unique); clearance joints and drivers refer to it.")
    type: Literal["revolute", "prismatic"] = F("revolute", description="'revolute' (pin) or 'prismatic' (slider).")
    connects: tuple[str, str] = F(
        description="The two points joined, as 'body.point' or 'ground.point', e.g. ['rod.A', 'crank.A']. "
        "Revolute: the points coincide. Prismatic: the second point slides along a line through the first, "
        "fixed in the first body, and the two bodies keep their relative angle."
    )
    direction: Vec2 | None = F(
        None,
        description="Prismatic only: direction of the sliding line in global coordinates at the assembly "
        "configuration (e.g. [1, 0]); it moves with the first body.",
    )

    @model_validator(mode="after")
    def _check(self) -> GeneralJointConfig:
        for ref in self.connects:
            if ref.count(".") != 1 or not all(ref.split(".")):
                raise ValueError(f"connects: {ref!r} must be 'body.point' (or 'ground.point')")
        bi, bj = (r.split(".")[0] for r in self.connects)
        if bi == bj:
            raise ValueError(f"connects: joint '{self.name}' joins body '{bi}' to itself")
        if self.type == "prismatic":
            if self.direction is None:
                raise ValueError(f"direction: prismatic joint '{self.name}' needs a guide direction")
            if math.hypot(*self.direction) == 0.0:
                raise ValueError(f"direction: guide direction of joint '{self.name}' is zero")
        elif self.direction is not None:
            raise ValueError(f"direction: only a prismatic joint has a direction (joint '{self.name}' is revolute)")
        return self


class DriverConfig(SIModel):
    """Constant-speed rotation of a body about a ground revolute joint."""

    joint: str = F(description="Name of the revolute joint between the driven body and the ground.")
    speed: float = F(unit="rad/s", description="Constant speed, CCW positive (key e.g. speed_rpm); must not be 0.")

    @field_validator("speed")
    @classmethod
    def _nonzero(cls, v: float) -> float:
        if v == 0.0:
            raise ValueError("driver speed must not be 0")
        return v


class GeneralMechanismConfig(SIModel):
    """Any planar linkage: bodies drawn in global coordinates, revolute/prismatic joints, constant-speed drivers.

    The drawing (global positions of every body's points and centre of mass) is the assembly configuration at
    t = 0: the mechanism is assembled around it (so the branch is the one drawn) and tracked by continuation over
    one revolution of the first driver, which is the cycle. Checked at load: names, degrees of freedom, assembly
    over the whole cycle (docs/config.md, "General linkages").
    """

    type: Literal["general"] = "general"
    bodies: list[GeneralBodyConfig] = F(description="The moving bodies ([[mechanism.bodies]]).")
    ground_points: dict[str, Vec2] = F(
        default_factory=dict, unit="m",
        description="Named fixed points (pivots, slider guide points), e.g. ground_points_mm = {O = [0, 0]}.",
    )
    joints: list[GeneralJointConfig] = F(description="Ideal joints ([[mechanism.joints]]); clearance joints name one of them.")
    drivers: list[DriverConfig] = F(
        description="Constant-speed drivers ([[mechanism.drivers]]); the cycle is one revolution of the first. "
        "Further drivers must turn an integer number of times per cycle."
    )
    gravity: Vec2 = F((0.0, -9.80665), unit="m/s^2", description="Gravity vector; default (0, -g) as in the four_bar.")
    closure_tolerance: float = F(
        0.05, gt=0,
        description="Largest gap between the two drawn points of a revolute joint, as a fraction of the median "
        "link size; smaller gaps are closed by the assembly (project choice).",
    )
    assembly_steps: int = F(
        360, ge=12, description="Driver positions per cycle at which the assembly is checked and tabulated (1 deg).",
    )

    @model_validator(mode="before")
    @classmethod
    def _point_units(cls, data: Any) -> Any:
        return _convert_point_tables(data, frozenset(cls.model_fields), ("ground_points",))

    @property
    def crank_speed(self) -> float:
        """Speed of the first driver (rad/s): the cycle is one of its revolutions."""
        return self.drivers[0].speed

    @property
    def crank_angle0(self) -> float:
        return 0.0

    def revolute_joint_bodies(self) -> dict[str, tuple[str, str]]:
        """Revolute joints that can carry clearance (not driver joints): name -> (body_i, body_j)."""
        driven = {d.joint for d in self.drivers}
        return {j.name: tuple(r.split(".")[0] for r in j.connects) for j in self.joints
                if j.type == "revolute" and j.name not in driven}

    @model_validator(mode="after")
    def _topology(self) -> GeneralMechanismConfig:
        names = [b.name for b in self.bodies]
        if not names:
            raise ValueError("bodies: at least one body is needed")
        for i, n in enumerate(names):
            if n in names[:i]:
                raise ValueError(f"bodies[{i}].name: duplicate body name '{n}'")
        for k in self.ground_points:
            if not k or "." in k:
                raise ValueError(f"ground_points: point name {k!r} must be non-empty without '.'")
        bodies = {b.name: b for b in self.bodies}
        jnames = [j.name for j in self.joints]
        used: set[str] = set()
        for i, j in enumerate(self.joints):
            if j.name in jnames[:i]:
                raise ValueError(f"joints[{i}].name: duplicate joint name '{j.name}'")
            for ref in j.connects:
                b, p = ref.split(".")
                if b == "ground":
                    if p not in self.ground_points:
                        raise ValueError(f"joints[{i}].connects: '{ref}': no ground point '{p}' "
                                         f"(ground_points: {', '.join(self.ground_points) or 'none'})")
                elif b not in bodies:
                    raise ValueError(f"joints[{i}].connects: '{ref}': unknown body '{b}' (bodies: {', '.join(names)})")
                elif p not in bodies[b].points:
                    raise ValueError(f"joints[{i}].connects: '{ref}': body '{b}' has no point '{p}' "
                                     f"(points: {', '.join(bodies[b].points)})")
                used.add(b)
        for i, n in enumerate(names):
            if n not in used:
                raise ValueError(f"bodies[{i}]: body '{n}' has no joints")
        if not self.drivers:
            raise ValueError("drivers: at least one driver is needed (the cycle is one revolution of the first)")
        jmap = {j.name: j for j in self.joints}
        driven: set[str] = set()
        for i, d in enumerate(self.drivers):
            j = jmap.get(d.joint)
            if j is None:
                raise ValueError(f"drivers[{i}].joint: unknown joint '{d.joint}' (joints: {', '.join(jnames)})")
            ends = [r.split(".")[0] for r in j.connects]
            if j.type != "revolute" or "ground" not in ends:
                raise ValueError(f"drivers[{i}].joint: '{d.joint}' must be a revolute joint between a body and the ground")
            body = ends[0] if ends[1] == "ground" else ends[1]
            if body in driven:
                raise ValueError(f"drivers[{i}].joint: body '{body}' is driven twice")
            driven.add(body)
            ratio = d.speed / self.drivers[0].speed
            if abs(ratio - round(ratio)) > 1e-9:
                raise ValueError(f"drivers[{i}].speed: must be an integer multiple of the first driver's speed "
                                 f"(ratio {ratio:.6g}): the cycle is one revolution of the first driver")
        n_free = len(names) - len(driven)
        n_rows = sum(2 for j in self.joints if j.name not in {d.joint for d in self.drivers})
        dof = 3 * n_free - n_rows
        if dof < 0:
            raise ValueError(f"joints: the mechanism is over-constrained: {dof} degrees of freedom after the drivers "
                             f"(3 x {n_free} free bodies - 2 x {n_rows // 2} joints); remove joints or add bodies")
        from jointwear.mechanism.model import (
            check_general_assembly,  # lazy: model imports this module
        )

        check_general_assembly(self)
        return self


MechanismConfig = Annotated[FourBarConfig | SliderCrankConfig | GeneralMechanismConfig, Field(discriminator="type")]

_MECH_JOINTS = {
    "four_bar": {"O": ("ground", "crank"), "A": ("crank", "rod"), "B": ("rod", "rocker"), "C": ("ground", "rocker")},
    "slider_crank": {"O": ("ground", "crank"), "A": ("crank", "rod"), "B": ("rod", "slider")},
}


# ---------------------------------------------------------------------------------------------
# simulation
# ---------------------------------------------------------------------------------------------
class SimulationConfig(SIModel):
    """Integrator and recording settings (Dormand-Prince 5(4) with error control)."""

    rtol: float = F(1e-6, gt=0, lt=1, description="Relative tolerance of the step-size control (project choice).")
    atol: float = F(
        1e-9, unit="m", gt=0,
        description="Absolute tolerance on positions (m); angles use atol / length_ref, velocities atol * "
        "omega_ref (docs/dynamics.md). Project choice, checked against tighter runs.",
    )
    max_step: float | None = F(
        None, unit="s", gt=0, description="Largest step; default period / 200 (so no phase of the cycle is skipped)."
    )
    clearance_step_fraction: float = F(
        0.25, gt=0, le=1,
        description="A step may move the journal relative to the bearing by at most this fraction of the clearance "
        "(impact-capture rule; project choice).",
    )
    baumgarte_alpha: float = F(
        100.0, unit="1/s", ge=0, description="Baumgarte alpha (paper Eq. 6, value not given; project choice)."
    )
    baumgarte_beta: float = F(
        100.0, unit="1/s", ge=0, description="Baumgarte beta (paper Eq. 6, value not given; project choice)."
    )
    settle_cycles: int = F(
        3, ge=0, description="Crank cycles simulated and discarded before recording (transient from the centred start)."
    )
    cycles: int = F(2, ge=1, description="Crank cycles recorded by `jointwear simulate` unless --cycles is given.")
    max_steps: int = F(50_000_000, ge=1000, description="Safety limit on accepted+rejected steps per call.")
    method: Literal["dopri5", "radau5"] = F(
        "dopri5",
        description="Integrator: 'dopri5' (explicit Dormand-Prince 5(4), the default, validated by every test and "
        "convergence study) or 'radau5' (implicit Radau IIA order 5, experimental: damps the contact ringing, so at "
        "rtol 1e-5 it takes 2,600 steps per cycle and matches dopri5 at 1e-6 within 1 %, but is 2-3x slower per "
        "cycle so far; docs/dynamics.md).",
    )


# ---------------------------------------------------------------------------------------------
# study
# ---------------------------------------------------------------------------------------------
class StudyConfig(SIModel):
    """A whole study. Later stages add their sections here (wear, uncertainty, reliability, sensitivity, compute)."""

    name: str = F("study", description="Name of the study / preset.")
    citation: str = F("", description="Source of the data (presets are cited data).")
    description: str = F("", description="Free text.")
    mechanism: MechanismConfig = F(
        description="The planar mechanism (type = 'four_bar', 'slider_crank' or 'general').")
    clearance_joints: list[ClearanceJointConfig] = F(
        default_factory=list, description="Revolute joints with clearance (any number)."
    )
    simulation: SimulationConfig = F(default_factory=SimulationConfig, description="Integrator settings.")
    wear: WearSettings = F(default_factory=WearSettings, description="Archard wear and the cycle-block history.")
    uncertainty: UncertaintySettings | None = F(
        None, description="Random inputs (paper Tables 5-6); needed by the reliability and sensitivity stages.")
    reliability: ReliabilitySettings = F(default_factory=ReliabilitySettings, description="Wear reliability (Section 5).")
    sensitivity: SensitivitySettings = F(default_factory=SensitivitySettings, description="Sensitivity (Section 6.2.3).")
    compute: ComputeSettings = F(default_factory=ComputeSettings, description="Where model calls run.")
    reference: ReferenceData | None = F(
        None, description="Cited results of the publication the study reproduces; the report compares with them "
        "only when given (jointwear.reference).")
    design: DesignSettings | None = F(None, description="Uncertainty control: controls, costs and targets (docs/design.md).")

    @model_validator(mode="after")
    def _targets_exist(self) -> StudyConfig:
        if self.uncertainty is None:
            return self
        data = self.model_dump()
        for i, spec in enumerate(self.uncertainty.all_specs()):
            problem = target_error(data, spec.target)
            if problem:
                where = "uncertainty.clearance" if spec.name == "c" else f"uncertainty.variables[{spec.name}]"
                raise ValueError(f"{where}.target: {problem}")
        return self

    @model_validator(mode="after")
    def _joints_exist(self) -> StudyConfig:
        if self.mechanism.type == "general":
            joints, excluded = self.mechanism.revolute_joint_bodies(), set()  # driver joints already left out
        else:
            joints, excluded = _MECH_JOINTS[self.mechanism.type], {"O"}
        seen = set()
        for i, cj in enumerate(self.clearance_joints):
            where = f"clearance_joints[{i}]"
            if cj.joint not in joints or cj.joint in excluded:
                allowed = ", ".join(k for k in joints if k not in excluded)
                raise ValueError(f"{where}.joint: '{cj.joint}' is not a joint that can carry clearance (allowed: {allowed})")
            if cj.joint in seen:
                raise ValueError(f"{where}.joint: joint '{cj.joint}' given twice")
            seen.add(cj.joint)
            pair = set(joints[cj.joint])
            if {cj.bearing_body, cj.journal_body} != pair:
                raise ValueError(
                    f"{where}: bearing_body/journal_body must be the bodies of joint {cj.joint}: "
                    f"{' and '.join(joints[cj.joint])}"
                )
        return self


# ---------------------------------------------------------------------------------------------
# loading
# ---------------------------------------------------------------------------------------------
def _loc(loc: tuple[Any, ...]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in ("four_bar", "slider_crank", "general") and out == "mechanism":
            continue  # discriminated-union tag
        else:
            out += ("." if out else "") + str(part)
    return out or "config"


def validation_problems(exc: ValidationError) -> list[str]:
    """Every problem of a pydantic validation error as 'field.path: message (got value)'.

    An unknown key usually also causes a "missing" error for the key it misspells: unknown keys come first.
    """
    errors = sorted(exc.errors(), key=lambda e: e.get("type") != "extra_forbidden")
    out = []
    for err in errors:
        where = _loc(tuple(err.get("loc", ())))
        msg = err.get("msg", "invalid").removeprefix("Value error, ")
        inp = err.get("input")
        shown = ""
        if err.get("type") not in ("missing", "extra_forbidden") and isinstance(inp, (int, float, str)) \
                and not isinstance(inp, bool):
            shown = f" (got {inp!r}{', SI units' if isinstance(inp, float) else ''})"
        if err.get("type") == "extra_forbidden":
            msg = "unknown key (not a setting of this section)"
        text = f"{where}: {msg}{shown}".replace("\n", " ")
        if text not in out:
            out.append(text)
    return out


def available_presets() -> list[str]:
    """Names of the built-in presets."""
    files = resources.files("jointwear.presets")
    return sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".toml"))


def config_from_dict(data: dict[str, Any], source: str = "config") -> StudyConfig:
    """Validate a dict (as parsed from TOML) into a StudyConfig, raising ConfigError."""
    try:
        return StudyConfig.model_validate(data)
    except ValidationError as exc:
        raise ConfigError.from_problems(validation_problems(exc), source) from None


def _parse_toml(text: str, source: str) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{source}: malformed TOML: {exc}") from None


def _read_source(source: str | Path) -> tuple[dict[str, Any], str, Path | None]:
    """The parsed TOML of a preset name or a file, its name for messages and its folder (None for a preset)."""
    text_source = str(source)
    path = Path(text_source)
    is_pathlike = isinstance(source, Path) or text_source.endswith(".toml") or "/" in text_source or "\\" in text_source
    if not is_pathlike and not path.exists():
        names = available_presets()
        if text_source not in names:
            raise ConfigError(
                f"config: unknown preset '{text_source}' and no such file (available presets: {', '.join(names)})"
            )
        text = (resources.files("jointwear.presets") / f"{text_source}.toml").read_text(encoding="utf-8")
        return _parse_toml(text, f"preset {text_source}"), f"preset {text_source}", None
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ConfigError(f"config: cannot read file '{path}': {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"config: file '{path}' is not UTF-8 text (expected TOML)") from None
    return _parse_toml(text, str(path)), str(path), path.parent


def merge_tables(base: dict[str, Any], override: dict[str, Any]) -> dict[str, Any]:
    """``override`` laid over ``base``: tables merge key by key, anything else (numbers, strings, arrays and
    arrays of tables) replaces the base's value."""
    out = dict(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge_tables(out[key], value)
        else:
            out[key] = value
    return out


def _resolve(source: str | Path, chain: tuple[str, ...] = ()) -> tuple[dict[str, Any], str]:
    """The TOML data of ``source`` with its ``extends`` chain resolved (a preset name, or a path relative to the
    extending file)."""
    data, name, folder = _read_source(source)
    if name in chain:
        raise ConfigError(f"{name}: extends: circular ({' -> '.join(chain + (name,))})")
    base = data.pop("extends", None)
    if base is None:
        return data, name
    if not isinstance(base, str):
        raise ConfigError(f"{name}: extends: expected a preset name or a TOML path (got {base!r})")
    if folder is not None and (base.endswith(".toml") or "/" in base) and not Path(base).is_absolute():
        base = str(folder / base)
    base_data, _ = _resolve(base, chain + (name,))
    return merge_tables(base_data, data), name


def load_config(source: str | Path | None = None) -> StudyConfig:
    """Load and validate a study config.

    A file may start from another config with ``extends = "<preset name or TOML path>"``: its tables are laid
    over the base's key by key (arrays, including arrays of tables, replace the base's).

    Parameters
    ----------
    source : str, Path, StudyConfig or None
        A TOML file, a preset name (:func:`available_presets`), a config already validated (returned as is),
        or None for the default preset ``jin2025_flapping_wing``.

    Returns
    -------
    StudyConfig
        The whole config in SI units.

    Raises
    ------
    jointwear.schema.ConfigError
        The file cannot be read or is not valid; the message names every field at fault.
    """
    if source is None:
        source = DEFAULT_PRESET
    if isinstance(source, StudyConfig):
        return source
    data, name = _resolve(source)
    return config_from_dict(data, name)


# ---------------------------------------------------------------------------------------------
# reference documentation
# ---------------------------------------------------------------------------------------------
def config_reference_markdown() -> str:
    """Markdown reference of every config section and field, generated from the pydantic models."""
    lines = [
        "# Configuration reference",
        "",
        "Generated by `jointwear.config.config_reference_markdown()`. Values are SI; a TOML key may carry a",
        "unit suffix (`length_mm`, `crank_speed_rpm`, `youngs_modulus_GPa`, `hardness_HB`, `crank_angle0_deg`, ...)",
        "that is converted to SI on load (table in `jointwear/units.py`). Unknown keys are errors.",
        "",
    ]
    sections: list[tuple[str, type[BaseModel]]] = [
        ("(top level)", StudyConfig),
        ("mechanism (type = \"four_bar\")", FourBarConfig),
        ("mechanism (type = \"slider_crank\")", SliderCrankConfig),
        ("mechanism.crank / rod / rocker / slider", LinkConfig),
        ("mechanism (type = \"general\")", GeneralMechanismConfig),
        ("[[mechanism.bodies]] (general)", GeneralBodyConfig),
        ("[[mechanism.joints]] (general)", GeneralJointConfig),
        ("[[mechanism.drivers]] (general)", DriverConfig),
        ("[[clearance_joints]]", ClearanceJointConfig),
        ("clearance_joints.bearing_material / journal_material", MaterialConfig),
        ("clearance_joints.friction", FrictionConfig),
        ("simulation", SimulationConfig),
        ("wear", WearSettings),
        ("uncertainty", UncertaintySettings),
        ("uncertainty.clearance", ClearanceSpec),
        ("[[uncertainty.variables]]", RandomVariableSpec),
        ("uncertainty.correlation", CorrelationSpec),
        ("reliability", ReliabilitySettings),
        ("sensitivity", SensitivitySettings),
        ("compute", ComputeSettings),
        ("reference", ReferenceData),
        ("[[reference.values]]", ReferenceValue),
        ("reference.values.band", AcceptanceBand),
        ("design", DesignSettings),
    ]
    for title, model in sections:
        lines += [f"## {title}", "", (model.__doc__ or "").strip().splitlines()[0], "",
                  "| key | unit (SI) | default | description |", "|---|---|---|---|"]
        for fname, finfo in model.model_fields.items():
            extra = finfo.json_schema_extra if isinstance(finfo.json_schema_extra, dict) else {}
            unit = extra.get("unit", "") if extra else ""
            if finfo.is_required():
                default = "required"
            elif finfo.default_factory is not None:
                default = "(section)"
            else:
                default = f"`{finfo.default!r}`"
            desc = (finfo.description or "").replace("|", "\\|")
            lines.append(f"| `{fname}` | {unit} | {default} | {desc} |")
        lines.append("")
    lines += ["## Presets", ""]
    for name in available_presets():
        cfg = load_config(name)
        lines.append(f"- `{name}`: {cfg.description} Source: {cfg.citation}")
    lines.append("")
    return "\n".join(lines)
