"""Behaviour mutants of the shipped MR-1 skills: mistakes a run alone does not reveal.

Each one plants a behavioural mistake in one of the nine skills of ``capabilities/skills``
— a wrong sign, an input it ignores, a stop that does not stop, a speed over the limit, a
drive into the obstacle, an output it makes up, a turn the other way round to the same
heading, a pose read in the odometry frame for the map frame — and names the scenario
that shows it and the oracles meant for that kind of mistake. ``bench/behaviour_catch_rate.py`` runs them
all and prints the catch rate; ``test_mutants.py`` checks that every edit still applies.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tests.conftest import SHIPPED_CAPABILITIES

SKILLS = SHIPPED_CAPABILITIES / "skills"

KINDS = (
    "wrong sign",
    "ignores an input",
    "never stops",
    "exceeds the speed limit",
    "drives into the obstacle",
    "made-up output",
    "out of its range",
    "keeps invalid readings",
    "the other way round",
    "the wrong frame",
)


@dataclass(frozen=True)
class BehaviourMutant:
    """One behavioural mistake planted in one skill."""

    skill: str
    kind: str
    scenario: str
    """The scenario of ``sim/scenarios`` that shows the mistake."""
    edits: tuple[tuple[str, str], ...]
    oracles: tuple[str, ...]
    """Oracle ids (or their prefix before ``:``) meant to catch it; any one suffices."""

    @property
    def id(self) -> str:
        """``skill:kind``."""
        return f"{self.skill}:{self.kind.replace(' ', '-')}"

    @property
    def capability(self) -> Path:
        """The capability model of the skill."""
        return SHIPPED_CAPABILITIES / f"{self.skill.replace('_', '-')}.ttl"

    def source(self) -> str:
        """The mutated skill's text (each edit must apply)."""
        text = (SKILLS / f"{self.skill}.py").read_text(encoding="utf-8")
        for old, new in self.edits:
            if old not in text:
                raise AssertionError(f"{self.id}: {old!r} is not in {self.skill}.py")
            text = text.replace(old, new)
        return text

    def caught_by(self, failed: set[str]) -> bool:
        """Whether one of the failed oracles is one meant for this mistake."""
        return any(o in failed or o in {f.split(":")[0] for f in failed} for o in self.oracles)


_ZERO = "            self.cmd_vel_publisher.publish(Twist())\n"

