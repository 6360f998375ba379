"""SEC and its baselines from Python, with the RunConfig of the CLI and the page."""

import json
import math
import os
from typing import Any, Optional

from . import _core
from .envs import _read_yaml, integer


class Run:
    """A run of `config` (a RunConfig as a dict: {"task": "double-t-maze",
    "agent": {"memory": {"tau": 0.5}}}; missing fields take the defaults, the code preset) with
    `seed`. Its `kind` and `mfec.embedding` pick the agent: `sec_playground.agents()` lists each
    agent's `kind` and `mfecEmbedding`. Each
    `episode()` plays one episode and returns the metrics the runner's JSON lines hold.

    `yaml_path`: an Animal-AI arena file (one of the Olympics arenas in the repository's
    `assets/arenas/competition/`, or your own) played instead of the task, named by the file's
    stem; no model was trained on it, so the run embeds with the untrained encoder and SEC's
    reconstruction gate is off (the configuration's `arena`, `perception` and `agent.gate`)."""

    def __init__(self, config: Optional[dict[str, Any]] = None, seed: int = 0, yaml_path=None, **settings: Any):
        if config is None:
            config = {}
        if not isinstance(config, dict):
            raise ValueError(f"config: {type(config).__name__} is not a dict (a RunConfig)")
        seed = integer("seed", seed, 0, _core.MAX_SEED)
        if yaml_path is not None:
            yaml = _read_yaml(yaml_path)
            name = os.path.splitext(os.path.basename(os.fspath(yaml_path)))[0]
            arena = json.loads(_core.with_arena(_config_json(config), name, yaml))
            # What the caller wrote wins (a trained encoder or a gate asked for is then refused,
            # naming it), over what the arena's run otherwise takes.
            _merge(arena, config)
            config = arena
        if settings:
            config = json.loads(_core.apply_settings(_config_json(config), _setting_pairs(settings)))
        self._run = _core.Run(_config_json(config), seed)
        self.seed = seed
        # What rebuilds the run when its agent does not checkpoint: the first configuration and
        # every call since (a run is a pure function of them), consecutive episodes counted.
        self._first = _config_json(config)
        self._base = None  # (configuration, checkpoint, decisions, episodes) the calls start from, if any
        self._calls: list = []

    @property
    def config(self) -> dict[str, Any]:
        """The configuration with every field filled in."""
        return json.loads(self._run.config())

    def configure(self, config: Optional[dict[str, Any]] = None, **settings: Any) -> dict[str, Any]:
        """Changes the fields `config` names (a partial RunConfig: {"agent": {"memory": {"tau":
        0.5}}}); every field it leaves out keeps its value. Returns {"applied": "live" or
        "restart", "changed": [{"field", "from", "to", "live"}]}: "live" when only live
        parameters changed (SEC's thresholds, alpha, beta, tau, m, ...; they act from the next
        decision), else "restart" (a new run with the same seed); each changed field with its
        path, old and new values, and whether a change of it alone acts live. A refused value
        raises ValueError naming it and changes nothing."""
        if config is None:
            config = {}
        if not isinstance(config, dict):
            raise ValueError(f"config: {type(config).__name__} is not a dict (a partial RunConfig)")
        if settings:
            # The page's keys (`tau=0.5`), applied by the core's settings table onto the fields
            # `config` changes; the whole result goes in as the change.
            merged = json.loads(self._run.config())
            _merge(merged, config)
            config = json.loads(_core.apply_settings(_config_json(merged), _setting_pairs(settings)))
        text = _config_json(config)
        applied = json.loads(self._run.configure(text))
        self._calls.append(("configure", text))
        return applied

    def episode(self) -> dict[str, Any]:
        """Plays the current episode to its end; its metrics (the runner's JSON line as a dict).
        "rawReward" is the episode's return as a Gymnasium loop sums it: the goal's reward plus
        the penalty of every env step (-1/t each), so -1.0 for an episode that times out;
        "reward" is the paper's tables' value, rawReward when positive and 0.0 otherwise."""
        return json.loads(self.episode_json())

    def episode_json(self) -> str:
        """The episode's metrics as the runner writes them (one JSON line)."""
        line = self._run.episode()
        self._count("episode", 1)
        return line

    def _count(self, call: str, n: int) -> None:
        if self._calls and self._calls[-1][0] == call:
            self._calls[-1] = (call, self._calls[-1][1] + n)
        else:
            self._calls.append((call, n))

    def episodes(self, n: int) -> list:
        """Plays `n` episodes (0..=1000000); their metrics."""
        n = integer("n", n, 0, 1_000_000)
        return [self.episode() for _ in range(n)]

    def decisions(self, n: int) -> list:
        """Runs `n` decisions (1..=100000); the metrics of the episodes they finished."""
        n = integer("n", n, 1, 100_000)
        done = [json.loads(line) for line in self._run.decisions(n)]
        self._count("decisions", n)
        return done

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


    def __getstate__(self) -> dict:
        """Pickling (and `copy.deepcopy`): between two episodes a run whose agent checkpoints
        (SEC, NSEC) travels as its checkpoint, the runner's own format; otherwise (mid-episode,
        MFEC, the reactive walk) as its last checkpoint (or its first configuration) and the
        calls since, replayed on unpickling (a run is a pure function of them). Either way it
        continues bit for bit; only `view()`'s last decision is not kept (none until the next)."""
        try:
            checkpoint, decisions, episodes = self._run.checkpoint()
            base, calls = (self._run.config(), checkpoint, decisions, episodes), []
        except ValueError:
            base, calls = self._base, list(self._calls)
        return {"seed": self.seed, "first": self._first, "base": base, "calls": calls}

    def __setstate__(self, state: dict) -> None:
        self.seed, self._first, self._base = state["seed"], state["first"], state["base"]
        if self._base is None:
            self._run = _core.Run(self._first, self.seed)
        else:
            config, checkpoint, decisions, episodes = self._base
            self._run = _core.Run.resume(config, self.seed, checkpoint, decisions, episodes)
        self._calls = []
        for call, arg in state["calls"]:
            if call == "configure":
                self._run.configure(arg)
                self._calls.append((call, arg))
            elif call == "episode":
                for _ in range(arg):
                    self._run.episode()
                self._count(call, arg)
            else:
                self._run.decisions(arg)
                self._count(call, arg)


