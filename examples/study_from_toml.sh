#!/usr/bin/env bash
# The whole study of your own mechanism from its TOML file: dynamics, wear, R(N), life, sensitivity, report.
#   bash examples/study_from_toml.sh [CONFIG] [OUT]
# Check the config first (every problem is listed; nothing is written), then whether the wear history's numerical
# settings are fine enough for this mechanism (each refined 2x; the report shows the verdicts), then run everything.
set -euo pipefail
CONFIG="${1:-$(dirname "$0")/my_linkage.toml}"
OUT="${2:-my_linkage_results}"
jointwear check "$CONFIG" > /dev/null
jointwear converge "$CONFIG" --out "$OUT"
jointwear run "$CONFIG" --out "$OUT"
echo "open $OUT/report.html"
