"""The arenas as Gymnasium environments: `ArenaEnv` (one arena) and `ArenaVectorEnv` (n arenas
stepped in one call across cores, the GIL released).

Two limits, each with one meaning in every constructor (`gym.make`, `gym.make_vec`, `ArenaEnv`,
`ArenaVectorEnv`):

- `t`: the arena's own episode limit in *env steps*, as an Animal-AI arena file's `t`. The episode
  is truncated after `t` env steps and every env step costs `1/t` reward (the task's default:
  1000 env steps, -0.001 each). `frame_skip` env steps make one agent step.
- `max_episode_steps`: Gymnasium's limit in *agent steps* (calls to `step`): the episode is
  truncated after that many steps; the reward is not rescaled. `gym.make` applies it as
  Gymnasium's `TimeLimit`; `env.spec.max_episode_steps` is the task's `t` (at `frame_skip=1`
  one agent step is one env step; with `frame_skip=k` the arena's own limit ends an episode after
  `ceil(t / k)` agent steps, first).
"""

import json
import os
import operator
import warnings
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

#: What each of the nine actions does: 3 * a0 + a1 (a0: none, forward, back; a1: none, right, left).
ACTION_MEANINGS = [
    "NOOP", "RIGHT", "LEFT", "FORWARD", "FORWARD_RIGHT", "FORWARD_LEFT", "BACK", "BACK_RIGHT", "BACK_LEFT",
]

#: Largest Animal-AI YAML file read (bytes, the core's limit for every text file a user hands in):
#: a bigger one is refused before it is read whole.
MAX_YAML_BYTES = _core.MAX_TEXT_FILE_BYTES
MAX_FRAME_SKIP = 100
MAX_T = 100_000
MAX_EPISODE_STEPS = 10_000_000
MAX_RENDER_SIZE = 2048


def integer(name: str, value: Any, lo: int, hi: int) -> int:
    """`value` as an int in lo..=hi: Python and numpy integers pass; bools, floats, strings and
    anything out of range raise ValueError naming the parameter."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name}: {value!r} is a boolean, not an integer")
    try:
        v = operator.index(value)
    except TypeError:
        raise ValueError(f"{name}: {value!r} is not an integer") from None
    if not lo <= v <= hi:
        raise ValueError(f"{name}: {v} is out of range {lo}..={hi}")
    return v


def _optional(name: str, value: Any, lo: int, hi: int) -> Optional[int]:
    return None if value is None else integer(name, value, lo, hi)


def _read_yaml(yaml_path) -> str:
    # A path is a str or an os.PathLike: an int would be a file descriptor (0 reads stdin and
    # blocks; True is 1, which closing would take from the process).
    if isinstance(yaml_path, (bool, int, np.integer)) or not isinstance(yaml_path, (str, os.PathLike)):
        raise ValueError(f"yaml_path: {yaml_path!r} is not a path (a str or os.PathLike)")
    # The core reads it: regular files only (a named pipe is refused before it could block).
    return _core.read_text_file(os.fspath(yaml_path), "yaml_path")


def _arena(task: Optional[str], yaml_path) -> tuple:
    """(name, YAML text or None) of a preset task or an Animal-AI file."""
    if yaml_path is not None:
        return (task or str(yaml_path)), _read_yaml(yaml_path)
    if task is None:
        raise ValueError("task: give a task (one of sec_playground.TASKS) or yaml_path (an Animal-AI YAML file)")
    if not isinstance(task, str):
        raise ValueError(f"task: {task!r} is not a string")
    return task, None


def _seed_from(rng: np.random.Generator) -> int:
    return int(rng.integers(0, _core.MAX_SEED, endpoint=True))


def _render_options(render_mode, render_view, render_size) -> int:
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise ValueError(f"render_mode: {render_mode!r} is not one of {RENDER_MODES} or None")
    if render_view not in RENDER_VIEWS:
        raise ValueError(f"render_view: {render_view!r} is not one of {RENDER_VIEWS}")
    return integer("render_size", render_size, 16, MAX_RENDER_SIZE)


def _generator_state(env) -> Optional[dict]:
    """The env's own generator (`np_random`) as its state, or None before it was made."""
    return env.np_random.bit_generator.state if env._np_random is not None else None


def _restore_generator(env, state: Optional[dict]) -> None:
    if state is not None:
        env._np_random = np.random.Generator(np.random.PCG64())
        env._np_random.bit_generator.state = state


