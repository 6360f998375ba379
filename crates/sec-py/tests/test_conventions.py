"""Gymnasium's conventions (issue 37): the standard wrappers, one meaning per argument, bad calls
refused by name, and state that survives pickling and set_state bit for bit."""

import copy
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.wrappers import RecordEpisodeStatistics
from gymnasium.wrappers.vector import RecordEpisodeStatistics as VectorRecordEpisodeStatistics

import sec_playground
from sec_playground import ACTION_MEANINGS, ArenaEnv, ArenaVectorEnv, Encoder, Run

DTM = "SecPlayground/DoubleTMaze-v0"


def play(env, actions):
    """(observation checksums, rewards, ends) of `actions` taken from now."""
    out = []
    for a in actions:
        obs, r, term, trunc, info = env.step(a)
        out.append((int(obs.astype(np.int64).sum()), r, term, trunc, info["success"]))
        if term or trunc:
            env.reset()
    return out


def test_record_episode_statistics_on_the_single_env_records_return_and_length():
    env = RecordEpisodeStatistics(gym.make(DTM, frame_skip=4, max_episode_steps=30))
    env.reset(seed=1)
    total, n = 0.0, 0
    while True:
        _, r, term, trunc, info = env.step(3)
        total, n = total + r, n + 1
        if term or trunc:
            break
    assert "episode" in info and "episode_index" in info
    assert info["episode"]["l"] == n == 30
    assert info["episode"]["r"] == pytest.approx(total)


def test_record_episode_statistics_on_the_vector_env_records_return_and_length():
    envs = VectorRecordEpisodeStatistics(gym.make_vec(DTM, num_envs=3, frame_skip=4, max_episode_steps=20))
    envs.reset(seed=5)
    totals, steps = np.zeros(3), 0
    while True:
        _, r, term, trunc, info = envs.step(np.array([3, 0, 1]))
        totals, steps = totals + r, steps + 1
        if (term | trunc).any():
            break
    assert steps == 20 and (trunc | term).all()
    assert np.array_equal(info["episode"]["l"], [20, 20, 20])
    assert np.allclose(info["episode"]["r"], totals)


def test_one_meaning_of_each_limit_and_the_spec_gives_the_tasks():
    env = gym.make(DTM)
    assert env.spec.max_episode_steps == 1000 == env.unwrapped.t
    # max_episode_steps counts agent steps and keeps the penalty; t counts env steps and sets it.
    a = ArenaEnv("double-t-maze", frame_skip=4, max_episode_steps=10)
    a.reset(seed=1)
    steps = [a.step(0) for _ in range(10)]
    assert [s[3] for s in steps] == [False] * 9 + [True]
    assert steps[0][1] == pytest.approx(-4 / 1000)
    b = ArenaEnv("double-t-maze", frame_skip=4, t=40)
    b.reset(seed=1)
    steps = [b.step(0) for _ in range(10)]
    assert [s[3] for s in steps] == [False] * 9 + [True]
    assert steps[0][1] == pytest.approx(-4 / 40)
    with pytest.raises(gym.error.ResetNeeded):
        a.step(0)
    v = ArenaVectorEnv(2, "double-t-maze", frame_skip=4, max_episode_steps=10)
    v.reset(seed=1)
    for _ in range(9):
        _, _, _, trunc, _ = v.step(np.zeros(2, dtype=np.int64))
        assert not trunc.any()
    _, r, _, trunc, info = v.step(np.zeros(2, dtype=np.int64))
    assert trunc.all() and np.allclose(r, -4 / 1000) and np.array_equal(info["agent_steps"], [10, 10])


