"""Stand-in of ``rclpy.timer``: timers and rates in virtual time."""

from __future__ import annotations

from _skillwright_child.core import core

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable


class Timer:
    """Calls ``callback`` every ``timer_period_ns`` of virtual time on the executor."""

    def __init__(
        self, callback: Callable[[], object] | None, period_sec: float, autostart: bool = True
    ) -> None:
        if period_sec <= 0:
            raise ValueError(f"timer period must be positive, got {period_sec}")
        c = core()
        self.callback = callback
        self._period = float(period_sec)
        self._canceled = not autostart
        self._last = c.now
        self._next_due = c.now + self._period
        self._id = c.new_id()
        c.timers[self._id] = self

    @property
    def _active(self) -> bool:
        return not self._canceled and self._id in core().timers

    @property
    def timer_period_ns(self) -> int:
        return round(self._period * 1e9)

    def _fire(self) -> None:
        c = core()
        while self._next_due <= c.now:
            self._next_due += self._period
        self._last = c.now
        c.dispatched += 1
        if self.callback is not None:
            self.callback()

    def cancel(self) -> None:
        self._canceled = True

    def is_canceled(self) -> bool:
        return self._canceled

    def reset(self) -> None:
        c = core()
        self._canceled = False
        self._next_due = c.now + self._period

    def is_ready(self) -> bool:
        return self._active and self._next_due <= core().now

    def time_until_next_call(self) -> int | None:
        if self._canceled:
            return None
        return max(0, round((self._next_due - core().now) * 1e9))

    def time_since_last_call(self) -> int:
        return round((core().now - self._last) * 1e9)

    def destroy(self) -> None:
        core().timers.pop(self._id, None)


class Rate:
    """Sleeps so that a loop runs at ``frequency`` Hz of virtual time."""

    def __init__(self, frequency: float) -> None:
        if frequency <= 0:
            raise ValueError("frequency must be > 0")
        self._period = 1.0 / float(frequency)
        self._next = core().now + self._period
        self._destroyed = False

    def sleep(self) -> None:
        if self._destroyed:
            raise RuntimeError("Rate was destroyed")
        c = core()
        while self._next <= c.now:
            self._next += self._period
        c.block(self._next, None, "rate")

    def destroy(self) -> None:
        self._destroyed = True
