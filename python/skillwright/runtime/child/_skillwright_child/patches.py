"""Virtual time for everything in the child that reads or waits on the clock.

``time.sleep/time/monotonic/perf_counter`` (and their ``_ns`` forms), ``datetime.now``,
``threading.Event.wait`` and ``threading.Timer`` follow the run's virtual clock, so a
skill written against wall time runs in lockstep with the simulation. The threading
module's own internal waits (a thread starting, a lock) keep real time.
"""

from __future__ import annotations

import datetime as _datetime
import sys
import threading
import time

from _skillwright_child.core import Core

_MONOTONIC_BASE = 1000.0


def install(core: Core) -> None:
    """Replaces the clock functions of ``time``, ``datetime`` and ``threading``."""
    epoch = core.epoch_ns / 1e9

    def monotonic() -> float:
        return _MONOTONIC_BASE + core.now

    def monotonic_ns() -> int:
        return round((_MONOTONIC_BASE + core.now) * 1e9)

    def wall() -> float:
        return epoch + core.now

    def wall_ns() -> int:
        return core.epoch_ns + round(core.now * 1e9)

    time.sleep = core.sleep
    time.monotonic = monotonic
    time.monotonic_ns = monotonic_ns
    time.perf_counter = monotonic
    time.perf_counter_ns = monotonic_ns
    time.time = wall
    time.time_ns = wall_ns

    class VirtualDatetime(_datetime.datetime):
        """``datetime`` whose ``now``, ``today`` and ``utcnow`` read virtual time."""

        @classmethod
        def now(cls, tz: _datetime.tzinfo | None = None) -> VirtualDatetime:  # type: ignore[override]
            return cls.fromtimestamp(wall(), tz)

        @classmethod
        def today(cls) -> VirtualDatetime:  # type: ignore[override]
            return cls.fromtimestamp(wall())

        @classmethod
        def utcnow(cls) -> VirtualDatetime:  # type: ignore[override]
            return cls.fromtimestamp(wall(), _datetime.UTC).replace(tzinfo=None)

    VirtualDatetime.__name__ = "datetime"
    VirtualDatetime.__qualname__ = "datetime"
    VirtualDatetime.__module__ = "datetime"
    _datetime.datetime = VirtualDatetime  # type: ignore[misc]

    real_wait = threading.Event.wait
    timer_run = threading.Timer.run.__code__
    threading_file = threading.__file__

    def wait(self: threading.Event, timeout: float | None = None) -> bool:
        caller = sys._getframe(1).f_code
        if caller.co_filename == threading_file and caller is not timer_run:
            return real_wait(self, timeout)
        until = None if timeout is None else core.now + max(0.0, float(timeout))
        return core.block(until, self.is_set, "event wait")

    threading.Event.wait = wait  # type: ignore[method-assign]
