"""The History tab: earlier results read from their records, opened, and compared."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from textual.widgets import ContentSwitcher, DataTable, Static

from skillwright.pipeline import GenerationRecord, GenerationRequest, run_generation
from skillwright.tui.screens.history import HistoryPane, diff_results
from skillwright.tui.widgets.code_view import CodeView
from skillwright.tui.workspace import Workspace
from tests.tui.conftest import app_for, running, screen_text, wait_until

pytestmark = pytest.mark.anyio


def _generate(workspace: Path, name: str, **changes: Any) -> Path:
    """A result folder written by the headless pipeline, as `skillwright generate` does."""
    out = workspace / "generated" / name
    values: dict[str, Any] = {
        "capability": workspace / "rotate.ttl",
        "spec": workspace / "rotate.spec.yaml",
        "interfaces": workspace / "recordings" / "mr1",
        "out_dir": out,
        "skeleton": True,
        "dense": False,
    }
    run_generation(GenerationRequest(**(values | changes)))
    return out


async def test_results_are_listed_newest_first_and_open_with_their_code(workspace: Path) -> None:
    older = _generate(workspace, "rotate-20250101-080000", k=2)
    newer = _generate(workspace, "rotate-20250102-080000", pinned=("/odom",))
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        await pilot.press("f7")
        pane = app.query_one(HistoryPane)
        await wait_until(pilot, lambda: len(pane.entries) == 2)
        assert [folder for folder, _ in pane.entries] == [newer, older]
        table = app.query_one("#history-table", DataTable)
        # The skeleton's states raise: the checks failed, so nothing was run or simulated.
        assert [str(c) for c in table.get_row_at(0)][1:] == [
            newer.name,
            "✗ failed",
            "✗ failed",
            "- skipped",
            "- skipped",
            "skeleton",
            "-",
            "1",
        ]
        code = app.query_one("#history-code", CodeView)
        assert code.text == (newer / "skill.py").read_text(encoding="utf-8")
        summary = str(app.query_one("#history-summary", Static).render())
        assert "capability rotate.ttl  spec rotate.spec.yaml" in summary
        assert "pinned: /odom" in summary
        assert "✗ failed: checks ✗ failed (5 error(s), 0 warning(s)) · run - skipped" in summary
        await pilot.press("down")
        await wait_until(pilot, lambda: code.text == (older / "skill.py").read_text("utf-8"))


async def test_two_results_are_compared_as_a_diff(workspace: Path) -> None:
    older = _generate(workspace, "rotate-20250101-080000", k=2)
    newer = _generate(workspace, "rotate-20250102-080000", k=4)
    app = app_for(workspace)
    async with running(app, (160, 48)) as pilot:
        await pilot.press("f7")
        pane = app.query_one(HistoryPane)
        await wait_until(pilot, lambda: len(pane.entries) == 2)
        await pilot.press("d")  # nothing marked yet: says what to do
        assert app.query_one("#history-view", ContentSwitcher).current == "history-code"
        await pilot.press("down", "m")
        rows = [line for line in screen_text(app).splitlines() if older.name in line]
        assert rows[0].split()[:2] == ["◆", older.name]  # the marked result shows its mark
        await pilot.press("up", "d")
        switcher = app.query_one("#history-view", ContentSwitcher)
        await wait_until(pilot, lambda: switcher.current == "history-diff")
        assert pane.diff_text == diff_results(pane.entries[1], pane.entries[0], app.workspace)
        assert f"--- {older.name}/record.json" in pane.diff_text
        assert f"+++ {newer.name}/skill.py" in pane.diff_text
        assert "k=2" in pane.diff_text
        assert "k=4" in pane.diff_text


def test_results_with_the_same_code_differ_only_in_their_names(workspace: Path) -> None:
    first = _generate(workspace, "rotate-20250101-080000")
    second = _generate(workspace, "rotate-20250101-080001")
    entries = [(f, GenerationRecord.load(f / "record.json")) for f in (first, second)]
    text = diff_results(entries[0], entries[1], Workspace(workspace))
    assert "skill.py" not in text  # the same code: no hunk for it
    changed = [
        line
        for line in text.splitlines()
        if line[:1] in "+-" and not line.startswith(("+++", "---"))
    ]
    assert changed == [
        f"-{first.name}: skeleton, model none (skeleton)",
        f"+{second.name}: skeleton, model none (skeleton)",
    ]


async def test_a_damaged_record_is_reported_and_the_others_still_listed(workspace: Path) -> None:
    good = _generate(workspace, "rotate-20250101-080000")
    bad = workspace / "generated" / "rotate-20250102-080000"
    bad.mkdir(parents=True)
    (bad / "record.json").write_text("{broken", encoding="utf-8")
    app = app_for(workspace)
    async with running(app, (120, 40)) as pilot:
        await pilot.press("f7")
        pane = app.query_one(HistoryPane)
        await wait_until(pilot, lambda: len(pane.entries) == 1)
        assert pane.entries[0][0] == good
        status = str(app.query_one("#history-status", Static).render())
        assert status.startswith("1 result in generated")
        assert "✗" in status
        assert "rotate-20250102-080000" in status
