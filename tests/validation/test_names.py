"""Names nothing defines: unimported classes, attributes never set, rclpy calls that do not exist."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability, load_capability
from skillwright.spec import SkillSpec, load_spec
from skillwright.validation.model import CheckReport
from skillwright.validation.static import check_skill
from tests.conftest import SHIPPED_CAPABILITIES
from tests.validation.test_static import CATALOG, GOOD


@pytest.fixture(scope="module")
def move_forward() -> tuple[Capability, SkillSpec]:
    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    return capability, load_spec(SHIPPED_CAPABILITIES / "move-forward.spec.yaml")


def _check(source: str, inputs: tuple[Capability, SkillSpec]) -> CheckReport:
    capability, spec = inputs
    return check_skill(source, capability=capability, spec=spec, catalog=CATALOG)


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (
            "command = Twist()",
            "command = Twist(linear=Vector3(x=speed))",
            "Vector3 is not defined: import it",
        ),
        (
            'self.node.get_logger().info(f"{self.in_distance}',
            'self.logger.info(f"{self.in_distance}',
            "self.logger is never set in this class; log with self.node.get_logger()",
        ),
        (
            "while self.odom_msg is None and time.time() < deadline:",
            "while self.odom_mgs is None and time.time() < deadline:",
            "self.odom_mgs is never set in this class; did you mean self.odom_msg?",
        ),
        (
            "            time.sleep(0.05)\n\n    @execute",
            "            self.odom_subscription.wait_for_message(timeout_sec=0.05)\n\n    @execute",
            "self.odom_subscription is a Subscription, which has no 'wait_for_message' in rclpy; "
            "its callback keeps the latest message in self.odom_msg: wait for the first one with "
            'self._wait_until(lambda: self.odom_msg is not None, 2.0, "odom_msg")',
        ),
        (
            "self.cmd_vel_publisher.publish(command)",
            "self.cmd_vel_publisher.send(command)",
            "self.cmd_vel_publisher is a Publisher, which has no 'send' in rclpy",
        ),
        (
            'self.node.get_logger().info(f"{self.in_distance}',
            'self.node.get_logger().log(f"{self.in_distance}',
            "is the logger, which has no 'log' in rclpy",
        ),
        (
            "    def _travelled(self) -> float:",
            "    def _travelled(self, p: Odometry.Pose = None) -> float:",
            "Odometry.Pose does not exist",
        ),
    ],
    ids=[
        "unimported class",
        "logger on the skill",
        "misspelt attribute",
        "subscription method",
        "publisher method",
        "logger method",
        "nested message class",
    ],
)
def test_names_nothing_defines_are_errors_located_at_their_use(
    move_forward: tuple[Capability, SkillSpec], old: str, new: str, expected: str
) -> None:
    assert old in GOOD
    source = GOOD.replace(old, new, 1)
    report = _check(source, move_forward)
    found = [f for f in report.findings if f.check == "names"]
    assert any(expected in f.message for f in found), found
    finding = next(f for f in found if expected in f.message)
    assert finding.severity == "error"
    changed = next(line.strip() for line in new.splitlines() if line.strip() not in old)
    assert changed[:20] in source.splitlines()[finding.line - 1]


def test_the_good_skill_uses_no_undefined_name(move_forward: tuple[Capability, SkillSpec]) -> None:
    assert not [f for f in _check(GOOD, move_forward).findings if f.check == "names"]


def test_pyskillup_decorators_builtins_and_locals_are_known(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    source = GOOD.replace(
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)",
        "        speed = min(abs(self.in_linear_velocity), self.LINEAR_VELOCITY_MAX)\n"
        "        values = [round(v, 2) for v in (speed, 1.0)]\n"
        "        for index, value in enumerate(values):\n"
        "            self.node.get_logger().debug(f'{index}: {value}')",
    )
    assert not [f for f in _check(source, move_forward).findings if f.check == "names"]
