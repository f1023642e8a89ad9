"""Loops that wait for the robot must wait: a sleep in them, or a method that sleeps."""

from __future__ import annotations

import textwrap

import pytest

from skillwright.capability.model import Capability
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.loops import check_waits
from tests.validation.test_facts import facts_of

HEAD = """
class Skill:
    def starting(self):
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)

    def _on_odom(self, msg):
        self.odom_msg = msg

    def _wait_until(self, condition, timeout, what):
        while not condition():
            time.sleep(0.02)

    def _pause(self):
        self.node.get_logger().debug("pausing")
        time.sleep(0.05)

"""


def skill_facts(head: str, method: str, capability: Capability | None = None) -> SkillFacts:
    """The facts of the class of ``head`` (a class statement and members) with ``method``
    added to it."""
    source = head + textwrap.indent(textwrap.dedent(method).strip(), "    ") + "\n"
    return facts_of(source, capability=capability)


def _waits(execute: str) -> list[Finding]:
    return check_waits(skill_facts(HEAD, execute))


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
            while self.odom_msg.twist.twist.angular.z > 0.01:
                self._pause()
            """,
            None,
        ),
        (
            """
            while abs(self.remaining) > 0.01:
                self.cmd_vel_publisher.publish(command)
                self._wait_until(lambda: self.odom_msg is not None, 0.05, "odometry")
            """,
            "the robot while it publishes",
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
    ids=[
        "sleeps",
        "publishes",
        "callback attribute",
        "clock",
        "future",
        "helper waits",
        "helper waits only for data",
        "data",
    ],
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


def test_a_timeout_that_compares_the_clock_with_a_duration_gets_a_deadline() -> None:
    # MR-1 navigate-to-point (ev43): the goal "was not completed within 5 s" on the first pass.
    found = _waits(
        """
        def execute(self):
            while not self.result_future.done():
                if time.monotonic() > 5.0:
                    raise RuntimeError("the navigation was not completed within 5 s")
                time.sleep(0.5)
        """
    )
    assert [f.check for f in found] == ["waits"]
    assert "time.monotonic() > 5.0 compares the clock's reading" in found[0].message
    assert "`deadline = time.monotonic() + 5.0`" in found[0].message
    assert found[0].line == HEAD.count("\n") + 2
    assert found[0].replacement == (
        "deadline = time.monotonic() + 5.0\n"
        "while not self.result_future.done():\n"
        "    if time.monotonic() > deadline:\n"
        "        raise RuntimeError('the navigation was not completed within 5 s')\n"
        "    time.sleep(0.5)"
    )


def test_a_deadline_named_timeout_is_a_deadline_not_a_duration() -> None:
    """``timeout = time.time() + 3.0`` is a moment, whatever its name says: comparing the
    clock with it is how a deadline is kept."""
    found = _waits(
        """
        def execute(self):
            timeout = time.time() + 3.0
            while time.time() < timeout:
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.1)
        """
    )
    assert found == []
    still = _waits(
        """
        def execute(self):
            timeout = 3.0
            while time.time() < timeout:
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.1)
        """
    )
    assert [f.code for f in still] == ["SW401"]


def test_one_fix_takes_each_deadline_and_adds_the_missing_sleep() -> None:
    found = _waits(
        """
        def execute(self):
            deadline = 1
            while self.TIMEOUT >= time.time() and time.monotonic() < 2:
                if time.monotonic() > 2:
                    break
                self.cmd_vel_publisher.publish(command)
        """
    )
    assert len(found) == 4  # three comparisons and the missing sleep, one fix for all
    assert {f.replacement for f in found} == {
        "deadline_2 = time.time() + self.TIMEOUT\n"
        "deadline_3 = time.monotonic() + 2\n"
        "while deadline_2 >= time.time() and time.monotonic() < deadline_3:\n"
        "    if time.monotonic() > deadline_3:\n"
        "        break\n"
        "    self.cmd_vel_publisher.publish(command)\n"
        "    time.sleep(0.05)"
    }


@pytest.mark.parametrize(
    "comparison",
    [
        "time.monotonic() > deadline",
        "time.monotonic() - start > 5.0",
        "time.monotonic() > self.START_TIME",
        "time.monotonic() > self.goal_deadline",
        "elapsed > 5.0",
        "0.0 < time.monotonic() < 5.0",
    ],
)
def test_a_deadline_or_an_elapsed_time_is_not_flagged(comparison: str) -> None:
    found = _waits(
        f"""
        def execute(self):
            while not self.result_future.done():
                if {comparison}:
                    break
                time.sleep(0.1)
        """
    )
    assert found == []


def test_outside_a_while_loop_the_model_is_told_without_a_fix() -> None:
    found = _waits(
        """
        def execute(self):
            for point in self.points:
                if time.monotonic() > self.in_timeout:
                    break
            if time.monotonic() >= 3:
                raise RuntimeError("too slow")
        """
    )
    assert sorted((f.line - HEAD.count("\n"), f.replacement) for f in found) == [
        (3, None),
        (5, None),
    ]
    assert all("compares the clock's reading" in f.message for f in found)
