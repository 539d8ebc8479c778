"""Bad input at the wear API boundary: clear errors naming the field."""


import pytest
from pydantic import ValidationError
from wear_synthetic import FakeModel, fake_simulate

from jointwear.wear import WearSettings, wear_history
from jointwear.wear.settings import check_cycles


@pytest.mark.parametrize("bad", [0, -5, float("nan"), float("inf"), "abc", 2.5, None, True])
def test_cycles_rejected(bad):
    with pytest.raises(ValueError, match="cycles"):
        check_cycles(bad)
    if bad is not None:
        with pytest.raises(ValueError, match="cycles"):
            wear_history(FakeModel(), WearSettings(), bad, simulate=fake_simulate)


@pytest.mark.parametrize("bad", [0, -1, float("nan"), "x"])
def test_settings_cycles_field(bad):
    with pytest.raises(ValidationError, match="cycles"):
        WearSettings(cycles=bad)


@pytest.mark.parametrize("field,value", [("n_grid", 3), ("geometry_mode", "wavy"), ("pressure", "flat"),
                                         ("rate_tolerance", 0), ("half_width_factor", -1), ("record_cycles", 0),
                                         ("bogus", 1)])
def test_settings_fields(field, value):
    with pytest.raises(ValidationError, match=field):
        WearSettings(**{field: value})


def test_block_order():
    with pytest.raises(ValidationError, match="initial_block"):
        WearSettings(initial_block=100, min_block=1000)

