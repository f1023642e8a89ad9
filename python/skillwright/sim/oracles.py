"""Oracles derived from the capability model, judged on the simulator's ground truth.

For one run of a skill in a scenario:

* ``outcome`` — the run ended as the scenario expects (completed, stopped, or aborted
  because the skill refused its inputs).
* ``constraint:<name>`` — each OpenMath constraint of the capability holds for the inputs
  and the outputs **the skill reported**; constraints on inputs alone are preconditions.
* ``truth:<name>`` — the same constraint with the outputs replaced by what the simulator
  **measured** (the distance really travelled, the heading really reached), so a skill
  that reports the right number without doing the work fails.
* ``output:<name>`` — each reported output equals its measured value, within the tolerance
  of its unit (angles on the circle); a bearing to the nearest obstacle also passes when the
  true range that way is as near, within the distance tolerance. ``assured:<name>`` — an
  output whose value the model asserts (``outLinearVelocity = 0.0``, Assurance) is reported
  with that value.
* ``requirement:<input>`` — an input that is a requirement on the motion
  (``inMinObstacleDistance``, ``>=``): the clearance the lidar saw stays above it, less the
  distance the base needs to brake once something came that close.
* ``limit:<property>`` — the resource's velocity requirements (``linearVelocity <= 0.8``)
  are never exceeded: neither by a command the skill published nor by the base's measured
  velocity.
* ``contact`` — the chassis never touched anything.
* ``rest:<state>`` — when completing (or stopping, or aborting) ended, nothing kept the base
  moving: the command in force was zero and no navigation goal was running. It does not
  apply after completing when the capability promises motion (an output velocity that is
  not asserted to be zero, as set-velocity's).

Resource properties that are actual values (``heading``, ``positionX``) take the measured
value of the moment execute began. Outputs of the end state (:data:`END_STATE`: a pose, a
distance travelled, a turn, a mapped extent) are measured once the base has settled after
execute returned (within the scenario's time), and a value the base had while it braked
after the skill's stop passes too; instant values (a velocity, the nearest obstacle) are
measured when execute returned. Both are in each verdict's data.

Judged by what the robot can know: on a robot without localisation (nothing publishes
``map -> odom``) a pose is compared in the odometry frame, which starts where the robot
started; no tolerance is less than :data:`NOISE_SIGMAS` standard deviations of the noise of
the sensor the value comes from (:func:`noise_floor`); a saved map is asked for only of a
robot with a map-saving service.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from skillwright.capability.model import Capability, Constraint, DataElement
from skillwright.runtime.motion import wrap_pi
from skillwright.sim.openmath import (
    UNIT_TOLERANCES,
    EvaluationError,
    Value,
    as_value,
    difference,
    evaluate,
    is_output_variable,
)
from skillwright.sim.scenario import Scenario, infer_quantity
from skillwright.sim.truth import GroundTruth, wrap_two_pi

__all__ = ["RunView", "StateSpan", "Verdict", "judge"]

REST_LINEAR = 0.01
REST_ANGULAR = 0.02
MEASURED_LIMIT_SLACK = {"m/s": 0.02, "rad/s": 0.03}
"""Measured velocities may overshoot a limit this much (servo tracking, not the skill)."""
_VELOCITY_UNITS = ("m/s", "rad/s")


class Verdict(BaseModel):
    """The judgement of one oracle on one run."""

    model_config = ConfigDict(extra="forbid")

    oracle: str = Field(description="Identifier, e.g. `constraint:distanceCovered`.")
    kind: Literal[
        "outcome",
        "precondition",
        "constraint",
        "truth",
        "output",
        "requirement",
        "limit",
        "contact",
        "rest",
    ] = Field(description="Which family of oracle.")
    check: str = Field(description="What it checks, e.g. `abs(outDistance - inDistance) <= 0.02`.")
    passed: bool | None = Field(description="True, False, or None when it does not apply.")
    message: str = Field(description="The verdict in words, with the values compared.")
    measured: dict[str, Any] = Field(
        default_factory=dict, description="The values involved, by name."
    )
    tolerance: float | None = Field(default=None, description="The tolerance used, if any.")
    time: float | None = Field(
        default=None, description="Virtual time the verdict refers to (e.g. first violation)."
    )
    state: str | None = Field(default=None, description="The PackML state running then.")


@dataclass(frozen=True)
class StateSpan:
    """One state method run: when, and how it ended."""

    name: str
    start: float
    end: float
    outcome: str = "returned"


@dataclass
class RunView:
    """What the oracles need to know about a run, whatever ran it."""

    states: list[StateSpan]
    outputs: dict[str, Any]
    ended: Literal["completed", "stopped", "aborted", "failed"]
    end_time: float
    message: str = ""
    """Why the run aborted or failed, in the runtime's words."""
    notes: list[str] = field(default_factory=list)
    events: list[dict[str, Any]] = field(default_factory=list)
    """The runtime's trace entries in the order things happened (several can share a time)."""
    command_topic: str | None = None
    """The base's velocity command topic."""

    def at_end_of(self, state: str) -> _InForce | None:
        """The skill's velocity command and the world's running goals when ``state`` ended,
        in the order of events (a command published by the next state at the same virtual
        time does not count); ``None`` when the trace does not show the state's end."""
        end = None
        for index, event in enumerate(self.events):
            if (
                event.get("kind") == "state"
                and event.get("name") == state
                and event.get("phase") in ("end", "absent")
            ):
                end = index
        if end is None:
            return None
        found = _InForce()
        for event in self.events[: end + 1]:
            kind = event.get("kind")
            if kind == "publish" and event.get("topic") == self.command_topic:
                message = event.get("message") or {}
                twist = message.get("twist", message)
                linear, angular = twist.get("linear") or {}, twist.get("angular") or {}
                found.command = (
                    float(linear.get("x", 0.0) or 0.0),
                    float(linear.get("y", 0.0) or 0.0),
                    float(angular.get("z", 0.0) or 0.0),
                )
                found.published = (float(event.get("t", 0.0)), event.get("state"))
            elif kind == "world.goal":
                key = f"{event.get('action')}@{event.get('accepted')}"
                if event.get("outcome") == "executing":
                    found.goals[key] = str(event.get("action"))
                elif key in found.goals:
                    del found.goals[key]
                    # The world's controller stopped the base when its goal ended.
                    found.command = (0.0, 0.0, 0.0)
        return found

    def state_at(self, t: float) -> str | None:
        """The state running at ``t``."""
        for span in self.states:
            if span.start - 1e-9 <= t <= span.end + 1e-9:
                return span.name
        return None

    def span(self, name: str) -> StateSpan | None:
        """The last run of the state ``name``."""
        found = None
        for span in self.states:
            if span.name == name:
                found = span
        return found


