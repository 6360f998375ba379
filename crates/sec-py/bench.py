"""The Python package's speed (BENCHMARKS.md, "From Python"): env steps/s of one arena through
`ArenaEnv.step` (each step physics plus the 84x84 camera frame it returns), of the package's
vector env at several sizes beside Gymnasium's own SyncVectorEnv and AsyncVectorEnv of the same
arenas, and physics-only steps/s via frame_skip (one frame rendered per 4 env steps).

    ./scripts/python-test.sh && target/py-venv/bin/python crates/sec-py/bench.py
"""

import time

import gymnasium as gym
import numpy as np

from sec_playground import ArenaEnv, ArenaVectorEnv

SCRIPT = [3, 3, 1, 3, 2, 3, 0, 3]  # rust's BENCH_SCRIPT: forward, turns, a pause


def single(task, frame_skip, steps):
    env = ArenaEnv(task, frame_skip=frame_skip)
    env.reset(seed=1)
    t0 = time.perf_counter()
    for i in range(steps):
        _, _, term, trunc, _ = env.step(SCRIPT[i % len(SCRIPT)])
        if term or trunc:
            env.reset()
    return steps / (time.perf_counter() - t0)


def vector(task, n, steps):
    env = ArenaVectorEnv(n, task=task)
    env.reset(seed=1)
    actions = [np.full(n, a, np.int64) for a in SCRIPT]
    t0 = time.perf_counter()
    for i in range(steps):
        env.step(actions[i % len(SCRIPT)])
    return n * steps / (time.perf_counter() - t0)


def gym_vector(kind, task, n, steps):
    """Gymnasium's SyncVectorEnv or AsyncVectorEnv (one process per arena) of `ArenaEnv`s."""
    make = [lambda: ArenaEnv(task) for _ in range(n)]
    env = gym.vector.SyncVectorEnv(make) if kind == "sync" else gym.vector.AsyncVectorEnv(make)
    env.reset(seed=1)
    actions = [np.full(n, a, np.int64) for a in SCRIPT]
    t0 = time.perf_counter()
    for i in range(steps):
        env.step(actions[i % len(SCRIPT)])
    rate = n * steps / (time.perf_counter() - t0)
    env.close()
    return rate


def main():
    for task in ["double-t-maze", "cylinder"]:
        print(f"{task}: one env, a frame per step: {single(task, 1, 20000):,.0f} steps/s (frames/s)")
        fs = single(task, 4, 5000)
        print(f"{task}: one env, frame_skip 4: {fs * 4:,.0f} env steps/s ({fs:,.0f} frames/s)")
        for n in [1, 2, 16]:
            print(f"{task}: vector env of {n}: {vector(task, n, 20000 // n):,.0f} steps/s (frames/s)")
            for kind in ["sync", "async"]:
                print(f"{task}: gymnasium {kind} vector env of {n}: {gym_vector(kind, task, n, 20000 // n):,.0f} steps/s")


if __name__ == "__main__":
    main()
