"""The design stage finds the true cheapest feasible design of an analytic wear model.

The wear law has Archard's structure (analytic.py), so the exact R(N*) of every candidate is known by brute-force
Monte Carlo with 10^6 samples; the design stage sees the model only through true-model calls.
"""

import copy
import json
from html import escape

import numpy as np
import pytest

from jointwear.design import DesignResult, build_controls, enumerate_candidates, run_design
from jointwear.study import run_reliability

from design_fixtures import DESIGN, analytic_config, analytic_context, exact_reliabilities

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

N_STAR = DESIGN["targets"][0]["life_cycles"]
R_STAR = DESIGN["targets"][0]["reliability"]


@pytest.fixture(scope="module")
def setup():
    cfg = analytic_config()
    ctx, model = analytic_context(cfg)
    rel = run_reliability(ctx)
    controls = build_controls(cfg)
    cands = list(enumerate_candidates(controls))
    exact = exact_reliabilities(ctx, model, controls, cands, N_STAR)
    return cfg, ctx, model, rel, controls, cands, exact


@pytest.fixture(scope="module")
def design(setup):
    cfg, ctx, model, rel, *_ = setup
    return run_design(ctx, rel)


def _brute_force(controls, cands, exact):
    feasible = [i for i in range(len(cands)) if exact[i] >= R_STAR]
    return min(feasible, key=lambda i: cands[i].cost(controls))


def test_chosen_is_the_true_cheapest_feasible_design(setup, design):
    cfg, ctx, model, rel, controls, cands, exact = setup
    best = _brute_force(controls, cands, exact)
    # the problem separates: every cheaper candidate misses R* by more than 0.01 and the best clears it by more
    # (so Monte Carlo noise of 3e-4 in the exact values cannot change the answer)
    cheaper = [i for i in range(len(cands)) if cands[i].cost(controls) < cands[best].cost(controls)]
    assert max(exact[i] for i in cheaper) < R_STAR - 0.01 and exact[best] > R_STAR + 0.01
    assert design.chosen["choices"] == cands[best].choices(controls)
    assert design.chosen["cost"] == pytest.approx(cands[best].cost(controls))


def test_estimates_agree_with_the_exact_reliabilities_within_their_error(setup, design):
    cfg, ctx, model, rel, controls, cands, exact = setup
    by_choice = {tuple(c.choices(controls).values()): e for c, e in zip(cands, exact)}
    for row in design.pareto + [design.chosen]:
        e = by_choice[tuple(row["choices"].values())]
        # the reported 95 % bound (surrogate ESC + population Monte Carlo) plus 3 s.e. of the 1e6-sample reference
        tol = row["reliability_error"] + 3 * np.sqrt(e * (1 - e) / 1e6)
        assert abs(row["reliability_at_target_life"] - e) <= tol, (row["choices"], row["reliability_at_target_life"], e)


def test_todays_design_is_read_on_the_same_surrogate(setup, design):
    """The report gave the choice but not today's design beside it (a manager could not see that the choice was
    cheaper than today's). Today's R(N*) against the exact one (brute force on the study's own inputs): within
    its own error bound, computed as every candidate's (it was shown without one)."""
    from jointwear.reliability import IsoTransform

    cfg, ctx, model, rel, *_ = setup
    z = np.random.default_rng(7).standard_normal((1_000_000, len(ctx.names)))
    exact = float(np.mean(model.life(IsoTransform(ctx.marginals).to_x(z)) > N_STAR))
    bound = design.baseline_reliability_error
    assert bound > 0.0
    assert abs(design.baseline_reliability_at_target_life - exact) <= bound + 3 * np.sqrt(exact * (1 - exact) / 1e6)
    assert exact < R_STAR  # today's design misses the target the design reaches


