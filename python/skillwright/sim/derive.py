"""Scenarios derived from a capability model alone, and deadlines from a scenario's inputs.

A capability without a scenario file is validated in scenarios derived from what its model
says: its inputs' data types and units (a length, an angle, a velocity, a time), its
constraints (an OpenMath relation on inputs alone is a precondition a correct skill checks),
its resource's limits (``linearVelocity <= 0.8 m/s``, Requirement), what its outputs measure
(:func:`~skillwright.sim.scenario.infer_quantity`) and whether it senses its surroundings.
One scenario at the origin with odometry and map aligned cannot tell a heading read from
odometry from one read from the map, a turn that ignores its sign, a speed that is never
clipped or a range that is never compared; so besides the nominal scenario each rule below
adds one where the model gives it something to vary (an angle input its words call a turn
to make is bound to the measured turn in each, ``turned``):

* ``negative`` — the inputs that carry the motion's direction with the other sign: ROS
  (REP 103) measures angles counter-clockwise positive and a ``geometry_msgs/Twist`` carries
  signed velocities, so an angle, or the velocities of a capability whose motion is given by
  velocities alone, can be negative; a length only where its model says it is signed.
* ``wraps`` — an angle near pi from a heading near pi: headings from ``atan2`` (tf2's yaw)
  jump from +pi to -pi there, and a heading reported in [0, 2 pi) wraps at zero.
* ``elsewhere`` — the base starts away from the origin, turned: the odometry frame starts
  where the robot was switched on (``odom`` and ``map`` coincide only at the origin), so a
  skill that reads the map pose from odometry, or sends a map goal in the odometry frame,
  shows it here.
* ``clipped`` — a velocity input half again above the resource's stated maximum: the
  resource's Requirement (``<=``) must hold for any input, so the skill has to clip.
* ``refused`` — inputs that violate a precondition (``inDistance >= 0``, a target beyond
  ``armReach``): the skill must refuse them (the scenario expects it to abort).
* ``obstacle`` — where the capability reads a range sensor (a clearance input, an output
  of the nearest return): the box 4 m down the corridor in front, so the clearance must end
  the motion; where the model promises *valid* returns, the lidar also reports dropouts as
  drivers do (``sensor_msgs/LaserScan``: ranges outside [range_min, range_max] are to be
  discarded).

Deadlines grow with the inputs: the motion a scenario asks for takes distance / speed plus
angle / rate plus its explicit times (speeds from the inputs, clipped to the resource's
limits, else the speed a derived input would get), and a scenario may take twice that plus
10 s, never less than the 30 s a scenario gets by default.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Literal

from skillwright.capability.model import Capability, Constraint, DataElement, Parameter
from skillwright.sim.openmath import (
    UNIT_TOLERANCES,
    EvaluationError,
    Value,
    as_value,
    evaluate,
    is_output_variable,
)
from skillwright.sim.scenario import (
    NoiseSpec,
    Scalar,
    Scenario,
    StartPose,
    default_input,
    infer_quantity,
    limit_for_unit,
    surroundings,
)

__all__ = [
    "DEFAULT_DURATION",
    "Role",
    "derived_duration",
    "derived_scenarios",
    "input_roles",
    "violated_preconditions",
]

DEFAULT_DURATION = 30.0
"""The virtual seconds a scenario gets when nothing says otherwise (``Scenario.duration``)."""

_MARGIN_FACTOR = 2.0
_MARGIN_SECONDS = 10.0
_DEGREE_UNITS = ("deg", "°", "degree")
_ANGLE_UNITS = ("rad", *_DEGREE_UNITS)
_SIGNED_WORDS = ("negative", "backward", "backwards", "reverse", "signed", "either direction")
_CLEARANCE_WORDS = ("obstacle", "clearance", "min")

Role = Literal[
    "angle", "angular_rate", "linear_rate", "length", "clearance", "position", "time", "other"
]

# Where a derived scenario may put the base: poses with room around them in each shipped
# world (sim/README.md: the walled room spans -1.4..8.4 m by -1.9..3.9 m with a shelf at
# x 4.5..4.95, y 0..0.65; the corridor runs along +x, 2 m wide, with a box 4 m ahead).
_ELSEWHERE = {"open_floor": StartPose(x=1.2, y=-0.8, heading=2.2)}
_ELSEWHERE["walled_room"] = StartPose(x=2.0, y=2.0, heading=2.2)
_WRAP_HEADING = 2.8
"""A start heading near pi [rad]: a turn of :data:`_WRAP_ANGLE` from it crosses +-pi."""
_WRAP_ANGLE = 3.0
"""An angle near pi [rad], less than half a turn: as a target heading its way round is not
ambiguous."""
_WRAP_TURN = 3.6
"""A turn to make just past half a turn [rad]: from :data:`_WRAP_HEADING` it crosses +-pi
and then zero, and only the measured turn tells it from the shorter one the other way round
to the same heading (a constraint modulo a full turn holds for both)."""
_OBSTACLE_FACE = 4.0
"""x of the near face of the corridor's box [m] (``sim/worlds/corridor.xml``)."""
_SENSE_START = StartPose(x=2.9, y=0.0, heading=0.0)
"""In the corridor, where the box ahead is the nearest thing the lidar sees."""
_DRIVE_START = StartPose(x=1.5, y=0.0, heading=0.0)
"""In the corridor, 2.5 m before the box: room to reach speed before the clearance ends it."""
_DROPOUTS = 0.1
_OTHER_MAGNITUDE = 0.7
"""The ``elsewhere`` scenario's inputs relative to the nominal ones."""
_MAP_TOLERANCE = 0.075
"""Tolerance of a mapped extent [m]: one cell's diagonal of a 0.05 m grid (slam_toolbox's
default resolution), as far apart as two readings of the same map can be when the start
heading is not along the grid."""


