"""A measured value tested for exact equality (check ``equality``).

Odometry, scans and transforms carry floating-point readings with noise: a velocity the
robot reaches is 0.2994 or 0.3008, never the 0.3 it was asked for. A loop that runs until
``velocity == self.in_velocity`` with the velocity read from odometry runs until the state's
deadline, and fails on a robot that did what it was told.

A comparison with ``==`` or ``!=`` is flagged when one side is a measured number: a
coordinate or component (``x``, ``y``, ``z``, ``w``) of a field of a latest message
(``self.X_msg``, which a callback keeps), a reading of ``ranges``, the skeleton's
``self._yaw(...)``, arithmetic on those, or a name or attribute the class assigns from one.
Tests against ``None``, strings, booleans and upper-case constants (``GoalStatus.
STATUS_SUCCEEDED``, a status code) are not measurements and are left alone. In a loop's
condition or in the ``if`` that leaves a loop it is an error (the loop most likely never
ends); elsewhere a warning. Where the other side has a unit the capability states (an input,
an output, or a local copied from one), the fix tests for closeness within a tolerance of
that unit instead.
"""

from __future__ import annotations

import ast
import copy
from collections.abc import Mapping

from skillwright.capability.model import Capability
from skillwright.generation.names import snake_case
from skillwright.rules.behaviour import EXACT_EQUALITY
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts

__all__ = ["check_equality"]

_TOLERANCES = {
    "m": 0.01,
    "m/s": 0.01,
    "rad": 0.01,
    "rad/s": 0.01,
    "°": 1.0,
    "deg": 1.0,
    "s": 0.1,
}
"""How close is close enough, by the unit the capability states."""


def check_equality(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``equality``) for measured numbers compared with ``==`` or ``!=``
    (what is measured: :attr:`~skillwright.validation.facts.SkillFacts.is_measured`)."""
    is_measured = facts.is_measured
    units = _units(facts.capability)
    findings = []
    for method in facts.functions:
        aliases = _aliases(method, units)
        exits = _loop_exits(method)
        for node in facts.walk(method):
            if not (
                isinstance(node, ast.Compare)
                and len(node.ops) == 1
                and isinstance(node.ops[0], ast.Eq | ast.NotEq)
            ):
                continue
            left, right = node.left, node.comparators[0]
            sides = [(left, right), (right, left)]
            found = next(
                (
                    (reading, other)
                    for reading, other in sides
                    if is_measured(reading) and _is_number_like(other)
                ),
                None,
            )
            statement = facts.statement_holding(node, method)
            if found is None or statement is None:
                continue
            reading, other = found
            unit = _unit_of(other, units, aliases)
            in_loop_exit = id(statement) in exits
            findings.append(_finding(statement, node, reading, other, unit, in_loop_exit))
    return findings


def _finding(
    statement: ast.stmt,
    compare: ast.Compare,
    reading: ast.expr,
    other: ast.expr,
    unit: str | None,
    in_loop_exit: bool,
) -> Finding:
    equal = isinstance(compare.ops[0], ast.Eq)
    message = (
        f"`{ast.unparse(compare)}` tests a measured value, `{ast.unparse(reading)}`, for exact "
        "equality: readings carry noise and are never exactly the number asked for"
        + (", so this loop most likely never ends" if in_loop_exit else "")
        + f"; test closeness instead: abs({ast.unparse(reading)} - {ast.unparse(other)}) "
        + ("<" if equal else ">=")
        + " tolerance"
    )
    replacement = None
    if unit is not None:
        tolerance = _TOLERANCES[unit]
        message += f" (the fix uses {tolerance} {unit})"
        close = ast.parse(
            f"abs({ast.unparse(reading)} - {ast.unparse(other)}) "
            f"{'<' if equal else '>='} {tolerance}",
            mode="eval",
        ).body
        replacement = ast.unparse(_replaced(statement, compare, close))
    return EXACT_EQUALITY.finding(
        severity="error" if in_loop_exit else "warning",
        data={"reading": ast.unparse(reading), "other": ast.unparse(other)},
        line=compare.lineno,
        column=compare.col_offset + 1,
        message=message,
        replacement=replacement if in_loop_exit or unit is not None else None,
    )


def _replaced(statement: ast.stmt, old: ast.expr, new: ast.expr) -> ast.stmt:
    memo: dict[int, object] = {}
    changed = copy.deepcopy(statement, memo)
    target = memo[id(old)]

    class _Swap(ast.NodeTransformer):
        def visit(self, node: ast.AST) -> ast.AST:
            return new if node is target else self.generic_visit(node)

    swapped = _Swap().visit(changed)
    assert isinstance(swapped, ast.stmt)
    return ast.fix_missing_locations(swapped)


def _is_number_like(node: ast.expr) -> bool:
    """Not ``None``, a string, a boolean or an upper-case constant (a status code)."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, int | float) and not isinstance(node.value, bool)
    if isinstance(node, ast.Attribute) and node.attr.isupper():
        return False
    return isinstance(node, ast.Name | ast.Attribute | ast.BinOp | ast.UnaryOp | ast.Call)


def _units(capability: Capability) -> dict[str, str]:
    """``self.<attribute>`` of each input and output with a unit that has a tolerance."""
    out = {}
    for parameter in (*capability.inputs, *capability.outputs):
        for component in parameter.components:
            unit = (component.unit or parameter.element.unit or "").strip()
            if unit in _TOLERANCES:
                out[f"self.{snake_case(component.name)}"] = unit
    return out


def _aliases(method: ast.FunctionDef, units: Mapping[str, str]) -> dict[str, str]:
    """Local names the method copies an input or output into (``velocity =
    self.in_velocity``), with its unit."""
    out = {}
    for node in ast.walk(method):
        if (
            isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
            and ast.unparse(node.value) in units
        ):
            out[node.targets[0].id] = units[ast.unparse(node.value)]
    return out


def _unit_of(node: ast.expr, units: Mapping[str, str], aliases: Mapping[str, str]) -> str | None:
    if isinstance(node, ast.Name):
        return aliases.get(node.id)
    return units.get(ast.unparse(node))


def _loop_exits(method: ast.FunctionDef) -> set[int]:
    """Ids of the ``while`` statements of ``method`` and of the ``if`` statements in a loop
    body whose body leaves the loop (``break`` or ``return``)."""
    out: set[int] = set()
    for loop in ast.walk(method):
        if not isinstance(loop, ast.While | ast.For):
            continue
        if isinstance(loop, ast.While):
            out.add(id(loop))
        for node in ast.walk(loop):
            if isinstance(node, ast.If) and any(
                isinstance(s, ast.Break | ast.Return) for s in node.body
            ):
                out.add(id(node))
    return out
