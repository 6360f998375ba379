"""The paper's experiment grid on Ray: every (condition, seed) of an experiment preset as a Ray task.

Each task makes one run through the same Rust runner as ``sec-experiment run`` (the GIL released
while it plays), so the folder it writes is the CLI's, file for file: finished runs are skipped,
an interrupted run resumes from its checkpoint, and a task whose worker dies is retried. Without
``address`` a local Ray instance is started, so one command serves a laptop and a cluster::

    python -m sec_playground.grid run exp1 --only double-t-maze/SEC --seeds 1..20 --episodes 5000 \\
        --out results/experiments [--address auto]

DQN and ERLAM train with burn, which this package leaves out: their runs fail by name (make them
with ``sec-experiment run``). Ray is not a dependency of the package; install it (``pip install
ray``) to use this module.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Iterable
from pathlib import Path

from . import _core

__all__ = ["conditions", "run", "main"]

#: Times a task whose worker died (killed, out of memory, node lost) is tried again.
MAX_RETRIES = 3


def _seeds(seeds: str | int | Iterable[int]) -> str:
    """Seeds as the CLI's ``--seeds`` reads them: ``N``, ``A..B`` or ``A,B,C``."""
    if isinstance(seeds, str):
        return seeds
    if isinstance(seeds, int):
        return str(seeds)
    xs = [int(s) for s in seeds]
    if len(xs) == 1:
        return f"{xs[0]}..{xs[0]}"
    return ",".join(str(s) for s in xs)


def conditions(experiment: str, only: str | None = None) -> list[str]:
    """The condition names (``group/model``) of an experiment preset, cut to ``only``."""
    return _core.grid_conditions(experiment, only)


def _run_task(experiment: str, condition: str, seed: int, episodes: int, out: str, every: int) -> bool:
    # Module level, so a Ray worker imports it from the installed package.
    return _core.grid_run(experiment, condition, seed, episodes, out, every)


class _Progress:
    """One status line on stderr: runs done / running / failed, and the time left."""

    def __init__(self, total: int, slots: int, stream=sys.stderr, show: bool = True):
        self.total, self.slots, self.stream, self.show = total, max(1, slots), stream, show
        self.start = time.monotonic()
        self.done = self.failed = 0

    def line(self) -> str:
        left = self.total - self.done - self.failed
        running = min(left, self.slots)
        elapsed = time.monotonic() - self.start
        if self.done:
            eta = elapsed / self.done * left
            eta_text = f"{int(eta // 3600)}:{int(eta % 3600 // 60):02d}:{int(eta % 60):02d}"
        else:
            eta_text = "-"
        return f"[grid] {self.done}/{self.total} runs done, {running} running, {self.failed} failed, eta {eta_text}"

    def update(self) -> None:
        if self.show:
            end = "\r" if self.stream.isatty() else "\n"
            print(self.line(), end=end, file=self.stream, flush=True)


def run(
    experiment: str,
    *,
    out: str | os.PathLike = "results/experiments",
    seeds: str | int | Iterable[int] = "1..20",
    episodes: int = 5000,
    only: str | None = None,
    address: str | None = None,
    num_cpus: int | None = None,
    checkpoint_every: int = 50,
    progress: bool = True,
) -> dict:
    """Makes every (condition, seed) run of ``experiment`` under ``out/EXPERIMENT`` on Ray.

    ``seeds``, ``episodes``, ``only`` and ``checkpoint_every`` mean what the CLI's flags mean.
    ``address``: a running cluster (``"auto"``, ``"HOST:PORT"``); ``None`` starts a local
    instance with ``num_cpus`` CPUs (all by default). One CPU per task. Returns ``{"runs",
    "made", "skipped", "failed"}`` (``failed``: ``(condition, seed, error)``); raises
    ``RuntimeError`` after the other runs finish when any failed, and ``ValueError`` at once for
    a bad argument (nothing is started then).
    """
    import ray  # optional: only this module needs it

    seed_text = _seeds(seeds)
    seed_list = _core.grid_seeds(seed_text)
    names = _core.grid_conditions(experiment, only)
    if not isinstance(checkpoint_every, int) or checkpoint_every < 0:
        raise ValueError(f"checkpoint_every: {checkpoint_every!r} is not a whole number >= 0")
    if num_cpus is not None and (not isinstance(num_cpus, int) or num_cpus < 1):
        raise ValueError(f"num_cpus: {num_cpus!r} is not a whole number >= 1")
    out = str(Path(out))
    _core.grid_prepare(experiment, seed_text, episodes, out, only)
    # The CLI's order: seeds outer, conditions inner.
    jobs = [(c, s) for s in seed_list for c in names]
    started_here = not ray.is_initialized()
    if started_here:
        if address is None:
            ray.init(num_cpus=num_cpus, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    try:
        task = ray.remote(num_cpus=1, max_retries=MAX_RETRIES)(_run_task)
        pending = {
            task.remote(experiment, c, s, episodes, out, checkpoint_every): (c, s) for c, s in jobs
        }
        bar = _Progress(len(jobs), int(ray.cluster_resources().get("CPU", 1)), show=progress)
        made = skipped = 0
        failed: list[tuple[str, int, str]] = []
        bar.update()
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                c, s = pending.pop(ref)
                try:
                    played = ray.get(ref)
                    made += played
                    skipped += not played
                    bar.done += 1
                except Exception as e:  # a run's error, or a task out of retries
                    failed.append((c, s, str(e).strip().splitlines()[-1] if str(e).strip() else repr(e)))
                    bar.failed += 1
            bar.update()
        if progress and sys.stderr.isatty():
            print(file=sys.stderr)
    finally:
        if started_here:
            ray.shutdown()
    result = {"runs": len(jobs), "made": made, "skipped": skipped, "failed": failed}
    if failed:
        c, s, e = failed[0]
        raise RuntimeError(f"{len(failed)} run(s) failed; the first: {c} seed {s}: {e}")
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sec_playground.grid", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="make an experiment preset's runs on Ray")
    r.add_argument("experiment", help="an experiment preset (sec-experiment list)")
    r.add_argument("--only", help="comma-separated conditions, or groups ending in /")
    r.add_argument("--seeds", default="1..20", help="N, A..B or A,B,C (default 1..20)")
    r.add_argument("--episodes", type=int, default=5000, help="episodes per run (default 5000)")
    r.add_argument("--out", default="results/experiments", help="the results folder (default results/experiments)")
    r.add_argument("--address", help="a running Ray cluster: auto or HOST:PORT (default: start a local one)")
    r.add_argument("--num-cpus", type=int, help="CPUs of the local instance (default: all)")
    r.add_argument("--checkpoint-every", type=int, default=50, help="episodes between checkpoints (0: none)")
    sub.add_parser("list", help="the experiment presets' conditions")
    args = parser.parse_args(argv)
    try:
        if args.command == "list":
            for name in _core.EXPERIMENTS:
                print(name)
                for c in conditions(name):
                    print(f"  {c}")
            return 0
        t0 = time.monotonic()
        result = run(
            args.experiment,
            out=args.out,
            seeds=args.seeds,
            episodes=args.episodes,
            only=args.only,
            address=args.address,
            num_cpus=args.num_cpus,
            checkpoint_every=args.checkpoint_every,
        )
    except (ValueError, RuntimeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(
        f"{result['made']} runs made, {result['skipped']} already there, in {time.monotonic() - t0:.0f} s",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
