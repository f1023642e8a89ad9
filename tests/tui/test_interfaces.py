"""The Interfaces tab: load any source, filter and search, details, enrichment, pins."""

from __future__ import annotations

import importlib.util
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from textual.coordinate import Coordinate
from textual.widgets import Checkbox, DataTable, Input, ProgressBar, Select, Static

from skillwright.errors import OperationCancelledError
from skillwright.interfaces.load import load_inventory
from skillwright.tui.screens.interfaces import InterfacesPane
from tests.interfaces.sources.test_live import FILES, ROBOT, RecordedGraph
from tests.interfaces.test_load import cut_recording
from tests.tui.conftest import (
    Gate,
    Watch,
    app_for,
    notifications,
    preset_session,
    running,
    screen_text,
    wait_until,
)

pytestmark = pytest.mark.anyio


def _names(pane: InterfacesPane) -> list[str]:
    return [i.name for i in pane.shown]


def _status(app: Any) -> str:
    return str(app.query_one("#interfaces-status", Static).render())


async def _loaded(pilot: Any, app: Any) -> InterfacesPane:
    pane = app.query_one(InterfacesPane)
    await wait_until(pilot, lambda: app.loaded.inventory is not None and pane.shown)
    return pane


async def test_a_recording_loads_into_a_table_with_infrastructure_hidden(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        select = app.query_one("#interfaces-source", Select)
        select.value = str(workspace / "recordings" / "mr1")
        pane = await _loaded(pilot, app)
        inventory = load_inventory(workspace / "recordings" / "mr1")
        assert "/cmd_vel" in _names(pane)
        assert "/rosout" not in _names(pane)
        hidden = len(inventory.interfaces) - len(pane.shown)
        assert hidden > 0
        assert f"{hidden} infrastructure hidden" in _status(app)
        assert "mr1 from recordings/mr1" in _status(app)
        assert app.session.interfaces == "recordings/mr1"

        app.query_one("#interfaces-infra", Checkbox).value = True
        await wait_until(pilot, lambda: "/rosout" in _names(pane))
        assert len(pane.shown) == len(inventory.interfaces)
        assert app.session.show_infrastructure


async def test_the_filter_searches_names_types_and_descriptions(workspace: Path) -> None:
    preset_session(workspace, interfaces="recordings/mr1")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        pane = await _loaded(pilot, app)
        await pilot.press("slash")
        assert app.focused is app.query_one("#interfaces-filter", Input)
        await pilot.press(*"twist")
        await wait_until(pilot, lambda: set(_names(pane)) == {"/cmd_vel", "/cmd_vel_nav"})
        await pilot.press(*["backspace"] * 5, *"laserscan")
        await wait_until(pilot, lambda: _names(pane) == ["/scan"])
        # Keys that pin and drop in the table are plain letters in the filter.
        await pilot.press(*["backspace"] * 9, *"px")
        assert app.query_one("#interfaces-filter", Input).value == "px"
        assert app.session.pinned == app.session.dropped == ()


async def test_a_reference_tool_report_loads_like_any_source(
    workspace: Path, shared_data: Path
) -> None:
    report = shared_data / "cap2skill" / "interface-reports" / "ros2_system_report.json"
    app = app_for(workspace)
    async with running(app) as pilot:
        await pilot.press("f4", "ctrl+o")
        app.screen.query_one("#open-path", Input).value = str(report)
        await pilot.press("enter")
        pane = await _loaded(pilot, app)
        assert app.loaded.inventory is not None
        assert app.loaded.inventory.sources[0].kind == "report"
        assert "/cmd_vel" in _names(pane)
        assert app.session.interfaces == str(report.resolve())


async def test_the_detail_pane_shows_the_expanded_message_definition(workspace: Path) -> None:
    preset_session(workspace, interfaces="recordings/mr1")
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        await pilot.press("f4")
        pane = await _loaded(pilot, app)
        table = app.query_one("#interfaces-table", DataTable)
        table.focus()
        await pilot.press("ctrl+home", *["down"] * _names(pane).index("/cmd_vel"))
        await wait_until(
            pilot, lambda: "linear: Vector3  (geometry_msgs/msg/Vector3)" in screen_text(app)
        )
        text = screen_text(app)
        assert "geometry_msgs/msg/Twist" in text
        assert "linear: Vector3  (geometry_msgs/msg/Vector3)" in text
        assert "  x: float64" in text


async def test_describing_fills_every_description_and_saves_the_inventory(
    workspace: Path,
) -> None:
    preset_session(workspace, interfaces="recordings/mr1")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        pane = await _loaded(pilot, app)
        assert all(i.description is None for i in pane.shown)
        progress = app.query_one("#interfaces-progress", ProgressBar)
        await pilot.press("ctrl+e")
        target = workspace / "mr1.inventory.json"
        await wait_until(pilot, lambda: app.session.interfaces == "mr1.inventory.json")
        saved = load_inventory(target)
        assert all(i.description is not None for i in saved.interfaces)
        assert all(i.relevance is not None for i in saved.interfaces)
        assert any("described by rules" in n and "control" in n for n in notifications(app))
        assert all(i.description is not None for i in pane.shown)
        assert progress.total == progress.progress == len(saved.interfaces)
        assert not progress.display
        assert app.loaded.inventory_source == target
        row = _names(pane).index("/cmd_vel")
        cmd_vel = pane.shown[row]
        assert cmd_vel.description is not None
        table = app.query_one("#interfaces-table", DataTable)
        assert str(table.get_cell_at(Coordinate(row, 5))) == cmd_vel.description.purpose


async def test_describing_with_a_model_that_is_not_installed_names_it(
    workspace: Path, models_file: Path
) -> None:
    preset_session(workspace, interfaces="recordings/mr1", model="ghost", enrich_engine="llm")
    app = app_for(workspace, models_file)
    async with running(app) as pilot:
        await pilot.press("f4")
        await _loaded(pilot, app)
        assert app.query_one("#interfaces-engine", Select).value == "llm"
        await pilot.press("ctrl+e")
        await wait_until(pilot, lambda: any("ghost.gguf" in n for n in notifications(app)))
        assert not (workspace / "mr1.inventory.json").exists()
        assert not app.query_one("#interfaces-progress", ProgressBar).display


async def test_pins_and_drops_are_marked_and_kept_in_the_session(workspace: Path) -> None:
    preset_session(workspace, interfaces="recordings/mr1")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        pane = await _loaded(pilot, app)
        table = app.query_one("#interfaces-table", DataTable)
        table.focus()
        await pilot.press("ctrl+home", *["down"] * _names(pane).index("/odom"), "p")
        assert app.session.pinned == ("/odom",)
        assert str(table.get_cell_at(Coordinate(table.cursor_row, 0))) == "pin"
        await pilot.press("x")  # dropping a pinned interface un-pins it
        assert app.session.pinned == ()
        assert app.session.dropped == ("/odom",)
        assert str(table.get_cell_at(Coordinate(table.cursor_row, 0))) == "drop"
        await pilot.press("x")
        assert app.session.dropped == ()


async def test_a_source_that_is_not_one_is_reported_in_words(workspace: Path) -> None:
    (workspace / "notes.inventory.json").write_text('{"hello": 1}', encoding="utf-8")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        app.query_one(InterfacesPane).load(workspace / "notes.inventory.json")
        await wait_until(pilot, lambda: "notes.inventory.json" in _status(app))
        assert "not a skillwright inventory" in _status(app) or "report" in _status(app)
        assert any("notes.inventory.json" in n for n in notifications(app))
        assert app.loaded.inventory is None


async def test_a_recording_cut_short_loads_what_it_holds_and_warns(workspace: Path) -> None:
    cut = cut_recording(workspace)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        app.query_one(InterfacesPane).load(cut)
        pane = await _loaded(pilot, app)
        assert "/cmd_vel" in _names(pane)
        assert any("read only up to byte" in n for n in notifications(app))


async def test_the_live_graph_without_ros2_says_how_to_get_it(workspace: Path) -> None:
    if importlib.util.find_spec("rclpy") is not None:
        pytest.skip("ROS 2 is sourced here; this test is about machines without it")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        app.query_one("#interfaces-live").focus()
        await pilot.press("enter")
        await wait_until(pilot, lambda: any("ROS 2" in n for n in notifications(app)))
        assert any("source /opt/ros" in n for n in notifications(app))


async def test_the_live_graph_is_discovered_and_saved_as_an_inventory(
    workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.interfaces.sources import rclpy_graph

    graph = RecordedGraph([ROBOT, ROBOT], FILES)

    @contextmanager
    def recorded(node_name: str = "x"):  # type: ignore[no-untyped-def]
        yield graph

    monkeypatch.setattr(rclpy_graph, "open_graph", recorded)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f4")
        app.query_one("#interfaces-live").focus()
        await pilot.press("enter")
        pane = await _loaded(pilot, app)
        assert "/cmd_vel" in _names(pane)
        assert app.session.interfaces == "ros2_graph.inventory.json"
        assert load_inventory(workspace / "ros2_graph.inventory.json").sources[0].kind == (
            "ros2_live"
        )


async def test_esc_stops_reading_a_recording_at_the_engines_next_step(
    workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright import core
    from skillwright.interfaces import load

    reading = Gate(monkeypatch, core, "read_mcap")
    loaded = Watch(monkeypatch, load, "load_inventory")
    preset_session(workspace, interfaces="recordings/mr1", active_tab="interfaces")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        try:
            await reading.reached()
            await pilot.press("escape")
        finally:
            reading.open()
        assert isinstance(await loaded.first(), OperationCancelledError)
        await pilot.pause()
        assert app.loaded.inventory is None
        assert _status(app) == "cancelled"
