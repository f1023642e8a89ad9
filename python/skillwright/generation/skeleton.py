"""The skill skeleton: everything about a skill that follows from its inputs alone.

From the capability (IRIs, inputs, outputs, resource limits), the skill specification
(name, interface type, states) and the chosen interfaces, this writes a pySkillUp skill
class whose structure and annotations are right by construction. Behaviour that needs
judgement is left as ``raise NotImplementedError(...)`` in the state that needs it, and
listed in :attr:`Skeleton.unimplemented`, so neither a person nor a checker can mistake
the skeleton for a finished skill.
"""

from __future__ import annotations

import ast
import json
import math
import re
import textwrap
from collections.abc import Collection, Sequence
from typing import TYPE_CHECKING, Literal

from skillwright.capability.model import Capability, Expression, Parameter
from skillwright.generation.assured import RestOutput, rest_outputs
from skillwright.generation.helpers import helper_lines
from skillwright.generation.model import InterfaceRef, Skeleton, SkeletonParameter, Unwired
from skillwright.generation.names import attribute_name, class_name, python_import, snake_case
from skillwright.spec.model import PACKML_STATES, SkillSpec

if TYPE_CHECKING:
    from skillwright.interfaces.inventory import QosProfile

__all__ = [
    "SKELETON_NOTE",
    "action_stem",
    "build_skeleton",
    "class_constants",
    "handle_attribute",
    "helper_dependencies",
    "helper_summaries",
    "mint_skill_iri",
    "rest_lines",
    "skeleton_helpers",
    "topic_role",
    "type_class",
    "unstated_limits",
]

SKELETON_NOTE = (
    "Skeleton written by skillwright: structure, annotations and interface handles.",
    "States that raise NotImplementedError still need their behaviour.",
)
"""The module docstring's account of who wrote what (merging replaces it)."""

PYTHON_TYPES = {"Real": "float", "Integer": "int", "Boolean": "bool", "String": "str"}
DEFAULTS = {"float": "0.0", "int": "0", "bool": "False", "str": '""'}

# Message types that command a robot rather than report on it.
_COMMAND_TYPES = re.compile(
    r"/(Twist|TwistStamped|JointTrajectory|JointJog|Float64MultiArray|PoseStamped|"
    r"AckermannDrive|AckermannDriveStamped|GripperCommand)$"
)
_COMMAND_NAMES = re.compile(r"(cmd|command|goal|setpoint|target)", re.IGNORECASE)


def topic_role(name: str, type_name: str) -> Literal["publish", "subscribe"]:
    """Whether a skill publishes to a topic (a command) or subscribes to it (a reading).

    Sources that know the graph (publisher and subscriber counts) decide better; this is
    the convention-based fallback: command-like types or names are published to.
    """
    if _COMMAND_TYPES.search(type_name) or _COMMAND_NAMES.search(name.rsplit("/", 1)[-1]):
        return "publish"
    return "subscribe"


def mint_skill_iri(capability: Capability, skill_name: str) -> str:
    """A skill IRI next to the resource (``.../skills/<name>``) or next to the capability."""
    anchor = capability.resource.iri if capability.resource else capability.iri
    base = re.sub(r"[^/#]*$", "", anchor)
    return f"{base}skills/{skill_name}"


def _q(text: str) -> str:
    """A double-quoted Python string literal (JSON string syntax is valid Python)."""
    return json.dumps(text, ensure_ascii=False)


def _literal(text: str) -> str:
    return _q(" ".join(text.split()))


def _docstring(text: str, indent: str) -> list[str]:
    """A docstring holding ``text`` verbatim apart from wrapping; quotes made safe."""
    safe = " ".join(text.split()).replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    words = safe.split(" ")
    lines: list[str] = []
    current = ""
    for word in words:
        if current and len(indent) + len(current) + len(word) + 1 > 92:
            lines.append(current)
            current = word
        else:
            current = f"{current} {word}" if current else word
    lines.append(current)
    if len(lines) == 1:
        return [f'{indent}"""{lines[0]}"""']
    return [f'{indent}"""{lines[0]}', *(f"{indent}{line}" for line in lines[1:]), f'{indent}"""']


_ANGLE_UNITS = frozenset({"rad", "radian", "radians", "°", "deg", "degree", "degrees"})
_TURNS = {math.tau: "math.tau", 360.0: "360.0"}
_TURN_TEXT = {"math.tau": "2 pi", "360.0": "360"}


