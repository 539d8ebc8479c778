"""Every figure function draws from plain data, in the house style, with units on every axis."""

from __future__ import annotations

import re

import numpy as np
import pytest
from matplotlib.projections.polar import PolarAxes

from jointwear.reliability import Z95
from jointwear.report import figures as F
from jointwear.report.style import (
    COLORS,
    DPI,
    figure,
    savefig,
    scale_to_unit,
    to_data_uri,
    to_png_bytes,
)

ANG = np.linspace(0, 359, 360)
DEPTH = 0.0249 * np.exp(-0.5 * ((ANG - 110) / 14) ** 2) + 0.0087 * np.exp(-0.5 * ((ANG - 310) / 11) ** 2)
CYC = np.arange(300_000, 560_001, 20_000)
REL = 1 / (1 + np.exp((CYC - 410_000) / 20_000))

CASES = {
    "mechanism": lambda: F.mechanism_figure(6, 38, 12, (11.5, 38), branch=1),
    "mechanism_other_branch": lambda: F.mechanism_figure(6, 38, 12, (11.5, 38), branch=-1),
    "orbit": lambda: F.orbit_figure(2e-3 * np.cos(ANG / 30), 2e-3 * np.sin(ANG / 30), 2e-3, angle_labels=True),
    "force": lambda: F.contact_force_figure(np.linspace(0, 720, 500), 0.03 + 0.01 * np.sin(np.linspace(0, 12, 500)),
                                            mean_N=0.03, ideal_N=np.full(500, 0.03)),
    "polar": lambda: F.wear_polar_figure(ANG, DEPTH, radius_mm=1.002, peaks=[{"angle_deg": 110, "depth_mm": 0.0249}],
                                         cycles=400_000),
    "polar_no_wear": lambda: F.wear_polar_figure(ANG, np.zeros_like(ANG)),
    "panels": lambda: F.wear_panels_figure(ANG, DEPTH, slip_mm=DEPTH / 20, contact_force_N=DEPTH,
                                           contact_area_mm2=DEPTH / 10, cycles=400_000),
    "panels_depth_only": lambda: F.wear_panels_figure(ANG, DEPTH),
    "history": lambda: F.wear_history_figure(CYC, 7e-8 * CYC, limit_mm=0.03, mean_cycles=CYC,
                                             mean_max_wear_mm=7.1e-8 * CYC, reference_mean={400_000: 0.0285},
                                             reference_nominal=(400_000, 0.0249), reference_label="Author 2030"),
    "reliability": lambda: F.reliability_curve_figure(CYC, REL, pf_cov=[0.02] * len(CYC), target=0.9,
                                                      life_cycles=371_640, reference={400_000: 0.739},
                                                      reference_life=371_640, reference_label="Author 2030"),
    "histograms": lambda: F.wear_histograms_figure([360_000, 400_000, 440_000],
                                                   [np.random.default_rng(k).normal(0.026 + k * 0.003, 0.002, 500)
                                                    for k in range(3)], limit_mm=0.03,
                                                   reference_means={360_000: 0.0256}),
    "one_histogram": lambda: F.wear_histograms_figure([400_000], [np.random.default_rng(1).normal(0.028, 0.002, 300)]),
    "convergence": lambda: F.convergence_figure(np.arange(12, 40), np.geomspace(0.3, 0.001, 28),
                                                cov=np.full(28, 0.05)),
    "tornado": lambda: F.tornado_figure(["rod length", "clearance", "crank"], [0.0, 0.99, 0.95], [0.0, 0.5, 0.98],
                                        0.978, cycles=360_000),
    "sobol": lambda: F.sobol_figure(["a", "b", "c"], [0.1, 0.5, 0.2], [0.15, 0.6, 0.2], S1_conf=[0.01] * 3,
                                    ST_conf=[0.02] * 3),
}


def _has_unit(label: str) -> bool:
    return bool(re.search(r"\([^()]+\)\s*$", label.strip()))


@pytest.mark.parametrize("name", sorted(CASES))
def test_figure_draws_with_units_on_every_axis(name, tmp_path):
    fig = CASES[name]()
    for ax in fig.axes:
        if not ax.get_visible() or isinstance(ax, PolarAxes):
            continue  # polar wear profile: angle ticks in degrees, radius explained on the figure
        if not ax.get_xticks().size and not ax.get_yticks().size:
            continue  # an empty panel that says "not provided"
        for label, ticks in ((ax.get_xlabel(), ax.get_xticklabels()), (ax.get_ylabel(), ax.get_yticklabels())):
            categorical = label == "" and any(re.search(r"[A-Za-z]", t.get_text()) for t in ticks)
            assert categorical or _has_unit(label), f"{name}: axis label without a unit: {label!r}"
    if name.startswith("polar"):
        texts = " ".join(t.get_text() for t in fig.texts)
        assert "exaggerated" in texts and "clockwise" in texts
    path = savefig(fig, tmp_path / f"{name}.png")
    data = path.read_bytes()
    assert data.startswith(b"\x89PNG")