MUTANTS: tuple[BehaviourMutant, ...] = (
    # move_forward
    BehaviourMutant(
        "move_forward",
        "wrong sign",
        "straight_ahead",
        (("command.linear.x = min(speed", "command.linear.x = -min(speed"),),
        ("truth:distanceCovered", "output:outDistance"),
    ),
    BehaviourMutant(
        "move_forward",
        "ignores an input",
        "straight_ahead",
        (
            (
                "while self.moving and self._travelled() < self.in_distance:",
                "while self.moving and self._travelled() < 1.0:",
            ),
        ),
        ("truth:distanceCovered",),
    ),
    BehaviourMutant(
        "move_forward",
        "never stops",
        "straight_ahead",
        ((_ZERO, "            pass\n"),),
        ("rest:completing", "rest:stopping"),
    ),
    BehaviourMutant(
        "move_forward",
        "exceeds the speed limit",
        "too_fast_asked",
        (("LINEAR_VELOCITY_MAX = 0.8", "LINEAR_VELOCITY_MAX = 1.5"),),
        ("limit:linearVelocity",),
    ),
    BehaviourMutant(
        "move_forward",
        "made-up output",
        "straight_ahead",
        (
            (
                "self.out_linear_velocity = self.odom_msg.twist.twist.linear.x",
                "self.out_linear_velocity = self.in_linear_velocity",
            ),
        ),
        ("assured:outLinearVelocity", "output:outLinearVelocity"),
    ),
    # rotate
    BehaviourMutant(
        "rotate",
        "wrong sign",
        "quarter_left",
        (
            ("self.remaining = self.in_angle - turned", "self.remaining = -self.in_angle - turned"),
            (
                "direction = 1.0 if self.in_angle >= 0.0 else -1.0",
                "direction = -1.0 if self.in_angle >= 0.0 else 1.0",
            ),
        ),
        ("truth:headingTarget", "constraint:headingTarget"),
    ),
    BehaviourMutant(
        "rotate",
        "ignores an input",
        "long_way_clockwise",
        (
            ("self.remaining = self.in_angle - turned", "self.remaining = -1.0 - turned"),
            ("direction = 1.0 if self.in_angle >= 0.0 else -1.0", "direction = -1.0"),
        ),
        ("truth:headingTarget", "constraint:headingTarget"),
    ),
    BehaviourMutant(
        "rotate",
        "the other way round",
        "long_way_clockwise",
        (
            (
                "self.remaining = self.in_angle - turned",
                "self.remaining = math.remainder(self.in_angle, 2.0 * math.pi) - turned",
            ),
            (
                "direction = 1.0 if self.in_angle >= 0.0 else -1.0",
                "direction = 1.0 if math.remainder(self.in_angle, 2.0 * math.pi) >= 0.0 else -1.0",
            ),
        ),
        ("asked:inAngle",),
    ),
    BehaviourMutant(
        "rotate",
        "never stops",
        "quarter_left",
        ((_ZERO, "            pass\n"),),
        ("rest:completing", "rest:stopping"),
    ),
    BehaviourMutant(
        "rotate",
        "exceeds the speed limit",
        "long_way_clockwise",
        (("ANGULAR_VELOCITY_MAX = 1.2", "ANGULAR_VELOCITY_MAX = 2.5"),),
        ("limit:angularVelocity",),
    ),
    BehaviourMutant(
        "rotate",
        "out of its range",
        "long_way_clockwise",
        (
            (
                "self.out_heading = self._heading() % (2.0 * math.pi)",
                "self.out_heading = self._heading()",
            ),
        ),
        ("constraint:headingNotNegative",),
    ),
    BehaviourMutant(
        "rotate",
        "made-up output",
        "quarter_left",
        (
            (
                "self.out_heading = self._heading() % (2.0 * math.pi)",
                "self.out_heading = self.in_angle % (2.0 * math.pi)",
            ),
        ),
        ("output:outHeading",),
    ),
    # set_velocity
    BehaviourMutant(
        "set_velocity",
        "wrong sign",
        "arc",
        (
            (
                "self.out_angular_velocity = twist.angular.z",
                "self.out_angular_velocity = -twist.angular.z",
            ),
        ),
        ("output:outAngularVelocity",),
    ),
    BehaviourMutant(
        "set_velocity",
        "never stops",
        "arc",
        (
            (
                "        for _ in range(3):\n            self._publish_zero()\n            time.sleep(0.05)",
                "        for _ in range(3):\n            time.sleep(0.05)",
            ),
        ),
        ("rest:stopping",),
    ),
    BehaviourMutant(
        "set_velocity",
        "exceeds the speed limit",
        "clipped",
        (("LINEAR_VELOCITY_MAX = 0.8", "LINEAR_VELOCITY_MAX = 2.0"),),
        ("limit:linearVelocity",),
    ),
    BehaviourMutant(
        "set_velocity",
        "made-up output",
        "arc",
        (("self.out_linear_velocity = twist.linear.x", "self.out_linear_velocity = linear + 0.3"),),
        ("output:outLinearVelocity", "constraint:linearVelocityClipped"),
    ),
    # collision_avoidance
    BehaviourMutant(
        "collision_avoidance",
        "drives into the obstacle",
        "obstacle_ahead",
        (("if distance < self.in_min_obstacle_distance:", "if distance < 0.0:"),),
        ("contact",),
    ),
    BehaviourMutant(
        "collision_avoidance",
        "ignores an input",
        "obstacle_ahead",
        (("if distance < self.in_min_obstacle_distance:", "if distance < 0.2:"),),
        ("requirement:inMinObstacleDistance",),
    ),
    BehaviourMutant(
        "collision_avoidance",
        "never stops",
        "time_runs_out",
        ((_ZERO, "            pass\n"),),
        ("rest:completing", "rest:stopping"),
    ),
    BehaviourMutant(
        "collision_avoidance",
        "exceeds the speed limit",
        "time_runs_out",
        (("command.linear.x = vx", "command.linear.x = vx * 3.0"),),
        ("limit:linearVelocity",),
    ),
    BehaviourMutant(
        "collision_avoidance",
        "made-up output",
        "obstacle_ahead",
        (
            (
                "self.out_duration = time.monotonic() - started",
                "self.out_duration = self.in_duration",
            ),
        ),
        ("output:outDuration",),
    ),
    # navigate_to_point
    BehaviourMutant(
        "navigate_to_point",
        "wrong sign",
        "around_the_shelf",
        (
            (
                "goal.pose.pose.position.y = self.in_position_y",
                "goal.pose.pose.position.y = -self.in_position_y",
            ),
        ),
        ("truth:goalYReached", "constraint:goalYReached"),
    ),
    BehaviourMutant(
        "navigate_to_point",
        "ignores an input",
        "around_the_shelf",
        (("goal.pose.pose.position.x = self.in_position_x", "goal.pose.pose.position.x = 3.0"),),
        ("truth:goalXReached", "constraint:goalXReached"),
    ),
    BehaviourMutant(
        "navigate_to_point",
        "never stops",
        "around_the_shelf",
        (
            (
                "            self._wait(self.goal_handle.cancel_goal_async(), timeout=2.0)\n",
                "            pass\n",
            ),
        ),
        ("rest:stopping",),
    ),
    BehaviourMutant(
        "navigate_to_point",
        "made-up output",
        "around_the_shelf",
        (
            (
                "self.out_position_x, self.out_position_y, _ = self._robot_pose()",
                "self.out_position_x, self.out_position_y = 6.0, 0.0",
            ),
        ),
        ("output:outPositionX", "output:outPositionY"),
    ),
    # get_position
    BehaviourMutant(
        "get_position",
        "wrong sign",
        "in_the_room",
        (
            (
                "self.out_heading = yaw % (2.0 * math.pi)",
                "self.out_heading = -yaw % (2.0 * math.pi)",
            ),
        ),
        ("output:outHeading", "constraint:headingReported"),
    ),
    BehaviourMutant(
        "get_position",
        "out of its range",
        "heading_wraps",
        (("self.out_heading = yaw % (2.0 * math.pi)", "self.out_heading = yaw"),),
        ("constraint:headingNotNegative",),
    ),
    BehaviourMutant(
        "get_position",
        "made-up output",
        "in_the_room",
        (("self.out_position_y = translation.y", "self.out_position_y = 0.0"),),
        ("output:outPositionY", "constraint:positionYReported"),
    ),
    # get_distance_to_nearest_object
    BehaviourMutant(
        "get_distance_to_nearest_object",
        "wrong sign",
        "wall_to_the_right",
        (
            (
                "self.out_angle = math.atan2(math.sin(bearing), math.cos(bearing))",
                "self.out_angle = -math.atan2(math.sin(bearing), math.cos(bearing))",
            ),
        ),
        ("output:outAngle",),
    ),
    BehaviourMutant(
        "get_distance_to_nearest_object",
        "keeps invalid readings",
        "dropouts",
        (
            (
                "if math.isfinite(distance) and scan.range_min <= distance <= scan.range_max:",
                "if distance == distance:",
            ),
        ),
        ("output:outDistance",),
    ),
    BehaviourMutant(
        "get_distance_to_nearest_object",
        "made-up output",
        "obstacle_ahead",
        (("        self.out_distance = distance\n", "        self.out_distance = 1.0\n"),),
        ("output:outDistance",),
    ),
    # move_to_point
    BehaviourMutant(
        "move_to_point",
        "wrong sign",
        "within_reach",
        (("target.position.y = self.in_position_y", "target.position.y = -self.in_position_y"),),
        ("truth:targetYReached", "constraint:targetYReached"),
    ),
    BehaviourMutant(
        "move_to_point",
        "ignores an input",
        "within_reach",
        (("target.position.z = self.in_position_z", "target.position.z = 0.5"),),
        ("truth:targetZReached", "constraint:targetZReached"),
    ),
    BehaviourMutant(
        "move_to_point",
        "made-up output",
        "within_reach",
        (("self.out_position_x = translation.x", "self.out_position_x = 0.3"),),
        ("output:outPositionX", "constraint:targetXReached"),
    ),
    # the odometry frame for the map frame: they coincide only where the robot was switched on
    BehaviourMutant(
        "rotate",
        "the wrong frame",
        "quarter_left",
        (('MAP_FRAME = "map"', 'MAP_FRAME = "odom"'),),
        ("constraint:headingTarget", "output:outHeading"),
    ),
    BehaviourMutant(
        "get_position",
        "the wrong frame",
        "in_the_room",
        (('MAP_FRAME = "map"', 'MAP_FRAME = "odom"'),),
        ("output:outPositionX", "output:outPositionY", "output:outHeading"),
    ),
    # mapping
    BehaviourMutant(
        "mapping",
        "never stops",
        "sweep_the_room",
        (
            (
                "            self._wait(self.goal_handle.cancel_goal_async(), 2.0)\n",
                "            pass\n",
            ),
        ),
        ("rest:stopping",),
    ),
    BehaviourMutant(
        "mapping",
        "made-up output",
        "sweep_the_room",
        (
            (
                "self.out_map_length = along",
                "self.out_map_length = self.in_area_length",
            ),
        ),
        ("output:outMapLength",),
    ),
)
