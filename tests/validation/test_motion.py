"""Loops that wait for the robot to move when nothing commands it to."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability
from skillwright.rules.finding import Finding
from skillwright.spec import SkillSpec
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


def _published_once_before_the_loop() -> str:
    """The good skill with its drive's command published once, before the loop that waits
    for the distance, and never in it."""
    source = GOOD.replace(PUBLISH_IN_LOOP, "", 1).replace(
        "        while self._travelled() < self.in_distance:\n",
        "        self.cmd_vel_publisher.publish(command)\n"
        "        while self._travelled() < self.in_distance:\n",
        1,
    )
    assert source != GOOD
    return source


def test_a_command_published_once_before_a_waiting_loop_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the MR-1 move forward of the evaluation at 1840a63: the base's driver drops a command
    # that is not repeated, the robot stood still and execute ran into its deadline
    source = _published_once_before_the_loop()
    [finding] = _motion(source, move_forward)
    lines = source.splitlines()
    assert lines[finding.line - 1].strip() == "time.sleep(0.05)"
    assert lines[finding.line - 2].strip() == "while self._travelled() < self.in_distance:"
    assert "(self.cmd_vel_publisher.publish(command) on line" in finding.message
    assert "never again while the loop waits" in finding.message
    assert finding.replacement == "self.cmd_vel_publisher.publish(command)\ntime.sleep(0.05)"


def test_a_while_true_left_by_a_branch_that_stops_is_a_waiting_loop(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = _published_once_before_the_loop().replace(
        "        while self._travelled() < self.in_distance:\n            time.sleep(0.05)\n",
        "        while True:\n"
        "            if self._travelled() >= self.in_distance:\n"
        "                self.cmd_vel_publisher.publish(Twist(linear=Vector3(x=0.0)))\n"
        "                break\n"
        "            time.sleep(0.05)\n",
        1,
    )
    assert "while True:" in source
    [finding] = _motion(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == "while True:"
    assert finding.replacement is None  # an `if` comes first: the message says what to do


def _stop_helper(source: str, body: str) -> str:
    """``source`` with a method ``_halt`` publishing ``body`` called right before the loop
    that waits."""
    helper = f"    def _halt(self) -> None:\n        self.cmd_vel_publisher.publish({body})\n\n"
    return source.replace("    @starting\n", helper + "    @starting\n", 1).replace(
        "        self.cmd_vel_publisher.publish(command)\n        while",
        "        self.cmd_vel_publisher.publish(command)\n        self._halt()\n        while",
        1,
    )


def test_a_wait_after_the_skills_own_stop_helper_is_no_one_shot(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # A helper that publishes only a zero velocity stops the base: the loop after it waits
    # for the base to come to rest, which needs no repeated command.
    source = _stop_helper(_published_once_before_the_loop(), "Twist()")
    assert "self._halt()\n        while" in source
    assert not [f for f in _motion(source, move_forward) if "goes out once" in f.message]
    # A helper that commands motion is no stop: the command before the loop is still one shot.
    moving = _stop_helper(_published_once_before_the_loop(), "Twist(linear=Vector3(x=0.2))")
    assert [f for f in _motion(moving, move_forward) if "goes out once" in f.message]


@pytest.mark.parametrize(
    ("old", "new"),
    [
        # a timer of the skill may repeat the command
        (
            "    @starting\n",
            "    def _tick(self):\n        pass\n\n    @starting\n",
        ),
        # the command before the loop is a stop: the loop waits for the robot to settle
        (
            "        self.cmd_vel_publisher.publish(command)\n        while",
            "        self.cmd_vel_publisher.publish(Twist(linear=Vector3(x=0.0)))\n        while",
        ),
    ],
)
def test_a_command_repeated_elsewhere_or_a_stop_is_no_one_shot(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str
) -> None:
    source = _published_once_before_the_loop().replace(old, new, 1)
    if "_tick" in new:
        source = source.replace(
            "        deadline = time.time() + 2.0\n",
            "        self.timer = self.node.create_timer(0.05, self._tick)\n"
            "        deadline = time.time() + 2.0\n",
            1,
        )
        assert "create_timer" in source
    assert source != _published_once_before_the_loop()
    assert not [f for f in _motion(source, move_forward) if "goes out once" in f.message]


def _drives_for_a_time(sleep: str) -> str:
    """The good skill driving open-loop: the command published once, then a sleep."""
    source = _published_once_before_the_loop().replace(
        "        while self._travelled() < self.in_distance:\n            time.sleep(0.05)\n",
        f"        {sleep}\n",
        1,
    )
    assert sleep in source
    return source


def test_a_command_published_once_and_slept_on_is_an_error_with_a_loop_as_the_fix(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the cap2skill move forward of the evaluation at 1840a63, as the paper's skill does it:
    # publish, time.sleep(time_value), stop; the robot moved for half a second of it
    source = _drives_for_a_time("time.sleep(self.in_distance / speed)")
    [finding] = _motion(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip() == "time.sleep(self.in_distance / speed)"
    assert "then sleeps for self.in_distance / speed s" in finding.message
    assert finding.replacement == (
        "deadline = time.monotonic() + self.in_distance / speed\n"
        "while time.monotonic() < deadline:\n"
        "    self.cmd_vel_publisher.publish(command)\n"
        "    time.sleep(0.05)"
    )


@pytest.mark.parametrize(
    "sleep",
    [
        "time.sleep(0.2)",  # within the driver's half second
        "for _ in range(20):\n            self.cmd_vel_publisher.publish(command)\n"
        "            time.sleep(self.in_distance / 20)",  # repeated in a loop
    ],
)
def test_a_short_sleep_or_one_in_a_loop_that_publishes_is_fine(
    move_forward: tuple[Capability, SkillSpec], sleep: str
) -> None:
    source = _drives_for_a_time(sleep)
    assert not [f for f in _motion(source, move_forward) if "goes out once" in f.message]
