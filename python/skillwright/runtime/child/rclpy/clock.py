"""Stand-in of ``rclpy.clock``: every clock reads the run's virtual time."""

from __future__ import annotations

from _skillwright_child.core import core

from rclpy.clock_type import ClockType
from rclpy.duration import Duration
from rclpy.time import Time

__all__ = ["Clock", "ClockType", "ROSClock"]


class Clock:
    """A clock of the simulated graph; ROS, system and steady time all follow virtual time."""

    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        if not isinstance(clock_type, ClockType):
            raise TypeError("Clock type must be a ClockType enum")
        self._clock_type = clock_type

    @property
    def clock_type(self) -> ClockType:
        return self._clock_type

    def now(self) -> Time:
        return Time(nanoseconds=core().ros_time_ns(), clock_type=self._clock_type)

    def sleep_for(self, rel_time: Duration, context: object = None) -> bool:
        if not isinstance(rel_time, Duration):
            raise TypeError("rel_time must be a Duration")
        return self.sleep_until(self.now() + rel_time)

    def sleep_until(self, until: Time, context: object = None) -> bool:
        if not isinstance(until, Time):
            raise TypeError("until must be a Time")
        c = core()
        target = (until.nanoseconds - c.epoch_ns) / 1e9
        c.block(max(target, c.now), None, "sleep")
        return True

    def __repr__(self) -> str:
        return f"Clock(clock_type={self._clock_type.name})"


class ROSClock(Clock):
    """The ROS time clock."""

    def __init__(self) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)

    @property
    def ros_time_is_active(self) -> bool:
        return False
