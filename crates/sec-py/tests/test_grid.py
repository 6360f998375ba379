"""The experiment grid on Ray (sec_playground.grid): the smoke preset through a local Ray instance
gives the CLI's files byte for byte, a killed task is retried to the same log, bad arguments are
refused before anything starts."""

import gzip
import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

from sec_playground import _core, grid

ray = pytest.importorskip("ray")

# What differs between two makings of one run: when, where and how long.
CLOCK = {"start", "end", "wallSeconds", "cpuSeconds", "host"}


def files(root: Path) -> dict:
    """Every file under `root` by relative path; manifests without their clock fields."""
    out = {}
    for p in sorted(root.rglob("*")):
        if p.is_file():
            data = p.read_bytes()
            if p.name.endswith(".manifest.json"):
                data = {k: v for k, v in json.loads(data).items() if k not in CLOCK}
            out[str(p.relative_to(root))] = data
    return out


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def test_bad_arguments_are_refused_by_name_before_anything_starts(tmp_path):
    with pytest.raises(ValueError, match="exp9"):
        grid.run("exp9", out=tmp_path, episodes=3)
    with pytest.raises(ValueError, match="--only"):
        grid.run("smoke", out=tmp_path, only="nowhere/SEC", episodes=3)
    with pytest.raises(ValueError, match="--seeds"):
        grid.run("smoke", out=tmp_path, seeds="3..1", episodes=3)
    with pytest.raises(ValueError, match="episodes"):
        grid.run("smoke", out=tmp_path, episodes=0)
    assert not any(tmp_path.iterdir()), "nothing written"
    assert not ray.is_initialized()


def test_the_module_runs_from_the_command_line(tmp_path):
    import sys

    out = subprocess.run([sys.executable, "-m", "sec_playground.grid", "run", "smoke", "--only", "object-permanence/reactive",
                          "--seeds", "1", "--episodes", "2", "--out", str(tmp_path), "--num-cpus", "1"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "1 runs made" in out.stderr
    assert (tmp_path / "smoke/object-permanence/reactive/seed-1.jsonl.gz").exists()
    bad = subprocess.run([sys.executable, "-m", "sec_playground.grid", "run", "smoke", "--episodes", "0",
                          "--out", str(tmp_path)], capture_output=True, text=True)
    assert bad.returncode == 1 and "episodes" in bad.stderr
    assert _core.EXPERIMENTS[0] == "exp1"


def test_the_smoke_preset_on_ray_writes_the_clis_files(tmp_path, local_ray):
    binary = os.environ.get("SEC_EXPERIMENT_BIN")
    if not binary or not Path(binary).exists():
        pytest.skip("needs the sec-experiment binary (SEC_EXPERIMENT_BIN, set by scripts/python-test.sh)")
    result = grid.run("smoke", out=tmp_path / "ray", seeds="1..2", episodes=3, progress=False)
    assert result == {"runs": 6, "made": 6, "skipped": 0, "failed": []}
    subprocess.run([binary, "run", "smoke", "--seeds", "1..2", "--episodes", "3", "--jobs", "2",
                    "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    ours, theirs = files(tmp_path / "ray"), files(tmp_path / "cli")
    assert len([k for k in ours if k.endswith(".jsonl.gz")]) == 6
    built = lambda fs: {m["gitCommit"] for k, m in fs.items() if k.endswith(".manifest.json")}
    assert built(ours) == built(theirs), f"the CLI ({binary}) and the wheel are builds of other commits: rebuild"
    assert ours == theirs
    # A second call finds every run finished and plays nothing.
    again = grid.run("smoke", out=tmp_path / "ray", seeds="1..2", episodes=3, progress=False)
    assert again == {"runs": 6, "made": 0, "skipped": 6, "failed": []}


def workers_playing() -> list[int]:
    """PIDs of the Ray workers running a grid task (their process title names the task)."""
    pids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                title = (d / "cmdline").read_bytes().replace(b"\0", b" ")
            except OSError:
                continue
            if b"ray::_run_task" in title:
                pids.append(int(d.name))
    return pids


def test_a_killed_task_is_retried_and_resumes_to_the_same_log(tmp_path, local_ray):
    only, episodes = "object-permanence/SEC", 40
    run_dir = tmp_path / "killed" / "smoke" / "object-permanence" / "SEC"
    killed = []

    def kill_once_a_checkpoint_exists():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            if run_dir.is_dir() and any(p.suffix == ".ckpt" for p in run_dir.iterdir()):
                for pid in workers_playing():
                    os.kill(pid, signal.SIGKILL)
                    killed.append(pid)
            time.sleep(0.05)

    killer = threading.Thread(target=kill_once_a_checkpoint_exists)
    killer.start()
    result = grid.run("smoke", out=tmp_path / "killed", seeds="1..1", episodes=episodes, only=only,
                      checkpoint_every=5, progress=False)
    killer.join()
    assert killed, "the task was killed mid-run"
    assert result["made"] == 1 and not result["failed"]
    # The same log as an uninterrupted run of the same configuration and seed.
    whole = grid.run("smoke", out=tmp_path / "whole", seeds="1..1", episodes=episodes, only=only,
                     checkpoint_every=0, progress=False)
    assert whole["made"] == 1
    log = lambda root: gzip.decompress((root / "smoke/object-permanence/SEC/seed-1.jsonl.gz").read_bytes())
    assert log(tmp_path / "killed") == log(tmp_path / "whole")
    assert len(log(tmp_path / "whole").splitlines()) == episodes


def test_deep_baselines_fail_by_name_and_the_others_finish(tmp_path, local_ray):
    assert "double-t-maze/DQN" in grid.conditions("exp1")
    with pytest.raises(RuntimeError, match="burn"):
        grid.run("exp1", out=tmp_path, seeds="1..1", episodes=1, only="double-t-maze/DQN,double-t-maze/reactive",
                 progress=False)
    assert (tmp_path / "exp1/double-t-maze/reactive/seed-1.jsonl.gz").exists()
