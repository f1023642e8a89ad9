"""The History tab: earlier generations in the workspace, read from their records."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from pathlib import Path
from typing import Any, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, VerticalScroll
from textual.coordinate import Coordinate
from textual.widgets import Button, ContentSwitcher, DataTable, Static

from skillwright.errors import SkillwrightError
from skillwright.pipeline.verdict import Verdict, overall, stage_verdicts
from skillwright.tui.messages import HistoryLoaded
from skillwright.tui.screens.base import Pane
from skillwright.tui.widgets.code_view import CodeView
from skillwright.tui.workspace import Workspace

__all__ = ["COLUMNS", "JUDGING", "HistoryPane", "diff_results", "summary_lines", "verdict_cell"]

JUDGING = ("checks", "run", "simulate")
"""The stages that judge a skill, each a column of the table."""

COLUMNS = ("result", "verdict", "checks", "run", "simulate", "mode", "model", "pins")
"""The table's columns after the mark of the result marked for a diff."""

_MARKED = "◆"
"""The mark of the result marked as the old side of a diff."""


def _skill_text(folder: Path, record: Any) -> tuple[str, str]:
    """(file name, text) of the skill in a result folder."""
    names = [f for f in getattr(record, "files", []) if str(f).endswith(".py")] or ["skill.py"]
    path = folder / Path(str(names[0])).name
    try:
        return path.name, path.read_text(encoding="utf-8")
    except OSError as error:
        return path.name, f"# {path}: cannot be read ({error.strerror or error})\n"


def _shown(workspace: Workspace | None, path: str) -> str:
    return workspace.relative(Path(path)) if workspace is not None else path


def summary_lines(folder: Path, record: Any, workspace: Workspace | None = None) -> list[str]:
    """What a record says, in a few lines: when, how, with what, and the verdict."""
    model = record.model.id if record.model is not None else "none (skeleton)"
    retrieval = record.retrieval
    hits = ", ".join(h.name + (" (set aside)" if h.set_aside else "") for h in retrieval.hits)
    hits = hits or "none"
    inputs = record.inputs
    lines = [
        f"{folder.name}: {record.mode}, model {model}",
        f"capability {_shown(workspace, inputs.capability.path)}"
        f"  spec {_shown(workspace, inputs.spec.path)}",
        f"interfaces {_shown(workspace, inputs.interfaces.location)}  k={retrieval.k}: {hits}",
    ]
    if retrieval.pinned or retrieval.dropped:
        pinned = ", ".join(retrieval.pinned) or "-"
        dropped = ", ".join(retrieval.dropped) or "-"
        lines.append(f"pinned: {pinned}  dropped: {dropped}")
    verdicts = stage_verdicts(record)
    judged = overall(verdicts)
    lines.append(
        f"{judged.mark} {judged.word}: "
        + " · ".join(
            f"{stage} {verdicts[stage].verdict.mark} {verdicts[stage].verdict.word}"
            + (f" ({verdicts[stage].reason})" if verdicts[stage].reason else "")
            for stage in JUDGING
        )
    )
    return lines


def verdict_cell(judged: Verdict) -> Text:
    """A table cell with the verdict's mark and word in its colour."""
    return Text(f"{judged.mark} {judged.word}", style=judged.style)


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}" + ("" if count == 1 else "s")


def diff_results(
    old: tuple[Path, Any], new: tuple[Path, Any], workspace: Workspace | None = None
) -> str:
    """A unified diff of two results: their summaries, then their skill code."""
    (old_dir, old_record), (new_dir, new_record) = old, new
    old_name, old_text = _skill_text(old_dir, old_record)
    new_name, new_text = _skill_text(new_dir, new_record)
    parts = list(
        difflib.unified_diff(
            [line + "\n" for line in summary_lines(old_dir, old_record, workspace)],
            [line + "\n" for line in summary_lines(new_dir, new_record, workspace)],
            f"{old_dir.name}/record.json",
            f"{new_dir.name}/record.json",
            n=0,
        )
    )
    parts += difflib.unified_diff(
        old_text.splitlines(keepends=True),
        new_text.splitlines(keepends=True),
        f"{old_dir.name}/{old_name}",
        f"{new_dir.name}/{new_name}",
    )
    return "".join(parts) or "The two results are identical.\n"


