"""A choice its own verification refutes is not chosen again: the search goes on without it, and says so when no
candidate is left that was not refuted.

The verification is stubbed (it refutes the candidates named), so the search loop is tested on its own; the analytic
model of design_fixtures keeps the surrogate and the refinement cheap.
"""

import pytest
from design_fixtures import DESIGN, analytic_config, analytic_context

from jointwear.design import DesignResult, run_design
from jointwear.design import search as design_search
from jointwear.design.results import choices_text, verification_verdict
from jointwear.study import run_reliability

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures


@pytest.fixture(scope="module")
def study():
    cfg = analytic_config(dict(DESIGN, n_population=5_000, verification_max_calls=1_000))
    ctx, _ = analytic_context(cfg)
    return ctx, run_reliability(ctx)


def _stub(refute):
    """A verification that refutes a candidate when ``refute(choices)`` (R(N*) = 0.5 +/- 0.01), else meets the
    target; its 'true-model calls' are three points of the candidate's population (run on the analytic model)."""
    seen = []

    def verify(ctx, cand, controls, space, target, max_calls, seed, stopping="u"):
        choices = cand.choices(controls)
        seen.append(choices)
        x = space.population(cand)[0][len(seen) * 3:len(seen) * 3 + 3]
        ctx.log_life(x)
        r = 0.5 if refute(choices) else 0.99
        verdict = verification_verdict(r, 0.01, target["reliability"])
        return {"reliability_at_target_life": r, "error": 0.01, "model_calls": 3, "new_model_calls": 3,
                "run_now": 3, "confirmed": verdict != "misses", "verdict": verdict, "converged": True}, x

    return verify, seen


def test_a_refuted_choice_is_not_chosen_again(study, monkeypatch):
    """The verification's few calls hardly move the surrogate, so the search returned the refuted choice again and
    the stage reported it as its choice, with the verdict 'misses'."""
    ctx, rel = study
    first = run_design(ctx, rel).chosen["choices"]
    verify, seen = _stub(lambda choices: choices == first)
    monkeypatch.setattr(design_search, "verify", verify)
    res = run_design(ctx, rel)
    assert seen[0] == first and len(seen) == 2 and seen[1] != first
    assert res.chosen["choices"] == seen[1] and res.verdict() == "meets"
    assert [r["choices"] for r in res.refuted] == [first]
    assert [r["verdict"] for r in res.verification["rounds"]] == ["misses", "meets"]
    assert res.no_choice_reason is None and res.no_choice_sentence() == ""


def test_no_choice_is_left_when_every_candidate_is_refuted(study, monkeypatch):
    ctx, rel = study
    verify, seen = _stub(lambda choices: True)
    monkeypatch.setattr(design_search, "verify", verify)
    settings = ctx.config.design
    res = run_design(ctx, rel, settings.model_copy(update={"properties": settings.properties[1:]}))  # 18 candidates
    assert len(seen) >= 2 and len({choices_text(c) for c in seen}) == len(seen)  # each verified once
    assert res.chosen is None and not res.feasible and res.verdict() is None
    assert res.no_choice_reason == "refuted" and [r["choices"] for r in res.refuted] == seen
    assert res.verification["verdict"] == "misses" and len(res.verification["rounds"]) == len(seen)
    assert res.no_choice_sentence().startswith(f"no choice is left that its verification did not refute: the "
                                               f"{len(seen)} candidates that reached")
    assert choices_text(seen[0]) in res.no_choice_sentence()
    # nor is a refuted candidate named as the nearest to the target
    assert all(choices_text(c) not in res.nearest_sentence() for c in seen)


def test_a_budget_spent_on_refuted_choices_leaves_the_next_one_unverified(study, monkeypatch):
    ctx, rel = study
    verify, seen = _stub(lambda choices: True)
    monkeypatch.setattr(design_search, "verify", verify)
    res = run_design(ctx, rel, ctx.config.design.model_copy(update={"verification_max_calls": 6}))
    assert len(seen) == 2 and [r["choices"] for r in res.refuted] == seen
    assert res.chosen is not None and res.chosen["choices"] not in seen and res.verdict() == "not_verified"
    assert res.no_choice_reason is None and "budget spent" in res.verification_sentence()
    # a refuted candidate is not named as an undecided cheaper one either
    assert all(choices_text(c) not in res.undecided_sentence() for c in seen)


def test_the_reason_survives_the_json(tmp_path):
    refuted = [{"choices": {"fit": "H7/g6"}, "cost": 1.0, "reliability_at_target_life": 0.5, "error": 0.01}]
    res = DesignResult(target_life_cycles=1e6, target_reliability=0.9, chosen=None, pareto=[], verification=None,
                       model_calls=10, wall_seconds=1.0, refuted=refuted)
    res.save(tmp_path, figures=False)
    back = DesignResult.load(tmp_path)
    assert back.no_choice_reason == "refuted" and back.no_choice_sentence() == res.no_choice_sentence()
    assert "fit H7/g6 (cost 1: R(N*) = 0.5000 +/- 0.0100)" in back.no_choice_sentence()
    plain = DesignResult(target_life_cycles=1e6, target_reliability=0.9, chosen=None, pareto=[], verification=None,
                         model_calls=10, wall_seconds=1.0)
    assert plain.no_choice_reason == "unreached"
    assert plain.no_choice_sentence().startswith("no candidate reaches the target on the surrogate (1,000,000 "
                                                 "cycles at R = 0.9)")
