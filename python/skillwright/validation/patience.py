"""A wait of the skill's own helpers given no time at all (check ``waits``).

The skeleton's helpers that wait take their seconds as ``timeout``: ``_wait_until``,
``_transform``, ``_result_of`` and the goal helpers. Given 0 (``self._transform("map",
"base_link", 0.0)`` reads like tf's "latest transform" stamp, ``Time()``, but is the helper's
timeout), such a wait gives up before the first message can come: rclpy delivers messages
and tf2's listener fills its buffer only while the skill waits. The fix
gives the wait the skeleton's own two seconds; a run that finds them short lengthens them.
"""

from __future__ import annotations

import ast
import copy

from skillwright.rules.behaviour import ZERO_TIMEOUT
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_method
from skillwright.validation.timeouts import bound_arguments

__all__ = ["check_zero_timeouts"]

_TIMEOUTS = frozenset({"timeout", "timeout_sec"})
_GIVEN = 2.0
"""The seconds the fix gives: the skeleton's own waits for a first message take as many."""


def check_zero_timeouts(facts: SkillFacts) -> list[Finding]:
    """Findings for calls of the skill's waiting methods with a timeout of zero or less."""
    methods = facts.methods
    waiting = {
        name: parameters
        for name, method in methods.items()
        if (parameters := {a.arg for a in method.args.args} & _TIMEOUTS)
    }
    findings = []
    for method in methods.values():
        for call in facts.calls(method):
            called = self_method(call)
            if called not in waiting:
                continue
            given, _ = bound_arguments(methods[called], call, waiting[called])
            zeros = [a for a in given if _at_most_zero(a)]
            statement = facts.statement_holding(call, method)
            if not zeros or statement is None:
                continue
            findings.append(
                error_at(
                    ZERO_TIMEOUT,
                    statement,
                    f"`{ast.unparse(call)}` gives {called}() a timeout of "
                    f"{ast.unparse(zeros[0])} s: the wait gives up before anything can "
                    f"arrive. Give it time, e.g. {_GIVEN:g} s (a transform's stamp is not "
                    "its timeout: the helper always asks for the latest one)",
                    ast.unparse(_given_time(statement, zeros)),
                )
            )
    return findings


def _at_most_zero(node: ast.expr) -> bool:
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        return _at_most_zero(node.operand) or (
            isinstance(node.operand, ast.Constant)
            and isinstance(node.operand.value, int | float)
            and not isinstance(node.operand.value, bool)
        )
    return (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int | float)
        and not isinstance(node.value, bool)
        and node.value <= 0
    )


def _given_time(statement: ast.stmt, zeros: list[ast.expr]) -> ast.stmt:
    memo: dict[int, object] = {}
    changed = copy.deepcopy(statement, memo)
    targets = {id(memo[id(z)]) for z in zeros if id(z) in memo}

    class _Give(ast.NodeTransformer):
        def visit(self, node: ast.AST) -> ast.AST:
            if id(node) in targets:
                return ast.Constant(_GIVEN)
            return self.generic_visit(node)

    given = _Give().visit(changed)
    assert isinstance(given, ast.stmt)
    return ast.fix_missing_locations(given)
