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


def test_bad_configurations_raise_value_error_by_name():
    cases = [
        ({"agent": {"memory": {"alpha": -1}}}, "alpha: -1 is out of range"),
        ({"agent": {"memory": {"tau": "x"}}}, "agent.memory.tau"),
        ({"agnet": {}}, "agnet"),
        ({"task": "nowhere"}, "task"),
        ({"kind": "dqn"}, "kind"),
        ({"agent": {"memory": {"beta": float("nan")}}}, "NaN"),
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