def test_pareto_front_is_non_dominated(design):
    costs = [r["cost"] for r in design.pareto]
    lives = [r["life_at_target_cycles"] for r in design.pareto]
    assert costs == sorted(costs) and all(b > a for a, b in zip(lives, lives[1:]))
    for row in design.candidates:  # nothing off the front is cheaper and longer-lived than a front point
        assert not any(row["cost"] < f["cost"] and row["life_at_target_cycles"] > f["life_at_target_cycles"]
                       for f in design.pareto)


def test_verification_confirms_and_matches_the_exact_value(setup, design):
    cfg, ctx, model, rel, controls, cands, exact = setup
    ver = design.verification
    best = _brute_force(controls, cands, exact)
    assert ver["confirmed"] and ver["reliability_at_target_life"] >= R_STAR
    # its own error bound plus 3 s.e. of the reference
    assert abs(ver["reliability_at_target_life"] - exact[best]) <= ver["error"] + 3 * np.sqrt(exact[best] * (1 - exact[best]) / 1e6)
    # the study's, the refinement's and the verification's inputs: here the session evaluated nothing else
    assert design.model_calls == sum(design.calls[k] for k in ("study", "refinement", "verification"))
    assert design.model_calls == ctx.n_evaluated
    assert design.calls["verification"] <= cfg.design.verification_max_calls


def test_a_wrong_choice_from_a_coarse_surrogate_is_caught_and_corrected(setup):
    # only the 12 Latin-hypercube points of the study: the surrogate misjudges the cheapest feasible design; the
    # verification rejects it, its calls enter the surrogate and the search picks the true answer
    cfg, ctx, model, rel, controls, cands, exact = setup
    coarse = copy.copy(rel)
    coarse.design_x = np.asarray(rel.design_x)[:cfg.reliability.n_initial]
    res = run_design(ctx, coarse)
    best = _brute_force(controls, cands, exact)
    assert res.chosen["choices"] == cands[best].choices(controls)
    assert res.verification["confirmed"]


def test_design_json_has_the_contract_keys_and_loads_back(design, tmp_path):
    design.save(tmp_path, figures=False)
    data = json.loads((tmp_path / "design.json").read_text())
    for key in ("target_life_cycles", "target_reliability", "chosen", "pareto", "verification", "model_calls",
                "wall_seconds"):
        assert key in data
    for key in ("choices", "cost", "life_at_target_cycles", "reliability_at_target_life"):
        assert key in data["chosen"] and all(key in row for row in data["pareto"])
    for key in ("reliability_at_target_life", "error", "model_calls"):
        assert key in data["verification"]
    assert (tmp_path / "design_pareto.csv").read_text().count("\n") == len(data["pareto"]) + 1
    assert data["no_choice_reason"] is None and data["nearest"] is None
    from result_keys import undocumented_keys

    assert undocumented_keys(tmp_path / "design.json") == []  # every key in docs/results.md (tests/result_keys.py)
    back = DesignResult.load(tmp_path)
    assert back.chosen["choices"] == design.chosen["choices"] and back.target_life_cycles == design.target_life_cycles
    # and with every other stage's result: load_results had no design field although Study.design() writes one
    from jointwear import load_results

    folder = load_results(tmp_path)
    assert folder.stages == ["design"] and folder.design.chosen["choices"] == design.chosen["choices"]


def test_report_section_shows_the_front_the_choice_and_the_verified_reliability(setup, design, tmp_path):
    from jointwear.report.design_section import design_section

    assert design_section(tmp_path) is None  # no design.json: no section
    design.save(tmp_path)
    rel = setup[3]
    rel.save(tmp_path, figures=False)  # its crank speed gives the chosen life in hours
    html = design_section(tmp_path)
    hours = design.chosen["life_at_target_cycles"] / rel.crank_speed_rpm / 60
    assert f"cycles ({hours:,.2f} h) at R*" in html
    assert (tmp_path / "design_pareto.png").read_bytes().startswith(b"\x89PNG")
    assert "data:image/png;base64," in html
    for option in design.chosen["choices"].values():
        assert option in html
    assert f"{design.verification['reliability_at_target_life']:.4f}" in html
    assert escape(design.verification_sentence()[1:]) in html and design.verdict() in ("meets", "within_error")
    today = f"{design.baseline_reliability_at_target_life:.4f} +- {design.baseline_reliability_error:.4f}"
    assert f"today&#x27;s design (the study&#x27;s own inputs) reads R(N*) = {today} on the surrogate the candidates are read on" in html
    assert "Extrapolated candidates" not in html and "outside the study's inputs</th>" in html


