"""Mutants of the shipped MR-1 skills: the mistakes LLMs make, each one edit away.

Each mutant names the skill, the kind of mistake, the edits (old text -> new text, each
old text present in the skill) and the run setting it needs. ``test_mutants.py`` runs
them; ``bench/mutation_rate.py`` prints the catch rate per kind.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tests.conftest import SHIPPED_CAPABILITIES

SKILLS = SHIPPED_CAPABILITIES / "skills"

KINDS = (
    "wrong topic",
    "wrong field",
    "missing stop",
    "hard-coded input",
    "never returns",
    "wrong QoS",
)


@dataclass(frozen=True)
class Mutant:
    """One mistake planted in one skill."""

    skill: str
    kind: str
    edits: tuple[tuple[str, str], ...]
    hardcode: tuple[str, str] | None = None
    """``(attribute, literal)``: every use of ``self.<attribute>`` in the states becomes the literal."""

    @property
    def id(self) -> str:
        return f"{self.skill}:{self.kind.replace(' ', '-')}"

    def source(self) -> str:
        """The mutated skill's text."""
        text = (SKILLS / f"{self.skill}.py").read_text(encoding="utf-8")
        for old, new in self.edits:
            if old not in text:
                raise AssertionError(f"{self.id}: {old!r} is not in {self.skill}.py")
            text = text.replace(old, new)
        if self.hardcode is not None:
            attribute, literal = self.hardcode
            head, marker, states = text.partition("    @starting")
            uses = f"self.{attribute}"
            if uses not in states:
                raise AssertionError(f"{self.id}: the states never use {uses}")
            text = head + marker + states.replace(uses, literal)
        return text

    @property
    def path(self) -> Path:
        return SKILLS / f"{self.skill}.py"


def _never(old: str, new: str) -> tuple[tuple[str, str], ...]:
    return ((old, new),)


