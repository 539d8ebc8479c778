"""The comparison with the paper as a Markdown table, for docs/paper-comparison.md.

    python -m jointwear.report.compare results        # prints the table of the study in results/

Same numbers, bands and statuses as the report's "Comparison with the paper" section
(:func:`jointwear.report.html.paper_checks`).
"""

from __future__ import annotations

import sys
from pathlib import Path

from .html import FAIL, NA, PASS, _num, paper_checks, read_inputs


def comparison_markdown(out_dir: Path | str) -> str:
    """A Markdown table: quantity | paper | this study | relative difference | band | status | note."""
    checks = paper_checks(read_inputs(Path(out_dir)).data)
    rows = ["| quantity | paper | jointwear | relative difference | band | status | note |",
            "|---|---|---|---|---|---|---|"]
    for c in checks:
        unit = "" if c.unit in ("-", "") else f" {c.unit}"
        paper = "-" if c.paper is None else _num(c.paper, c.digits) + unit
        ours = "-" if c.ours is None else _num(c.ours, c.digits) + unit
        rd = "-" if c.rel_diff is None else f"{c.rel_diff * 100:+.1f} %"
        status = {PASS: "**pass**", FAIL: "**FAIL**", NA: "no data"}.get(c.status, c.status)
        rows.append(f"| {c.quantity} | {paper} | {ours} | {rd} | {c.band} | {status} | "
                    f"{c.note.replace('|', '/')} |")
    return "\n".join(rows) + "\n"


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1 or not Path(args[0]).is_dir():
        print("usage: python -m jointwear.report.compare RESULTS_DIR", file=sys.stderr)
        return 2
    sys.stdout.write(comparison_markdown(args[0]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
