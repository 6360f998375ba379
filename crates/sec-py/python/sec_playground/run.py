"""SEC and its baselines from Python, with the RunConfig of the CLI and the page."""

import json
from typing import Any, Optional

from . import _core


class Run:
    """A run of `config` (a RunConfig as a dict: {"task": "double-t-maze", "kind": "sec",
    "agent": {...}}; missing fields take the defaults, the code preset) with `seed`. Each
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
        try:
            text = json.dumps(config, allow_nan=False)
        except (ValueError, TypeError) as e:
            raise ValueError(f"config: {e} (values must be numbers, strings, booleans, lists or dicts; no NaN or infinity)") from None
        self._run = _core.Run(text, seed)
        self.seed = seed

    @property
    def config(self) -> dict[str, Any]:
        """The configuration with every field filled in."""
        return json.loads(self._run.config())

    def episode(self) -> dict[str, Any]:
        return json.loads(self._run.episode())

    def episode_json(self) -> str:
        """The episode's metrics as the runner writes them (one JSON line)."""
        return self._run.episode()

    def episodes(self, n: int) -> list:
        return [self.episode() for _ in range(n)]
