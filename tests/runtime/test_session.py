"""What one episode turns into findings: errors at the skill's line, deadlines, silence,
and a child that breaks the protocol."""

from __future__ import annotations
import __future__

import base64
import json
import marshal
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.report import RunReport
from skillwright.runtime.run import run_skill
from skillwright.runtime.sandbox import CHILD_ROOT
from skillwright.runtime.session import compiled
from tests.runtime.conftest import SKILLS, quick

HEAD = """import os
import sys
import time

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface
{imports}

@skill(skill_interface=SkillInterface.REST, skill_iri="urn:s", module_iri="urn:m",
       capability_iri="urn:c", description="a test skill")
class Subject(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("subject")
        self.messages = []

    @execute
    def execute(self) -> None:
{body}
"""


def run(inventory: Inventory, body: str, imports: str = "") -> tuple[RunReport, str]:
    source = HEAD.format(imports=imports, body=body)
    return run_skill(Path("subject.py"), inventory, source=source, scenario=quick()), source


def line_of(source: str, text: str) -> int:
    return next(n for n, line in enumerate(source.splitlines(), start=1) if text in line)


@pytest.mark.parametrize(
    ("imports", "message"),
    [
        (
            "from nav2_msgs.action import DockRobot",
            "the robot has no type nav2_msgs/action/DockRobot",
        ),
        ("import acme_msgs.msg", "the robot has no ROS 2 package acme_msgs"),
    ],
)
def test_importing_what_the_robot_lacks_is_reported_at_the_import(
    mr1_inventory: Inventory, imports: str, message: str
) -> None:
    report, source = run(mr1_inventory, "        pass", imports)

    [finding] = report.findings
    assert (finding.check, finding.line) == ("run.import", line_of(source, imports))
    assert message in finding.message
    assert report.trace.episodes[0].states == []


def test_an_exception_in_a_callback_is_reported_at_the_callbacks_line(
    mr1_inventory: Inventory,
) -> None:
    body = (
        "        from nav_msgs.msg import Odometry\n"
        "        self.node.create_subscription(Odometry, '/odom', lambda m: 1 / 0, 10)\n"
        "        time.sleep(0.5)\n"
    )
    report, source = run(mr1_inventory, body)

    assert [(f.check, f.line) for f in report.findings] == [
        ("run.exception", line_of(source, "1 / 0"))
    ]
    assert "ZeroDivisionError" in report.findings[0].message


def test_an_exception_in_a_helper_carries_the_lines_of_the_calls_that_led_there(
    mr1_inventory: Inventory,
) -> None:
    source = HEAD.format(imports="", body="        self._outer()\n").replace(
        "    @execute\n",
        "    def _inner(self) -> None:\n"
        "        raise RuntimeError('no result')\n\n"
        "    def _outer(self) -> None:\n"
        "        self._inner()\n\n"
        "    @execute\n",
    )
    report = run_skill(Path("subject.py"), mr1_inventory, source=source, scenario=quick())

    [finding] = report.findings
    assert finding.line == line_of(source, "raise RuntimeError('no result')")
    assert finding.stack == (
        line_of(source, "        self._outer()"),
        line_of(source, "self._inner()"),
    )


def test_a_state_that_waits_forever_times_out_where_it_waits(mr1_inventory: Inventory) -> None:
    report, source = run(mr1_inventory, "        time.sleep(1000.0)")

    [finding] = report.findings
    assert (finding.check, finding.line) == ("run.timeout", line_of(source, "time.sleep(1000.0)"))
    assert "within 10 s of virtual time" in finding.message
    assert report.trace.episodes[0].virtual_seconds == pytest.approx(10.0, abs=0.5)


def test_a_loop_that_publishes_but_never_waits_is_interrupted_as_busy_at_its_line(
    mr1_inventory: Inventory,
) -> None:
    # The child talks all the time, so it is never quiet; virtual time standing still is
    # what gives it away, well before the sandbox's CPU limit. The interrupt mostly comes
    # while it publishes, and must still say where it was.
    body = (
        "        from geometry_msgs.msg import Twist\n"
        "        publisher = self.node.create_publisher(Twist, '/cmd_vel', 10)\n"
        "        while True:\n"
        "            publisher.publish(Twist())\n"
    )
    report, source = run(mr1_inventory, body)

    [finding] = report.findings
    assert (finding.check, finding.line) == ("run.busy", line_of(source, "publisher.publish("))
    states = [(s.name, s.outcome, s.detail) for s in report.trace.episodes[0].states]
    assert ("execute", "interrupted", "busy") in states
    assert report.trace.episodes[0].wall_seconds < 20.0