@dataclass
class _InForce:
    """What kept the base moving at a moment of a run."""

    command: tuple[float, float, float] = (0.0, 0.0, 0.0)
    published: tuple[float, str | None] | None = None
    """Time and state of the skill's last velocity command."""
    goals: dict[str, str] = field(default_factory=dict)
    """Running goals of the world's action servers (key -> action)."""


@dataclass
class _Context:
    capability: Capability
    scenario: Scenario
    run: RunView
    truth: GroundTruth
    units: dict[str, str | None]
    tolerances: dict[str, float]
    exec_start: float
    exec_end: float
    settle_time: float = 0.0
    """When the base came to rest after execute returned (see :func:`_settling`); the end
    state is measured then."""
    settled: bool = True
    """False when the base had not come to rest within the scenario's time."""
    brake_start: float = 0.0
    """When the skill commanded the stop that ended its motion (its last zero velocity
    command up to execute's return), else when execute returned: from then on until
    :attr:`settle_time` the base brakes at its driver's deceleration limit."""

    @property
    def odometry_frame(self) -> bool:
        """Whether poses are judged in the odometry frame (the robot has no localisation)."""
        return not self.truth.localised

    def end_of(self, quantity: str) -> float:
        """The moment ``quantity`` is measured at: once the base settled for a quantity of
        the end state, else when execute returned."""
        return self.settle_time if quantity in END_STATE else self.exec_end

    def measure(self, quantity: str, unit: str | None) -> Value | None:
        """The simulator's value of ``quantity`` for this run's execute (end state settled,
        poses in the frame the robot can know)."""
        return measure(
            quantity,
            self.truth,
            self.exec_start,
            self.end_of(quantity),
            unit,
            odometry_frame=self.odometry_frame,
        )


def _elements(capability: Capability, direction: str) -> list[tuple[DataElement, Any]]:
    parameters = capability.inputs if direction == "input" else capability.outputs
    return [(e, p) for p in parameters for e in p.components]


_DEGREES = ("deg", "°", "degree")
_ANGLES = ("heading", "nearest_obstacle_bearing", "angular_velocity", "turned")


END_STATE = frozenset(
    {
        "position_x",
        "position_y",
        "heading",
        "travelled_distance",
        "displacement",
        "path_length",
        "turned",
        "tcp_position_x",
        "tcp_position_y",
        "tcp_position_z",
        "map_length",
        "map_width",
    }
)
"""Quantities that describe where a motion ended (a pose, a distance travelled, a heading
reached, the area mapped), not how the robot is moving at an instant. A base brakes for a
while after its last command (a velocity controller ramps down at its deceleration limit),
so they are measured once it has come to rest, not the moment execute returns."""

_POSE = ("position_x", "position_y", "heading")


def measure(
    quantity: str,
    truth: GroundTruth,
    start: float,
    end: float,
    unit: str | None = None,
    *,
    odometry_frame: bool = False,
) -> Value | None:
    """The simulator's value of a quantity (see :data:`~skillwright.sim.scenario.QUANTITIES`)
    for an execute state that ran from ``start`` to ``end``, in ``unit`` where that is
    degrees (the simulator measures in radians).

    With ``odometry_frame`` a pose (``position_x``, ``position_y``, ``heading``) is the true
    pose in the odometry frame, which starts where the robot started: a robot without
    localisation (nothing publishes ``map -> odom``) can know its pose only there."""
    if odometry_frame and quantity in _POSE:
        x, y, yaw = truth.in_odometry_frame(truth.at(end))
        value: Value | None = {"position_x": x, "position_y": y, "heading": wrap_two_pi(yaw)}[
            quantity
        ]
    else:
        value = _measure(quantity, truth, start, end)
    base = (unit or "").split("/")[0]
    if quantity in _ANGLES and base in _DEGREES and isinstance(value, float):
        value = math.degrees(value)
    return value


def _measure(quantity: str, truth: GroundTruth, start: float, end: float) -> Value | None:
    sample = truth.at(end)
    if quantity.startswith("tcp_position_"):
        return sample.tcp["xyz".index(quantity[-1])]
    simple: dict[str, float] = {
        "position_x": sample.x,
        "position_y": sample.y,
        "heading": wrap_two_pi(sample.yaw),
        "linear_velocity_x": sample.vx,
        "linear_velocity_y": sample.vy,
        "angular_velocity": sample.wz,
    }
    if quantity in simple:
        return simple[quantity]
    if quantity == "travelled_distance":
        return truth.travelled(start, end)
    if quantity == "displacement":
        return truth.displacement(start, end)
    if quantity == "path_length":
        return truth.path_length(start, end)
    if quantity == "turned":
        return truth.turned(start, end)
    if quantity == "command_duration":
        return truth.command_duration(start, end)
    if quantity in ("nearest_obstacle_distance", "nearest_obstacle_bearing"):
        nearest = truth.nearest_at(end)
        if nearest is None:
            return None
        return nearest[0] if quantity.endswith("distance") else wrap_pi(nearest[1])
    if quantity in ("map_length", "map_width"):
        extent = truth.extent_at(end)
        if extent is None:
            return None
        return extent[0] if quantity == "map_length" else extent[1]
    if quantity == "map_file":
        saved = [m for m in truth.saved_maps if m["t"] <= end + 1e-9]
        return saved[-1]["name"] if saved else None
    return None