@dataclass(frozen=True)
class _Input:
    element: DataElement
    parameter: Parameter
    role: Role


def _text(parameter: Parameter, element: DataElement) -> str:
    parts = [element.name, element.definition or "", parameter.name, parameter.comment or ""]
    return " ".join(parts).lower()


def _role(element: DataElement, parameter: Parameter) -> Role:
    """What kind of quantity an input is, from its unit first and its name second (a name
    that says angular wins over a unit that says m/s, a slip some models make)."""
    if element.data_type in ("Boolean", "String"):
        return "other"
    name = element.name.lower()
    unit = (element.unit or "").strip()
    if "angular" in name or unit in ("rad/s", "deg/s", "°/s"):
        return "angular_rate"
    if unit == "m/s":
        return "linear_rate"
    if unit in _ANGLE_UNITS or any(w in name for w in ("angle", "degree", "heading", "yaw")):
        return "angle"
    if unit == "s":
        return "time"
    if unit == "m":
        if element.expression_goal == "Requirement" or any(w in name for w in _CLEARANCE_WORDS):
            return "clearance"
        if "position" in name or "goal" in name or "target" in name:
            return "position"
        return "length"
    return "other"


def input_roles(capability: Capability) -> dict[str, Role]:
    """Each input component's role, by name."""
    return {i.element.name: i.role for i in _inputs(capability)}


def _inputs(capability: Capability) -> list[_Input]:
    return [
        _Input(element, parameter, _role(element, parameter))
        for parameter in capability.inputs
        for element in parameter.components
    ]


def _axis(name: str) -> str:
    found = re.search(r"[a-z0-9]([XYZ])$|_([xyzXYZ])$", name)
    return (found.group(1) or found.group(2)).lower() if found else ""


def _radians(value: float, element: DataElement) -> float:
    unit = (element.unit or "").strip()
    return math.radians(value) if unit in _DEGREE_UNITS else value


def _from_radians(value: float, element: DataElement) -> float:
    unit = (element.unit or "").strip()
    return round(math.degrees(value), 3) if unit in _DEGREE_UNITS else value


def _output_quantities(capability: Capability) -> set[str]:
    found = set()
    for parameter in capability.outputs:
        for element in parameter.components:
            quantity = infer_quantity(element, parameter, capability.comment or "")
            if quantity is not None:
                found.add(quantity)
    return found


def _maps(capability: Capability) -> bool:
    """Whether the capability builds a map (its lengths are then an area to cover)."""
    quantities = _output_quantities(capability)
    return bool(quantities & {"map_file", "map_length", "map_width"}) or (
        "map" in capability.name.lower()
    )


