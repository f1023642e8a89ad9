"""The Interfaces tab: load an interface source, browse and search it, describe it."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, VerticalScroll
from textual.coordinate import Coordinate
from textual.widgets import Button, Checkbox, DataTable, Input, ProgressBar, Select, Static
from textual.worker import get_current_worker

from skillwright.errors import OperationCancelledError, SkillwrightError
from skillwright.tui.jobs import EngineJob
from skillwright.tui.messages import EnrichProgress, InventoryEnriched, InventoryLoaded, JobFailed
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.open_path import OpenPathScreen
from skillwright.tui.widgets.interface_detail import mark_of, relevance_of, render_interface

if TYPE_CHECKING:
    from skillwright.interfaces.inventory import Interface, Inventory
    from skillwright.llm.model_lock import ModelWait

__all__ = ["InterfacesPane", "is_infrastructure", "matches"]

_PROGRESS_SECONDS = 0.1

ENGINES = ("rules", "llm")
"""Enrichment engines: the deterministic rules, or the local model chosen for generation."""


def is_infrastructure(interface: Interface) -> bool:
    """True when the engine flagged the interface as ROS 2 or tooling plumbing."""
    if interface.relevance is not None:
        return interface.relevance.category == "infrastructure"
    return interface.infrastructure is not None


def matches(interface: Interface, query: str) -> bool:
    """True when every word of ``query`` occurs in the name, kind, type or description."""
    haystack = " ".join(
        [
            interface.name,
            interface.kind,
            interface.type_name,
            interface.description.text() if interface.description else "",
        ]
    ).lower()
    return all(word in haystack for word in query.lower().split())


def inventory_target(workspace_root: Path, source: Path) -> Path:
    """Where an enriched inventory of ``source`` is saved: a saved inventory in place, any
    other source as ``<workspace>/<name>.inventory.json``."""
    if source.name.lower().endswith(".inventory.json"):
        return source
    name = source.name
    for suffix in (".inventory.json", ".json", ".mcap"):
        if name.lower().endswith(suffix):
            name = name[: -len(suffix)]
            break
    return workspace_root / f"{name or 'interfaces'}.inventory.json"


class InterfacesPane(Pane):
    """A table of the inventory's interfaces with a detail pane; pins and drops."""

    job = "interfaces"
    primary = "#interfaces-table"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("ctrl+o", "open_source", "Open source"),
        # Before the filter box's own Ctrl+E (end of line; End does that too).
        Binding("ctrl+e", "enrich", "Describe", priority=True),
        Binding("slash", "filter", "Filter"),
        Binding("p", "pin", "Pin"),
        Binding("x", "drop", "Drop"),
    ]

    def __init__(self) -> None:
        super().__init__(id="interfaces-pane")
        self._load_job = EngineJob()
        self._enrich_job = EngineJob()
        self.shown: list[Interface] = []
        """The interfaces in the table, in table order."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="interfaces-bar", classes="bar"):
            yield Select[str]([], prompt="interface source", id="interfaces-source", compact=True)
            yield Button("Open… ^O", id="interfaces-open", compact=True)
            yield Button("Live ROS 2", id="interfaces-live", compact=True)
        with Horizontal(id="interfaces-tools", classes="bar"):
            yield Input(
                placeholder="/ filter: name, type, description",
                id="interfaces-filter",
                compact=True,
            )
            yield Checkbox("infrastructure", id="interfaces-infra", compact=True)
            yield Select[str](
                [("rules", "rules"), ("model", "llm")],
                value=self.sw.session.enrich_engine,
                allow_blank=False,
                id="interfaces-engine",
                compact=True,
            )
            yield Button("Describe ^E", id="interfaces-enrich", compact=True)
        yield Static(
            "No interfaces loaded: choose a source above.", id="interfaces-status", markup=False
        )
        yield ProgressBar(id="interfaces-progress", show_eta=False)
        yield DataTable(id="interfaces-table", cursor_type="row", zebra_stripes=True)
        with VerticalScroll(id="interfaces-detail"):
            yield Static("", id="interfaces-detail-text", markup=False)

    def on_mount(self) -> None:
        self.query_one("#interfaces-progress").display = False
        table = self.query_one("#interfaces-table", DataTable)
        table.add_columns("mark", "kind", "name", "type", "relevance", "description")
        self.query_one("#interfaces-infra", Checkbox).value = self.sw.session.show_infrastructure
        self.refresh_sources()
        stored = self.sw.session.interfaces
        if stored:
            self.load(self.sw.workspace.absolute(stored))

    def refresh_sources(self) -> None:
        """Lists the workspace's interface sources in the selector."""
        workspace = self.sw.workspace
        select = self.query_one("#interfaces-source", Select)
        paths = workspace.interface_sources()
        current = self.sw.loaded.inventory_source
        if current is not None and current not in paths:
            paths.append(current)
        with self.prevent(Select.Changed):
            select.set_options((Text(workspace.relative(p)), str(p)) for p in paths)
            if current is not None:
                select.value = str(current)

    # --- loading ------------------------------------------------------------------------------
    @on(Select.Changed, "#interfaces-source")
    def _source_chosen(self, event: Select.Changed) -> None:
        if isinstance(event.value, str):
            self.load(Path(event.value))

    @on(Button.Pressed, "#interfaces-open")
    def action_open_source(self) -> None:
        """Asks for an inventory, an .mcap file, a rosbag2 folder or a report."""

        def chosen(path: Path | None) -> None:
            if path is not None:
                self.load(path)

        self.app.push_screen(
            OpenPathScreen(
                "Open an interface source (inventory or report .json, .mcap, rosbag2 folder)",
                self.sw.workspace.root,
            ),
            chosen,
        )

    def load(self, source: Path) -> None:
        """Reads ``source`` in a worker."""
        self.query_one("#interfaces-status", Static).update(f"reading {source} …")
        self._load_job.start(lambda cancel: self._read(source, cancel))

    @work(thread=True, exclusive=True, group="interfaces", exit_on_error=False)
    def _read(self, source: Path, cancel: threading.Event) -> None:
        from skillwright.interfaces.load import load_inventory

        try:
            inventory = load_inventory(source, cancel=cancel)
        except OperationCancelledError:
            return  # the pane already says so, or a newer read replaced this one
        except SkillwrightError as error:
            self.fail(str(error))
            return
        if not get_current_worker().is_cancelled:
            self.post_message(InventoryLoaded(source, inventory))

    @on(Button.Pressed, "#interfaces-live")
    def action_live(self) -> None:
        """Discovers the running ROS 2 graph (needs rclpy) and saves it as an inventory."""
        self.query_one("#interfaces-status", Static).update(
            "discovering the live ROS 2 graph (until two snapshots agree, at most 10 s) …"
        )
        # Live discovery does not take the switch yet: cancelling it only drops its result.
        root = self.sw.workspace.root
        self._load_job.start(lambda _cancel: self._discover_live(root))

    @work(thread=True, exclusive=True, group="interfaces", exit_on_error=False)
    def _discover_live(self, root: Path) -> None:
        from skillwright.fileio import write_atomic
        from skillwright.interfaces.sources.live import LiveSource

        try:
            inventory = LiveSource().discover()
            target = root / f"{inventory.resource.name}.inventory.json"
            # Generation reads its interfaces from a file, and the next start finds it there.
            write_atomic(target, inventory.model_dump_json(indent=2) + "\n")
        except SkillwrightError as error:
            self.fail(str(error))
            return
        if not get_current_worker().is_cancelled:
            self.post_message(InventoryLoaded(target, inventory))

    def on_inventory_loaded(self, message: InventoryLoaded) -> None:
        from skillwright.interfaces.load import read_warnings

        for warning in read_warnings(message.inventory):
            self.notify(warning, title="Interfaces", severity="warning", markup=False)
        self.sw.update_session(interfaces=self.sw.workspace.relative(message.source))
        self.sw.loaded.inventory_source = message.source
        self.sw.loaded.inventory = message.inventory
        self.refresh_sources()
        self.show_table()
        self.sw.inventory_changed()

    # --- table ----------------------------------------------------------------------------------
    def show_table(self) -> None:
        """Fills the table with the interfaces that pass the filter."""
        inventory = self.sw.loaded.inventory
        table = self.query_one("#interfaces-table", DataTable)
        table.clear()
        self.shown = []
        if inventory is None:
            return
        query = self.query_one("#interfaces-filter", Input).value
        show_infra = self.sw.session.show_infrastructure
        hidden = 0
        for interface in inventory.interfaces:
            if not show_infra and is_infrastructure(interface):
                hidden += 1
                continue
            if not matches(interface, query):
                continue
            self.shown.append(interface)
            table.add_row(*self._cells(interface), key=f"{interface.kind} {interface.name}")
        source = self.sw.loaded.inventory_source
        where = self.sw.workspace.relative(source) if source else "?"
        counts = f"{len(self.shown)} of {len(inventory.interfaces)} interfaces shown"
        if hidden:
            counts += f", {hidden} infrastructure hidden"
        status = self.query_one("#interfaces-status", Static)
        status.set_class(False, "error")
        status.update(f"{inventory.resource.name} from {where}: {counts}")
        self._show_detail()

    def _cells(self, interface: Interface) -> tuple[Text, ...]:
        session = self.sw.session
        return tuple(
            Text(cell)
            for cell in (
                mark_of(interface.name, session.pinned, session.dropped),
                interface.kind,
                interface.name,
                interface.type_name,
                relevance_of(interface),
                interface.description.purpose if interface.description else "",
            )
        )

    def show_marks(self) -> None:
        """Redraws the mark column after pins or drops changed."""
        table = self.query_one("#interfaces-table", DataTable)
        session = self.sw.session
        for row, interface in enumerate(self.shown):
            mark = mark_of(interface.name, session.pinned, session.dropped)
            table.update_cell_at(Coordinate(row, 0), mark)

    @on(Input.Changed, "#interfaces-filter")
    def _filter_changed(self) -> None:
        self.show_table()

    @on(Checkbox.Changed, "#interfaces-infra")
    def _infra_toggled(self, event: Checkbox.Changed) -> None:
        self.sw.update_session(show_infrastructure=event.value)
        self.show_table()

    def action_filter(self) -> None:
        """Puts the cursor in the filter field."""
        self.query_one("#interfaces-filter", Input).focus()

    @on(DataTable.RowHighlighted, "#interfaces-table")
    def _highlighted(self) -> None:
        self._show_detail()

    def highlighted(self) -> Interface | None:
        """The interface under the table's cursor."""
        table = self.query_one("#interfaces-table", DataTable)
        if not self.shown or table.cursor_row < 0 or table.cursor_row >= len(self.shown):
            return None
        return self.shown[table.cursor_row]

    def _show_detail(self) -> None:
        interface = self.highlighted()
        text = self.query_one("#interfaces-detail-text", Static)
        text.update(render_interface(interface) if interface is not None else "")

    def action_pin(self) -> None:
        """Forces the highlighted interface into generation (again: undoes it)."""
        interface = self.highlighted()
        if interface is not None:
            self.sw.toggle_mark(interface.name, "pinned")

    def action_drop(self) -> None:
        """Keeps the highlighted interface out of generation (again: undoes it)."""
        interface = self.highlighted()
        if interface is not None:
            self.sw.toggle_mark(interface.name, "dropped")

    # --- enrichment -----------------------------------------------------------------------------
    @on(Select.Changed, "#interfaces-engine")
    def _engine_chosen(self, event: Select.Changed) -> None:
        if event.value in ENGINES:
            self.sw.update_session(enrich_engine=event.value)

    @on(Button.Pressed, "#interfaces-enrich")
    def action_enrich(self) -> None:
        """Describes and judges every interface with the chosen engine; saves the inventory."""
        inventory, source = self.sw.loaded.inventory, self.sw.loaded.inventory_source
        if inventory is None or source is None:
            self.fail("load an interface source first (Ctrl+O)")
            return
        if self._enrich_job.running:
            return
        progress = self.query_one("#interfaces-progress", ProgressBar)
        progress.update(total=len(inventory.interfaces), progress=0)
        progress.display = True
        session = self.sw.session
        # The llm engine uses the model chosen for generation (or the configured default).
        model = None if session.skeleton else session.model
        target = inventory_target(self.sw.workspace.root, source)
        self._enrich_job.start(
            lambda cancel: self._enrich(inventory, target, session.enrich_engine, model, cancel)
        )

    @work(thread=True, exclusive=True, group="enrich", exit_on_error=False)
    def _enrich(
        self,
        inventory: Inventory,
        target: Path,
        engine_name: str,
        model: str | None,
        cancel: threading.Event,
    ) -> None:
        from skillwright.fileio import write_atomic
        from skillwright.interfaces.enrich import (
            Engine,
            LlmEngine,
            RulesEngine,
            default_cache,
            enrich,
        )

        last = 0.0

        def progress(done: int, total: int, name: str) -> None:
            nonlocal last
            # A few updates a second are enough to watch; thousands would flood the queue.
            now = time.monotonic()
            if now - last >= _PROGRESS_SECONDS or done == total:
                last = now
                self.post_message(EnrichProgress(done, total, name))

        generator = None
        try:
            engine: Engine = RulesEngine()
            if engine_name == "llm":
                from skillwright.llm import load_generator
                from skillwright.llm.config import load_registry

                total = len(inventory.interfaces)
                self.post_message(EnrichProgress(0, total, "loading the model"))

                def waiting(wait: ModelWait) -> None:
                    self.post_message(EnrichProgress(0, total, wait.message()))

                generator = load_generator(
                    load_registry(self.sw.models_file), model, on_wait=waiting, cancel=cancel
                )
                engine = LlmEngine(generator)
            report = enrich(
                inventory, engine, cache=default_cache(), progress=progress, cancel=cancel
            )
            if report.cancelled:
                self.fail("enrichment cancelled; the inventory is unchanged", cancelled=True)
                return
            write_atomic(target, report.inventory.model_dump_json(indent=2) + "\n")
        except SkillwrightError as error:
            self.fail(str(error), cancelled=cancel.is_set())
            return
        finally:
            if generator is not None:
                generator.close()
        summary = report.summary()
        summary.append(f"{report.control} control, {report.infrastructure} infrastructure")
        self.post_message(InventoryEnriched(report.inventory, target, "; ".join(summary)))

    def on_enrich_progress(self, message: EnrichProgress) -> None:
        self.query_one("#interfaces-progress", ProgressBar).update(
            total=message.total, progress=message.done
        )
        self.query_one("#interfaces-status", Static).update(
            f"describing {message.done}/{message.total}: {message.current}"
        )

    def on_inventory_enriched(self, message: InventoryEnriched) -> None:
        self.query_one("#interfaces-progress").display = False
        self.sw.loaded.inventory = message.inventory
        self.sw.loaded.inventory_source = message.saved_to
        self.sw.update_session(interfaces=self.sw.workspace.relative(message.saved_to))
        self.refresh_sources()
        self.show_table()
        where = self.sw.workspace.relative(message.saved_to)
        self.notify(f"{message.summary}; saved as {where}", title="Interfaces", markup=False)
        self.sw.inventory_changed()

    def on_job_failed(self, message: JobFailed) -> None:
        if message.job != self.job:
            return
        self.query_one("#interfaces-progress").display = False
        status = self.query_one("#interfaces-status", Static)
        status.update(f"✗ {message.message}")
        status.set_class(not message.cancelled, "error")

    def cancel_job(self) -> bool:
        for job in (self._enrich_job, self._load_job):
            if job.stop():
                self.query_one("#interfaces-progress").display = False
                if job is self._load_job:
                    self.query_one("#interfaces-status", Static).update("cancelled")
                return True
        return False

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand(
            "Open interface source",
            "Inventory, .mcap or rosbag2 folder (Ctrl+O)",
            self._open_from_palette,
        )
        yield SystemCommand(
            "Discover the live ROS 2 graph", "Needs ROS 2 sourced (rclpy)", self.action_live
        )
        yield SystemCommand(
            "Describe interfaces",
            "Enrich the inventory with descriptions (Ctrl+E)",
            self.action_enrich,
        )

    def _open_from_palette(self) -> None:
        self.sw.action_show_tab("interfaces")
        self.action_open_source()
