"""SEC and its baselines from Python, and the bundled encoders."""

import struct

import numpy as np
import pytest

from sec_playground import ArenaEnv, Encoder, Run


def test_a_run_from_python_gives_the_native_golden_run_log(golden):
    # `sec_playground::experiment::fixtures::golden_run(Untrained)`'s configurations.
    sec = {"task": "object-permanence"}
    mfec = {"warmupDecisions": 100, "warmupRewardedEpisodes": 1}
    mfec_ae = dict(sec, kind="mfec", t=250, mfec=mfec)
    mfec_rp = dict(mfec_ae, mfec=dict(mfec, embedding="random-projection"))
    reactive = dict(sec, kind="reactive", t=250, mfec=dict(mfec, embedding="random-projection"))
    lines = []
    for config, episodes in [(sec, 20), (mfec_ae, 6), (mfec_rp, 6), (reactive, 2)]:
        run = Run(config, seed=2)
        lines += [run.episode_json() for _ in range(episodes)]
    assert lines == (golden / "run-untrained.txt").read_text().splitlines()


def test_a_textured_run_from_python_gives_the_native_golden_log(golden):
    # `sec_playground::experiment::fixtures::golden_textured_run()`.
    run = Run({"surface": "textured", "agent": {"minSequences": 1}}, seed=1)
    lines = [run.episode_json() for _ in range(30)]
    assert lines == (golden / "run-textured.txt").read_text().splitlines()


def test_bad_configurations_raise_value_error_by_name():
    cases = [
        ({"agent": {"memory": {"alpha": -1}}}, "alpha: -1 is out of range"),
        ({"agent": {"memory": {"tau": "x"}}}, "agent.memory.tau"),
        ({"agnet": {}}, "agnet"),
        ({"task": "nowhere"}, "task"),
        ({"kind": "dqn"}, "kind"),
        ({"agent": {"memory": {"beta": float("nan")}}}, "agent.memory.beta: NaN"),
    ]
    for config, name in cases:
        with pytest.raises(ValueError, match=name):
            Run(config, seed=1)
    for seed in (-1, 2**60, 1.5, True):
        with pytest.raises(ValueError, match="seed"):
            Run({}, seed=seed)
    with pytest.raises(ValueError, match="config"):
        Run([1, 2], seed=1)


def test_the_bundled_encoder_gives_the_golden_embedding(golden):
    env = ArenaEnv("double-t-maze")
    obs, _ = env.reset(seed=1)
    e = Encoder("double-t-maze").encode(obs)
    assert e.shape == (20,) and e.dtype == np.float32
    bits = [f"{struct.unpack('>I', struct.pack('>f', float(v)))[0]:08x}" for v in e]
    assert bits == (golden / "embedding.txt").read_text().splitlines()[:20]
    untrained = Encoder("double-t-maze", perception="untrained", seed=3)
    assert np.array_equal(untrained.encode(obs), Encoder("double-t-maze", "untrained", 3).encode(obs))
    assert not np.array_equal(untrained.encode(obs), e)
    with pytest.raises(ValueError, match="perception"):
        Encoder("double-t-maze", perception="pretrained")
    with pytest.raises(ValueError, match="frame"):
        Encoder("double-t-maze").encode(np.zeros((84, 84, 4), np.uint8))


def test_a_run_shows_and_explains_its_decisions_as_the_page_does():
    run = Run({"task": "object-permanence"}, seed=2)
    view = run.view()
    assert view["action"] is None and view["decisions"] == 0
    assert set(view) == {
        "action", "layer", "selected", "entropy", "p", "gateMse", "ltm", "capacity", "episode", "step",
        "episodeReward", "x", "z", "heading", "decisions", "minSequences", "gate", "embedding",
    }
    # Golden seed 2: the contextual layer acts from the 16th episode.
    explained = None
    for _ in range(40):
        run.decisions(500)
        e = run.explain()
        if e["couplets"]:
            explained = e
            break
    assert explained is not None, "memory selected couplets within 20000 decisions"
    q = [0.0] * 9
    for c in explained["couplets"]:
        q[c["action"]] += c["value"]
    assert q == pytest.approx(explained["q"], rel=1e-12)
    assert sum(explained["p"]) == pytest.approx(1.0)
    view = run.view()
    assert view["selected"] == len(explained["couplets"]) and len(view["embedding"]) == 20
    assert view["decisions"] >= 500 and view["ltm"] >= 1
    assert run.configure({"task": "object-permanence", "agent": {"memory": {"tau": 0.5}}})["applied"] == "live"
    assert run.explain()["tau"] == 0.5
    assert run.configure({"task": "object-permanence", "agent": {"memory": {"n": 30}}})["applied"] == "restart"
    assert run.view()["decisions"] == 0
    with pytest.raises(ValueError, match="tau"):
        run.configure({"agent": {"memory": {"tau": -1}}})
    assert run.config["agent"]["memory"]["n"] == 30
    for n in (0, 100_001, 1.5, True):
        with pytest.raises(ValueError, match="n:"):
            run.decisions(n)
    mfec = Run({"task": "object-permanence", "kind": "mfec"}, seed=1)
    mfec.decisions(10)
    assert mfec.view()["embedding"] is None and mfec.explain()["couplets"] == []


def test_the_agent_table_runs_every_agent_the_page_offers():
    from sec_playground import agents

    table = agents()
    keys = [a["key"] for a in table]
    assert len(set(keys)) == len(keys) and any(a["nativeOnly"] for a in table)
    for a in table:
        config = {"task": "object-permanence", "kind": a["kind"]}
        if a["mfecEmbedding"]:
            config["mfec"] = {"embedding": a["mfecEmbedding"]}
        if a["nativeOnly"]:
            with pytest.raises(ValueError, match="kind"):
                Run(config, seed=1)
            continue
        run = Run(config, seed=1)
        run.decisions(5)
        assert (run.view()["embedding"] is not None) == a["hasMemory"], a["key"]


def test_an_olympics_arena_file_runs_from_python_as_natively(golden, repo):
    # `sec_playground::experiment::fixtures::golden_arena_run()`: the file named by its stem, the
    # untrained encoder and no gate, minSequences 1, seed 3.
    path = repo / "assets" / "arenas" / "competition" / "05-25-01.yaml"
    run = Run({"agent": {"minSequences": 1}}, seed=3, yaml_path=path)
    config = run.config
    assert (config["task"], config["perception"], config["agent"]["gate"]) == ("05-25-01", "untrained", None)
    lines = [run.episode_json() for _ in range(12)]
    assert lines == (golden / "run-arena.txt").read_text().splitlines()
    # What needs a model trained on the arena is refused by name, whether asked in the config or as a setting.
    with pytest.raises(ValueError, match="perception"):
        Run({"perception": "trained"}, yaml_path=path)
    with pytest.raises(ValueError, match="agent.gate"):
        Run({"agent": {"gate": 0.01}}, yaml_path=path)
    with pytest.raises(ValueError, match="perception"):
        Run(yaml_path=path, perception="trained")
    with pytest.raises(ValueError, match="yaml_path"):
        Run(yaml_path=3)
