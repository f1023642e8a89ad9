"""A loop that waits for a motion must not stop the robot on every pass."""

from __future__ import annotations

import textwrap

import pytest

from skillwright.rules.finding import Finding
from skillwright.validation.stops import check_stops
from tests.validation.test_facts import facts_of

HEAD = """
class Skill:
    def _stop_base(self):
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    def _yaw(self):
        return self.heading

"""

START = """
        command = Twist()
        command.angular.z = 0.5
        self.cmd_vel_publisher.publish(command)
"""


def _stops(execute: str) -> list[Finding]:
    body = "    def execute(self):\n" + textwrap.indent(
        textwrap.dedent(execute).strip(), "        "
    )
    return check_stops(facts_of(HEAD + body + "\n"))


@pytest.mark.parametrize(
    "stop",
    ["self.cmd_vel_publisher.publish(Twist())", "self._stop_base()"],
    ids=["zero twist", "the skeleton's stop"],
)
def test_a_loop_that_stops_the_turn_it_waits_for_publishes_the_turn_instead(stop: str) -> None:
    # MR-1 rotate, ev45-ev51: the turn once before the loop, a stop on every pass
    [finding] = _stops(
        START
        + f"""
        while abs(self.target - self._yaw()) > 0.01:
            if time.monotonic() > deadline:
                self._stop_base()
                raise RuntimeError("not turned within 10 s")
            {stop}
            time.sleep(0.05)
        """
    )
    assert finding.check == "stops"
    assert f"this loop commands zero velocity on every pass ({stop})" in finding.message
    assert "right after self.cmd_vel_publisher.publish(command) started the motion" in (
        finding.message
    )
    assert finding.replacement == "self.cmd_vel_publisher.publish(command)"


@pytest.mark.parametrize(
    "loop",
    [
        # the stop before giving up, and the motion command on every pass
        """
        while abs(self.target - self._yaw()) > 0.01:
            if time.monotonic() > deadline:
                self.cmd_vel_publisher.publish(Twist())
                raise RuntimeError("not turned within 10 s")
            self.cmd_vel_publisher.publish(command)
            time.sleep(0.05)
        """,
        # only the stop before giving up: the motion goes on from before the loop
        """
        while abs(self.target - self._yaw()) > 0.01:
            if time.monotonic() > deadline:
                self._stop_base()
                raise RuntimeError("not turned within 10 s")
            time.sleep(0.05)
        """,
        # a loop that brakes on purpose, after the turn was done
        """
        self.cmd_vel_publisher.publish(Twist())
        while abs(self._yaw_rate()) > 0.01:
            self.cmd_vel_publisher.publish(Twist())
            time.sleep(0.05)
        """,
    ],
    ids=["motion in the loop", "stop only when leaving", "braking loop"],
)
def test_loops_that_keep_the_motion_or_mean_to_stop_are_left_alone(loop: str) -> None:
    assert _stops(START + loop) == []
