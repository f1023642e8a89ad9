"""Fixtures of the TUI tests: a workspace copied from the shipped capabilities, an isolated
configuration, the tiny GGUF model, and helpers to wait for workers and read the screen."""

from __future__ import annotations

import asyncio
import io
import itertools
import shutil
import threading
import time
import weakref
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import pytest
from pytest_textual_snapshot import SVGImageExtension
from textual.app import App
from textual.pilot import Pilot
from textual.widgets import OptionList

from skillwright.tui.app import SkillwrightApp, make_app
from skillwright.tui.screens.base import Pane
from skillwright.tui.session import SessionState, save_session
from skillwright.tui.workspace import Workspace
from tests.conftest import SHIPPED_CAPABILITIES
from tests.llm.conftest import isolated_config, tiny_gguf, wordy_gguf

# pytest-textual-snapshot 1.0 names the snapshot suffix the syrupy 4 way (_file_extension);
# syrupy 5 and later read file_extension and would store the SVG snapshots as .raw files.
SVGImageExtension.file_extension = "svg"

__all__ = [
    "MODEL_RUN",
    "STEP",
    "Gate",
    "Watch",
    "choose",
    "isolated_config",
    "running",
    "screen_text",
    "tiny_gguf",
    "wait_until",
    "wordy_gguf",
]


STEP = 120.0
"""Deadline of one step of the app (a worker reading a file, keys handled): it takes a
second or two on an idle machine, and ten times that on a 2-core machine busy with builds
and other test runs. Only a failing test waits this long."""

MODEL_RUN = 600.0
"""Deadline of a run of the tiny model: a generation prompt is about 6,000 tokens of the wordy
tiny model (16,000 of the byte-level one), evaluated in seconds on an idle machine and in
minutes on a busy one."""


@pytest.fixture
def anyio_backend() -> str:
    """Pilot tests run on asyncio (Textual's loop); anyio's plugin runs ``async def`` tests."""
    return "asyncio"


@pytest.fixture(scope="session")
def _run_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("tui-cache")


