"""The default study's numbers that docs/study.md and docs/paper-comparison.md quote are those of its record,
benchmarks/results/study.json (`python benchmarks/study.py`): the life surrogate's fit and the sensitivity's shifted
reliabilities. A re-run that moves them fails here until the docs follow."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "benchmarks" / "results" / "study.json"


def _run() -> dict:
    return json.loads(RECORD.read_text(encoding="utf-8"))["runs"][0]


def _quoted(run: dict) -> dict[str, str]:
    """Each quoted figure as the docs write it, computed from the record."""
    fit, sens = run["surrogate_fit"], run["sensitivity"]
    r0 = sens["reliability_nominal"]
    var = {v["name"]: v for v in sens["variables"]}
    check = {(c["variable"], c["factor"]): c for c in sens["archard_checks"]}
    hb, k = var["HB_b"], var["k_b"]
    k12 = check[("k_b", 1.2)]
    return {
        "q2": f"Q^2 = {fit['q2']:.2f}",
        "scatter": f"scatter of {100 * fit['life_scatter']:.1f} %",
        "nominal": f"nominal {r0:.3f}",
        "HB shift": f"by {r0 - hb['reliability_low']:.3f} and k at 120 % (x 1.2) by {r0 - k['reliability_high']:.3f}",
        "errors": f"errors {hb['reliability_low_error']:.3f} and {k['reliability_high_error']:.3f}",
        "spans": (f"HB_b spans {hb['reliability_high'] - hb['reliability_low']:.3f} and k_b\n"
                  f"{k['reliability_low'] - k['reliability_high']:.3f}"),
        "direct": (f"lower R by {r0 - check[('HB_b', 0.8)]['reliability_surrogate']:.3f} and "
                   f"{r0 - k12['reliability_surrogate']:.3f}"),
        "k x 1.2": (f"k x 1.2 gives {k12['reliability_archard']:.3f} by the scaling against the surrogate's "
                    f"{k12['reliability_surrogate']:.3f}, {abs(k12['difference']):.3f} apart\n  where their errors "
                    f"allow {k12['tolerance']:.3f}"),
    }


@pytest.mark.parametrize("key", ["q2", "scatter", "nominal", "HB shift", "errors", "spans", "direct", "k x 1.2"])
def test_docs_study_quotes_the_record(key):
    text = (ROOT / "docs" / "study.md").read_text(encoding="utf-8")
    quoted = _quoted(_run())[key]
    assert quoted in text, f"docs/study.md does not quote the record's {key}: {quoted!r}"


def test_paper_comparison_quotes_the_record():
    run = _run()
    sens = run["sensitivity"]
    r0 = sens["reliability_nominal"]
    var = {v["name"]: v for v in sens["variables"]}
    text = (ROOT / "docs" / "paper-comparison.md").read_text(encoding="utf-8")
    hb, k = var["HB_b"], var["k_b"]
    for quoted in (f"{100 * run['surrogate_fit']['life_scatter']:.1f} % in life on this run",
                   f"HB_b moves R(360k) by {hb['reliability_high'] - hb['reliability_low']:.3f} and k_b by "
                   f"{k['reliability_low'] - k['reliability_high']:.3f}",
                   f"nominal R = {r0:.3f}: HB_b at 80 % lowers it by {r0 - hb['reliability_low']:.3f}, k_b at 120 % "
                   f"by {r0 - k['reliability_high']:.3f}"):
        assert quoted in text, quoted


def test_the_reports_trust_sentence_quotes_the_validations():
    """The report's "How far to trust the life" quotes how short the presets' learnt lives read against their true
    models' on the same samples (the validation's paired check, recorded by benchmarks/surrogate_bias.py) and their
    intervals' half-widths (the validation records): the figures are those of the current records."""
    from jointwear.report.result_sections import LIFE_TRUST

    bias = json.loads((ROOT / "benchmarks" / "results" / "surrogate_bias.json").read_text(encoding="utf-8"))
    shorts, halves = [], []
    profile = "jin2025_flapping_wing_profile"
    for key, name in (("jin2025_flapping_wing", "validate_swept_deposit_znver4.json"),
                      (profile, f"validate_{profile}_swept_gather_znver4.json")):
        paired = bias[key]["paired"]["life"]
        row = json.loads((ROOT / "benchmarks" / "results" / name).read_text(encoding="utf-8"))["validation"][
            "life_table"][0]
        assert paired["surrogate_cycles"] == row["surrogate_cycles"]  # the same study
        assert paired["paired_ratio_high"] < 0  # "short"
        shorts.append(f"{-100 * paired['paired_ratio']:.1f} %")
        half = (row["surrogate_cycles_high"] - row["surrogate_cycles_low"]) / 2 / row["surrogate_cycles"]
        halves.append(f"{100 * half:.1f} %")
    assert (f"learnt lives are {shorts[0]} (uniform mode) and {shorts[1]} (profile mode) short, as much as or more "
            f"than their 95 % intervals' half-widths ({halves[0]} and {halves[1]})") in LIFE_TRUST, (shorts, halves)


def test_the_paired_validation_table_quotes_the_record():
    """docs/study.md's table of the learnt lives against the true models' on the same samples is the record's."""
    from jointwear.study.reliability_results import signed_percent

    bias = json.loads((ROOT / "benchmarks" / "results" / "surrogate_bias.json").read_text(encoding="utf-8"))
    text = (ROOT / "docs" / "study.md").read_text(encoding="utf-8")
    for key in ("jin2025_flapping_wing", "jin2025_flapping_wing_profile", "jin2025_flapping_wing_archard_trend",
                "jin2025_flapping_wing_profile_archard_trend"):
        paired = bias[key]["paired"]
        life = paired["life"]
        cell = (f"| {signed_percent(life['paired_ratio'])} ({signed_percent(life['paired_ratio_low'])} to "
                f"{signed_percent(life['paired_ratio_high'])}) |")
        within = f"| {sum(paired['within_error'])} of {len(paired['within_error'])} |"
        assert any(cell in line and line.rstrip().endswith(within) for line in text.splitlines()), (key, cell, within)


def test_the_sample_count_table_quotes_the_record():
    """docs/study.md's table of the paired check at 200-2,000 samples is benchmarks/results/validate_samples.json's."""
    from jointwear.study.reliability_results import signed_percent

    runs = json.loads((ROOT / "benchmarks" / "results" / "validate_samples.json").read_text(encoding="utf-8"))[
        "jin2025_flapping_wing"]["runs"]
    text = (ROOT / "docs" / "study.md").read_text(encoding="utf-8")
    for r in runs:
        row = (f"| {r['samples']:,} | {r['cycles']:,.0f} ({r['cycles_low']:,.0f}-{r['cycles_high']:,.0f}) | "
               f"{signed_percent(r['surrogate_cycles'] / r['cycles'] - 1)} | {signed_percent(r['paired_ratio'])} "
               f"({signed_percent(r['paired_ratio_low'])} to {signed_percent(r['paired_ratio_high'])}) | "
               f"{r['levels_agree']} of {r['levels']} | {r['levels_within_error']} of {r['levels']} |")
        assert row in text, row