def test_action_meanings_success_version_and_vector_parity():
    env = gym.make(DTM, render_mode="rgb_array")
    assert env.unwrapped.get_action_meanings() == ACTION_MEANINGS and len(ACTION_MEANINGS) == 9
    assert isinstance(sec_playground.__version__, str) and sec_playground.__version__[0].isdigit()
    _, info = env.reset(seed=2)
    assert set(info) == {"layout", "episode_index", "env_steps", "agent_steps", "position", "height", "heading", "success"}
    v = gym.make_vec(DTM, num_envs=2, render_mode="rgb_array")
    _, infos = v.reset(seed=2)
    assert set(infos) == set(info)
    assert infos["layout"][0] == info["layout"] and tuple(infos["position"][0]) == info["position"]
    frames = v.render()
    assert len(frames) == 2 and frames[0].shape == (256, 256, 3)
    assert np.array_equal(frames[0], env.render())


def test_a_goal_is_reported_as_success(tmp_path):
    yaml = tmp_path / "arena.yaml"
    yaml.write_text(
        "!ArenaConfig\narenas:\n  0: !Arena\n    t: 250\n    items:\n"
        "    - !Item\n      name: GoodGoal\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 30}\n"
        "    - !Item\n      name: Agent\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 10}\n      rotations: [0]\n"
    )
    env = ArenaEnv(yaml_path=str(yaml))
    env.reset(seed=1)
    for _ in range(250):
        _, _, term, _, info = env.step(3)
        if term:
            break
    assert term and info["success"]


@pytest.mark.parametrize("make", [lambda: gym.make(DTM, frame_skip=4).unwrapped, lambda: ArenaEnv("detour")])
def test_a_pickled_deep_copied_or_set_state_env_continues_bit_for_bit(make):
    rng = np.random.default_rng(0)
    env = make()
    env.reset(seed=7)
    play(env, rng.integers(0, 9, 300))
    copies = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
    restored = make()
    restored.set_state(env.get_state())
    copies.append(restored)
    actions = rng.integers(0, 9, 400)
    want = play(env, actions)
    for c in copies:
        assert play(c, actions) == want
    # Unseeded resets draw from the env's generator: restored too.
    fresh = make()
    fresh.reset()
    twin = pickle.loads(pickle.dumps(fresh))
    assert play(fresh, actions[:50]) == play(twin, actions[:50])


def test_a_pickled_vector_env_continues_bit_for_bit():
    v = ArenaVectorEnv(3, "double-t-maze", frame_skip=4, max_episode_steps=40)
    v.reset(seed=11)
    rng = np.random.default_rng(1)
    for _ in range(70):
        v.step(rng.integers(0, 9, 3))
    w = pickle.loads(pickle.dumps(v))
    for _ in range(60):
        a = rng.integers(0, 9, 3)
        o1, r1, t1, u1, _ = v.step(a)
        o2, r2, t2, u2, _ = w.step(a)
        assert np.array_equal(o1, o2) and np.array_equal(r1, r2) and np.array_equal(t1, t2) and np.array_equal(u1, u2)


@pytest.mark.parametrize("kind", ["sec", "mfec", "reactive"])
def test_a_pickled_run_continues_bit_for_bit(kind):
    run = Run({"task": "object-permanence", "kind": kind}, seed=3)
    run.episodes(4)
    between = pickle.loads(pickle.dumps(run))
    run.decisions(30)  # mid-episode
    mid = copy.deepcopy(run)
    assert [mid.episode() for _ in range(3)] == [run.episode() for _ in range(3)]
    # The copy made between episodes goes on as a run never pickled.
    twin = Run({"task": "object-permanence", "kind": kind}, seed=3)
    twin.episodes(4)
    assert between.decisions(30) == twin.decisions(30)
    assert [between.episode() for _ in range(2)] == [twin.episode() for _ in range(2)]


def test_a_pickled_run_keeps_a_live_change():
    run = Run({"task": "object-permanence"}, seed=4)
    run.episodes(3)
    assert run.configure({"task": "object-permanence", "agent": {"memory": {"tau": 0.5}}})["applied"] == "live"
    run.decisions(17)
    copy_ = pickle.loads(pickle.dumps(run))
    assert copy_.config["agent"]["memory"]["tau"] == 0.5
    assert [copy_.episode() for _ in range(3)] == [run.episode() for _ in range(3)]


