"""Tabbed content whose tab follows the focus only while that focus still holds."""

from __future__ import annotations

from textual.widgets import TabbedContent, TabPane

__all__ = ["FocusTabs"]


class FocusTabs(TabbedContent):
    """A :class:`TabbedContent` that a late focus message cannot switch back.

    Textual shows the tab of a widget that gets the focus, by a message the tab pane posts
    after the fact. When the user switches tabs quickly on a busy machine (F2 then F4 while a
    worker streams), the message for the first tab's widget can arrive after the second tab
    was shown, and it switched back to the first tab: the second key looked ignored. Here a
    pane's message only switches tabs while the focus is still inside that pane.
    """

    def on_tab_pane_focused(self, event: TabPane.Focused) -> None:
        focused = self.screen.focused
        if focused is None or event.tab_pane not in focused.ancestors:
            event.prevent_default()
            event.stop()
