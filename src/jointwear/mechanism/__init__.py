"""jointwear.mechanism: planar multibody model, assembly, kinematics and forward dynamics.

    from jointwear.mechanism import build_model, simulate
    model = build_model(config)
    res = simulate(model, n_cycles=2)
"""

from jointwear.mechanism.assembly import AssemblyError, check_assembly
from jointwear.mechanism.builders import build_model
from jointwear.mechanism.initial import initial_state
from jointwear.mechanism.model import (
    GROUND,
    Body,
    ClearanceJoint,
    Driver,
    Joint,
    MechanismModel,
)
from jointwear.mechanism.results import (
    ContactTrace,
    SimulationCancelled,
    SimulationError,
    SimulationResult,
    SimulationState,
    whirl_measure,
    whirl_threshold,
)
from jointwear.mechanism.simulate import simulate

__all__ = [
    "GROUND",
    "AssemblyError",
    "Body",
    "ClearanceJoint",
    "ContactTrace",
    "Driver",
    "Joint",
    "MechanismModel",
    "SimulationCancelled",
    "SimulationError",
    "SimulationResult",
    "SimulationState",
    "build_model",
    "check_assembly",
    "initial_state",
    "simulate",
    "whirl_measure",
    "whirl_threshold",
]
