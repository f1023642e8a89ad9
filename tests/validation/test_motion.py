"""Loops that wait for the robot to move when nothing commands it to."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability
from skillwright.spec import SkillSpec
from skillwright.validation.model import Finding
from skillwright.validation.static import check_skill
from tests.validation.test_static import CATALOG, GOOD

PUBLISH_IN_LOOP = "            self.cmd_vel_publisher.publish(command)\n"


def _motion(source: str, inputs: tuple[Capability, SkillSpec]) -> list[Finding]:
    capability, spec = inputs
    report = check_skill(source, capability=capability, spec=spec, catalog=CATALOG)
    return [f for f in report.findings if f.check == "motion"]


def _commanding_only_in_completing() -> str:
    """The good skill with its drive's command sent in completing, after the loop."""
    log = '        self.node.get_logger().info(f"{self.in_distance} m asked'
    assert log in GOOD
    return GOOD.replace(PUBLISH_IN_LOOP, "", 1).replace(
        log, "        self.cmd_vel_publisher.publish(Twist(linear=Vector3(x=0.1)))\n" + log, 1
    )


def test_the_good_skill_commands_its_motion(move_forward: tuple[Capability, SkillSpec]) -> None:
    assert PUBLISH_IN_LOOP in GOOD
    assert _motion(GOOD, move_forward) == []


def test_a_skill_that_never_commands_the_velocity_asked_for_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the cap2skill collision avoidance of the evaluation at d678df9 slept for the time
    # asked and stopped the base: nothing ever published a velocity
    source = GOOD.replace(PUBLISH_IN_LOOP, "", 1)
    [finding] = _motion(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == "def execute(self) -> None:"
    assert "the capability asks for a velocity (inLinearVelocity (m/s))" in finding.message
    assert "the robot never moves" in finding.message


def test_a_loop_waiting_for_progress_nothing_commands_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the cap2skill rotate of the evaluation at d678df9 published nothing and waited for the
    # heading until the deadline; here the drive's command is built and sent only later
    source = _commanding_only_in_completing()
    [finding] = _motion(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == (
        "while self._travelled() < self.in_distance:"
    )
    assert "`self._travelled() < self.in_distance` compares a reading" in finding.message
    assert "no velocity is published on self.cmd_vel_publisher" in finding.message


@pytest.mark.parametrize(
    ("old", "new"),
    [
        # the command sent by a helper the state calls
        (
            PUBLISH_IN_LOOP,
            "            self._drive(command)\n",
        ),
        # or once before the loop, in starting
        (
            "        deadline = time.time() + 2.0\n",
            "        self.cmd_vel_publisher.publish(Twist(linear=Vector3(x=0.1)))\n"
            "        deadline = time.time() + 2.0\n",
        ),
    ],
)
def test_a_command_sent_elsewhere_on_the_path_counts(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str
) -> None:
    drive = "    def _drive(self, command):\n        self.cmd_vel_publisher.publish(command)\n\n"
    source = GOOD.replace(PUBLISH_IN_LOOP, "", 1) if old != PUBLISH_IN_LOOP else GOOD
    source = source.replace(old, new, 1).replace("    @starting\n", drive + "    @starting\n", 1)
    assert _motion(source, move_forward) == []


def test_a_loop_that_only_waits_for_a_first_message_is_no_motion(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = _commanding_only_in_completing().replace(
        "        while self._travelled() < self.in_distance:\n            time.sleep(0.05)\n",
        "        while self.odom_msg is None:\n            time.sleep(0.05)\n",
        1,
    )
    assert "while self.odom_msg is None:" in source
    assert _motion(source, move_forward) == []
