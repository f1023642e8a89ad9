"""The skeleton's helpers as real methods: what they do, the text the skeleton copies and
the signatures the checks read."""

from __future__ import annotations

import math
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
