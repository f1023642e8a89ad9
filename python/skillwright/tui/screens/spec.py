"""The Specification tab: a form for the skill specification, checked as you type.

Every keystroke updates the session's draft (saved a moment later), so nothing typed is
lost. The engine's :func:`~skillwright.spec.parse_spec` judges the draft; its message is
shown as it is. The form is built once the specification module (pydantic) has been
imported in a worker, so the first paint does not wait for it.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult, SystemCommand
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, VerticalScroll
from textual.widgets import Button, Input, Label, LoadingIndicator, Select, Static, TextArea

from skillwright.errors import SkillwrightError
from skillwright.tui.messages import JobFailed, SpecFileLoaded, SpecFormReady
from skillwright.tui.screens.base import Pane
from skillwright.tui.screens.open_path import OpenPathScreen
from skillwright.tui.session import SpecDraft

if TYPE_CHECKING:
    from skillwright.spec.model import SkillSpec

__all__ = ["SpecPane"]


class SpecPane(Pane):
    """Name, description, skill interface and one text per PackML acting state."""

    job = "specification"
    primary = "#spec-name"
    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("ctrl+s", "save", "Save"),
        Binding("ctrl+o", "load_file", "Load file"),
    ]

    def __init__(self) -> None:
        super().__init__(id="spec-pane")
        self.states: tuple[str, ...] = ()
        self.spec: SkillSpec | None = None
        """The draft as the engine accepted it; None while it is invalid."""
        self.problem: str | None = None
        """Why the draft is invalid (the engine's message)."""
        self._file_spec: SkillSpec | None = None

    @property
    def ready(self) -> bool:
        """True once the form is built."""
        return bool(self.states)

    def compose(self) -> ComposeResult:
        yield LoadingIndicator(id="spec-loading")
        yield VerticalScroll(id="spec-form")

    def on_mount(self) -> None:
        self._prepare(self.sw.session.spec_path)

    @work(thread=True, group="spec-prepare", exit_on_error=False)
    def _prepare(self, spec_path: str | None) -> None:
        from skillwright.spec.loader import load_spec
        from skillwright.spec.model import PACKML_STATES, SKILL_INTERFACES

        if spec_path:
            # What the file holds now: tells "saved" from "unsaved changes" after a restart.
            try:
                spec = load_spec(self.sw.workspace.absolute(spec_path))
                self.post_message(SpecFileLoaded(self.sw.workspace.absolute(spec_path), spec))
            except SkillwrightError:
                pass
        self.post_message(SpecFormReady(PACKML_STATES, SKILL_INTERFACES))

    def on_spec_form_ready(self, message: SpecFormReady) -> None:
        self.states = message.states
        draft = self.sw.session.spec_draft
        form = self.query_one("#spec-form", VerticalScroll)
        options = [(Text(self.sw.workspace.relative(p)), str(p)) for p in self.sw.workspace.specs()]
        form.mount_all(
            [
                Horizontal(
                    Select(options, prompt="specification files", id="spec-file", compact=True),
                    Button("Load… ^O", id="spec-load", compact=True),
                    Button("Save ^S", id="spec-save", compact=True),
                    Button("Save as…", id="spec-save-as", compact=True),
                    id="spec-bar",
                ),
                Static("", id="spec-status", markup=False),
                Label("Name (a Python identifier, e.g. move_forward)"),
                # Focus keeps the cursor at the end: a selected name goes with one key.
                Input(draft.name, id="spec-name", compact=True, select_on_focus=False),
                Label("Description"),
                TextArea(draft.description, id="spec-description"),
                Label("Skill interface"),
                Select(
                    [(i, i) for i in message.interfaces],
                    value=draft.skill_interface
                    if draft.skill_interface in message.interfaces
                    else message.interfaces[0],
                    allow_blank=False,
                    id="spec-interface",
                    compact=True,
                ),
            ]
        )
        for state in self.states:
            label = f"{state} (required)" if state == "execute" else state
            form.mount(Label(label, classes="state-label"))
            form.mount(
                TextArea(draft.states.get(state, ""), id=f"state-{state}", classes="state-text")
            )
        self.query_one("#spec-loading").display = False
        self.validate()

    # --- editing ------------------------------------------------------------------------------
    def draft_from_form(self) -> SpecDraft:
        """The draft as the form shows it."""
        interface = self.query_one("#spec-interface", Select).value
        return SpecDraft(
            name=self.query_one("#spec-name", Input).value,
            description=self.query_one("#spec-description", TextArea).text,
            skill_interface=interface if isinstance(interface, str) else "REST",
            states={
                s: text
                for s in self.states
                if (text := self.query_one(f"#state-{s}", TextArea).text)
            },
        )

    @on(Input.Changed, "#spec-name")
    @on(Select.Changed, "#spec-interface")
    @on(TextArea.Changed, "#spec-description, .state-text")
    def _edited(self) -> None:
        if not self.ready:
            return
        self.sw.update_session(spec_draft=self.draft_from_form())
        self.validate()

    def validate(self) -> None:
        """Asks the engine whether the draft is a valid specification; shows the answer."""
        from skillwright.spec.loader import parse_spec

        status = self.query_one("#spec-status", Static)
        try:
            self.spec = parse_spec(self.sw.session.spec_draft.document(), where="specification")
        except SkillwrightError as error:
            self.spec, self.problem = None, str(error)
            status.update(f"✗ {error}")
            status.set_class(True, "error")
            return
        self.problem = None
        status.set_class(False, "error")
        where = self.sw.session.spec_path
        saved = (
            f"saved in {where}"
            if where and self.spec == self._file_spec
            else "unsaved changes"
            if where
            else "not saved to a file yet"
        )
        status.update(f"✓ valid: {', '.join(self.spec.states)} — {saved}")

    def fill(self, spec: SkillSpec) -> None:
        """Shows ``spec`` in the form (the draft follows through the change events)."""
        self.sw.update_session(
            spec_draft=SpecDraft(
                name=spec.name,
                description=spec.description,
                skill_interface=spec.skill_interface,
                states=dict(spec.states),
            )
        )
        if not self.ready:
            return
        self.query_one("#spec-name", Input).value = spec.name
        self.query_one("#spec-description", TextArea).load_text(spec.description)
        self.query_one("#spec-interface", Select).value = spec.skill_interface
        for state in self.states:
            self.query_one(f"#state-{state}", TextArea).load_text(spec.states.get(state, ""))
        self.validate()

    # --- files --------------------------------------------------------------------------------
    @on(Select.Changed, "#spec-file")
    def _file_chosen(self, event: Select.Changed) -> None:
        if isinstance(event.value, str):
            self.load(Path(event.value))

    @on(Button.Pressed, "#spec-load")
    def action_load_file(self) -> None:
        """Asks for a specification file to load."""

        def chosen(path: Path | None) -> None:
            if path is not None:
                self.load(path)

        self.app.push_screen(
            OpenPathScreen("Load a skill specification", self.sw.workspace.root), chosen
        )

    def load(self, path: Path) -> None:
        """Reads ``path`` in a worker and fills the form with it."""
        self._read(path)

    @work(thread=True, exclusive=True, group="spec-read", exit_on_error=False)
    def _read(self, path: Path) -> None:
        from skillwright.spec.loader import load_spec

        try:
            spec = load_spec(path)
        except SkillwrightError as error:
            self.fail(str(error))
            return
        self.post_message(SpecFileLoaded(path, spec, fill=True))

    def on_spec_file_loaded(self, message: SpecFileLoaded) -> None:
        self._file_spec = message.spec
        if message.fill:
            self.sw.update_session(spec_path=self.sw.workspace.relative(message.path))
            self.fill(message.spec)
            self.notify(
                f"loaded {self.sw.workspace.relative(message.path)}",
                title="Specification",
                markup=False,
            )
        elif self.ready:
            self.validate()

    @on(Button.Pressed, "#spec-save")
    def action_save(self) -> None:
        """Saves to the file the draft came from, or asks where."""
        if self.sw.session.spec_path:
            self.save_to(self.sw.workspace.absolute(self.sw.session.spec_path))
        else:
            self.action_save_as()

    @on(Button.Pressed, "#spec-save-as")
    def action_save_as(self) -> None:
        """Asks for a file name (.json or .yaml) and saves there."""
        name = self.sw.session.spec_draft.name.strip() or "skill"
        default = self.sw.workspace.root / f"{name}.spec.yaml"

        def chosen(path: Path | None) -> None:
            if path is not None:
                self.save_to(path)

        self.app.push_screen(
            OpenPathScreen(
                "Save the specification as (.json or .yaml)",
                self.sw.workspace.root,
                value=str(default),
                must_exist=False,
            ),
            chosen,
        )

    def save_to(self, path: Path) -> Path | None:
        """Writes the valid draft to ``path``; None (and a notification) when it cannot."""
        from skillwright.tui.specfile import write_spec

        if not self.ready:
            return None
        if self.spec is None:
            self.fail(f"not saved: {self.problem}")
            return None
        try:
            self._file_spec = write_spec(self.spec, path)
        except SkillwrightError as error:
            self.fail(str(error))
            return None
        self.sw.update_session(spec_path=self.sw.workspace.relative(path))
        self.validate()
        self.notify(
            f"saved {self.sw.workspace.relative(path)}", title="Specification", markup=False
        )
        return path

    def saved_path(self, *, required: bool = True) -> Path | None:
        """The specification as a file for the engine, saving the draft first if it changed.

        None when the draft is invalid; with ``required`` the user is told why and shown the
        form, without it (retrieval can do without a specification) nothing is said.
        """
        if not self.ready or self.spec is None:
            if required:
                self.fail(
                    "the specification form is still loading; try again in a moment"
                    if not self.ready
                    else str(self.problem)  # it names the specification already
                )
                self.sw.action_show_tab("specification")
            return None
        if self.sw.session.spec_path:
            path = self.sw.workspace.absolute(self.sw.session.spec_path)
            if self.spec == self._file_spec and path.is_file():
                return path
        else:
            path = self.sw.workspace.root / f"{self.spec.name}.spec.yaml"
        return self.save_to(path)

    # --- coupling with the other tabs -------------------------------------------------------------
    def capability_changed(self) -> None:
        """Loads the capability's own specification when nothing has been typed yet."""
        path = self.sw.loaded.capability_path
        if path is None or not self.sw.session.spec_draft.is_empty:
            return
        spec = self.sw.workspace.spec_for(path)
        if spec is not None:
            self.load(spec)

    def on_job_failed(self, message: JobFailed) -> None:
        if message.job == self.job and self.ready:
            self.validate()

    def commands(self) -> Iterable[SystemCommand]:
        yield SystemCommand("Save specification", "Save the form (Ctrl+S)", self.action_save)
        yield SystemCommand(
            "Save specification as…",
            "Save the form to a new .json or .yaml file",
            self.action_save_as,
        )
        yield SystemCommand(
            "Load specification", "Fill the form from a file (Ctrl+O)", self._load_from_palette
        )

    def _load_from_palette(self) -> None:
        self.sw.action_show_tab("specification")
        self.action_load_file()