def test_report_section_warns_of_extrapolated_candidates_and_of_uniform_wear_outside_its_range(design, tmp_path):
    """A user's PTFE option showed R(N*) = 1.0000 with 99.7 % of its population outside the study's inputs, and the
    choice rested on uniform-mode wear the wear stage called untrustworthy: both are now said above the front."""
    from jointwear.report.design_section import EXTRAPOLATED_SHARE, design_section
    from jointwear.study import WearSummary

    far = copy.deepcopy(design)
    far.pareto[-1]["outside_design_fraction"] = 0.997
    far.save(tmp_path, figures=False)
    WearSummary(cycles=1, max_wear_mm=0.1, geometry_mode="uniform", conformity=17.9,
                uniform_mode_valid=False).write(tmp_path)
    html = design_section(tmp_path)
    assert "<strong>Extrapolated candidates.</strong> 1 of these designs draw more than " \
           f"{EXTRAPOLATED_SHARE:.0%}" in html and "<td>99.7%</td>" in html
    assert "<strong>The wear model is outside its range.</strong>" in html and "conformity 17.9" in html


def test_a_refinement_that_learns_nothing_stops_at_its_budget(setup, design, monkeypatch):
    """The refinement's budget counts the points it asks for. It counted only new model calls, so a point the store
    already held (a failed call) was asked for again and again: a user's design ran 320 iterations until killed.
    Here every refinement point is a known study point and the surrogate learns nothing from it."""
    import signal

    from jointwear.design import search

    cfg, ctx, model, rel, controls, cands, exact = setup
    known = np.asarray(rel.design_x)[:1]
    monkeypatch.setattr(search, "_refine_point", lambda *args, **kwargs: known.copy())
    monkeypatch.setattr(search.LifeSurrogate, "add", lambda self, x: None)
    # a target life where the cheapest feasible design sits on R*: undecided until the surrogate learns
    target = cfg.design.targets[0].model_copy(update={"life_cycles": design.chosen["life_at_target_cycles"]})
    settings = cfg.design.model_copy(update={"targets": [target], "verify": False, "refine_max_calls": 3,
                                             "batch_size": 1, "n_population": 10_000})

    def endless(*_):
        raise TimeoutError("the refinement did not stop at its budget")

    previous = signal.signal(signal.SIGALRM, endless)
    signal.alarm(60)
    try:
        res = run_design(ctx, rel, settings=settings)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert res.refinement["iterations"] == 3 and res.refinement["model_calls"] == 0
    assert res.refinement["undecided_left"] >= 1


def test_with_several_targets_the_design_names_the_cheapest_meeting_them_all(setup, tmp_path):
    """Each target's own choice may miss the others (a user's headline choice gave R(110k) = 0.9585 against a second
    target of 0.99); a drawing needs one design meeting every target, and the result and report now give it."""
    from jointwear.report.design_section import design_section

    cfg, ctx, model, rel, controls, cands, exact = setup
    second = cfg.design.targets[0].model_copy(update={"reliability": 0.99, "life_cycles": 380_000})
    settings = cfg.design.model_copy(update={"targets": [cfg.design.targets[0], second], "verify": False})
    res = run_design(ctx, rel, settings=settings)
    assert res.verdict() == "not_verified" and "(design.verify = false)" in res.verification_sentence()
    every = res.chosen_every_target
    assert every is not None and every["choices"] != res.chosen["choices"] and "verification" not in every
    meets = [t["reliability"] for t in settings.model_dump()["targets"]]
    assert all(r >= m for r, m in zip(every["reliability_at_target_life"], meets))
    assert every["cost"] >= max(t["chosen"]["cost"] for t in res.targets)
    # the cheapest on the surrogate: no cheaper candidate meets both (the exact answer, within the estimates' error)
    both = [i for i in range(len(cands)) if exact[i] >= R_STAR]
    assert every["cost"] >= min(cands[i].cost(controls) for i in both)
    res.save(tmp_path, figures=False)
    assert "<strong>The headline choice does not meet every target.</strong>" in design_section(tmp_path)


