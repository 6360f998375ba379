"""An experiment preset on a Slurm cluster from Python, with submitit: one job per shard, each
running the Rust runner (`sec-experiment run ... --shard i/N`), so the files are the CLI's own.
Without Slurm (or with --local) submitit runs the jobs as local processes, which is how the test
suite runs it. Finished runs are skipped and interrupted ones resume, so resubmitting is safe;
bring node-local folders together with `sec-experiment merge`.

    cargo build --release -p sec-tools --bin sec-experiment
    python submitit_grid.py exp1 --shards 8 --seeds 1..20 --episodes 5000 --partition cpu
"""

import argparse
import subprocess

import submitit


def shard(binary, experiment, i, n, seeds, episodes, out, jobs):
    """One shard of the grid: the runner's own command, its standard error returned."""
    cmd = [binary, "run", experiment, "--shard", f"{i}/{n}", "--seeds", seeds, "--episodes", str(episodes),
           "--jobs", str(jobs), "--out", out]
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stderr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("experiment")
    ap.add_argument("--bin", default="./target/release/sec-experiment")
    ap.add_argument("--shards", type=int, default=8)
    ap.add_argument("--seeds", default="1..20")
    ap.add_argument("--episodes", type=int, default=5000)
    ap.add_argument("--out", default="results/experiments")
    ap.add_argument("--cpus", type=int, default=8, help="CPUs per job (the runner's --jobs)")
    ap.add_argument("--partition", default=None)
    ap.add_argument("--hours", type=int, default=24)
    ap.add_argument("--logs", default="submitit-logs")
    ap.add_argument("--local", action="store_true", help="run the jobs as local processes")
    args = ap.parse_args(argv)
    executor = submitit.LocalExecutor(folder=args.logs) if args.local else submitit.AutoExecutor(folder=args.logs)
    params = {"timeout_min": args.hours * 60, "cpus_per_task": args.cpus}
    if args.partition and not args.local:
        params["slurm_partition"] = args.partition
    executor.update_parameters(**params)
    jobs = [
        executor.submit(shard, args.bin, args.experiment, i, args.shards, args.seeds, args.episodes, args.out, args.cpus)
        for i in range(1, args.shards + 1)
    ]
    for i, job in enumerate(jobs, 1):
        print(f"shard {i}/{args.shards} (job {job.job_id}): {job.result().strip().splitlines()[-1]}")
    return jobs


if __name__ == "__main__":
    main()
