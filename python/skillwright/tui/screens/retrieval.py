"""The Retrieval tab: the interfaces the engine ranks for the capability, with pins and drops."""

from __future__ import annotations

import threading
from collections.abc import Iterable
from typing import Any, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal
from textual.widgets import Button, Checkbox, DataTable, Input, Label, Static
from textual.worker import get_current_worker

from skillwright.errors import OperationCancelledError, SkillwrightError
from skillwright.tui.jobs import EngineJob
from skillwright.tui.messages import JobFailed, RetrievalFinished
from skillwright.tui.screens.base import Pane
from skillwright.tui.widgets.interface_detail import mark_of

__all__ = ["COLUMNS", "RetrievalPane"]

COLUMNS = ("mark", "#", "name", "kind", "type", "score", "dense", "lexical", "reason")


def _row(mark: str, name: str, reason: str) -> list[Text]:
    """A table row for an interface retrieval did not rank."""
    return [Text(c) for c in (mark, "", name, "", "", "", "", "", reason)]


def _twins_note(twins: tuple[str, ...]) -> str:
    """What a hit's reason starts with when the interface list cannot tell it from others."""
    if not twins:
        return ""
    return f"not told apart from {', '.join(twins)} (the list has no endpoint counts); "


class RetrievalPane(Pane):
    """Ranked interfaces with scores and reasons; ``p`` pins, ``x`` drops."""

    job = "retrieval"
    primary = "#retrieval-table"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("ctrl+r", "rank", "Rank"),
        Binding("p", "pin", "Pin"),
        Binding("x", "drop", "Drop"),
    ]

    def __init__(self) -> None:
        super().__init__(id="retrieval-pane")
        self._job = EngineJob()
        self._without_spec = False
        self._rank_when_loaded = False
        """The last session showed a ranking: rank again once both inputs are loaded."""
        self.rows: list[str] = []
        """Interface names in table order."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="retrieval-bar", classes="bar"):
            yield Button("Rank ^R", id="retrieval-rank", compact=True)
            yield Label(" k ")
            yield Input(str(self.sw.session.k), id="retrieval-k", type="integer", compact=True)
            yield Checkbox("embeddings", self.sw.session.dense, id="retrieval-dense", compact=True)
        yield Static(
            "Load a capability and interfaces, then rank them (Ctrl+R).",
            id="retrieval-status",
            markup=False,
        )
        yield DataTable(id="retrieval-table", cursor_type="row", zebra_stripes=True)
        yield Static("", id="retrieval-detail", markup=False)
        yield Static("", id="retrieval-marks", markup=False)

    def on_mount(self) -> None:
        table = self.query_one("#retrieval-table", DataTable)
        table.add_columns(*COLUMNS)
        self._rank_when_loaded = self.sw.session.ranked
        self.show_marks()

    # --- settings -----------------------------------------------------------------------------
    @on(Input.Changed, "#retrieval-k")
    def _k_changed(self, event: Input.Changed) -> None:
        try:
            k = int(event.value)
        except ValueError:
            return
        if k > 0:
            self.sw.update_session(k=k)

    @on(Checkbox.Changed, "#retrieval-dense")
    def _dense_changed(self, event: Checkbox.Changed) -> None:
        self.sw.update_session(dense=event.value)

    # --- ranking ------------------------------------------------------------------------------
    @on(Button.Pressed, "#retrieval-rank")
    def action_rank(self) -> None:
        """Ranks the inventory's interfaces for the capability (and the specification)."""
        loaded = self.sw.loaded
        if loaded.capability_path is None:
            self.fail("load a capability first (Capability tab, F2)")
            return
        if loaded.inventory_source is None:
            self.fail("load the robot's interfaces first (Interfaces tab, F4)")
            return
        spec_path = self.sw.spec_pane().saved_path(required=False)
        session = self.sw.session
        request = {
            "capability": loaded.capability_path,
            "spec": spec_path,
            "interfaces": loaded.inventory_source,
            "capability_iri": session.capability_iri,
            "ontologies": self.sw.workspace.ontologies(),
            "k": session.k,
            "include_infrastructure": session.show_infrastructure,
            "dense": session.dense,
            "models_file": self.sw.models_file,
            "dropped": tuple(name for name in session.dropped if name in self._known_names()),
        }
        status = self.query_one("#retrieval-status", Static)
        status.update(
            "ranking …" if session.dense is False else "loading the embedding model and ranking …"
        )
        self._without_spec = spec_path is None
        self._job.start(lambda cancel: self._rank(request, cancel))

    def _known_names(self) -> set[str]:
        inventory = self.sw.loaded.inventory
        return {i.name for i in inventory.interfaces} if inventory is not None else set()

    @work(thread=True, exclusive=True, group="retrieval", exit_on_error=False)
    def _rank(self, request: dict[str, Any], cancel: threading.Event) -> None:
        from skillwright.pipeline import retrieve

        try:
            result = retrieve(**request, cancel=cancel)
        except OperationCancelledError:
            return  # the pane already says so, or a newer ranking replaced this one
        except SkillwrightError as error:
            self.fail(str(error))
            return
        if not get_current_worker().is_cancelled:
            self.post_message(RetrievalFinished(result.hits, result.method == "hybrid"))

    def on_retrieval_finished(self, message: RetrievalFinished) -> None:
        self.sw.loaded.hits = message.hits
        self.sw.update_session(ranked=True)
        how = "embeddings + BM25" if message.dense else "BM25 only"
        if self._without_spec:
            how += "; the specification is not valid, so it was left out"
        twinned = [h.name for h in message.hits if h.twins]
        check = (
            f"; check which topic the robot uses for {', '.join(twinned)} (p pins, x drops)"
            if twinned
            else ""
        )
        self.query_one("#retrieval-status", Static).update(
            f"{len(message.hits)} interfaces ranked for "
            f"{self.sw.loaded.capability.capability.label if self.sw.loaded.capability else '?'}"
            f" ({how}){check}"
        )
        self.show_table()

    def show_table(self) -> None:
        """The hits, then interfaces pinned that retrieval did not choose."""
        table = self.query_one("#retrieval-table", DataTable)
        table.clear()
        self.rows = []
        session = self.sw.session
        for rank, hit in enumerate(self.sw.loaded.hits, start=1):
            dense = "" if hit.dense is None else f"{hit.dense:.2f}"
            cells = (
                mark_of(hit.name, session.pinned, session.dropped),
                str(rank),
                hit.name,
                hit.kind,
                hit.type_name,
                f"{hit.score:.2f}",
                dense,
                f"{hit.lexical:.2f}",
                _twins_note(hit.twins) + hit.reason,
            )
            table.add_row(*(Text(c) for c in cells))
            self.rows.append(hit.name)
        for name in session.pinned:
            if name not in self.rows:
                table.add_row(*_row("pin", name, "pinned by you"))
                self.rows.append(name)
        for name in session.dropped:
            if name not in self.rows:
                table.add_row(*_row("drop", name, "dropped by you: not ranked"))
                self.rows.append(name)
        self.show_detail()

    @on(DataTable.RowHighlighted, "#retrieval-table")
    def show_detail(self) -> None:
        """The highlighted interface's whole reason, scores and the model's verdict: the
        table cuts them to its columns."""
        box = self.query_one("#retrieval-detail", Static)
        name = self.highlighted()
        hit = next((h for h in self.sw.loaded.hits if h.name == name), None)
        if name is None:
            box.update("")
            return
        if hit is None:
            box.update(f"{name}: {'pinned' if name in self.sw.session.pinned else 'dropped'}")
            return
        dense = "" if hit.dense is None else f", dense {hit.dense:.3f}"
        lines = [
            f"{hit.name} ({hit.kind}, {hit.type_name}): score {hit.score:.3f}{dense}, "
            f"lexical {hit.lexical:.3f}",
            f"why: {_twins_note(hit.twins)}{hit.reason}",
        ]
        if hit.needed is not None or hit.judgement:
            verdict = {True: "needed", False: "not needed", None: "no verdict"}[hit.needed]
            lines.append(f"the model: {verdict}" + (f" — {hit.judgement}" if hit.judgement else ""))
        box.update("\n".join(lines))

    def show_marks(self) -> None:
        """Redraws marks and the pin/drop summary."""
        self.show_table()
        session = self.sw.session
        parts = []
        if session.pinned:
            parts.append("pinned: " + ", ".join(session.pinned))
        if session.dropped:
            parts.append("dropped: " + ", ".join(session.dropped))
        self.query_one("#retrieval-marks", Static).update(
            "; ".join(parts) or "p pins the highlighted interface into generation, x drops it"
        )

    def highlighted(self) -> str | None:
        """Name of the interface under the cursor."""
        table = self.query_one("#retrieval-table", DataTable)
        if not self.rows or not 0 <= table.cursor_row < len(self.rows):
            return None
        return self.rows[table.cursor_row]

    def action_pin(self) -> None:
        """Pins the highlighted interface (again: undoes it)."""
        name = self.highlighted()
        if name is not None:
            self.sw.toggle_mark(name, "pinned")

    def action_drop(self) -> None:
        """Drops the highlighted interface (again: undoes it)."""
        name = self.highlighted()
        if name is not None:
            self.sw.toggle_mark(name, "dropped")

    def inputs_changed(self) -> None:
        """The capability or inventory changed: the ranking shown is no longer theirs (on
        start, once both are loaded, the last session's ranking is made again)."""
        loaded = self.sw.loaded
        if self._rank_when_loaded and loaded.capability is not None and loaded.inventory:
            self._rank_when_loaded = False
            self.action_rank()
            return
        if self.sw.loaded.hits:
            self.sw.loaded.hits = []
            self.show_table()
            self.query_one("#retrieval-status", Static).update(
                "The inputs changed: rank again (Ctrl+R)."
            )

    def on_job_failed(self, message: JobFailed) -> None:
        if message.job == self.job:
            self.query_one("#retrieval-status", Static).update(f"✗ {message.message}")

    def cancel_job(self) -> bool:
        if self._job.stop():
            self.query_one("#retrieval-status", Static).update("cancelled")
            return True
        return False

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand(
            "Rank interfaces", "Retrieval for the capability (Ctrl+R)", self._rank_cmd
        )

    def _rank_cmd(self) -> None:
        self.sw.action_show_tab("retrieval")
        self.action_rank()
