"""The skillwright TUI: one app, six tabs, each driving one part of the engine.

The app owns the workspace, the session (saved as it changes) and the documents loaded so
far (capability, inventory, ranked interfaces). The tabs in :mod:`skillwright.tui.screens`
call the engine in thread workers and show what it returns; nothing here decides anything
the headless commands would decide differently.

Only Textual and standard-library-light skillwright modules are imported here, so the first
paint does not wait for rdflib, pydantic, NumPy or llama.cpp; each loads in the worker that
first needs it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from textual.app import App, ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.screen import Screen
from textual.timer import Timer
from textual.widgets import Footer, Header, TabbedContent, TabPane
from textual.worker import Worker, WorkerState

from skillwright.errors import SkillwrightError
from skillwright.tui.messages import JobFailed
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.capability import CapabilityPane
from skillwright.tui.screens.generation import GenerationPane
from skillwright.tui.screens.help import HelpScreen
from skillwright.tui.screens.history import HistoryPane
from skillwright.tui.screens.interfaces import InterfacesPane
from skillwright.tui.screens.retrieval import RetrievalPane
from skillwright.tui.screens.spec import SpecPane
from skillwright.tui.session import TABS, load_session, save_session
from skillwright.tui.widgets.tabs import FocusTabs
from skillwright.tui.workspace import Workspace

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityLoad
    from skillwright.interfaces.inventory import Inventory
    from skillwright.retrieval.retrieve import Hit

__all__ = ["SkillwrightApp", "make_app"]

TAB_TITLES = {
    "capability": "Capability",
    "specification": "Specification",
    "interfaces": "Interfaces",
    "retrieval": "Retrieval",
    "generation": "Generation",
    "history": "History",
}
TAB_KEYS = {"capability": "f2", "specification": "f3", "interfaces": "f4"}
TAB_KEYS |= {"retrieval": "f5", "generation": "f6", "history": "f7"}


@dataclass
class Loaded:
    """Documents the engine returned in this session (not saved: they are re-read on start)."""

    capability_path: Path | None = None
    capability: CapabilityLoad | None = None
    inventory_source: Path | None = None
    inventory: Inventory | None = None
    hits: list[Hit] = field(default_factory=list)


class SkillwrightApp(App[None]):
    """Pick a capability, write the specification, load interfaces, rank, generate, review."""

    CSS_PATH = "app.tcss"
    TITLE = "skillwright"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("f1", "help", "Help"),
        # Before the focused widget's own keys: a text area takes F6 and F7 (select line,
        # select all), and the tab keys must work from every tab.
        *(
            Binding(key, f"show_tab('{tab}')", TAB_TITLES[tab], show=False, priority=True)
            for tab, key in TAB_KEYS.items()
        ),
        Binding("ctrl+g", "generate", "Generate", priority=True),
        Binding("escape", "cancel", "Cancel"),
    ]

    def __init__(
        self,
        workspace: Path,
        *,
        models_file: Path | None = None,
        save_delay: float = 0.4,
    ) -> None:
        super().__init__()
        self.workspace = Workspace(workspace)
        self.models_file = models_file
        self.save_delay = save_delay
        """Seconds after the last change before the session is written."""
        self.session, problem = load_session(self.workspace.session_path)
        self._session_problem = problem
        self.loaded = Loaded()
        self._save_timer: Timer | None = None
        self._save_failed = False
        self.sub_title = f"workspace {self.workspace.root.name}"
        # Wider terminals give side panels more room; from 160 columns the findings go
        # beside the code (see app.tcss).
        self.HORIZONTAL_BREAKPOINTS = [(0, "-narrow"), (120, "-wide"), (160, "-wider")]

    # --- layout -----------------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        yield Header()
        with FocusTabs(initial=self.session.active_tab, id="tabs"):
            with TabPane(TAB_TITLES["capability"], id="capability"):
                yield CapabilityPane()
            with TabPane(TAB_TITLES["specification"], id="specification"):
                yield SpecPane()
            with TabPane(TAB_TITLES["interfaces"], id="interfaces"):
                yield InterfacesPane()
            with TabPane(TAB_TITLES["retrieval"], id="retrieval"):
                yield RetrievalPane()
            with TabPane(TAB_TITLES["generation"], id="generation"):
                yield GenerationPane()
            with TabPane(TAB_TITLES["history"], id="history"):
                yield HistoryPane()
        yield Footer()

    def on_mount(self) -> None:
        if self._session_problem:
            self.notify(
                self._session_problem, title="Session", severity="warning", timeout=10, markup=False
            )

    # --- session ----------------------------------------------------------------------------
    def update_session(self, **changes: Any) -> None:
        """Changes the session and saves it a moment later (one write per burst of typing)."""
        updated = replace(self.session, **changes)
        if updated == self.session:
            return
        self.session = updated
        if self._save_timer is not None:
            self._save_timer.stop()
        self._save_timer = self.set_timer(self.save_delay, self.save_session_now)

    def save_session_now(self) -> None:
        """Writes the session file now (atomically)."""
        self._save_timer = None
        try:
            save_session(self.workspace.session_path, self.session)
        except SkillwrightError as error:
            if not self._save_failed:  # say it once, not on every keystroke
                self.notify(
                    f"{error}; your session is not being saved", severity="error", markup=False
                )
            self._save_failed = True
        else:
            self._save_failed = False

    async def action_quit(self) -> None:
        """Saves the session, stops running jobs (their threads would keep the process
        alive until done), then quits."""
        if self._save_timer is not None:
            self._save_timer.stop()
            self.save_session_now()
        for pane in self._panes():
            pane.cancel_job()
        await super().action_quit()

    # --- navigation -------------------------------------------------------------------------
    def on_tabbed_content_tab_activated(self, event: TabbedContent.TabActivated) -> None:
        # The tab shown now, not the event's: the first activation can arrive after the user
        # has already switched tabs, and must not pull the focus or the session back.
        tabs = event.tabbed_content
        tab = tabs.active
        if tab in TABS:
            self.update_session(active_tab=tab)
        # Now, so the next key reaches the tab, and again after the refresh, because hiding
        # the old tab can move the focus in between.
        self._focus_active_pane()
        self.call_after_refresh(self._focus_active_pane)

    def _focus_active_pane(self) -> None:
        # The tab active when this runs: focusing a widget in another tab would switch to it.
        tabs = self.query_one("#tabs", TabbedContent)
        for pane in tabs.get_pane(tabs.active).query(Pane):
            focused = self.focused
            if focused is None or pane not in focused.ancestors_with_self:
                pane.focus_primary()

    def action_show_tab(self, tab: str) -> None:
        """Switches to the tab with id ``tab`` and focuses it in the same step, so no focus
        message still on its way for the tab left can take the tab back."""
        self.query_one("#tabs", TabbedContent).active = tab
        self._focus_active_pane()

    def action_help(self) -> None:
        """Shows the keys and the flow."""
        if not isinstance(self.screen, HelpScreen):
            self.push_screen(HelpScreen())

    def action_generate(self) -> None:
        """Starts a generation (from any tab)."""
        self.action_show_tab("generation")
        self.query_one(GenerationPane).start()

    def action_cancel(self) -> None:
        """Cancels the running engine job of the visible tab, if any."""
        for pane in self._panes():
            if pane.cancel_job():
                return

    def _panes(self) -> list[Any]:
        active = self.query_one("#tabs", TabbedContent).active
        panes: list[Any] = [
            self.query_one(p)
            for p in (
                GenerationPane,
                InterfacesPane,
                RetrievalPane,
                CapabilityPane,
                SpecPane,
                HistoryPane,
            )
        ]
        # The visible tab's job first: Esc means "stop what I am looking at".
        return sorted(panes, key=lambda p: p.parent is None or p.parent.id != active)

    # --- notifications from the panes ----------------------------------------------------------
    def capability_changed(self) -> None:
        """A capability was loaded: the specification may follow it, results are stale."""
        self.query_one(SpecPane).capability_changed()
        self.query_one(RetrievalPane).inputs_changed()

    def inventory_changed(self) -> None:
        """An inventory was loaded or enriched: ranked results are stale."""
        self.query_one(RetrievalPane).inputs_changed()

    def pins_changed(self) -> None:
        """Pins or drops changed in one table; the other shows them too."""
        self.query_one(InterfacesPane).show_marks()
        self.query_one(RetrievalPane).show_marks()

    def toggle_mark(self, name: str, mark: str) -> None:
        """Pins (``mark="pinned"``) or drops (``"dropped"``) ``name``; again undoes it.

        An interface is never both: pinning one that was dropped un-drops it.
        """
        pinned, dropped = list(self.session.pinned), list(self.session.dropped)
        chosen, other = (pinned, dropped) if mark == "pinned" else (dropped, pinned)
        if name in chosen:
            chosen.remove(name)
        else:
            chosen.append(name)
            if name in other:
                other.remove(name)
        self.update_session(pinned=tuple(pinned), dropped=tuple(dropped))
        self.pins_changed()

    def spec_pane(self) -> SpecPane:
        """The Specification tab (the draft and its file)."""
        return self.query_one(SpecPane)

    def history_changed(self) -> None:
        """A generation finished: the history lists it."""
        self.query_one(HistoryPane).reload()

    def on_job_failed(self, message: JobFailed) -> None:
        self.notify(
            message.message,
            title=message.job.capitalize(),
            severity="warning" if message.cancelled else "error",
            timeout=8,
            markup=False,
        )

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        # Engine errors arrive as JobFailed; an exception here is a bug. Show it as a
        # notification instead of Textual's traceback screen, and keep the session alive.
        if event.state == WorkerState.ERROR and event.worker.error is not None:
            error = event.worker.error
            self.notify(
                f"{type(error).__name__}: {error} (in {event.worker.name}); this is a bug in "
                "skillwright, please report it",
                title="Internal error",
                severity="error",
                timeout=15,
                markup=False,
            )

    # --- command palette --------------------------------------------------------------------
    def get_system_commands(self, screen: Screen[Any]) -> Iterable[SystemCommand]:
        yield from super().get_system_commands(screen)
        for tab, title in TAB_TITLES.items():
            yield SystemCommand(
                f"Go to {title}",
                f"Show the {title} tab ({TAB_KEYS[tab].upper()})",
                lambda tab=tab: self.action_show_tab(tab),
            )
        yield SystemCommand("Help", "Keys and flow of the TUI (F1)", self.action_help)
        yield SystemCommand(
            "Generate skill",
            "Run the pipeline with the current inputs (Ctrl+G)",
            self.action_generate,
        )
        yield SystemCommand("Cancel job", "Stop the running job (Esc)", self.action_cancel)
        for pane in self._panes():
            yield from pane.commands()


def make_app(workspace: Path, *, models_file: Path | None = None) -> SkillwrightApp:
    """The app for ``workspace`` (the CLI entry point and the tests both build it here)."""
    return SkillwrightApp(workspace, models_file=models_file)
