"""The arenas as Gymnasium environments: `ArenaEnv` (one arena) and `ArenaVectorEnv` (n arenas
stepped in one call across cores, the GIL released)."""

import json
from typing import Any, Optional

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv

from . import _core

# Gymnasium ids of the tasks (the core's task table); "AnimalAI-v0" takes an Animal-AI YAML file
# (`yaml_path`).
ENV_IDS = {t["gymId"]: t["name"] for t in json.loads(_core.TASKS_JSON)}
ENV_IDS["SecPlayground/AnimalAI-v0"] = None

RENDER_MODES = ["rgb_array"]
RENDER_VIEWS = ("top-down", "first-person")

OBSERVATION_SPACE = spaces.Box(0, 255, (84, 84, 3), np.uint8)
ACTION_SPACE = spaces.Discrete(9)


def _arena(task: Optional[str], yaml_path: Optional[str]):
    """(name, YAML text or None) of a preset task or an Animal-AI file."""
    if yaml_path is not None:
        with open(yaml_path, encoding="utf-8") as f:
            text = f.read()
        return (task or str(yaml_path)), text
    if task is None:
        raise ValueError("task: give a task (one of sec_playground.TASKS) or yaml_path (an Animal-AI YAML file)")
    if not isinstance(task, str):
        raise ValueError(f"task: {task!r} is not a string")
    return task, None


def _seed_from(rng: np.random.Generator) -> int:
    return int(rng.integers(0, _core.MAX_SEED, endpoint=True))


class ArenaEnv(gym.Env):
    """One arena, seen through the agent's 84x84 camera.

    Observations are the camera's RGB bytes, (84, 84, 3) uint8; actions are Animal-AI's nine,
    3 * a0 + a1 (a0: 0 none, 1 forward, 2 back; a1: 0 none, 1 right, 2 left). `frame_skip` holds
    each action for that many env steps (SEC's runs use 4). The episode limit ends an episode as
    `truncated`; a goal or a death zone as `terminated`. `render()` gives the top-down view with
    the agent's trail (`render_view="first-person"`: the camera, enlarged).
    """

    metadata = {"render_modes": RENDER_MODES, "render_fps": round(1 / 0.06)}

    def __init__(
        self,
        task: Optional[str] = None,
        yaml_path: Optional[str] = None,
        frame_skip: int = 1,
        max_episode_steps: Optional[int] = None,
        render_mode: Optional[str] = None,
        render_view: str = "top-down",
        render_size: int = 256,
    ):
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise ValueError(f"render_mode: {render_mode!r} is not one of {RENDER_MODES} or None")
        if render_view not in RENDER_VIEWS:
            raise ValueError(f"render_view: {render_view!r} is not one of {RENDER_VIEWS}")
        name, text = _arena(task, yaml_path)
        self._env = _core.Env(name, t=max_episode_steps, yaml=text, frame_skip=frame_skip)
        self.observation_space = OBSERVATION_SPACE
        self.action_space = ACTION_SPACE
        self.render_mode = render_mode
        self.render_view = render_view
        self.render_size = render_size
        self.metadata = dict(self.metadata, render_fps=round(1 / self._env.step_seconds))
        self._seeded = False
        self._over = False

    @property
    def task(self) -> str:
        return self._env.task

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None):
        """With a seed the run restarts from it (its layout order and draws); without one the
        next layout of the cycle (the first reset without a seed draws one from `np_random`)."""
        super().reset(seed=seed)
        if seed is None and not self._seeded:
            seed = _seed_from(self.np_random)
        obs = self._env.reset(seed)
        self._seeded = True
        self._over = False
        return obs, self._env.info()

    def step(self, action):
        if not self._seeded:
            raise gym.error.ResetNeeded("reset() before step()")
        if self._over:
            raise gym.error.ResetNeeded("the episode is over: reset() first")
        obs, reward, terminated, truncated = self._env.step(int(action))
        self._over = terminated or truncated
        return obs, reward, terminated, truncated, self._env.info()

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() without render_mode: make the env with render_mode='rgb_array'")
            return None
        if self.render_view == "first-person":
            scale = max(1, self.render_size // 84)
            return np.repeat(np.repeat(self._env.observation(), scale, axis=0), scale, axis=1)
        return self._env.top_down(self.render_size)


class ArenaVectorEnv(VectorEnv):
    """`num_envs` arenas of one task, stepped in one Rust call across cores with the GIL
    released. Autoreset is Gymnasium's next-step mode: the step after an episode ends resets
    that arena (its action ignored, reward 0) and returns the new episode's first observation."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        num_envs: int,
        task: Optional[str] = None,
        yaml_path: Optional[str] = None,
        frame_skip: int = 1,
        max_episode_steps: Optional[int] = None,
        **_ignored,
    ):
        name, text = _arena(task, yaml_path)
        if not isinstance(num_envs, int) or isinstance(num_envs, bool):
            raise ValueError(f"num_envs: {num_envs!r} is not an integer")
        self._env = _core.VecEnv(name, num_envs, t=max_episode_steps, yaml=text, frame_skip=frame_skip)
        self.num_envs = num_envs
        self.single_observation_space = OBSERVATION_SPACE
        self.single_action_space = ACTION_SPACE
        self.observation_space = spaces.Box(0, 255, (num_envs, 84, 84, 3), np.uint8)
        self.action_space = spaces.MultiDiscrete(np.full(num_envs, 9))
        self._seeded = False

    def reset(self, *, seed=None, options=None):
        """`seed`: one int (arena i gets seed + i), a list of one per arena, or None."""
        super().reset(seed=seed if isinstance(seed, int) else None)
        if seed is None:
            seeds = [_seed_from(self.np_random) for _ in range(self.num_envs)]
        elif isinstance(seed, int):
            seeds = [seed + i for i in range(self.num_envs)]
        else:
            seeds = [int(s) for s in seed]
        obs = self._env.reset(seeds)
        self._seeded = True
        return obs, self._infos()

    def step(self, actions):
        if not self._seeded:
            raise gym.error.ResetNeeded("reset() before step()")
        actions = np.asarray(actions)
        if actions.dtype.kind not in "iu":
            raise ValueError(f"actions: dtype {actions.dtype} is not an integer type")
        obs, rewards, terminated, truncated = self._env.step(actions.astype(np.int64).reshape(-1))
        return obs, rewards, terminated, truncated, self._infos()

    def _infos(self):
        layouts, episodes, steps = zip(*self._env.infos())
        return {"layout": np.array(layouts), "episode": np.array(episodes), "env_steps": np.array(steps)}