def _render(env, observation, top_down):
    """A frame as `render_view` says (`observation()`, `top_down(size)`), or None without a render_mode."""
    if env.render_mode is None:
        gym.logger.warn("render() without render_mode: make the env with render_mode='rgb_array'")
        return None
    if env.render_view == "first-person":
        scale = max(1, env.render_size // 84)
        return np.repeat(np.repeat(observation(), scale, axis=0), scale, axis=1)
    return top_down(env.render_size)


class _Pickled:
    """Pickling and `copy.deepcopy` through `get_state`/`set_state`: the Rust side is made again
    by `_make_core()` from the constructor's arguments and brought to the state by replay."""

    def __getstate__(self):
        d = {k: v for k, v in self.__dict__.items() if k not in ("_env", "_np_random")}
        d["_core_state"] = self.get_state()
        return d

    def __setstate__(self, d):
        core_state = d.pop("_core_state")
        self.__dict__.update(d)
        self._np_random = None
        self._env = self._make_core()
        self.set_state(core_state)


SURFACES = ("flat", "textured")


def _surface(surface):
    """A surface name, refused by name unless one of SURFACES."""
    if surface not in SURFACES:
        raise ValueError(f"surface: {surface!r} is not one of {', '.join(SURFACES)}")
    return surface


class ArenaEnv(_Pickled, gym.Env):
    """One arena, seen through the agent's 84x84 camera.

    Observations are the camera's RGB bytes, (84, 84, 3) uint8; actions are Animal-AI's nine,
    3 * a0 + a1 (a0: 0 none, 1 forward, 2 back; a1: 0 none, 1 right, 2 left;
    `get_action_meanings()` names them). An action must be an integer (Python or numpy) in 0..=8.

    Arguments: `task` (one of `sec_playground.TASKS`) or `yaml_path` (an Animal-AI YAML file, at
    most 1 MiB); `frame_skip` env steps each action is held for (1..=100; SEC's runs use 4);
    `t` the arena's limit in env steps (0..=100000, 0: none; default the task's; each env step
    costs 1/t); `max_episode_steps` a limit in agent steps (Gymnasium's meaning; None: none);
    `render_mode` None or "rgb_array"; `render_view` "top-down" (the arena from above with the
    agent's trail) or "first-person" (the camera, enlarged); `render_size` pixels (16..=2048);
    `surface` "flat" (one colour for the floor and the fences) or "textured" (v1's tiled floor and
    planked fences).

    `info` holds `layout`, `episode_index` (episodes since the last seeded reset), `env_steps`,
    `agent_steps`, `position` (x, z), `height` (of the agent's bottom: 0 on the floor, more on a
    box or a ramp), `heading` (degrees) and `success` (the step touched a good goal). A goal or a death zone ends an episode as `terminated`, a limit as `truncated`.
    `get_state()`/`set_state()` (and pickle, `copy.deepcopy`) save and restore the env exactly.
    """

    metadata = {"render_modes": RENDER_MODES, "render_fps": round(1 / 0.06)}

    def __init__(
        self,
        task: Optional[str] = None,
        yaml_path: Optional[str] = None,
        frame_skip: int = 1,
        t: Optional[int] = None,
        max_episode_steps: Optional[int] = None,
        render_mode: Optional[str] = None,
        render_view: str = "top-down",
        render_size: int = 256,
        surface: str = "flat",
    ):
        self.render_size = _render_options(render_mode, render_view, render_size)
        frame_skip = integer("frame_skip", frame_skip, 1, MAX_FRAME_SKIP)
        t = _optional("t", t, 0, MAX_T)
        self.max_episode_steps = _optional("max_episode_steps", max_episode_steps, 1, MAX_EPISODE_STEPS)
        name, text = _arena(task, yaml_path)
        self._args = (name, t, text, frame_skip, _surface(surface))
        self._env = self._make_core()
        # A file v1 reads by changing it (a size clamped into its range) loads the same way here,
        # and says so.
        for message in self._env.warnings:
            warnings.warn(f"{name}: {message}", UserWarning, stacklevel=2)
        self.observation_space = OBSERVATION_SPACE
        self.action_space = ACTION_SPACE
        self.render_mode = render_mode
        self.render_view = render_view
        self.metadata = dict(self.metadata, render_fps=round(1 / self._env.step_seconds))
        self._seeded = False
        self._over = False

    def _make_core(self):
        name, t, text, frame_skip, surface = self._args
        return _core.Env(name, t=t, yaml=text, frame_skip=frame_skip, max_steps=self.max_episode_steps, surface=surface)

    @property
    def task(self) -> str:
        """The task's name (or the YAML file's)."""
        return self._env.task

    @property
    def t(self) -> int:
        """The arena's episode limit in env steps (0: none)."""
        return self._env.t

    @property
    def frame_skip(self) -> int:
        """Env steps each action is held for."""
        return self._env.frame_skip

    def get_action_meanings(self) -> list:
        """The nine actions' names, by index."""
        return list(ACTION_MEANINGS)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None):
        """With a seed the run restarts from it (its layout order and draws); without one the
        next layout of the cycle (the first reset without a seed draws one from `np_random`)."""
        seed = _optional("seed", seed, 0, _core.MAX_SEED)
        super().reset(seed=seed)
        if seed is None and not self._seeded:
            seed = _seed_from(self.np_random)
        obs = self._env.reset(seed)
        self._seeded = True
        self._over = False
        return obs, self._env.info()

    def step(self, action):
        """Holds `action` for `frame_skip` env steps: (obs, reward, terminated, truncated, info)."""
        a = integer("action", action, 0, 8)
        if not self._seeded:
            raise gym.error.ResetNeeded("reset() before step()")
        if self._over:
            raise gym.error.ResetNeeded("the episode is over: reset() first")
        obs, reward, terminated, truncated = self._env.step(a)
        self._over = terminated or truncated
        return obs, reward, terminated, truncated, self._env.info()

    def render(self):
        """The top-down view with the trail, or the camera enlarged (`render_view`), as RGB."""
        return _render(self, self._env.observation, self._env.top_down)

    def get_state(self) -> dict:
        """Everything that makes this env what it is now: `set_state` on an env of the same
        arguments (or the pickle of this one) continues bit for bit. The arena is rebuilt by
        replaying its last seeded reset, the resets since and this episode's actions."""
        seed, resets, actions = self._env.get_state()
        return {
            "arena": (seed, resets, bytes(actions)),
            "seeded": self._seeded,
            "over": self._over,
            "np_random": _generator_state(self),
        }

    def set_state(self, state: dict) -> None:
        """Restores a `get_state` (of an env made with the same arguments); a bad state raises
        ValueError and leaves the env as it was."""
        if not isinstance(state, dict) or set(state) != {"arena", "seeded", "over", "np_random"}:
            raise ValueError("state: not an ArenaEnv.get_state() dict")
        seed, resets, actions = state["arena"]
        self._env.set_state((seed, resets, list(actions)))
        self._seeded, self._over = bool(state["seeded"]), bool(state["over"])
        _restore_generator(self, state["np_random"])