def full_turn(capability: Capability, iri: str | None, unit: str | None) -> str | None:
    """The full turn (as Python) when the capability bounds the angle ``iri`` to
    [0, one turn): ``angle >= 0`` and ``angle < 2 * pi`` (or ``< 360`` in degrees).

    An angle a turn further is the same heading, so the skill reports it in the range the
    capability states: a yaw from ``math.atan2`` lies in [-pi, pi], and a heading reported
    so is negative half of the time, outside the capability's range.
    """
    if iri is None or (unit or "").strip().lower() not in _ANGLE_UNITS:
        return None
    non_negative, upper = False, None
    for constraint in capability.constraints:
        expression = constraint.expression
        if len(expression.arguments) != 2:
            continue
        angle, bound = expression.arguments
        if angle.kind != "variable" or angle.refers_to != iri:
            continue
        operator = (expression.operator or "").rsplit("/", 1)[-1]
        value = _constant(bound)
        non_negative |= operator == "relation1#geq" and value == 0.0
        upper = value if operator == "relation1#lt" and value is not None else upper
    if not non_negative or upper is None:
        return None
    return next((text for turn, text in _TURNS.items() if math.isclose(upper, turn)), None)


def _constant(expression: Expression) -> float | None:
    """The value of a term without variables (a literal, pi, a product or sum of them)."""
    if expression.kind == "literal":
        try:
            return float(expression.text)
        except ValueError:
            return None
    if expression.kind == "variable":
        named = expression.refers_to or expression.text
        return math.pi if named == "pi" or named.endswith("nums1#pi") else None
    values = [_constant(argument) for argument in expression.arguments]
    if any(v is None for v in values) or not values:
        return None
    operator = (expression.operator or "").rsplit("/", 1)[-1]
    if operator == "arith1#times":
        return math.prod(v for v in values if v is not None)
    if operator == "arith1#plus":
        return math.fsum(v for v in values if v is not None)
    return None


def _parameters(parameters: Sequence[Parameter], capability: Capability) -> list[SkeletonParameter]:
    out = []
    for parameter in parameters:
        for component in parameter.components:
            python_type = PYTHON_TYPES.get(component.data_type or "", "str")
            pieces = [component.definition or parameter.name]
            if component.unit and component.unit != "-":
                pieces.append(f"Unit: {component.unit}.")
            if component.expression_goal:
                pieces.append(f"Expression goal: {component.expression_goal}.")
            out.append(
                SkeletonParameter(
                    name=component.name,
                    attribute=snake_case(component.name),
                    python_type=python_type,
                    direction=parameter.direction,
                    description=" ".join(pieces),
                    turn=full_turn(capability, component.iri, component.unit)
                    if parameter.direction == "output"
                    else None,
                )
            )
    return out


def class_constants(capability: Capability) -> list[tuple[str, str, str]]:
    """Class constants for the resource's requirements: (NAME, value, comment)."""
    out: list[tuple[str, str, str]] = []
    if capability.resource is None:
        return out
    for prop in capability.resource.properties:
        for instance in prop.instances:
            if instance.expression_goal != "Requirement" or instance.value is None:
                continue
            relation = instance.logic_interpretation or "="
            suffix = {"<=": "MAX", "<": "MAX", ">=": "MIN", ">": "MIN"}.get(relation, "VALUE")
            name = f"{snake_case(prop.name).upper()}_{suffix}"
            unit = f" {instance.unit}" if instance.unit else ""
            comment = f"resource requirement: {prop.name} {relation} {instance.value}{unit}"
            out.append((name, repr(instance.value), comment))
    return out


_LIMIT_WORDS = re.compile(
    r"\b(?<!desired )(?<!requested )(?<!given )(maximum|minimum|max|min|limits?)\b", re.IGNORECASE
)
_BOUND = re.compile(r"(<=?|>=?)\s*-?\d|\d\s*(<=?|>=?)|\b(min|max)\(")


def unstated_limits(capability: Capability, spec: SkillSpec) -> list[str]:
    """Warnings for sentences of the specification that ask for a limit (``if it does not
    exceed the maximum possible velocity``) with no value, where the capability states none
    either: no resource requirement and no numeric bound in its constraints. The skill then
    enforces no limit at all, and the engineer should know before it drives a robot."""
    stated = class_constants(capability) or any(
        _BOUND.search(c.text) for c in capability.constraints
    )
    if stated:
        return []
    out = []
    for state, text in spec.states.items():
        for sentence in re.split(r"(?<=[.!?])\s+", text.strip()):
            if _LIMIT_WORDS.search(sentence) and not re.search(r"\d", sentence):
                out.append(
                    f'the specification\'s {state} state asks for a limit ("{sentence}") that '
                    f"the capability {capability.name} does not give: neither a resource "
                    "requirement nor a constraint states a value, so the skill enforces no "
                    "limit. State the value in the capability model (for example a requirement "
                    "on the resource's maximum velocity) and generate again"
                )
    return out


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)

    def text(self) -> str:
        return "\n".join(self.lines) + "\n"


