"""The README's Python quick start, run exactly as printed: a reader who pastes it gets no error."""

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]


def quick_start() -> str:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("### From Python"):]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert blocks, "the README's Python section has a python block"
    return blocks[0]


def test_the_readme_quick_start_runs_as_printed():
    code = quick_start()
    assert "get_action_meanings" in code
    here = os.getcwd()
    os.chdir(ROOT)  # the block's file paths are the repository's
    try:
        scope: dict = {}
        exec(compile(code, "README.md (From Python)", "exec"), scope)
    finally:
        os.chdir(here)
    # What the comments promise.
    assert scope["obs"].shape == (84, 84, 3)
    assert len(scope["env"].unwrapped.get_action_meanings()) == 9
    assert scope["top"].ndim == 3


def test_the_readme_widget_block_runs_as_printed():
    """The notebook widget's lines (no page shows it here: nothing comes back, nothing fails)."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"```python\n(.*?)```", readme, flags=re.S) if "sec_playground.widget(" in b]
    assert len(blocks) == 1
    scope: dict = {}
    exec(compile(blocks[0], "README.md (the widget)", "exec"), scope)
    assert (scope["w"].task, scope["w"].alpha, scope["w"].episodes) == ("detour", 0.1, [])
