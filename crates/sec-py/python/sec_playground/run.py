"""SEC and its baselines from Python, with the RunConfig of the CLI and the page."""

import json
from typing import Any, Optional

from . import _core


class Run:
    """A run of `config` (a RunConfig as a dict: {"task": "double-t-maze",
    "agent": {"memory": {"tau": 0.5}}}; missing fields take the defaults, the code preset) with
    `seed`. Its `kind` and `mfec.embedding` pick the agent: `sec_playground.agents()` lists each
    agent's `kind` and `mfecEmbedding`. Each
    `episode()` plays one episode and returns the metrics the runner's JSON lines hold."""

    def __init__(self, config: Optional[dict[str, Any]] = None, seed: int = 0):
        if config is None:
            config = {}
        if not isinstance(config, dict):
            raise ValueError(f"config: {type(config).__name__} is not a dict (a RunConfig)")
        if not isinstance(seed, int) or isinstance(seed, bool):
            raise ValueError(f"seed: {seed!r} is not an integer")
        if not 0 <= seed <= _core.MAX_SEED:
            raise ValueError(f"seed: {seed} is out of range 0..={_core.MAX_SEED}")
        self._run = _core.Run(_config_json(config), seed)
        self.seed = seed

    @property
    def config(self) -> dict[str, Any]:
        """The configuration with every field filled in."""
        return json.loads(self._run.config())

    def configure(self, config: dict[str, Any]) -> str:
        """Applies a new configuration: "live" when only live parameters changed (SEC's
        thresholds, alpha, beta, tau, m, ...; they act from the next decision), else "restart"
        (a new run with the same seed). A refused value raises ValueError and changes nothing."""
        if not isinstance(config, dict):
            raise ValueError(f"config: {type(config).__name__} is not a dict (a RunConfig)")
        return self._run.configure(_config_json(config))

    def episode(self) -> dict[str, Any]:
        """Plays the current episode to its end; its metrics (the runner's JSON line as a dict)."""
        return json.loads(self._run.episode())

    def episode_json(self) -> str:
        """The episode's metrics as the runner writes them (one JSON line)."""
        return self._run.episode()

    def episodes(self, n: int) -> list:
        """Plays `n` episodes; their metrics."""
        return [self.episode() for _ in range(n)]

    def decisions(self, n: int) -> list:
        """Runs `n` decisions (1..=100000); the metrics of the episodes they finished."""
        if not isinstance(n, int) or isinstance(n, bool) or not 1 <= n <= 100_000:
            raise ValueError(f"n: {n!r} is out of range 1..=100000")
        return [json.loads(line) for line in self._run.decisions(n)]

    def view(self) -> dict[str, Any]:
        """The last decision and the run's state, with the page's field names: action, layer
        ("R" reactive, "C" contextual, "H" a person), selected, entropy, p, gateMse, ltm,
        capacity, episode, step, episodeReward, x, z, heading, decisions, minSequences, gate,
        embedding."""
        return json.loads(self._run.view())

    def explain(self) -> dict[str, Any]:
        """The last decision's contextual layer term by term, as the page's "explain this
        decision": couplets (sequence, position, g, t, rr, d, action, value), q and p per
        action, and tau, valueFunction, thetaAbs, thetaProp, sequentialBias."""
        return json.loads(self._run.explain())


def _config_json(config: dict[str, Any]) -> str:
    try:
        return json.dumps(config, allow_nan=False)
    except (ValueError, TypeError) as e:
        raise ValueError(
            f"config: {e} (values must be numbers, strings, booleans, lists or dicts; no NaN or infinity)"
        ) from None
