"""Settings of the mechanism (``[mechanism]``: four-bar, slider-crank or any planar linkage) and of its
integrator (``[simulation]``).

The schema checks each section (names, ranges, degrees of freedom, closure of the four-bar and slider-crank loops);
whether a general linkage assembles over a whole cycle is a numerical check made after it
(jointwear.mechanism.assembly.check_assembly, called by build_model and by the study's checks).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Field, field_validator, model_validator

from jointwear.schema import F, SIModel, item_key
from jointwear.units import fmt_mm

MECHANISM_KIND = ("Mechanism kind: 'four_bar' (crank OA, rod AB, rocker CB), 'slider_crank' (crank OA, rod AB, "
                  "slider at B) or 'general' (bodies, joints and drivers as listed); it selects the fields below.")

#: Most crank cycles `jointwear simulate` records (every step is kept: ~20,000 rows a cycle, 1-2 GB for 100 cycles).
MAX_RECORDED_CYCLES = 100
#: Most crank cycles settled before recording (no record, but each costs the integration of a cycle).
MAX_SETTLE_CYCLES = 10_000

Vec2 = tuple[float, float]


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



    @property
    def com(self) -> float:
        """Distance of the centre of mass from the link's first joint (m)."""
        return self.length / 2 if self.com_offset is None else self.com_offset


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

    type: Literal["four_bar"] = Field("four_bar", description=MECHANISM_KIND)
    crank_pivot: Vec2 = F((0.0, 0.0), unit="m", description="Ground pivot O of the crank.")
    rocker_pivot: Vec2 = F(unit="m", description="Ground pivot C of the rocker.")
    crank: LinkConfig = F(description="Crank OA. Its mass does not matter while its speed is imposed.")
    rod: LinkConfig = F(description="Connecting rod AB.")
    rocker: LinkConfig = F(
        description="Rocker CB: length = l_BC; com_offset measured from C."
    )
    crank_speed: float = F(
        unit="rad/s", description="Constant crank speed, positive counter-clockwise."
    )
    crank_angle0: float = F(0.0, unit="rad", description="Crank angle at t = 0, from +x, CCW.")
    assembly_branch: Literal[1, -1] = F(
        1,
        description="+1: joint B lies to the left of the directed line from crank pin A to rocker pivot C "
        "((C-A) x (B-A) > 0); -1: to the right. The paper does not fix it (baseline reading).",
    )
    gravity: Vec2 = F(
        (0.0, -9.80665), unit="m/s^2", description="Gravity vector; paper silent, baseline reading (0, -g)."
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
        links = (l1, l2, l3, d)
        if not (lo > need_lo and hi < need_hi and d > l1):
            raise ValueError(
                f"links rod ({fmt_mm(l2)}) and rocker ({fmt_mm(l3)}) cannot close the loop for every crank angle: "
                f"the distance from crank pin A to rocker pivot C ranges over [{fmt_mm(max(lo, 0))}, {fmt_mm(hi)}] "
                f"(crank {fmt_mm(l1)}, pivots {fmt_mm(d)} apart) but must stay strictly inside "
                f"[{fmt_mm(need_lo)}, {fmt_mm(need_hi)}]: the crank cannot turn a full revolution (Grashof: a crank "
                f"turns fully when it is the shortest link and shortest + longest, here "
                f"{fmt_mm(min(links) + max(links))}, stays below the other two, here "
                f"{fmt_mm(sum(links) - min(links) - max(links))})"
            )
        return self

    def revolute_joint_bodies(self) -> dict[str, tuple[str, str]]:
        """Revolute joints that can carry clearance (not the driven pivot O): name -> (body_i, body_j)."""
        return {"A": ("crank", "rod"), "B": ("rod", "rocker"), "C": ("ground", "rocker")}


class SliderCrankConfig(SIModel):
    """Slider-crank O-A-B: crank OA driven at constant speed, rod AB, slider at B on a straight guide.

    Body frames: origin at the centre of mass, x along O->A (crank), A->B (rod), the guide (slider).
    """

    type: Literal["slider_crank"] = Field("slider_crank", description=MECHANISM_KIND)
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

    def revolute_joint_bodies(self) -> dict[str, tuple[str, str]]:
        """Revolute joints that can carry clearance (not the driven pivot O): name -> (body_i, body_j)."""
        return {"A": ("crank", "rod"), "B": ("rod", "slider")}



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
        description="Two of the body's points defining its x axis (first -> second): the frame of the body's own "
        "angles (a bearing's body_angle_deg in wear_profile.csv). The reported wear angles are directions at the "
        "bearing body's mean pose (docs/wear.md, 'Angle convention') and do not depend on it. Default: the global "
        "x axis of the drawing.",
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
    one revolution of the first driver, which is the cycle. The schema checks names and degrees of freedom; the
    assembly over the whole cycle is checked after it (jointwear.mechanism.check_assembly, when the model is built).
    """

    type: Literal["general"] = Field("general", description=MECHANISM_KIND)
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
                        raise ValueError(f"joints[{item_key(i, jnames)}].connects: '{ref}': no ground point '{p}' "
                                         f"(ground_points: {', '.join(self.ground_points) or 'none'})")
                elif b not in bodies:
                    raise ValueError(f"joints[{item_key(i, jnames)}].connects: '{ref}': unknown body '{b}' "
                                     f"(bodies: {', '.join(names)})")
                elif p not in bodies[b].points:
                    raise ValueError(f"joints[{item_key(i, jnames)}].connects: '{ref}': body '{b}' has no point '{p}' "
                                     f"(points: {', '.join(bodies[b].points)})")
                used.add(b)
        for i, n in enumerate(names):
            if n not in used:
                raise ValueError(f"bodies[{item_key(i, names)}]: body '{n}' has no joints")
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
        dof = self.free_degrees_of_freedom()
        if dof < 0:
            n_free = len(names) - len(driven)
            n_joints = len(self.joints) - len(self.drivers)
            mobility = dof + len(self.drivers)  # each driver prescribes a body (3) in place of a joint (2)
            fix = ("remove joints or add bodies" if len(self.drivers) == 1 or mobility < 1 else
                   f"each of the {len(self.drivers)} drivers takes a degree of freedom, and the linkage has "
                   f"{mobility}: remove {len(self.drivers) - mobility} driver(s), or remove joints or add bodies")
            raise ValueError(f"joints: the mechanism is over-constrained: {dof} degrees of freedom after the drivers "
                             f"(3 x {n_free} free bodies - 2 x {n_joints} joints); {fix}")
        return self

    def free_degrees_of_freedom(self) -> int:
        """Degrees of freedom left after the drivers (Gruebler): 3 per body not driven, less 2 per joint that is not
        a driver's. Above 0, some bodies move only under their loads (a pendulum), or a joint is missing."""
        driver_joints = {d.joint for d in self.drivers}
        jmap = {j.name: j for j in self.joints}
        driven = {end for d in self.drivers if d.joint in jmap
                  for end in (r.split(".")[0] for r in jmap[d.joint].connects) if end != "ground"}
        return 3 * (len(self.bodies) - len(driven)) - 2 * sum(1 for j in self.joints if j.name not in driver_joints)


MechanismConfig = Annotated[FourBarConfig | SliderCrankConfig | GeneralMechanismConfig, Field(discriminator="type")]


class SimulationConfig(SIModel):
    """Integrator and recording settings (Dormand-Prince 5(4) with error control)."""

    rtol: float = F(1e-6, gt=0, lt=1, description="Relative tolerance of the step-size control (project choice).")
    atol: float = F(
        1e-9, unit="m", gt=0,
        description="Absolute tolerance on positions; angles use atol / length_ref, velocities atol * "
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
        3, ge=0, le=MAX_SETTLE_CYCLES,
        description="Crank cycles simulated and discarded before recording (transient from the centred start); at most "
        "10,000 (minutes of integration; a settling transient lasts a few cycles).",
    )
    cycles: int = F(
        2, ge=1, le=MAX_RECORDED_CYCLES,
        description="Crank cycles recorded by `jointwear simulate` unless --cycles is given; at most 100 (every "
        "integration step is kept, about 20,000 per cycle: 100 cycles hold 1-2 GB).")
    max_steps: int = F(50_000_000, ge=1000, description="Safety limit on accepted+rejected steps per call.")
    method: Literal["dopri5", "radau5"] = F(
        "dopri5",
        description="Integrator: 'dopri5' (explicit Dormand-Prince 5(4), the default, validated by every test and "
        "convergence study) or 'radau5' (implicit Radau IIA order 5, experimental: damps the contact ringing, so at "
        "rtol 1e-5 it takes 2,600 steps per cycle and matches dopri5 at 1e-6 within 1 %, but is 2-3x slower per "
        "cycle so far; docs/dynamics.md).",
    )