def is_tf(interface: InterfaceRef) -> bool:
    """Whether ``interface`` is the transform tree (``/tf``): skills read it through a tf2
    buffer and listener, which also take in ``/tf_static``, not through a plain subscription."""
    return (
        interface.kind == "topic"
        and interface.role == "subscribe"
        and interface.type_name == "tf2_msgs/msg/TFMessage"
        and interface.name.rsplit("/", 1)[-1] == "tf"
    )


def handle_attribute(interface: InterfaceRef) -> str:
    """The attribute holding the handle of ``interface``: ``cmd_vel_publisher``."""
    if is_tf(interface):
        return "tf_listener"
    suffix = {"publish": "publisher", "subscribe": "subscription"}.get(interface.role, "client")
    return attribute_name(interface.name, suffix)


def type_class(interface: InterfaceRef) -> str:
    """The Python class of the interface's type: ``Twist``."""
    return python_import(interface.type_name, interface.kind)[1]


def _create_lines(interface: InterfaceRef, indent: str) -> list[str]:
    cls = type_class(interface)
    handle = f"self.{handle_attribute(interface)}"
    name = _q(interface.name)
    if interface.kind == "action":
        return [f"{indent}{handle} = ActionClient(self.node, {cls}, {name})"]
    if interface.kind == "service":
        return [f"{indent}{handle} = self.node.create_client({cls}, {name})"]
    if interface.role == "publish":
        return [f"{indent}{handle} = self.node.create_publisher({cls}, {name}, 10)"]
    if is_tf(interface):
        return [
            f"{indent}self.tf_buffer = Buffer()",
            f"{indent}{handle} = TransformListener(self.tf_buffer, self.node)",
        ]
    callback = f"self._on_{snake_case(interface.name)}"
    return [
        f"{indent}{handle} = self.node.create_subscription(",
        f"{indent}    {cls}, {name}, {callback}, {_QOS_ARGUMENT[interface.qos]}",
        f"{indent})",
    ]


_QOS_ARGUMENT = {
    "default": "10",
    "sensor_data": "qos_profile_sensor_data",
    "latched": "QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)",
}
_QOS_IMPORTS = {
    "sensor_data": ["qos_profile_sensor_data"],
    "latched": ["DurabilityPolicy", "QoSProfile"],
}


def subscription_qos(
    role: str, offered: Sequence[QosProfile]
) -> Literal["default", "sensor_data", "latched"]:
    """The QoS a subscription needs for the profiles the publishers offer.

    A reliable subscription receives nothing from a best-effort publisher, so one best-effort
    publisher makes it ``sensor_data``; publishers that all keep their last message (transient
    local, e.g. a map) make it ``latched``, so a skill started later still gets that message.
    """
    if role != "subscribe" or not offered:
        return "default"
    if any(profile.reliability == "best_effort" for profile in offered):
        return "sensor_data"
    if all(profile.durability == "transient_local" for profile in offered):
        return "latched"
    return "default"


def _release_lines(interface: InterfaceRef, indent: str) -> list[str]:
    handle = f"self.{handle_attribute(interface)}"
    if interface.kind == "action":
        release = f"{handle}.destroy()"
    elif interface.kind == "service":
        release = f"self.node.destroy_client({handle})"
    elif interface.role == "publish":
        release = f"self.node.destroy_publisher({handle})"
    elif is_tf(interface):
        release = f"{handle}.unregister()"
    else:
        release = f"self.node.destroy_subscription({handle})"
    # A base keeps driving on its last velocity command (a skill may complete while it
    # moves): the skill leaves it at rest before it lets go of the publisher, after which
    # nothing could stop it.
    stop = [f"{indent}    {handle}.publish({type_class(interface)}())"]
    return [
        f"{indent}if {handle} is not None:",
        *(stop if _is_twist_publisher(interface) else []),
        f"{indent}    {release}",
        f"{indent}    {handle} = None",
    ]


