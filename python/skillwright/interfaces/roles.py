"""Which of a robot's topics plays a role every mobile base has, by type and name.

The worlds that stand in for the robot (the kinematic one of the run, MuJoCo's of the
simulation) take over its velocity command wherever the robot has it: ``/cmd_vel`` on the
MR-1, ``/panther/cmd_vel`` on a Husarion Panther, ``/stretch/cmd_vel`` on a Stretch.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

__all__ = ["TWIST_TYPES", "command_topic"]

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
