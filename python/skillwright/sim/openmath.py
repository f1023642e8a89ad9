"""Evaluating a capability's OpenMath constraints on numbers, with units and tolerances.

A constraint such as ``abs(outDistance - inDistance) <= 0.02`` or
``outHeading = (heading + inAngle) mod (2 * pi)`` is evaluated on values bound to its
variables (inputs from the scenario, outputs as the skill reported them or as the simulator
measured them, the resource's properties). Relations between measured quantities hold within
a tolerance that comes from their unit; angles (unit ``rad``) are compared on the circle, so
``6.28`` equals ``0.0``. A relation against a literal bound written in the model
(``... <= 0.02``) is already a tolerance and is checked as written.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from skillwright.capability.model import Expression

__all__ = [
    "PERIODS",
    "UNIT_TOLERANCES",
    "Evaluation",
    "EvaluationError",
    "Value",
    "as_value",
    "difference",
    "evaluate",
    "is_output_variable",
    "symbol",
    "unit_of",
    "variables",
]

Value = float | bool | str

UNIT_TOLERANCES: dict[str, float] = {
    "m": 0.03,
    "mm": 30.0,
    "cm": 3.0,
    "rad": 0.03,
    "deg": 2.0,
    "°": 2.0,
    "m/s": 0.05,
    "rad/s": 0.05,
    "deg/s": 3.0,
    "s": 0.1,
    "ms": 100.0,
}
"""How far apart two measured quantities of a unit may be and still count as equal: about
what the MR-1's odometry, localisation and 20 Hz control loops can tell apart."""

_CONSTANTS = {"nums1#pi": math.pi, "nums1#e": math.e}


class EvaluationError(ValueError):
    """A constraint cannot be evaluated: an unbound variable, an unknown operator, a type."""


def symbol(operator: str | None) -> str:
    """``http://www.openmath.org/cd/arith1#abs`` -> ``arith1#abs``."""
    if not operator:
        return ""
    return operator.rstrip("/").rsplit("/", 1)[-1]