def test_style_helpers(tmp_path):
    fig, ax = figure()
    ax.plot([0, 1], [0, 1])
    assert ax.get_lines()[0].get_color().lower() == COLORS[0].lower()
    uri = to_data_uri(fig)
    assert uri.startswith("data:image/png;base64,")
    fig, _ = figure(size=(2.0, 1.0))
    path = savefig(fig, tmp_path / "x.svg")  # always PNG
    assert path.suffix == ".png"
    import struct

    width = struct.unpack(">I", path.read_bytes()[16:20])[0]
    assert abs(width - 2.0 * DPI) <= 0.25 * 2.0 * DPI  # tight bbox trims a little
    vals, unit = scale_to_unit([0.029, 0.001], "N")
    assert unit == "mN" and vals[0] == pytest.approx(29.0)
    assert scale_to_unit([2e-6], "m")[1] == "\u00b5m"


@pytest.mark.parametrize("name", sorted(CASES))
def test_figures_are_written_with_a_palette_that_keeps_their_colours(name):
    """256 colours: a palette PNG at 31-44 % of the full-colour file's size on these figures (bound: 60 %), whose
    pixels stay within 7 of 255 levels of the full-colour rendering at the 99.9th percentile (bound: 12) and
    0.03 on average (bound: 0.1)."""
    from io import BytesIO

    import matplotlib
    from PIL import Image

    from jointwear.report.style import RC

    fig = CASES[name]()
    full = BytesIO()
    with matplotlib.rc_context(RC):
        fig.savefig(full, dpi=DPI, format="png")
    png = to_png_bytes(fig)
    with Image.open(BytesIO(png)) as small, Image.open(full) as big:
        assert small.mode == "P" and small.info.get("Software") == "jointwear"
        assert small.size == big.size and len(png) < 0.6 * len(full.getvalue())
        diff = np.abs(np.asarray(small.convert("RGB"), float) - np.asarray(big.convert("RGB"), float))
    assert np.percentile(diff, 99.9) <= 12 and diff.mean() < 0.1


def test_reference_points_carry_the_reference_label():
    """A cited reference is named by its label in the legend; without one nothing reference-like is drawn."""
    def legend(fig):
        return [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]

    with_ref = legend(CASES["reliability"]())
    assert "Author 2030" in with_ref and any(t.startswith("Author 2030: life") for t in with_ref)
    assert any(t.startswith("Author 2030") for t in legend(CASES["history"]()))
    bare = legend(F.reliability_curve_figure(CYC, REL, target=0.9, life_cycles=371_640))
    assert bare == ["95 % band (COV of Pf)", "this study"] or bare == ["this study"]


def test_figures_leave_the_users_matplotlib_settings_alone():
    import matplotlib as mpl

    from jointwear.report import figures as F
    from jointwear.report.style import RC, to_png_bytes

    before = dict(mpl.rcParams)
    png = to_png_bytes(F.reliability_curve_figure([1, 2, 3], [0.99, 0.9, 0.5], target=0.9))
    assert png.startswith(b"\x89PNG")
    assert dict(mpl.rcParams) == before
    # the house style did apply inside the drawing: a key it sets differs from matplotlib's default somewhere
    assert any(mpl.rcParamsDefault[k] != v for k, v in RC.items() if k in mpl.rcParamsDefault)


def test_the_reliability_band_adds_the_surrogates_error_to_the_monte_carlo_half_width():
    """The band was the Monte Carlo half-width alone (a third of the uncertainty on the piston pump); with the
    surrogate's error it is the combined half-width the validation judges agreement by."""
    def band(fig):  # the band's width at the last level (300k cycles)
        (poly,) = fig.axes[0].collections
        v = poly.get_paths()[0].vertices
        ys = v[np.isclose(v[:, 0], 300.0), 1]
        return ys.max() - ys.min()

    cyc, rel, cov = [1e5, 2e5, 3e5], [0.9, 0.7, 0.5], [0.02, 0.02, 0.02]
    mc = band(F.reliability_curve_figure(cyc, rel, pf_cov=cov))
    both = F.reliability_curve_figure(cyc, rel, pf_cov=cov, pf_error=[0.01, 0.03, 0.05])
    # the widest point is the last: R = 0.5 +- (1.96 x 0.02 x 0.5 + 0.05), clipped at neither end
    assert band(both) == pytest.approx(2 * (Z95 * 0.02 * 0.5 + 0.05), rel=1e-9) and band(both) > mc
    assert "95 % band (COV of Pf + surrogate error)" in [t.get_text() for t in both.axes[0].get_legend().get_texts()]


