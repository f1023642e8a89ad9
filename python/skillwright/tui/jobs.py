"""An engine call running in a worker thread, and the switch that stops it.

Cancelling a Textual thread worker only marks it: the thread runs on until the engine call
returns. Each job therefore hands the engine a :class:`threading.Event` that the engine
looks at between its steps (see :mod:`skillwright.cancel`); stopping the job sets it, so
the call ends at its next step instead of finishing work nobody will see.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from textual.worker import Worker, WorkerState

__all__ = ["EngineJob"]


class EngineJob:
    """One kind of engine call of a pane (reading a capability, ranking, ...); at most one
    runs at a time."""

    def __init__(self) -> None:
        self.worker: Worker[None] | None = None
        """The worker of the latest call, running or done."""
        self.cancel = threading.Event()
        """The switch the latest call's engine looks at."""

    @property
    def running(self) -> bool:
        """True while the latest call has not finished."""
        return _unfinished(self.worker)

    def start(self, run: Callable[[threading.Event], Worker[None]]) -> None:
        """Stops the call in progress, if any, and starts ``run`` with a fresh switch."""
        self.stop()
        self.cancel = threading.Event()
        self.worker = run(self.cancel)

    def stop(self) -> bool:
        """Sets the switch and cancels the worker; False when nothing was running."""
        worker = self.worker
        if worker is None or not _unfinished(worker):
            return False
        self.cancel.set()
        worker.cancel()
        return True


def _unfinished(worker: Worker[None] | None) -> bool:
    return worker is not None and worker.state in (WorkerState.PENDING, WorkerState.RUNNING)
