"""Guards that give up on a subscription's first message nothing waited for."""

from __future__ import annotations

import pytest

from skillwright.capability import Capability
from skillwright.rules.finding import Finding
from skillwright.spec import SkillSpec
from skillwright.validation.static import check_skill
from tests.validation.test_static import CATALOG, GOOD

WAIT_IN_STARTING = (
    "        deadline = time.time() + 2.0\n"
    "        while self.odom_msg is None and time.time() < deadline:\n"
    "            time.sleep(0.05)\n"
)
EXECUTE_DOC = '        """Drive until the distance is covered, then stop."""\n'
WAIT = 'self._wait_until(lambda: self.odom_msg is not None, 2.0, "odom_msg")'


def _waits(source: str, inputs: tuple[Capability, SkillSpec]) -> list[Finding]:
    capability, spec = inputs
    report = check_skill(source, capability=capability, spec=spec, catalog=CATALOG)
    return [f for f in report.findings if f.check == "waits"]


def _execute_starting_with(statements: str, *, starting_waits: bool) -> str:
    assert WAIT_IN_STARTING in GOOD
    source = GOOD if starting_waits else GOOD.replace(WAIT_IN_STARTING, "", 1)
    return source.replace(EXECUTE_DOC, EXECUTE_DOC + statements, 1)


@pytest.mark.parametrize(
    ("guard", "replacement"),
    [
        (
            "        if self.odom_msg is None:\n            raise RuntimeError('no odometry')\n",
            WAIT,
        ),
        (
            "        odom = self.odom_msg\n"
            "        if not odom:\n"
            "            raise RuntimeError('no odometry')\n",
            f"{WAIT}\nodom = self.odom_msg",
        ),
    ],
)
def test_giving_up_on_a_first_message_nothing_waited_for_is_replaced_by_the_wait(
    move_forward: tuple[Capability, SkillSpec], guard: str, replacement: str
) -> None:
    source = _execute_starting_with(guard, starting_waits=False)
    [finding] = _waits(source, move_forward)
    assert source.splitlines()[finding.line - 1].strip().startswith("if ")
    assert finding.severity == "error"
    assert "nothing waited for it before this guard in execute" in finding.message
    assert finding.replacement == replacement


