"""The child's stand-ins of rclpy, tf2_ros, pySkillUp and the message packages behave as
the real ones do where skills notice, in virtual time (``skills/probe.py`` logs what it sees)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.run import run_skill
from tests.runtime.conftest import quick

PROBE = Path(__file__).parent / "skills" / "probe.py"


def test_probe_sees_rclpy_semantics_in_virtual_time(mr1_inventory: Inventory) -> None:
    report = run_skill(PROBE, mr1_inventory, scenario=quick())

    assert report.findings == []
    logs = [e["text"] for e in report.trace.episodes[0].events if e["kind"] == "log"]
    assert logs == [
        "sleep 0.500",
        "timer 5",
        "rate 0.50",
        "spin_once 1 360",
        "wait_for_message True odom",
        "event False 0.30",
        "event set True",
        "clock True 2026",
        "duration 2000000000",
        "service ready True",
        "future done at once False None",
        "response ListControllers_Response",
        "twist 1.0 0.0",
        "assert The 'x' field must be of type 'float'",
        "constructor Invalid arguments passed to constructor: speed",
        "field 'Odometry' object has no attribute 'position' (nav_msgs/msg/Odometry has: "
        "header, child_frame_id, pose, twist)",
        "copy True",
        "fields {'linear': 'geometry_msgs/Vector3', 'angular': 'geometry_msgs/Vector3'}",
        "constant 4",
        "covariance 36 True",
        "logger TypeError",
        "publish Expected <class 'geometry_msgs.msg.Twist'>, got <class 'geometry_msgs.msg.Vector3'>",
        # the robot's endpoints (discovery names no node) and the skill's own, with its QoS
        "odom publishers [('_NODE_NAME_UNKNOWN_', 'nav_msgs/msg/Odometry', 'RELIABLE')]",
        "cmd_vel publishers [('probe', 'PUBLISHER', 10), ('_NODE_NAME_UNKNOWN_', 'PUBLISHER', 0)]",
        "scan subscriptions ['_NODE_NAME_UNKNOWN_', 'probe']",
        "parameters ['speed', 'turn']",
        "parameters ['speed'] [('probe', '/')]",
        # tf2's words for a frame that does not exist, and the frames the robot has
        "tf ['arm_base_link', 'base_link']",
    ]


def test_the_product_never_imports_the_stand_ins() -> None:
    code = (
        "import sys\n"
        "import skillwright.runtime.run, skillwright.runtime.commands, skillwright.runtime.session\n"
        "import skillwright.runtime.worlds.kinematic\n"
        "names = ('rclpy', 'tf2_ros', 'pyskillup', '_skillwright_child')\n"
        "print([m for m in sys.modules if m.split('.')[0] in names or '.child' in m])\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    assert result.stdout.strip() == "[]"
