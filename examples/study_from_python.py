"""The study of your own mechanism from Python: run it, read the typed results, script a variation.

    python examples/study_from_python.py [CONFIG] [OUT]

1. ``jointwear.Study`` runs every stage of the TOML config (the same as ``jointwear run CONFIG --out OUT``).
2. The results are typed objects: the R(N) curve, the life table, the sensitivity's two rankings.
3. A variation is a new config: here the bushing's hardness specification tightened from 10 % to 5 %
   scatter, run into its own folder and compared at the headline target.
"""

from __future__ import annotations

import sys
from pathlib import Path

import jointwear
from jointwear.config import load_config, updated


def main() -> None:
    config_path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).with_name("my_linkage.toml")
    out = Path(sys.argv[2]) if len(sys.argv) > 2 else Path("my_linkage_results")

    # 1. the whole study ------------------------------------------------------------------------------------
    config = load_config(config_path)
    results = jointwear.Study(config, out=out / "baseline", echo=print).run()

    # 2. typed results ----------------------------------------------------------------------------------------
    rel = results.reliability
    for n, r in zip(rel.cycles, rel.reliability):
        print(f"R({n:,.0f} cycles) = {r:.3f}")
    for row in rel.life_table:  # a life outside the curve has no cycles, only where it lies (its status)
        low, high = row.get("cycles_low"), row.get("cycles_high")
        interval = f" (95 % interval {low:,.0f}-{high:,.0f})" if low is not None and high is not None else ""
        life = f"{row['cycles']:,.0f} cycles{interval}" if row["cycles"] is not None else row["status"]
        print(f"life at R = {row['target']}: {life}")
    sens = results.sensitivity
    # two different questions: which nominal value moves R most when changed by 20 % (the reference paper's
    # ranking), and whose scatter drives the scatter of the wear (the Sobol' total index: what to specify tighter)
    print("largest change of R for a 20 % change of a nominal value:", sens.ranking[0])
    name, share = sens.variance_ranking()[0]
    print(f"largest share of the wear's variance: {name} (Sobol' total index {share:.2f})")

    # 3. a variation: a tighter hardness specification ----------------------------------------------------------
    tight = updated(config, {"uncertainty.variables.HB_b.std_HB": 6.0}, source="tight hardness")  # 5 % of 120 HB
    rel_tight = jointwear.Study(tight, out=out / "tight_hardness", echo=print).reliability()
    print(f"life at R = {rel.target}: baseline {rel.life_cycles}, tight hardness {rel_tight.life_cycles} cycles")


if __name__ == "__main__":  # model calls run in worker processes, which import this file again
    main()
