"""The examples run (tiny sizes): a numpy DQN on pixels, a multiprocessing seed grid, logging
with RecordEpisodeStatistics."""

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_dqn_example_trains_and_writes_its_curve(tmp_path):
    out = tmp_path / "curve.csv"
    returns = load("dqn_pixels").main(["--episodes", "2", "--csv", str(out)])
    assert len(returns) == 2
    lines = out.read_text().splitlines()
    assert lines[0] == "episode,reward,mean20" and len(lines) == 3


def test_the_seed_grid_runs_on_worker_processes():
    args = ["--task", "object-permanence", "--seeds", "2", "--episodes", "3", "--workers", "2"]
    out = subprocess.run([sys.executable, str(EXAMPLES / "seed_grid.py"), *args], capture_output=True, text=True, check=True).stdout
    line = re.search(r"^SEC: mean reward per episode [\d.]+ over 2 seeds \(([\d.]+), ([\d.]+)\)$", out, re.M)
    assert line, out
    # The same numbers as a run in this process: pure functions of configuration and seed.
    assert line.group(2) == f"{load('seed_grid').one(('SEC', 'object-permanence', 2, 3))[2]:.2f}"


def test_record_episode_statistics_logs_every_episode():
    logged = load("record_stats").main(["--num-envs", "2", "--steps", "60", "--max-episode-steps", "25"])
    assert len(logged) >= 4 and all(length <= 25 for _, length in logged)


def test_the_submitit_example_runs_the_shards_to_the_clis_files(tmp_path):
    import os

    import pytest

    binary = os.environ.get("SEC_EXPERIMENT_BIN")
    if not binary or not Path(binary).exists():
        pytest.skip("needs the sec-experiment binary (SEC_EXPERIMENT_BIN, set by scripts/python-test.sh)")
    pytest.importorskip("submitit")
    out = tmp_path / "grid"
    args = ["smoke", "--bin", binary, "--shards", "2", "--seeds", "2", "--episodes", "3", "--out", str(out),
            "--cpus", "1", "--logs", str(tmp_path / "logs"), "--local"]
    load("submitit_grid").main(args)
    whole = tmp_path / "whole"
    subprocess.run([binary, "run", "smoke", "--seeds", "2", "--episodes", "3", "--jobs", "1", "--out", str(whole)], check=True,
                   capture_output=True)
    logs = lambda root: {p.relative_to(root): p.read_bytes() for p in root.rglob("*.jsonl.gz")}
    assert logs(out) and logs(out) == logs(whole)
