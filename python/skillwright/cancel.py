"""Stopping long engine calls from another thread.

A thread cannot be stopped from outside, so the engine calls a user may wait on (reading a
capability, loading interfaces, ranking them, generating) take a ``cancel`` event and look
at it at their natural steps: between files, between interfaces, before and after loading a
model, between ranking phases. Once the event is set, the call raises
:class:`~skillwright.errors.OperationCancelledError` at its next step instead of running on
to produce a result nobody will read. The TUI sets the event when the user presses Esc,
starts the same job again or quits; the headless commands pass none.
"""

from __future__ import annotations

import threading

from skillwright.errors import OperationCancelledError

__all__ = ["raise_if_cancelled"]


def raise_if_cancelled(cancel: threading.Event | None, what: str) -> None:
    """Raises :class:`OperationCancelledError` (``"<what> cancelled"``) once ``cancel`` is set."""
    if cancel is not None and cancel.is_set():
        raise OperationCancelledError(f"{what} cancelled")