def _setting_pairs(settings: dict[str, Any]) -> list:
    """Keyword arguments as the page's settings: (key, value as the URL hash writes it)."""
    pairs = []
    for key, value in settings.items():
        if isinstance(value, bool):
            text = "1" if value else "0"
        elif isinstance(value, (int, float, str)):
            text = str(value)
        else:
            raise ValueError(f"{key}: {value!r} is not a number, a string or a boolean")
        pairs.append((key, text))
    return pairs


def _merge(into: dict, change: dict) -> None:
    for k, v in change.items():
        if isinstance(v, dict) and isinstance(into.get(k), dict):
            _merge(into[k], v)
        else:
            into[k] = v


def _config_json(config: dict[str, Any]) -> str:
    bad = _not_json(config, "")
    if bad:
        raise ValueError(bad)
    return json.dumps(config, allow_nan=False)


def _not_json(value: Any, path: str) -> Optional[str]:
    """Why `value` (at `path`, dotted) is not a JSON value of a configuration, or None."""
    where = path or "config"
    if isinstance(value, dict):
        for k, v in value.items():
            if not isinstance(k, str):
                return f"{where}: key {k!r} is not a string"
            bad = _not_json(v, f"{path}.{k}" if path else k)
            if bad:
                return bad
        return None
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            bad = _not_json(v, f"{where}[{i}]")
            if bad:
                return bad
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return f"{where}: {'NaN' if math.isnan(value) else value} is not a finite number"
    if value is None or isinstance(value, (str, bool, int, float)):
        return None
    return f"{where}: {value!r} ({type(value).__name__}) is not a number, string, boolean, list or dict"
