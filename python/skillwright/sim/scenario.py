"""Scenarios: the situation a skill is validated in, and how its outputs are measured.

A scenario file (YAML) names the capability it is for and lists one or more scenarios::

    capability: http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward
    scenarios:
      - name: straight_ahead
        description: Drive 1.5 m over the open floor at 0.4 m/s.
        world: open_floor            # a shipped world, or a path to an MJCF file
        start: {x: 0.0, y: 0.0, heading: 0.0}
        inputs: {inDistance: 1.5, inLinearVelocity: 0.4}
        duration: 20                 # virtual seconds the run may take at most
        ground_truth: {outDistance: travelled_distance}

An input bound under ``ground_truth`` (``inAngle: turned``) is a motion the skill is asked
for: the simulator's measure of it over execute must equal the input, so a rotate skill that
reaches the target heading the other way round fails.

Inputs a scenario leaves out, the ground truth of outputs it does not bind, and whole
scenarios for capabilities without a file are derived from the capability model (its
parameters' units, names and comments). Every error names the file and line.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from skillwright.capability.model import Capability, DataElement, Parameter
from skillwright.errors import FileFormatError, InputFileError, InputFileNotFoundError
from skillwright.sim.assets import resolve_world, scenario_files

__all__ = [
    "QUANTITIES",
    "NoiseSpec",
    "Scenario",
    "ScenarioFile",
    "ScenarioSet",
    "StartPose",
    "default_input",
    "default_scenario",
    "derived_set",
    "infer_quantity",
    "limit_for_unit",
    "load_scenario_file",
    "scenarios_for",
    "surroundings",
]

QUANTITIES: dict[str, str] = {
    "position_x": "x of the base in the map frame when execute ended [m]",
    "position_y": "y of the base in the map frame when execute ended [m]",
    "heading": "heading of the base in the map frame when execute ended, in [0, 2 pi) [rad]",
    "linear_velocity_x": "forward velocity of the base when execute ended [m/s]",
    "linear_velocity_y": "leftward velocity of the base when execute ended [m/s]",
    "angular_velocity": "yaw rate of the base when execute ended [rad/s]",
    "travelled_distance": "distance the base moved during execute along its heading at the "
    "start of execute; negative when it went backwards [m]",
    "displacement": "straight-line distance the base moved during execute, in any direction [m]",
    "path_length": "length of the path the base drove during execute [m]",
    "turned": "how far the base turned during execute, counter-clockwise positive, not "
    "wrapped [rad]",
    "command_duration": "how long the skill's velocity commands kept the base moving [s]",
    "nearest_obstacle_distance": "range of the nearest return of the last scan, without noise [m]",
    "nearest_obstacle_bearing": "bearing of that return in the lidar frame, in [-pi, pi] [rad]",
    "map_length": "extent of the mapped area along the start heading [m]",
    "map_width": "extent of the mapped area across the start heading [m]",
    "map_file": "the name of a map saved through a map-saver service",
    "tcp_position_x": "x of the arm's tool centre point in the arm's base frame [m]",
    "tcp_position_y": "y of the arm's tool centre point in the arm's base frame [m]",
    "tcp_position_z": "z of the arm's tool centre point in the arm's base frame [m]",
}
"""What the simulator can measure, by the name a scenario binds an output to."""

Scalar = float | int | bool | str


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class StartPose(_Model):
    """Where the base starts, in the map (world) frame."""

    x: float = Field(default=0.0, description="x [m].")
    y: float = Field(default=0.0, description="y [m].")
    heading: float = Field(default=0.0, description="Heading [rad], counter-clockwise from +x.")


class NoiseSpec(_Model):
    """Standard deviations of the sensors' noise; leave out what should keep its default."""

    odometry_linear: float | None = Field(default=None, ge=0, description="[m/s]")
    odometry_angular: float | None = Field(default=None, ge=0, description="[rad/s]")
    scan: float | None = Field(default=None, ge=0, description="Range noise [m].")
    imu: float | None = Field(default=None, ge=0, description="Yaw rate noise [rad/s].")
    localisation: float | None = Field(default=None, ge=0, description="Pose noise [m].")
    scan_invalid: float | None = Field(
        default=None,
        ge=0,
        le=1,
        description="Share of scan beams reported invalid (half NaN, half 0.0 below range_min).",
    )


