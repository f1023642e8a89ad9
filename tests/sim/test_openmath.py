"""Evaluating the capabilities' OpenMath constraints with units and tolerances."""

from __future__ import annotations

import math

import pytest

from skillwright.capability.model import Capability, Constraint, Expression
from skillwright.sim.openmath import UNIT_TOLERANCES, EvaluationError, evaluate, symbol, unit_of


def _constraint(capability: Capability, name: str) -> Constraint:
    return next(c for c in capability.constraints if c.name == name)


def _values(
    capability: Capability, **named: object
) -> tuple[dict[str, object], dict[str, str | None]]:
    """Values by IRI for the named inputs, outputs and resource properties, and their units."""
    elements = [e for p in capability.inputs + capability.outputs for e in p.components]
    if capability.resource is not None:
        elements += [i for p in capability.resource.properties for i in p.instances]
    values: dict[str, object] = {}
    units: dict[str, str | None] = {}
    for element in elements:
        if element.iri:
            units[element.iri] = element.unit
            if element.name in named:
                values[element.iri] = named[element.name]
    return values, units


@pytest.mark.parametrize(
    ("capability", "constraint", "values", "holds"),
    [
        ("move-forward", "distanceCovered", {"inDistance": 1.5, "outDistance": 1.51}, True),
        ("move-forward", "distanceCovered", {"inDistance": 1.5, "outDistance": 1.53}, False),
        ("move-forward", "distanceForward", {"inDistance": -0.1}, False),
        (
            "rotate",
            "headingTarget",
            {"heading": 5.0, "inAngle": 2.0, "outHeading": 7.0 - 2 * math.pi},
            True,
        ),
        (
            "rotate",
            "headingTarget",
            {"heading": 0.1, "inAngle": -0.2, "outHeading": 2 * math.pi - 0.11},
            True,
        ),
        ("rotate", "headingTarget", {"heading": 0.1, "inAngle": -0.2, "outHeading": 0.1}, False),
        (
            "set-velocity",
            "linearVelocityClipped",
            {"inLinearVelocity": 1.5, "outLinearVelocity": 0.79},
            True,
        ),
        (
            "set-velocity",
            "linearVelocityClipped",
            {"inLinearVelocity": 1.5, "outLinearVelocity": 1.5},
            False,
        ),
        (
            "set-velocity",
            "angularVelocityClipped",
            {"inAngularVelocity": -0.5, "outAngularVelocity": -0.49},
            True,
        ),
        (
            "collision-avoidance",
            "endCondition",
            {
                "inDuration": 5.0,
                "outDuration": 2.0,
                "inMinObstacleDistance": 0.6,
                "outObstacleDistance": 0.55,
            },
            True,
        ),
        (
            "collision-avoidance",
            "endCondition",
            {
                "inDuration": 5.0,
                "outDuration": 2.0,
                "inMinObstacleDistance": 0.6,
                "outObstacleDistance": 1.2,
            },
            False,
        ),
        ("get-distance-to-nearest-object", "angleNormalised", {"outAngle": -3.0}, True),
        ("get-distance-to-nearest-object", "angleNormalised", {"outAngle": 4.0}, False),
        ("get-distance-to-nearest-object", "distanceWithinRange", {"outDistance": 11.0}, True),
        (
            "move-to-point",
            "targetInReach",
            {"inPositionX": 0.4, "inPositionY": 0.2, "inPositionZ": 0.3},
            True,
        ),
        (
            "move-to-point",
            "targetInReach",
            {"inPositionX": 0.8, "inPositionY": 0.5, "inPositionZ": 0.3},
            False,
        ),
        ("mapping", "lengthCovered", {"inAreaLength": 4.0, "outMapLength": 9.8}, True),
        (
            "get-position",
            "headingReported",
            {"heading": 0.01, "outHeading": 2 * math.pi - 0.01},
            True,
        ),
    ],
)
def test_the_shipped_constraints_hold_or_fail_as_the_numbers_say(
    mr1_capabilities: dict[str, Capability],
    capability: str,
    constraint: str,
    values: dict[str, float],
    holds: bool,
) -> None:
    model = mr1_capabilities[capability]
    bound, units = _values(model, **values)
    for prop in model.resource.properties if model.resource else []:
        for instance in prop.instances:
            if instance.iri and instance.value is not None and instance.iri not in bound:
                bound[instance.iri] = instance.value
    result = evaluate(_constraint(model, constraint).expression, bound, units, UNIT_TOLERANCES)
    assert result.value is holds
    assert result.checks


def test_angles_are_equal_across_the_wrap_but_lengths_are_not(
    mr1_capabilities: dict[str, Capability],
) -> None:
    expression = _constraint(mr1_capabilities["get-position"], "headingReported").expression
    assert (
        unit_of(expression.arguments[0], {expression.arguments[0].refers_to or "": "rad"}) == "rad"
    )
    left = Expression(kind="variable", text="a", refers_to="a")
    right = Expression(kind="variable", text="b", refers_to="b")
    equal = Expression(
        kind="application",
        text="a = b",
        operator="http://www.openmath.org/cd/relation1#eq",
        arguments=[left, right],
    )
    assert (
        evaluate(equal, {"a": 6.27, "b": 0.0}, {"a": "rad", "b": "rad"}, UNIT_TOLERANCES).value
        is True
    )
    assert (
        evaluate(equal, {"a": 6.27, "b": 0.0}, {"a": "m", "b": "m"}, UNIT_TOLERANCES).value is False
    )


def test_an_unbound_variable_or_an_unknown_operator_is_an_evaluation_error(
    mr1_capabilities: dict[str, Capability],
) -> None:
    model = mr1_capabilities["move-forward"]
    with pytest.raises(EvaluationError, match="no value for"):
        evaluate(_constraint(model, "distanceCovered").expression, {}, {}, UNIT_TOLERANCES)
    odd = Expression(
        kind="application",
        text="f(1)",
        operator="http://example.org/cd/odd#f",
        arguments=[Expression(kind="literal", text="1")],
    )
    with pytest.raises(EvaluationError, match="not supported"):
        evaluate(odd, {}, {}, UNIT_TOLERANCES)


def test_symbols_are_content_dictionary_and_name() -> None:
    assert symbol("http://www.openmath.org/cd/arith1#abs") == "arith1#abs"
    assert symbol(None) == ""


@pytest.mark.parametrize(
    ("a", "b", "unit", "gap"),
    [
        (359.0, 1.0, "°", 2.0),
        (6.2, 0.1, "rad", 2 * math.pi - 6.1),
        (359.0, 1.0, "m", 358.0),
        (1.0, 3.0, None, 2.0),
    ],
)
def test_angles_in_degrees_and_radians_are_compared_on_the_circle(
    a: float, b: float, unit: str | None, gap: float
) -> None:
    from skillwright.sim.openmath import difference

    assert difference(a, b, unit) == pytest.approx(gap)
