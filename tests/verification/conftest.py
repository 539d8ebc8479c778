import pytest

from jointwear.config import load_config
from jointwear.mechanism import build_model

from .closed_form import RIG, Rig


@pytest.fixture(scope="session")
def rig_config():
    return load_config(str(RIG))


@pytest.fixture(scope="session")
def rig(rig_config):
    return Rig.from_config(rig_config)


@pytest.fixture(scope="session")
def rig_model(rig_config):
    return build_model(rig_config)


def still_config(rig_config, journal_wear_coefficient: float | None = None):
    """The rig with a 1 um crank and no friction: nothing excites the pendulum (the pin's acceleration is 2.5e-6 of
    g, and no friction torque appears at the start), so the contact stays at the load line in the bearing frame
    and one revolution of the pin lays one stationary patch. Archard's law needs the sliding, not the friction."""
    data = rig_config.model_dump(mode="python")
    x = 1e-6
    for body in data["mechanism"]["bodies"]:
        for name in body["points"]:
            if name != "O":
                body["points"][name] = (x, body["points"][name][1])
        body["com"] = (x / 2, 0.0) if body["name"] == "crank" else (x, body["com"][1])
    data["clearance_joints"][0]["friction"]["law"] = "none"
    if journal_wear_coefficient is not None:
        data["clearance_joints"][0]["journal_material"]["wear_coefficient"] = journal_wear_coefficient
    return type(rig_config).model_validate(data)


@pytest.fixture(scope="session")
def still_model(rig_config):
    return build_model(still_config(rig_config))
