"""What a file, a pipe, a resume or a partial change hands Python cannot alter a run silently
(issue 52): each is refused by name at once, or applied exactly as asked."""

import json
import os
import threading

import numpy as np
import pytest

import sec_playground
from sec_playground import ArenaEnv, ArenaVectorEnv, Run, _core, fingerprint


def _returns_at_once(call):
    """Runs `call` in a thread; fails if it has not returned once the thread is joined for long
    (a blocked read would hang the test suite; the thread is a daemon so it cannot)."""
    out = {}

    def target():
        try:
            call()
        except Exception as e:  # noqa: BLE001 - the refusal is what is looked at
            out["error"] = e

    t = threading.Thread(target=target, daemon=True)
    t.start()
    t.join(120)
    assert not t.is_alive(), "the call blocked"
    return out.get("error")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are a Unix thing")
def test_a_named_pipe_a_directory_and_a_descriptor_are_refused_before_any_read(tmp_path):
    pipe = tmp_path / "p.yaml"
    os.mkfifo(pipe)
    err = _returns_at_once(lambda: ArenaEnv(yaml_path=str(pipe)))
    assert isinstance(err, ValueError) and "yaml_path" in str(err) and "named pipe" in str(err), err
    err = _returns_at_once(lambda: ArenaEnv(yaml_path=tmp_path))
    assert isinstance(err, ValueError) and "directory" in str(err), err
    for fd in (0, 1, True, np.int64(0)):
        with pytest.raises(ValueError, match="yaml_path: .* is not a path"):
            ArenaEnv(yaml_path=fd)
    print("still writable")  # file descriptor 1 was not closed


def test_configure_changes_only_the_fields_it_names():
    run = Run({"task": "object-permanence", "t": 300, "agent": {"memory": {"alpha": 0.05}}}, seed=1)
    before = run.config
    answer = run.configure({"agent": {"memory": {"tau": 0.5}}})
    assert answer == {
        "applied": "live",
        "changed": [{"field": "agent.memory.tau", "from": before["agent"]["memory"]["tau"], "to": 0.5, "live": True}],
    }
    after = run.config
    before["agent"]["memory"]["tau"] = 0.5
    assert after == before, "alpha 0.05, t 300 and the task kept"
    answer = run.configure({"t": 400, "agent": {"memory": {"beta": 0.5}}})
    assert answer["applied"] == "restart"
    assert [(c["field"], c["live"]) for c in answer["changed"]] == [("agent.memory.beta", True), ("t", False)]
    assert run.config["agent"]["memory"]["alpha"] == 0.05
    with pytest.raises(ValueError, match="agent.memory.tua"):
        run.configure({"agent": {"memory": {"tua": 1}}})
    with pytest.raises(ValueError, match=r"agent\.memory\.tau: NaN is not a finite number"):
        run.configure({"agent": {"memory": {"tau": float("nan")}}})
    with pytest.raises(ValueError, match=r"agent\.gate: inf"):
        Run({"agent": {"gate": float("inf")}})
    assert run.config["t"] == 400 and run.config["agent"]["memory"]["beta"] == 0.5


def test_reward_and_raw_reward_agree_with_a_gymnasium_loop_over_the_same_seed():
    # The reactive walk: its actions are read back from the run's view, then replayed in the
    # Gymnasium env of the same task and seed, four env steps per decision as the run holds them.
    run = Run({"task": "object-permanence", "kind": "reactive", "t": 200}, seed=5)
    actions, done = [], []
    while not done:
        done = run.decisions(1)
        actions.append(run.view()["action"])
    episode = done[0]
    env = ArenaEnv("object-permanence", frame_skip=4, t=200)
    env.reset(seed=5)
    total, end = 0.0, None
    for a in actions:
        _, reward, terminated, truncated, _ = env.step(a)
        total += reward
        if terminated or truncated:
            end = (terminated, truncated)
            break
    assert end is not None, "the Gymnasium episode ended with the run's"
    assert episode["rawReward"] == pytest.approx(total, abs=1e-9)
    assert episode["reward"] == max(total, 0.0) or episode["reward"] == pytest.approx(max(total, 0.0), abs=1e-9)
    assert episode["rawReward"] == pytest.approx(-1.0, abs=1e-9) and episode["reward"] == 0.0, "a timeout"


