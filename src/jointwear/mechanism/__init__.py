"""jointwear.mechanism: planar multibody model, assembly, kinematics and forward dynamics.

    from jointwear.mechanism import build_model, simulate
    model = build_model(config)
    res = simulate(model, n_cycles=2)
"""

from jointwear.mechanism.model import (
    GROUND,
    Body,
    ClearanceJoint,
    Driver,
    IntegratorSettings,
    Joint,
    Material,
    MechanismModel,
    build_model,
)
from jointwear.mechanism.simulate import (
    ContactTrace,
    SimulationError,
    SimulationResult,
    SimulationState,
    initial_state,
    simulate,
)

__all__ = [
    "GROUND",
    "Body",
    "ClearanceJoint",
    "ContactTrace",
    "Driver",
    "IntegratorSettings",
    "Joint",
    "Material",
    "MechanismModel",
    "SimulationError",
    "SimulationResult",
    "SimulationState",
    "build_model",
    "initial_state",
    "simulate",
]
