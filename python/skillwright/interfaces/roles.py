"""Which part a robot's interface plays, by type and name, and the words that ask for it.

The worlds that stand in for the robot (the kinematic one of the run, MuJoCo's of the
simulation) take over its velocity command wherever the robot has it: ``/cmd_vel`` on the
MR-1, ``/panther/cmd_vel`` on a Husarion Panther, ``/stretch/cmd_vel`` on a Stretch.

:func:`interface_role` names what an interface is for a skill (a velocity command, an
odometry source, a laser scan, an action with a goal ...) from its ROS 2 type, which fixes
what its messages mean (REP 103/105, the message definitions of ``geometry_msgs``,
``nav_msgs``, ``sensor_msgs``, Nav2 and MoveIt), and gives the words with which a
specification or a capability model asks for that part: a skill that "watches the lidar"
calls for the scan, one that "publishes a zero command" for the velocity command. An
interface of a type no role covers (a Nav2 behaviour such as ``BackUp``, a map saver) is
asked for by its own name: the words of its type and of its name's parts.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass

__all__ = ["TWIST_TYPES", "Role", "command_topic", "interface_role", "normalised_words"]

TWIST_TYPES = frozenset({"geometry_msgs/msg/Twist", "geometry_msgs/msg/TwistStamped"})
"""The types a base's velocity command has."""

_COMMAND_NAMES: tuple[Callable[[str], bool], ...] = (
    lambda s: s == "cmd_vel",
    lambda s: s.startswith("cmd_vel") and "nav" not in s,
    lambda s: "cmd" in s and "nav" not in s,
    lambda s: "cmd" in s,
)
"""Tests of a Twist topic's last name part, best first (Nav2's ``cmd_vel_nav`` comes last:
the velocity smoother turns it into ``cmd_vel``)."""


def command_topic(twist_topics: Iterable[str]) -> str | None:
    """The base's velocity command among the robot's Twist topics: ``cmd_vel`` by name first,
    the shortest name among equals; ``None`` when no name says command."""
    names = list(twist_topics)
    for test in _COMMAND_NAMES:
        found = [n for n in names if test(n.rstrip("/").rsplit("/", 1)[-1])]
        if found:
            return min(found, key=lambda n: (len(n), n))
    return None


def normalised_words(text: str) -> str:
    """``text`` as lower-case words split at case changes and non-letters, one space apart:
    ``inLinearVelocity`` -> ``in linear velocity``, ``/map_saver/save_map`` -> ``map saver
    save map``; the form the cues of :class:`Role` are matched against."""
    spaced = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", " ", text)
    return " ".join(w for w in re.split(r"[^0-9A-Za-z]+", spaced.lower()) if w)


@dataclass(frozen=True)
class Role:
    """What an interface is for a skill, and the words that ask for it."""

    name: str
    """In words: ``velocity command``, ``odometry``, ``laser scan``."""
    cues: re.Pattern[str]
    """Matched against :func:`normalised_words` of a specification's or capability's text."""
    family: str | None = None
    """Roles that are different means to one end share a family (``arm motion``: MoveIt's
    planned motion or a joint trajectory)."""
    generic: re.Pattern[str] | None = None
    """Words that ask for the family's end without choosing a means ("move the arm")."""

    def called_for(self, words: str) -> str | None:
        """The first cue ``words`` (normalised) contain, or ``None``."""
        match = self.cues.search(words)
        return None if match is None else match.group(0)

    def called_for_generically(self, words: str) -> str | None:
        """The first of the family's generic cues ``words`` contain, or ``None``."""
        match = None if self.generic is None else self.generic.search(words)
        return None if match is None else match.group(0)


def _cues(*patterns: str) -> re.Pattern[str]:
    return re.compile(r"\b(?:" + "|".join(patterns) + r")", re.IGNORECASE)