def test_the_design_meeting_every_target_is_verified_at_every_target(setup, tmp_path):
    """The cheapest design meeting every target is what a drawing needs, yet only the headline choice was verified
    (at the first target): it now gets its own verification at every target's N*, each R(N*) within its error bound
    (plus 3 s.e. of the 10^6-sample reference) of the exact value."""
    from jointwear.report.design_section import design_section

    cfg, ctx, model, rel, controls, cands, exact = setup
    second = cfg.design.targets[0].model_copy(update={"reliability": 0.99, "life_cycles": 380_000})
    settings = cfg.design.model_copy(update={"targets": [cfg.design.targets[0], second]})
    res = run_design(ctx, rel, settings=settings)
    every = res.chosen_every_target
    checked = every["verification"]
    index = next(i for i, c in enumerate(cands) if c.choices(controls) == every["choices"])
    for k, life in enumerate((N_STAR, 380_000)):
        truth = exact_reliabilities(ctx, model, controls, [cands[index]], life)[0]
        assert abs(checked["reliability_at_target_life"][k] - truth) <= (
            checked["error"][k] + 3 * np.sqrt(truth * (1 - truth) / 1e6)), k
    assert checked["verdict"] == min(checked["verdicts"], key=["misses", "within_error", "meets"].index)
    assert res.calls["verification"] == res.verification["model_calls"] + checked["new_model_calls"]
    res.save(tmp_path, figures=False)
    assert "verified at every target on the true model: R(N*) = " in design_section(tmp_path)
    from result_keys import undocumented_keys

    assert undocumented_keys(tmp_path / "design.json") == []  # its keys too are in docs/results.md


def test_candidates_of_equal_cost_rank_by_fewest_changes_then_by_their_margin(setup):
    """With every option at cost 0 the design chose the first candidate in enumeration order that met R*, changing
    controls that bought nothing (a user's tie: three drawing changes where today's design met the target as well).
    Ties now go to the fewest changes from today's design, then to the highest R(N*) minus its error."""
    cfg, ctx, model, rel, controls, cands, exact = setup
    free = copy.deepcopy(DESIGN)
    free["tolerances"][0].update(grades=["IT11", "IT10", "IT9"], costs=[0.0, 0.0, 0.0])  # loosest first
    free["fit"]["options"].reverse()  # today's fit (H7/g6) last
    for option in free["fit"]["options"]:
        option["cost"] = 0.0
    for prop in free["properties"]:
        for option in prop["classes"]:
            option["cost"] = 0.0
    free.update(refine_max_calls=0, verify=False)
    res = run_design(ctx, rel, settings=analytic_config(free).design)
    # today's design: the fit and the two properties match their first options; the study's l2 is no grade listed,
    # so every l2 option is a change alike
    today = {"fit": "H7/g6", "HB_b": "standard", "k_b": "standard"}
    meeting = [r for r in res.candidates if r["reliability_at_target_life"] >= R_STAR]
    changes = {id(r): sum(r["choices"][k] != v for k, v in today.items()) + 1 for r in meeting}
    fewest = min(changes.values())
    best = max((r for r in meeting if changes[id(r)] == fewest),
               key=lambda r: r["reliability_at_target_life"] - r["reliability_error"])
    assert res.chosen["choices"] == best["choices"]
    first = meeting[0]["choices"]  # what enumeration order alone picked: a change of fit that bought nothing
    assert first["fit"] == "H6/g5" and first["l2"] == "IT11" and best["choices"]["fit"] == "H7/g6"
