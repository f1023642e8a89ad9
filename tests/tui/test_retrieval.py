"""The Retrieval tab: ranked interfaces with scores and reasons; pins and drops."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from textual.widgets import DataTable, Static

from skillwright.errors import OperationCancelledError
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.sources.report import report_from_inventory
from skillwright.pipeline import retrieve
from skillwright.tui.screens.retrieval import RetrievalPane
from tests.tui.conftest import (
    Gate,
    Watch,
    app_for,
    notifications,
    preset_session,
    running,
    wait_until,
)

pytestmark = pytest.mark.anyio

INPUTS = {
    "capability": "move-forward.ttl",
    "spec_path": "move-forward.spec.yaml",
    "interfaces": "recordings/mr1",
    "dense": False,
}


def _status(app: Any) -> str:
    return str(app.query_one("#retrieval-status", Static).render())


async def _ready(pilot: Any, app: Any) -> RetrievalPane:
    await wait_until(
        pilot,
        lambda: (
            app.loaded.capability is not None
            and app.loaded.inventory is not None
            and app.spec_pane().spec is not None
        ),
    )
    await pilot.press("f5")
    return app.query_one(RetrievalPane)


async def test_ranking_shows_the_engines_hits_with_scores_and_reasons(workspace: Path) -> None:
    preset_session(workspace, **INPUTS, k=3)
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+r")
        await wait_until(pilot, lambda: len(app.loaded.hits) == 3)
        expected = retrieve(
            workspace / "move-forward.ttl",
            workspace / "move-forward.spec.yaml",
            workspace / "recordings" / "mr1",
            k=3,
            dense=False,
        )
        assert [h.name for h in app.loaded.hits] == [h.name for h in expected.hits]
        assert pane.rows == [h.name for h in expected.hits]
        table = app.query_one("#retrieval-table", DataTable)
        first = [str(cell) for cell in table.get_row_at(0)]
        hit = expected.hits[0]
        assert first[2:6] == [hit.name, hit.kind, hit.type_name, f"{hit.score:.2f}"]
        assert first[8] == hit.reason
        assert "3 interfaces ranked for Move forward (BM25 only" in _status(app)
        # The pane under the table holds the highlighted interface's whole reason.
        detail = str(app.query_one("#retrieval-detail", Static).render())
        assert detail.startswith(f"{hit.name} ({hit.kind}, {hit.type_name}): score ")
        assert f"why: {hit.reason}" in detail


async def test_the_last_sessions_ranking_is_made_again_on_start(workspace: Path) -> None:
    preset_session(workspace, **INPUTS, k=2, ranked=True)
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await wait_until(pilot, lambda: len(app.loaded.hits) == 2)
        assert app.query_one(RetrievalPane).rows == [h.name for h in app.loaded.hits]


async def test_a_velocity_topic_the_report_cannot_tell_apart_is_marked_in_the_table(
    workspace: Path,
) -> None:
    base = load_inventory(workspace / "recordings" / "mr1")
    driver = base.interface("/cmd_vel").model_copy(update={"name": "/driver/cmd_vel"})
    inventory = base.model_copy(update={"interfaces": [*base.interfaces, driver]})
    document, _ = report_from_inventory(inventory)
    (workspace / "report.json").write_text(json.dumps(document), encoding="utf-8")
    preset_session(workspace, **{**INPUTS, "interfaces": "report.json"}, k=4)
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+r")
        await wait_until(pilot, lambda: len(app.loaded.hits) == 4)
        row = pane.rows.index("/cmd_vel")
        reason = str(app.query_one("#retrieval-table", DataTable).get_row_at(row)[8])
        assert reason.startswith("not told apart from /driver/cmd_vel (the list has no endpoint")
        assert "check which topic the robot uses for /cmd_vel (p pins, x drops)" in _status(app)


async def test_pinned_interfaces_are_listed_and_dropped_ones_left_out(workspace: Path) -> None:
    preset_session(workspace, **INPUTS, k=4, pinned=("/battery_state",), dropped=("/odom",))
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        pane = await _ready(pilot, app)
        await pilot.press("ctrl+r")
        await wait_until(pilot, lambda: len(app.loaded.hits) == 4)
        assert "/odom" not in [h.name for h in app.loaded.hits]
        assert pane.rows[4:] == ["/battery_state", "/odom"]
        marks = str(app.query_one("#retrieval-marks", Static).render())
        assert "pinned: /battery_state" in marks
        assert "dropped: /odom" in marks
        # Un-drop /odom from its row, pin the first hit.
        table = app.query_one("#retrieval-table", DataTable)
        table.focus()
        await pilot.press("ctrl+end", "x")
        assert app.session.dropped == ()
        await pilot.press("ctrl+home", "p")
        assert app.session.pinned == ("/battery_state", app.loaded.hits[0].name)


async def test_ranking_needs_a_capability_and_interfaces_and_says_so(workspace: Path) -> None:
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f5", "ctrl+r")
        await wait_until(pilot, lambda: any("capability first" in n for n in notifications(app)))


@pytest.mark.parametrize("key", ["escape", "ctrl+q"])
async def test_esc_or_quitting_stops_the_ranking_once_the_embedding_model_has_loaded(
    workspace: Path, monkeypatch: pytest.MonkeyPatch, key: str
) -> None:
    import skillwright.llm.embeddings
    import skillwright.pipeline

    embedded: list[object] = []

    class Embedder:
        def embed(self, texts: object) -> object:
            embedded.append(texts)
            raise AssertionError("embedded after the cancel")

    monkeypatch.setattr(skillwright.llm.embeddings, "load_embedder", lambda *a: Embedder())
    loading = Gate(monkeypatch, skillwright.llm.embeddings, "load_embedder")
    ranked = Watch(monkeypatch, skillwright.pipeline, "retrieve")
    preset_session(workspace, **{**INPUTS, "dense": True})
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await _ready(pilot, app)
        try:
            await pilot.press("ctrl+r")
            await loading.reached()
            await pilot.press(key)
        finally:
            loading.open()
        if key == "escape":
            assert isinstance(await ranked.first(), OperationCancelledError)
            assert _status(app) == "cancelled"
            assert app.loaded.hits == []
    assert isinstance(await ranked.first(), OperationCancelledError)
    assert embedded == []
