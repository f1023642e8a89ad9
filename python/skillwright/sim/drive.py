"""The MR-1's base driver: velocity commands to wheel speeds, as its motor controllers see them.

A command (body-frame ``vx``, ``vy``, ``wz``) is shaped as a base driver shapes it: the
change per control period is limited by the acceleration limits, then turned into the four
wheel speeds of a mecanum drive and scaled down together when one wheel would exceed its
speed limit (so the direction of motion is kept). The resulting wheel speeds are what the
wheel servos of the MuJoCo model are told; odometry integrates the speeds the wheels
actually turn at, through the forward kinematics here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from skillwright.runtime.motion import Command

__all__ = ["DriveLimits", "DriverState", "MecanumKinematics"]


@dataclass(frozen=True)
class MecanumKinematics:
    """Four mecanum wheels (front left, front right, rear left, rear right) with rollers at
    45 degrees, at ``(+-half_length, +-half_width)`` from the base's centre."""

    wheel_radius: float
    half_length: float
    half_width: float

    def wheel_speeds(self, command: Command) -> tuple[float, float, float, float]:
        """Wheel angular speeds [rad/s] that move the base at ``command``."""
        k = self.half_length + self.half_width
        r = self.wheel_radius
        vx, vy, wz = command.vx, command.vy, command.wz
        return (
            (vx - vy - k * wz) / r,
            (vx + vy + k * wz) / r,
            (vx + vy - k * wz) / r,
            (vx - vy + k * wz) / r,
        )

    def body_velocity(self, wheels: tuple[float, float, float, float]) -> Command:
        """The base velocity the four wheel speeds produce when they do not slip."""
        fl, fr, rl, rr = wheels
        r = self.wheel_radius
        k = self.half_length + self.half_width
        return Command(
            vx=r * (fl + fr + rl + rr) / 4.0,
            vy=r * (-fl + fr + rl - rr) / 4.0,
            wz=r * (-fl + fr - rl + rr) / (4.0 * k),
        )


@dataclass(frozen=True)
class DriveLimits:
    """What the drive hardware allows (not the capability's requirements, which are
    checked by the oracles)."""

    wheel_speed_max: float
    """Largest wheel speed the motor controllers command [rad/s]."""
    accel_linear: float
    """Largest change of vx and vy per second [m/s^2]."""
    accel_lateral: float
    """Largest change of vy per second [m/s^2]."""
    accel_angular: float
    """Largest change of the yaw rate per second [rad/s^2]."""
    command_timeout: float = 0.0
    """Seconds without a command after which the driver stops the base; 0 holds the last one."""


def _towards(current: float, target: float, step: float) -> float:
    if target > current:
        return min(target, current + step)
    return max(target, current - step)


@dataclass
class DriverState:
    """The base driver between control periods: the command in force and the shaped one."""

    kinematics: MecanumKinematics
    limits: DriveLimits
    command: Command = field(default_factory=Command)
    """The latest command received (from the skill or the navigation controller)."""
    command_time: float = 0.0
    """Virtual time the latest command arrived."""
    shaped: Command = field(default_factory=Command)
    """The acceleration-limited command the wheels follow now."""

    def receive(self, command: Command, time: float) -> None:
        """A new velocity command arrived at ``time``."""
        if not all(math.isfinite(v) for v in (command.vx, command.vy, command.wz)):
            # A driver ignores NaN and infinite commands rather than spinning the wheels.
            return
        self.command = command
        self.command_time = time

    def target(self, now: float) -> Command:
        """The command in force at ``now`` (zero once a timeout has passed)."""
        timeout = self.limits.command_timeout
        if timeout > 0.0 and now - self.command_time > timeout:
            return Command()
        return self.command

    def step(self, now: float, dt: float) -> tuple[float, float, float, float]:
        """Advance the shaping by ``dt`` and return the wheel speeds to command."""
        target = self.target(now)
        self.shaped = Command(
            vx=_towards(self.shaped.vx, target.vx, self.limits.accel_linear * dt),
            vy=_towards(self.shaped.vy, target.vy, self.limits.accel_lateral * dt),
            wz=_towards(self.shaped.wz, target.wz, self.limits.accel_angular * dt),
        )
        wheels = self.kinematics.wheel_speeds(self.shaped)
        largest = max(abs(w) for w in wheels)
        if largest > self.limits.wheel_speed_max:
            scale = self.limits.wheel_speed_max / largest
            fl, fr, rl, rr = (w * scale for w in wheels)
            return (fl, fr, rl, rr)
        return wheels