class Scenario(_Model):
    """One situation to run the skill in, and what to expect."""

    name: str = Field(description="Short identifier, unique in its file.", pattern=r"^[\w.-]+$")
    description: str = Field(default="", description="What the scenario checks, in words.")
    world: str = Field(
        default="open_floor",
        description="A shipped world (open_floor, corridor, walled_room) or an MJCF file "
        "relative to the scenario file.",
    )
    start: StartPose = Field(default_factory=StartPose, description="Start pose of the base.")
    inputs: dict[str, Scalar] = Field(
        default_factory=dict, description="Skill parameters by name; missing ones are derived."
    )
    duration: float = Field(
        default=30.0, gt=0, le=3600, description="Virtual seconds the whole run may take."
    )
    seed: int = Field(default=0, description="Seed of the sensors' noise.")
    noise: Literal["default", "none"] | NoiseSpec = Field(
        default="default", description="`default`, `none`, or standard deviations."
    )
    stop_after: float | None = Field(
        default=None,
        gt=0,
        description="In the second run, stop the skill this many virtual seconds after execute "
        "began (default: half of execute's duration in the first run).",
    )
    stop_run: Literal["auto", "always", "never"] = Field(
        default="auto",
        description="Whether the skill is run a second time and stopped during execute; "
        "`auto`: when the first run moved the base or sent goals.",
    )
    expect: Literal["completed", "aborted"] = Field(
        default="completed",
        description="How the first run should end: completed, or aborted (the skill must "
        "refuse the scenario's inputs).",
    )
    runtime: dict[str, Any] = Field(
        default_factory=dict,
        description="Settings of the simulated runtime for interfaces the world does not "
        "serve: `topics`, `services`, `actions`, `deadlines`, `limits`, `replay`, `settle` "
        "(see `skillwright run`'s scenarios).",
    )
    ground_truth: dict[str, str] = Field(
        default_factory=dict,
        description="Output name -> what the simulator measures for it (see QUANTITIES); "
        "input name -> the motion that input asks for (`inAngle: turned`), which the "
        "simulator's measure must then equal.",
    )
    tolerances: dict[str, float] = Field(
        default_factory=dict,
        description="Tolerance by unit (`m`, `rad`, ...) or by output or constraint name.",
    )
    skip: list[str] = Field(
        default_factory=list, description="Oracles to leave out, by id (e.g. `contact`)."
    )


class ScenarioFile(_Model):
    """The contents of a scenario file."""

    capability: str = Field(description="IRI (or local name) of the capability.")
    scenarios: list[Scenario] = Field(min_length=1, description="At least one scenario.")


class ScenarioSet(_Model):
    """Scenarios ready to run for one capability, with where they came from."""

    source: str = Field(description="The scenario file, or `derived from <capability>`.")
    folder: str | None = Field(default=None, description="Folder relative worlds resolve in.")
    scenarios: list[Scenario]
    notes: list[str] = Field(default_factory=list, description="What was derived or assumed.")


# ------------------------------------------------------------------ deriving from the model


def _words(parameter: Parameter | None, element: DataElement) -> str:
    parts = [element.name, element.definition or ""]
    if parameter is not None:
        parts += [parameter.name, parameter.comment or ""]
    return " ".join(parts).lower()


_ANGLE_UNITS = ("rad", "deg", "°", "degree")
_ARM_WORDS = ("tool", "tcp", "end effector", "end-effector", "arm", "manipulator")
_SENSED_WORDS = ("lidar", "closest", "nearest", "obstacle", "scan")


