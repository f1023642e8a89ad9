"""A dialog that asks for a file or folder: type a path or pick it in a folder tree."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Button, DirectoryTree, Input, Label, Static

__all__ = ["OpenPathScreen", "missing_part"]


def missing_part(path: Path) -> str:
    """Which step of the missing ``path`` does not exist, and the existing folder it is not in.

    The dialog shows the reason first and this after it, so however long the path and
    narrow the terminal, "no such file" stays in view; the full path is in the field above.
    """
    existing = path
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        return f"{existing} is a file, not a folder"
    return f"{path.relative_to(existing).parts[0]} is not in {existing}"


class OpenPathScreen(ModalScreen[Path | None]):
    """Returns the chosen path, or None when cancelled.

    ``must_exist`` refuses paths that do not exist (opening); without it any path in an
    existing folder is accepted (saving). The tree starts in ``start``; a relative path typed
    in the field is taken from the folder the TUI was started in, as a shell would take it
    (``base``, the current directory by default), and the field says so.
    """

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "cancel", "Cancel"),
        Binding("ctrl+u", "up", "Parent folder"),
    ]

    def __init__(
        self,
        title: str,
        start: Path,
        *,
        value: str = "",
        must_exist: bool = True,
        base: Path | None = None,
    ) -> None:
        super().__init__()
        self.title_text = title
        self.start = start if start.is_dir() else start.parent
        self.base = base if base is not None else Path.cwd()
        self.value = value
        self.must_exist = must_exist

    def compose(self) -> ComposeResult:
        with Vertical(id="open-dialog"):
            yield Label(self.title_text, id="open-title")
            yield Input(
                value=self.value,
                placeholder=f"path (a relative one is taken from {self.base}; Enter confirms)",
                id="open-path",
            )
            yield Static("", id="open-error", markup=False)
            yield DirectoryTree(self.start, id="open-tree")
            with Horizontal(id="open-buttons"):
                yield Button("OK", variant="primary", id="open-ok", compact=True)
                yield Button("Parent folder ^U", id="open-up", compact=True)
                yield Button("Cancel Esc", id="open-cancel", compact=True)

    def on_mount(self) -> None:
        self.query_one("#open-path", Input).focus()

    def action_cancel(self) -> None:
        """Closes the dialog without a path."""
        self.dismiss(None)

    def action_up(self) -> None:
        """Shows the parent of the folder in the tree."""
        tree = self.query_one(DirectoryTree)
        tree.path = Path(tree.path).resolve().parent

    @on(DirectoryTree.FileSelected)
    @on(DirectoryTree.DirectorySelected)
    def _picked(self, event: DirectoryTree.FileSelected | DirectoryTree.DirectorySelected) -> None:
        self.query_one("#open-path", Input).value = str(event.path)

    @on(Input.Submitted, "#open-path")
    @on(Button.Pressed, "#open-ok")
    def _confirm(self) -> None:
        text = self.query_one("#open-path", Input).value.strip()
        error = self.query_one("#open-error", Static)
        if not text:
            error.update("type a path or pick one in the tree")
            return
        path = Path(text).expanduser()
        if not path.is_absolute():
            path = self.base / path
        try:
            if self.must_exist and not path.exists():
                error.update(f"no such file or folder: {missing_part(path)}")
                return
            if not self.must_exist and not path.parent.is_dir():
                error.update(f"no such folder: {missing_part(path.parent)}")
                return
        except OSError as problem:  # a folder on the way that may not be looked into
            error.update(f"cannot look there: {problem.strerror} ({problem.filename})")
            return
        self.dismiss(path)

    @on(Button.Pressed, "#open-up")
    def _up(self) -> None:
        self.action_up()

    @on(Button.Pressed, "#open-cancel")
    def _cancel(self) -> None:
        self.dismiss(None)