def test_waiting_for_a_topic_nobody_publishes_names_the_topic(mr1_inventory: Inventory) -> None:
    body = (
        "        from geometry_msgs.msg import PoseStamped\n"
        "        self.node.create_subscription(PoseStamped, '/goal_pose', self.messages.append, 10)\n"
        "        time.sleep(2.0)\n"
        "        if not self.messages:\n"
        "            raise RuntimeError('no goal pose')\n"
    )
    report, source = run(mr1_inventory, body)

    checks = {(f.check, f.severity, f.line) for f in report.findings}
    assert ("run.exception", "error", line_of(source, "raise RuntimeError")) in checks
    assert ("run.no_data", "warning", line_of(source, "create_subscription")) in checks


@pytest.mark.parametrize(("patience", "still_running"), [(1.0, True), (9.0, False)])
def test_a_result_wait_that_gives_up_on_a_running_goal_says_the_wait_was_too_short(
    mr1_inventory: Inventory, patience: float, still_running: bool
) -> None:
    # The skeleton's result helper, and a goal 2 m away: the kinematic world's Nav2 needs
    # longer than a second for it and reaches it within nine (then the skill raises anyway).
    body = (
        "        from nav2_msgs.action import NavigateToPose\n"
        "        from rclpy.action import ActionClient\n"
        "        client = ActionClient(self.node, NavigateToPose, '/navigate_to_pose')\n"
        "        goal = NavigateToPose.Goal()\n"
        "        goal.pose.header.frame_id = 'map'\n"
        "        goal.pose.pose.position.x = 2.0\n"
        "        goal.pose.pose.orientation.w = 1.0\n"
        "        sent = client.send_goal_async(goal)\n"
        "        while not sent.done():\n"
        "            time.sleep(0.02)\n"
        "        result = sent.result().get_result_async()\n"
        f"        deadline = time.monotonic() + {patience}\n"
        "        while not result.done():\n"
        "            if time.monotonic() > deadline:\n"
        f"                raise RuntimeError('no result of the /navigate_to_pose goal within {patience:g} s')\n"
        "            time.sleep(0.02)\n"
        "        raise RuntimeError('no result of the /navigate_to_pose goal within 0 s')\n"
    )
    source = HEAD.format(imports="", body=body)
    report = run_skill(
        Path("subject.py"), mr1_inventory, source=source, scenario=quick(world="kinematic")
    )

    [finding] = [f for f in report.findings if f.check == "run.exception"]
    assert "no result of the /navigate_to_pose goal" in finding.message
    assert ("the /navigate_to_pose goal was still running" in finding.message) is still_running
    if still_running:
        assert (
            f"it gave up after {patience:g} s while the /navigate_to_pose goal was still "
            "running: the result wait was too short" in finding.message
        )


_GIVE_UP = "                raise RuntimeError('the motion was not finished within 2 s')\n"


