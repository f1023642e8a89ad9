"""Tabbed content whose tab follows the focus only while that focus is newer than the tab."""

from __future__ import annotations

from textual.widgets import TabbedContent, TabPane

__all__ = ["FocusTabs"]


class FocusTabs(TabbedContent):
    """A :class:`TabbedContent` that a late focus message cannot switch back.

    Textual shows the tab of a widget that gets the focus, by a message the tab pane posts
    after the fact. When the user switches tabs quickly on a busy machine (F2 then F4 while a
    worker streams, or F4 while the start-up focus is on its way), the message for the first
    tab's widget can arrive after the second tab was shown, and it switched back to the first
    tab: the key looked ignored. Here a pane's message only switches tabs while the focus is
    still inside that pane and was put there after the last tab switch: a widget focused
    while its tab was shown does not pull that tab back once the user has left it.
    """

    _events = 0
    """Tab switches and focus moves so far, counted together to order them."""
    _switched_at = 0
    _focused_at = 0

    def on_mount(self) -> None:
        self.watch(self.screen, "focused", self._focus_moved, init=False)

    def watch_active(self) -> None:
        self._events += 1
        self._switched_at = self._events

    def _focus_moved(self) -> None:
        self._events += 1
        self._focused_at = self._events

    def on_tab_pane_focused(self, event: TabPane.Focused) -> None:
        focused = self.screen.focused
        if (
            focused is None
            or event.tab_pane not in focused.ancestors
            or self._focused_at < self._switched_at
        ):
            event.prevent_default()
            event.stop()
