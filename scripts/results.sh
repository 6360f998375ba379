#!/usr/bin/env bash
# Regenerates everything the docs and the page show from the runs in results/experiments: each
# experiment's report.md, summary.csv and plots/, results/orderings.md, the perception matching
# analysis, the comparison with the authors' runs (the tables REPRODUCTION.md quotes are rewritten
# there) and the page's reference curves (assets/reference/), after checking that every pair of
# runs of one configuration and seed agrees. Run it before committing new runs, so that runs and
# reports agree.
#   BIN=/some/copy/of/sec-experiment ./scripts/results.sh   # no rebuild
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
OUT="${OUT:-results/experiments}"
# BIN=/a/pinned/sec-experiment: the binary the grid runs with, without a rebuild.
if [ -z "${BIN:-}" ]; then cargo build --release -p sec-tools --bin sec-experiment; fi
bin="${BIN:-./target/release/sec-experiment}"
# PARTIAL=1: report on folders whose planned runs are not all finished (the reports refuse them
# otherwise, naming what is missing).
partial=${PARTIAL:+--partial}
"$bin" verify --out "$OUT"
for exp in "$OUT"/*/; do
    exp=$(basename "$exp")
    [ -f "$OUT/$exp/experiment.json" ] && "$bin" report "$exp" --out "$OUT" --quote REPRODUCTION.md $partial > /dev/null
done
"$bin" orderings --out "$OUT" --quote REPRODUCTION.md $partial > /dev/null
"$bin" matching --out "$OUT" --quote REPRODUCTION.md > /dev/null
"$bin" versus-authors --out "$OUT" --quote REPRODUCTION.md > /dev/null
"$bin" surfaces --out "$OUT" --quote REPRODUCTION.md > /dev/null
"$bin" reference --out "$OUT" $partial
