"""The app shell: tabs, keys, help, command palette, start-up cost and the CLI entry point."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner
from textual.command import CommandList, CommandPalette
from textual.widgets import TabbedContent

from skillwright.cli import main
from skillwright.tui.app import SkillwrightApp
from skillwright.tui.screens.help import HelpScreen
from skillwright.tui.session import load_session
from tests.tui.conftest import app_for, running, screen_text, wait_until

pytestmark = pytest.mark.anyio

# Loaded by workers when first needed; the first paint must not wait for them.
ENGINE_MODULES = [
    "rdflib",
    "pydantic",
    "yaml",
    "numpy",
    "torch",
    "sentence_transformers",
    "tokenizers",
    "llama_cpp",
    "skillwright._core",
    "skillwright.pipeline.run",
]


def test_building_the_app_loads_no_engine_library() -> None:
    code = (
        "import sys, json\n"
        "from pathlib import Path\n"
        "from skillwright.tui.app import make_app\n"
        "make_app(Path('.'))\n"
        f"print(json.dumps([m for m in {ENGINE_MODULES!r} if m in sys.modules]))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert json.loads(result.stdout.strip().splitlines()[-1]) == []


async def test_the_tabs_are_shown_and_function_keys_switch_them(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (80, 24)) as pilot:
        text = screen_text(app)
        for title in ("Capability", "Specification", "Interfaces", "Retrieval", "Generation"):
            assert title in text
        tabs = app.query_one("#tabs", TabbedContent)
        for key, tab in [("f4", "interfaces"), ("f7", "history"), ("f2", "capability")]:
            await pilot.press(key)
            assert tabs.active == tab
        await pilot.press("f5")
        await wait_until(
            pilot, lambda: load_session(app.workspace.session_path)[0].active_tab == "retrieval"
        )


async def test_the_session_restores_the_tab_the_user_was_on(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app) as pilot:
        await pilot.press("f6")
        await wait_until(pilot, app.workspace.session_path.exists)
    again = app_for(workspace)
    async with running(again):
        assert again.query_one("#tabs", TabbedContent).active == "generation"


async def test_f1_shows_the_help_and_escape_closes_it(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (80, 24)) as pilot:
        await pilot.press("f1")
        assert isinstance(app.screen, HelpScreen)
        assert "command palette" in screen_text(app)
        await pilot.press("escape")
        assert not isinstance(app.screen, HelpScreen)


async def test_every_action_is_in_the_command_palette(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (100, 30)) as pilot:
        titles = {command.title for command in app.get_system_commands(app.screen)}
        for expected in (
            "Go to Retrieval",
            "Help",
            "Generate skill",
            "Cancel job",
            "Open capability file",
            "Save specification",
            "Load specification",
            "Open interface source",
            "Describe interfaces",
            "Rank interfaces",
            "Reload history",
            "Diff results",
        ):
            assert expected in titles
        await pilot.press("ctrl+p")
        await wait_until(pilot, lambda: isinstance(app.screen, CommandPalette))
        await pilot.press(*"go to hist")
        # The palette searches in the background; Enter picks the best hit once it is there.
        await wait_until(pilot, lambda: "Go to History" in _best_hit(app))
        await pilot.press("enter")
        await wait_until(pilot, lambda: app.query_one("#tabs", TabbedContent).active == "history")


def _best_hit(app: SkillwrightApp) -> str:
    commands = app.screen.query_one(CommandList)
    return str(commands.get_option_at_index(0).prompt) if commands.option_count else ""


def test_the_tui_command_refuses_a_workspace_that_does_not_exist(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["tui", "--workspace", str(tmp_path / "nowhere")])
    assert result.exit_code == 2
    assert f"workspace {tmp_path / 'nowhere'}: no such folder" in result.output


def test_the_tui_command_is_listed_in_the_help() -> None:
    result = CliRunner().invoke(main, ["--help"])
    assert "tui" in result.output
    assert CliRunner().invoke(main, ["tui", "--help"]).exit_code == 0


async def test_tab_keys_work_from_a_focused_code_view_and_the_filter_keeps_ctrl_e(
    workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from textual.widgets import Input

    from skillwright.tui.screens.interfaces import InterfacesPane

    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        tabs = app.query_one("#tabs", TabbedContent)
        await pilot.press("f6")
        code = app.query_one("#generation-code")
        app.set_focus(code)
        # A text area takes F6 and F7 (select line, select all); the tab keys come first.
        await pilot.press("f7")
        await wait_until(pilot, lambda: tabs.active == "history")
        app.set_focus(app.query_one("#history-code"))
        await pilot.press("f6")
        await wait_until(pilot, lambda: tabs.active == "generation")
        # Ctrl+E in the filter box describes the interfaces instead of moving to the end.
        described: list[bool] = []
        monkeypatch.setattr(InterfacesPane, "action_enrich", lambda self: described.append(True))
        await pilot.press("f4", "slash")
        await wait_until(pilot, lambda: isinstance(app.focused, Input))
        await pilot.press("ctrl+e")
        assert described == [True]


async def test_arrows_on_the_retrieval_tab_stay_on_it(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (80, 24)) as pilot:
        tabs = app.query_one("#tabs", TabbedContent)
        await pilot.press("f5")
        await wait_until(pilot, lambda: tabs.active == "retrieval")
        await pilot.press("right", "right", "left")
        assert tabs.active == "retrieval"