def _values(context: _Context, outputs: Mapping[str, Value | None]) -> dict[str, Value]:
    """Variables of the constraints by IRI: inputs, outputs, resource properties."""
    capability = context.capability
    values: dict[str, Value] = {}
    for element, _p in _elements(capability, "input"):
        value = as_value(context.scenario.inputs.get(element.name))
        if value is not None and element.iri:
            values[element.iri] = value
    for element, _p in _elements(capability, "output"):
        value = outputs.get(element.name)
        if value is not None and element.iri:
            values[element.iri] = value
    if capability.resource is not None:
        for prop in capability.resource.properties:
            for instance in prop.instances:
                if instance.iri is None:
                    continue
                if instance.value is not None:
                    values[instance.iri] = instance.value
                    continue
                quantity = infer_quantity(instance)
                if quantity is None:
                    continue
                measured = measure(
                    quantity,
                    context.truth,
                    context.exec_start,
                    context.exec_start,
                    instance.unit,
                    odometry_frame=context.odometry_frame,
                )
                if measured is not None:
                    values[instance.iri] = measured
    return values


def _units(capability: Capability) -> dict[str, str | None]:
    units: dict[str, str | None] = {}
    elements = [e for e, _ in _elements(capability, "input") + _elements(capability, "output")]
    if capability.resource is not None:
        elements += [i for p in capability.resource.properties for i in p.instances]
    for element in elements:
        if element.iri:
            units[element.iri] = (element.unit or "").strip() or None
        units.setdefault(element.name, (element.unit or "").strip() or None)
    return units


NOISE_SIGMAS = 3.0
"""How many standard deviations of a sensor's noise a measured value may be off: a correct
skill's reading lies within three of them 99.7 % of the time."""


def noise_floor(context: _Context, quantity: str | None, unit: str | None) -> float:
    """The least tolerance a value of ``quantity`` can be judged to, given the noise of the
    sensor a skill has to read it from in this scenario (:class:`NoiseSpec`):
    :data:`NOISE_SIGMAS` standard deviations of the lidar's range noise for a range; of the
    odometry's drift over the run (its wheel-speed noise integrated once per driver period,
    a random walk) for a distance, a turn or, on a robot without localisation, a pose; of
    the localisation's pose noise for a pose in the map frame. 0 for anything else."""
    noise = context.truth.noise
    elapsed = max(context.settle_time - context.exec_start, 0.0)
    walk = math.sqrt(elapsed * context.truth.odometry_period)
    base = (unit or "").strip().split("/")[0]
    sigma = 0.0
    if quantity == "nearest_obstacle_distance":
        sigma = noise.get("scan", 0.0)
    elif quantity in ("travelled_distance", "displacement", "path_length") or (
        quantity in ("position_x", "position_y") and context.odometry_frame
    ):
        sigma = noise.get("odometry_linear", 0.0) * walk
    elif quantity in ("position_x", "position_y"):
        sigma = noise.get("localisation", 0.0)
    elif quantity in ("heading", "turned"):
        sigma = (
            noise.get("odometry_angular", 0.0) * walk
            if context.odometry_frame or quantity == "turned"
            else noise.get("localisation", 0.0) / 10.0
        )
        if base in _DEGREES:
            sigma = math.degrees(sigma)
    if base in ("mm", "cm") and quantity not in ("heading", "turned"):
        sigma *= 1000.0 if base == "mm" else 100.0
    return NOISE_SIGMAS * sigma


def _tolerance_for(
    context: _Context, name: str, unit: str | None, quantity: str | None = None
) -> float:
    """The scenario's tolerance for ``name``, else its unit's, and never less than the noise
    of the sensor ``quantity`` is read from (:func:`noise_floor`)."""
    scenario_tolerances = context.scenario.tolerances
    if name in scenario_tolerances:
        return scenario_tolerances[name]
    return max(context.tolerances.get(unit or "", 0.0), noise_floor(context, quantity, unit))


def _constraint_verdicts(context: _Context) -> list[Verdict]:
    capability = context.capability
    output_iris = {e.iri for e, _ in _elements(capability, "output") if e.iri}
    reported = {name: as_value(value) for name, value in context.run.outputs.items()}
    quantities = context.scenario.ground_truth
    units = {e.name: e.unit for e, _ in _elements(capability, "output")}
    measured: dict[str, Value | None] = {
        name: context.measure(q, units.get(name)) for name, q in quantities.items()
    }
    verdicts: list[Verdict] = []
    # Preconditions (on inputs alone) first: they say whether the rest can hold at all.
    ordered = sorted(
        capability.constraints, key=lambda c: is_output_variable(c.expression, output_iris)
    )
    floors: dict[str, float] = {}
    for name, quantity in quantities.items():
        unit = (units.get(name) or "").strip()
        floors[unit] = max(floors.get(unit, 0.0), noise_floor(context, quantity, unit))
    for constraint in ordered:
        tolerances = dict(context.tolerances)
        for unit, floor in floors.items():
            tolerances[unit] = max(tolerances.get(unit, 0.0), floor)
        if constraint.name in context.scenario.tolerances:
            for unit in UNIT_TOLERANCES:
                tolerances[unit] = context.scenario.tolerances[constraint.name]
        if not is_output_variable(constraint.expression, output_iris):
            verdicts.append(_judge(constraint, "precondition", context, reported, tolerances))
            continue
        verdicts.append(_judge(constraint, "constraint", context, reported, tolerances))
        names = {
            e.name
            for e, _ in _elements(capability, "output")
            if e.iri and _mentions(constraint, e.iri)
        }
        if names and all(measured.get(n) is not None for n in names):
            verdicts.append(_truth_verdict(constraint, context, names, units, tolerances))
        else:
            missing = sorted(n for n in names if measured.get(n) is None)
            verdicts.append(
                Verdict(
                    oracle=f"truth:{constraint.name}",
                    kind="truth",
                    check=constraint.text,
                    passed=None,
                    message="not checked on ground truth: nothing measured for "
                    + ", ".join(missing),
                )
            )
    return verdicts


