"""The skeleton's helpers as real methods: what they do, the text the skeleton copies and
the signatures the checks read."""

from __future__ import annotations

import math
import threading
import time
from types import SimpleNamespace

import pytest

from skillwright.generation.helpers import (
    SkeletonHelpers,
    helper_lines,
    helper_names,
    helper_signature,
)


class _Done:
    def __init__(self, result: object) -> None:
        self._result = result

    def done(self) -> bool:
        return True

    def result(self) -> object:
        return self._result


def _scan(ranges: list[float]) -> SimpleNamespace:
    return SimpleNamespace(
        ranges=ranges, range_min=0.1, range_max=10.0, angle_min=-1.0, angle_increment=0.5
    )


def test_wait_until_returns_once_the_condition_holds_and_raises_naming_what_it_waited_for() -> None:
    helpers = SkeletonHelpers()
    ticks = iter([False, False, True])
    helpers._wait_until(lambda: next(ticks), 1.0, "odometry")
    with pytest.raises(RuntimeError, match=r"no odometry within 0\.05 s"):
        helpers._wait_until(lambda: False, 0.05, "odometry")


def test_result_of_gives_the_futures_result() -> None:
    assert SkeletonHelpers()._result_of(_Done(7), 1.0, "the response") == 7


def test_the_closest_reading_skips_invalid_ones_and_has_the_bearing_of_its_index() -> None:
    helpers = SkeletonHelpers()
    near = _scan([math.nan, 0.05, 3.0, 2.0, math.inf])
    assert helpers._closest_reading(near) == (2.0, 0.5)
    assert helpers._closest_reading(_scan([math.inf]), near) == (2.0, 0.5)
    assert helpers._closest_reading(_scan([])) == (math.inf, 0.0)


@pytest.mark.parametrize("yaw", [0.0, 0.5, -2.0, math.pi])
def test_yaw_is_the_heading_of_a_quaternion(yaw: float) -> None:
    q = SimpleNamespace(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    assert SkeletonHelpers()._yaw(q) == pytest.approx(yaw)


def test_stop_base_commands_every_velocity_publisher_to_stand_still() -> None:
    assert helper_lines(
        "_stop_base",
        repeated=[
            {"velocity_publisher": "cmd_vel_publisher", "Velocity": "Twist"},
            {"velocity_publisher": "base_publisher", "Velocity": "TwistStamped"},
        ],
    )[2:] == [
        "        if self.cmd_vel_publisher is not None:",
        "            self.cmd_vel_publisher.publish(Twist())",
        "        if self.base_publisher is not None:",
        "            self.base_publisher.publish(TwistStamped())",
    ]


def test_the_copy_leaves_out_the_annotations_the_skill_has_no_names_for() -> None:
    assert helper_lines("_wait_until")[0] == (
        "    def _wait_until(self, condition, timeout: float, what: str) -> None:"
    )
    assert helper_lines("_result_of")[0] == (
        "    def _result_of(self, future, timeout: float, what: str):"
    )
    assert helper_lines("_closest_reading")[0] == (
        "    def _closest_reading(self, *scans) -> tuple[float, float]:"
    )


def test_an_actions_helpers_are_named_after_it_and_only_moveit_checks_an_error_code() -> None:
    names = {"stem": "backup", "Action": "BackUp", "/action": "/backup"}
    result = helper_lines("_stem_result", names)
    assert result[0] == '    def _backup_result(self, timeout: float) -> "BackUp.Result":'
    assert "self._send_backup_goal" in result[1]
    assert not any("MoveItErrorCodes" in line for line in result)
    assert any(
        "MoveItErrorCodes" in line for line in helper_lines("_stem_result", names, moveit=True)
    )
    assert 'raise RuntimeError("/backup rejected the goal")' in "\n".join(
        helper_lines("_send_stem_goal", names)
    )


@pytest.mark.parametrize(
    ("name", "parameters"),
    [
        ("_wait_until", ["condition", "timeout", "what"]),
        ("_transform", ["target_frame", "source_frame", "timeout"]),
        ("_pose_goal", ["frame", "x", "y", "yaw"]),
        ("_send_navigate_to_pose_goal", ["goal", "timeout"]),
        ("_navigate_to_pose_result", ["timeout"]),
        ("_cancel_move_action_goal", ["timeout"]),
        ("_closest_reading", ["scans"]),
    ],
)
def test_a_helpers_signature_is_read_from_its_method(name: str, parameters: list[str]) -> None:
    assert list(helper_signature(name).parameters) == parameters


def test_a_name_no_helper_has_is_a_lookup_error() -> None:
    assert "_send_stem_goal" in helper_names()
    with pytest.raises(LookupError, match="no helper _travelled"):
        helper_signature("_travelled")


def _odometry(linear_x: float, angular_z: float) -> SimpleNamespace:
    twist = SimpleNamespace(
        linear=SimpleNamespace(x=linear_x, y=0.0, z=0.0),
        angular=SimpleNamespace(x=0.0, y=0.0, z=angular_z),
    )
    return SimpleNamespace(twist=SimpleNamespace(twist=twist))


def test_settle_base_commands_zero_and_returns_once_odometry_shows_rest() -> None:
    helpers = SkeletonHelpers()
    stops: list[int] = []
    helpers._stop_base = lambda: stops.append(1)  # type: ignore[method-assign]
    helpers.odometry_msg = _odometry(0.3, 0.0)
    timer = threading.Timer(0.1, lambda: setattr(helpers, "odometry_msg", _odometry(0.004, 0.01)))
    timer.start()
    started = time.monotonic()
    helpers._settle_base(2.0)
    assert time.monotonic() - started >= 0.09
    assert stops == [1]
    timer.join()


@pytest.mark.parametrize("moving", [_odometry(0.02, 0.0), _odometry(0.0, -0.05), None])
def test_settle_base_raises_naming_the_odometry_when_the_base_never_rests(
    moving: SimpleNamespace | None,
) -> None:
    helpers = SkeletonHelpers()
    helpers._stop_base = lambda: None  # type: ignore[method-assign]
    helpers.odometry_msg = moving
    with pytest.raises(RuntimeError, match=r"no rest of the base on /odometry within 0\.05 s"):
        helpers._settle_base(0.05)


def test_the_settle_helper_is_named_after_the_odometry_it_reads() -> None:
    lines = helper_lines("_settle_base", {"odometry_msg": "odom_msg", "/odometry": "/odom"})
    text = "\n".join(lines)
    assert "self.odom_msg.twist.twist" in text
    assert '"rest of the base on /odom"' in text
    assert "odometry_msg" not in text
