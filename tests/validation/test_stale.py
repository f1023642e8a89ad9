"""A loop whose condition nothing in it changes ends only by raising."""

from __future__ import annotations

import pytest

from skillwright.rules.finding import Finding
from skillwright.validation.stale import check_stale_conditions
from tests.validation.test_loops import HEAD as LOOPS_HEAD
from tests.validation.test_loops import skill_facts

HEAD = (
    LOOPS_HEAD
    + """    def watching(self):
        self.node.create_subscription(Pose2D, "/pose", self._on_pose, 10)

    def _on_pose(self, msg):
        self.heading = msg.theta

    def _yaw(self):
        return self.heading

    def _turn_a_little(self):
        self.turned = self.turned + 1

"""
)
"""The loops' skill (a subscription's callback sets ``odom_msg``), with a heading another
callback sets and a method that changes an attribute."""


def _stale(execute: str) -> list[Finding]:
    return check_stale_conditions(skill_facts(HEAD, execute))


def test_a_reading_taken_once_before_the_loop_is_taken_again_at_its_end() -> None:
    # cap2skill rotate, every evaluation since ev46
    [finding] = _stale(
        """
        def execute(self):
            last_angle = self._yaw()
            self.out_degree = (self.in_degree + last_angle) % 360
            deadline = time.monotonic() + 20.0
            while abs(last_angle - self.out_degree) > 0.05:
                if time.monotonic() > deadline:
                    raise RuntimeError("the robot did not reach the orientation within 20 s")
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.05)
        """
    )
    assert finding.check == "stale"
    assert finding.severity == "error"
    assert "reads last_angle, which nothing in the loop changes" in finding.message
    assert "the fix repeats `last_angle = self._yaw()` at the end of the loop" in finding.message
    assert finding.replacement is not None
    assert finding.replacement.splitlines()[-2:] == [
        "    time.sleep(0.05)",
        "    last_angle = self._yaw()",
    ]


def test_a_while_true_left_on_values_worked_out_from_a_reading_taken_once_reads_it_again() -> None:
    # MR-1 rotate of the evaluation at 3ec2321: the remaining angle was worked out on every
    # pass from a heading read once before the loop, and stayed 2 rad for 400 passes
    [finding] = _stale(
        """
        def execute(self):
            current = self._yaw()
            target = (current + self.in_angle) % (2 * math.pi)
            while True:
                remaining = (target - current) % (2 * math.pi)
                if remaining < 0.01:
                    break
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.05)
        """
    )
    assert "`remaining < 0.01`, comes from current, target" in finding.message
    assert "the fix repeats `current = self._yaw()` at the start of each pass" in finding.message
    assert finding.replacement is not None
    assert finding.replacement.splitlines()[:3] == [
        "while True:",
        "    current = self._yaw()",
        "    remaining = (target - current) % (2 * math.pi)",
    ]


@pytest.mark.parametrize(
    "loop",
    [
        # read again in the loop
        "while True:\n"
        "    current = self._yaw()\n"
        "    if abs(target - current) < 0.01:\n"
        "        break\n"
        "    time.sleep(0.05)\n",
        # decided on a reading itself
        "while True:\n    if abs(target - self._yaw()) < 0.01:\n        break\n    time.sleep(0.05)\n",
        # a pass counter changes
        "while True:\n    i = i + 1\n    if i > 10:\n        break\n    time.sleep(0.05)\n",
    ],
)
def test_a_while_true_whose_exit_can_change_is_left_alone(loop: str) -> None:
    body = "\n".join("            " + line for line in loop.splitlines())
    execute = (
        "\n        def execute(self):\n            current = self._yaw()\n"
        "            target = current + 1.0\n            i = 0\n" + body + "\n"
    )
    assert _stale(execute) == []


def test_a_stale_name_without_a_reading_to_repeat_is_left_to_the_model() -> None:
    [finding] = _stale(
        """
        def execute(self):
            remaining = self.in_angle
            while remaining > 0.01:
                self.cmd_vel_publisher.publish(command)
                time.sleep(0.05)
        """
    )
    assert "reads remaining" in finding.message
    assert finding.replacement is None


@pytest.mark.parametrize(
    "loop",
    [
        # the body reads the heading again
        """
        def execute(self):
            heading = self._yaw()
            while abs(heading - self.target) > 0.05:
                time.sleep(0.05)
                heading = self._yaw()
        """,
        # a callback sets what the condition reads
        """
        def execute(self):
            while abs(self.heading - self.target) > 0.05 or pause:
                time.sleep(0.05)
        """,
        # a method the loop calls sets it
        """
        def execute(self):
            limit = 3
            while self.turned < limit:
                self._turn_a_little()
                time.sleep(0.05)
        """,
        # the loop has another way out
        """
        def execute(self):
            heading = self._yaw()
            while abs(heading - self.target) > 0.05:
                if self._yaw() > self.target:
                    break
                time.sleep(0.05)
        """,
        # a list a subscription appends to changes without an assignment
        """
        def execute(self):
            messages = []
            self.node.create_subscription(Odometry, "/odom", messages.append, 10)
            while len(messages) < 3:
                time.sleep(0.05)
        """,
        # a call the condition makes may give another answer each time
        """
        def execute(self):
            target = self._yaw() + 1.0
            while abs(self._yaw() - target) > 0.05:
                time.sleep(0.05)
        """,
        # while True is meant
        """
        def execute(self):
            while True:
                time.sleep(0.05)
                if self._yaw() > 1.0:
                    return
        """,
    ],
    ids=["read again", "callback", "called method", "break", "appended", "call", "true"],
)
def test_loops_whose_condition_can_change_are_left_alone(loop: str) -> None:
    assert _stale(loop) == []