def infer_quantity(
    element: DataElement, parameter: Parameter | None = None, context: str = ""
) -> str | None:
    """What the simulator measures for an output (or a resource property), from its name,
    unit and comment, and the capability's comment as ``context``; ``None`` when nothing
    fits."""
    name = element.name.lower()
    unit = (element.unit or "").strip()
    words = _words(parameter, element)
    around = f"{words} {context.lower()}"
    # An axis is a capital X/Y/Z after the name (outPositionX) or a suffix _x/_y/_z.
    found = re.search(r"[a-z0-9]([XYZ])$|_([xyzXYZ])$", element.name)
    axis = (found.group(1) or found.group(2)).lower() if found else ""
    if "position" in name and axis:
        if any(w in around for w in _ARM_WORDS):
            return f"tcp_position_{axis}"
        return f"position_{axis}" if axis in "xy" else None
    sensed = any(w in around for w in _SENSED_WORDS)
    angle = unit in _ANGLE_UNITS or any(w in name for w in ("angle", "degree", "bearing"))
    if "angular" in name or unit in ("rad/s", "deg/s"):
        # A name that says angular wins over a unit that says m/s (a slip in a model).
        return "angular_velocity"
    if unit == "m" and sensed and ("distance" in name or "range" in words):
        return "nearest_obstacle_distance"
    if angle and sensed:
        return "nearest_obstacle_bearing"
    if angle and ("heading" in name or "degree" in name or "orientation" in name):
        return "heading"
    if unit == "m/s":
        return "linear_velocity_y" if axis == "y" else "linear_velocity_x"
    if unit == "m" and "map" in name:
        if "length" in name:
            return "map_length"
        if "width" in name:
            return "map_width"
    if unit == "m" and "distance" in name:
        return "travelled_distance"
    if "map" in name and (element.data_type == "String" or unit in ("", "-")):
        return "map_file"
    if unit == "s" and ("duration" in name or "time" in name):
        return "command_duration"
    return None


def default_input(element: DataElement, parameter: Parameter, capability: Capability) -> Scalar:
    """A sensible value for an input the scenario does not give."""
    if element.value is not None:
        return element.value
    kind = element.data_type or "Real"
    if kind == "Boolean":
        return True
    if kind == "String":
        return ""
    unit = (element.unit or "").strip()
    name = element.name.lower()
    limit = limit_for_unit(capability, unit)
    value = {
        "m": 0.5 if ("obstacle" in name or "min" in name) else 1.0,
        "m/s": 0.3,
        "rad": 1.5708,
        "rad/s": 0.5,
        # The same quarter turn and rate in degrees.
        "deg": 90.0,
        "°": 90.0,
        "degree": 90.0,
        "deg/s": 30.0,
        "s": 3.0,
    }.get(unit, 1.0)
    if limit is not None:
        value = min(value, limit / 2.0)
    return int(value) if kind == "Integer" else value


def limit_for_unit(capability: Capability, unit: str) -> float | None:
    """The resource's stated maximum for quantities of ``unit`` (a Requirement with ``<=`` or
    ``<`` and a number, as ``linearVelocity <= 0.8 m/s``), else ``None``."""
    if capability.resource is None:
        return None
    for prop in capability.resource.properties:
        for instance in prop.instances:
            if (
                instance.unit == unit
                and instance.expression_goal == "Requirement"
                and isinstance(instance.value, int | float)
                and instance.logic_interpretation in ("<=", "<")
            ):
                return float(instance.value)
    return None


def default_scenario(capability: Capability) -> Scenario:
    """A scenario derived from the capability alone: the walled room for a capability that
    senses or maps its surroundings, else the open floor; the origin, inputs from the
    parameters' types and units, ground truth inferred for every output."""
    inputs: dict[str, Scalar] = {}
    for parameter in capability.inputs:
        for element in parameter.components:
            inputs[element.name] = default_input(element, parameter, capability)
    return Scenario(
        name="derived",
        description=f"derived from the capability model of {capability.name}",
        world="walled_room" if surroundings(capability) else "open_floor",
        inputs=inputs,
    )


def surroundings(capability: Capability) -> bool:
    """Whether the capability senses or maps what is around the robot (on the open floor
    its scan returns nothing: the paper's get-distance-to-nearest-object rightly raised "no
    object detected" there, and the scenario blamed it)."""
    parts = [capability.name, capability.label or "", capability.comment or ""]
    for parameter in (*capability.inputs, *capability.outputs):
        parts += [parameter.name, parameter.comment or ""]
        parts += [f"{e.name} {e.definition or ''}" for e in parameter.components]
    text = " ".join(parts).lower()
    outputs = [e.name for p in capability.outputs for e in p.components]
    maps = any("map" in name.lower() for name in (capability.name, *outputs))
    return maps or any(w in text for w in _SENSED_WORDS)


