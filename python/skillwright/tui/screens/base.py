"""What every tab of the main screen has in common."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, cast

from textual.app import SystemCommand
from textual.containers import Vertical
from textual.widget import Widget

from skillwright.tui.messages import JobFailed

if TYPE_CHECKING:
    from skillwright.tui.app import SkillwrightApp

__all__ = ["Pane"]


class Pane(Vertical):
    """A tab's content: drives one part of the engine and reports back to the app."""

    job = "job"
    """Name of this pane's job in notifications."""
    primary = ""
    """Selector of the widget that gets the focus when the tab is shown."""

    @property
    def sw(self) -> SkillwrightApp:
        """The app, typed."""
        return cast("SkillwrightApp", self.app)

    def focus_primary(self) -> None:
        """Puts the focus on the tab's main widget, so the tab's keys work at once."""
        found = self.query(self.primary) if self.primary else None
        if found:
            self.focus_now(found.first())

    def focus_now(self, widget: Widget) -> None:
        """Focuses ``widget`` at once, where ``widget.focus()`` would do it a moment later.

        Callers decide from the tab shown now; a deferred focus could land after a tab key
        was read, and focusing a widget of a hidden tab switches back to that tab.
        """
        self.screen.set_focus(widget)

    def cancel_job(self) -> bool:
        """Cancels this pane's running job; False when none was running."""
        return False

    def commands(self) -> Iterable[SystemCommand]:
        """Command palette entries for this pane's actions."""
        return ()

    def fail(self, message: str, *, cancelled: bool = False) -> None:
        """Reports an engine error (thread-safe: posts a message)."""
        self.post_message(JobFailed(self.job, message, cancelled=cancelled))