def test_a_guard_after_starting_waited_for_the_message_is_fine(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    guard = "        if self.odom_msg is None:\n            raise RuntimeError('no odometry')\n"
    assert _waits(_execute_starting_with(guard, starting_waits=True), move_forward) == []


def test_a_wait_in_a_helper_the_state_calls_counts(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    helper = (
        f"    def _odometry(self):\n        {WAIT}\n        return self.odom_msg\n\n    @execute\n"
    )
    source = _execute_starting_with(
        "        self._odometry()\n"
        "        if self.odom_msg is None:\n"
        "            raise RuntimeError('no odometry')\n",
        starting_waits=False,
    ).replace("    @execute\n", helper, 1)
    assert _waits(source, move_forward) == []


def test_a_guard_that_does_more_than_give_up_is_left_alone(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    guard = (
        "        if self.odom_msg is None:\n"
        "            self.node.get_logger().warning('no odometry yet')\n"
        "            return\n"
    )
    assert _waits(_execute_starting_with(guard, starting_waits=False), move_forward) == []


def test_reading_a_first_message_nothing_waited_for_gets_the_wait_before_it(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # a Panther set-velocity read the odometry in execute after a starting that waited for
    # nothing: AttributeError on a robot that is fine
    read = "        speed = self.odom_msg.twist.twist.linear.x\n"
    source = _execute_starting_with(read, starting_waits=False)
    [finding] = _waits(source, move_forward)
    assert source.splitlines()[finding.line - 1] == read.rstrip("\n")
    assert "nothing waited for it before execute reads its fields here" in finding.message
    assert finding.replacement == f"{WAIT}\nspeed = self.odom_msg.twist.twist.linear.x"
    # waited for in starting, read under a test of it, or in a wait's own condition: fine
    assert _waits(_execute_starting_with(read, starting_waits=True), move_forward) == []
    for safe in (
        "        if self.odom_msg is not None:\n    " + read,
        "        speed = self.odom_msg and self.odom_msg.twist.twist.linear.x\n",
        "        self._wait_until(lambda: self.odom_msg.twist.twist.linear.x > 0, 2.0, 'v')\n",
    ):
        found = _waits(_execute_starting_with(safe, starting_waits=False), move_forward)
        assert [
            f for f in found if f.line == source.splitlines().index(read.rstrip("\n")) + 1
        ] == []


@pytest.mark.parametrize(
    ("helper", "error"),
    [
        ("    def _speed(self, odom):\n        return odom.twist.twist.linear.x\n\n", True),
        ("    def _speed(self, odom):\n        return 0.0 if odom is None else 1.0\n\n", False),
        # the skeleton's _closest_reading(self, *scans) reads each element's fields
        (
            "    def _speed(self, *odoms):\n"
            "        for odom in odoms:\n"
            "            return odom.twist.twist.linear.x\n\n",
            True,
        ),
        ("    def _speed(self, *odoms):\n        return odoms[0].twist.twist.linear.x\n\n", True),
        (
            "    def _speed(self, *odoms):\n        first = odoms[0]\n        return first.pose\n\n",
            True,
        ),
        ("    def _speed(self, *odoms):\n        return float(len(odoms))\n\n", False),
    ],
)
def test_handing_a_first_message_to_a_method_that_reads_its_fields_counts_as_reading_it(
    move_forward: tuple[Capability, SkillSpec], helper: str, error: bool
) -> None:
    # ev70's cap2skill get-distance called self._closest_reading(self.scan_msg) at once in
    # execute: AttributeError in the run
    read = "        speed = self._speed(self.odom_msg)\n"
    source = _execute_starting_with(read, starting_waits=False)
    source = source.replace("    @starting", helper + "    @starting", 1)
    line = source.splitlines().index(read.rstrip("\n")) + 1
    found = [f.replacement for f in _waits(source, move_forward) if f.line == line]
    assert found == ([f"{WAIT}\nspeed = self._speed(self.odom_msg)"] if error else [])


def test_one_statement_reading_two_first_messages_gets_both_waits_in_one_finding(
    move_forward: tuple[Capability, SkillSpec],
) -> None:
    # the cap2skill get-distance of the evaluation at d678df9 unpacked
    # self._closest_reading(self.scan_msg, self.scan2_msg) in execute, waiting for neither
    helper = (
        "    def _nearest(self, *scans):\n"
        "        return min(min(scan.ranges) for scan in scans)\n\n"
    )
    read = "        nearest = self._nearest(self.odom_msg, self.scan_msg)\n"
    source = _execute_starting_with(read, starting_waits=False)
    source = source.replace("    @starting", helper + "    @starting", 1)
    source = source.replace(
        "        self.odom_msg: Odometry | None = None\n",
        "        self.odom_msg: Odometry | None = None\n        self.scan_msg: object = None\n",
        1,
    )
    line = source.splitlines().index(read.rstrip("\n")) + 1
    [finding] = [f for f in _waits(source, move_forward) if f.line == line]
    scan_wait = WAIT.replace("odom_msg", "scan_msg")
    assert "self.odom_msg and self.scan_msg stay None" in finding.message
    assert finding.replacement == f"{WAIT}\n{scan_wait}\n{read.strip()}"


@pytest.mark.parametrize(
    ("poll", "waits"),
    [
        (
            "        for _ in range(40):\n"
            "            if self.odom_msg is not None:\n"
            "                break\n"
            "            time.sleep(0.05)\n",
            True,
        ),
        (
            "        for _ in range(40):\n"
            "            rclpy.spin_once(self.node, timeout_sec=0.05)\n"
            "            if self.odom_msg:\n"
            "                break\n",
            True,
        ),
        # it neither sleeps nor spins: the executor never gets to deliver the message
        (
            "        for _ in range(40):\n            if self.odom_msg is not None:\n                break\n",
            False,
        ),
    ],
)
def test_a_bounded_poll_for_the_first_message_counts_as_waiting_for_it(
    move_forward: tuple[Capability, SkillSpec], poll: str, waits: bool
) -> None:
    read = "        speed = self.odom_msg.twist.twist.linear.x\n"
    source = _execute_starting_with(poll + read, starting_waits=False)
    line = source.splitlines().index(read.rstrip("\n")) + 1
    flagged = [f for f in _waits(source, move_forward) if f.line == line]
    assert bool(flagged) is not waits
