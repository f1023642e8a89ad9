"""EngineJob: one engine call at a time per pane, with the switch its engine looks at."""

from __future__ import annotations

import threading

import pytest
from textual import work
from textual.app import App
from textual.worker import Worker

from skillwright.tui.jobs import EngineJob
from tests.tui.conftest import running, wait_until

pytestmark = pytest.mark.anyio


class _Host(App[None]):
    """Runs a stand-in engine call that works until its switch is set."""

    def __init__(self) -> None:
        super().__init__()
        self.job = EngineJob()
        self.started: list[int] = []
        self.stopped: list[int] = []

    @work(thread=True, exit_on_error=False)
    def call(self, number: int, cancel: threading.Event) -> None:
        self.started.append(number)
        cancel.wait(60)
        self.stopped.append(number)

    def start(self, number: int) -> Worker[None]:
        self.job.start(lambda cancel: self.call(number, cancel))
        assert self.job.worker is not None
        return self.job.worker


async def test_stopping_sets_the_switch_and_starting_again_stops_the_previous_call() -> None:
    app = _Host()
    async with running(app, (40, 10)) as pilot:
        assert not app.job.stop(), "nothing runs yet"
        first = app.start(1)
        assert app.job.running
        await wait_until(pilot, lambda: app.started == [1])
        app.start(2)
        await wait_until(pilot, lambda: app.stopped == [1])
        assert first.is_cancelled
        await wait_until(pilot, lambda: app.started == [1, 2])
        assert app.job.stop()
        await wait_until(pilot, lambda: app.stopped == [1, 2])
        await wait_until(pilot, lambda: not app.job.running)
        assert not app.job.stop()
