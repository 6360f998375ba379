"""The playground in a notebook cell: an anywidget (JupyterLab, Notebook, VS Code, Colab, marimo)
whose front end is the page's <sec-playground> element, wasm and all, from the wheel (no network).

    >>> w = sec_playground.widget(task="detour", alpha=0.05)   # doctest: +SKIP
    >>> w                                                      # shows it; it learns in the cell
    >>> w.alpha = 0.1        # the page's knob moves; a value the page refuses comes back as it was
    >>> w.episodes[-1]       # the episodes of the run on the page, as the page's export has them
    >>> w.pause(); w.step()  # then, in the next cell: w.explain()

Settings are traits named by the settings table's keys (`sec_playground.parameters()`: task,
alpha, thetaAbs, ...), synced both ways; `hide` and `autoplay` are the element's attributes.
Messages from the page (episodes, explanations, errors) arrive between cells: a cell that waits
for them in a loop holds the kernel and sees none.
"""

import json
import math
from pathlib import Path
from typing import Any, Optional

import anywidget
import traitlets

from . import _core

_HERE = Path(__file__).parent / "_widget"
_ESM = _HERE / "widget.js"
_FILES = _HERE / "files"
#: The parts the `hide` attribute takes besides setting keys (the element's; docs/EMBED.md).
_PARTS = ("runbar", "keepbar", "controls", "views", "charts", "compare",
          "camera", "arena", "reconstruction", "heat", "policy")


def _trait(param: dict, default: str) -> traitlets.TraitType:
    """The trait of one setting of the table, with the page's default."""
    kind = param["kind"]
    help_ = f"{param['help']} ({'live' if param['live'] else 'a new run'})"
    if kind["type"] == "integer":
        return traitlets.Int(int(default), help=help_)
    if kind["type"] == "number":
        if kind.get("auto"):
            value = default if default == "auto" else float(default)
            return traitlets.Union([traitlets.Float(), traitlets.Enum(["auto"])], default_value=value, help=help_)
        return traitlets.Float(float(default), help=help_)
    if kind["type"] == "switch":
        return traitlets.Int(int(default), help=help_)
    return traitlets.Unicode(default, help=help_)


