"""The comparison with the study's cited reference as a Markdown table (for docs such as
docs/paper-comparison.md).

    python -m jointwear.report.compare results        # prints the table of the study in results/

The reference is the one in the folder's settings JSON (``config.json``, key ``reference``: the config's
``[reference]``). Same numbers, bands and statuses as the report's comparison section
(:func:`jointwear.report.reference_checks.reference_checks`). A study without a reference has nothing to compare: the
command says so and exits with status 1.
"""

from __future__ import annotations

import sys
from pathlib import Path

from jointwear.study.results import load_results

from .markup import format_number
from .reference_checks import FAIL, NA, PASS, reference_checks, reference_label, reference_of


def comparison_markdown(out_dir: Path | str) -> str:
    """A Markdown table: quantity | reference | jointwear | difference (relative; absolute for R) | band | status |
    note | source.

    Raises ``LookupError`` when the study in ``out_dir`` declares no reference.
    """
    results = load_results(Path(out_dir))
    ref = reference_of(results.config)
    if ref is None:
        raise LookupError(f"{out_dir}: the study's settings (config.json) declare no [reference]; nothing to compare")
    rows = [f"| quantity | {reference_label(ref)} | jointwear | difference (relative; absolute for R) | band | status "
            "| note | source |",
            "|---|---|---|---|---|---|---|---|"]
    for c in reference_checks(results, ref):
        unit = "" if c.unit in ("-", "") else f" {c.unit}"
        theirs = "-" if c.reference is None else format_number(c.reference, c.digits) + unit
        ours = "-" if c.ours is None else format_number(c.ours, c.digits) + unit
        rd = c.difference_text.replace("\u2014", "-")
        status = {PASS: "**pass**", FAIL: "**FAIL**", NA: "no data"}.get(c.status, c.status)
        rows.append(f"| {c.quantity} | {theirs} | {ours} | {rd} | {c.band} | {status} | "
                    f"{c.note.replace('|', '/')} | {c.source.replace('|', '/')} |")
    return "\n".join(rows) + "\n"


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1 or not Path(args[0]).is_dir():
        print("usage: python -m jointwear.report.compare RESULTS_DIR", file=sys.stderr)
        return 2
    try:
        sys.stdout.write(comparison_markdown(args[0]))
    except LookupError as exc:
        print(str(exc), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
