"""How many samples does `jointwear validate` need? The paired check (the surrogate read on the validation's own
samples) against the comparison of two independent intervals, at several sample counts.

    python benchmarks/validate.py --config CONFIG --samples 2000 --keep FOLDER   # first: a kept validation
    python benchmarks/validate_samples.py --config CONFIG --folder FOLDER --samples 200 500 1000 2000

Runs `Study.validate(n)` for each n on FOLDER's study (its learning replayed from the evaluation store; samples the
store lacks are run, and counted in `new_calls`) and writes, per n, the learnt life at each target against the true
model's on the same samples (`paired_ratio` with its 95 % bounds) beside the two lives with their own intervals, to
KEY (default: the config's name) of benchmarks/results/validate_samples.json (docs/study.md, "Direct validation").
"""

from __future__ import annotations

import argparse
import json
import warnings
from pathlib import Path

OUT = Path(__file__).parent / "results" / "validate_samples.json"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", required=True)
    ap.add_argument("--folder", type=Path, required=True, help="a kept validation's folder (benchmarks/validate.py)")
    ap.add_argument("--samples", type=int, nargs="+", required=True)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--key", default=None)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    import jointwear
    from jointwear.study.io import provenance

    study = jointwear.Study(args.config, out=args.folder, resume=True, workers=args.workers, echo=lambda line: None)
    rows = []
    for n in args.samples:
        val = study.validate(n)
        life = val.life_table[0]
        rows.append({"samples": n, "new_calls": val.model_calls, "wall_seconds": val.wall_seconds,
                     **{k: life.get(k) for k in ("target", "cycles", "cycles_low", "cycles_high", "surrogate_cycles",
                                                  "surrogate_cycles_low", "surrogate_cycles_high", "agree",
                                                  "paired_ratio", "paired_ratio_low", "paired_ratio_high")},
                     "levels_agree": int(val.agreement.sum()), "levels": int(val.agreement.size),
                     "levels_within_error": None if not val.paired else int(val.paired_within_error().sum())})
        print(json.dumps({k: rows[-1][k] for k in ("samples", "new_calls", "cycles", "surrogate_cycles",
                                                    "paired_ratio", "paired_ratio_low", "paired_ratio_high")}))
    record = json.loads(args.out.read_text(encoding="utf-8")) if args.out.is_file() else {}
    record[args.key or study.config.name] = {"config": args.config, "machine": provenance(), "runs": rows}
    args.out.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