def _arm(capability: Capability) -> bool:
    """Whether what the capability moves or reports is the arm's tool, not the base."""
    quantities = _output_quantities(capability)
    return bool(quantities) and all(q.startswith("tcp_") for q in quantities)


# ------------------------------------------------------------------ deadlines


def _speed(capability: Capability, inputs: dict[str, Scalar], role: Role) -> float:
    """The speed a motion goes at: the inputs' (their magnitude, clipped to the resource's
    limit), else the speed a derived input would get (half the limit at most)."""
    unit = "rad/s" if role == "angular_rate" else "m/s"
    limit = limit_for_unit(capability, unit)
    given = [
        abs(float(value))
        for i in _inputs(capability)
        if i.role == role
        and isinstance(value := inputs.get(i.element.name), int | float)
        and not isinstance(value, bool)
    ]
    if role == "linear_rate" and given:
        speed = math.hypot(*given) if len(given) > 1 else given[0]
    else:
        speed = max(given, default=0.0)
    if limit is not None and limit > 0:
        speed = min(speed, limit) if speed > 0 else 0.0
    if speed <= 1e-6:
        speed = 0.3 if role == "linear_rate" else 0.5
        if limit is not None and limit > 0:
            speed = min(speed, limit / 2.0)
    return speed


def derived_duration(
    capability: Capability, inputs: dict[str, Scalar], start: StartPose | None = None
) -> float:
    """The virtual seconds a run with ``inputs`` may take: twice what its motion needs plus
    10 s, at least :data:`DEFAULT_DURATION`.

    The motion needs, added up: each length to travel over the linear speed (an area to map:
    its boundary, 2 (length + width), which a range sensor's reach covers from the inside);
    the distance from ``start`` to a position target in the map; each angle (in radians)
    over the angular rate; each time input as it is. Clearances and arm targets add
    nothing of their own (an arm target: its distance from the arm's base at the linear
    speed)."""
    start = start or StartPose()
    linear = _speed(capability, inputs, "linear_rate")
    angular = _speed(capability, inputs, "angular_rate")
    seconds = 0.0
    lengths: list[float] = []
    positions: dict[str, float] = {}
    for item in _inputs(capability):
        value = inputs.get(item.element.name)
        if isinstance(value, bool) or not isinstance(value, int | float):
            continue
        number = float(value)
        if item.role == "length":
            lengths.append(abs(number))
        elif item.role == "angle":
            seconds += abs(_radians(number, item.element)) / angular
        elif item.role == "time":
            seconds += max(number, 0.0)
        elif item.role == "position":
            positions[_axis(item.element.name) or item.element.name] = number
    if _maps(capability) and lengths:
        seconds += 2.0 * sum(lengths) / linear
    else:
        seconds += sum(lengths) / linear
    if positions:
        if _arm(capability):
            seconds += math.sqrt(sum(v * v for v in positions.values())) / linear
        else:
            dx = positions.get("x", start.x) - start.x
            dy = positions.get("y", start.y) - start.y
            seconds += math.hypot(dx, dy) / linear + math.pi / angular
    needed = _MARGIN_FACTOR * seconds + _MARGIN_SECONDS
    return float(max(DEFAULT_DURATION, math.ceil(needed)))


# ------------------------------------------------------------------ preconditions


def _preconditions(capability: Capability) -> list[Constraint]:
    outputs = {e.iri for p in capability.outputs for e in p.components if e.iri}
    return [c for c in capability.constraints if not is_output_variable(c.expression, outputs)]


def violated_preconditions(capability: Capability, inputs: dict[str, Scalar]) -> list[str]:
    """The names of the constraints on inputs alone (with the resource's stated values) that
    ``inputs`` violate; one that cannot be evaluated on them (a measured property) is not
    counted."""
    values: dict[str, Value] = {}
    units: dict[str, str | None] = {}
    for item in _inputs(capability):
        value = as_value(inputs.get(item.element.name))
        if item.element.iri:
            units[item.element.iri] = (item.element.unit or "").strip() or None
            if value is not None:
                values[item.element.iri] = value
    if capability.resource is not None:
        for prop in capability.resource.properties:
            for instance in prop.instances:
                if instance.iri and instance.value is not None:
                    values[instance.iri] = instance.value
                    units[instance.iri] = (instance.unit or "").strip() or None
    violated = []
    for constraint in _preconditions(capability):
        try:
            result = evaluate(constraint.expression, values, units, UNIT_TOLERANCES)
        except EvaluationError:
            continue
        if result.value is False:
            violated.append(constraint.name)
    return violated


