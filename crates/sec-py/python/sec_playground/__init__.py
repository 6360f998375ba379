"""SEC Playground from Python: the Animal-AI arenas of Freire, Amil & Verschure's "Sequential
memory improves sample and memory efficiency in Episodic Control" as Gymnasium environments,
SEC, NSEC, MFEC and the reactive walk as runs, and the bundled encoders.

    import gymnasium as gym
    import sec_playground  # registers SecPlayground/DoubleTMaze-v0 and the others
    env = gym.make("SecPlayground/DoubleTMaze-v0", frame_skip=4)
    obs, info = env.reset(seed=1)

Everything runs in Rust (the same core as the browser playground and the native experiments);
a run is a pure function of its configuration and seed, on every platform.
"""

import json as _json

from ._core import AGENTS_JSON as _AGENTS_JSON
from ._core import TASKS_JSON as _TASKS_JSON
from ._core import MAX_SEED, TASKS, Encoder, fingerprint
from .envs import ENV_IDS, ArenaEnv, ArenaVectorEnv
from .run import Run

__all__ = ["ArenaEnv", "ArenaVectorEnv", "Encoder", "Run", "TASKS", "ENV_IDS", "MAX_SEED", "agents", "tasks", "fingerprint"]


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


def _register():
    from gymnasium.envs.registration import register, registry

    for env_id, task in ENV_IDS.items():
        if env_id not in registry:
            kwargs = {} if task is None else {"task": task}
            register(
                id=env_id,
                entry_point="sec_playground.envs:ArenaEnv",
                vector_entry_point="sec_playground.envs:ArenaVectorEnv",
                kwargs=kwargs,
            )


_register()
