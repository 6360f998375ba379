#!/usr/bin/env bash
# Runs the paper's four experiments at full scale (20 seeds x 5000 episodes, as the paper) on all
# cores, then writes each report (report.md, summary.csv, plots/) under results/experiments/.
# Resumable: run it again after an interruption and it skips the finished runs.
#   SEEDS=5 EPISODES=500 ./scripts/reproduce.sh     # a smaller scale
#   SHARD=2/4 ./scripts/reproduce.sh                # one machine's quarter of the grid
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
SEEDS="${SEEDS:-1..20}"
EPISODES="${EPISODES:-5000}"
SHARD="${SHARD:-1/1}"
OUT="${OUT:-results/experiments}"
cargo build --release -p sec-tools --bin sec-experiment
for exp in ${EXPERIMENTS:-exp1 exp2 exp3 exp4}; do
    ./target/release/sec-experiment run "$exp" --seeds "$SEEDS" --episodes "$EPISODES" --shard "$SHARD" --out "$OUT"
    ./target/release/sec-experiment report "$exp" --out "$OUT" > /dev/null
done
