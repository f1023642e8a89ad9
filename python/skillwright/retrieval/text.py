"""Words for retrieval: splitting ROS and ontology names, light stemming, a domain thesaurus.

Interface names are terse (``/cmd_vel``, ``/odom``, ``/amcl_pose``) and capability names are
camelCase (``inLinearVelocity``); neither matches the other, nor the embedding model's
vocabulary, until both are turned into the words an engineer would say. The thesaurus is
general ROS 2 and robotics usage, not any one robot's names.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["UNIT_WORDS", "expand", "split_words", "stem", "tokens"]

# Abbreviations common in ROS 2 interface and field names -> the words they stand for.
ABBREVIATIONS: dict[str, str] = {
    "cmd": "command",
    "vel": "velocity",
    "odom": "odometry",
    "pos": "position",
    "pose": "pose position orientation",
    "nav": "navigation navigate",
    "nav2": "navigation navigate",
    "amcl": "localization pose",
    "slam": "mapping localization map",
    "ik": "inverse kinematics",
    "fk": "forward kinematics",
    "tf": "transform frame",
    "imu": "inertial acceleration angular velocity orientation",
    "joy": "joystick",
    "traj": "trajectory",
    "jnt": "joint",
    "ctrl": "controller",
    "goal": "goal target",
    "scan": "laser range scan distance obstacle",
    "lidar": "laser range scan distance obstacle",
    "costmap": "cost map obstacle",
    "twist": "velocity linear angular",
    "odometry": "odometry position velocity",
    "laserscan": "laser range scan distance obstacle",
    "occupancygrid": "map grid occupancy",
    "pointcloud2": "point cloud depth obstacle",
    "movegroup": "arm motion planning manipulator",
    "gripper": "gripper grasp",
    "moveit": "arm motion planning manipulator",
    "yaw": "yaw heading orientation rotation",
    "rotate": "rotate rotation turn yaw",
    "rotation": "rotation turn yaw orientation",
    "heading": "heading yaw orientation",
    "degree": "angle rotation",
    "angle": "angle rotation orientation",
    "speed": "speed velocity",
    "obstacle": "obstacle distance range collision",
    "collision": "collision obstacle distance",
    "map": "map mapping",
    "point": "point position",
}

UNIT_WORDS: dict[str, str] = {
    "m/s": "velocity speed linear",
    "rad/s": "angular velocity yaw rate rotation",
    "°/s": "angular velocity yaw rate rotation",
    "deg/s": "angular velocity yaw rate rotation",
    "m": "distance position length",
    "mm": "distance position length",
    "cm": "distance position length",
    "rad": "angle heading orientation yaw",
    "°": "angle heading orientation yaw",
    "deg": "angle heading orientation yaw",
    "s": "time duration",
    "ms": "time duration",
    "m/s^2": "acceleration",
    "n": "force effort",
    "nm": "torque effort",
}
"""Unit of measure -> the physical quantity words it implies."""

_STOPWORDS = frozenset(
    {
        "a",
        "an",
        "and",
        "are",
        "as",
        "at",
        "be",
        "by",
        "for",
        "from",
        "if",
        "in",
        "into",
        "is",
        "it",
        "its",
        "of",
        "on",
        "or",
        "that",
        "the",
        "then",
        "this",
        "to",
        "with",
        "msg",
        "msgs",
        "srv",
        "action",
        "ros",
        "ros2",
        "i",
        "am",
        "my",
        "me",
        "value",
        "type",
        "data",
        "out",
        "get",
        "set",
    }
)


def split_words(text: str) -> list[str]:
    """``/cmd_vel`` -> [cmd, vel]; ``inLinearVelocity`` -> [in, linear, velocity]."""
    spaced = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", " ", text)
    return [w for w in re.split(r"[^0-9A-Za-z]+", spaced.lower()) if w]


def stem(word: str) -> str:
    """A light English stemmer: enough to make plural and verb forms meet."""
    for suffix, keep in (("ies", "y"), ("ing", ""), ("ed", ""), ("es", ""), ("s", "")):
        if word.endswith(suffix) and len(word) - len(suffix) >= 3:
            if suffix == "s" and word.endswith("ss"):
                return word
            base = word[: len(word) - len(suffix)] + keep
            # "mapping" -> "mapp" -> "map", "planned" -> "plann" -> "plan"
            if suffix in {"ing", "ed"} and base[-1] == base[-2] and base[-1] not in "lsz":
                base = base[:-1]
            return base
    return word


def expand(words: Iterable[str]) -> list[str]:
    """The words plus what their abbreviations stand for."""
    out: list[str] = []
    for word in words:
        out.append(word)
        for extra in ABBREVIATIONS.get(word, "").split():
            out.append(extra)
            # one more level: "odom" -> "odometry" -> "position velocity"
            out.extend(w for w in ABBREVIATIONS.get(extra, "").split() if w != extra)
    return out


def tokens(text: str) -> list[str]:
    """Split, expand abbreviations, drop stop words and stem: the lexical index's terms."""
    stemmed = (stem(w) for w in expand(split_words(text)) if w not in _STOPWORDS)
    return [w for w in stemmed if w not in _STOPWORDS and len(w) > 1]
