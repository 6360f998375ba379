"""Logging with Gymnasium's RecordEpisodeStatistics, as CleanRL- and SB3-style scripts do:
`info["episode"]["r"]` and `["l"]` at every episode end, from a vector env of the arenas.

    python record_stats.py --num-envs 8 --steps 2000
"""

import argparse

import gymnasium as gym
import numpy as np
from gymnasium.wrappers.vector import RecordEpisodeStatistics

import sec_playground  # noqa: F401  (registers the environments)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--env", default="SecPlayground/ObjectPermanence-v0")
    ap.add_argument("--num-envs", type=int, default=8)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--max-episode-steps", type=int, default=250)
    args = ap.parse_args(argv)
    envs = RecordEpisodeStatistics(
        gym.make_vec(args.env, num_envs=args.num_envs, frame_skip=4, max_episode_steps=args.max_episode_steps)
    )
    envs.reset(seed=1)
    rng = np.random.default_rng(1)
    logged = []
    for step in range(args.steps):
        _, _, _, _, info = envs.step(rng.integers(0, 9, args.num_envs))
        if "episode" in info:
            for i in np.flatnonzero(info["_episode"]):
                r, length = float(info["episode"]["r"][i]), int(info["episode"]["l"][i])
                logged.append((r, length))
                print(f"step {step}: env {i} episode return {r:.3f}, length {length}, success {bool(info['success'][i])}")
    print(f"{len(logged)} episodes logged")
    return logged


if __name__ == "__main__":
    main()
