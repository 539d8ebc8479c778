"""design.require = 'proven': the choice is the cheapest candidate whose own verification meets the target beyond its
error bound; a verification that straddles R* ('within_error') passes the search to the next point of the Pareto
front, within the verifications' budget; without a proven candidate there is no choice, and the result says why.

The verification is stubbed (its verdict is set per candidate), so the search loop is tested on its own; the analytic
model of design_fixtures keeps the surrogate and the refinement cheap.
"""

import json

import pytest
from design_fixtures import DESIGN, analytic_config, analytic_context

from jointwear.config import load_config, updated
from jointwear.design import DesignResult, run_design
from jointwear.design import search as design_search
from jointwear.design.results import choices_text, verification_verdict
from jointwear.schema import ConfigError
from jointwear.study import run_reliability

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

CALLS = 3  # the stub's true-model calls per verification


@pytest.fixture(scope="module")
def study():
    cfg = analytic_config(dict(DESIGN, n_population=5_000, verification_max_calls=CALLS))
    ctx, _ = analytic_context(cfg)
    return ctx, run_reliability(ctx)


def _stub(straddles):
    """A verification whose R(N*) straddles R* (0.9 +/- 0.01, 'within_error') when ``straddles(choices)``, else
    meets it (0.99 +/- 0.01); its 'true-model calls' are CALLS points of the candidate's population."""
    seen = []

    def verify(ctx, cand, controls, space, target, max_calls, seed, stopping="u"):
        choices = cand.choices(controls)
        seen.append(choices)
        x = space.population(cand)[0][len(seen) * CALLS:(len(seen) + 1) * CALLS]
        ctx.log_life(x)
        r = target["reliability"] if straddles(choices) else 0.99
        verdict = verification_verdict(r, 0.01, target["reliability"])
        return {"reliability_at_target_life": r, "error": 0.01, "model_calls": CALLS, "new_model_calls": CALLS,
                "run_now": CALLS, "confirmed": verdict != "misses", "verdict": verdict, "converged": False}, x

    return verify, seen


def _row(res, choices):
    return next(r for r in res.candidates if r["choices"] == choices)


def test_a_choice_not_proven_passes_to_the_next_point_of_the_front(study, monkeypatch):
    """The audit's choice (R = 0.8995 +/- 0.0124 at 80 calls, 0.9043 +/- 0.0066 at 240) stayed 'the choice' however
    the budget grew; a user who signs off a purchase could not ask for the cheapest design the true model proves."""
    ctx, rel = study
    first = run_design(ctx, rel).chosen["choices"]
    verify, seen = _stub(lambda choices: choices == first)
    monkeypatch.setattr(design_search, "verify", verify)

    default = run_design(ctx, rel)  # today's rule: a verdict 'within_error' stands
    assert seen == [first] and default.chosen["choices"] == first and default.verdict() == "within_error"
    assert default.decision_rule == "not_refuted" and default.unproven == []
    assert default.verification_sentence().startswith("chosen by design.require = 'not_refuted'")

    seen.clear()
    res = run_design(ctx, rel, ctx.config.design.model_copy(update={"require": "proven"}))
    assert seen[0] == first and len(seen) == 2 and res.chosen["choices"] == seen[1] != first
    assert res.verdict() == "meets" and res.no_choice_reason is None
    assert res.decision_rule == "proven" and [r["choices"] for r in res.unproven] == [first]
    assert [r["verdict"] for r in res.verification["rounds"]] == ["within_error", "meets"]
    # the next point of the front: dearer, and living longer at R* than the unproven one beyond the front's resolution
    passed, chosen = _row(res, first), _row(res, seen[1])
    assert chosen["cost"] >= passed["cost"]
    assert chosen["life_at_target_cycles"] > passed["life_at_target_cycles"] * (1 + res.life_resolution)
    assert seen[1] in [r["choices"] for r in res.pareto]
    sentence = res.verification_sentence()
    assert sentence.startswith(f"chosen by design.require = 'proven' (the cheapest up the front that its "
                               f"verification proves) after 1 not proven ({choices_text(first)}, cost")
    # the choice's own study, and every verification's calls (it said 160 calls of the choice's 80-call study)
    assert f"its own reliability study ({CALLS} true-model calls; {2 * CALLS} true-model calls in the 2 " \
           "verifications) gives R(N*) = 0.9900 +/- 0.0100: it meets R* beyond its error" in sentence
    assert res.unproven_sentence() == ""  # proven: nothing to warn of


def test_with_no_proven_candidate_there_is_no_choice_and_design_json_says_why(study, monkeypatch, tmp_path):
    ctx, rel = study
    verify, seen = _stub(lambda choices: True)
    monkeypatch.setattr(design_search, "verify", verify)
    res = run_design(ctx, rel, ctx.config.design.model_copy(update={"require": "proven"}))
    # the default budget: three verifications of verification_max_calls each
    assert len(seen) == 3 and len({choices_text(c) for c in seen}) == 3
    assert res.chosen is None and res.no_choice_reason == "unproven"
    assert [r["choices"] for r in res.unproven] == seen and res.calls["verification"] == 3 * CALLS
    costs = [r["cost"] for r in res.unproven]
    assert costs == sorted(costs)  # walked up the front
    nxt = res.unverified_next
    assert nxt is not None and nxt["choices"] not in seen and nxt["cost"] >= costs[-1]
    sentence = res.no_choice_sentence()
    assert sentence.startswith("no candidate is proven to meet 400,000 cycles at R = 0.9 (design.require = 'proven')")
    assert f"the verification budget ran out before {choices_text(nxt['choices'])}" in sentence
    assert "design.verification_total_max_calls" in sentence and "design.require = 'not_refuted'" in sentence
    res.save(tmp_path, figures=False)
    data = json.loads((tmp_path / "design.json").read_text())
    assert data["no_choice_reason"] == "unproven" and data["decision_rule"] == "proven"
    assert data["nearest"]["choices"] == seen[0] and data["nearest"]["reliability_error"] == 0.01
    back = DesignResult.load(tmp_path)
    assert back.no_choice_sentence() == sentence

    # a larger budget walks further: to the end of the front that reaches R* on the surrogate
    seen.clear()
    wide = run_design(ctx, rel, ctx.config.design.model_copy(update={"require": "proven",
                                                                     "verification_total_max_calls": 1_000}))
    assert len(seen) > 3 and wide.unverified_next is None and wide.no_choice_reason == "unproven"
    assert wide.no_choice_sentence().endswith("no dearer point of the Pareto front reaches the target on the "
                                              "surrogate; or take the cheapest design its verification does not "
                                              "refute, told as not proven, with design.require = 'not_refuted'")


def test_require_proven_without_a_verification_is_refused_naming_the_field():
    cfg = load_config("jin2025_flapping_wing")
    for change, words in (({"design.verify": False}, "verify = false"),
                          ({"design.verification_max_calls": 0}, "verification_max_calls = 0"),
                          ({"design.verification_total_max_calls": 0}, "verification_total_max_calls = 0")):
        with pytest.raises(ConfigError, match=r"design\.require: 'proven' needs the verification") as info:
            updated(cfg, {"design.require": "proven", **change})
        assert words in str(info.value)
    with pytest.raises(ConfigError, match=r"design\.verification_total_max_calls: must be >= 0"):
        updated(cfg, {"design.verification_total_max_calls": -1})
    assert updated(cfg, {"design.require": "proven"}).design.verification_budget == 3 * 80  # the preset's 80 calls
    assert cfg.design.verification_budget == 80
