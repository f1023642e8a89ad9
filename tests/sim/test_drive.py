"""The base driver: mecanum kinematics, acceleration limits, wheel saturation."""

from __future__ import annotations

import math

import pytest

from skillwright.runtime.motion import Command
from skillwright.sim.drive import DriveLimits, DriverState, MecanumKinematics

KINEMATICS = MecanumKinematics(wheel_radius=0.05, half_length=0.24, half_width=0.235)
LIMITS = DriveLimits(wheel_speed_max=30.0, accel_linear=1.0, accel_lateral=1.0, accel_angular=2.0)


@pytest.mark.parametrize(
    "command",
    [
        Command(0.5, 0.0, 0.0),
        Command(0.0, -0.3, 0.0),
        Command(0.0, 0.0, 1.0),
        Command(0.2, 0.1, -0.4),
    ],
)
def test_wheel_speeds_and_forward_kinematics_are_inverse(command: Command) -> None:
    back = KINEMATICS.body_velocity(KINEMATICS.wheel_speeds(command))
    assert back.vx == pytest.approx(command.vx)
    assert back.vy == pytest.approx(command.vy)
    assert back.wz == pytest.approx(command.wz)


def test_driving_forward_turns_all_wheels_forward_and_strafing_turns_them_crosswise() -> None:
    assert all(w == pytest.approx(10.0) for w in KINEMATICS.wheel_speeds(Command(vx=0.5)))
    fl, fr, rl, rr = KINEMATICS.wheel_speeds(Command(vy=0.5))
    assert fl == rr == pytest.approx(-10.0)
    assert fr == rl == pytest.approx(10.0)


def test_acceleration_is_limited_per_period() -> None:
    driver = DriverState(KINEMATICS, LIMITS)
    driver.receive(Command(vx=0.8, wz=1.0), 0.0)
    driver.step(0.0, 0.1)
    assert driver.shaped.vx == pytest.approx(0.1)
    assert driver.shaped.wz == pytest.approx(0.2)
    for k in range(1, 20):
        driver.step(0.1 * k, 0.1)
    assert driver.shaped.vx == pytest.approx(0.8)


def test_saturated_wheels_keep_the_direction_of_motion() -> None:
    limits = DriveLimits(
        wheel_speed_max=10.0, accel_linear=100.0, accel_lateral=100.0, accel_angular=100.0
    )
    driver = DriverState(KINEMATICS, limits)
    driver.receive(Command(vx=1.0, vy=0.5), 0.0)
    wheels = driver.step(0.0, 1.0)
    assert max(abs(w) for w in wheels) == pytest.approx(10.0)
    body = KINEMATICS.body_velocity(wheels)
    assert body.vy / body.vx == pytest.approx(0.5)


def test_the_last_command_holds_without_a_timeout_and_lapses_with_one() -> None:
    holding = DriverState(KINEMATICS, LIMITS)
    holding.receive(Command(vx=0.3), 0.0)
    assert holding.target(100.0).vx == 0.3
    timed = DriverState(KINEMATICS, DriveLimits(30.0, 1.0, 1.0, 2.0, command_timeout=0.5))
    timed.receive(Command(vx=0.3), 0.0)
    assert timed.target(0.4).vx == 0.3
    assert timed.target(0.6).is_zero()


def test_a_command_with_nan_or_infinity_is_ignored() -> None:
    driver = DriverState(KINEMATICS, LIMITS)
    driver.receive(Command(vx=0.2), 0.0)
    driver.receive(Command(vx=math.nan), 1.0)
    driver.receive(Command(wz=math.inf), 2.0)
    assert driver.command == Command(vx=0.2)
