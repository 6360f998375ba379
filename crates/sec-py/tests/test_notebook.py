"""The notebook widget's Python side (sec_playground.notebook): its traits against the settings
table, the checks a value meets before the page sees it, the files it hands the page and what it
makes of the page's messages. The page itself is tested in JupyterLab (tests/browser/notebook.test.mjs)."""

import json

import pytest

import sec_playground
from sec_playground import notebook


class Sent(list):
    """What the widget sends the page, instead of a comm."""

    def __call__(self, content, buffers=None):
        self.append((content, buffers))


@pytest.fixture
def w():
    widget = sec_playground.widget(task="detour", alpha=0.05)
    widget.send = Sent()
    return widget


def test_one_trait_per_setting_with_the_page_defaults():
    widget = sec_playground.widget()
    keys = [p["key"] for p in sec_playground.parameters()]
    for key in keys:
        assert widget.traits()[key].metadata.get("sync"), key
    assert widget.settings == json.loads(sec_playground._core.page_settings([], []))
    assert set(widget.settings) == set(keys)


def test_settings_are_typed_and_take_any_spelling_of_a_key():
    widget = sec_playground.widget(task="cylinder", theta_abs="0.5", minSequences=3, embedding_scale="auto")
    assert (widget.task, widget.thetaAbs, widget.minSequences, widget.embeddingScale) == ("cylinder", 0.5, 3, "auto")
    assert widget.settings["thetaAbs"] == "0.5"


@pytest.mark.parametrize("settings, message", [
    ({"alpha": 2}, r"alpha: .* out of range \[0, 1\]"),
    ({"m": 2}, r"minSequences: .*m = 2"),
    ({"task": "maze"}, r"task: .*double-t-maze"),
    ({"bogus": 1}, r"bogus"),
])
def test_a_bad_setting_is_refused_naming_it(settings, message):
    with pytest.raises(ValueError, match=message):
        sec_playground.widget(**settings)


def test_a_refused_trait_keeps_its_value_and_sends_nothing(w):
    with pytest.raises(ValueError, match=r"tau: .*\[0.01, 100\]"):
        w.tau = 1000
    assert w.settings["tau"] == str(w.tau) or float(w.settings["tau"]) == w.tau
    with pytest.raises(ValueError, match="minSequences"):
        w.m = 3
    assert w.m == 500
    w.m = 40
    assert (w.m, w.settings["m"]) == (40, "40")


def test_hide_takes_parts_and_setting_keys_only(w):
    w.hide = "compare alpha, charts"
    with pytest.raises(Exception, match="hide: bogus is not a part"):
        w.hide = "controls bogus"
    assert w.hide == "compare alpha, charts"


def test_the_page_gets_the_wheels_files_and_nothing_else(w):
    w._on_page(w, {"type": "file", "id": 1, "path": "pkg/sec_playground_bg.wasm"}, [])
    content, buffers = w.send[-1]
    assert content == {"type": "file", "id": 1, "path": "pkg/sec_playground_bg.wasm"}
    assert buffers[0][:4] == b"\0asm"
    w._on_page(w, {"type": "file", "id": 2, "path": "assets/encoders/detour.secae"}, [])
    assert len(w.send[-1][1][0]) > 100_000
    for bad in ["../notebook.py", "../../sec_playground/__init__.py", "/etc/passwd", "assets/nothing.json", "assets"]:
        w._on_page(w, {"type": "file", "id": 3, "path": bad}, [])
        content, buffers = w.send[-1]
        assert content["error"] == "not among the widget's files" and buffers is None, bad


def test_episodes_stream_in_and_a_new_run_starts_them_again(w):
    w._on_page(w, {"type": "episodes", "rows": [{"episode": 1, "reward": 0.0}, {"episode": 2, "reward": 1.0}]}, [])
    w._on_page(w, {"type": "episodes", "rows": [{"episode": 3, "reward": 0.5}]}, [])
    assert [e["episode"] for e in w.episodes] == [1, 2, 3]
    w.episodes.clear()  # a copy
    assert len(w.episodes) == 3
    w._on_page(w, {"type": "run"}, [])
    assert w.episodes == []


def test_the_pages_changes_reach_the_traits_and_only_those(w):
    w._on_page(w, {"type": "settings", "settings": {"beta": "0.3", "m": "100"}}, [])
    assert (w.beta, w.m, w.alpha) == (0.3, 100, 0.05)
    assert w.send == [], "a value from the page is not sent back"


def test_explanation_state_and_errors_are_kept(w):
    assert w.explain() is None
    w._on_page(w, {"type": "explanation", "explanation": {"p": [0.1] * 9, "couplets": []}}, [])
    w._on_page(w, {"type": "state", "state": {"playing": False, "episode": 4}}, [])
    w._on_page(w, {"type": "error", "message": "m: 2 is out of range"}, [])
    assert w.explain()["p"] == [0.1] * 9
    assert w.state["episode"] == 4
    assert w.errors == ["m: 2 is out of range"]


def test_commands_go_to_the_page(w):
    w.pause()
    w.step("episode")
    w.play()
    w.reset()
    assert [c[0] for c in w.send] == [
        {"type": "command", "name": "pause", "args": []},
        {"type": "command", "name": "step", "args": ["episode"]},
        {"type": "command", "name": "play", "args": []},
        {"type": "command", "name": "reset", "args": []},
    ]
    with pytest.raises(ValueError, match="what: 'forever'"):
        w.step("forever")


def test_the_wheel_carries_the_module_and_its_files():
    assert notebook._ESM.is_file() and notebook._ESM.stat().st_size > 100_000
    for path in ["pkg/sec_playground_bg.wasm", "pkg/scalar/sec_playground_bg.wasm", "www/style.css",
                 "assets/reference/index.json", "assets/warm-up/index.json"]:
        assert (notebook._FILES / path).is_file(), path
    for task in sec_playground.tasks():
        assert (notebook._FILES / "assets" / "encoders" / f"{task['name']}.secae").is_file(), task["name"]
