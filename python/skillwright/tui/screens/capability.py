"""The Capability tab: the workspace's capability models and the summary of the chosen one.

A file that holds several capabilities shows them in a list above the summary (label, local
name, IRI); the one chosen is kept in the session with the file.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from rich.console import RenderableType
from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.widgets import Button, Label, LoadingIndicator, OptionList, Static, TabbedContent
from textual.widgets.option_list import Option
from textual.worker import get_current_worker

from skillwright.errors import (
    CapabilitySelectionError,
    OperationCancelledError,
    SkillwrightError,
)
from skillwright.tui.jobs import EngineJob
from skillwright.tui.messages import CapabilityChoices, CapabilityLoaded, JobFailed
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.open_path import OpenPathScreen

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityChoice

__all__ = ["CapabilityPane", "choice_prompt"]


def choice_prompt(choice: CapabilityChoice) -> Text:
    """How a capability is offered in the list: label and local name, its IRI below."""
    return Text.assemble(
        (choice.label, "bold"), "  ", choice.name, "\n", (choice.iri, "dim"), no_wrap=False
    )


class CapabilityPane(Pane):
    """Browse capability models; the engine's summary of the selected one."""

    job = "capability"
    primary = "#capability-list"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("ctrl+o", "open_file", "Open file"),
        Binding("ctrl+r", "reload", "Reload"),
    ]

    def __init__(self) -> None:
        super().__init__(id="capability-pane")
        self._job = EngineJob()
        self._path: Path | None = None
        self.summary: RenderableType = ""
        """The engine's summary of the loaded capability, as shown."""

    def compose(self) -> ComposeResult:
        with Horizontal():
            with Vertical(id="capability-side"):
                yield Label("Capabilities in the workspace", classes="section")
                yield OptionList(id="capability-list")
                yield Button("Open file… ^O", id="capability-open", compact=True)
            with VerticalScroll(id="capability-view"):
                yield LoadingIndicator(id="capability-loading")
                yield Static("", id="capability-status", markup=False)
                yield OptionList(id="capability-choices")
                yield Static(
                    "Choose a capability model on the left (Enter), or open any file with Ctrl+O.",
                    id="capability-summary",
                    markup=False,
                )

    def on_mount(self) -> None:
        self.query_one("#capability-loading").display = False
        self.query_one("#capability-choices").display = False
        self.refresh_list()
        stored = self.sw.session.capability
        if stored:
            self.load(self.sw.workspace.absolute(stored))

    def refresh_list(self) -> None:
        """Lists the workspace's capability models again."""
        options = self.query_one("#capability-list", OptionList)
        options.clear_options()
        workspace = self.sw.workspace
        paths = workspace.capabilities()
        options.add_options(Option(Text(workspace.relative(p)), id=str(p)) for p in paths)
        if not paths:
            options.add_option(Option(Text(f"(no .ttl files in {workspace.root})"), disabled=True))
        stored = self.sw.session.capability
        if stored:
            chosen = str(workspace.absolute(stored))
            for index, path in enumerate(paths):
                if str(path) == chosen:
                    options.highlighted = index

    # --- actions ------------------------------------------------------------------------------
    @on(OptionList.OptionSelected, "#capability-list")
    def _selected(self, event: OptionList.OptionSelected) -> None:
        if event.option.id:
            self.load(Path(event.option.id))

    @on(OptionList.OptionSelected, "#capability-choices")
    def _choice_selected(self, event: OptionList.OptionSelected) -> None:
        if event.option.id and self._path is not None:
            self.sw.update_session(capability_iri=event.option.id)
            self.load(self._path)

    @on(Button.Pressed, "#capability-open")
    def action_open_file(self) -> None:
        """Asks for any capability file."""
        current = self.sw.loaded.capability_path or self.sw.workspace.root

        def chosen(path: Path | None) -> None:
            if path is not None:
                self.load(path)

        self.app.push_screen(OpenPathScreen("Open a capability model", current), chosen)

    def action_reload(self) -> None:
        """Reads the selected file again (after editing it, or with another IRI)."""
        path = self.sw.loaded.capability_path
        if path is None and self.sw.session.capability:
            path = self.sw.workspace.absolute(self.sw.session.capability)
        if path is not None:
            self.load(path)

    def load(self, path: Path) -> None:
        """Reads ``path`` in a worker; the summary follows when it is done.

        The capability chosen earlier is kept for the same file and forgotten for another.
        """
        relative = self.sw.workspace.relative(path)
        if relative != self.sw.session.capability:
            self.sw.update_session(capability=relative, capability_iri=None)
        self._path = path
        self.query_one("#capability-loading").display = True
        self.query_one("#capability-status", Static).update(f"reading {path} …")
        iri = self.sw.session.capability_iri
        self._job.start(lambda cancel: self._read(path, iri, cancel))

    @work(thread=True, exclusive=True, group="capability", exit_on_error=False)
    def _read(self, path: Path, iri: str | None, cancel: threading.Event) -> None:
        # rdflib and pydantic load here, in the worker, on first use.
        from skillwright.capability.reader import load_capability
        from skillwright.capability.render import render_capability

        try:
            load = load_capability(
                path,
                capability_iri=iri,
                ontologies=self.sw.workspace.ontologies(),
                cancel=cancel,
                ontology_hint=self.sw.workspace.ontology_hint(),
            )
        except OperationCancelledError:
            return  # the pane already says so, or a newer read replaced this one
        except CapabilitySelectionError as error:
            self.post_message(CapabilityChoices(path, error.choices, iri))
            return
        except SkillwrightError as error:
            self.fail(str(error))
            return
        # Show where the file is relative to the workspace, as everywhere in the TUI.
        load = load.model_copy(update={"source": self.sw.workspace.relative(path)})
        if not get_current_worker().is_cancelled:
            self.post_message(CapabilityLoaded(path, load, render_capability(load)))

    def cancel_job(self) -> bool:
        if self._job.stop():
            self.query_one("#capability-loading").display = False
            self.query_one("#capability-status", Static).update("cancelled")
            return True
        return False

    # --- results ------------------------------------------------------------------------------
    def on_capability_loaded(self, message: CapabilityLoaded) -> None:
        self.query_one("#capability-loading").display = False
        status = self.query_one("#capability-status", Static)
        status.set_class(False, "error")
        warnings = [f"warning: {w}" for w in message.load.warnings]
        status.update("\n".join(warnings))
        status.set_class(bool(warnings), "warning")
        self.summary = message.summary
        self.query_one("#capability-summary", Static).update(message.summary)
        self._show_choices(message.load.choices, message.load.capability.iri)
        self.sw.loaded.capability_path = message.path
        self.sw.loaded.capability = message.load
        self.sw.capability_changed()

    def on_capability_choices(self, message: CapabilityChoices) -> None:
        where = self.sw.workspace.relative(message.path)
        if len(message.choices) == 1:
            # The choice saved earlier is gone from the file and one capability is left.
            self.notify(
                f"{message.wanted} is no longer in {where}; reading its only capability",
                title="Capability",
                severity="warning",
                markup=False,
            )
            self.sw.update_session(capability_iri=None)
            self.load(message.path)
            return
        self.query_one("#capability-loading").display = False
        status = self.query_one("#capability-status", Static)
        status.set_class(False, "error")
        status.set_class(True, "warning")
        count = len(message.choices)
        if message.wanted:
            status.update(
                f"{message.wanted} does not name one of the {count} capabilities in {where}: "
                "choose one (Enter)"
            )
        else:
            status.update(f"{where} holds {count} capabilities: choose one (Enter)")
        self.summary = ""
        self.query_one("#capability-summary", Static).update("")
        self._show_choices(message.choices, None)
        # Focusing a widget of a hidden tab would switch to it; only take the focus if shown.
        if self.sw.query_one("#tabs", TabbedContent).active == "capability":
            self.focus_now(self.query_one("#capability-choices", OptionList))
        self.sw.loaded.capability = None
        self.sw.loaded.capability_path = None

    def _show_choices(self, choices: list[CapabilityChoice], chosen: str | None) -> None:
        picker = self.query_one("#capability-choices", OptionList)
        picker.clear_options()
        picker.display = len(choices) > 1
        if picker.display:
            picker.add_options(Option(choice_prompt(c), id=c.iri) for c in choices)
            iris = [c.iri for c in choices]
            picker.highlighted = iris.index(chosen) if chosen in iris else 0

    def on_job_failed(self, message: JobFailed) -> None:
        if message.job != self.job:
            return
        self.query_one("#capability-loading").display = False
        self.query_one("#capability-choices").display = False
        status = self.query_one("#capability-status", Static)
        status.set_class(False, "warning")
        status.set_class(True, "error")
        status.update(message.message)
        self.summary = ""
        self.query_one("#capability-summary", Static).update("")
        self.sw.loaded.capability = None
        self.sw.loaded.capability_path = None

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand(
            "Open capability file", "Read any capability model (Ctrl+O)", self._open_from_palette
        )
        yield SystemCommand("Reload capability", "Read the file again", self.action_reload)

    def _open_from_palette(self) -> None:
        self.sw.action_show_tab("capability")
        self.action_open_file()
