"""A read-only, syntax-highlighted view of a skill's code that text can stream into.

Highlighting is Textual's tree-sitter highlighting (``tree-sitter`` and
``tree-sitter-python`` are installed wheels with the grammar compiled in: nothing is fetched).
Without them the code is shown plain. Streamed text is buffered and appended a few times a
second, because each append re-highlights the document.
"""

from __future__ import annotations

from textual.widgets import TextArea

__all__ = ["CodeView"]

_FLUSH_SECONDS = 0.05


class CodeView(TextArea):
    """Python source, read-only, with line numbers; :meth:`append` streams into it."""

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(
            "",
            read_only=True,
            show_line_numbers=True,
            soft_wrap=False,
            id=id,
        )
        self._pending: list[str] = []
        self._flush_scheduled = False

    def on_mount(self) -> None:
        # Set here, not in __init__, so a missing grammar degrades to plain text silently.
        if "python" in self.available_languages:
            self.language = "python"

    def append(self, text: str) -> None:
        """Adds ``text`` at the end (batched; visible within a few hundredths of a second)."""
        self._pending.append(text)
        if not self._flush_scheduled:
            self._flush_scheduled = True
            self.set_timer(_FLUSH_SECONDS, self.flush)

    def flush(self) -> None:
        """Appends the buffered text now and keeps the end in view."""
        self._flush_scheduled = False
        if not self._pending:
            return
        text, self._pending = "".join(self._pending), []
        self.insert(text, self.document.end, maintain_selection_offset=False)
        self.scroll_end(animate=False)

    def show(self, text: str) -> None:
        """Replaces the whole content (drops anything still buffered)."""
        self._pending = []
        self.load_text(text)

    def jump_to(self, line: int, column: int = 0) -> None:
        """Selects 1-based ``line`` and scrolls it into the middle of the view."""
        row = max(0, min(line - 1, self.document.line_count - 1))
        self.select_line(row)
        self.move_cursor((row, max(0, column - 1)), center=True)
        self.select_line(row)