def _text(value: Any) -> str:
    """A trait's value as the page's settings write it."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float) and value.is_integer() and not math.isinf(value):
        return repr(value)
    return str(value)


class _Base(anywidget.AnyWidget):
    _esm = _ESM if _ESM.exists() else "export default { render({ el }) { el.textContent = " \
        "'This sec_playground was installed without its widget files (scripts/build.sh makes them).'; } }"
    hide = traitlets.Unicode("", help="Parts or setting keys to hide, space-separated").tag(sync=True)
    autoplay = traitlets.Bool(True, help="Play when shown").tag(sync=True)

    def __init__(self, **kwargs: Any):
        # Each value is checked against the others' final values, whatever order they are set in.
        keys = [k for k in kwargs if k in self.class_traits() and k not in ("hide", "autoplay")]
        self._settings: dict[str, str] = json.loads(_core.page_settings([], [(k, _text(kwargs[k])) for k in keys]))
        self._episodes: list[dict] = []
        self._explanation: Optional[dict] = None
        self._state: dict = {}
        self._errors: list[str] = []
        self._from_page = False
        super().__init__(**kwargs)
        self.on_msg(self._on_page)

    @traitlets.validate(*(p["key"] for p in json.loads(_core.parameters_json(None))))
    def _check_setting(self, proposal):
        """A value the core's table refuses raises here, naming the key and its range, and the
        trait keeps its value; a fine one goes to the page."""
        key = proposal["trait"].name
        if self._from_page:
            return proposal["value"]
        merged = json.loads(_core.page_settings(list(self._settings.items()), [(key, _text(proposal["value"]))]))
        return _typed(self.traits()[key], merged[key])

    @traitlets.observe(*(p["key"] for p in json.loads(_core.parameters_json(None))))
    def _setting_changed(self, change):
        self._settings[change["name"]] = _text(change["new"])

    @traitlets.validate("hide")
    def _check_hide(self, proposal):
        keys = set(self._settings)
        bad = [w for w in proposal["value"].replace(",", " ").split() if w not in keys and w not in _PARTS]
        if bad:
            raise traitlets.TraitError(
                f"hide: {', '.join(bad)} {'is' if len(bad) == 1 else 'are'} not a part "
                f"({', '.join(_PARTS)}) or a setting key")
        return proposal["value"]

    # What the page says, between cells.
    def _on_page(self, _widget, msg: dict, buffers: list) -> None:
        kind = msg.get("type")
        if kind == "file":
            self._send_file(msg)
        elif kind == "episodes":
            self._episodes.extend(msg.get("rows", []))
        elif kind == "run":
            self._episodes = []
        elif kind == "settings":
            self._mirror(msg.get("settings") or {})
        elif kind == "explanation":
            self._explanation = msg.get("explanation")
        elif kind in ("state", "result"):
            self._state = msg.get("state") or {}
        elif kind == "error":
            self._errors.append(str(msg.get("message")))

    def _mirror(self, settings: dict) -> None:
        """Settings the page changed (a control moved) or kept (it refused Python's values)
        into the traits; only those: others of Python's may still be on their way."""
        self._from_page = True
        try:
            with self.hold_trait_notifications():
                for key, text in settings.items():
                    if key in self.traits() and key in self._settings:
                        value = _typed(self.traits()[key], text)
                        if getattr(self, key) != value:
                            setattr(self, key, value)
            self._settings.update({k: str(v) for k, v in settings.items() if k in self._settings})
        finally:
            self._from_page = False

    def _send_file(self, msg: dict) -> None:
        """A file the page asks for: the wasm, a model, a reference run, a style sheet; only
        those the wheel carries, by their path in the package."""
        path = str(msg.get("path", ""))
        target = (_FILES / path).resolve()
        if ".." in Path(path).parts or not target.is_relative_to(_FILES.resolve()) or not target.is_file():
            self.send({"type": "file", "id": msg.get("id"), "path": path, "error": "not among the widget's files"})
            return
        self.send({"type": "file", "id": msg.get("id"), "path": path}, buffers=[target.read_bytes()])

    # Driving it.
    def _command(self, name: str, *args: Any) -> None:
        self.send({"type": "command", "name": name, "args": list(args)})

    def play(self) -> None:
        """Plays (the page's Play)."""
        self._command("play")

    def pause(self) -> None:
        """Pauses; the page then explains each decision it steps."""
        self._command("pause")

    def reset(self) -> None:
        """A new run with the same settings and seed."""
        self._command("reset")

    def step(self, what: str = "decision") -> None:
        """One decision or one episode (`what`), paused after it."""
        if what not in ("decision", "episode"):
            raise ValueError(f"what: {what!r} is not 'decision' or 'episode'")
        self._command("step", what)

    # Reading it.
    @property
    def settings(self) -> dict:
        """Every setting, as the page's URL hash writes it."""
        return dict(self._settings)

    @property
    def episodes(self) -> list:
        """The finished episodes of the page's current run (its metrics rows, as the page's
        export and `Run.episode()` have them), up to the last message the page sent."""
        return list(self._episodes)

    def episodes_frame(self):
        """`episodes` as a pandas DataFrame (pandas is not a dependency: install it)."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("episodes_frame needs pandas (pip install pandas); episodes is a list of dicts") from e
        return pd.DataFrame(self._episodes)

    def explain(self) -> Optional[dict]:
        """The last decision the page explained (it does while paused or stepping), as
        `Run.explain()` gives it: couplets (sequence, position, g, t, rr, d, action, value), q
        and p per action, tau, valueFunction, thetaAbs, thetaProp, sequentialBias; None before
        the first."""
        return self._explanation

    @property
    def state(self) -> dict:
        """The page's last reported state: playing, running, decisions, episode, ltm, capacity."""
        return dict(self._state)

    @property
    def errors(self) -> list:
        """The errors the page reported, oldest first (a refused value names its key and range)."""
        return list(self._errors)


def _typed(trait: traitlets.TraitType, text: str) -> Any:
    """The page's text of a setting as the trait's type."""
    if isinstance(trait, traitlets.Int):
        return int(text)
    if isinstance(trait, traitlets.Float):
        return float(text)
    if isinstance(trait, traitlets.Union):
        return text if text == "auto" else float(text)
    return text


def _widget_class() -> type:
    """The widget's class: one synced trait per key of the core's settings table."""
    defaults = json.loads(_core.page_settings([], []))
    traits = {p["key"]: _trait(p, defaults[p["key"]]).tag(sync=True) for p in json.loads(_core.parameters_json(None))}
    doc = __doc__
    return type("PlaygroundWidget", (_Base,), {**traits, "__doc__": doc, "__module__": __name__})


PlaygroundWidget = _widget_class()


def widget(task: str = "double-t-maze", *, hide: str = "", autoplay: bool = True, **settings: Any) -> "PlaygroundWidget":
    """The playground as a notebook widget: `task` and any settings of `sec_playground.parameters()`
    by their keys (any case or kebab/snake form: `theta_abs=0.05`), checked together as the page
    checks them; a bad one raises ValueError naming it and its range."""
    pairs = [("task", _text(task))] + [(k, _text(v)) for k, v in settings.items()]
    checked = json.loads(_core.page_settings([], pairs))  # raises on a bad key or value
    values = {k: _typed(PlaygroundWidget.class_traits()[k], checked[k]) for k in checked}
    return PlaygroundWidget(hide=hide, autoplay=autoplay, **values)