def test_a_resume_is_bounded_by_the_caller_and_an_old_format_needs_asking():
    run = Run({"task": "object-permanence", "t": 100}, seed=2)
    log = "".join(run.episode_json() + "\n" for _ in range(3))
    checkpoint, decisions, episodes = run._run.checkpoint()
    assert episodes == 3
    config = run._run.config()
    resumed = _core.Run.resume(config, 2, checkpoint, decisions, 3, log=log)
    assert json.loads(resumed.episode()) == run.episode()
    with pytest.raises(ValueError, match="episodes: 3 claimed, more than the 2 expected"):
        _core.Run.resume(config, 2, checkpoint, decisions, 2)
    with pytest.raises(ValueError, match="log"):
        _core.Run.resume(config, 2, checkpoint, decisions, 3, log=log.replace('"goal":', '"goal": ', 1))
    with pytest.raises(ValueError, match=r"decisions: 18446744073709551615 is out of range"):
        _core.Run.resume(config, 2, checkpoint, 2**64 - 1, 3)
    # Relabelled as the checksum-less version 2 and cut by its checksum: refused unless asked.
    old = b"SECCKPT2" + checkpoint[8:-8]
    with pytest.raises(ValueError, match="version-2 checkpoint"):
        _core.Run.resume(config, 2, old, decisions, 3)


def test_messages_name_the_value_they_were_given():
    vec = ArenaVectorEnv(2, task="cylinder")
    vec.reset(seed=1)
    for big, shown in ((2**63, "9223372036854775808"), (2**64 - 1, "18446744073709551615")):
        with pytest.raises(ValueError, match=rf"actions\[1\]: {shown} is out of range 0..=8"):
            vec.step(np.array([3, big], dtype=np.uint64))
    vec.step(np.array([3, 3], dtype=np.int64))
    frame = np.zeros((84, 84, 3), np.float32)
    with pytest.raises(ValueError, match="frame: an array of float32 and shape"):
        fingerprint(frame)
    with pytest.raises(ValueError, match="frame: an array of uint8 and shape"):
        fingerprint(np.zeros((84, 84), np.uint8))
    with pytest.raises(ValueError, match="frame: dtype int64 is not uint8"):
        sec_playground.Encoder("cylinder").encode([1, 2, 3])
    with pytest.raises(ValueError, match="frame: a list is not a uint8 array"):
        _core.Encoder("cylinder", "trained", 0).encode([1, 2, 3])


def test_parameters_are_the_pages_table_and_run_takes_its_keys():
    table = sec_playground.parameters()
    alpha = next(p for p in table if p["key"] == "alpha")
    assert alpha["kind"]["type"] == "number" and alpha["kind"]["max"] == 1 and alpha["live"]
    assert "alpha" in {p["key"] for p in sec_playground.parameters(agent="sec")}
    assert "alpha" not in {p["key"] for p in sec_playground.parameters(agent="reactive")}
    with pytest.raises(ValueError, match="agent: 'nope' is not one of sec"):
        sec_playground.parameters(agent="nope")
    run = Run({"task": "object-permanence"}, seed=1, alpha=0.02, bias=False)
    assert run.config["agent"]["memory"]["alpha"] == 0.02
    assert run.config["agent"]["memory"]["sequentialBias"] is False
    answer = run.configure(tau=0.5)
    assert answer["applied"] == "live" and [c["field"] for c in answer["changed"]] == ["agent.memory.tau"]
    assert run.config["agent"]["memory"]["alpha"] == 0.02, "kept"
    with pytest.raises(ValueError, match=r"beta: '7' is out of range \[0, 1\]"):
        run.configure(beta=7)
    with pytest.raises(ValueError, match="seed"):
        run.configure(seed=3)
    with pytest.raises(ValueError, match="alpah"):
        Run(alpah=0.1)


def test_the_modules_example_runs():
    import doctest

    result = doctest.testmod(sec_playground)
    assert result.attempted >= 8 and result.failed == 0, result