def _complete(scenario: Scenario, capability: Capability, notes: list[str]) -> Scenario:
    """Fill in what the scenario leaves to the model: inputs and ground truth bindings."""
    inputs = dict(scenario.inputs)
    for parameter in capability.inputs:
        for element in parameter.components:
            if element.name not in inputs:
                inputs[element.name] = default_input(element, parameter, capability)
                notes.append(
                    f"scenario {scenario.name}: input {element.name} not given; "
                    f"{inputs[element.name]!r} derived from its type and unit"
                )
    ground_truth = dict(scenario.ground_truth)
    for parameter in capability.outputs:
        for element in parameter.components:
            if element.name in ground_truth:
                continue
            quantity = infer_quantity(element, parameter, capability.comment or "")
            if quantity is not None:
                ground_truth[element.name] = quantity
            else:
                notes.append(
                    f"scenario {scenario.name}: nothing the simulator measures fits output "
                    f"{element.name}; bind it under ground_truth to check it"
                )
    update: dict[str, Any] = {"inputs": inputs, "ground_truth": ground_truth}
    if "duration" not in scenario.model_fields_set:
        from skillwright.sim.derive import DEFAULT_DURATION, derived_duration

        duration = derived_duration(capability, inputs, scenario.start)
        if duration > DEFAULT_DURATION:
            notes.append(
                f"scenario {scenario.name}: no duration given; {duration:g} s derived from its "
                "inputs (twice what distance / speed, angle / rate and its times need, plus 10 s)"
            )
        update["duration"] = duration
    return scenario.model_copy(update=update)


# ------------------------------------------------------------------ reading files


def _yaml_line(text: str, location: tuple[Any, ...]) -> int | None:
    """The 1-based line of the YAML node at ``location`` (keys and list indexes)."""
    import yaml

    try:
        node = yaml.compose(text)
    except yaml.YAMLError:
        return None
    line = None if node is None else node.start_mark.line + 1
    for key in location:
        if isinstance(node, yaml.MappingNode):
            found = None
            for key_node, value_node in node.value:
                if key_node.value == str(key):
                    found = value_node
                    line = key_node.start_mark.line + 1
                    break
            node = found
        elif isinstance(node, yaml.SequenceNode) and isinstance(key, int) and key < len(node.value):
            node = node.value[key]
            line = node.start_mark.line + 1
        else:
            break
        if node is None:
            break
    return line


def _where(path: Path, text: str, location: tuple[Any, ...]) -> str:
    line = _yaml_line(text, location)
    field = ".".join(str(p) for p in location)
    return f"{path}:{line}: {field}" if line else f"{path}: {field}"


def load_scenario_file(path: Path) -> ScenarioFile:
    """Read and check the shape of a scenario file (not yet against a capability)."""
    import yaml

    if not path.is_file():
        raise InputFileNotFoundError(f"scenario file {path}: no such file; check the path")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"scenario file {path}: cannot be read as UTF-8 text") from error
    try:
        # libyaml's safe loader where PyYAML has it: a validation reads every shipped
        # scenario file until it finds the capability's, several times faster.
        document = yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
        problem = getattr(error, "problem", None) or str(error)
        raise FileFormatError(f"{where}: YAML syntax error: {problem}") from None
    if not isinstance(document, dict):
        raise FileFormatError(
            f"{path}: a scenario file is a mapping with `capability` and `scenarios`"
        )
    try:
        parsed = ScenarioFile.model_validate(document)
    except ValidationError as error:
        first = error.errors()[0]
        location = tuple(first["loc"])
        raise FileFormatError(
            f"{_where(path, text, location)}: {first['msg']}"
            + (f" ({error.error_count()} problems in all)" if error.error_count() > 1 else "")
        ) from None
    names = [s.name for s in parsed.scenarios]
    for index, name in enumerate(names):
        if names.index(name) != index:
            raise FileFormatError(
                f"{_where(path, text, ('scenarios', index, 'name'))}: scenario name {name!r} "
                "is used twice"
            )
    return parsed


def _matches(reference: str, capability: Capability) -> bool:
    reference = reference.strip()
    return reference in (capability.iri, capability.name)


