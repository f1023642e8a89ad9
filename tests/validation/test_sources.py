"""Where a skill can read the quantity an output reports."""

from __future__ import annotations

import textwrap

import pytest

from skillwright.validation.sources import measuring_sources
from tests.validation.test_facts import facts_of

SKILL = textwrap.dedent(
    """
    class Skill:
        def __init__(self) -> None:
            self.cmd_vel_publisher = None
            self.odom_msg: Odometry | None = None
            self.scan_msg: LaserScan | None = None
            self.goal_msg: Optional[PoseStamped] = None
            self.count: int = 0
    """
)


def sources(unit: str, source: str = SKILL) -> list[str]:
    return measuring_sources(facts_of(source), unit)


def test_each_latest_message_offers_the_fields_of_the_outputs_unit() -> None:
    assert sources("m") == [
        "self.odom_msg.pose.pose.position (the distance travelled: math.hypot of its change "
        "in x and y since execute began)",
        "self.scan_msg.ranges (the nearest obstacle: the smallest range between range_min and "
        "range_max)",
    ]
    assert sources("m/s") == ["self.odom_msg.twist.twist.linear.x (the measured forward speed)"]
    assert sources("rad/s") == ["self.odom_msg.twist.twist.angular.z (the measured yaw rate)"]
    assert [s.split(" (")[0] for s in sources("°")] == [
        "self.odom_msg.pose.pose.orientation",
        "self.scan_msg.angle_min + i * self.scan_msg.angle_increment",
    ]


def test_a_duration_is_read_from_the_clock() -> None:
    assert sources("s") == [
        "time.monotonic() (how long it took: its value at the end minus at the start)"
    ]


@pytest.mark.parametrize("unit", ["kg", "N", ""])
def test_a_unit_no_message_carries_offers_nothing(unit: str) -> None:
    assert sources(unit) == []


def test_a_skill_without_latest_messages_offers_nothing() -> None:
    assert sources("m", "class Skill:\n    def execute(self):\n        pass\n") == []


def test_a_skill_with_the_nearest_reading_helper_is_pointed_at_it() -> None:
    helper = "    def _closest_reading(self, scan):\n        return 0.0, 0.0\n"
    assert sources("m", SKILL + helper)[1:] == [
        "self._closest_reading(self.scan_msg)[0] (the range of the nearest valid reading)"
    ]
    assert sources("rad", SKILL + helper)[1:] == [
        "self._closest_reading(self.scan_msg)[1] (its bearing, in radians)"
    ]


def test_a_skill_with_the_heading_helper_is_pointed_at_it_for_angles_only() -> None:
    helper = "    def _yaw(self, q):\n        return 0.0\n"
    assert sources("rad", SKILL + helper) == [
        "self._yaw(self.odom_msg.pose.pose.orientation) (the heading, in radians)",
        sources("rad")[1],
    ]
    assert sources("m/s", SKILL + helper) == sources("m/s")
    assert sources("m", SKILL + helper) == sources("m")