def _module_head(
    out: _Writer,
    capability: Capability,
    interfaces: Sequence[InterfaceRef],
    source_note: str,
    helpers: Sequence[str],
    math_needed: bool = False,
) -> None:
    imports: dict[str, set[str]] = {}
    for interface in interfaces:
        if is_tf(interface):
            imports.setdefault("tf2_ros", set()).update({"Buffer", "TransformListener"})
            if "_transform" in helpers:
                imports["tf2_ros"].add("TransformException")
                imports.setdefault("rclpy.time", set()).add("Time")
            continue
        module, name = python_import(interface.type_name, interface.kind)
        imports.setdefault(module, set()).add(name)
        if interface.kind == "action" and f"_{action_stem(interface)}_result" in helpers:
            imports.setdefault("action_msgs.msg", set()).add("GoalStatus")
            if interface.type_name in _MOVEIT_RESULTS:
                imports.setdefault("moveit_msgs.msg", set()).add("MoveItErrorCodes")
    if "_position_goal" in helpers:
        imports.setdefault("geometry_msgs.msg", set()).add("Pose")
        imports.setdefault("moveit_msgs.msg", set()).update({"Constraints", "PositionConstraint"})
        imports.setdefault("shape_msgs.msg", set()).add("SolidPrimitive")
    header = f"skill for the capability {capability.name}"
    if capability.resource:
        header += f" of {capability.resource.name}"
    out.add(f'"""{header[0].upper()}{header[1:]}.', "")
    if source_note:
        out.add(source_note, "")
    out.add(*SKELETON_NOTE, '"""', "")
    if math_needed or helpers:
        out.add(
            *(["import math"] if math_needed else []), *(["import time"] if helpers else []), ""
        )
    out.add("import rclpy")
    if any(i.kind == "action" for i in interfaces):
        out.add("from rclpy.action import ActionClient")
    qos_names = sorted(
        {n for i in interfaces if i.role == "subscribe" for n in _QOS_IMPORTS.get(i.qos, [])}
    )
    if qos_names:
        out.add(f"from rclpy.qos import {', '.join(qos_names)}")
    out.add(
        "",
        "from pyskillup.decorators.decorators import *  # noqa: F403",
        "from pyskillup.decorator_check.decorator_check import ROS2Skill",
        "from pyskillup.decorators.skill_interface import SkillInterface",
    )
    if imports:
        out.add("")
        for module in sorted(imports):
            out.add(f"from {module} import {', '.join(sorted(imports[module]))}")


def _class_head(
    out: _Writer, capability: Capability, spec: SkillSpec, cls: str, skill_iri: str
) -> None:
    module_iri = capability.resource.iri if capability.resource else capability.iri
    out.add(
        "",
        "",
        "@skill(",
        f"    skill_interface=SkillInterface.{spec.skill_interface},",
        f"    skill_iri={_q(skill_iri)},",
        f"    module_iri={_q(module_iri)},",
        f"    capability_iri={_q(capability.iri)},",
        f"    description={_literal(spec.description or capability.comment or spec.name)},",
        ")",
        f"class {cls}(ROS2Skill):",
    )
    out.add(*_docstring(spec.description or capability.label, "    "), "")
    limits = class_constants(capability)
    for name, value, comment in limits:
        out.add(f"    {name} = {value}  # {comment}")
    if limits:
        out.add("")


def _init(
    out: _Writer,
    spec: SkillSpec,
    parameters: Sequence[SkeletonParameter],
    interfaces: Sequence[InterfaceRef],
    notes: list[str],
) -> None:
    out.add("    def __init__(self) -> None:", f"        super().__init__({_q(spec.name)})")
    for parameter in parameters:
        default = DEFAULTS[parameter.python_type]
        out.add(f"        self.{parameter.attribute}: {parameter.python_type} = {default}")
    for interface in interfaces:
        out.add(f"        self.{handle_attribute(interface)} = None")
        if interface.kind == "action":
            stem = action_stem(interface)
            out.add(
                f"        self.{stem}_goal_handle = None",
                f"        self.{stem}_result_future = None",
                f"        self.{stem}_feedback = None",
            )
        if is_tf(interface):
            out.add("        self.tf_buffer: Buffer | None = None")
        elif interface.role == "subscribe":
            cls = type_class(interface)
            out.add(f"        self.{snake_case(interface.name)}_msg: {cls} | None = None")
    if "starting" not in spec.states and interfaces:
        notes.append("the spec has no 'starting' state, so interface handles are made in __init__")
        for interface in interfaces:
            out.add(*_create_lines(interface, "        "))
    if interfaces and "resetting" not in spec.states:
        notes.append("the spec has no 'resetting' state, so interface handles are never released")