_MOTION = (
    r"velocit",
    r"speed",
    r"driv",
    r"drove",
    r"mov(e|es|ed|ing)\b",
    r"motion",
    r"turn",
    r"rotat(e|es|ed|ing)\b",
    r"yaw rate",
    r"revers(e|es|ed|ing)\b",
    r"strafe",
    r"stop",
    r"halt",
    r"brak",
    r"cmd vel",
)
"""A base moves (and stops) by its velocity command: geometry_msgs/Twist on ``cmd_vel``.
A direction alone ("forward", "the closest return ahead") asks for no motion; "drive
forward" does, by its verb."""

_ARM = _cues(r"arm\b", r"manipulator", r"end effector", r"tool", r"tcp\b", r"gripper")
"""Words that ask for an arm's motion without saying by which means."""

_ROLES: tuple[tuple[frozenset[str], str | None, Role], ...] = (
    (
        TWIST_TYPES,
        "publish",
        Role("velocity command", _cues(*_MOTION)),
    ),
    (
        frozenset({"nav_msgs/msg/Odometry"}),
        "subscribe",
        # nav_msgs/Odometry: the base's pose in the odometry frame and its measured twist.
        Role(
            "odometry",
            _cues(
                r"odom",
                r"wheel",
                r"travel",
                r"covered",
                r"position",
                r"pose\b",
                r"heading",
                r"orientation",
                r"where",
                r"(current|actual|measured|final|reached) (forward |linear |angular )?"
                r"(speed|velocit|yaw rate)",
            ),
        ),
    ),
    (
        frozenset(
            {
                "geometry_msgs/msg/PoseStamped",
                "geometry_msgs/msg/PoseWithCovarianceStamped",
                "geometry_msgs/msg/Pose",
            }
        ),
        "subscribe",
        # A pose estimate (AMCL's amcl_pose, a localiser's pose): where the base is in a map.
        Role(
            "pose estimate",
            _cues(
                r"pose\b",
                r"position",
                r"locali[sz]",
                r"amcl",
                r"heading",
                r"orientation",
                r"where",
                r"map frame",
            ),
        ),
    ),
    (
        frozenset({"tf2_msgs/msg/TFMessage"}),
        "subscribe",
        # The transform tree: every frame's pose in every other (map, odom, base_link, tool0).
        Role(
            "transform tree",
            _cues(
                r"transform",
                r"tf2?\b",
                r"frame",
                r"base link",
                r"map\b",
                r"position",
                r"pose\b",
                r"heading",
                r"orientation",
                r"locali[sz]",
                r"where",
            ),
        ),
    ),
    (
        frozenset(
            {"sensor_msgs/msg/LaserScan", "sensor_msgs/msg/PointCloud2", "sensor_msgs/msg/Range"}
        ),
        "subscribe",
        # Range sensing: how far the nearest things are, by bearing.
        Role(
            "range sensor",
            _cues(
                r"lidar",
                r"laser",
                r"scan",
                r"sonar",
                r"range",
                r"obstacle",
                r"nearest",
                r"closest",
                r"clearance",
                r"collision",
                r"distance to",
                r"wall",
                r"point cloud",
                r"sees?\b",
                r"seen",
            ),
        ),
    ),
    (
        frozenset({"nav_msgs/msg/OccupancyGrid"}),
        "subscribe",
        Role("occupancy map", _cues(r"map", r"occupancy", r"grid")),
    ),
    (
        frozenset({"sensor_msgs/msg/Imu"}),
        "subscribe",
        Role("inertial measurement", _cues(r"imu", r"inertial", r"gyro", r"accelerat", r"tilt")),
    ),
    (
        frozenset({"sensor_msgs/msg/JointState", "control_msgs/msg/DynamicJointState"}),
        "subscribe",
        Role("joint states", _cues(r"joint", r"arm\b", r"manipulator", r"gripper", r"finger")),
    ),
    # An arm moves through MoveIt (a motion planned to a goal), by a joint trajectory (its
    # controller's action or topic) or by joint commands: a specification that names one
    # means has chosen it, one that only says "move the arm" has not.
    (
        frozenset({"moveit_msgs/action/MoveGroup", "moveit_msgs/action/ExecuteTrajectory"}),
        None,
        Role(
            "planned arm motion",
            _cues(r"move ?it", r"move group", r"planning group", r"motion plan", r"planned"),
            "arm motion",
            _ARM,
        ),
    ),
    (
        frozenset(
            {"control_msgs/action/FollowJointTrajectory", "trajectory_msgs/msg/JointTrajectory"}
        ),
        None,
        Role("joint trajectory", _cues(r"joint", r"trajector"), "arm motion", _ARM),
    ),
    (
        frozenset({"control_msgs/msg/JointJog", "std_msgs/msg/Float64MultiArray"}),
        "publish",
        Role("joint command", _cues(r"joint", r"jog", r"servo"), "arm motion", _ARM),
    ),
    (
        frozenset({"control_msgs/action/GripperCommand"}),
        None,
        Role("gripper", _cues(r"gripper", r"grip", r"grasp", r"finger", r"jaw")),
    ),
    (
        frozenset(
            {
                "nav2_msgs/action/NavigateToPose",
                "nav2_msgs/action/NavigateThroughPoses",
                "nav2_msgs/action/FollowWaypoints",
                "nav2_msgs/action/ComputePathToPose",
            }
        ),
        None,
        # Nav2's navigation: a goal pose (or several) the navigator plans to and follows.
        Role(
            "navigation goal",
            _cues(r"navigat", r"nav ?2", r"waypoint", r"goal pose"),
        ),
    ),
)