def _truth_verdict(
    constraint: Constraint,
    context: _Context,
    names: set[str],
    units: Mapping[str, str | None],
    tolerances: Mapping[str, float],
) -> Verdict:
    """``constraint`` on the outputs as measured once the base settled; when that fails and
    an output is of the end state, it also holds if it held at a moment the base braked
    after the skill's stop (:func:`_window`): the driver's braking is not the skill's."""
    quantities = context.scenario.ground_truth
    measured = {n: context.measure(quantities[n], units.get(n)) for n in names}
    verdict = _judge(constraint, "truth", context, measured, tolerances)
    if verdict.passed is not False or not any(quantities[n] in END_STATE for n in names):
        return verdict
    for t in _braking(context, points=30):
        at = {
            n: measure(
                quantities[n],
                context.truth,
                context.exec_start,
                t if quantities[n] in END_STATE else context.exec_end,
                units.get(n),
                odometry_frame=context.odometry_frame,
            )
            for n in names
        }
        if any(v is None for v in at.values()):
            continue
        braking = _judge(constraint, "truth", context, at, tolerances)
        if braking.passed:
            return braking.model_copy(
                update={
                    "message": f"{braking.message} at t={t:.2f} s, while the base braked "
                    f"after the skill's stop; at rest (t={context.settle_time:.2f} s): "
                    + verdict.message,
                    "measured": {**braking.measured, "at": t, "settled": verdict.measured},
                    "time": t,
                }
            )
    return verdict


def _mentions(constraint: Constraint, iri: str) -> bool:
    from skillwright.sim.openmath import variables

    return any(v.refers_to == iri for v in variables(constraint.expression))


def _judge(
    constraint: Constraint,
    kind: Literal["precondition", "constraint", "truth"],
    context: _Context,
    outputs: Mapping[str, Value | None],
    tolerances: Mapping[str, float],
) -> Verdict:
    oracle = f"{kind}:{constraint.name}"
    values = _values(context, outputs)
    shown = {}
    from skillwright.sim.openmath import variables

    for variable in variables(constraint.expression):
        key = variable.refers_to or variable.text
        if key in values:
            shown[variable.text] = values[key]
    try:
        result = evaluate(constraint.expression, values, context.units, tolerances)
    except EvaluationError as error:
        missing = str(error)
        passed = False if kind == "constraint" else None
        return Verdict(
            oracle=oracle,
            kind=kind,
            check=constraint.text,
            passed=passed,
            message=f"cannot be evaluated: {missing}"
            + (" (an output the skill never set?)" if kind == "constraint" else ""),
            measured=shown,
        )
    holds = result.value is True
    source = {"constraint": "as reported", "truth": "as measured", "precondition": "inputs"}[kind]
    detail = "; ".join(result.checks)
    if kind == "precondition" and not holds:
        message = (
            f"the scenario's inputs violate it ({detail}); a correct skill refuses them, so "
            "the scenario should expect: aborted"
        )
    else:
        message = f"{'holds' if holds else 'violated'} {source}: {detail}"
    return Verdict(
        oracle=oracle,
        kind=kind,
        check=constraint.text,
        passed=holds,
        message=message,
        measured=shown,
        time=context.exec_end,
        state="execute",
    )


def _asked_verdicts(context: _Context) -> list[Verdict]:
    """Inputs the scenario binds to a motion (``inAngle: turned``): the simulator's measure of
    it over execute equals what the input asked for. A constraint over headings modulo 2 pi
    (``outDegree = (inDegree + degree) mod 360``) holds for a turn either way round, so it
    cannot tell a turn of -4.0 rad from one of +2.28 rad; the measured turn can."""
    verdicts = []
    for element, _parameter in _elements(context.capability, "input"):
        quantity = context.scenario.ground_truth.get(element.name)
        asked = as_value(context.scenario.inputs.get(element.name))
        if quantity is None or not isinstance(asked, float):
            continue
        unit = element.unit
        seen = context.measure(quantity, unit)
        if not isinstance(seen, float):
            continue
        tolerance = _tolerance_for(context, element.name, unit, quantity)
        passed = abs(seen - asked) <= tolerance
        at_rest = seen
        if not passed and quantity in END_STATE:
            window = _window(context, quantity, unit)
            best = min(window, key=lambda tv: abs(tv[1] - asked), default=None)
            if best is not None and abs(best[1] - asked) <= tolerance:
                passed, seen = True, best[1]
        how = "" if passed or seen * asked > 0 else ", the other way round"
        verdicts.append(
            Verdict(
                oracle=f"asked:{element.name}",
                kind="requirement",
                check=f"{quantity} = {element.name}",
                passed=passed,
                message=f"{quantity} {seen:.4g} {unit or ''} during execute for {element.name} "
                f"{asked:g}{how} (within {tolerance:g})"
                + (
                    f"; {at_rest:.4g} once at rest (t={context.settle_time:.2f} s), the rest "
                    "the base's braking after the skill's stop"
                    if at_rest != seen
                    else ""
                ),
                measured={
                    "measured": seen,
                    "asked": asked,
                    "settled": at_rest,
                    "settled_at": context.settle_time if context.settled else None,
                },
                tolerance=tolerance,
                time=context.exec_end,
                state="execute",
            )
        )
    return verdicts


