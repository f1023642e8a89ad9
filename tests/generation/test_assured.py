"""Which outputs the capability asserts the base's rest for (the skeleton sets them)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

from skillwright.capability.model import Capability, Constraint, DataElement, Expression, Parameter
from skillwright.capability.reader import load_capability
from skillwright.generation.assured import RestOutput, rest_outputs
from tests.conftest import SHIPPED_CAPABILITIES


@pytest.mark.parametrize(
    ("stem", "names"),
    [
        ("move-forward", ["outLinearVelocity"]),
        ("rotate", ["outAngularVelocity"]),
        ("collision-avoidance", ["outAngularVelocity", "outLinearVelocityX", "outLinearVelocityY"]),
        # Measured once the command is reached: no value asserted.
        ("set-velocity", []),
        ("navigate-to-point", []),
        ("get-position", []),
    ],
)
def test_the_shipped_capabilities_assert_rest_for_their_final_velocities(
    stem: str, names: list[str]
) -> None:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    assert [o.name for o in rest_outputs(capability)] == names


@pytest.mark.parametrize(
    ("stem", "names"),
    [
        ("move-forward", ["outVelocity"]),
        ("rotate", ["outVelocity"]),
        ("collision-avoidance", ["outVelocityAngular", "outVelocityX", "outVelocityY"]),
        ("set-velocity", []),
        ("get-distance-to-nearest-object", []),
    ],
)
def test_the_papers_capabilities_assert_rest_alike(
    shared_data: Path, stem: str, names: list[str]
) -> None:
    path = shared_data / "cap2skill" / "capability-models" / f"{stem}.ttl"
    outputs = rest_outputs(load_capability(path).capability)
    assert [o.name for o in outputs] == names
    assert all(o.value == "0.0" and o.source == "Assurance" for o in outputs)


def _capability(element: DataElement, constraints: Sequence[Constraint] = ()) -> Capability:
    output = Parameter(
        iri=f"urn:x:{element.name}",
        name=element.name,
        direction="output",
        kind="Information",
        components=[element],
    )
    return Capability(
        iri="urn:x:cap",
        name="cap",
        label="cap",
        kinds=[],
        outputs=[output],
        constraints=list(constraints),
    )


def test_an_output_a_constraint_equates_with_zero_is_asserted_too() -> None:
    element = DataElement(iri="urn:x:outSpeed_ID", name="outSpeed", unit="m/s", data_type="Real")
    zero = Constraint(
        iri="urn:x:stopped",
        name="stopped",
        relation="=",
        expression=Expression(
            kind="application",
            text="outSpeed = 0",
            operator="http://www.openmath.org/cd/relation1#eq",
            arguments=[
                Expression(kind="literal", text="0"),
                Expression(kind="variable", text="outSpeed", refers_to="urn:x:outSpeed_ID"),
            ],
        ),
    )
    assert rest_outputs(_capability(element, [zero])) == [
        RestOutput("outSpeed", "out_speed", "0.0", "stopped")
    ]
    assert rest_outputs(_capability(element)) == []


@pytest.mark.parametrize(
    "element",
    [
        # A speed the capability asserts that is not zero is the behaviour's to reach.
        DataElement(name="outSpeed", unit="m/s", expression_goal="Assurance", value=0.5),
        # Zero, but no velocity: a count, a distance.
        DataElement(name="outErrors", unit="-", expression_goal="Assurance", value=0),
        DataElement(name="outDistance", unit="m", expression_goal="Assurance", value=0.0),
        # A value that is a requirement, not a promise.
        DataElement(name="outSpeed", unit="m/s", expression_goal="Requirement", value=0.0),
        DataElement(name="outStopped", unit="m/s", expression_goal="Assurance", value=False),
    ],
)
def test_only_a_velocity_asserted_zero_is_a_rest_output(element: DataElement) -> None:
    assert rest_outputs(_capability(element)) == []


def test_an_integer_velocity_gets_an_integer_zero() -> None:
    element = DataElement(
        name="outTicksPerSecond",
        unit="1/s",
        data_type="Integer",
        expression_goal="Assurance",
        value=0,
    )
    assert rest_outputs(_capability(element))[0].value == "0"