def _check_against(path: Path, parsed: ScenarioFile, capability: Capability) -> None:
    """Names in the scenarios must be the capability's, worlds must exist."""
    text = path.read_text(encoding="utf-8")
    inputs = {e.name for p in capability.inputs for e in p.components}
    outputs = {e.name for p in capability.outputs for e in p.components}
    constraints = {c.name for c in capability.constraints}
    for index, scenario in enumerate(parsed.scenarios):
        at = ("scenarios", index)
        for name in scenario.inputs:
            if name not in inputs:
                raise FileFormatError(
                    f"{_where(path, text, (*at, 'inputs', name))}: {capability.name} has no input "
                    f"{name!r}; its inputs are {', '.join(sorted(inputs)) or 'none'}"
                )
        for name, quantity in scenario.ground_truth.items():
            if name not in outputs and name not in inputs:
                raise FileFormatError(
                    f"{_where(path, text, (*at, 'ground_truth', name))}: {capability.name} has no "
                    f"output or input {name!r}; its outputs are "
                    f"{', '.join(sorted(outputs)) or 'none'}, its inputs "
                    f"{', '.join(sorted(inputs)) or 'none'}"
                )
            if quantity not in QUANTITIES:
                raise FileFormatError(
                    f"{_where(path, text, (*at, 'ground_truth', name))}: {quantity!r} is not "
                    f"something the simulator measures; use one of {', '.join(QUANTITIES)}"
                )
        for key, value in scenario.tolerances.items():
            known = key in outputs or key in constraints or re.fullmatch(r"[\w/°]+", key)
            if not known or value < 0 or not math.isfinite(value):
                raise FileFormatError(
                    f"{_where(path, text, (*at, 'tolerances', key))}: a tolerance is a "
                    "non-negative number keyed by a unit, an output or a constraint name"
                )
        try:
            resolve_world(scenario.world, path.parent)
        except InputFileNotFoundError as error:
            raise FileFormatError(f"{_where(path, text, (*at, 'world'))}: {error}") from None
        _check_runtime(path, text, at, scenario)


_RUNTIME_KEYS = (
    "topics",
    "services",
    "actions",
    "deadlines",
    "limits",
    "replay",
    "settle",
    "traffic",
)


def _check_runtime(path: Path, text: str, at: tuple[Any, ...], scenario: Scenario) -> None:
    from skillwright.runtime.scenario import RunScenario

    for key in scenario.runtime:
        if key not in _RUNTIME_KEYS:
            raise FileFormatError(
                f"{_where(path, text, (*at, 'runtime', key))}: unknown runtime setting {key!r}; "
                f"use {', '.join(_RUNTIME_KEYS)}"
            )
    try:
        RunScenario.model_validate(scenario.runtime)
    except ValidationError as error:
        first = error.errors()[0]
        location = (*at, "runtime", *first["loc"])
        raise FileFormatError(f"{_where(path, text, location)}: {first['msg']}") from None


def scenarios_for(
    capability: Capability, scenario_file: Path | None = None, *, localised: bool = True
) -> ScenarioSet:
    """The scenarios to validate a skill of ``capability`` in: those of ``scenario_file``,
    else those of the shipped file for the capability, else those derived from the model
    (:func:`skillwright.sim.derive.derived_scenarios`; ``localised``: whether the robot has
    a map frame)."""
    notes: list[str] = []
    candidates = [scenario_file] if scenario_file is not None else scenario_files()
    for path in candidates:
        parsed = load_scenario_file(path)
        if not _matches(parsed.capability, capability):
            if scenario_file is not None:
                raise FileFormatError(
                    f"{path}: the scenarios are for {parsed.capability}, not for "
                    f"{capability.iri}; give a scenario file for this capability"
                )
            continue
        _check_against(path, parsed, capability)
        scenarios = [_complete(s, capability, notes) for s in parsed.scenarios]
        return ScenarioSet(
            source=str(path), folder=str(path.parent), scenarios=scenarios, notes=notes
        )
    return derived_set(capability, localised=localised)


def derived_set(capability: Capability, *, localised: bool = True) -> ScenarioSet:
    """The scenarios derived from the capability model alone
    (:func:`skillwright.sim.derive.derived_scenarios`), completed and with notes."""
    from skillwright.sim.derive import derived_scenarios

    notes: list[str] = []
    derived = derived_scenarios(capability, localised=localised)
    notes.append(
        f"no scenario file for {capability.iri}; {len(derived)} scenario(s) derived from the "
        f"capability model ({', '.join(s.name for s in derived)}: the walled room for a "
        "capability that senses or maps its surroundings, else the open floor; inputs from "
        "the parameters' units, varied by sign, wrap-around, start pose, limits, "
        "preconditions and obstacles where the model allows; deadlines from the inputs)"
    )
    scenarios = [_complete(s, capability, notes) for s in derived]
    return ScenarioSet(source=f"derived from {capability.name}", scenarios=scenarios, notes=notes)
