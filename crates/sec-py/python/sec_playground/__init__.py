"""SEC Playground from Python: the Animal-AI arenas of Freire, Amil & Verschure's "Sequential
memory improves sample and memory efficiency in Episodic Control" as Gymnasium environments,
SEC, NSEC, MFEC and the reactive walk as runs, and the bundled encoders.

    >>> import gymnasium as gym
    >>> import sec_playground  # registers SecPlayground/DoubleTMaze-v0 and the others
    >>> env = gym.make("SecPlayground/DoubleTMaze-v0", frame_skip=4)
    >>> obs, info = env.reset(seed=1)
    >>> obs.shape, str(obs.dtype)
    ((84, 84, 3), 'uint8')
    >>> run = sec_playground.Run({"task": "object-permanence", "t": 100}, seed=1, tau=0.5)
    >>> run.config["agent"]["memory"]["tau"]
    0.5
    >>> run.configure(alpha=0.02)["applied"]  # the page's keys; the rest keeps its values
    'live'
    >>> run.episode()["episode"]
    0

Everything runs in Rust (the same core as the browser playground and the native experiments);
a run is a pure function of its configuration and seed, on every platform.
"""

import json as _json
from typing import Optional

from . import _core
from importlib.metadata import PackageNotFoundError as _NotFound
from importlib.metadata import version as _version

from ._core import AGENTS_JSON as _AGENTS_JSON
from ._core import TASKS_JSON as _TASKS_JSON
from ._core import MAX_SEED, TASKS, fingerprint
from .envs import ACTION_MEANINGS, ENV_IDS, ArenaEnv, ArenaVectorEnv, integer
from .run import Run

try:
    __version__ = _version("sec-playground")
except _NotFound:  # imported from a source tree without installing
    __version__ = "0+unknown"

__all__ = [
    "ArenaEnv", "ArenaVectorEnv", "Encoder", "Run", "TASKS", "ENV_IDS", "MAX_SEED", "ACTION_MEANINGS",
    "agents", "parameters", "tasks", "fingerprint", "widget", "__version__",
]


class Encoder:
    """A bundled encoder: `task`'s trained autoencoder (`perception="trained"`), or the untrained
    one the authors' agent embedded with, drawn from `seed` (0..=MAX_SEED)."""

    def __init__(self, task: str, perception: str = "trained", seed: int = 0):
        if not isinstance(task, str):
            raise ValueError(f"task: {task!r} is not a string")
        if not isinstance(perception, str):
            raise ValueError(f"perception: {perception!r} is not 'trained' or 'untrained'")
        self._encoder = _core.Encoder(task, perception, integer("seed", seed, 0, MAX_SEED))

    def encode(self, frame):
        """The embedding of one camera frame ((84, 84, 3) uint8): 20 float32."""
        import numpy as np

        frame = np.asarray(frame)
        if frame.dtype != np.uint8:
            raise ValueError(f"frame: dtype {frame.dtype} is not uint8")
        return self._encoder.encode(frame)


def tasks() -> list:
    """The core's task table: one dict per task with its name, title, description, gymId and
    modelFile (its trained autoencoder under assets/encoders)."""
    return _json.loads(_TASKS_JSON)


def agents() -> list:
    """The core's agent table, as the page and the CLI read it: one dict per agent with its key
    (the page's `agent` setting), label, about, explores, section (the RunConfig section of its
    parameters), reads ("embedding", "image" or "nothing"), hasMemory, hasGate, nativeOnly
    (runs only through sec-experiment), canBeDriven, and the RunConfig `kind` and
    `mfecEmbedding` (`mfec.embedding`) that run it."""
    return _json.loads(_AGENTS_JSON)


def parameters(agent: Optional[str] = None) -> list:
    """The settings the page builds its controls from, for `agent` (a key of `agents()`; None:
    every setting): one dict each with its key (the page's and the URL hash's, which `Run` and
    `Run.configure` take as keyword arguments: `Run(alpha=0.02)`), symbol, help, kind (its type
    and range: number with min, max, minOpen, step and auto; integer with min and max; choice with
    its options; switch), live (applied to a running agent, or a new run), group and agents. An
    unknown agent raises ValueError naming the agents."""
    if agent is not None and not isinstance(agent, str):
        raise ValueError(f"agent: {agent!r} is not a string (a key of sec_playground.agents())")
    return _json.loads(_core.parameters_json(agent))


def widget(task: str = "double-t-maze", **settings):
    """The playground in a notebook cell (an anywidget: `pip install sec-playground[widget]`):
    the page's element, run from the wheel's wasm with no network, its settings traits synced
    both ways. See `sec_playground.notebook`."""
    from .notebook import widget as _widget

    return _widget(task, **settings)


def _register():
    from gymnasium.envs.registration import register, registry

    from ._core import Env

    for env_id, task in ENV_IDS.items():
        if env_id not in registry:
            kwargs = {} if task is None else {"task": task}
            # Gymnasium's limit in agent steps: the task's own t (env steps) at frame_skip=1.
            limit = None if task is None else Env(task).t
            register(
                id=env_id,
                entry_point="sec_playground.envs:ArenaEnv",
                vector_entry_point="sec_playground.envs:ArenaVectorEnv",
                kwargs=kwargs,
                max_episode_steps=limit,
            )


_register()
