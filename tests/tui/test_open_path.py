"""The open dialog: a path that does not exist is refused with the reason in view."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.app import App, ComposeResult
from textual.widgets import Input, Static

from skillwright.tui.screens.open_path import OpenPathScreen, missing_part
from tests.tui.conftest import running, screen_text

pytestmark = pytest.mark.anyio


class _Host(App[None]):
    """An empty app that shows the dialog and keeps what it returned."""

    def __init__(self, start: Path, *, must_exist: bool = True) -> None:
        super().__init__()
        self.start = start
        self.must_exist = must_exist
        self.returned: list[Path | None] = []

    def compose(self) -> ComposeResult:
        yield Static("host")

    def on_mount(self) -> None:
        dialog = OpenPathScreen("Open a file", self.start, must_exist=self.must_exist)
        self.push_screen(dialog, self.returned.append)


def test_the_missing_part_names_the_first_step_that_does_not_exist(tmp_path: Path) -> None:
    (tmp_path / "here").mkdir()
    (tmp_path / "file.ttl").write_text("", encoding="utf-8")
    assert missing_part(tmp_path / "here" / "x.ttl") == f"x.ttl is not in {tmp_path / 'here'}"
    assert missing_part(tmp_path / "gone" / "deeper" / "x.ttl") == f"gone is not in {tmp_path}"
    assert (
        missing_part(tmp_path / "file.ttl" / "x")
        == f"{tmp_path / 'file.ttl'} is a file, not a folder"
    )


# A path far longer than any terminal line, as deep project folders give.
LONG = "/".join(f"{i:02d}-a-folder-name-that-is-long-on-purpose" for i in range(6))


@pytest.mark.parametrize("size", [(80, 24), (100, 30), (200, 50)], ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("depth", ["short", "long"])
async def test_a_missing_file_is_refused_and_the_reason_is_in_view(
    tmp_path: Path, size: tuple[int, int], depth: str
) -> None:
    folder = tmp_path / "x" if depth == "short" else tmp_path / LONG
    folder.mkdir(parents=True)
    app = _Host(tmp_path)
    async with running(app, size) as pilot:
        assert isinstance(app.screen, OpenPathScreen)
        field = app.screen.query_one("#open-path", Input)
        field.value = str(folder / "nothing.ttl")
        await pilot.press("enter")
        assert isinstance(app.screen, OpenPathScreen), "the dialog stays open"
        error = app.screen.query_one("#open-error", Static)
        assert str(error.render()) == f"no such file or folder: nothing.ttl is not in {folder}"
        # The reason starts the message, so it is on one line whatever the path's length.
        assert error.region.height >= 1
        assert error.region.y + error.region.height <= size[1]
        assert "no such file or folder: nothing.ttl is not in" in screen_text(app)
        (folder / "nothing.ttl").write_text("", encoding="utf-8")
        await pilot.press("enter")
        assert app.returned == [folder / "nothing.ttl"]


async def test_saving_needs_an_existing_folder_and_names_the_one_missing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    started_in = tmp_path / "started-in"
    started_in.mkdir()
    monkeypatch.chdir(started_in)
    app = _Host(tmp_path, must_exist=False)
    async with running(app, (80, 24)) as pilot:
        field = app.screen.query_one("#open-path", Input)
        field.value = str(tmp_path / "new" / "skill.spec.yaml")
        await pilot.press("enter")
        error = app.screen.query_one("#open-error", Static)
        assert str(error.render()) == f"no such folder: new is not in {tmp_path}"
        # Relative: from the folder the TUI was started in, not the tree's (the workspace).
        assert str(started_in) in field.placeholder
        field.value = "skill.spec.yaml"
        await pilot.press("enter")
        assert app.returned == [started_in / "skill.spec.yaml"]
