"""SVG snapshots of the main screens at 80x24 (the smallest supported) and 160x48.

Update them after a deliberate change of the layout with ``pytest --snapshot-update`` and
look at the SVG files under ``__snapshots__/`` before committing them.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from textual.pilot import Pilot
from textual.widgets import Input, Select, TabbedContent, TextArea
from textual.widgets.input import Selection

from skillwright.pipeline import GenerationRequest, run_generation
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.history import HistoryPane
from tests.tui.conftest import app_for, preset_session, wait_until

SIZES = [(80, 24), (160, 48)]


def _inputs(workspace: Path, tab: str) -> None:
    preset_session(
        workspace,
        capability="move-forward.ttl",
        spec_path="move-forward.spec.yaml",
        interfaces="recordings/mr1",
        dense=False,
        active_tab=tab,
    )


def _focus_in_active_tab(app: Any) -> bool:
    """The focus is on the main widget of the tab shown, or in the tab when it has none (its
    first activation can come late on a busy machine), so the footer shows that tab's keys."""
    tabs = app.query_one("#tabs", TabbedContent)
    pane = tabs.get_pane(tabs.active)
    if app.focused is None or pane not in app.focused.ancestors_with_self:
        return False
    primaries = [p.primary for p in pane.query(Pane) if p.primary]
    return not primaries or any(app.focused in pane.query(p) for p in primaries)


def _settled(
    extra: Callable[[Any], object] = lambda app: True,
) -> Callable[[Pilot[Any]], Awaitable[None]]:
    """Waits for the inputs to load and ``extra``; then hides what changes from run to run."""

    async def run_before(pilot: Pilot[Any]) -> None:
        app = pilot.app
        await wait_until(
            pilot,
            lambda: (
                app.loaded.capability is not None
                and app.loaded.inventory is not None
                and app.spec_pane().spec is not None
                and app.query_one("#generation-model", Select).value is not Select.NULL
                and _focus_in_active_tab(app)
                and extra(app)
            ),
        )
        app.clear_notifications()
        for widget in [*app.query(Input), *app.query(TextArea)]:
            widget.cursor_blink = False
        if isinstance(app.focused, Input):
            # Whether the focused input's text is selected depends on how its focus arrived
            # (Textual selects on a widget's focus, not on focus the app's own brings back),
            # which varied from run to run on a busy machine: the snapshot shows it selected.
            app.focused.selection = Selection(0, len(app.focused.value))
        await pilot.wait_for_scheduled_animations()
        await pilot.pause()

    return run_before


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("tab", ["capability", "specification", "interfaces", "generation"])
def test_screen_with_the_inputs_loaded(
    snap_compare: Any, workspace: Path, models_file: Path, tab: str, size: tuple[int, int]
) -> None:
    _inputs(workspace, tab)
    app = app_for(workspace, models_file)
    assert snap_compare(app, terminal_size=size, run_before=_settled())


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_retrieval_screen_with_ranked_interfaces(
    snap_compare: Any, workspace: Path, models_file: Path, size: tuple[int, int]
) -> None:
    _inputs(workspace, "retrieval")
    app = app_for(workspace, models_file)

    async def rank(pilot: Pilot[Any]) -> None:
        await _settled()(pilot)
        await pilot.press("ctrl+r")
        await _settled(lambda app: app.loaded.hits)(pilot)

    assert snap_compare(app, terminal_size=size, run_before=rank)


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_history_screen_with_two_results(
    snap_compare: Any, workspace: Path, models_file: Path, size: tuple[int, int]
) -> None:
    for name, k in (("move_forward-20250101-080000", 2), ("move_forward-20250102-080000", 4)):
        run_generation(
            GenerationRequest(
                capability=workspace / "move-forward.ttl",
                spec=workspace / "move-forward.spec.yaml",
                interfaces=workspace / "recordings" / "mr1",
                out_dir=workspace / "generated" / name,
                skeleton=True,
                dense=False,
                k=k,
            )
        )
    _inputs(workspace, "history")
    app = app_for(workspace, models_file)
    run_before = _settled(lambda app: len(app.query_one(HistoryPane).entries) == 2)
    assert snap_compare(app, terminal_size=size, run_before=run_before)


def test_help_screen(snap_compare: Any, workspace: Path, models_file: Path) -> None:
    _inputs(workspace, "capability")
    app = app_for(workspace, models_file)

    async def help_shown(pilot: Pilot[Any]) -> None:
        await _settled()(pilot)
        await pilot.press("f1")

    assert snap_compare(app, terminal_size=(80, 24), run_before=help_shown)
