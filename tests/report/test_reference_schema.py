"""The [reference] section: cited values with units checked against their quantity, bands of one kind each."""

from __future__ import annotations

import pytest

from jointwear.config import config_from_dict, load_config
from jointwear.schema import ConfigError


def _with_reference(values: list[dict], **ref) -> dict:
    data = load_config("flores_slider_crank").model_dump()
    data["reference"] = {"citation": "A. Author, Journal 2030", "values": values, **ref}
    return data


def _error(values: list[dict], **ref) -> str:
    with pytest.raises(ConfigError) as exc:
        config_from_dict(_with_reference(values, **ref))
    return str(exc.value)


def test_values_in_si_and_back_in_report_units():
    cfg = config_from_dict(_with_reference([
        {"quantity": "nominal_max_wear", "cycles": 40_000, "value_um": 100.0, "source": "Table 1",
         "band": {"lower_mm": 0.08, "upper_mm": 0.12, "justification": "j"}},
        {"quantity": "nominal_max_wear_angle", "value_deg": 90.0, "source": "Fig. 2"},
        {"quantity": "life_hours", "target_reliability": 0.9, "value_h": 0.5, "source": "Sec. 3"},
        {"quantity": "reliability", "cycles": 40_000, "value": 0.5, "source": "Fig. 3"}]))
    wear, angle, hours, rel = cfg.reference.values
    assert wear.value == pytest.approx(1e-4) and wear.band.lower == pytest.approx(8e-5)  # SI inside
    assert angle.value == pytest.approx(1.5707963, rel=1e-7) and hours.value == pytest.approx(1800.0)
    shown = [v.report_dict() for v in cfg.reference.values]
    assert [(d["value"], d["unit"]) for d in shown] == [(0.1, "mm"), (90.0, "deg"), (0.5, "h"), (0.5, "")]
    assert shown[0]["band"] == {"kind": "interval", "absolute": None, "relative": None, "lower": 0.08,
                                "upper": 0.12, "justification": "j"}
    assert cfg.reference.series("reliability") == {40_000: 0.5} and cfg.reference.life(0.9) is None
    assert cfg.reference.label == "reference"  # default label


@pytest.mark.parametrize("value, message", [
    ({"quantity": "nominal_max_wear", "cycles": 1, "value_deg": 1.0, "source": "s"}, "value_deg: the quantity is a length"),
    ({"quantity": "reliability", "cycles": 1, "value_mm": 1.0, "source": "s"}, "the quantity is a plain number"),
    ({"quantity": "reliability", "value": 0.5, "source": "s"}, "reliability needs `cycles`"),
    ({"quantity": "life_cycles", "value": 5.0, "source": "s"}, "life_cycles needs `target_reliability`"),
    ({"quantity": "reliability", "cycles": 1, "value": 0.5}, "source"),
    ({"quantity": "reliability", "cycles": 1, "value": 0.5, "source": "s",
      "band": {"absolute": 0.1, "relative": 0.1, "justification": "j"}}, "exactly one kind of band"),
    ({"quantity": "reliability", "cycles": 1, "value": 0.5, "source": "s", "band": {"absolute": 0.1}},
     "justification"),
    ({"quantity": "sensitivity_ranking", "group": "tolerance", "source": "s"}, "needs `ranking`"),
    ({"quantity": "sensitivity_ranking", "group": "tolerance", "ranking": ["a"], "source": "s",
      "band": {"relative": 0.1, "justification": "j"}}, "same_order"),
    ({"quantity": "wear_rate", "value": 1.0, "source": "s"}, "quantity"),
])
def test_bad_reference_values_name_the_field(value, message):
    err = _error([value])
    assert err.startswith("config: reference.values[0]") and message in err, err


def test_a_reference_needs_a_citation_and_values():
    assert "reference.citation" in _error([], citation="")
    assert "reference.values" in _error([])
