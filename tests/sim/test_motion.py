"""Helpers of the motion servers (the servers themselves are exercised in test_world)."""

from __future__ import annotations

import math

import pytest

from skillwright.sim.motion import duration, fill, from_duration, yaw_of


def test_fill_keeps_the_fields_a_type_has_and_drops_the_others() -> None:
    template = {"error_code": 0, "total_elapsed_time": {"sec": 0, "nanosec": 0}}
    filled = fill(
        template, {"error_code": 9000, "error_msg": "x", "total_elapsed_time": {"sec": 3}}
    )
    assert filled == {"error_code": 9000, "total_elapsed_time": {"sec": 3, "nanosec": 0}}
    assert template["error_code"] == 0


@pytest.mark.parametrize("seconds", [0.0, 1.5, 12.000000001, 59.999])
def test_durations_round_trip(seconds: float) -> None:
    assert from_duration(duration(seconds)) == pytest.approx(seconds, abs=1e-9)
    assert from_duration("bad") == 0.0


@pytest.mark.parametrize(
    ("orientation", "yaw"),
    [
        ({"x": 0.0, "y": 0.0, "z": math.sin(0.4), "w": math.cos(0.4)}, 0.8),
        ({"x": 0.0, "y": 0.0, "z": 0.0, "w": 0.0}, 0.0),
        (None, 0.0),
    ],
)
def test_the_yaw_of_a_quaternion(orientation: object, yaw: float) -> None:
    assert yaw_of(orientation) == pytest.approx(yaw)