def test_numpy_integers_are_integers():
    Run({"task": "object-permanence"}, seed=np.int64(1))
    env = ArenaEnv("detour", frame_skip=np.int32(4), max_episode_steps=np.int64(5))
    env.reset(seed=np.uint16(3))
    env.step(np.int8(3))
    v = ArenaVectorEnv(np.int64(2), "detour")
    v.reset(seed=np.int64(3))
    v.reset(seed=[np.int64(1), 2])
    Encoder("detour", "untrained", np.int64(2))


BAD_CALLS = [
    ("action", lambda env: env.step(3.5)),
    ("action", lambda env: env.step("3")),
    ("action", lambda env: env.step(True)),
    ("action", lambda env: env.step(9)),
    ("action", lambda env: env.step(np.float32(1))),
    ("seed", lambda env: env.reset(seed=-1)),
    ("seed", lambda env: env.reset(seed=2.0)),
]


@pytest.mark.parametrize("name,call", BAD_CALLS)
def test_bad_env_calls_name_their_parameter(name, call):
    env = ArenaEnv("detour")
    env.reset(seed=1)
    with pytest.raises(ValueError, match=rf"^{name}: "):
        call(env)


@pytest.mark.parametrize(
    "name,make",
    [
        ("frame_skip", lambda: ArenaEnv("detour", frame_skip=10**30)),
        ("frame_skip", lambda: ArenaEnv("detour", frame_skip=1.5)),
        ("max_episode_steps", lambda: ArenaEnv("detour", max_episode_steps=-1)),
        ("max_episode_steps", lambda: ArenaEnv("detour", max_episode_steps=0)),
        ("t", lambda: ArenaEnv("detour", t=10**12)),
        ("render_size", lambda: ArenaEnv("detour", render_mode="rgb_array", render_size=-5)),
        ("seed", lambda: Encoder("detour", "untrained", seed=-1)),
        ("seed", lambda: Run({}, seed=2**70)),
        ("num_envs", lambda: ArenaVectorEnv(0, "detour")),
        ("num_envs", lambda: ArenaVectorEnv(True, "detour")),
        ("yaml_path", lambda: ArenaEnv(yaml_path="/dev/zero")),
    ],
)
def test_bad_arguments_name_their_parameter(name, make):
    with pytest.raises(ValueError, match=rf"^{name}: "):
        make()


def test_a_binary_arena_file_is_refused_by_name(tmp_path):
    f = tmp_path / "arena.yaml"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\xff\xfe")
    with pytest.raises(ValueError, match=r"^yaml_path: .* is not UTF-8 text"):
        ArenaEnv(yaml_path=str(f))


def test_the_vector_env_refuses_unknown_keywords_and_bad_actions():
    with pytest.raises(TypeError, match="unknown keyword argument 'frameskip'"):
        ArenaVectorEnv(2, "detour", frameskip=4)
    with pytest.raises(TypeError, match="frameskip"):
        gym.make_vec("SecPlayground/Detour-v0", num_envs=2, frameskip=4)
    v = ArenaVectorEnv(2, "detour")
    v.reset(seed=1)
    with pytest.raises(ValueError, match=r"^actions: shape \(2, 1\) is not \(2,\)"):
        v.step(np.zeros((2, 1), dtype=np.int64))
    with pytest.raises(ValueError, match="^actions: dtype float64"):
        v.step(np.zeros(2))
    with pytest.raises(ValueError, match="^seed: 3 seeds for 2 envs"):
        v.reset(seed=[1, 2, 3])


def test_the_suite_runs_against_the_installed_wheel_without_rust():
    import os
    import shutil

    if not os.environ.get("SEC_NO_RUST"):
        pytest.skip("run by scripts/python-test.sh against the wheel, with no Rust on PATH")
    assert shutil.which("cargo") is None and shutil.which("rustc") is None
    assert "site-packages" in sec_playground.__file__
    assert sec_playground.__version__ == "0.1.0"
