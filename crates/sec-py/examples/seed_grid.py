"""A seed grid of SEC and NSEC runs on all cores with multiprocessing: each worker builds its
`Run` from a plain config dict (a run is a pure function of its configuration and seed, so the
grid gives the same numbers on any machine and any number of workers).

    python seed_grid.py --task double-t-maze --seeds 10 --episodes 300
"""

import argparse
import multiprocessing as mp

import numpy as np

from sec_playground import Run


def one(job):
    model, task, seed, episodes = job
    config = {"task": task, "agent": {"memory": {"sequentialBias": model == "SEC"}}}
    rewards = [m["reward"] for m in Run(config, seed=seed).episodes(episodes)]
    return model, seed, float(np.mean(rewards))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--task", default="double-t-maze")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--episodes", type=int, default=300)
    ap.add_argument("--workers", type=int, default=mp.cpu_count())
    args = ap.parse_args(argv)
    jobs = [(m, args.task, s, args.episodes) for m in ("SEC", "NSEC") for s in range(1, args.seeds + 1)]
    with mp.get_context("spawn").Pool(args.workers) as pool:
        results = pool.map(one, jobs)
    for model in ("SEC", "NSEC"):
        per_seed = [r for m, _, r in results if m == model]
        print(f"{model}: mean reward per episode {np.mean(per_seed):.3f} over {len(per_seed)} seeds "
              f"({', '.join(f'{r:.2f}' for r in per_seed)})")
    return results


if __name__ == "__main__":
    main()
