"""Stopping long engine calls from another thread, and keeping Ctrl-C out of short steps.

A thread cannot be stopped from outside, so the engine calls a user may wait on (reading a
capability, loading interfaces, ranking them, generating) take a ``cancel`` event and look
at it at their natural steps: between files, between interfaces, before and after loading a
model, between ranking phases. Once the event is set, the call raises
:class:`~skillwright.errors.OperationCancelledError` at its next step instead of running on
to produce a result nobody will read. The TUI sets the event when the user presses Esc,
starts the same job again or quits; the headless commands pass none.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

from skillwright.errors import OperationCancelledError

__all__ = ["interrupts_held", "raise_if_cancelled"]


def raise_if_cancelled(cancel: threading.Event | None, what: str) -> None:
    """Raises :class:`OperationCancelledError` (``"<what> cancelled"``) once ``cancel`` is set."""
    if cancel is not None and cancel.is_set():
        raise OperationCancelledError(f"{what} cancelled")


@contextmanager
def interrupts_held() -> Iterator[None]:
    """Holds Ctrl-C (SIGINT) back while the block runs and delivers it when the block is done.

    For short steps that must not stop half-way, such as moving a result's files into place:
    an interrupt there would leave some files new and some old. When the block raises, a
    held interrupt is dropped (the block's error says what happened). Python delivers
    signals to the main thread only, so in any other thread this does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum: int, _frame: FrameType | None) -> None:
        held.append(signum)

    previous = signal.signal(signal.SIGINT, hold)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if held:
        if callable(previous):
            previous(signal.SIGINT, None)
        elif previous == signal.SIG_DFL:
            signal.raise_signal(signal.SIGINT)