def _accessors(out: _Writer, parameters: Sequence[SkeletonParameter]) -> None:
    for parameter in parameters:
        decorator = "skill_parameter" if parameter.direction == "input" else "skill_output"
        out.add(
            "",
            f"    @{decorator}(",
            "        is_required=True,",
            f"        name={_q(parameter.name)},",
            f"        description={_literal(parameter.description)},",
            "    )",
            f"    def get_{parameter.attribute}(self) -> {parameter.python_type}:",
            *(
                [
                    f"        # The capability bounds {parameter.name} to [0, "
                    f"{_TURN_TEXT.get(parameter.turn, parameter.turn)}):",
                    "        # an angle a turn further is the same one.",
                    f"        return self.{parameter.attribute} % {parameter.turn}",
                ]
                if parameter.turn
                else [f"        return self.{parameter.attribute}"]
            ),
        )


def _callbacks(out: _Writer, interfaces: Sequence[InterfaceRef]) -> None:
    for interface in interfaces:
        if interface.role != "subscribe" or is_tf(interface):
            continue
        attribute = snake_case(interface.name)
        out.add(
            "",
            f"    def _on_{attribute}(self, msg: {type_class(interface)}) -> None:",
            f'        """Keeps the latest message of {interface.name} ({interface.type_name})."""',
            f"        self.{attribute}_msg = msg",
        )


def _is_twist_publisher(interface: InterfaceRef) -> bool:
    return (
        interface.kind == "topic"
        and interface.role == "publish"
        and interface.type_name.rsplit("/", 1)[-1] in {"Twist", "TwistStamped"}
    )


def skeleton_helpers(
    interfaces: Sequence[InterfaceRef], wanted: Collection[str] = ()
) -> dict[str, list[str]]:
    """Helper methods the behaviour may call, by name, as code lines (class indentation).

    They are written here, once and tested, so that a small model spends its tokens on
    behaviour: waiting with a deadline while callbacks run, waiting for a future (service
    responses, action goals and results) and commanding the base to stand still. Only the
    helpers the interfaces make useful are offered; unused ones are removed after generation.
    The helpers that need no interface (waiting) are offered too when ``wanted`` names them:
    the behaviour may call them on futures of its own after the interfaces they were first
    offered for turned out unused.
    """
    helpers: dict[str, list[str]] = {}
    generic = {"_wait_until", "_result_of"} & set(wanted)
    if interfaces or generic:
        helpers["_wait_until"] = helper_lines("_wait_until")
    if "_result_of" in generic or any(i.kind in {"service", "action"} for i in interfaces):
        helpers["_result_of"] = helper_lines("_result_of")
    for interface in interfaces:
        if interface.kind == "action":
            helpers.update(_action_helpers(interface))
    if any(i.type_name in _MOVE_GROUP for i in interfaces):
        helpers["_position_goal"] = helper_lines("_position_goal")
    if any(i.type_name in _NAVIGATE_TO_POSE for i in interfaces):
        helpers["_pose_goal"] = helper_lines("_pose_goal")
    if any(is_tf(i) for i in interfaces):
        helpers["_transform"] = helper_lines("_transform")
    if any(i.role == "subscribe" and i.type_name in _LASER_SCANS for i in interfaces):
        helpers["_closest_reading"] = helper_lines("_closest_reading")
    if any(is_tf(i) or (i.role == "subscribe" and i.type_name in _ORIENTED) for i in interfaces):
        helpers["_yaw"] = helper_lines("_yaw")
    twists = [
        {"velocity_publisher": handle_attribute(i), "Velocity": type_class(i)}
        for i in interfaces
        if _is_twist_publisher(i)
    ]
    if twists:
        helpers["_stop_base"] = helper_lines("_stop_base", repeated=twists)
    odometry = next((i for i in interfaces if _is_odometry(i)), None)
    if twists and odometry is not None:
        names = {"odometry_msg": f"{snake_case(odometry.name)}_msg", "/odometry": odometry.name}
        helpers["_settle_base"] = helper_lines("_settle_base", names)
    return helpers


def _is_odometry(interface: InterfaceRef) -> bool:
    return interface.role == "subscribe" and interface.type_name in _ODOMETRY


_ODOMETRY = frozenset({"nav_msgs/msg/Odometry", "nav_msgs/Odometry"})
"""nav_msgs/Odometry: the base's pose in the odometry frame and its measured twist."""


