"""The arenas as Gymnasium environments: the checker, the golden trace, the vector env."""

import struct

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import sec_playground
from sec_playground import ENV_IDS, TASKS, ArenaEnv, ArenaVectorEnv, fingerprint

PRESET_IDS = [i for i, t in ENV_IDS.items() if t is not None]


@pytest.mark.parametrize("env_id", PRESET_IDS)
def test_every_task_passes_gymnasiums_env_checker(env_id):
    env = gym.make(env_id, render_mode="rgb_array")
    assert isinstance(env.unwrapped, gym.Env)
    check_env(env.unwrapped, skip_render_check=False)
    obs, _ = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    frame = env.render()
    assert frame.shape == (256, 256, 3) and frame.dtype == np.uint8


def test_the_six_tasks_are_registered_and_an_animal_ai_file_loads(tmp_path):
    assert sorted(ENV_IDS[i] for i in PRESET_IDS) == sorted(TASKS)
    yaml = tmp_path / "arena.yaml"
    yaml.write_text(
        "!ArenaConfig\narenas:\n  0: !Arena\n    t: 250\n    items:\n"
        "    - !Item\n      name: GoodGoal\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 30}\n"
        "    - !Item\n      name: Agent\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 10}\n      rotations: [0]\n"
    )
    env = gym.make("SecPlayground/AnimalAI-v0", yaml_path=str(yaml))
    obs, info = env.reset(seed=1)
    assert obs.shape == (84, 84, 3) and info["position"] == (20.0, 10.0)
    # Forward until the goal ahead is reached: terminated with a positive reward.
    for _ in range(250):
        obs, reward, terminated, truncated, _ = env.step(3)
        if terminated or truncated:
            break
    assert terminated and reward > 0


def test_a_size_v1_clamps_is_clamped_with_a_warning(tmp_path):
    yaml = tmp_path / "big.yaml"
    yaml.write_text(
        "!ArenaConfig\narenas:\n  0: !Arena\n    t: 250\n    items:\n"
        "    - !Item\n      name: GoodGoal\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 30}\n"
        "      sizes:\n      - !Vector3 {x: 8, y: 8, z: 8}\n"
    )
    with pytest.warns(UserWarning) as caught:
        env = gym.make("SecPlayground/AnimalAI-v0", yaml_path=str(yaml))
    # A sphere's size is its x: the one warning, naming the line, the field and both values.
    assert [str(w.message).split(": ", 1)[1] for w in caught] == [
        "line 11: arenas.0.items[0].sizes[0].x: 8 is outside 0.5..=5 for a GoodGoal; clamped to 5, as v1 does"
    ]
    env.reset(seed=1)
    assert env.unwrapped._env.warnings == [str(caught[0].message).split(": ", 1)[1]]


def _bits(fmt, value):
    """The IEEE bits of a double ('d') or of a float ('f', exact: positions are f32s)."""
    return struct.unpack(">Q" if fmt == "d" else ">I", struct.pack(">" + fmt, value))[0]


def _scripted_trace(task, seed, steps, surface="flat"):
    """tests/golden/trace.txt's lines for `task` (trace-textured.txt's for the textured surface),
    through the Gymnasium env (the LCG script of `sec_playground::env::trace::scripted_run`)."""
    env = ArenaEnv(task, surface=surface)
    obs, info = env.reset(seed=seed)
    name = task if surface == "flat" else f"{task}-{surface}"
    lines = [f"# {name} seed {seed} layout {info['layout']} frame {fingerprint(obs):016x}"]
    lcg = (seed ^ 0x9E3779B9) & 0xFFFFFFFF
    for i in range(steps):
        lcg = (lcg * 1664525 + 1013904223) & 0xFFFFFFFF
        k = lcg >> 28
        a = 3 if k <= 6 else 1 if k <= 9 else 2 if k <= 12 else k % 9
        obs, reward, term, trunc, info = env.step(a)
        x, z = info["position"]
        lines.append(
            f"{i} {a} {_bits('d', reward):016x} {int(term)} {int(trunc)} "
            f"{_bits('f', x):08x} {_bits('f', z):08x} {fingerprint(obs):016x}"
        )
        if term or trunc:
            obs, info = env.reset()
            lines.append(f"# reset layout {info['layout']} frame {fingerprint(obs):016x}")
    return lines


@pytest.mark.parametrize("surface, file", [("flat", "trace.txt"), ("textured", "trace-textured.txt")])
def test_a_seeded_scripted_episode_equals_the_rust_golden_trace_bit_for_bit(golden, surface, file):
    expected = (golden / file).read_text().splitlines()
    got = [line for task in TASKS for line in _scripted_trace(task, 7, 200, surface)]
    assert len(got) == len(expected)
    for i, (a, b) in enumerate(zip(got, expected)):
        assert a == b, f"{file}: line {i + 1} differs"


def test_a_bad_surface_is_refused_by_name():
    with pytest.raises(ValueError, match="surface: 'tiled' is not one of flat, textured"):
        ArenaEnv("detour", surface="tiled")
    with pytest.raises(ValueError, match="surface"):
        ArenaVectorEnv(2, "detour", surface=3)


def _actions(n, steps, seed=5):
    return np.random.default_rng(seed).integers(0, 9, size=(steps, n))


def test_the_vector_env_equals_n_single_envs_with_next_step_autoreset():
    n, steps = 3, 400
    vec = gym.make_vec("SecPlayground/ObjectPermanence-v0", num_envs=n, vectorization_mode="vector_entry_point", frame_skip=4)
    assert isinstance(vec.unwrapped, gym.vector.VectorEnv)
    singles = [ArenaEnv("object-permanence", frame_skip=4) for _ in range(n)]
    obs, _ = vec.reset(seed=10)
    for i, env in enumerate(singles):
        o, _ = env.reset(seed=10 + i)
        assert np.array_equal(obs[i], o)
    ended = [False] * n
    resets = 0
    for acts in _actions(n, steps):
        obs, rewards, term, trunc, _ = vec.step(acts)
        for i, env in enumerate(singles):
            if ended[i]:
                o, _ = env.reset()
                r, te, tr = 0.0, False, False
                resets += 1
            else:
                o, r, te, tr, _ = env.step(int(acts[i]))
            ended[i] = te or tr
            assert np.array_equal(obs[i], o) and rewards[i] == r and term[i] == te and trunc[i] == tr
    assert resets > 0, "the script never reached an episode's end"


def test_bad_env_arguments_raise_value_error_by_name():
    cases = [
        (lambda: ArenaEnv("no-such-task"), "task"),
        (lambda: ArenaEnv("cylinder", frame_skip=0), "frame_skip"),
        (lambda: ArenaEnv("cylinder", render_mode="human"), "render_mode"),
        (lambda: ArenaEnv(), "task"),
    ]
    for make, name in cases:
        with pytest.raises(ValueError, match=name):
            make()
    env = ArenaEnv("cylinder")
    env.reset(seed=1)
    for bad in (9, -1):
        with pytest.raises(ValueError, match="action"):
            env.step(bad)
    env.step(3)  # the env is untouched by the refused steps
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=2**60)
    with pytest.raises(ValueError, match="num_envs"):
        sec_playground.ArenaVectorEnv(0, task="cylinder")


def test_the_task_table_registers_every_task():
    import gymnasium as gym

    from sec_playground import tasks

    table = tasks()
    assert [t["name"] for t in table] == list(TASKS)
    for t in table:
        assert gym.spec(t["gymId"]).kwargs == {"task": t["name"]}
        assert t["modelFile"] == f"{t['name']}.secae" and t["title"]
