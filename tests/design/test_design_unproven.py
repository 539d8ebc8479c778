"""A choice its verification neither refutes nor proves ('within_error') is told as not proven, with the cheapest
design on the front that clears R* by its error; a verification stopped on its budget on a scattering model is not
told that a larger budget will settle it."""

import contextlib

import pytest

import jointwear
from jointwear.design.results import DesignResult
from jointwear.study.reliability_results import SurrogateFit

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

# the user's audit (flores_slider_crank, five controls, 162 candidates): the front, and the 80-call verification
FRONT = [({"k_b": "standard", "HB_b": "standard"}, 0.0, 32_769, 0.5598, 0.0231),
         ({"k_b": "screened", "HB_b": "standard"}, 1.0, 33_883, 0.5699, 0.0257),
         ({"k_b": "standard", "HB_b": "hardened"}, 1.5, 40_135, 0.9166, 0.0134),
         ({"k_b": "lowwear", "HB_b": "standard"}, 2.2, 41_947, 0.9509, 0.0113),
         ({"k_b": "lowwear", "HB_b": "hardened"}, 3.7, 49_434, 0.9994, 0.0051)]
SCATTER = SurrogateFit(n_points=80, q2=0.929, rmse_log_life=0.0458, noise_sd_log_life=0.0392,
                       process_sd_log_life=0.3628, relative_nugget=0.0117, nugget_at_bound=False)
NOISE_FREE = SurrogateFit(n_points=80, q2=0.99, rmse_log_life=0.01, noise_sd_log_life=1e-5, process_sd_log_life=0.36,
                          relative_nugget=1e-8, nugget_at_bound=False)


def _audit_result(fit=SCATTER, r=0.8995, err=0.0124):
    rows = [{"choices": c, "cost": cost, "life_at_target_cycles": life, "reliability_at_target_life": rel,
             "reliability_error": e, "outside_design_fraction": 0.004} for c, cost, life, rel, e in FRONT]
    ver = {"reliability_at_target_life": r, "error": err, "model_calls": 80, "confirmed": r + err >= 0.9,
           "verdict": "within_error", "converged": False, "surrogate_fit": fit.to_json()}
    return DesignResult(target_life_cycles=39_618, target_reliability=0.9, chosen=dict(rows[2]), pareto=rows,
                        verification=ver, model_calls=166, wall_seconds=1.0, candidates=rows)


def test_a_choice_within_the_error_of_its_verification_is_told_not_proven_with_the_design_with_margin():
    """The headline read R = 0.9166 +/- 0.0134 as if it cleared 0.9 by its error; its verification (0.8995 +/- 0.0124,
    'within_error') straddled R*, and the front's next point (k_b lowwear, cost 2.2) would clear it, unnamed."""
    res = _audit_result()
    assert res.unproven_sentence() == (
        "not proven: the true model's R(N*) = 0.8995 +- 0.0124 straddles R* = 0.9; the cheapest design with margin is "
        "k_b lowwear, HB_b standard (cost 2.2, R(N*) 0.9509 +- 0.0113 on the surrogate, not verified); "
        "design.require = 'proven' chooses the cheapest design its verification proves")
    met = _audit_result(r=0.95, err=0.01)
    assert met.verdict() == "meets" and met.unproven_sentence() == ""
    res.pareto[3]["reliability_error"] = 0.06  # its lower bound no longer clears R*: the next one does
    assert "is k_b lowwear, HB_b hardened (cost 3.7" in res.unproven_sentence()
    res.pareto = res.pareto[:4]
    assert res.unproven_sentence().endswith("no dearer design on the Pareto front clears R* by its error on the "
                                            "surrogate; design.require = 'proven' chooses the cheapest design its "
                                            "verification proves")


def test_a_verification_stopped_on_its_budget_on_a_scattering_model_is_not_told_more_calls_settle_it():
    """'Raise the budget and run again with --resume to settle it': tripling it (240 calls) left the verdict
    'within_error' (0.9043 +/- 0.0066); its stopping rule never held on a model whose life scatters 4 % per call."""
    sentence = _audit_result().verification_sentence()
    assert "to settle it" not in sentence
    assert "On this model a call's life scatters by about 4 % about what the inputs set" in sentence
    assert sentence.endswith("; the verdict is limited by that scatter: R(N*) lies 0.0005 from R*, and a larger budget "
                             "(--resume) settles it only if the error falls below that distance")
    assert sentence.count("(raise the budget and run again with --resume to settle it)") == 0
    noise_free = _audit_result(fit=NOISE_FREE).verification_sentence()
    assert "(raise the budget and run again with --resume to settle it)" in noise_free and "scatter" not in noise_free


def test_the_report_and_the_console_tell_the_choice_not_proven(tmp_path, monkeypatch):
    from jointwear.design import search
    from jointwear.report.design_section import design_section

    res = _audit_result()
    res.save(tmp_path / "saved", figures=False)
    page = design_section(tmp_path / "saved")
    assert "<strong>The choice is not proven to meet the target.</strong> Not proven: the true model" in page
    assert "the cheapest design with margin is k_b lowwear, HB_b standard (cost 2.2" in page

    lines: list[str] = []
    study = jointwear.Study("jin2025_flapping_wing", out=tmp_path / "study", workers=1, echo=lines.append)

    class _Ctx:
        n_model_calls = 0

    monkeypatch.setattr(study, "_prepare", lambda *a, **k: None)
    monkeypatch.setattr(study, "_session", lambda **k: contextlib.nullcontext(_Ctx()))
    monkeypatch.setattr(study, "_learned", lambda ctx: None)
    monkeypatch.setattr(search, "run_design", lambda *a, **k: _audit_result())
    study.design()
    (head,) = [line for line in lines if line.startswith("design: ") and " model calls" in line]
    assert ("at the target 39,618 cycles, a life of 40,135 cycles at R = 0.9; not proven: the true model's R(N*) = "
            "0.8995 +- 0.0124 straddles R* = 0.9; the cheapest design with margin is k_b lowwear") in head
    # the choice's life with its 95 % interval where the result holds one
    with_interval = _audit_result()
    with_interval.chosen.update(life_at_target_low_cycles=39_692.0, life_at_target_high_cycles=40_539.0)
    monkeypatch.setattr(search, "run_design", lambda *a, **k: with_interval)
    lines.clear()
    study.design()
    (head,) = [line for line in lines if line.startswith("design: ") and " model calls" in line]
    assert "a life of 40,135 (39,692-40,539) cycles at R = 0.9;" in head