class HistoryPane(Pane):
    """Earlier results, newest first; Enter opens one, ``m`` marks, ``d`` diffs."""

    job = "history"
    primary = "#history-table"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("m", "mark", "Mark"),
        Binding("d", "diff", "Diff with mark"),
        Binding("ctrl+r", "reload", "Reload"),
    ]

    def __init__(self) -> None:
        super().__init__(id="history-pane")
        self.entries: list[tuple[Path, Any]] = []
        self.marked: Path | None = None
        self.diff_text = ""
        """The last diff shown (unified diff text)."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="history-bar", classes="bar"):
            yield Button("Reload ^R", id="history-reload", compact=True)
            yield Button("Mark m", id="history-mark", compact=True)
            yield Button("Diff d", id="history-diff-button", compact=True)
        yield Static("", id="history-status", markup=False)
        yield DataTable(id="history-table", cursor_type="row", zebra_stripes=True)
        yield Static("", id="history-summary", markup=False)
        with ContentSwitcher(initial="history-code", id="history-view"):
            yield CodeView(id="history-code")
            with VerticalScroll(id="history-diff"):
                yield Static("", id="history-diff-text", markup=False)

    def on_mount(self) -> None:
        table = self.query_one("#history-table", DataTable)
        # A column as wide as its mark: a column sized by its content is 0 wide while no
        # result is marked, and the mark would not show.
        table.add_column("", width=1)
        table.add_columns(*COLUMNS)
        self.reload()

    @on(Button.Pressed, "#history-reload")
    def action_reload(self) -> None:
        """Reads the workspace's records again."""
        self.reload()

    def reload(self) -> None:
        """Lists ``generated/`` (in a worker: records are pydantic documents)."""
        self._read(self.sw.workspace.results())

    @work(thread=True, exclusive=True, group="history", exit_on_error=False)
    def _read(self, folders: list[Path]) -> None:
        if not folders:
            self.post_message(HistoryLoaded([], []))
            return
        from skillwright.pipeline.record import GenerationRecord

        entries, problems = [], []
        for folder in folders:
            try:
                entries.append((folder, GenerationRecord.load(folder / "record.json")))
            except SkillwrightError as error:
                problems.append(str(error))
        self.post_message(HistoryLoaded(entries, problems))

    def on_history_loaded(self, message: HistoryLoaded) -> None:
        self.entries = message.entries
        table = self.query_one("#history-table", DataTable)
        table.clear()
        for folder, record in self.entries:
            model = record.model.id if record.model is not None else "-"
            pins = len(record.retrieval.pinned) + len(record.retrieval.dropped)
            verdicts = stage_verdicts(record)
            table.add_row(
                Text(_MARKED if folder == self.marked else ""),
                Text(folder.name),
                verdict_cell(overall(verdicts)),
                *(verdict_cell(verdicts[stage].verdict) for stage in JUDGING),
                Text(record.mode),
                Text(model),
                Text(str(pins) if pins else ""),
            )
        where = self.sw.workspace.relative(self.sw.workspace.generated_dir)
        status = f"{_plural(len(self.entries), 'result')} in {where}"
        if not self.entries:
            status = "No results yet: generate one (Ctrl+G)."
        for problem in message.problems:
            status += f"\n✗ {problem}"
        self.query_one("#history-status", Static).update(status)
        self._open_highlighted()

    def highlighted(self) -> tuple[Path, Any] | None:
        """The result under the cursor."""
        table = self.query_one("#history-table", DataTable)
        if not self.entries or not 0 <= table.cursor_row < len(self.entries):
            return None
        return self.entries[table.cursor_row]

    @on(DataTable.RowHighlighted, "#history-table")
    @on(DataTable.RowSelected, "#history-table")
    def _open_highlighted(self) -> None:
        entry = self.highlighted()
        if entry is None:
            self.query_one("#history-summary", Static).update("")
            return
        folder, record = entry
        lines = summary_lines(folder, record, self.sw.workspace)
        self.query_one("#history-summary", Static).update("\n".join(lines))
        self.query_one(CodeView).show(_skill_text(folder, record)[1])
        self.query_one("#history-view", ContentSwitcher).current = "history-code"

    @on(Button.Pressed, "#history-mark")
    def action_mark(self) -> None:
        """Marks the highlighted result as the old side of a diff."""
        entry = self.highlighted()
        if entry is None:
            return
        self.marked = None if self.marked == entry[0] else entry[0]
        table = self.query_one("#history-table", DataTable)
        for row, (folder, _record) in enumerate(self.entries):
            table.update_cell_at(Coordinate(row, 0), _MARKED if folder == self.marked else "")
        self.notify(
            f"marked {entry[0].name}: highlight another result and press d to diff"
            if self.marked is not None
            else "mark removed",
            title="History",
            markup=False,
        )

    @on(Button.Pressed, "#history-diff-button")
    def action_diff(self) -> None:
        """Shows the difference between the marked result and the highlighted one."""
        from rich.syntax import Syntax

        entry = self.highlighted()
        marked = next((e for e in self.entries if e[0] == self.marked), None)
        if entry is None or marked is None:
            self.notify(
                "mark a result with m, then highlight another and press d",
                title="History",
                markup=False,
            )
            return
        self.diff_text = diff_results(marked, entry, self.sw.workspace)
        self.query_one("#history-diff-text", Static).update(
            Syntax(self.diff_text, "diff", theme="ansi_dark", word_wrap=False)
        )
        self.query_one("#history-view", ContentSwitcher).current = "history-diff"

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand("Reload history", "Read generated/ again", self.reload)
        yield SystemCommand(
            "Diff results", "Marked result against the highlighted one", self.action_diff
        )