@pytest.mark.parametrize(
    ("motion", "under_way"),
    [
        (  # MR-1 rotate: its own loop drives the base, stops it, and gives up after 2 s
            "        from geometry_msgs.msg import Twist\n"
            "        cmd = self.node.create_publisher(Twist, '/cmd_vel', 10)\n"
            "        deadline = time.monotonic() + 2.0\n"
            "        while True:\n"
            "            turn = Twist()\n"
            "            turn.angular.z = 0.3\n"
            "            cmd.publish(turn)\n"
            "            if time.monotonic() > deadline:\n"
            "                cmd.publish(Twist())\n" + _GIVE_UP + "            time.sleep(0.05)\n",
            "the base was still moving on its commands on /cmd_vel",
        ),
        (  # MR-1 navigate-to-point: cancels the goal Nav2 is still driving, then gives up
            "        from nav2_msgs.action import NavigateToPose\n"
            "        from rclpy.action import ActionClient\n"
            "        client = ActionClient(self.node, NavigateToPose, '/navigate_to_pose')\n"
            "        goal = NavigateToPose.Goal()\n"
            "        goal.pose.header.frame_id = 'map'\n"
            "        goal.pose.pose.position.x = 3.0\n"
            "        goal.pose.pose.orientation.w = 1.0\n"
            "        sent = client.send_goal_async(goal)\n"
            "        while not sent.done():\n"
            "            time.sleep(0.02)\n"
            "        handle = sent.result()\n"
            "        deadline = time.monotonic() + 2.0\n"
            "        while True:\n"
            "            if time.monotonic() > deadline:\n"
            "                handle.cancel_goal_async()\n"
            "                time.sleep(0.1)\n" + _GIVE_UP + "            time.sleep(0.05)\n",
            "the /navigate_to_pose goal was still running (the skill cancelled it)",
        ),
        (  # nothing moves: the message stays as the skill wrote it
            "        deadline = time.monotonic() + 2.0\n"
            "        while True:\n"
            "            if time.monotonic() > deadline:\n"
            + _GIVE_UP
            + "            time.sleep(0.05)\n",
            None,
        ),
    ],
    ids=["velocity", "cancelled goal", "no motion"],
)
def test_a_state_that_gives_up_on_a_motion_under_way_is_told_its_timeout_was_too_short(
    mr1_inventory: Inventory, motion: str, under_way: str | None
) -> None:
    source = HEAD.format(imports="", body=motion)
    report = run_skill(
        Path("subject.py"), mr1_inventory, source=source, scenario=quick(world="kinematic")
    )

    [finding] = [f for f in report.findings if f.check == "run.exception"]
    assert finding.message.startswith(
        "execute raised RuntimeError: the motion was not finished within 2 s"
    )
    if under_way is None:
        assert finding.message.endswith("within 2 s")
    else:
        assert f"; it gave up after 2 s while {under_way}: its timeout" in finding.message
        assert "its timeout was too short" in finding.message


def test_a_skill_that_writes_garbage_to_the_runtimes_socket_is_a_protocol_finding(
    mr1_inventory: Inventory,
) -> None:
    body = (
        "        sockets = [f for f in range(3, 64) if _socket(f)]\n"
        "        os.write(sockets[0], b'\\x7f\\xff\\xff\\xff' + b'x' * 64)\n"
        "        time.sleep(0.1)"
    )
    imports = (
        "import stat\n\n\ndef _socket(fd):\n    try:\n"
        "        return stat.S_ISSOCK(os.fstat(fd).st_mode)\n    except OSError:\n"
        "        return False\n"
    )
    report, _ = run(mr1_inventory, body, imports)

    assert [f.check for f in report.findings] == ["run.protocol"]
    assert report.trace.episodes[0].ended == "protocol"