def test_a_series_systems_figure_draws_each_joints_own_curve_with_its_band():
    """Each joint's R(N) dashed, named in the legend, with a band of its own half-width; none without joints."""
    cyc, rel = [1e5, 2e5, 3e5], [0.9, 0.7, 0.5]
    joints = {"A": ([0.95, 0.8, 0.6], [0.01, 0.02, 0.04]), "E": ([0.99, 0.9, 0.8], None)}
    fig = F.reliability_curve_figure(cyc, rel, pf_cov=[0.02] * 3, joints=joints)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "joint A alone" in labels and "joint E alone" in labels and "the mechanism" in labels
    dashed = {line.get_label(): line.get_ydata() for line in ax.lines if line.get_linestyle() == "--"}
    np.testing.assert_array_equal(dashed["joint A alone"], [0.95, 0.8, 0.6])
    (_, joint_band) = ax.collections  # the mechanism's band, then joint A's (E has no half-width)
    v = joint_band.get_paths()[0].vertices
    ys = v[np.isclose(v[:, 0], 300.0), 1]
    assert ys.max() - ys.min() == pytest.approx(0.08)
    alone = F.reliability_curve_figure(cyc, rel).axes[0].get_legend().get_texts()
    assert "the mechanism" not in [t.get_text() for t in alone]


def test_a_figure_drawn_here_supersedes_the_stage_file_it_names_exactly(tmp_path):
    """validation.png was listed again among the figures 'the sections above do not show': its key also names
    cross_validation.png, which sorts first, so drawing the validation figure superseded the wrong file."""
    import matplotlib.pyplot as plt

    from jointwear.report.markup import Figures
    from jointwear.report.style import to_png_bytes

    fig = plt.figure(figsize=(1, 1))
    pngs = {}
    for stem in ("cross_validation", "validation"):
        pngs[stem] = tmp_path / f"{stem}.png"
        pngs[stem].write_bytes(to_png_bytes(fig))
    plt.close(fig)
    figs = Figures(pngs)
    figs.draw(lambda: F.reliability_curve_figure([1, 2], [0.9, 0.5]), "validation", png_keys=("validation",))
    figs.draw(lambda: F.reliability_curve_figure([1, 2], [0.9, 0.5]), "cv", png_keys=("cross_validation",))
    assert figs.leftovers() == []


@pytest.mark.parametrize("offset, guide, branch", [(0.0, 0.0, 1), (10.0, 30.0, 1), (-5.0, 90.0, -1)])
def test_the_slider_crank_sketch_closes_its_loop_on_the_guide(offset, guide, branch):
    """A slider-crank got no sketch ('drawn for four-bar and general linkages'): its rod keeps its length and its
    slider B lies on the guide line offset * n + s u, on the side the assembly branch picks."""
    fig = F.slider_crank_figure(50.0, 120.0, offset_mm=offset, guide_angle_deg=guide, branch=branch)
    lines = {ln.get_label(): np.asarray(ln.get_xydata()) for ln in fig.axes[0].get_lines()}
    a, b = lines["rod 120 mm"]
    assert np.hypot(*(b - a)) == pytest.approx(120.0, rel=1e-12)
    u = np.array([np.cos(np.deg2rad(guide)), np.sin(np.deg2rad(guide))])
    n = np.array([-u[1], u[0]])
    assert b @ n == pytest.approx(offset, abs=1e-9)
    assert np.sign((b - a) @ u) == branch


def test_a_general_linkage_sketch_draws_a_slider_and_its_guide():
    """A slider (a body of one point) had a legend entry but no mark, and its prismatic guide was not drawn."""
    mech = {"ground_mm": {"O": [0.0, 0.0], "G": [80.0, 10.0]},
            "bodies": [{"name": "crank", "points_mm": {"O": [0.0, 0.0], "A": [10.0, 0.0]}, "com_mm": [5.0, 0.0]},
                       {"name": "rod", "points_mm": {"A": [10.0, 0.0], "B": [80.0, 10.0]}, "com_mm": [45.0, 5.0]},
                       {"name": "slider", "points_mm": {"B": [80.0, 10.0]}, "com_mm": [80.0, 10.0]}],
            "joints": [{"name": "O", "type": "revolute", "at_mm": [0.0, 0.0]},
                       {"name": "B", "type": "revolute", "at_mm": [80.0, 10.0]},
                       {"name": "P", "type": "prismatic", "at_mm": [80.0, 10.0], "direction": [2.0, 0.0]}],
            "driven_joints": ["O"], "clearance_joints": ["B"]}
    ax = F.linkage_figure(mech).axes[0]
    (slider,) = [ln for ln in ax.get_lines() if ln.get_label() == "slider"]
    assert slider.get_marker() == "s"
    (guide,) = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    xy = np.asarray(guide.get_xydata())
    assert np.allclose(xy.mean(axis=0), [80.0, 10.0]) and np.allclose(xy[:, 1], 10.0)  # through P, along x
    # B and P drawn at one point: their names one under the other, not on top of each other
    offsets = {t.get_text(): t.xyann for t in ax.texts}
    assert offsets["B"] != offsets["P"]


