"""A random variable whose mean the model cannot use (a clearance in mm where um was meant, a hardness without its
unit) passed `check`, then every model call failed and `run` ended in the engine's 49-line traceback; the model's
own reason was only in evaluations.sqlite."""

import numpy as np
import pytest

from jointwear.cli import main_entry
from jointwear.config import load_config, updated
from jointwear.schema import ConfigError
from jointwear.study import Study
from jointwear.study.checks import random_input_problems, random_input_warnings

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


def test_a_clearance_mean_in_mm_is_a_problem_naming_the_variable_and_the_models_reason():
    cfg = updated(load_config(), {"uncertainty.clearance.mean_mm": 12.5})
    (problem,) = random_input_problems(cfg)
    assert problem.startswith("uncertainty.clearance: at its mean, 12.5 mm, the model cannot be built")
    assert "bearing_outer_radius" in problem and "mean_um" in problem


def test_a_hardness_mean_without_its_unit_is_refused_by_the_studys_check(tmp_path):
    cfg = load_config()
    name = next(s.name for s in cfg.uncertainty.all_specs() if s.target.endswith("bearing_material.hardness"))
    index = [v.name for v in cfg.uncertainty.variables].index(name)
    bad = updated(cfg, {"design": None, f"uncertainty.variables[{index}].mean": 90.0,
                        f"uncertainty.variables[{index}].std": 7.0})
    with pytest.raises(ConfigError) as exc:
        Study(bad, out=tmp_path / "o").check()
    assert (f"uncertainty.variables[{name}]: at its mean, {90.0 / 9.807e6:.6g} HB, the model cannot be built"
            in str(exc.value))
    assert "hardness" in str(exc.value) and "mean_HB" in str(exc.value)
    assert not (tmp_path / "o").exists()


def test_a_variable_whose_3_sigma_end_cannot_be_built_is_warned():
    cfg = load_config()
    # a clearance so wide that its +3 sigma end pushes the bore through the bearing's wall, its mean does not
    wide = updated(cfg, {"uncertainty.clearance.nominal_diameter_mm": 100.0,
                         "uncertainty.clearance.hole_grade": "IT11", "uncertainty.clearance.shaft_grade": "IT11",
                         "clearance_joints[0].bearing_outer_radius_mm": 1.05})
    assert random_input_problems(wide) == [] and random_input_warnings(cfg) == []
    (warning,) = random_input_warnings(wide)
    assert warning.startswith("uncertainty.clearance: at its +3 sigma end") and "bearing_outer_radius" in warning


def test_a_learning_whose_first_calls_all_fail_ends_in_one_line_with_the_stored_reason(tmp_path, capsys,
                                                                                       monkeypatch):
    """The engine's 'g returned NaN ... check g' becomes the first call's own reason, exit status 2."""
    from jointwear.study.model_call import WearModelCall

    def cannot_run(self, x):
        return np.full(self.n_outputs, np.nan), "infeasible sample: the journal left its bore"

    monkeypatch.setattr(WearModelCall, "__call__", cannot_run)
    cfg = tmp_path / "small.toml"
    cfg.write_text('extends = "jin2025_flapping_wing"\n[reliability]\nn_initial = 4\nmax_calls = 8\nn_mc = 2000\n',
                   encoding="utf-8")
    code = main_entry(["reliability", str(cfg), "--out", str(tmp_path / "o"), "--workers", "1"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and "Traceback" not in "\n".join(lines)
    assert lines[-1].startswith("error: reliability: every one of the first 4 model calls failed")
    assert "the first call's stored reason: failed: model: infeasible sample: the journal left its bore" in lines[-1]
    assert len(lines) == 1, lines
