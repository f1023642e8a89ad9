"""Where a skill can read the quantity an output reports, for the finding that it reports none.

An output the capability measures (a distance in m, a heading in rad, a velocity in m/s) that
a skill only ever sets to ``0.0`` reports a fixed number whatever the robot did. Being told
so does not say which of its messages carries a distance. The skeleton keeps the latest
message of each subscribed topic in an attribute declared in ``__init__`` (``self.odom_msg:
Odometry | None``), so the finding can name the fields of those messages that carry a
quantity of the output's unit, by what the message types are (an ``Odometry``'s position and
twist, a ``LaserScan``'s ranges and beam angles), and how a skill gets the usual quantity out
of them.
"""

from __future__ import annotations

from skillwright.validation.facts import SkillFacts

__all__ = ["measuring_sources", "raw_scans"]

_LENGTH = frozenset({"m", "mm", "cm"})
_SPEED = frozenset({"m/s"})
_TURN_RATE = frozenset({"rad/s", "°/s", "deg/s"})
_ANGLE = frozenset({"rad", "°", "deg", "degree", "degrees"})
_TIME = frozenset({"s"})

_FIELDS: dict[str, list[tuple[frozenset[str], str]]] = {
    "Odometry": [
        (
            _LENGTH,
            "{a}.pose.pose.position (the distance travelled: math.hypot of its change in x "
            "and y since execute began)",
        ),
        (_SPEED, "{a}.twist.twist.linear.x (the measured forward speed)"),
        (_TURN_RATE, "{a}.twist.twist.angular.z (the measured yaw rate)"),
        (_ANGLE, "{a}.pose.pose.orientation (the heading: 2 * math.atan2(z, w) on flat ground)"),
    ],
    "PoseWithCovarianceStamped": [
        (_LENGTH, "{a}.pose.pose.position (the position in the map)"),
        (_ANGLE, "{a}.pose.pose.orientation (the heading: 2 * math.atan2(z, w) on flat ground)"),
    ],
    "PoseStamped": [
        (_LENGTH, "{a}.pose.position (the position)"),
        (_ANGLE, "{a}.pose.orientation (the heading: 2 * math.atan2(z, w) on flat ground)"),
    ],
    "LaserScan": [
        (
            _LENGTH,
            "{a}.ranges (the nearest obstacle: the smallest range between range_min and range_max)",
        ),
        (
            _ANGLE,
            "{a}.angle_min + i * {a}.angle_increment (the direction of range i, in radians)",
        ),
    ],
}
"""Message type -> (the units a field carries, where and how a skill reads it)."""

_HELPERS: dict[str, tuple[str, list[tuple[frozenset[str], str]]]] = {
    "Odometry": (
        "_yaw",
        [
            *_FIELDS["Odometry"][:3],
            (_ANGLE, "self._yaw({a}.pose.pose.orientation) (the heading, in radians)"),
        ],
    ),
    "PoseWithCovarianceStamped": (
        "_yaw",
        [
            *_FIELDS["PoseWithCovarianceStamped"][:1],
            (_ANGLE, "self._yaw({a}.pose.pose.orientation) (the heading, in radians)"),
        ],
    ),
    "PoseStamped": (
        "_yaw",
        [
            *_FIELDS["PoseStamped"][:1],
            (_ANGLE, "self._yaw({a}.pose.orientation) (the heading, in radians)"),
        ],
    ),
    "LaserScan": (
        "_closest_reading",
        [
            (_LENGTH, "self._closest_reading({a})[0] (the range of the nearest valid reading)"),
            (_ANGLE, "self._closest_reading({a})[1] (its bearing, in radians)"),
        ],
    ),
}
"""Message type -> (the skeleton's helper that reads it, the advice when the skill has it)."""


def measuring_sources(facts: SkillFacts, unit: str) -> list[str]:
    """Where the skill can read a quantity in ``unit``: fields of the latest messages it
    declares (``self.odom_msg: Odometry | None``), and the clock for a duration; empty when it
    keeps nothing that carries one."""
    out = []
    for attribute, type_name in facts.latest_messages.items():
        helper, advice = _HELPERS.get(type_name, ("", []))
        for units, text in advice if helper in facts.methods else _FIELDS.get(type_name, []):
            if unit in units:
                out.append(text.format(a=f"self.{attribute}"))
    if unit in _TIME:
        out.append("time.monotonic() (how long it took: its value at the end minus at the start)")
    return out


def raw_scans(facts: SkillFacts, unit: str) -> list[str]:
    """The latest LaserScan messages whose raw fields :func:`measuring_sources` names for a
    quantity in ``unit`` (the class lacks the skeleton's ``_closest_reading``, which reads
    them for it)."""
    if "_closest_reading" in facts.methods or not any(unit in u for u, _ in _FIELDS["LaserScan"]):
        return []
    return [a for a, type_name in facts.latest_messages.items() if type_name == "LaserScan"]
