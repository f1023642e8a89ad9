"""Giving up on a reading taken the moment after a command (check ``waits``)."""

from __future__ import annotations

import pytest

from skillwright.validation.settle import check_settling
from tests.validation.test_loops import skill_facts

HEAD = """class S:
    def __init__(self) -> None:
        self.odom_msg: Odometry | None = None
        self.scan_msg: LaserScan | None = None

    def _wait_until(self, condition, timeout: float, what: str) -> None:
        pass

"""

SET_VELOCITY = """
def execute(self) -> None:
    command = Twist()
    command.linear.x = self.in_velocity
    self.cmd_vel_publisher.publish(command)
    self._wait_until(lambda: self.odom_msg is not None, 30.0, "odometry on /odom")
    {test}
        raise RuntimeError("constraint violated")
    self.out_velocity = self.odom_msg.twist.twist.linear.x
"""


@pytest.mark.parametrize(
    ("test", "wait_for"),
    [
        (  # ev70 cap2skill set-velocity
            "if abs(self.in_velocity - self.odom_msg.twist.twist.linear.x) > 0.05:",
            "abs(self.in_velocity - self.odom_msg.twist.twist.linear.x) <= 0.05",
        ),
        (
            "if not math.isclose(self.odom_msg.twist.twist.linear.x, self.in_velocity):",
            "math.isclose(self.odom_msg.twist.twist.linear.x, self.in_velocity)",
        ),
        (
            "if self.odom_msg.twist.twist.linear.x < 0.1 or self.in_velocity < 0:",
            "not (self.odom_msg.twist.twist.linear.x < 0.1 or self.in_velocity < 0)",
        ),
    ],
)
def test_a_test_of_the_reading_right_after_the_command_becomes_a_wait(
    test: str, wait_for: str
) -> None:
    [finding] = check_settling(skill_facts(HEAD, SET_VELOCITY.format(test=test)))
    assert (finding.check, finding.severity) == ("waits", "error")
    assert "right after `self.cmd_vel_publisher.publish(command)`" in finding.message
    assert "on self.odom_msg as it was before the command" in finding.message
    assert finding.replacement == (
        f"self._wait_until(lambda: {wait_for}, 5.0, '{wait_for} after the command')"
    )


def test_without_the_skeletons_wait_the_finding_has_no_fix() -> None:
    head = HEAD.replace("_wait_until", "_other")
    test = "if self.odom_msg.twist.twist.linear.x > 0.5:"
    [finding] = check_settling(skill_facts(head, SET_VELOCITY.format(test=test)))
    assert finding.replacement is None
    assert "wait until self.odom_msg.twist.twist.linear.x <= 0.5 instead" in finding.message


@pytest.mark.parametrize(
    "between",
    [
        "time.sleep(1.0)",
        "self._wait_until(lambda: self.odom_msg.twist.twist.linear.x > 0.2, 5.0, 'moving')",
        "while self.odom_msg.twist.twist.linear.x < 0.2:\n        time.sleep(0.05)",
    ],
)
def test_a_test_after_something_that_gave_the_robot_time_is_left_alone(between: str) -> None:
    method = SET_VELOCITY.format(test="if self.odom_msg.twist.twist.linear.x > 0.5:").replace(
        "    self._wait_until(lambda: self.odom_msg is not None", f"    {between}\n    pass  #", 1
    )
    assert check_settling(skill_facts(HEAD, method)) == []


@pytest.mark.parametrize(
    "method",
    [
        # before the command: a check of the starting point
        """
        def execute(self) -> None:
            if self.odom_msg.twist.twist.linear.x > 0.01:
                raise RuntimeError("the base is moving already")
            self.cmd_vel_publisher.publish(Twist())
        """,
        # not only a raise: the skill reacts to the reading
        """
        def execute(self) -> None:
            self.cmd_vel_publisher.publish(Twist())
            if self.odom_msg.twist.twist.linear.x > 0.5:
                self._stop_base()
                raise RuntimeError("too fast")
        """,
        # a test of the inputs, not of a reading
        """
        def execute(self) -> None:
            self.cmd_vel_publisher.publish(Twist())
            if self.in_velocity > 1.0:
                raise ValueError("too fast")
        """,
        # inside a loop that commands and tests on every pass: a guard
        """
        def execute(self) -> None:
            while True:
                self.cmd_vel_publisher.publish(Twist())
                if self._closest_reading(self.scan_msg)[0] < 0.3 or self.scan_msg.ranges[0] < 0.3:
                    raise RuntimeError("obstacle")
                time.sleep(0.05)
        """,
    ],
)
def test_other_tests_are_left_alone(method: str) -> None:
    assert check_settling(skill_facts(HEAD, method)) == []
