"""Measured values tested for exact equality."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability
from skillwright.rules.finding import Finding
from skillwright.spec import SkillSpec
from skillwright.validation.static import check_skill
from tests.validation.test_static import CATALOG, GOOD

EXECUTE_DOC = '        """Drive until the distance is covered, then stop."""\n'


def _equality(statements: str, inputs: tuple[Capability, SkillSpec]) -> list[Finding]:
    assert EXECUTE_DOC in GOOD
    source = GOOD.replace(EXECUTE_DOC, EXECUTE_DOC + statements, 1)
    capability, spec = inputs
    report = check_skill(source, capability=capability, spec=spec, catalog=CATALOG)
    return [f for f in report.findings if f.check == "equality"]


def test_a_loop_left_when_a_reading_equals_the_input_is_an_error_with_the_closeness_test(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the cap2skill set-velocity of the evaluation at d678df9: the loop ran to the deadline
    loop = (
        "        velocity = self.in_linear_velocity\n"
        "        while True:\n"
        "            self.out_linear_velocity = self.odom_msg.twist.twist.linear.x\n"
        "            if velocity == self.out_linear_velocity:\n"
        "                break\n"
        "            time.sleep(0.05)\n"
    )
    [finding] = _equality(loop, move_forward)
    assert finding.severity == "error"
    assert "`velocity == self.out_linear_velocity` tests a measured value" in finding.message
    assert "this loop most likely never ends" in finding.message
    assert finding.replacement == ("if abs(self.out_linear_velocity - velocity) < 0.01:\n    break")


def test_a_loop_condition_on_a_reading_not_equal_to_the_input_is_an_error(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    loop = (
        "        while self.odom_msg.twist.twist.linear.x != self.in_linear_velocity:\n"
        "            time.sleep(0.05)\n"
    )
    [finding] = _equality(loop, move_forward)
    assert finding.severity == "error"
    assert finding.replacement == (
        "while abs(self.odom_msg.twist.twist.linear.x - self.in_linear_velocity) >= 0.01:\n"
        "    time.sleep(0.05)"
    )


def test_a_part_of_a_message_kept_in_a_local_is_followed(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    loop = (
        "        for _ in range(100):\n"
        "            here = self.odom_msg.pose.pose.position\n"
        "            if here.x == 2.0:\n"
        "                break\n"
        "            time.sleep(0.05)\n"
    )
    [finding] = _equality(loop, move_forward)
    assert finding.severity == "error"
    assert finding.replacement is None  # 2.0 of what: the model is told the form


def test_outside_a_loop_it_is_a_warning(move_forward: tuple[Capability, SkillSpec]) -> None:
    [finding] = _equality(
        "        if self.odom_msg.twist.twist.linear.x == self.in_linear_velocity:\n"
        "            self.node.get_logger().info('at speed')\n",
        move_forward,
    )
    assert finding.severity == "warning"
    assert finding.replacement is not None


@pytest.mark.parametrize(
    "statements",
    [
        "        if self.odom_msg == None:\n            return\n",
        "        if self.in_distance == 0.0:\n            return\n",  # a request, not a reading
        "        while self.odom_msg.header.frame_id == 'odom':\n            break\n",
        "        while GoalStatus.STATUS_SUCCEEDED == self.odom_msg.pose.pose.position.x:\n"
        "            break\n",
        "        while abs(self.odom_msg.twist.twist.linear.x - self.in_linear_velocity) > 0.01:\n"
        "            time.sleep(0.05)\n",
    ],
)
def test_what_is_no_measurement_or_no_exact_test_is_left_alone(
    move_forward: tuple[Capability, SkillSpec], statements: str
) -> None:
    assert _equality(statements, move_forward) == []
