"""The Retrieval tab: the interfaces the engine ranks for the capability, with pins and drops."""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any, ClassVar

from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal
from textual.widgets import Button, Checkbox, DataTable, Input, Label, Static
from textual.worker import Worker, get_current_worker

from skillwright.errors import SkillwrightError
from skillwright.tui.messages import JobFailed, RetrievalFinished, RetrievalProgress
from skillwright.tui.screens.base import Pane
from skillwright.tui.widgets.interface_detail import mark_of

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityLoad
    from skillwright.interfaces.inventory import Inventory
    from skillwright.spec.model import SkillSpec

__all__ = ["RetrievalPane"]


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
        self._worker: Worker[None] | None = None
        self.rows: list[str] = []
        """Interface names in table order."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="retrieval-bar", classes="bar"):
            yield Button("Rank ^R", id="retrieval-rank", compact=True)
            yield Label(" k ")
            yield Input(str(self.sw.session.k), id="retrieval-k", type="integer", compact=True)
            yield Checkbox("embeddings", self.sw.session.dense, id="retrieval-dense", compact=True)
        yield Static(
            "Load a capability and interfaces, then rank them (Ctrl+R).", id="retrieval-status"
        )
        yield DataTable(id="retrieval-table", cursor_type="row", zebra_stripes=True)
        yield Static("", id="retrieval-marks")

    def on_mount(self) -> None:
        table = self.query_one("#retrieval-table", DataTable)
        table.add_columns("mark", "#", "name", "kind", "type", "score", "dense", "lexical", "reason")
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
        if loaded.capability is None:
            self.fail("load a capability first (Capability tab, F2)")
            return
        if loaded.inventory is None:
            self.fail("load the robot's interfaces first (Interfaces tab, F4)")
            return
        spec = self.sw.spec_pane().spec
        session = self.sw.session
        self.query_one("#retrieval-status", Static).update("ranking …")
        self._worker = self._rank(
            loaded.capability,
            spec,
            loaded.inventory,
            session.k,
            session.show_infrastructure,
            session.dense,
        )

    @work(thread=True, exclusive=True, group="retrieval", exit_on_error=False)
    def _rank(
        self,
        capability: CapabilityLoad,
        spec: SkillSpec | None,
        inventory: Inventory,
        k: int,
        include_infrastructure: bool,
        dense: bool,
    ) -> None:
        from skillwright.retrieval.retrieve import rank_interfaces

        started = time.perf_counter()
        try:
            embed: Any = None
            if dense:
                self.post_message(RetrievalProgress("loading the embedding model …"))
                embed = self.sw.embedder()
                self.post_message(RetrievalProgress("ranking …"))
            hits = rank_interfaces(
                inventory,
                capability.capability,
                spec,
                k=k,
                include_infrastructure=include_infrastructure,
                embed=embed,
            )
        except SkillwrightError as error:
            self.fail(str(error))
            return
        if not get_current_worker().is_cancelled:
            self.post_message(RetrievalFinished(hits, time.perf_counter() - started, dense))

    def on_retrieval_progress(self, message: RetrievalProgress) -> None:
        self.query_one("#retrieval-status", Static).update(message.detail)

    def on_retrieval_finished(self, message: RetrievalFinished) -> None:
        self.sw.loaded.hits = message.hits
        how = "embeddings + BM25" if message.dense else "BM25 only"
        self.query_one("#retrieval-status", Static).update(
            f"{len(message.hits)} interfaces ranked for "
            f"{self.sw.loaded.capability.capability.label if self.sw.loaded.capability else '?'}"
            f" ({how}, {message.seconds:.2f} s)"
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
            table.add_row(
                mark_of(hit.name, session.pinned, session.dropped),
                str(rank),
                hit.name,
                hit.kind,
                hit.type_name,
                f"{hit.score:.2f}",
                dense,
                f"{hit.lexical:.2f}",
                hit.reason,
            )
            self.rows.append(hit.name)
        for name in session.pinned:
            if name not in self.rows:
                table.add_row("pin", "", name, "", "", "", "", "", "pinned by you")
                self.rows.append(name)

    def show_marks(self) -> None:
        """Redraws marks and the pin/drop summary."""
        if self.sw.loaded.hits or self.sw.session.pinned:
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
        """The capability or inventory changed: the ranking shown is no longer theirs."""
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
        if self._worker is not None and self._worker.is_running:
            self._worker.cancel()
            self.query_one("#retrieval-status", Static).update("cancelled")
            return True
        return False

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand("Rank interfaces", "Retrieval for the capability (Ctrl+R)", self._rank_cmd)

    def _rank_cmd(self) -> None:
        self.sw.action_show_tab("retrieval")
        self.action_rank()