# ------------------------------------------------------------------ the variants


def nominal_inputs(capability: Capability) -> dict[str, Scalar]:
    """Every input from its type and unit (see :func:`~skillwright.sim.scenario.default_input`)."""
    return {
        element.name: default_input(element, parameter, capability)
        for parameter in capability.inputs
        for element in parameter.components
    }


def _number(value: Scalar) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


def _direction_inputs(capability: Capability) -> list[_Input]:
    """The inputs whose sign says which way the motion goes: the angles; else the lengths
    the model says are signed; else, when no length or angle bounds the motion, the
    velocities (a motion given by velocities alone)."""
    items = _inputs(capability)
    angles = [i for i in items if i.role == "angle"]
    if angles:
        return angles
    lengths = [i for i in items if i.role == "length"]
    signed = [i for i in lengths if any(w in _text(i.parameter, i.element) for w in _SIGNED_WORDS)]
    if signed:
        return signed
    if lengths or any(i.role == "position" for i in items):
        return []
    return [i for i in items if i.role in ("linear_rate", "angular_rate")]


def _negative(capability: Capability, base: dict[str, Scalar]) -> dict[str, Scalar] | None:
    inputs = dict(base)
    changed = False
    for item in _direction_inputs(capability):
        value = _number(inputs[item.element.name])
        if value is not None and value != 0.0:
            inputs[item.element.name] = -value
            changed = True
    return inputs if changed else None


def _refusing(capability: Capability, base: dict[str, Scalar]) -> tuple[dict[str, Scalar], str]:
    """Inputs that violate one precondition, and its name: the precondition's inputs negated,
    else scaled up fourfold (past a bound such as a reach); empty when neither does."""
    for constraint in _preconditions(capability):
        from skillwright.sim.openmath import variables

        mentioned = {v.refers_to for v in variables(constraint.expression) if v.refers_to}
        names = [i.element.name for i in _inputs(capability) if i.element.iri in mentioned]
        numbers = [n for n in names if _number(base[n]) is not None]
        if not numbers:
            continue
        for factor in (-1.0, 4.0):
            candidate = dict(base)
            for name in numbers:
                value = _number(base[name]) or 0.0
                candidate[name] = value * factor if value != 0.0 else factor
            if constraint.name in violated_preconditions(capability, candidate):
                return candidate, constraint.name
    return {}, ""


def _wrapped(
    capability: Capability, base: dict[str, Scalar], angles: list[_Input]
) -> dict[str, Scalar]:
    """The nominal inputs with each angle near pi: an angle its words call a turn to make
    just past half a turn (:data:`_WRAP_TURN`), unless a precondition bounds it to half a
    turn; any other angle (perhaps a target heading) just below (:data:`_WRAP_ANGLE`)."""
    inputs = dict(base)
    for item in angles:
        inputs[item.element.name] = _from_radians(_WRAP_ANGLE, item.element)
    turned = dict(inputs)
    for item in angles:
        if _turn_by(item):
            turned[item.element.name] = _from_radians(_WRAP_TURN, item.element)
    return inputs if violated_preconditions(capability, turned) else turned


def _scaled(capability: Capability, base: dict[str, Scalar], factor: float) -> dict[str, Scalar]:
    """The nominal inputs with every motion magnitude (length, angle, velocity, time, target)
    times ``factor``: a skill that uses a constant for an input can only be told from one
    that uses the input where the input has another value than the constant."""
    inputs = dict(base)
    for item in _inputs(capability):
        value = _number(inputs[item.element.name])
        kinds = ("angle", "angular_rate", "linear_rate", "length", "position", "time")
        if value is not None and item.role in kinds:
            inputs[item.element.name] = round(value * factor, 4)
    return inputs


