#!/usr/bin/env bash
# The reproduction grid as a Slurm job array. Each array task runs its share of one experiment
# preset: `sec-experiment run` reads SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT and
# SLURM_ARRAY_TASK_MIN and takes shard (ID - MIN + 1)/COUNT, so the tasks write disjoint runs.
# On a shared file system they write into one OUT folder; with node-local folders (OUT=/scratch/...),
# bring them together afterwards with `sec-experiment merge OUT-1 OUT-2 ... --into DIR`, which
# checks configurations and duplicates and lists the seeds still missing. Resumable: resubmit and
# finished runs are skipped, interrupted SEC/DQN/ERLAM runs continue from their checkpoints.
#
#   cargo build --release -p sec-tools --bin sec-experiment
#   sbatch --export=ALL,EXPERIMENT=exp1,SEEDS=1..20,EPISODES=5000 scripts/slurm-grid.sh
#   sbatch --array=1-4 --export=ALL,EXPERIMENT=exp2,EPISODES=5000 scripts/slurm-grid.sh
#
# Outside Slurm it runs as one shard of the array its SLURM_* variables describe (the test suite
# runs it so, crates/sec-tools/tests/cluster.rs).
#SBATCH --job-name=sec-grid
#SBATCH --array=1-8
#SBATCH --cpus-per-task=8
#SBATCH --mem-per-cpu=1G
#SBATCH --time=24:00:00
#SBATCH --output=slurm-%A_%a.out
set -euo pipefail
: "${EXPERIMENT:?set EXPERIMENT (exp1, exp2, ...: sec-experiment list)}"
BIN="${BIN:-./target/release/sec-experiment}"
OUT="${OUT:-results/experiments}"
args=(run "$EXPERIMENT" --seeds "${SEEDS:-1..20}" --episodes "${EPISODES:-5000}" --jobs "${SLURM_CPUS_PER_TASK:-1}" --out "$OUT")
if [ -n "${ONLY:-}" ]; then args+=(--only "$ONLY"); fi
echo "[slurm-grid] task ${SLURM_ARRAY_TASK_ID:-?} of ${SLURM_ARRAY_TASK_COUNT:-?} on $(hostname): $BIN ${args[*]}"
exec "$BIN" "${args[@]}"