MUTANTS: tuple[Mutant, ...] = (
    # set_velocity
    Mutant("set_velocity", "wrong topic", (('"/cmd_vel"', '"/cmd_vel_mr1"'),)),
    Mutant(
        "set_velocity",
        "wrong field",
        (("twist = self.odom_msg.twist.twist", "twist = self.odom_msg.twist"),),
    ),
    Mutant(
        "set_velocity",
        "missing stop",
        (
            (
                "        for _ in range(3):\n            self._publish_zero()\n            time.sleep(0.05)",
                '        self.node.get_logger().info("stopping")',
            ),
        ),
    ),
    Mutant("set_velocity", "hard-coded input", (), hardcode=("in_linear_velocity", "0.3")),
    Mutant(
        "set_velocity",
        "never returns",
        (
            ("elif now - settled_since >= 0.5:", "elif now - settled_since >= 1e9:"),
            (
                "        while time.monotonic() < deadline:\n            twist",
                "        while True:\n            twist",
            ),
        ),
    ),
    # get_position
    Mutant("get_position", "wrong topic", (('MAP_FRAME = "map"', 'MAP_FRAME = "world"'),)),
    Mutant(
        "get_position",
        "wrong field",
        (("translation = transform.transform.translation", "translation = transform.translation"),),
    ),
    # navigate_to_point
    Mutant("navigate_to_point", "wrong topic", (('"/navigate_to_pose"', '"/navigate_to_goal"'),)),
    Mutant(
        "navigate_to_point",
        "wrong field",
        (
            (
                "goal.pose.pose.position.x = self.in_position_x",
                "goal.pose.position.x = self.in_position_x",
            ),
        ),
    ),
    Mutant(
        "navigate_to_point",
        "missing stop",
        (
            (
                "            self._wait(self.goal_handle.cancel_goal_async(), timeout=2.0)",
                '            self.node.get_logger().info("stopping")',
            ),
        ),
    ),
    Mutant("navigate_to_point", "hard-coded input", (), hardcode=("in_position_x", "2.0")),
    Mutant(
        "navigate_to_point",
        "never returns",
        _never("        while not future.done():", "        while True:"),
    ),
    # move_forward
    Mutant("move_forward", "wrong topic", (('"/cmd_vel"', '"/cmd_vel_mr1"'),)),
    Mutant(
        "move_forward",
        "wrong field",
        (
            (
                "position = self.odom_msg.pose.pose.position\n        return",
                "position = self.odom_msg.pose.position\n        return",
            ),
        ),
    ),
    Mutant(
        "move_forward",
        "missing stop",
        (
            (
                '        """Stop the forward command and publish a zero velocity at once."""\n        self._publish_zero()',
                '        """Stop the forward command and publish a zero velocity at once."""\n        self.moving = False',
            ),
        ),
    ),
    Mutant("move_forward", "hard-coded input", (), hardcode=("in_distance", "0.5")),
    Mutant(
        "move_forward",
        "never returns",
        _never(
            "while self.moving and self._travelled() < self.in_distance:",
            "while self.moving and self.in_distance >= 0.0:",
        ),
    ),
    # get_distance_to_nearest_object
    Mutant("get_distance_to_nearest_object", "wrong topic", (('"/scan"', '"/lidar/scan"'),)),
    Mutant(
        "get_distance_to_nearest_object",
        "wrong field",
        (("scan.angle_increment", "scan.angle_step"),),
    ),
    Mutant(
        "get_distance_to_nearest_object",
        "never returns",
        _never(
            "while self.scans == seen and time.monotonic() < deadline:", "while self.scans >= seen:"
        ),
    ),
    Mutant(
        "get_distance_to_nearest_object",
        "wrong QoS",
        (("self._on_scan, qos_profile_sensor_data", "self._on_scan, 10"),),
    ),
    # rotate
    Mutant("rotate", "wrong topic", (('"/cmd_vel"', '"/cmd_vel_mr1"'),)),
    Mutant(
        "rotate", "wrong field", (("q = transform.transform.rotation", "q = transform.rotation"),)
    ),
    Mutant(
        "rotate",
        "missing stop",
        (
            (
                '        """Publish a zero velocity at once."""\n        self._publish_zero()',
                '        """Publish a zero velocity at once."""\n        self.turning = False',
            ),
        ),
    ),
    Mutant("rotate", "hard-coded input", (), hardcode=("in_angle", "1.5708")),
    Mutant(
        "rotate",
        "never returns",
        _never(
            "while self.turning and abs(self.remaining) >= self.TOLERANCE:", "while self.turning:"
        ),
    ),
    # collision_avoidance
    Mutant("collision_avoidance", "wrong topic", (('"/cmd_vel"', '"/cmd_vel_mr1"'),)),
    Mutant("collision_avoidance", "wrong field", (("scan.angle_increment", "scan.angle_step"),)),
    Mutant(
        "collision_avoidance",
        "missing stop",
        (
            (
                '        """Publish a zero velocity at once and end the command loop."""\n        self._publish_zero()',
                '        """Publish a zero velocity at once and end the command loop."""\n        self.moving = False',
            ),
        ),
    ),
    Mutant(
        "collision_avoidance", "hard-coded input", (), hardcode=("in_min_obstacle_distance", "0.5")
    ),
    Mutant(
        "collision_avoidance",
        "never returns",
        _never(
            "if time.monotonic() - started >= self.in_duration:",
            "if time.monotonic() - started >= self.in_duration * 1e9:",
        ),
    ),
    Mutant(
        "collision_avoidance",
        "wrong QoS",
        (("self._on_scan, qos_profile_sensor_data", "self._on_scan, 10"),),
    ),
    # mapping
    Mutant("mapping", "wrong topic", (('"/map_saver/save_map"', '"/map_server/save_map"'),)),
    Mutant("mapping", "wrong field", (("/ info.resolution)", "/ info.cell_size)"),)),
    Mutant(
        "mapping",
        "missing stop",
        (
            (
                '        """Cancel the active navigation goal and publish a zero velocity."""\n        if self.goal_handle is not None:\n            self._wait(self.goal_handle.cancel_goal_async(), 2.0)',
                '        """Cancel the active navigation goal and publish a zero velocity."""',
            ),
        ),
    ),
    Mutant("mapping", "hard-coded input", (), hardcode=("in_area_length", "1.5")),
    Mutant(
        "mapping",
        "never returns",
        _never(
            "while (self.map_msg is None or self.scan_msg is None) and time.monotonic() < deadline:",
            "while self.map_msg is None or self.scan_msg is not None:",
        ),
    ),
    # move_to_point
    Mutant("move_to_point", "wrong topic", (('"/move_action"', '"/move_group"'),)),
    Mutant(
        "move_to_point",
        "wrong field",
        (
            (
                "constraint.constraint_region.primitive_poses = [target]",
                "constraint.constraint_region.poses = [target]",
            ),
        ),
    ),
    Mutant(
        "move_to_point",
        "missing stop",
        (
            (
                '        """Cancel the active move-group goal so the arm halts where it is."""\n        if self.goal_handle is not None and self.goal_handle.accepted:\n            self._wait(self.goal_handle.cancel_goal_async(), 2.0)',
                '        """Cancel the active move-group goal so the arm halts where it is."""',
            ),
        ),
    ),
    Mutant("move_to_point", "hard-coded input", (), hardcode=("in_position_z", "0.4")),
    Mutant(
        "move_to_point",
        "never returns",
        _never(
            "while not future.done() and time.monotonic() < deadline:",
            "while not future.done() or time.monotonic() < deadline:",
        ),
    ),
)