def _clipped(capability: Capability, base: dict[str, Scalar]) -> tuple[dict[str, Scalar], str]:
    inputs = dict(base)
    clipped = []
    for item in _inputs(capability):
        if item.role not in ("linear_rate", "angular_rate"):
            continue
        unit = (item.element.unit or "").strip()
        limit = limit_for_unit(capability, unit)
        value = _number(inputs[item.element.name])
        if limit is None or limit <= 0 or value is None:
            continue
        inputs[item.element.name] = round(1.5 * limit, 4)
        clipped.append(f"{item.element.name} {1.5 * limit:g} {unit} (limit {limit:g})")
    return (inputs, ", ".join(clipped)) if clipped else ({}, "")


def _reads_range(capability: Capability) -> bool:
    """Whether the capability compares or reports a range sensor's returns: a clearance input
    or an output measured as the nearest return."""
    nearest = {"nearest_obstacle_distance", "nearest_obstacle_bearing"}
    clearance = any(i.role == "clearance" for i in _inputs(capability))
    return clearance or bool(_output_quantities(capability) & nearest)


def _promises_valid(capability: Capability) -> bool:
    parts = [capability.comment or ""]
    for parameter in capability.outputs:
        parts += [parameter.comment or ""] + [e.definition or "" for e in parameter.components]
    return re.search(r"\bvalid\b", " ".join(parts).lower()) is not None


def _towards_obstacle(capability: Capability, base: dict[str, Scalar]) -> dict[str, Scalar]:
    """Inputs that drive straight at the box: forward at the nominal speed, nothing sideways
    or turning, for long enough to reach it, so only the clearance can end the motion."""
    inputs = dict(base)
    items = _inputs(capability)
    forward = 0.0
    for item in items:
        value = _number(inputs[item.element.name])
        if value is None:
            continue
        sideways = item.role == "linear_rate" and _axis(item.element.name) in ("y", "z")
        if item.role == "angular_rate" or sideways:
            inputs[item.element.name] = 0.0
        elif item.role == "linear_rate":
            inputs[item.element.name] = abs(value)
            forward = max(forward, abs(value))
    if forward > 0.0:
        reach = _OBSTACLE_FACE - _DRIVE_START.x + 1.0
        for item in items:
            if item.role == "time" and _number(inputs[item.element.name]) is not None:
                inputs[item.element.name] = round(reach / forward, 1)
    return inputs


_TURN_WORDS = ("turn by", "rotate by", "to turn", "counter-clockwise", "clockwise")


def _turn_by(item: _Input) -> bool:
    """Whether an angle input is a turn to make, by its words ("angle to turn by", "positive
    turns counter-clockwise"): the simulator's measure of the turn over execute must then
    equal it (``turned``). A heading constraint modulo a full turn holds for a turn either
    way round; the measured turn does not. An angle that may be a target heading is not
    bound."""
    return item.role == "angle" and any(
        w in _text(item.parameter, item.element) for w in _TURN_WORDS
    )


def _moves(capability: Capability) -> bool:
    return any(
        i.role in ("angle", "angular_rate", "linear_rate", "length", "position")
        for i in _inputs(capability)
    )