@pytest.fixture(autouse=True)
def _config(isolated_config: Path, _run_cache: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Every TUI test gets its own configuration and data folders.

    The cache folder is shared by the run's TUI tests, as a user's runs share theirs: the
    tiny model's 6,000-token prompt prefix is then evaluated once per run instead of once
    per generating test (half a minute each on a busy machine).
    """
    monkeypatch.setenv("XDG_CACHE_HOME", str(_run_cache))
    return isolated_config


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    """A copy of the shipped ``capabilities/`` folder (a workspace as it is) at ``.../workspace``."""
    root = tmp_path / "workspace"
    shutil.copytree(SHIPPED_CAPABILITIES, root)
    return root


def write_models(path: Path, model_file: Path, *, max_tokens: int = 32) -> Path:
    """A models.toml whose default generation model is ``tiny`` (room for the long prompt:
    the tiny model's tokenizer spends about one token per two characters)."""
    path.write_text(
        f"""
[defaults]
generation = "tiny"

[[llm]]
id = "tiny"
file = "{model_file.as_posix()}"
context_length = 32768
batch_size = 512
threads = 1

[llm.sampling]
max_tokens = {max_tokens}

[[llm]]
id = "ghost"
file = "{(path.parent / "ghost.gguf").as_posix()}"
""",
        encoding="utf-8",
    )
    return path


@pytest.fixture
def models_file(tmp_path: Path, wordy_gguf: Path) -> Path:
    """The tiny model as default (32 tokens) and ``ghost``, a model whose file is missing."""
    return write_models(tmp_path / "models.toml", wordy_gguf)


def preset_session(workspace: Path, **values: object) -> SessionState:
    """Writes a session into the workspace as if a previous run had left it."""
    state = SessionState(**values)  # type: ignore[arg-type]
    save_session(Workspace(workspace).session_path, state)
    return state


def app_for(workspace: Path, models_file: Path | None = None) -> SkillwrightApp:
    """The app as the CLI builds it, saving the session quickly for the tests; without
    animations, so what a snapshot shows does not depend on when it is taken."""
    app = make_app(workspace, models_file=models_file)
    app.save_delay = 0.05
    app.animation_level = "none"
    told: list[str] = []
    show = app.notify

    def notify(message: str, *args: Any, **kwargs: Any) -> None:
        told.append(message)
        show(message, *args, **kwargs)

    app.notify = notify  # type: ignore[method-assign]
    _told[app] = told
    return app


@asynccontextmanager
async def running(app: App[None], size: tuple[int, int] = (120, 40)) -> AsyncIterator[Pilot[None]]:
    """Runs ``app`` headless at ``size`` once its widgets have all mounted.

    Keys pressed before the tabs have finished mounting would be overridden by the tabs'
    own start-up; a user cannot type that fast, a test can.
    """
    async with app.run_test(size=size) as pilot:
        await pilot.pause()
        try:
            yield pilot
        finally:
            # A test that fails mid-run leaves without the app's quit path: stop its jobs, or
            # their threads would hold the test run until they finish on their own.
            for pane in app.query(Pane):
                pane.cancel_job()


async def wait_until(
    pilot: Pilot[object], condition: Callable[[], object], timeout: float = STEP
) -> None:
    """Lets the app run until ``condition()`` is true; fails the test after ``timeout``."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"timed out after {timeout} s waiting for {condition.__doc__ or condition}")
        await pilot.pause(0.05)
    await pilot.pause()  # let the screen catch up with what the condition saw


async def choose(pilot: Pilot[object], options: OptionList, label: str) -> None:
    """Moves to the option ``label`` with the arrow keys and presses Enter, as a user would."""
    labels = [str(options.get_option_at_index(i).prompt) for i in range(options.option_count)]
    options.focus()
    await pilot.press("home", *["down"] * labels.index(label), "enter")


def screen_text(app: App[object]) -> str:
    """The visible screen as plain text (what a user reads), for assertions and notes."""
    from rich.console import Console

    width, height = app.size
    console = Console(
        width=width,
        height=height,
        file=io.StringIO(),
        force_terminal=True,
        record=True,
        legacy_windows=False,
        safe_box=False,
    )
    console.print(
        app.screen._compositor.render_update(full=True, screen_stack=app._background_screens)
    )
    return console.export_text()


def rich_text(renderable: object, width: int = 120) -> str:
    """A rich renderable as the plain text it prints."""
    from rich.console import Console

    console = Console(width=width, file=io.StringIO(), record=True)
    console.print(renderable)
    return console.export_text()


_told: weakref.WeakKeyDictionary[App[Any], list[str]] = weakref.WeakKeyDictionary()


def notifications(app: App[Any]) -> list[str]:
    """Messages of every notification the app has shown, expired ones included: a toast
    lasts 5 s, and a busy machine may take longer than that to get the test to look."""
    return list(_told[app])


class Gate:
    """Holds the engine inside one of its steps until the test opens the gate, so the test
    can cancel while the step runs (as a user pressing Esc during a slow read would)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, module: object, name: str) -> None:
        self.entered = threading.Event()
        self.opened = threading.Event()
        real = getattr(module, name)

        def held(*args: Any, **kwargs: Any) -> Any:
            self.entered.set()
            self.opened.wait(STEP)
            return real(*args, **kwargs)

        monkeypatch.setattr(module, name, held)

    async def reached(self) -> None:
        """Waits (without blocking the app) until a worker is inside the step."""
        assert await asyncio.to_thread(self.entered.wait, STEP), "the engine never got there"

    def open(self) -> None:
        """Lets the step finish."""
        self.opened.set()


class Watch:
    """Records what an engine function called by a worker returned or raised, call by call."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, module: object, name: str) -> None:
        self.outcomes: dict[int, object] = {}
        """Each call's result or exception by the order the calls began in."""
        self.returned = threading.Event()
        """Set once the first call has returned (later calls may return before it)."""
        calls = itertools.count()
        real = getattr(module, name)

        def watched(*args: Any, **kwargs: Any) -> Any:
            call = next(calls)
            try:
                result = real(*args, **kwargs)
            except BaseException as error:
                self._ended(call, error)
                raise
            self._ended(call, result)
            return result

        monkeypatch.setattr(module, name, watched)

    def _ended(self, call: int, outcome: object) -> None:
        self.outcomes[call] = outcome
        if call == 0:
            self.returned.set()

    async def first(self) -> object:
        """The first call's result or exception, once it has returned."""
        assert await asyncio.to_thread(self.returned.wait, STEP), "the engine call never returned"
        return self.outcomes[0]