_JOIN = r"(?: (?:the|a|an|its))? ?"
"""Between the words of an interface's own phrase: together, apart or with an article
("backup", "back up"; "save the map", "dock the robot")."""

_VAGUE = frozenset({"data", "raw", "state", "states", "status", "info", "value", "values"})
"""Last name parts that say nothing of what an interface does (``/imu/data``)."""


def _long_type(type_name: str, kind: str) -> str:
    parts = [p for p in type_name.split("/") if p]
    if len(parts) == 2:
        sub = {"topic": "msg", "service": "srv", "action": "action"}.get(kind, "msg")
        return f"{parts[0]}/{sub}/{parts[1]}"
    return type_name


def interface_role(name: str, kind: str, type_name: str, direction: str) -> Role:
    """The role of the interface ``name`` (``kind`` topic, service or action, ROS 2
    ``type_name``, ``direction`` publish, subscribe or call) for a skill.

    A type the table above knows gets its role (a Twist only as a command the skill
    publishes, a reading only as a subscription). Any other interface, and the known ones
    besides, is also asked for by its own words: the phrase its type's class name makes
    (``BackUp`` by "back up" or "backup", ``SaveMap`` by "save the map") the last part of its
    name (``/map_saver/save_map`` by "save map") and a node's name of several words before
    it ("map saver"), so that a Nav2 behaviour action is wired
    when a specification says what it does, not because ranking put it in the first ``k``.
    """
    long_type = _long_type(type_name, kind)
    parts = [normalised_words(part) for part in name.split("/") if part]
    own = [normalised_words(type_name.rsplit("/", 1)[-1])]
    own += [part for part in parts[-1:] if part not in _VAGUE]
    # A node's name before a service's or action's (``map_saver``) names it too; a single
    # word there is more likely the robot's namespace (``/panther/...``), which a
    # specification names everywhere.
    own += [part for part in parts[:-1] if " " in part]
    phrases = sorted(
        {_JOIN.join(re.escape(w) for w in phrase.split(" ")) for phrase in own if phrase},
        key=len,
        reverse=True,
    )
    own_cues = [rf"{p}\b" for p in phrases]
    for types, wanted, role in _ROLES:
        if long_type in types and (wanted is None or wanted == direction):
            own_role = _cues(role.cues.pattern[len(r"\b(?:") : -1], *own_cues)
            return Role(role.name, own_role, role.family, role.generic)
    what = {"action": "action", "service": "service"}.get(kind, "topic")
    return Role(f"{what} {type_name.rsplit('/', 1)[-1]}", _cues(*own_cues))
