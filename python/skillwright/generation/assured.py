"""Outputs the capability asserts the base's rest for, which the skeleton sets itself.

A DIN EN 61360 instance description with the expression goal ``Assurance`` and a value is
a promise of the capability: whatever the inputs, that output has that value
(``outLinearVelocity = 0.0``: "the base has stopped"). A CSS constraint that equates an
output with a constant (``outVelocity = 0``) says the same. When the output is a velocity
of the base and the value is zero, keeping the promise is no behaviour of the skill's own:
the motion is over, the base is commanded to zero and, where odometry is read, waited for
until it stands still; then the output holds the asserted value. The skeleton writes that
where pySkillUp's life cycle puts it: at the start of ``completing``, which runs after
execute returned and before pySkillUp reads the outputs, or at the end of ``execute`` when
the specification has no completing state. A model left to do it has reported a range
where the capability asserts a speed.

Other asserted values (a speed that is not zero, a flag) are the behaviour's to bring
about, and are left to it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skillwright.capability.model import Capability, DataElement, Expression
from skillwright.generation.names import snake_case
from skillwright.interfaces.roles import normalised_words

__all__ = ["RestOutput", "rest_outputs"]

VELOCITY_UNITS = frozenset({"m/s", "rad/s", "deg/s", "°/s", "degree/s", "1/s"})
"""Units of a velocity (linear or angular) a DIN EN 61360 type description gives."""


@dataclass(frozen=True)
class RestOutput:
    """An output the capability asserts zero for, a velocity of the base at rest."""

    name: str
    """The capability's name for it, e.g. outLinearVelocity."""
    attribute: str
    """The skill's attribute holding it."""
    value: str
    """The asserted value as Python: ``0.0`` (or ``0`` for an Integer)."""
    source: str
    """Where the capability asserts it: ``Assurance`` or the constraint's name."""


def _is_velocity(element: DataElement) -> bool:
    unit = (element.unit or "").strip().lower()
    words = normalised_words(element.name)
    return unit in VELOCITY_UNITS or any(w in words for w in ("velocity", "speed", "yaw rate"))


def _zero(value: object) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, int | float):
        return math.isclose(float(value), 0.0, abs_tol=1e-12)
    try:
        return math.isclose(float(str(value)), 0.0, abs_tol=1e-12)
    except ValueError:
        return False


def _constant_zero(term: Expression) -> bool:
    return term.kind == "literal" and _zero(term.text)


def _asserted_by_constraint(capability: Capability, element: DataElement) -> str | None:
    """The name of a constraint ``element = 0`` (either side), if the capability has one."""
    for constraint in capability.constraints:
        expression = constraint.expression
        operator = (expression.operator or "").rsplit("/", 1)[-1]
        if operator != "relation1#eq" or len(expression.arguments) != 2:
            continue
        left, right = expression.arguments
        for variable, constant in ((left, right), (right, left)):
            if (
                variable.kind == "variable"
                and element.iri is not None
                and variable.refers_to == element.iri
                and _constant_zero(constant)
            ):
                return constraint.name
    return None


def rest_outputs(capability: Capability) -> list[RestOutput]:
    """The outputs of ``capability`` that are velocities it asserts to be zero at the end
    (see the module docstring), in the order the capability lists them."""
    out = []
    for parameter in capability.outputs:
        for element in parameter.components:
            if not _is_velocity(element):
                continue
            if element.expression_goal == "Assurance" and _zero(element.value):
                source = "Assurance"
            else:
                found = _asserted_by_constraint(capability, element)
                if found is None:
                    continue
                source = found
            value = "0" if element.data_type == "Integer" else "0.0"
            out.append(RestOutput(element.name, snake_case(element.name), value, source))
    return out
