#!/usr/bin/env bash
# Runs the reproduction grid of results/PROTOCOL.md on all cores (or one shard of it), then writes
# every report: each experiment's report.md, summary.csv and plots/, results/orderings.md, the
# perception analysis and the page's reference curves (assets/reference/). Resumable: run it again after an interruption and it skips finished runs.
# A condition another experiment already ran (exp1's double T-maze SEC is exp2's m = 500, exp3's
# default, ...) is copied from its finished runs, not played again (`sec-experiment run --reuse`).
#   SCALE=2 ./scripts/reproduce.sh      # every seeds x episodes of the protocol multiplied by 2
#   SHARD=2/4 ./scripts/reproduce.sh    # one machine's quarter of the grid (copy the trees together)
#   JOBS=1 nice -n 19 ./scripts/reproduce.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
SHARD="${SHARD:-1/1}"
OUT="${OUT:-results/experiments}"
SCALE="${SCALE:-1}"
JOBS="${JOBS:-$(nproc)}"
cargo build --release -p sec-tools --bin sec-experiment
# BIN: a copy of the binary, so that rebuilding while the grid runs changes nothing under it.
bin="${BIN:-./target/release/sec-experiment}"
run() { # EXPERIMENT SEEDS EPISODES [--only ...]
    local exp=$1 seeds=$(( $2 * SCALE )) episodes=$(( $3 * SCALE ))
    shift 3
    "$bin" run "$exp" --seeds "1..$seeds" --episodes "$episodes" --shard "$SHARD" --jobs "$JOBS" --out "$OUT" "$@"
}
run exp1 20 2000 --only double-t-maze/SEC,double-t-maze/NSEC
run exp1 5 2000 --only double-t-maze/MFEC-ae,double-t-maze/MFEC-rp,double-t-maze/reactive
run heading 5 2000
# The deep baselines before exp2: their runs take hours and continue from their checkpoints.
run exp1 3 1000 --only double-t-maze/DQN,double-t-maze/ERLAM
# ERLAM merging on the raw bottleneck (no D17 scale): one seed, a sensitivity row.
run exp1 1 1000 --only double-t-maze/ERLAM-raw
# ERLAM whose propagation stops at terminal nodes: one seed, a test of why ERLAM fails here.
run exp1 1 1000 --only double-t-maze/ERLAM-noPastTerminals
run exp2 10 2000
others=""
for task in detour cylinder object-permanence; do
    for model in SEC NSEC MFEC-ae; do others="$others,$task/$model"; done
done
run exp1 10 1000 --only "${others#,}"
run exp3 10 2000
run exp4 10 2000
run perception 6 2000
OUT="$OUT" ./scripts/results.sh
