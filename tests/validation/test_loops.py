"""Loops that wait for the robot must wait: a sleep in them, or a method that sleeps."""

from __future__ import annotations

import ast
import textwrap

import pytest

from skillwright.validation.loops import check_waits
from skillwright.validation.model import Finding

HEAD = """
class Skill:
    def starting(self):
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)

    def _on_odom(self, msg):
        self.odom_msg = msg

    def _wait_until(self, condition, timeout, what):
        while not condition():
            time.sleep(0.02)

"""


def _waits(execute: str) -> list[Finding]:
    source = HEAD + textwrap.indent(textwrap.dedent(execute).strip(), "    ") + "\n"
    cls = ast.parse(source).body[0]
    assert isinstance(cls, ast.ClassDef)
    return check_waits(cls)


@pytest.mark.parametrize(
    ("loop", "what"),
    [
        (
            """
            while self.odom_msg.pose.pose.position.x < self.in_distance:
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.05)
            """,
            None,
        ),
        (
            """
            while self.odom_msg.pose.pose.position.x < self.in_distance:
                self.cmd_vel_publisher.publish(command)
            """,
            "the robot while it publishes",
        ),
        (
            """
            while self.odom_msg.twist.twist.linear.x > 0.01:
                speed = self.odom_msg.twist.twist.linear.x
            """,
            "self.odom_msg, which a callback sets",
        ),
        (
            """
            deadline = time.monotonic() + 2.0
            while time.monotonic() < deadline:
                pass
            """,
            "the clock",
        ),
        (
            """
            while not self.goal_future.done():
                count += 1
            """,
            "a future",
        ),
        (
            """
            while self.odom_msg is None:
                self._wait_until(lambda: True, 1.0, "odometry")
            """,
            None,
        ),
        (
            """
            index = 0
            while index < len(ranges) and ranges[index] > 0.5:
                index += 1
            """,
            None,
        ),
    ],
    ids=["sleeps", "publishes", "callback attribute", "clock", "future", "helper waits", "data"],
)
def test_a_loop_waiting_for_the_robot_must_sleep(loop: str, what: str | None) -> None:
    found = _waits("def execute(self):\n" + textwrap.indent(textwrap.dedent(loop), "    "))
    if what is None:
        assert found == []
    else:
        assert [f.check for f in found] == ["waits"]
        assert f"this loop in execute waits for {what} but never sleeps" in found[0].message
        assert found[0].severity == "error"


def test_the_finding_carries_the_loop_with_a_sleep_at_its_end() -> None:
    found = _waits(
        """
        def execute(self):
            while self.odom_msg.pose.pose.position.x < self.in_distance:
                self.cmd_vel_publisher.publish(command)
        """
    )
    assert found[0].line == HEAD.count("\n") + 2
    assert found[0].replacement == (
        "while self.odom_msg.pose.pose.position.x < self.in_distance:\n"
        "    self.cmd_vel_publisher.publish(command)\n"
        "    time.sleep(0.05)"
    )


def test_a_loop_that_continues_gets_no_replacement_a_sleep_at_its_end_would_miss() -> None:
    found = _waits(
        """
        def execute(self):
            while time.monotonic() < self.deadline:
                if self.odom_msg is None:
                    continue
                self.cmd_vel_publisher.publish(command)
        """
    )
    assert len(found) == 1
    assert found[0].replacement is None
