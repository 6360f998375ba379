#!/usr/bin/env bash
# Runs the reproduction grid of results/PROTOCOL.md on all cores (or one shard of it), then writes
# every report: each experiment's report.md, summary.csv and plots/, results/orderings.md, the
# perception analysis, the comparison with the authors' runs and the page's reference curves
# (assets/reference/). Resumable: run it again after an interruption and it skips finished runs.
# A condition another experiment already ran (exp1's double T-maze SEC is exp2's m = 500, exp3's
# default, ...) is copied from its finished runs, not played again (`sec-experiment run --reuse`);
# a shorter run is the head of a longer one, so it is cut from it.
#   ./scripts/reproduce.sh horizon     # only the 5000-episode block (PROTOCOL.md, 2026-12-03)
#   ./scripts/reproduce.sh protocol    # only the first protocol's grid (2000 episodes)
#   ./scripts/reproduce.sh textured    # only the textured grid (PROTOCOL.md, 2026-12-06)
#   SCALE=2 ./scripts/reproduce.sh      # every seeds x episodes of the protocol multiplied by 2
#   SHARD=2/4 ./scripts/reproduce.sh    # one machine's quarter of the grid (merge the trees after)
#   JOBS=1 nice -n 19 ./scripts/reproduce.sh
#   BIN=/some/copy/of/sec-experiment ./scripts/reproduce.sh   # a pinned binary: rebuilding while
#                                                             # the grid runs changes nothing under it
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
SHARD="${SHARD:-1/1}"
OUT="${OUT:-results/experiments}"
SCALE="${SCALE:-1}"
JOBS="${JOBS:-$(nproc)}"
BLOCK="${1:-all}"
case "$BLOCK" in all|horizon|protocol|textured) ;; *) echo "reproduce.sh: '$BLOCK' is not all, horizon, protocol or textured" >&2; exit 2 ;; esac
if [ -z "${BIN:-}" ]; then cargo build --release -p sec-tools --bin sec-experiment; fi
bin="${BIN:-./target/release/sec-experiment}"
run() { # EXPERIMENT SEEDS EPISODES [--only ...]
    local exp=$1 seeds=$(( $2 * SCALE )) episodes=$(( $3 * SCALE ))
    shift 3
    "$bin" run "$exp" --seeds "1..$seeds" --episodes "$episodes" --shard "$SHARD" --jobs "$JOBS" --out "$OUT" "$@"
}
dtm() { local IFS=,; local out=(); for m in "$@"; do out+=("double-t-maze/$m"); done; echo "${out[*]}"; }
others() { local out=""; for task in detour cylinder object-permanence; do for m in "$@"; do out="$out,$task/$m"; done; done; echo "${out#,}"; }

if [ "$BLOCK" = all ] || [ "$BLOCK" = horizon ]; then
    # The paper's horizon, first: the protocol's shorter runs of these conditions are its heads.
    run exp1 10 5000 --only "$(dtm SEC NSEC MFEC-ae MFEC-rp reactive)"
    run exp1 20 5000 --only "$(dtm SEC NSEC)"
    run exp2 10 5000
    run exp1 3 1000 --only "$(dtm ERLAM-5k)"
    run exp4 10 5000
    run exp1 10 5000 --only "$(others SEC NSEC MFEC-ae)"
fi
if [ "$BLOCK" = all ] || [ "$BLOCK" = protocol ]; then
    run exp1 20 2000 --only "$(dtm SEC NSEC)"
    run exp1 5 2000 --only "$(dtm MFEC-ae MFEC-rp reactive)"
    run heading 5 2000
    # The deep baselines before exp2: their runs take hours and continue from their checkpoints.
    run exp1 3 1000 --only "$(dtm DQN ERLAM)"
    # ERLAM merging on the raw bottleneck (no D17 scale): one seed, a sensitivity row.
    run exp1 1 1000 --only "$(dtm ERLAM-raw)"
    # ERLAM whose propagation stops at terminal nodes: one seed, a test of why ERLAM fails here.
    run exp1 1 1000 --only "$(dtm ERLAM-noPastTerminals)"
    run exp2 10 2000
    run exp1 10 1000 --only "$(others SEC NSEC MFEC-ae)"
    run exp3 10 2000
    run exp4 10 2000
    run perception 6 2000
fi
if [ "$BLOCK" = all ] || [ "$BLOCK" = textured ]; then
    # The textured grid (PROTOCOL.md, 2026-12-06): the double T-maze first, ten seeds of every
    # model, then SEC's and NSEC's seeds 11..20; the other tasks as their textured models come.
    run textured 10 5000 --only "$(dtm SEC NSEC MFEC-ae MFEC-rp reactive)"
    run textured 20 5000 --only "$(dtm SEC NSEC)"
fi
# The reports quote into REPRODUCTION.md and write results/ and assets/reference/: only from the
# repository's own runs. Runs made elsewhere (OUT=...) are copied in first, then reported.
if [ "$(realpath -m "$OUT")" = "$(realpath -m results/experiments)" ]; then
    ./scripts/results.sh
else
    echo "reproduce.sh: runs are in $OUT; copy the finished ones into results/experiments, then run ./scripts/results.sh"
fi
