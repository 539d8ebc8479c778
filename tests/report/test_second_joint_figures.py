"""A figure the report draws for one clearance joint stands for that joint's stage file only: with joints K and C,
drawing K's orbit superseded orbit_C.png (it sorts first), so C's figures were shown nowhere and the appendix of
figures the sections do not show repeated K's (a designer's toggle press with two clearance joints)."""

import matplotlib.pyplot as plt

from jointwear.report import figures as F
from jointwear.report.markup import Figures
from jointwear.report.study_sections import joint_png_keys
from jointwear.report.style import to_png_bytes


def _pngs(tmp_path, stems):
    fig = plt.figure(figsize=(1, 1))
    out = {}
    for stem in stems:
        out[stem] = tmp_path / f"{stem}.png"
        out[stem].write_bytes(to_png_bytes(fig))
    plt.close(fig)
    return out


def test_drawing_the_first_joints_figures_leaves_the_second_joints_files_for_the_appendix(tmp_path):
    kinds = {"orbit": ("orbit",), "force": ("contact_force", "force"), "wear_history": ("history",),
             "wear_polar": ("polar",), "wear_vs_angle": ("fig17", "panels", "vs_angle")}
    figs = Figures(_pngs(tmp_path, [f"{kind}_{joint}" for kind in kinds for joint in ("C", "K")]))
    for keys in kinds.values():
        figs.draw(lambda: F.reliability_curve_figure([1, 2], [0.9, 0.5]), "K's figure",
                  png_keys=joint_png_keys(keys, "K"))
    assert sorted(figs.used) == sorted(f"{kind}_K" for kind in kinds)
    shown = "".join(figs.leftovers())
    assert all(f"{kind}_C.png" in shown for kind in kinds) and "_K.png" not in shown


def test_a_single_joints_unsuffixed_file_is_still_superseded(tmp_path):
    figs = Figures(_pngs(tmp_path, ["orbit", "contact_force"]))
    figs.draw(lambda: F.reliability_curve_figure([1, 2], [0.9, 0.5]), "orbit", png_keys=joint_png_keys(("orbit",), "B"))
    figs.draw(lambda: F.reliability_curve_figure([1, 2], [0.9, 0.5]), "force",
              png_keys=joint_png_keys(("contact_force", "force"), None))
    assert figs.leftovers() == []
