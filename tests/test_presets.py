"""Every shipped preset is cited data that can run the whole study: random variables, a limit state whose R(N)
curve, histogram levels and sensitivity level agree, and a reference only where a publication is reproduced."""

from __future__ import annotations

import numpy as np
import pytest

from jointwear.config import available_presets, load_config

PRESETS = available_presets()


def test_the_three_presets_ship():
    assert {"jin2025_flapping_wing", "flores_slider_crank", "watt_six_bar_two_clearances"} <= set(PRESETS)


@pytest.mark.parametrize("name", PRESETS)
def test_every_preset_passes_its_own_check(name, tmp_path):
    # every stage the preset can run, the design included (a variant that drops a variable must drop its design too)
    from jointwear import Study

    Study(name, out=tmp_path, echo=lambda line: None).check()


@pytest.mark.parametrize("name", PRESETS)
def test_preset_can_run_a_study(name):
    cfg = load_config(name)
    assert cfg.citation and cfg.description
    unc = cfg.uncertainty
    assert unc is not None and unc.clearance is not None, "every preset samples the clearance of its fit"
    assert unc.clearance.source == "iso286"
    groups = {s.group for s in unc.all_specs()}
    assert "tolerance" in groups and groups & {"bearing_material", "journal_material"}
    rel = cfg.reliability
    curve = rel.curve_cycles()
    # histogram levels inside the curve (a level outside would extend every model call beyond cycles_stop)
    assert min(curve) == rel.cycles_start and max(curve) <= rel.cycles_stop
    assert cfg.sensitivity.cycles in curve


@pytest.mark.parametrize("name", PRESETS)
def test_reference_only_where_a_publication_is_reproduced(name):
    cfg = load_config(name)
    if name.startswith("jin2025"):
        assert cfg.reference is not None and all(v.source for v in cfg.reference.values)
    else:
        assert cfg.reference is None


def test_slider_crank_reaches_its_allowance_inside_the_curve():
    """The nominal wear crosses the allowance between the first and last level, so R(N) goes from ~1 to ~0 in
    the curve (a 0.4 s wear history; the margins are 30 % of the nominal life, about twice the 14 % spread of
    the wear that the 10 % scatter of k and H gives)."""
    from jointwear.mechanism import build_model
    from jointwear.wear import wear_history

    cfg = load_config("flores_slider_crank")
    res = wear_history(build_model(cfg), cfg.wear, cfg.reliability.cycles_stop)
    hist = res.joints[0]
    life = float(np.interp(cfg.reliability.allowance, hist.history_max_bearing, hist.history_cycles))
    assert 1.3 * cfg.reliability.cycles_start < life < cfg.reliability.cycles_stop / 1.3


@pytest.mark.parametrize("name", available_presets())
def test_a_hardness_shown_in_hb_uses_the_packages_own_factor(name):
    """The presets' scale 1.0196999e-7 was not 1 / PA_PER_HB: a 350 HB mean was shown as 350.0069 HB."""
    from jointwear.units import PA_PER_HB

    unc = load_config(name).uncertainty
    for spec in [] if unc is None else unc.all_specs():
        if spec.unit == "HB":
            assert spec.scale * PA_PER_HB == pytest.approx(1.0, rel=1e-7), spec.name  # the scale's 8 digits
