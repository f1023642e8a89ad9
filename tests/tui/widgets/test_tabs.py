"""The tabs follow the focus, but a focus message that arrives late cannot switch them back."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.widgets import TabbedContent, TabPane

from skillwright.tui.screens.capability import CapabilityPane
from tests.tui.conftest import app_for, running, wait_until

pytestmark = pytest.mark.anyio


def _tab(app: object) -> str:
    return str(app.query_one("#tabs", TabbedContent).active)  # type: ignore[attr-defined]


async def test_a_late_focus_message_for_the_tab_left_does_not_switch_back(
    workspace: Path,
) -> None:
    # F2 then F4 on a busy machine: the capability pane's "a widget of mine was focused"
    # arrives after F4 showed the interfaces and focused their table.
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        table = app.query_one("#interfaces-table")
        await wait_until(pilot, lambda: app.focused is table)
        capability = app.query_one("#capability", TabPane)
        capability.post_message(TabPane.Focused(capability))
        await pilot.pause()
        await pilot.pause()
        assert _tab(app) == "interfaces"
        assert app.focused is table


async def test_focusing_a_widget_of_another_tab_still_shows_that_tab(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        options = app.query_one("#capability-list")
        options.focus()
        await wait_until(pilot, lambda: _tab(app) == "capability")
        assert app.focused is options


async def test_a_focus_chosen_for_the_tab_left_does_not_land_after_the_switch(
    workspace: Path,
) -> None:
    # The start-up focuses the shown tab's widget; F4 comes before that focus has landed. The
    # focus must follow the tab shown when the key was read, not the one shown before.
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        assert _tab(app) == "capability"
        app.screen.set_focus(None)
        app.query_one(CapabilityPane).focus_primary()
        app.action_show_tab("interfaces")
        table = app.query_one("#interfaces-table")
        await wait_until(pilot, lambda: app.focused is table, timeout=10)
        await pilot.pause()
        assert _tab(app) == "interfaces"
        assert app.focused is table
