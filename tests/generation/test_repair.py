"""Stage 7, repair: what the model is told of the findings of its answers."""

from __future__ import annotations

from skillwright.generation.repair import _helper_hint
from skillwright.rules.behaviour import MIXED_ANGLE_UNITS
from skillwright.rules.capability import OUTPUT_CONSTANT
from skillwright.rules.interfaces import ARGUMENT_TYPE_MISMATCH


def test_an_output_finding_that_says_to_read_a_scan_by_hand_names_the_helper() -> None:
    finding = OUTPUT_CONSTANT.finding(
        line=1,
        message="output outObstacleAngle is only ever set to 0.0: ...; the skill can read it "
        "from self.scan_msg.angle_min + i * self.scan_msg.angle_increment (the direction of "
        "range i, in radians)",
        data={
            "output": "outObstacleAngle",
            "attribute": "out_obstacle_angle",
            "scans": ["scan_msg"],
        },
    )
    assert _helper_hint(finding, ["_wait_until", "_closest_reading"]) == (
        "; self._closest_reading(self.scan_msg) returns (distance, bearing) of the nearest "
        "valid reading"
    )
    assert _helper_hint(finding, ["_wait_until"]) == ""
    other = finding.model_copy(update={"code": MIXED_ANGLE_UNITS.code, "check": "units"})
    assert _helper_hint(other, ["_closest_reading"]) == ""


def test_a_navigation_goal_of_the_wrong_type_is_told_the_goal_helper() -> None:
    finding = ARGUMENT_TYPE_MISMATCH.finding(
        line=1,
        message="self._send_navigate_to_pose_goal takes a nav2_msgs/action/NavigateToPose.Goal, "
        "not a geometry_msgs/msg/Pose",
        data={
            "call": "self._send_navigate_to_pose_goal",
            "expected": "nav2_msgs/action/NavigateToPose.Goal",
            "given": "geometry_msgs/msg/Pose",
        },
    )
    assert _helper_hint(finding, ["_pose_goal", "_result_of"]) == (
        "; self._pose_goal(frame, x, y, yaw) returns one for a point and a heading"
    )
    assert _helper_hint(finding, ["_result_of"]) == ""
    other = finding.model_copy(
        update={
            "message": "self.pub.publish takes a geometry_msgs/msg/Twist, not a Pose",
            "data": {"expected": "geometry_msgs/msg/Twist", "given": "geometry_msgs/msg/Pose"},
        }
    )
    assert _helper_hint(other, ["_pose_goal"]) == ""