def _number(value: Value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise EvaluationError(f"{where}: needs a number, got {value!r}")
    return float(value)


PERIODS = {"rad": 2 * math.pi, "deg": 360.0, "°": 360.0, "degree": 360.0}
"""Units of angles, and their full turn: such values are compared on the circle."""


def difference(a: float, b: float, unit: str | None) -> float:
    """``|a - b|``, the shorter way round the circle for an angle."""
    period = PERIODS.get(unit or "")
    return abs(math.remainder(a - b, period)) if period else abs(a - b)


@dataclass
class Evaluation:
    """The value of an expression and the relations checked on the way."""

    value: Value
    checks: list[str] = field(default_factory=list)
    """Each relation with the numbers it compared, e.g. ``0.004 <= 0.02``."""
    margin: float | None = None
    """For a single numeric relation: how far the two sides are apart (``|a - b|``)."""


def unit_of(expression: Expression, units: Mapping[str, str | None]) -> str | None:
    """The unit of a term: a variable's own, a sum's or difference's, an absolute value's..."""
    if expression.kind == "variable":
        return units.get(expression.refers_to or "") or units.get(expression.text)
    if expression.kind == "literal":
        return None
    name = symbol(expression.operator).split("#")[-1]
    if name in ("plus", "minus", "abs", "unary_minus", "mod", "remainder", "min", "max"):
        for argument in expression.arguments:
            unit = unit_of(argument, units)
            if unit:
                return unit
    return None


def _literal(text: str) -> Value:
    lowered = text.strip().lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        return float(text)
    except ValueError:
        return text


_ARITHMETIC: dict[str, Callable[[list[float]], float]] = {
    "plus": sum,
    "times": math.prod,
    "minus": lambda a: a[0] - sum(a[1:]) if len(a) > 1 else -a[0],
    "unary_minus": lambda a: -a[0],
    "divide": lambda a: a[0] / a[1],
    "power": lambda a: a[0] ** a[1],
    "abs": lambda a: abs(a[0]),
    "root": lambda a: a[0] ** (1.0 / a[1]) if len(a) > 1 else math.sqrt(a[0]),
    "mod": lambda a: a[0] % a[1],
    "remainder": lambda a: a[0] % a[1],
    "min": min,
    "max": max,
    "sin": lambda a: math.sin(a[0]),
    "cos": lambda a: math.cos(a[0]),
    "tan": lambda a: math.tan(a[0]),
    "arcsin": lambda a: math.asin(a[0]),
    "arccos": lambda a: math.acos(a[0]),
    "arctan": lambda a: math.atan(a[0]) if len(a) == 1 else math.atan2(a[0], a[1]),
    "exp": lambda a: math.exp(a[0]),
    "ln": lambda a: math.log(a[0]),
    "floor": lambda a: math.floor(a[0]),
    "ceiling": lambda a: math.ceil(a[0]),
}
_ARITY = {"divide": 2, "power": 2, "mod": 2, "remainder": 2, "unary_minus": 1, "abs": 1}


_RELATION_SIGNS = {
    "eq": "=",
    "approx": "~",
    "neq": "!=",
    "lt": "<",
    "gt": ">",
    "leq": "<=",
    "geq": ">=",
}


class _Evaluator:
    """One evaluation: the bindings, and the relations checked on the way."""

    def __init__(
        self,
        values: Mapping[str, Value],
        units: Mapping[str, str | None],
        tolerances: Mapping[str, float],
    ) -> None:
        self.values = values
        self.units = units
        self.tolerances = tolerances
        self.checks: list[str] = []
        self.margins: list[float] = []

    def term(self, node: Expression) -> Value:
        if node.kind == "literal":
            return _literal(node.text)
        if node.kind == "variable":
            return self.variable(node)
        name = symbol(node.operator)
        short = name.split("#")[-1]
        if name.startswith("relation1#"):
            return self.relation(node, short)
        if name.startswith("logic1#"):
            return self.logic(node, short)
        operation = _ARITHMETIC.get(short)
        if operation is None:
            raise EvaluationError(f"operator {name or '?'} is not supported")
        arguments = [_number(self.term(a), node.text) for a in node.arguments]
        expected = _ARITY.get(short)
        if not arguments or (expected is not None and len(arguments) < expected):
            raise EvaluationError(f"{node.text}: too few arguments")
        try:
            return operation(arguments)
        except (ZeroDivisionError, ValueError, OverflowError) as error:
            raise EvaluationError(f"{node.text}: {error}") from None

    def variable(self, node: Expression) -> Value:
        for key in (node.refers_to, node.text):
            if key and key in self.values:
                return self.values[key]
        # nums1#pi and nums1#e: the reader names them by their local name when the model
        # declares them as individuals rather than referring to them as inputs.
        constant = _CONSTANTS.get(symbol(node.refers_to)) or _CONSTANTS.get(f"nums1#{node.text}")
        own = f"http://www.openmath.org/cd/nums1#{node.text}"
        if constant is not None and node.refers_to in (None, own):
            return constant
        raise EvaluationError(f"no value for {node.text}")

    def logic(self, node: Expression, name: str) -> bool:
        results = [self.term(a) for a in node.arguments]
        if any(not isinstance(r, bool) for r in results):
            raise EvaluationError(f"{node.text}: logic on values that are not true or false")
        if name == "and":
            return all(results)
        if name == "or":
            return any(results)
        if name == "not" and len(results) == 1:
            return not results[0]
        if name == "implies" and len(results) == 2:
            return (not results[0]) or bool(results[1])
        if name == "equivalent" and len(results) == 2:
            return results[0] == results[1]
        raise EvaluationError(f"logic operator {name} is not supported")

    def relation(self, node: Expression, name: str) -> bool:
        if len(node.arguments) != 2:
            raise EvaluationError(f"{node.text}: a relation needs two sides")
        if name not in _RELATION_SIGNS:
            raise EvaluationError(f"relation {name} is not supported")
        left, right = node.arguments
        a, b = self.term(left), self.term(right)
        if isinstance(a, str | bool) or isinstance(b, str | bool):
            same = a == b
            self.checks.append(f"{a!r} {'=' if same else '!='} {b!r}")
            return same if name in ("eq", "approx") else (not same if name == "neq" else False)
        unit = unit_of(left, self.units) or unit_of(right, self.units)
        literal_bound = left.kind == "literal" or right.kind == "literal"
        tolerance = 0.0 if literal_bound else self.tolerances.get(unit or "", 0.0)
        tolerance += 1e-9 * max(1.0, abs(a), abs(b))
        circular = name in ("eq", "neq", "approx")
        gap = difference(a, b, unit if circular else None)
        self.margins.append(gap)
        outcome = {
            "eq": gap <= tolerance,
            "approx": gap <= tolerance,
            "neq": gap > tolerance,
            "lt": a < b + tolerance,
            "gt": a > b - tolerance,
            "leq": a <= b + tolerance,
            "geq": a >= b - tolerance,
        }[name]
        within = (
            f" (within {tolerance:.3g}{' ' + unit if unit else ''})" if tolerance > 1e-6 else ""
        )
        self.checks.append(f"{_show(a)} {_RELATION_SIGNS[name]} {_show(b)}{within}")
        return outcome


def evaluate(
    expression: Expression,
    values: Mapping[str, Value],
    units: Mapping[str, str | None],
    tolerances: Mapping[str, float],
) -> Evaluation:
    """The value of ``expression`` with its variables taken from ``values`` (by the IRI they
    refer to, else by name); relations use ``tolerances`` per unit (see :data:`UNIT_TOLERANCES`).
    """
    evaluator = _Evaluator(values, units, tolerances)
    value = evaluator.term(expression)
    margins = evaluator.margins
    return Evaluation(value, evaluator.checks, margins[0] if len(margins) == 1 else None)


def _show(value: float) -> str:
    return f"{value:.4g}" if math.isfinite(value) else str(value)


def is_output_variable(expression: Expression, output_iris: set[str]) -> bool:
    """Whether the term mentions any of the outputs."""
    if expression.kind == "variable":
        return (expression.refers_to or "") in output_iris
    return any(is_output_variable(a, output_iris) for a in expression.arguments)


def variables(expression: Expression) -> list[Expression]:
    """Every variable of the term, in order."""
    if expression.kind == "variable":
        return [expression]
    found: list[Expression] = []
    for argument in expression.arguments:
        found.extend(variables(argument))
    return found


def as_value(value: Any) -> Value | None:
    """A scenario or skill value as an evaluable value (``None`` if it is not one)."""
    if isinstance(value, bool | str):
        return value
    if isinstance(value, int | float):
        return float(value)
    return None