def test_the_tornado_shows_each_shifts_error_and_which_shifts_could_not_run():
    """A shifted R is read with an error (a reader took two bars within it for a ranking), and a mechanism that could
    not run counts R = 0, which looked like a real R = 0 of wear: whiskers of the given 95 % errors at the bars' ends,
    and the bars that could not run hatched, with a legend entry saying so."""
    import matplotlib.pyplot as plt

    fig = F.tornado_figure(["rod length", "clearance", "crank"], [0.0, 0.99, 0.95], [0.0, 0.5, 0.98], 0.978,
                           error_low=[0.0, 0.004, 0.02], error_high=[0.0, 0.03, 0.006],
                           not_run_low=[True, False, False], not_run_high=[True, False, False])
    ax = fig.axes[0]
    # the error bars: one per bar, at its end, as wide as its error (the order is the figure's: largest on top)
    segments = [seg for coll in ax.collections for seg in coll.get_segments()]
    spans = sorted((round(float(s[0][0]), 6), round(float(s[1][0]), 6)) for s in segments)
    expected = sorted((round(v - e, 6), round(v + e, 6)) for v, e in
                      zip([0.0, 0.99, 0.95, 0.0, 0.5, 0.98], [0.0, 0.004, 0.02, 0.0, 0.03, 0.006]))
    assert spans == expected
    hatched = [p for p in ax.patches if p.get_hatch()]
    assert len(hatched) == 2  # rod length at both shifts
    assert "could not run (R = 0)" in [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)
    plain = F.tornado_figure(["a"], [0.9], [0.95], 0.93)  # without errors and failures: as before
    assert not plain.axes[0].collections and not any(p.get_hatch() for p in plain.axes[0].patches)
    plt.close(plain)


def test_the_sensitivity_results_own_tornado_shows_the_errors_and_the_shifts_that_could_not_run(tmp_path):
    """The stage's sensitivity_tornado.png (SensitivityResult.plot, which the report draws per group) had neither:
    only the report's figure was given them (the default study's l2 x 0.8, whose linkage cannot close, read as an R
    of 0 by wear)."""
    import matplotlib.pyplot as plt

    from jointwear.study import SensitivityResult

    variables = [{"name": "l2", "label": "rod length", "group": "tolerance", "reliability_low": 0.0,
                  "reliability_high": 0.2, "reliability_low_error": 0.0, "reliability_high_error": 0.05},
                 {"name": "k_b", "label": "wear coefficient", "group": "material", "reliability_low": 0.99,
                  "reliability_high": 0.6, "reliability_low_error": 0.004, "reliability_high_error": 0.03}]
    rules = [{"variable": "l2", "factor": 0.8, "rule": "separable_scaling", "reliability": 0.0,
              "reason": "the shifted mechanism could not run (counted as failure): links cannot close the loop"}]
    sens = SensitivityResult(cycles=360_000, factors=[0.8, 1.2], reliability_nominal=0.94, variables=variables,
                             ranking=["l2", "k_b"], ranking_by_group={}, sobol={}, rules=rules)
    assert sens.shift_not_run("l2", 0.8) and not sens.shift_not_run("l2", 1.2) and not sens.shift_not_run("k_b", 0.8)
    ax = sens.plot().axes[0]
    assert len([p for p in ax.patches if p.get_hatch()]) == 1
    spans = sorted(round(float(seg[1][0] - seg[0][0]), 9) for c in ax.collections for seg in c.get_segments())
    assert spans == sorted(round(2 * e, 9) for e in (0.0, 0.05, 0.004, 0.03))
    plt.close("all")
    one = sens.plot(variables[1:], title="Material").axes[0]  # one group, as the report draws it
    assert "Material" in (one.get_title("left"), one.get_title())
    assert [t.get_text() for t in one.get_yticklabels()] == ["wear coefficient"]
    plt.close("all")
