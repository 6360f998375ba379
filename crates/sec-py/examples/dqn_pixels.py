"""A pixel agent trained with the usual Gymnasium loop: a small DQN in numpy alone (no deep
learning library), on the camera of one of the paper's tasks.

    python dqn_pixels.py --env SecPlayground/Cylinder-v0 --episodes 200

The network sees the 84x84 camera pooled to 21x21 grey levels, has one hidden layer of 64 ReLU
units and is trained with experience replay, a target network and epsilon-greedy exploration.
It prints the reward per episode with its 20-episode mean as a text curve and, with --csv,
writes the curve. Small on purpose: it shows the loop, not the paper's DQN (crates/sec-dqn).
"""

import argparse
import csv

import gymnasium as gym
import numpy as np

import sec_playground  # noqa: F401  (registers the environments)


def features(obs: np.ndarray) -> np.ndarray:
    """84x84x3 bytes -> 441 grey levels in [0, 1] (4x4 average pooling)."""
    grey = obs.astype(np.float32).mean(axis=2) / 255.0
    return grey.reshape(21, 4, 21, 4).mean(axis=(1, 3)).reshape(-1)


class QNet:
    """One hidden layer, Q-values for the nine actions; plain SGD on the squared TD error."""

    def __init__(self, rng, n_in=441, hidden=64, n_out=9):
        self.w1 = rng.normal(0, np.sqrt(2 / n_in), (n_in, hidden)).astype(np.float32)
        self.b1 = np.zeros(hidden, np.float32)
        self.w2 = rng.normal(0, np.sqrt(1 / hidden), (hidden, n_out)).astype(np.float32)
        self.b2 = np.zeros(n_out, np.float32)

    def params(self):
        return [self.w1, self.b1, self.w2, self.b2]

    def copy_from(self, other):
        for p, q in zip(self.params(), other.params()):
            p[...] = q

    def __call__(self, x):
        h = np.maximum(x @ self.w1 + self.b1, 0)
        return h @ self.w2 + self.b2, h

    def train(self, x, actions, targets, lr):
        q, h = self(x)
        grad_q = np.zeros_like(q)
        rows = np.arange(len(actions))
        grad_q[rows, actions] = (q[rows, actions] - targets) / len(actions)
        grad_h = (grad_q @ self.w2.T) * (h > 0)
        self.w2 -= lr * h.T @ grad_q
        self.b2 -= lr * grad_q.sum(0)
        self.w1 -= lr * x.T @ grad_h
        self.b1 -= lr * grad_h.sum(0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--env", default="SecPlayground/Cylinder-v0")
    ap.add_argument("--episodes", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--csv", help="write episode,reward,mean20 here")
    args = ap.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    env = gym.make(args.env, frame_skip=4)
    q, target = QNet(rng), QNet(rng)
    target.copy_from(q)
    size, gamma, lr, batch = 20_000, 0.99, 0.01, 32
    xs = np.zeros((size, 441), np.float32)
    xs2 = np.zeros((size, 441), np.float32)
    acts = np.zeros(size, np.int64)
    rews = np.zeros(size, np.float32)
    dones = np.zeros(size, np.float32)
    n, steps, returns = 0, 0, []
    obs, _ = env.reset(seed=args.seed)
    for episode in range(args.episodes):
        x, total, done = features(obs), 0.0, False
        while not done:
            eps = max(0.05, 1.0 - steps / 5000)
            a = int(rng.integers(9)) if rng.random() < eps else int(np.argmax(q(x[None])[0]))
            obs, r, terminated, truncated, _ = env.step(a)
            x2 = features(obs)
            i = n % size
            xs[i], xs2[i], acts[i], rews[i], dones[i] = x, x2, a, r, float(terminated)
            n, steps, total, x = n + 1, steps + 1, total + r, x2
            done = terminated or truncated
            if n >= batch:
                j = rng.integers(0, min(n, size), batch)
                best = target(xs2[j])[0].max(axis=1)
                q.train(xs[j], acts[j], rews[j] + gamma * (1 - dones[j]) * best, lr)
            if steps % 500 == 0:
                target.copy_from(q)
        returns.append(total)
        obs, _ = env.reset()
        mean = float(np.mean(returns[-20:]))
        bar = "#" * int(max(0.0, mean) * 20)
        print(f"episode {episode:4d}  reward {total:7.3f}  mean20 {mean:7.3f}  {bar}", flush=True)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["episode", "reward", "mean20"])
            for k, r in enumerate(returns):
                w.writerow([k, r, float(np.mean(returns[max(0, k - 19) : k + 1]))])
    return returns


if __name__ == "__main__":
    main()
