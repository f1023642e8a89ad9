"""Words for retrieval: splitting ROS and ontology names, light stemming, a domain thesaurus.

Interface names are terse (``/cmd_vel``, ``/odom``, ``/amcl_pose``) and capability names are
camelCase (``inLinearVelocity``); neither matches the other, nor the embedding model's
vocabulary, until both are turned into the words an engineer would say. The thesaurus is
general ROS 2 and robotics usage, not any one robot's names.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from functools import lru_cache

__all__ = [
    "EXPANSION_WEIGHT",
    "QUERY_STOPWORDS",
    "QUERY_SYNONYMS",
    "UNIT_WORDS",
    "expand",
    "split_words",
    "stem",
    "tokens",
    "weighted_tokens",
]

EXPANSION_WEIGHT = 0.5
"""Weight of a word an abbreviation stands for, relative to a word written out (1.0).

An expansion is a guess about meaning (``odom`` -> ``position``), weaker evidence than the
word itself; each further level of expansion halves again."""

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
    "mobile": "mobile base",
    "link": "link frame",
    "frame": "frame transform",
    "manipulator": "manipulator arm",
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


def _word_set(text: str) -> frozenset[str]:
    return frozenset(text.split())


QUERY_STOPWORDS = _word_set(
    """
    robot robots system resource capability skill state states transition fire trigger
    desired desire current actual given specified specifies specify any each all only not
    does do doe done can could should would will must may one some every other
    prepare begin log shut down process processes used use uses store stored storing
    output outputs input inputs retrieve obtain keep while until once after before when
    whether there than also so which who whose what how just still again
    """
)
"""Words every capability model and skill specification uses whatever the skill does:
the framework's own chatter (prepare, print, store as output, shut down processes) and
filler (desired, current). They say nothing about which interface is needed, so the query
leaves them out; interface documents keep them."""

# What a verb in a capability or spec text implies about the interface it acts on:
# setting, publishing or zeroing is commanding; printing, reading or checking a value
# needs a source that measures it. Applied to query texts only.
QUERY_SYNONYMS: dict[str, str] = {
    "set": "command",
    "publish": "command",
    "send": "command",
    "drive": "drive command",
    "zero": "zero stop",
    "halt": "stop",
    "print": "measure",
    "read": "measure",
    "report": "measure",
    "monitor": "measure",
    "check": "measure",
    "retrieve": "measure",
    "measured": "measure",
}

_VOWELS = re.compile(r"[aeiouy]")


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
            # "speed" and "string" are not verb forms: the rest must still be a word
            if suffix in {"ing", "ed"} and (word.endswith("eed") or not _VOWELS.search(base)):
                return word
            # "mapping" -> "mapp" -> "map", "planned" -> "plann" -> "plan"
            if suffix in {"ing", "ed"} and base[-1] == base[-2] and base[-1] not in "lsz":
                base = base[:-1]
            return base
    return word


def _expanded(words: Iterable[str]) -> list[tuple[str, float]]:
    out: list[tuple[str, float]] = []
    for word in words:
        out.append((word, 1.0))
        for extra in ABBREVIATIONS.get(word, "").split():
            if extra == word:
                continue
            out.append((extra, EXPANSION_WEIGHT))
            # one more level: "odom" -> "odometry" -> "position velocity"
            out.extend(
                (w, EXPANSION_WEIGHT**2)
                for w in ABBREVIATIONS.get(extra, "").split()
                if w not in {extra, word}
            )
    return out


def expand(words: Iterable[str]) -> list[str]:
    """The words plus what their abbreviations stand for."""
    return [word for word, _ in _expanded(words)]


def weighted_tokens(text: str, *, query: bool = False) -> list[tuple[str, float]]:
    """Like :func:`tokens`, each term with its weight (1 as written, less when expanded).

    ``query`` also drops :data:`QUERY_STOPWORDS` (for capability and spec texts).
    """
    return list(_weighted_tokens(text, query))


# Interface names, types and field names repeat across interfaces and queries.
@lru_cache(maxsize=8192)
def _weighted_tokens(text: str, query: bool) -> tuple[tuple[str, float], ...]:
    out = []
    words = split_words(text)
    if query:
        words = [
            v for w in words if w not in QUERY_STOPWORDS for v in QUERY_SYNONYMS.get(w, w).split()
        ]
    for word, weight in _expanded(words):
        if word in _STOPWORDS:
            continue
        term = stem(word)
        if term not in _STOPWORDS and len(term) > 1:
            out.append((term, weight))
    return tuple(out)


def tokens(text: str) -> list[str]:
    """Split, expand abbreviations, drop stop words and stem: the lexical index's terms."""
    return [term for term, _ in weighted_tokens(text)]
