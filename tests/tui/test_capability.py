"""The Capability tab: browse the workspace's models, read one, open any file, bad files."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.widgets import Input, OptionList, Static, TabbedContent

from skillwright.errors import OperationCancelledError
from skillwright.tui.screens.capability import CapabilityPane
from skillwright.tui.screens.open_path import OpenPathScreen
from skillwright.tui.session import load_session
from tests.tui.conftest import (
    Gate,
    Watch,
    app_for,
    choose,
    notifications,
    preset_session,
    rich_text,
    running,
    screen_text,
    wait_until,
)

pytestmark = pytest.mark.anyio


async def test_choosing_a_model_shows_its_inputs_outputs_and_limits(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        options = app.query_one("#capability-list", OptionList)
        assert app.focused is options
        await choose(pilot, options, "move-forward.ttl")
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        assert "Move forward" in screen_text(app)
        summary = rich_text(app.query_one(CapabilityPane).summary)
        assert "inDistance" in summary
        assert "linearVelocity <= 0.8 m/s" in summary
        assert "from move-forward.ttl" in summary  # workspace-relative, wherever it is
        assert "owl:imports" in str(app.query_one("#capability-status", Static).render())
        assert app.session.capability == "move-forward.ttl"


async def test_a_file_outside_the_workspace_opens_from_the_dialog(
    workspace: Path, tmp_path: Path
) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "turn.ttl").write_bytes((workspace / "rotate.ttl").read_bytes())
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        await pilot.press("ctrl+o")
        assert isinstance(app.screen, OpenPathScreen)
        field = app.screen.query_one("#open-path", Input)
        field.value = str(elsewhere / "nothing.ttl")
        await pilot.press("enter")
        error = app.screen.query_one("#open-error", Static)
        assert str(error.render()) == f"no such file or folder: nothing.ttl is not in {elsewhere}"
        assert "no such file or folder: nothing.ttl" in screen_text(app)
        field.value = str(elsewhere / "turn.ttl")
        await pilot.press("enter")
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        assert app.loaded.capability_path == elsewhere / "turn.ttl"
        assert app.session.capability == str(elsewhere / "turn.ttl")
        assert "Rotate" in screen_text(app)


async def test_a_broken_capability_file_is_reported_in_words_and_the_app_goes_on(
    workspace: Path,
) -> None:
    (workspace / "broken.ttl").write_text(
        "@prefix : <http://example.org/> .\n:a :b :c ;\n  :d \n", encoding="utf-8"
    )
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        options = app.query_one("#capability-list", OptionList)
        await choose(pilot, options, "broken.ttl")
        status = app.query_one("#capability-status", Static)
        await wait_until(pilot, lambda: "broken.ttl" in str(status.render()))
        assert status.has_class("error")
        assert any("broken.ttl" in n for n in notifications(app))
        assert app.loaded.capability is None
        assert "Traceback" not in screen_text(app)
        # The app is still alive: another file loads.
        await pilot.press("up", "enter")
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        assert not status.has_class("error")


ROTATE = "http://skillwright.dev/robots/mr1/capabilities/rotate/rotate"


async def test_a_file_with_several_capabilities_offers_them_in_a_list(workspace: Path) -> None:
    both = workspace / "both.ttl"
    both.write_text(
        (workspace / "rotate.ttl").read_text(encoding="utf-8")
        + "\n"
        + (workspace / "move-forward.ttl").read_text(encoding="utf-8"),
        encoding="utf-8",
    )
    app = app_for(workspace)
    async with running(app, (80, 24)) as pilot:
        await choose(pilot, app.query_one("#capability-list", OptionList), "both.ttl")
        status = app.query_one("#capability-status", Static)
        await wait_until(pilot, lambda: "holds 2 capabilities" in str(status.render()))
        picker = app.query_one("#capability-choices", OptionList)
        assert picker.display
        assert app.focused is picker
        offered = [str(picker.get_option_at_index(i).prompt) for i in range(2)]
        assert offered == [
            "Move forward  moveForward\n"
            "http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward",
            f"Rotate  rotate\n{ROTATE}",
        ]
        assert app.loaded.capability is None
        await choose(pilot, picker, offered[1])
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        assert app.loaded.capability is not None
        assert app.loaded.capability.capability.name == "rotate"
        assert app.session.capability_iri == ROTATE
        assert picker.display
        assert picker.highlighted == 1
        await wait_until(pilot, lambda: load_session(app.workspace.session_path)[0] == app.session)

    # The next start reads the same capability of the file, and the list stays offered.
    again = app_for(workspace)
    async with running(again, (80, 24)) as pilot:
        await wait_until(pilot, lambda: again.loaded.capability is not None)
        assert again.loaded.capability is not None
        assert again.loaded.capability.capability.iri == ROTATE
        assert again.query_one("#capability-choices", OptionList).display
        # Another file forgets the choice: it is a capability of both.ttl only.
        await choose(pilot, again.query_one("#capability-list", OptionList), "move-forward.ttl")
        await wait_until(
            pilot,
            lambda: (
                again.loaded.capability is not None
                and again.loaded.capability.capability.name == "moveForward"
            ),
        )
        assert again.session.capability_iri is None
        assert not again.query_one("#capability-choices", OptionList).display


@pytest.mark.parametrize("file", ["rotate.ttl", "both.ttl"])
async def test_a_choice_the_file_no_longer_holds_is_dropped(workspace: Path, file: str) -> None:
    both = workspace / "both.ttl"
    both.write_text(
        (workspace / "rotate.ttl").read_text(encoding="utf-8")
        + (workspace / "move-forward.ttl").read_text(encoding="utf-8"),
        encoding="utf-8",
    )
    preset_session(workspace, capability=file, capability_iri="spin", active_tab="generation")
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        if file == "rotate.ttl":  # one capability left: it is read, and the user told
            told = "spin is no longer in rotate.ttl; reading its only capability"
            await wait_until(pilot, lambda: any(told in n for n in notifications(app)))
            await wait_until(pilot, lambda: app.loaded.capability is not None)
            assert app.session.capability_iri is None
        else:
            status = app.query_one("#capability-status", Static)
            await wait_until(pilot, lambda: "spin does not name one" in str(status.render()))
            assert app.query_one("#capability-choices", OptionList).option_count == 2
            assert app.session.capability_iri == "spin"
        # The user stays on the tab they were on.
        assert app.query_one("#tabs", TabbedContent).active == "generation"


async def test_esc_stops_the_read_at_the_engines_next_step(
    workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import reader

    parsing = Gate(monkeypatch, reader, "parse_graph")
    read = Watch(monkeypatch, reader, "load_capability")
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        try:
            await choose(pilot, app.query_one("#capability-list", OptionList), "rotate.ttl")
            await parsing.reached()
            await pilot.press("escape")
        finally:
            parsing.open()
        assert isinstance(await read.first(), OperationCancelledError)
        await pilot.pause()
        assert app.loaded.capability is None
        assert str(app.query_one("#capability-status", Static).render()) == "cancelled"
        assert not app.query_one("#capability-loading").display


async def test_choosing_another_file_stops_the_read_in_progress(
    workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.capability import reader

    parsing = Gate(monkeypatch, reader, "parse_graph")
    read = Watch(monkeypatch, reader, "load_capability")
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        options = app.query_one("#capability-list", OptionList)
        try:
            await choose(pilot, options, "rotate.ttl")
            await parsing.reached()
            await choose(pilot, options, "move-forward.ttl")
        finally:
            parsing.open()
        await wait_until(pilot, lambda: app.loaded.capability is not None)
        assert app.loaded.capability is not None
        assert app.loaded.capability.capability.name == "moveForward"
        assert isinstance(await read.first(), OperationCancelledError)