def derived_scenarios(capability: Capability, *, localised: bool = True) -> list[Scenario]:
    """The scenarios to validate a skill of ``capability`` in when no file gives them: the
    nominal one, then each variant of the module's rules the model gives something to vary
    for (2 to 6 in all). Every scenario's description says what it checks and why; each has
    its own seed and a deadline from its inputs (:func:`derived_duration`).

    ``localised`` says whether the robot has a map frame (a localiser or SLAM). Without one
    the odometry frame is the only one it can know, while the simulator measures poses and
    headings in the world (map) frame: ``elsewhere`` and ``wraps`` then start at the origin,
    where the two coincide (``elsewhere`` keeps its other magnitudes)."""
    world = "walled_room" if surroundings(capability) else "open_floor"
    base = nominal_inputs(capability)
    made: list[Scenario] = []
    tolerances = {
        element.name: _MAP_TOLERANCE
        for parameter in capability.outputs
        for element in parameter.components
        if infer_quantity(element, parameter, capability.comment or "")
        in ("map_length", "map_width")
    }

    def add(
        name: str,
        description: str,
        inputs: dict[str, Scalar],
        *,
        start: StartPose | None = None,
        where: str = world,
        expect: Literal["completed", "aborted"] = "completed",
        noise: NoiseSpec | None = None,
    ) -> None:
        if expect == "completed" and violated_preconditions(capability, inputs):
            return  # the inputs break a precondition: a correct skill would refuse them
        pose = start or StartPose()
        made.append(
            Scenario(
                name=name,
                description=description,
                world=where,
                start=pose,
                inputs=inputs,
                duration=derived_duration(capability, inputs, pose),
                seed=len(made),
                expect=expect,
                tolerances=tolerances,
                ground_truth=dict(asked),
                noise=noise if noise is not None else "default",
            )
        )

    asked = {i.element.name: "turned" for i in _inputs(capability) if _turn_by(i)}
    add(
        "derived",
        f"derived from the capability model of {capability.name}: every input from its type "
        "and unit, at the origin with odometry and map aligned",
        base,
    )
    negative = _negative(capability, base)
    if negative is not None:
        names = ", ".join(i.element.name for i in _direction_inputs(capability))
        add(
            "negative",
            f"{names} with the other sign: ROS angles and velocities are signed "
            "(counter-clockwise and forward positive), so the motion must go the other way",
            negative,
        )
    angles = [i for i in _inputs(capability) if i.role == "angle"]
    if angles:
        wrapped = _wrapped(capability, base, angles)
        past = any(
            _turn_by(i) and abs(_radians(float(wrapped[i.element.name]), i.element)) > math.pi
            for i in angles
        )
        add(
            "wraps",
            f"{', '.join(i.element.name for i in angles)} near pi from a heading of "
            f"{_WRAP_HEADING:g} rad: a heading from atan2 jumps from +pi to -pi on the way, "
            "and a heading in [0, 2 pi) wraps at zero"
            + (
                "; a turn past half a turn, which the other way round would reach the same "
                "heading by a shorter turn than the one asked for"
                if past
                else ""
            ),
            wrapped,
            start=StartPose(heading=_WRAP_HEADING if localised else 0.0),
        )
    elsewhere = _ELSEWHERE.get(world)
    if elsewhere is not None and not _arm(capability) and not localised:
        add(
            "elsewhere",
            "at the origin (the robot has no map frame, so only there does the pose it can "
            f"know from odometry equal the map's) with {_OTHER_MAGNITUDE:g} times the nominal "
            "inputs, so an input replaced by a constant shows",
            _scaled(capability, base, _OTHER_MAGNITUDE),
        )
    elif elsewhere is not None and not _arm(capability):
        add(
            "elsewhere",
            f"start at ({elsewhere.x:g}, {elsewhere.y:g}) m facing {elsewhere.heading:g} rad: "
            "odometry starts where the robot starts, so the odometry and map frames are apart "
            "and a pose or heading taken from the wrong one shows; the inputs are "
            f"{_OTHER_MAGNITUDE:g} times the nominal ones, so an input replaced by a constant "
            "shows too",
            _scaled(capability, base, _OTHER_MAGNITUDE),
            start=elsewhere,
        )
    clipped, what = _clipped(capability, base)
    if clipped:
        add(
            "clipped",
            f"asked for more than the resource allows ({what}): its limits are Requirements "
            "that hold for any input, so the skill must clip the command",
            clipped,
        )
    refusing, constraint = _refusing(capability, base)
    if refusing:
        add(
            "refused",
            f"inputs that violate the precondition {constraint}: a correct skill refuses them",
            refusing,
            expect="aborted",
        )
    if _reads_range(capability):
        moving = _moves(capability)
        valid = _promises_valid(capability)
        add(
            "obstacle",
            "in the corridor with the box ahead"
            + (
                ", driving straight at it long enough to reach it: the clearance must end "
                "the motion before contact"
                if moving
                else ": the box is the nearest thing the lidar sees"
            )
            + (
                "; about one beam in ten is reported invalid (NaN or below range_min), which "
                "the model's valid returns exclude"
                if valid
                else ""
            ),
            _towards_obstacle(capability, base) if moving else base,
            start=_DRIVE_START if moving else _SENSE_START,
            where="corridor",
            noise=NoiseSpec(scan_invalid=_DROPOUTS) if valid else None,
        )
    return made