class ArenaVectorEnv(_Pickled, VectorEnv):
    """`num_envs` arenas of one task, stepped in one Rust call across cores with the GIL
    released. Autoreset is Gymnasium's next-step mode: the step after an episode ends resets
    that arena (its action ignored, reward 0) and returns the new episode's first observation.

    The arguments are `ArenaEnv`'s (the same meaning of `t` and `max_episode_steps`), and
    `num_envs` (1..=4096); an unknown keyword argument is refused by name. `infos` carries what
    the single env's `info` does, one array per key; `render()` gives one frame per arena.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": RENDER_MODES}

    def __init__(
        self,
        num_envs: int,
        task: Optional[str] = None,
        yaml_path: Optional[str] = None,
        frame_skip: int = 1,
        t: Optional[int] = None,
        max_episode_steps: Optional[int] = None,
        render_mode: Optional[str] = None,
        render_view: str = "top-down",
        render_size: int = 256,
        surface: str = "flat",
        **unknown,
    ):
        if unknown:
            raise TypeError(
                f"ArenaVectorEnv: unknown keyword argument {', '.join(map(repr, unknown))} (allowed: num_envs, task, "
                "yaml_path, frame_skip, t, max_episode_steps, render_mode, render_view, render_size, surface)"
            )
        self.render_size = _render_options(render_mode, render_view, render_size)
        num_envs = integer("num_envs", num_envs, 1, 4096)
        frame_skip = integer("frame_skip", frame_skip, 1, MAX_FRAME_SKIP)
        t = _optional("t", t, 0, MAX_T)
        self.max_episode_steps = _optional("max_episode_steps", max_episode_steps, 1, MAX_EPISODE_STEPS)
        name, text = _arena(task, yaml_path)
        self._args = (name, num_envs, t, text, frame_skip, _surface(surface))
        self._env = self._make_core()
        self.num_envs = num_envs
        self.render_mode = render_mode
        self.render_view = render_view
        self.single_observation_space = OBSERVATION_SPACE
        self.single_action_space = ACTION_SPACE
        self.observation_space = spaces.Box(0, 255, (num_envs, 84, 84, 3), np.uint8)
        self.action_space = spaces.MultiDiscrete(np.full(num_envs, 9))
        self._seeded = False

    def _make_core(self):
        name, num_envs, t, text, frame_skip, surface = self._args
        return _core.VecEnv(
            name, num_envs, t=t, yaml=text, frame_skip=frame_skip, max_steps=self.max_episode_steps, surface=surface
        )

    def get_action_meanings(self) -> list:
        """The nine actions' names, by index."""
        return list(ACTION_MEANINGS)

    def reset(self, *, seed=None, options=None):
        """`seed`: one integer (arena i gets seed + i), a sequence of one per arena, or None."""
        if seed is None or isinstance(seed, (int, np.integer)) and not isinstance(seed, (bool, np.bool_)):
            base = _optional("seed", seed, 0, _core.MAX_SEED - self.num_envs + 1)
            super().reset(seed=base)
            if base is None:
                seeds = [_seed_from(self.np_random) for _ in range(self.num_envs)]
            else:
                seeds = [base + i for i in range(self.num_envs)]
        else:
            try:
                seeds = [integer(f"seed[{i}]", s, 0, _core.MAX_SEED) for i, s in enumerate(seed)]
            except TypeError:
                raise ValueError(f"seed: {seed!r} is not an integer, a sequence of integers or None") from None
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed: {len(seeds)} seeds for {self.num_envs} envs")
            super().reset(seed=None)
        obs = self._env.reset(seeds)
        self._seeded = True
        return obs, self._infos()

    def step(self, actions):
        """One action per arena (integers 0..=8, shape (num_envs,))."""
        if not self._seeded:
            raise gym.error.ResetNeeded("reset() before step()")
        actions = np.asarray(actions)
        if actions.dtype.kind not in "iu":
            raise ValueError(f"actions: dtype {actions.dtype} is not an integer type")
        if actions.shape != (self.num_envs,):
            raise ValueError(f"actions: shape {actions.shape} is not ({self.num_envs},)")
        bad = np.flatnonzero((actions < 0) | (actions > 8))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"actions[{i}]: {int(actions[i])} is out of range 0..=8")
        obs, rewards, terminated, truncated = self._env.step(actions.astype(np.int64))
        return obs, rewards, terminated, truncated, self._infos()

    def _infos(self) -> dict:
        rows = self._env.infos()
        return {k: np.array([r[k] for r in rows]) for k in rows[0]}

    def render(self):
        """One RGB frame per arena (`render_view` as `ArenaEnv`'s), or None without render_mode."""
        if self.render_mode is None:
            return _render(self, None, None)
        return tuple(
            _render(self, lambda i=i: self._env.observation(i), lambda size, i=i: self._env.top_down(i, size))
            for i in range(self.num_envs)
        )

    def get_state(self) -> dict:
        """Every arena's state (as `ArenaEnv.get_state`'s) and the env's own generator: a
        `set_state` on a vector env of the same arguments, or the pickle, continues bit for bit."""
        return {
            "arenas": [(s, r, bytes(a), e) for s, r, a, e in self._env.get_state()],
            "seeded": self._seeded,
            "np_random": _generator_state(self),
        }

    def set_state(self, state: dict) -> None:
        """Restores a `get_state`; a bad state raises ValueError and leaves the env as it was."""
        if not isinstance(state, dict) or set(state) != {"arenas", "seeded", "np_random"}:
            raise ValueError("state: not an ArenaVectorEnv.get_state() dict")
        self._env.set_state([(s, r, list(a), bool(e)) for s, r, a, e in state["arenas"]])
        self._seeded = bool(state["seeded"])
        _restore_generator(self, state["np_random"])
