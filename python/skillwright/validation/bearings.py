"""A bearing of the skeleton's closest reading offset by a scan's ``angle_min`` again (check
``bearings``).

The skeleton's ``self._closest_reading(scan)`` returns ``(range, bearing)`` with the bearing
already counted from the scanner's x axis: ``scan.angle_min + index * scan.angle_increment``.
Subtracting ``angle_min`` from it again (``self.out_angle = scan[1] - self.scan_msg.angle_min``)
offsets every bearing by the scan's start angle: a LaserScan that starts at -pi, as a 360°
scanner's does, then reports an obstacle ahead as behind the robot.

An error stands at each ``+`` or ``-`` of such a bearing (``self._closest_reading(...)[1]``,
a local holding the call's result indexed ``[1]``, or the second name it was unpacked into)
with the ``angle_min`` of anything, when the class's ``_closest_reading`` itself counts from
``angle_min``. The fix is the statement with the bearing as it is.
"""

from __future__ import annotations

import ast
import copy

from skillwright.rules.behaviour import BEARING_OFFSET_TWICE
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_method, with_node_replaced

__all__ = ["check_bearings"]

_CLOSEST = "_closest_reading"


def check_bearings(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``bearings``) for a closest reading's bearing offset by ``angle_min``
    once more."""
    helper = next((n for n in facts.functions if n.name == _CLOSEST), None)
    if helper is None or not any(_is_angle_min(n) for n in facts.walk(helper)):
        return []
    statement_of = facts.statement_of
    findings = []
    for method in (n for n in facts.functions if n is not helper):
        results, bearings = _holders(method)
        for node in facts.walk(method):
            if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add | ast.Sub)):
                continue
            sides = (node.left, node.right)
            bearing = next((s for s in sides if _is_bearing(s, results, bearings)), None)
            other = node.right if bearing is node.left else node.left
            statement = statement_of.get(id(node))
            if bearing is None or not _is_angle_min(other) or statement is None:
                continue
            findings.append(
                error_at(
                    BEARING_OFFSET_TWICE,
                    statement,
                    f"`{ast.unparse(node)}` offsets the bearing of self.{_CLOSEST}"
                    f"(...) by {ast.unparse(other)} again, but the helper already counts it "
                    f"from angle_min (0 along the scanner's x axis, positive to the left): "
                    f"the result is off by angle_min (pi for a scan that starts at -pi). Use "
                    f"the bearing as it is, {ast.unparse(bearing)}",
                    _as_it_is(statement, node, bearing),
                )
            )
    return findings


def _holders(method: ast.FunctionDef) -> tuple[set[str], set[str]]:
    """Locals of ``method`` given the helper's whole result, and those given its bearing
    (the second of two names it is unpacked into)."""
    results: set[str] = set()
    bearings: set[str] = set()
    for node in ast.walk(method):
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1):
            continue
        if not (isinstance(node.value, ast.Call) and self_method(node.value) == _CLOSEST):
            continue
        target = node.targets[0]
        if isinstance(target, ast.Name):
            results.add(target.id)
        elif (
            isinstance(target, ast.Tuple)
            and len(target.elts) == 2
            and isinstance(target.elts[1], ast.Name)
        ):
            bearings.add(target.elts[1].id)
    return results, bearings


def _is_bearing(node: ast.expr, results: set[str], bearings: set[str]) -> bool:
    if isinstance(node, ast.Name):
        return node.id in bearings
    if not (
        isinstance(node, ast.Subscript)
        and isinstance(node.slice, ast.Constant)
        and node.slice.value == 1
    ):
        return False
    held = node.value
    return (isinstance(held, ast.Name) and held.id in results) or (
        isinstance(held, ast.Call) and self_method(held) == _CLOSEST
    )


def _is_angle_min(node: ast.AST) -> bool:
    return isinstance(node, ast.Attribute) and node.attr == "angle_min"


def _as_it_is(statement: ast.stmt, offset: ast.BinOp, bearing: ast.expr) -> str:
    """``statement`` with the ``offset`` of ``bearing`` replaced by the bearing alone."""
    return with_node_replaced(statement, offset, lambda _: copy.deepcopy(bearing))