def test_importing_types_costs_one_exchange_per_imported_type(
    mr1_inventory: Inventory, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.runtime.session import Episode

    asked: list[str] = []
    real_dispatch = Episode._dispatch

    def dispatch(episode: Episode, frame: dict[str, Any]) -> dict[str, Any] | None:
        if frame["op"] in {"type", "package"}:
            asked.append(f"{frame['op']} {frame['name']}")
        return real_dispatch(episode, frame)

    monkeypatch.setattr(Episode, "_dispatch", dispatch)
    body = "        goal = MoveGroup.Goal()\n        self.messages.append(goal.request.group_name)"
    report, _ = run(mr1_inventory, body, "from moveit_msgs.action import MoveGroup")

    assert report.findings == []
    assert asked == ["type moveit_msgs/action/MoveGroup"]


QUIET_BODY = """        self.node.create_subscription(Odometry, '/odom', self.{callback}, 10)
        for _ in range(10):
            time.sleep(0.1)
        stamp = self.last.header.stamp
        self.node.get_logger().info(f'last odometry {{stamp.sec}}.{{stamp.nanosec:09d}}')
"""
CALLBACKS = {
    # Only stores what it gets: nothing it does can reach the host before the sleep ends.
    "_store": "    def _store(self, msg) -> None:\n        self.last = msg\n",
    # Logs (a call): it could as well publish, so every delivery is answered in lockstep.
    "_log": (
        "    def _log(self, msg) -> None:\n"
        "        self.last = msg\n"
        "        self.node.get_logger().debug('odometry')\n"
    ),
}


def test_waits_whose_callbacks_only_store_take_one_exchange_and_see_the_same(
    mr1_inventory: Inventory, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.runtime.session import Episode

    batches: list[bool] = []
    real_dispatch = Episode._dispatch

    def dispatch(episode: Episode, frame: dict[str, Any]) -> dict[str, Any] | None:
        if frame["op"] == "advance" and frame.get("reason") == "sleep":
            batches.append(frame.get("batch") is True)
        return real_dispatch(episode, frame)

    monkeypatch.setattr(Episode, "_dispatch", dispatch)
    seen: dict[str, list[str]] = {}
    exchanges: dict[str, list[bool]] = {}
    for callback, method in CALLBACKS.items():
        batches.clear()
        source = HEAD.format(
            imports="from nav_msgs.msg import Odometry", body=QUIET_BODY.format(callback=callback)
        ).replace("    @execute", method + "\n    @execute")
        report = run_skill(Path("subject.py"), mr1_inventory, source=source, scenario=quick())
        assert report.findings == []
        events = report.trace.episodes[0].events
        seen[callback] = [e["text"] for e in events if e["kind"] == "log" and e["level"] == "info"]
        exchanges[callback] = list(batches)

    assert seen["_store"] == seen["_log"]
    assert seen["_store"][0].startswith("last odometry ")
    assert exchanges["_store"] == [True] * 10
    assert not any(exchanges["_log"])
    assert len(exchanges["_log"]) > 20, "lockstep: about one exchange per two odometry messages"


QUIET_CASES = """
import json, sys
sys.path.insert(0, sys.argv[1])
from _skillwright_child.core import quiet

class Skill:
    def store(self, msg):
        self.last = msg
    def store_constant(self, msg):
        self.seen = True
    def count(self, msg):
        self.count += 1
    def call(self, msg):
        self.last = msg
        print(msg)
    def store_elsewhere(self, msg):
        msg.seen = self

class Setter(Skill):
    def __setattr__(self, name, value):
        object.__setattr__(self, name, value)

class Property(Skill):
    @property
    def last(self):
        return 0
    @last.setter
    def last(self, value):
        print(value)

def function(msg):
    return None

skill, setter, prop = Skill(), Setter(), Property()
print(json.dumps([
    quiet(skill.store), quiet(skill.store_constant), quiet(skill.count), quiet(skill.call),
    quiet(skill.store_elsewhere), quiet(setter.store), quiet(prop.store), quiet(function),
    quiet(lambda msg: None), quiet(print),
]))
"""


def test_only_callbacks_that_store_on_their_own_object_are_quiet() -> None:
    found = subprocess.run(
        [sys.executable, "-I", "-S", "-c", QUIET_CASES, str(CHILD_ROOT)],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(found.stdout) == [
        True,  # self.last = msg
        True,  # self.seen = True
        False,  # self.count += 1 reads an attribute (could be a property)
        False,  # calls something
        False,  # stores on the message, not on its own object
        False,  # its class has its own __setattr__
        False,  # the attribute is a property of the skill
        False,  # not a method
        False,  # a lambda is not a method
        False,  # a builtin
    ]


def test_the_host_compiles_a_skill_once_as_the_child_would() -> None:
    source = (SKILLS / "move_forward.py").read_text(encoding="utf-8")
    packed = compiled(source)
    assert packed is not None
    assert compiled(source) is packed
    code = marshal.loads(base64.b64decode(packed))
    # The child's driver module has `from __future__ import annotations`, which its own
    # compile() inherits: the host's code must carry it too.
    assert code.co_flags & __future__.annotations.compiler_flag
    assert compiled("def broken(:\n") is None


@pytest.mark.parametrize(
    ("raised", "data"),
    [
        (
            "RuntimeError('not turned within 2 s')",
            {"state": "execute", "type": "RuntimeError", "seconds": 2.0},
        ),
        (
            "RuntimeError('no odometry on /odom within 0.5 s')",
            {"state": "execute", "type": "RuntimeError", "seconds": 0.5},
        ),
        ("ValueError('not a number')", {"state": "execute", "type": "ValueError"}),
    ],
)
def test_a_raised_state_says_in_its_data_how_long_its_wait_gave_up_after(
    mr1_inventory: Inventory, raised: str, data: dict[str, object]
) -> None:
    report, _ = run(mr1_inventory, f"        raise {raised}")

    [finding] = [f for f in report.findings if f.check == "run.exception"]
    assert {k: finding.data.get(k) for k in data} == data
    assert "seconds" in finding.data or "seconds" not in data