def helper_dependencies(helpers: Collection[str], offered: dict[str, list[str]]) -> set[str]:
    """``helpers`` and every offered helper they call or hand over, transitively."""
    wanted = set(helpers)
    pending = list(wanted)
    while pending:
        for name in re.findall(r"self\.(_\w+)", "\n".join(offered.get(pending.pop(), []))):
            if name in offered and name not in wanted:
                wanted.add(name)
                pending.append(name)
    return wanted


def helper_summaries(interfaces: Sequence[InterfaceRef]) -> dict[str, str]:
    """One line per helper a model may call, for the task card (callbacks are left out)."""
    out = dict(_GENERIC_SUMMARIES)
    for interface in interfaces:
        if interface.kind != "action":
            continue
        stem, cls, name = action_stem(interface), type_class(interface), interface.name
        out[f"_send_{stem}_goal"] = (
            f"self._send_{stem}_goal(goal, timeout) sends a {cls}.Goal() to {name} and waits "
            f"until it is accepted, else raises RuntimeError; while it runs self.{stem}_feedback "
            f"is the latest {cls}.Feedback or None, and self.{stem}_result_future.done() says "
            "whether it ended"
        )
        out[f"_{stem}_result"] = (
            f"self._{stem}_result(timeout) waits for its {cls}.Result and returns it, else "
            "raises RuntimeError (also when the goal did not succeed)"
        )
        out[f"_cancel_{stem}_goal"] = (
            f"self._cancel_{stem}_goal(timeout) cancels it if it is in progress"
        )
    if any(i.type_name in _MOVE_GROUP for i in interfaces):
        out["_position_goal"] = (
            "self._position_goal(group, link, frame, x, y, z, tolerance) returns a "
            "MoveGroup.Goal() that plans and executes a motion of link (planning group group) "
            "to the point x, y, z in frame within tolerance metres, any orientation; set "
            "goal.request's other fields on it"
        )
    odometry = next((i for i in interfaces if _is_odometry(i)), None)
    if odometry is not None and any(_is_twist_publisher(i) for i in interfaces):
        out["_settle_base"] = (
            "self._settle_base(timeout) commands zero velocity and waits until "
            f"{odometry.name} shows the base at rest (under 0.01 m/s and 0.02 rad/s), else "
            "raises RuntimeError"
        )
    if any(i.type_name in _NAVIGATE_TO_POSE for i in interfaces):
        out["_pose_goal"] = (
            "self._pose_goal(frame, x, y, yaw) returns a NavigateToPose.Goal() that moves the "
            "base to the point x, y in frame (e.g. 'map') with heading yaw in radians; hand it "
            "to the send helper"
        )
    return out


_LASER_SCANS = frozenset({"sensor_msgs/msg/LaserScan", "sensor_msgs/LaserScan"})
_ORIENTED = frozenset(
    f"{package}/{kind}{name}"
    for package, name in (
        ("nav_msgs", "Odometry"),
        ("geometry_msgs", "PoseStamped"),
        ("geometry_msgs", "PoseWithCovarianceStamped"),
        ("geometry_msgs", "Pose"),
    )
    for kind in ("msg/", "")
)
"""Messages that carry an orientation quaternion (with the transform tree, for ``_yaw``)."""
_GENERIC_SUMMARIES = {
    "_wait_until": "self._wait_until(condition, timeout, what) waits while callbacks run, else "
    "raises RuntimeError",
    "_result_of": "self._result_of(future, timeout, what) waits for a future and returns its "
    "result",
    "_stop_base": "self._stop_base() commands zero velocity",
    "_closest_reading": "self._closest_reading(scan) returns (distance, bearing) of the closest "
    "valid reading of a LaserScan, NaN, infinite and out-of-range readings skipped; "
    "(math.inf, 0.0) when there is none; self._closest_reading(scan, scan2) gives the "
    "closest reading of several scanners",
    "_yaw": "self._yaw(q) returns the heading in radians, in [-pi, pi], counter-clockwise "
    "positive, of an orientation quaternion q (an Odometry's pose.pose.orientation, a "
    "transform's transform.rotation)",
    "_transform": "self._transform(target_frame, source_frame, timeout) returns the latest "
    "TransformStamped (transform.translation.{x,y,z}, transform.rotation.{x,y,z,w}) or raises "
    "RuntimeError",
}


def action_stem(interface: InterfaceRef) -> str:
    """The stem of an action's handle and helpers: ``navigate_to_pose`` for the handle
    ``navigate_to_pose_client`` and the helper ``_send_navigate_to_pose_goal``."""
    return handle_attribute(interface).removesuffix("_client")


