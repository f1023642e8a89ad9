"""Ground truth: what really happened in the simulated world, for the oracles and the plot.

The world appends to a :class:`GroundTruth` as it steps: the base's true pose and velocity
after every physics step, every velocity command the skill published, contacts of the
chassis with anything, motion goals and their outcome, the nearest obstacle the lidar
would see without noise, the mapped extent and the maps saved. Queries read it back by
virtual time.
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from skillwright.runtime.motion import wrap_pi

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = [
    "CommandRecord",
    "ContactRecord",
    "GroundTruth",
    "Sample",
    "Sweep",
    "wrap_two_pi",
]


def wrap_two_pi(angle: float) -> float:
    """``angle`` in [0, 2*pi)."""
    return angle % (2 * math.pi)


@dataclass(frozen=True)
class Sample:
    """The base after one physics step (map frame; velocities in the base's own frame)."""

    t: float
    x: float
    y: float
    yaw: float
    vx: float
    vy: float
    wz: float
    command: tuple[float, float, float]
    """The velocity command the driver held at that moment."""
    tcp: tuple[float, float, float]
    """The arm's tool centre point in its base frame."""

    @property
    def speed(self) -> float:
        """Translational speed [m/s]."""
        return math.hypot(self.vx, self.vy)


@dataclass(frozen=True)
class CommandRecord:
    """A velocity command the skill published."""

    t: float
    topic: str
    vx: float
    vy: float
    wz: float


@dataclass(frozen=True)
class ContactRecord:
    """The chassis touching something: when it started and with what."""

    t: float
    geom: str
    x: float
    y: float


@dataclass(frozen=True)
class Sweep:
    """One lidar scan as the world measured it, without noise."""

    t: float
    angle_min: float
    angle_increment: float
    ranges: Sequence[float] | NDArray[np.float64]
    """Per beam; ``inf`` where the beam returns nothing."""

    def toward(self, bearing: float) -> float | None:
        """The range of the beam closest to ``bearing`` (lidar frame, radians), or ``None``
        when the lidar does not look that way."""
        count = len(self.ranges)
        if not count or self.angle_increment <= 0:
            return None
        index = round(wrap_two_pi(bearing - self.angle_min) / self.angle_increment)
        if count * self.angle_increment >= 2 * math.pi - 1e-6:
            index %= count  # a whole turn: past the last beam comes the first
        elif index >= count:
            return None
        return float(self.ranges[index])


@dataclass
class GroundTruth:
    """Everything the world recorded during one run."""

    samples: list[Sample] = field(default_factory=list)
    commands: list[CommandRecord] = field(default_factory=list)
    drive: list[tuple[float, float, float, float, str]] = field(default_factory=list)
    """Every command the base driver received: (t, vx, vy, wz, from ``skill`` or ``world``)."""
    contacts: list[ContactRecord] = field(default_factory=list)
    goals: list[dict[str, Any]] = field(default_factory=list)
    """Motion goals served: action, time accepted, outcome, time finished, target."""
    nearest: list[tuple[float, float, float]] = field(default_factory=list)
    """(t, distance, bearing) of the nearest lidar return without noise, per scan."""
    sweeps: list[Sweep] = field(default_factory=list)
    """The ranges without noise of every scan, in the order of :attr:`nearest`."""
    extents: list[tuple[float, float, float]] = field(default_factory=list)
    """(t, along, across): extent of the mapped area relative to the start pose."""
    saved_maps: list[dict[str, Any]] = field(default_factory=list)
    """Maps written through a map-saver service: the url asked for and the files written."""
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """The start pose (x, y, heading) in the map frame."""
    braking: float = 1.0
    """The base driver's deceleration [m/s^2]."""
    reaction: float = 0.1
    """The lidar's scan period [s]: how late a skill can know of an obstacle."""
    localised: bool = True
    """Whether the robot can know where it is in the map frame: something publishes a pose
    or a map (``map -> odom``). Without it a skill knows its pose only in the odometry
    frame, which starts at :attr:`start`."""
    noise: dict[str, float] = field(default_factory=dict)
    """Standard deviations of the sensors' noise the world drew (``scan`` [m],
    ``odometry_linear`` [m/s], ``odometry_angular`` [rad/s], ``localisation`` [m])."""
    odometry_period: float = 0.02
    """How often the odometry integrates its wheel speeds [s]."""
    map_savers: list[str] = field(default_factory=list)
    """The robot's map-saving services the world serves (none: it cannot save a map)."""
    catch_up: Callable[[], None] | None = field(default=None, repr=False, compare=False)
    """Brings :attr:`extents` up to date (the world traces its map only when asked)."""
    _times: list[float] = field(default_factory=list, repr=False)

    def add(self, sample: Sample) -> None:
        """Record one sample (in time order)."""
        self.samples.append(sample)
        self._times.append(sample.t)

    def at(self, t: float) -> Sample:
        """The last sample at or before ``t`` (the first one before the run began)."""
        if not self.samples:
            raise ValueError("no ground truth was recorded (the world never stepped)")
        index = bisect.bisect_right(self._times, t + 1e-9) - 1
        return self.samples[max(index, 0)]

    def between(self, t0: float, t1: float) -> list[Sample]:
        """Samples with ``t0 <= t <= t1``."""
        lo = bisect.bisect_left(self._times, t0 - 1e-9)
        hi = bisect.bisect_right(self._times, t1 + 1e-9)
        return self.samples[lo:hi]

    @property
    def end(self) -> float:
        """Time of the last sample."""
        return self._times[-1] if self._times else 0.0

    def settled(
        self, t0: float, t1: float, linear: float, angular: float, hold: float = 0.1
    ) -> float | None:
        """The first time in ``[t0, t1]`` from which the base stays slower than ``linear``
        [m/s] and ``angular`` [rad/s] for ``hold`` seconds (or until the record ends);
        ``None`` when it never comes to rest in that time."""
        candidate: float | None = None
        for sample in self.between(t0, t1):
            still = sample.speed < linear and abs(sample.wz) < angular
            if not still:
                candidate = None
                continue
            if candidate is None:
                candidate = sample.t
            if sample.t - candidate >= hold - 1e-9:
                return candidate
        return candidate

    def in_odometry_frame(self, sample: Sample) -> tuple[float, float, float]:
        """``sample``'s true pose in the odometry frame (which starts at :attr:`start`):
        the pose a robot without localisation can know, less its odometry's drift."""
        sx, sy, syaw = self.start
        c, s = math.cos(syaw), math.sin(syaw)
        dx, dy = sample.x - sx, sample.y - sy
        return (c * dx + s * dy, -s * dx + c * dy, sample.yaw - syaw)

    def displacement(self, t0: float, t1: float) -> float:
        """Straight-line distance of the base between two times [m]."""
        a, b = self.at(t0), self.at(t1)
        return math.hypot(b.x - a.x, b.y - a.y)

    def travelled(self, t0: float, t1: float) -> float:
        """Distance moved between two times along the heading at ``t0`` (negative: backwards)."""
        a, b = self.at(t0), self.at(t1)
        return (b.x - a.x) * math.cos(a.yaw) + (b.y - a.y) * math.sin(a.yaw)

    def turned(self, t0: float, t1: float) -> float:
        """How far the base turned between two times, counter-clockwise positive, not
        wrapped: three quarters of a turn clockwise is -4.71, not +1.57 [rad]."""
        samples = self.between(t0, t1)
        return sum(wrap_pi(b.yaw - a.yaw) for a, b in itertools.pairwise(samples))

    def path_length(self, t0: float, t1: float) -> float:
        """Length of the path the base drove between two times [m]."""
        samples = self.between(t0, t1)
        return sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in itertools.pairwise(samples))

    def skill_command_at(self, t: float) -> CommandRecord | None:
        """The last command the skill published at or before ``t``."""
        found = None
        for command in self.commands:
            if command.t > t + 1e-9:
                break
            found = command
        return found

    def stop_commanded(self, t0: float, t1: float) -> float | None:
        """When the skill last told the base to stop between two times: its last zero
        velocity command after a non-zero one (``None``: it commanded no stop then)."""
        found = None
        moving = False
        for command in self.commands:
            if command.t < t0 - 1e-9 or command.t > t1 + 1e-9:
                continue
            zero = abs(command.vx) < 1e-6 and abs(command.vy) < 1e-6 and abs(command.wz) < 1e-6
            if zero and moving:
                found = command.t
            moving = not zero
        return found

    def command_duration(self, t0: float, t1: float) -> float:
        """How long the skill's commands kept the base moving between two times [s]:
        from its first non-zero command to the zero command that followed (or ``t1``)."""
        started: float | None = None
        total = 0.0
        for command in self.commands:
            if command.t < t0 - 1e-9 or command.t > t1 + 1e-9:
                continue
            moving = not (
                abs(command.vx) < 1e-6 and abs(command.vy) < 1e-6 and abs(command.wz) < 1e-6
            )
            if moving and started is None:
                started = command.t
            elif not moving and started is not None:
                total += command.t - started
                started = None
        if started is not None:
            total += t1 - started
        return total

    def nearest_at(self, t: float) -> tuple[float, float] | None:
        """Distance and bearing of the nearest return of the last scan at or before ``t``."""
        found = None
        for when, distance, bearing in self.nearest:
            if when > t + 1e-9:
                break
            found = (distance, bearing)
        return found

    def range_toward(self, t: float, bearing: float) -> float | None:
        """The range without noise along ``bearing`` (lidar frame, radians) in the last scan
        at or before ``t`` that looks that way; ``None`` before the first scan or outside
        every scan's view. A robot with several scanners (corner scanners, each seeing its
        own side) publishes one ``LaserScan`` per scanner, and the nearest return of its view
        (:meth:`nearest_at`) may lie in another scanner's scan than the last one."""
        found = None
        for sweep in self.sweeps:
            if sweep.t > t + 1e-9:
                break
            toward = sweep.toward(bearing)
            if toward is not None:
                found = toward
        return found

    def clearance(self, t0: float, t1: float) -> tuple[float, float] | None:
        """The smallest nearest-obstacle range of the scans between two times, and when."""
        seen = [(d, t) for t, d, _ in self.nearest if t0 - 1e-9 <= t <= t1 + 1e-9]
        return min(seen) if seen else None

    def first_closer(self, t0: float, t1: float, distance: float) -> float | None:
        """When a scan between two times first saw something nearer than ``distance``."""
        for t, d, _ in self.nearest:
            if t0 - 1e-9 <= t <= t1 + 1e-9 and d < distance:
                return t
        return None

    def extent_at(self, t: float) -> tuple[float, float] | None:
        """Mapped extent (along, across the start heading) at or before ``t``."""
        if self.catch_up is not None:
            self.catch_up()
        found = None
        for when, along, across in self.extents:
            if when > t + 1e-9:
                break
            found = (along, across)
        return found

    def command_in_force(self, t: float) -> tuple[float, float, float, float, str] | None:
        """The last command the driver received at or before ``t`` (``None``: none yet)."""
        found = None
        for entry in self.drive:
            if entry[0] > t + 1e-9:
                break
            found = entry
        return found

    def goals_active_at(self, t: float) -> list[str]:
        """Actions whose goals the world was still executing at ``t``."""
        finished: dict[tuple[str, float], float] = {}
        for goal in self.goals:
            if goal.get("outcome") != "executing" and goal.get("finished") is not None:
                finished[(str(goal["action"]), float(goal["accepted"]))] = float(goal["finished"])
        active = set()
        for goal in self.goals:
            if goal.get("outcome") != "executing" or float(goal["accepted"]) > t + 1e-9:
                continue
            end = finished.get((str(goal["action"]), float(goal["accepted"])))
            if end is None or end > t + 1e-9:
                active.add(str(goal["action"]))
        return sorted(active)