def _braking(context: _Context, points: int = 60) -> list[float]:
    """Moments from the skill's stop command (or execute's return) until the base settled,
    at most about ``points`` of them, both ends included."""
    samples = context.truth.between(context.brake_start, context.settle_time)
    stride = max(1, len(samples) // points)
    return sorted({s.t for s in samples[::stride]} | {context.brake_start, context.settle_time})


def _window(context: _Context, quantity: str, unit: str | None) -> list[tuple[float, float]]:
    """``quantity``'s value at the moments of :func:`_braking`: what a reading of it could
    have shown while the base braked after the skill told it to stop. Through a velocity
    command a skill cannot brake harder than the base's driver does, so any of them is where
    the skill's motion ended."""
    times = _braking(context)
    found = []
    for t in times:
        value = measure(
            quantity,
            context.truth,
            context.exec_start,
            t,
            unit,
            odometry_frame=context.odometry_frame,
        )
        if isinstance(value, float):
            found.append((t, value))
    return found


def _assured_verdicts(context: _Context) -> list[Verdict]:
    """Outputs whose value the model asserts (``outLinearVelocity`` Assurance ``= 0.0``).

    An asserted velocity is a promise about how the motion ends (the base stops), and a base
    brakes at its deceleration limit after its last command: a skill that reads its odometry
    as execute returns reports the velocity of the braking, which is true of that moment. So
    a measured velocity (the scenario binds the output to one) that is not the asserted one
    passes when the base did settle to the asserted value within the scenario's time and the
    reported value is the base's velocity at some moment between execute's return and then.
    A skill without an output for it (the annotation checks report that) is judged by the
    promise itself: the measured velocity settled to the asserted value."""
    verdicts = []
    for element, _parameter in _elements(context.capability, "output"):
        if element.value is None or element.expression_goal != "Assurance":
            continue
        name = element.name
        unit = (element.unit or "").strip() or None
        quantity = context.scenario.ground_truth.get(name)
        tolerance = _tolerance_for(context, name, unit, quantity)
        reported = as_value(context.run.outputs.get(name))
        expected = as_value(element.value)
        measured: dict[str, Any] = {"reported": reported, "asserted": element.value}
        message = f"reported {reported!r}, the model asserts {element.value!r}"
        if reported is None and quantity in _VELOCITY_QUANTITIES and isinstance(expected, float):
            final = measure(quantity, context.truth, context.exec_start, context.settle_time, unit)
            passed = (
                context.settled
                and isinstance(final, float)
                and abs(final - expected) <= tolerance + 1e-9
            )
            measured.update(settled_at=context.settle_time, settled=final)
            message = (
                f"the skill reports no {name} (the annotation checks say so); the model asserts "
                f"{element.value!r} and the base's {quantity} "
                + (
                    f"settled to {final:.3g} at t={context.settle_time:.2f} s"
                    if context.settled and isinstance(final, float)
                    else f"had not settled by t={context.settle_time:.2f} s"
                )
                + f" (tolerance {tolerance:g})"
            )
        elif isinstance(reported, float) and isinstance(expected, float):
            passed = abs(reported - expected) <= tolerance + 1e-9
            if not passed and quantity in _VELOCITY_QUANTITIES and context.settled:
                final = measure(
                    quantity, context.truth, context.exec_start, context.settle_time, unit
                )
                # After the stop command: the velocity the base had before it is not braking.
                window = [
                    tv
                    for tv in _window(context, quantity, unit)
                    if tv[0] > context.brake_start + 1e-9 or tv[0] >= context.settle_time
                ]
                nearest = min(window, key=lambda tv: abs(tv[1] - reported), default=None)
                measured.update(settled_at=context.settle_time, settled=final)
                if (
                    isinstance(final, float)
                    and abs(final - expected) <= tolerance + 1e-9
                    and nearest is not None
                    and abs(nearest[1] - reported) <= tolerance + 1e-9
                ):
                    passed = True
                    measured["read_at"] = nearest[0]
                    message += (
                        f": the base's velocity was {nearest[1]:.3g} at t={nearest[0]:.2f} s "
                        f"while it braked, and it settled to {final:.3g} at "
                        f"t={context.settle_time:.2f} s"
                    )
            message += f" (tolerance {tolerance:g})"
        else:
            passed = reported == expected
        verdicts.append(
            Verdict(
                oracle=f"assured:{name}",
                kind="output",
                check=f"{name} {element.logic_interpretation or '='} {element.value} (Assurance)",
                passed=passed,
                message=message,
                measured=measured,
                tolerance=tolerance,
                time=context.exec_end,
                state="execute",
            )
        )
    return verdicts


_VELOCITY_QUANTITIES = ("linear_velocity_x", "linear_velocity_y", "angular_velocity")


def _map_file_verdict(context: _Context, name: str, reported: Any) -> Verdict:
    """A map output: it names the map saved through the robot's map saver; on a robot with
    no map-saving service in its inventory (neither Nav2's nor the SLAM Toolbox's
    ``SaveMap``) a skill cannot save one, so the map it reports (e.g. the occupancy grid it
    asked for) must only be there."""
    check = f"{name} = map_file"
    saved = context.measure("map_file", None)
    value = as_value(reported)
    values = {"reported": reported, "measured": saved, "map_savers": context.truth.map_savers}
    if not context.truth.map_savers:
        passed = value is not None and value != ""
        message = (
            "the robot has no map-saving service, so no saved file is asked for; "
            + (f"the skill reported a map ({len(str(value))} characters)" if passed else "")
            + ("" if passed else f"but the skill reported no map (got {reported!r})")
        )
    elif saved is None:
        passed = False
        message = "no map was saved through the map-saver service " + ", ".join(
            context.truth.map_savers
        )
    elif value is None:
        passed = False
        message = f"the skill did not report {name} (got {reported!r})"
    else:
        from skillwright.sim.mapfiles import safe_map_name

        passed = isinstance(value, str) and safe_map_name(value) == saved
        message = (
            f"reported {value!r} names the saved map {saved!r}"
            if passed
            else f"reported {value!r}, but the map saved was {saved!r}"
        )
    return Verdict(
        oracle=f"output:{name}",
        kind="output",
        check=check,
        passed=passed,
        message=message,
        measured=values,
        time=context.exec_end,
        state="execute",
    )


def _output_verdicts(context: _Context) -> list[Verdict]:
    verdicts = _assured_verdicts(context)
    for element, _parameter in _elements(context.capability, "output"):
        name = element.name
        quantity = context.scenario.ground_truth.get(name)
        oracle = f"output:{name}"
        reported = context.run.outputs.get(name)
        if element.value is not None and element.expression_goal == "Assurance":
            # "The base has stopped" (0.0) is a promise about the end of the skill: the
            # base may still be braking when execute returns. assured: checks the value
            # reported, rest: that nothing keeps the base moving.
            verdicts.append(
                Verdict(
                    oracle=oracle,
                    kind="output",
                    check=f"{name} equals what the simulator measures",
                    passed=None,
                    message=f"the model asserts {element.value!r}: checked by assured:{name} "
                    "and the rest oracles",
                )
            )
            continue
        if quantity is None:
            verdicts.append(
                Verdict(
                    oracle=oracle,
                    kind="output",
                    check=f"{name} equals what the simulator measures",
                    passed=None,
                    message="not checked: the scenario binds no measured quantity to it",
                )
            )
            continue
        if quantity == "map_file":
            verdicts.append(_map_file_verdict(context, name, reported))
            continue
        unit = (element.unit or "").strip() or None
        measured = context.measure(quantity, unit)
        tolerance = _tolerance_for(context, name, unit, quantity)
        check = f"{name} = {quantity}"
        values: dict[str, Any] = {"reported": reported, "measured": measured}
        if quantity in END_STATE:
            values["at_return"] = measure(
                quantity,
                context.truth,
                context.exec_start,
                context.exec_end,
                unit,
                odometry_frame=context.odometry_frame,
            )
            values["settled_at"] = context.settle_time if context.settled else None
            values["frame"] = "odom" if context.odometry_frame and quantity in _POSE else "map"
        if measured is None:
            verdicts.append(
                Verdict(
                    oracle=oracle,
                    kind="output",
                    check=check,
                    passed=None,
                    message=f"nothing measured for {quantity} (the world has no such sensor)",
                    measured=values,
                    state="execute",
                )
            )
            continue
        value = as_value(reported)
        if value is None:
            verdicts.append(
                Verdict(
                    oracle=oracle,
                    kind="output",
                    check=check,
                    passed=False,
                    message=f"the skill did not report {name} (got {reported!r})",
                    measured=values,
                    time=context.exec_end,
                    state="execute",
                )
            )
            continue
        passed, message = _compare_output(
            context, quantity, unit, value, measured, values, tolerance
        )
        verdicts.append(
            Verdict(
                oracle=oracle,
                kind="output",
                check=check,
                passed=passed,
                message=message,
                measured=values,
                tolerance=tolerance,
                time=context.exec_end,
                state="execute",
            )
        )
    return verdicts


def _compare_output(
    context: _Context,
    quantity: str,
    unit: str | None,
    value: Value,
    measured: Value,
    values: dict[str, Any],
    tolerance: float,
) -> tuple[bool, str]:
    """Whether a reported output equals its measured value, and the verdict in words: within
    the tolerance of the settled end state, or of a moment the base still braked; a bearing
    also when the range that way is as near (:func:`_as_near`)."""
    if isinstance(value, bool | str) or isinstance(measured, bool | str):
        passed = value == measured
        message = f"reported {value!r}, measured {measured!r}"
    else:
        gap = difference(value, float(measured), unit)
        passed = gap <= tolerance + 1e-9
        where = _where_measured(context, quantity)
        message = (
            f"reported {value:.4g}, measured {float(measured):.4g}{where}: "
            f"{'within' if passed else 'off by'} {gap:.3g}"
            f"{' ' + unit if unit else ''} (tolerance {tolerance:g})"
        )
        if not passed and quantity in END_STATE:
            # A reading taken while the base still braked is true of its moment.
            window = _window(context, quantity, unit)
            best = min(window, key=lambda tv: difference(value, tv[1], unit), default=None)
            if best is not None and difference(value, best[1], unit) <= tolerance + 1e-9:
                passed = True
                values["read_at"] = best[0]
                message += (
                    f"; but it was {best[1]:.4g} at t={best[0]:.2f} s while the base "
                    "braked after the skill told it to stop"
                )
        if not passed and quantity == "nearest_obstacle_bearing":
            as_near = _as_near(context, value, unit)
            if as_near is not None:
                passed = True
                message = (
                    f"reported {value:.4g}, measured {float(measured):.4g}: {gap:.3g}"
                    f"{' ' + unit if unit else ''} apart, but {as_near}"
                )
    return passed, message


def _where_measured(context: _Context, quantity: str) -> str:
    """When and in which frame ``quantity`` was measured, in words (empty for an instant
    value measured as execute returned)."""
    parts = []
    if quantity in END_STATE:
        parts.append(
            f"at rest from t={context.settle_time:.2f} s"
            if context.settled
            else f"at t={context.settle_time:.2f} s, still moving"
        )
    if quantity in _POSE:
        parts.append(
            "in the odometry frame (the robot has no localisation)"
            if context.odometry_frame
            else "in the map frame"
        )
    return f" ({', '.join(parts)})" if parts else ""


def _settling(
    capability: Capability, scenario: Scenario, truth: GroundTruth, exec_end: float
) -> tuple[float, bool]:
    """When the base came to rest after execute returned, and whether it did: the first
    moment it stays slower than :data:`REST_LINEAR` and :data:`REST_ANGULAR`, looked for
    until the scenario's time (or the record) ends; the last moment recorded when it did
    not. A capability that leaves the base moving (:func:`_promises_motion`) ends when
    execute returns."""
    if _promises_motion(capability) is not None or not truth.samples:
        return exec_end, True
    limit = max(exec_end, min(truth.end, scenario.duration))
    at = truth.settled(exec_end, limit, REST_LINEAR, REST_ANGULAR)
    if at is None:
        return limit, False
    return max(at, exec_end), True


def _as_near(context: _Context, bearing: float, unit: str | None) -> str | None:
    """Why ``bearing`` points at the nearest obstacle too, when the true range that way is
    within the distance tolerance of the nearest return (else ``None``).

    On a flat surface the ranges around the nearest point differ by less than the lidar's
    noise, so which beam reads least is the noise's choice: a skill that reports the bearing
    of its least reading is right, and one bearing is as near as another."""
    nearest = context.truth.nearest_at(context.exec_end)
    radians = math.radians(bearing) if (unit or "").split("/")[0] in _DEGREES else bearing
    toward = context.truth.range_toward(context.exec_end, radians)
    if nearest is None or toward is None or not math.isfinite(toward):
        return None
    allowance = next(
        (
            _tolerance_for(context, element.name, "m", "nearest_obstacle_distance")
            for element, _p in _elements(context.capability, "output")
            if context.scenario.ground_truth.get(element.name) == "nearest_obstacle_distance"
        ),
        max(
            context.tolerances.get("m", UNIT_TOLERANCES["m"]),
            noise_floor(context, "nearest_obstacle_distance", "m"),
        ),
    )
    farther = toward - nearest[0]
    if farther > allowance + 1e-9:
        return None
    return (
        f"the return that way is {farther:.3g} m farther than the nearest ({nearest[0]:.3g} m): "
        f"as near, within the {allowance:g} m a distance is judged to (on a flat surface the "
        "lidar's noise picks the beam that reads least)"
    )


def _requirement_verdicts(context: _Context) -> list[Verdict]:
    """Inputs that are requirements on the motion (``inMinObstacleDistance >=``): the
    clearance the lidar saw never fell below the requested one by more than the base
    needs to brake from the speed it had when something first came that close."""
    verdicts = []
    truth = context.truth
    for element, parameter in _elements(context.capability, "input"):
        if element.expression_goal != "Requirement" or element.logic_interpretation not in (
            ">=",
            ">",
        ):
            continue
        if (element.unit or "").strip() != "m" or infer_quantity(
            element, parameter, "obstacle"
        ) != "nearest_obstacle_distance":
            continue
        required = as_value(context.scenario.inputs.get(element.name))
        seen = truth.clearance(context.exec_start, context.exec_end)
        if not isinstance(required, float) or seen is None:
            continue
        closest, when = seen
        crossed = truth.first_closer(context.exec_start, context.exec_end, required)
        speed = truth.at(crossed).speed if crossed is not None else 0.0
        allowance = (
            speed * speed / (2.0 * truth.braking)
            + speed * truth.reaction
            + _tolerance_for(context, element.name, "m", "nearest_obstacle_distance")
        )
        passed = closest >= required - allowance
        verdicts.append(
            Verdict(
                oracle=f"requirement:{element.name}",
                kind="requirement",
                check=f"clearance {element.logic_interpretation} {element.name}",
                passed=passed,
                message=(
                    f"closest {closest:.3g} m at t={when:.2f} s for {required:g} m required "
                    f"(allowing {allowance:.3g} m to brake from {speed:.2g} m/s)"
                ),
                measured={"closest": closest, "required": required, "allowance": allowance},
                tolerance=allowance,
                time=when,
                state=context.run.state_at(when),
            )
        )
    return verdicts


def _limit_verdicts(context: _Context) -> list[Verdict]:
    capability = context.capability
    if capability.resource is None:
        return []
    verdicts = []
    truth = context.truth
    for prop in capability.resource.properties:
        for instance in prop.instances:
            unit = (instance.unit or "").strip()
            if (
                instance.expression_goal != "Requirement"
                or unit not in _VELOCITY_UNITS
                or not isinstance(instance.value, int | float)
                or instance.logic_interpretation not in ("<=", "<")
            ):
                continue
            limit = float(instance.value)
            angular = unit == "rad/s"
            oracle = f"limit:{prop.name}"
            check = f"{prop.name} <= {limit:g} {unit}"
            worst_command = 0.0
            first: tuple[float, str] | None = None
            for command in truth.commands:
                size = abs(command.wz) if angular else max(abs(command.vx), abs(command.vy))
                worst_command = max(worst_command, size)
                if size > limit + 1e-6 and first is None:
                    first = (command.t, f"the skill commanded {size:.3g} {unit}")
            slack = MEASURED_LIMIT_SLACK[unit]
            worst_measured = 0.0
            for sample in truth.samples:
                size = abs(sample.wz) if angular else max(abs(sample.vx), abs(sample.vy))
                worst_measured = max(worst_measured, size)
                if size > limit + slack and (first is None or sample.t < first[0]):
                    first = (sample.t, f"the base moved at {size:.3g} {unit}")
                    break
            measured = {
                "max_commanded": worst_command,
                "max_measured": worst_measured,
                "limit": limit,
            }
            if first is None:
                verdicts.append(
                    Verdict(
                        oracle=oracle,
                        kind="limit",
                        check=check,
                        passed=True,
                        message=f"kept: at most {worst_command:.3g} {unit} commanded, "
                        f"{worst_measured:.3g} {unit} measured",
                        measured=measured,
                        tolerance=slack,
                    )
                )
            else:
                t, what = first
                verdicts.append(
                    Verdict(
                        oracle=oracle,
                        kind="limit",
                        check=check,
                        passed=False,
                        message=f"exceeded at t={t:.2f} s: {what}, more than {limit:g} {unit}",
                        measured=measured,
                        tolerance=slack,
                        time=t,
                        state=context.run.state_at(t),
                    )
                )
    return verdicts


def _contact_verdict(context: _Context) -> Verdict:
    contacts = context.truth.contacts
    if not contacts:
        return Verdict(
            oracle="contact",
            kind="contact",
            check="the chassis touches nothing",
            passed=True,
            message="no contact with any obstacle",
        )
    first = contacts[0]
    return Verdict(
        oracle="contact",
        kind="contact",
        check="the chassis touches nothing",
        passed=False,
        message=f"the chassis hit {first.geom} at t={first.t:.2f} s at ({first.x:.2f}, "
        f"{first.y:.2f})" + (f", {len(contacts) - 1} more contact(s)" if len(contacts) > 1 else ""),
        measured={"contacts": len(contacts), "first_with": first.geom},
        time=first.t,
        state=context.run.state_at(first.t),
    )


def _promises_motion(capability: Capability) -> str | None:
    """An output velocity the capability does not assert to be zero (motion goes on)."""
    for element, _p in _elements(capability, "output"):
        unit = (element.unit or "").strip()
        if unit in _VELOCITY_UNITS and element.value in (None, ""):
            return element.name
    return None


def _rest_verdict(context: _Context, state: str) -> Verdict:
    oracle = f"rest:{state}"
    check = f"nothing keeps the base moving once {state} has ended"
    span = context.run.span(state)
    if span is None:
        # A skill without that state: its predecessor's end is the moment that counts.
        span = context.run.states[-1] if context.run.states else None
    if span is None:
        return Verdict(oracle=oracle, kind="rest", check=check, passed=None, message="no state ran")
    t = span.end
    truth = context.truth
    seen = context.run.at_end_of(span.name)
    if seen is None:
        # The trace lost the state's end (too long a run): judge by the virtual times.
        seen = _InForce()
        last = truth.command_in_force(t)
        if last is not None:
            seen.command = (last[1], last[2], last[3])
        skill = truth.skill_command_at(t)
        if skill is not None:
            seen.published = (skill.t, context.run.state_at(skill.t))
        seen.goals = {g: g for g in truth.goals_active_at(t)}
    vx, vy, wz = seen.command
    goals = sorted(set(seen.goals.values()))
    sample = truth.at(t)
    measured = {
        "time": t,
        "command": [vx, vy, wz],
        "speed": sample.speed,
        "yaw_rate": sample.wz,
        "goals": goals,
    }
    if goals:
        return Verdict(
            oracle=oracle,
            kind="rest",
            check=check,
            passed=False,
            message=f"when {span.name} ended at t={t:.2f} s the goal of {', '.join(goals)} was "
            "still running; cancel it",
            measured=measured,
            time=t,
            state=span.name,
        )
    if abs(vx) > REST_LINEAR or abs(vy) > REST_LINEAR or abs(wz) > REST_ANGULAR:
        origin = ""
        where = None
        if seen.published is not None:
            when, where = seen.published
            origin = (
                f"; the skill's last command (t={when:.2f} s, in {where or 'no state'}) "
                "was not zero"
            )
        return Verdict(
            oracle=oracle,
            kind="rest",
            check=check,
            passed=False,
            message=f"when {span.name} ended at t={t:.2f} s the base was still commanded to move "
            f"(vx {vx:.3g} m/s, vy {vy:.3g} m/s, wz {wz:.3g} rad/s){origin}",
            measured=measured,
            time=t,
            state=span.name if state != "completing" else (where or span.name),
        )
    settled = next(
        (
            s.t
            for s in context.truth.between(t, context.truth.end)
            if s.speed < REST_LINEAR and abs(s.wz) < REST_ANGULAR
        ),
        None,
    )
    message = f"zero command in force when {span.name} ended at t={t:.2f} s"
    if settled is not None:
        message += f"; at rest from t={settled:.2f} s"
    return Verdict(
        oracle=oracle,
        kind="rest",
        check=check,
        passed=True,
        message=message,
        measured=measured,
        time=t,
    )


def _refused_goals(truth: GroundTruth) -> list[str]:
    """Why the world's action servers aborted goals, as their servers said (an unknown
    planning group, a frame TF cannot transform, a target out of reach): a skill usually
    fails because of it, and the reason is otherwise only in the trace."""
    found = []
    for goal in truth.goals:
        if goal.get("outcome") == "aborted" and goal.get("reason"):
            found.append(
                f"{goal.get('action')} aborted the goal sent at t={float(goal['accepted']):.2f} s: "
                f"{goal['reason']}"
            )
    return list(dict.fromkeys(found))[:3]


def _outcome_verdict(context: _Context, expected: str) -> Verdict:
    run = context.run
    passed = run.ended == expected
    message = f"the run {run.ended}" + (f" ({run.message})" if run.message else "")
    if not passed:
        message += f"; the scenario expects it to have {expected}"
        refused = _refused_goals(context.truth)
        if refused:
            message += "; " + "; ".join(refused)
    failing = next((s for s in run.states if s.outcome != "returned"), None)
    return Verdict(
        oracle="outcome",
        kind="outcome",
        check=f"the run {expected}",
        passed=passed,
        message=message,
        measured={"ended": run.ended, "expected": expected},
        time=run.end_time,
        state=failing.name if failing is not None else None,
    )


Expected = Literal["completed", "stopped", "aborted"]


def judge(
    capability: Capability,
    scenario: Scenario,
    run: RunView,
    truth: GroundTruth,
    expected: Expected,
) -> list[Verdict]:
    """Every oracle's verdict on one run that should have ended ``expected`` (oracles the
    scenario skips are left out)."""
    execute = run.span("execute")
    exec_start = execute.start if execute is not None else 0.0
    exec_end = execute.end if execute is not None else run.end_time
    names = {e.name for e, _ in _elements(capability, "output")}
    names |= {c.name for c in capability.constraints}
    tolerances = dict(UNIT_TOLERANCES)
    tolerances.update({k: v for k, v in scenario.tolerances.items() if k not in names})
    settle_time, settled = _settling(capability, scenario, truth, exec_end)
    stopped = truth.stop_commanded(exec_start, exec_end)
    brake_start = stopped if stopped is not None else exec_end
    context = _Context(
        capability=capability,
        scenario=scenario,
        run=run,
        truth=truth,
        units=_units(capability),
        tolerances=tolerances,
        exec_start=exec_start,
        exec_end=exec_end,
        settle_time=settle_time,
        settled=settled,
        brake_start=min(brake_start, settle_time),
    )
    verdicts = [_outcome_verdict(context, expected)]
    if run.ended == expected == "completed":
        verdicts += _constraint_verdicts(context)
        verdicts += _asked_verdicts(context)
        verdicts += _output_verdicts(context)
        moving = _promises_motion(capability)
        if moving is None:
            last = "completing" if run.span("completing") else "execute"
            verdicts.append(_rest_verdict(context, last))
        else:
            verdicts.append(
                Verdict(
                    oracle="rest:completing",
                    kind="rest",
                    check="nothing keeps the base moving once completing has ended",
                    passed=None,
                    message=f"does not apply: the capability leaves the base moving ({moving})",
                )
            )
    elif run.ended == expected == "stopped":
        verdicts.append(_rest_verdict(context, "stopping"))
    elif run.ended == expected == "aborted":
        aborting = run.span("aborting")
        last = (
            aborting.name
            if aborting is not None
            else (run.states[-1].name if run.states else "execute")
        )
        verdicts.append(_rest_verdict(context, last))
    verdicts += _requirement_verdicts(context)
    verdicts += _limit_verdicts(context)
    verdicts.append(_contact_verdict(context))
    return [v for v in verdicts if v.oracle not in scenario.skip and v.kind not in scenario.skip]