_MOVE_GROUP = frozenset({"moveit_msgs/action/MoveGroup", "moveit_msgs/MoveGroup"})
"""MoveIt's move-group action: a goal is a motion plan request with constraints."""
_MOVEIT_RESULTS = frozenset(
    {*_MOVE_GROUP, "moveit_msgs/action/ExecuteTrajectory", "moveit_msgs/ExecuteTrajectory"}
)
"""MoveIt actions whose result carries a MoveItErrorCodes error_code: a goal can end in
SUCCEEDED with a failure code."""


_NAVIGATE_TO_POSE = frozenset({"nav2_msgs/action/NavigateToPose", "nav2_msgs/NavigateToPose"})


def _action_helpers(interface: InterfaceRef) -> dict[str, list[str]]:
    """The helpers of one action (:class:`~skillwright.generation.helpers.SkeletonHelpers`'
    ``stem`` templates), by their names in the skill."""
    stem = action_stem(interface)
    names = {"stem": stem, "Action": type_class(interface), "/action": interface.name}
    moveit = interface.type_name in _MOVEIT_RESULTS
    return {
        template.replace("stem", stem): helper_lines(template, names, moveit=moveit)
        for template in _ACTION_HELPERS
    }


_ACTION_HELPERS = ("_send_stem_goal", "_on_stem_feedback", "_stem_result", "_cancel_stem_goal")
"""An action goal's life, in the order the skeleton writes it: rclpy's ``send_goal_async``
gives a future of a ClientGoalHandle, whose ``get_result_async`` and ``cancel_goal_async``
give the result and the cancel, none of which the ActionClient itself offers."""


def _helpers(out: _Writer, helpers: dict[str, list[str]]) -> None:
    for lines in helpers.values():
        out.add("", *lines)


_HALTING = {"stopping": "a Stop", "aborting": "a fault"}
"""The states that must bring a moving robot to a halt, and what leads into each."""


def halting_states(spec: SkillSpec, interfaces: Sequence[InterfaceRef]) -> dict[str, list[str]]:
    """Halting states the specification leaves out although the skill can move the robot,
    written whole: they command zero velocity and cancel the goals in progress.

    Without them a fault (or a Stop) leaves the last velocity command or an action goal
    driving the robot; a specification's author rarely thinks of that, and it is no
    behaviour a model needs to invent.
    """
    twists = [i for i in interfaces if _is_twist_publisher(i)]
    actions = [i for i in interfaces if i.kind == "action"]
    if not twists and not actions:
        return {}
    states: dict[str, list[str]] = {}
    for state, cause in _HALTING.items():
        if state in spec.states:
            continue
        text = (
            f"Added by skillwright: the specification has no {state} state, and after {cause} "
            "the robot must not keep moving. Commands zero velocity and cancels the goals "
            "in progress."
        )
        lines = [f"    @{state}", f"    def {state}(self) -> None:", *_docstring(text, "        ")]
        if twists:
            lines.append("        self._stop_base()")
        for interface in actions:
            lines += [
                "        try:",
                f"            self._cancel_{action_stem(interface)}_goal(2.0)",
                "        except RuntimeError as error:",
                "            self.node.get_logger().error(str(error))",
            ]
        states[state] = lines
    return states


def _states(
    out: _Writer,
    spec: SkillSpec,
    prologues: dict[str, list[str]],
    epilogues: dict[str, list[str]],
    halting: dict[str, list[str]],
) -> list[str]:
    unimplemented: list[str] = []
    for state in PACKML_STATES:
        if state in halting:
            out.add("", *halting[state])
        if state not in spec.states:
            continue
        text = spec.states[state]
        out.add("", f"    @{state}", f"    def {state}(self) -> None:")
        out.add(*_docstring(text, "        "))
        # The skeleton alone cannot order the behaviour between them, so the handles are
        # made and released first and the placeholder follows.
        out.add(*prologues.get(state, []), *epilogues.get(state, []))
        message = f"{state}: behaviour from the specification still to be written"
        out.add(f"        raise NotImplementedError({_q(message)})")
        unimplemented.append(state)
    return unimplemented


_REST_TIMEOUT = 5.0
"""Seconds a base may take to come to rest after a zero command: braking from a mobile
base's top speed takes well under one."""


