"""What retrieval knows about each interface: a text to embed and weighted terms.

Both come from the same parts — the name, the type, the field names and the uniform
description — so the dense and the lexical score judge the same evidence.

A description somebody wrote (a report's, or a model's from ``inventory describe --engine
llm``) is not evidence the ranking weighs by default: it is free text of unknown care, and a
language model describes a Nav2 back-up action in the words of moving, distance and speed,
odometry in those of navigation and path planning, and a base controller's echo of its
applied command as the topic that sends velocity commands. The rules engine's description,
which reads only the type, the name and the fields, is weighed in its place; the written one
is kept for people and for the dense text, and :data:`WRITTEN_WEIGHT` says how much its words
count beside the rules' (``bench/bench_retrieval.py`` measures the choice).
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Iterable, Sequence

from skillwright.interfaces.description import describe_by_rules
from skillwright.interfaces.inventory import Description, Interface, MessageField
from skillwright.retrieval.text import weighted_tokens

__all__ = [
    "WRITTEN_WEIGHT",
    "describe",
    "field_paths",
    "interface_role",
    "interface_terms",
    "interface_text",
]

TERM_WEIGHTS = {
    "name": 3.0,
    "type": 2.0,
    "package": 0.5,
    "field": 0.5,
    "description": 1.0,
    "role": 2.0,
}

# Topics a skill writes to rather than reads: velocity commands (a bare Twist is one,
# whatever the topic's name: measured velocities come stamped or inside an Odometry),
# goals, setpoints, trajectories sent to a controller, and the request topic of a
# request/response pair (a vendor API served over topics: the client writes the request).
WRITTEN_WEIGHT = 0.0
"""Weight of a written description's words (a report's or a model's) relative to the rules
engine's description, which always counts fully. Measured on five robots the local model
described (``tests/retrieval/robots/described``), recall@4 over their 99 needs: 90 with the
written words not weighed, 87 beside the rules' at 0.1, 84 at 0.25, 66 in their place (how
it was before); no robot gained from them at any weight."""

_COMMAND_NAME = re.compile(r"(^|[/_])(cmd|command|commands|goal|setpoint|request)s?([/_]|$)")
_COMMAND_TYPE = re.compile(r"trajectory_msgs/msg/\w+|\w+/msg/\w*Command|geometry_msgs/msg/Twist")
_MAIN_ROLES = ("message", "goal", "request", "feedback", "result", "response")


def _paths(fields: Sequence[MessageField], prefix: str, depth: int) -> Iterable[str]:
    for field in fields:
        path = f"{prefix}{field.name}"
        yield path
        if depth > 1 and field.fields:
            yield from _paths(field.fields, f"{path}.", depth - 1)


def field_paths(interface: Interface, depth: int = 3) -> list[str]:
    """Field paths of the interface's main definitions (message; goal, feedback, ...)."""
    out: list[str] = []
    for role in _MAIN_ROLES:
        definition = interface.definitions.get(role)
        if definition is not None and definition.fields:
            out.extend(p for p in _paths(definition.fields, "", depth) if p not in out)
    return out


def describe(interface: Interface) -> Description:
    """The interface's description: the one enrichment stored, else the rules engine's."""
    if interface.description is not None:
        return interface.description
    return _by_rules(interface)


def _by_rules(interface: Interface) -> Description:
    return describe_by_rules(
        interface.kind, interface.name, interface.type_name, field_paths(interface, depth=2)
    )


def interface_role(interface: Interface) -> str | None:
    """``command`` for what a skill sends (actions, command topics), ``measure`` for what
    it reads (the other topics), ``None`` for services (they may do either)."""
    if interface.kind == "action":
        return "command"
    if interface.kind == "service":
        return None
    if _COMMAND_NAME.search(interface.name) or _COMMAND_TYPE.fullmatch(interface.type_name):
        return "command"
    return "measure"


def interface_text(interface: Interface, description: Description) -> str:
    """The text embedded for dense retrieval."""
    short_type = interface.type_name.rsplit("/", 1)[-1]
    return f"{interface.kind} {interface.name} ({short_type}). {description.text()}"


_CLOUD_TYPE = re.compile(r"\w*PointCloud2?")
_CLOUD_POINTS = re.compile(r"(?:(?<![A-Za-z])p|P)oints?(?![a-z])")
"""A point cloud's points are its measured samples: "points" in its name (``/depth/points``,
``/velodyne_points``) and "Point" in its type say cloud, not the point a capability moves
to, so they count as "cloud" (JetRover's ``/depth_cam/depth/points`` came first for
move-to-point's "goal point")."""


def _cloud(point: re.Match[str]) -> str:
    """ "cloud" in the case of the word it replaces, so that a type's words stay apart
    (``CompressedPointCloud2``: compressed, cloud, cloud2)."""
    return "Cloud" if point[0].startswith("P") else "cloud"


def _told(description: Description) -> str:
    """The parts of a description retrieval weighs: what the interface does, its tasks."""
    return description.purpose + " " + " ".join(description.tasks)


def interface_terms(
    interface: Interface,
    description: Description,
    written_weight: float = WRITTEN_WEIGHT,
    rules_weight: float = 1.0,
) -> dict[str, float]:
    """Weighted lexical terms of the interface. A ``description`` that the rules engine did
    not write counts at ``written_weight`` beside the rules' own at ``rules_weight``."""
    terms: defaultdict[str, float] = defaultdict(float)

    def add(text: str, part: str, share: float = 1.0) -> None:
        if share <= 0:
            return
        for term, weight in weighted_tokens(text):
            terms[term] += weight * TERM_WEIGHTS[part] * share

    package, _, rest = interface.type_name.partition("/")
    short_type = rest.rsplit("/", 1)[-1]
    cloud = _CLOUD_TYPE.fullmatch(short_type) is not None

    def own(text: str) -> str:
        return _CLOUD_POINTS.sub(_cloud, text) if cloud else text

    add(own(interface.name), "name")
    add(own(short_type), "type")
    add(own(package), "package")
    for path in field_paths(interface, depth=2):
        add(path.rsplit(".", 1)[-1], "field")
    written = description.engine != "rules"
    rules = _by_rules(interface) if written else description
    add(own(_told(rules)), "description", rules_weight if written else 1.0)
    if written:
        add(own(_told(description)), "description", written_weight)
    role = interface_role(interface)
    if role is not None:
        add(role, "role")
    return dict(terms)