def rest_lines(
    capability: Capability, interfaces: Sequence[InterfaceRef], indent: str = "        "
) -> tuple[list[RestOutput], list[str]]:
    """The outputs the skeleton sets for the base's rest (:mod:`~skillwright.generation.
    assured`) and the lines that do it: the base commanded to zero and, where odometry is
    read, waited for until it stands still (``_settle_base``), then each output given the
    value the capability asserts. None without a velocity command: a skill that cannot
    command the base cannot promise its rest."""
    outputs = rest_outputs(capability)
    if not outputs or not any(_is_twist_publisher(i) for i in interfaces):
        return [], []
    names = ", ".join(o.name for o in outputs)
    sources = ", ".join(dict.fromkeys(o.source for o in outputs))
    settle = any(_is_odometry(i) for i in interfaces)
    comment = (
        f"The capability asserts {names} = 0 ({sources}): the motion is over, and the base "
        "is at rest before the outputs say so."
    )
    lines = [
        *(f"{indent}# {line}" for line in textwrap.wrap(comment, 90 - len(indent))),
        f"{indent}self._settle_base({_REST_TIMEOUT})" if settle else f"{indent}self._stop_base()",
        *(f"{indent}self.{o.attribute} = {o.value}" for o in outputs),
    ]
    return outputs, lines


def build_skeleton(
    capability: Capability,
    spec: SkillSpec,
    interfaces: Sequence[InterfaceRef],
    *,
    source_note: str = "",
    helpers: Collection[str] | None = None,
    unwired: Sequence[Unwired] = (),
) -> Skeleton:
    """Writes the skeleton of the skill ``spec`` describes for ``capability``.

    ``source_note`` is a line for the module docstring, e.g. which files it came from;
    ``helpers`` limits the skeleton's helper methods to these names (default: every helper
    the interfaces make useful); ``unwired`` are given interfaces that get no handle
    (:mod:`~skillwright.generation.wiring`), recorded for the task card and the notes.

    Outputs the capability asserts the base's rest for are set by the skeleton
    (:func:`rest_lines`) at the start of ``completing``, or at the end of ``execute`` when
    the specification has no completing state.
    """
    notes: list[str] = []
    if capability.resource is None:
        notes.append("the capability names no providing resource; module_iri is the capability's")
    cls = class_name(spec.name)
    skill_iri = mint_skill_iri(capability, spec.name)
    parameters = _parameters(capability.inputs, capability) + _parameters(
        capability.outputs, capability
    )

    halting = halting_states(spec, interfaces)
    offered = skeleton_helpers(interfaces, helpers or ())
    assured, resting = rest_lines(capability, interfaces)
    halting_calls = {
        name
        for lines in [*halting.values(), resting]
        for name in re.findall(r"self\.(_\w+)\(", "\n".join(lines))
    }
    wanted = None if helpers is None else helper_dependencies({*helpers, *halting_calls}, offered)
    helper_code = {n: c for n, c in offered.items() if wanted is None or n in wanted}
    prologues: dict[str, list[str]] = {}
    epilogues: dict[str, list[str]] = {}
    if "starting" in spec.states:
        prologues["starting"] = [
            line for interface in interfaces for line in _create_lines(interface, "        ")
        ]
    if "resetting" in spec.states:
        epilogues["resetting"] = [
            line for interface in interfaces for line in _release_lines(interface, "        ")
        ]
    if resting and "completing" in spec.states:
        prologues["completing"] = resting
    elif resting:
        epilogues["execute"] = resting
    if unwired:
        notes.append(
            "retrieved but not wired (nothing in the specification or the capability calls "
            "for them; no handle): " + ", ".join(u.interface.name for u in unwired)
        )

    out = _Writer()
    _module_head(
        out,
        capability,
        interfaces,
        source_note,
        list(helper_code),
        math_needed=any(p.turn == "math.tau" for p in parameters)
        or "_closest_reading" in helper_code
        or "_settle_base" in helper_code
        or "_yaw" in helper_code
        or "_pose_goal" in helper_code,
    )
    _class_head(out, capability, spec, cls, skill_iri)
    _init(out, spec, parameters, interfaces, notes)
    _accessors(out, parameters)
    _callbacks(out, interfaces)
    _helpers(out, helper_code)
    unimplemented = _states(out, spec, prologues, epilogues, halting)

    code = out.text()
    ast.parse(code)  # the skeleton is generated, so a syntax error here is our bug
    return Skeleton(
        code=code,
        class_name=cls,
        skill_iri=skill_iri,
        parameters=parameters,
        interfaces=list(interfaces),
        unimplemented=unimplemented,
        notes=notes,
        helpers=list(helper_code),
        prologues={state: "\n".join(lines) for state, lines in prologues.items() if lines},
        epilogues={state: "\n".join(lines) for state, lines in epilogues.items() if lines},
        unwired=list(unwired),
        assured=[o.attribute for o in assured],
    )
