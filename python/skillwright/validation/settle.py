"""Giving up on a reading taken the moment after a command (check ``waits``).

A skill that publishes a velocity and then at once::

    self._wait_until(lambda: self.odom_msg is not None, 30.0, "odometry on /odom")
    if abs(self.in_velocity - self.odom_msg.twist.twist.linear.x) > 0.05:
        raise RuntimeError(f"constraint violated: ...")

tests odometry that came in before the command: a base takes time to accelerate, so the
skill gives up on a robot that is fine ("constraint violated: 0.3 != 0.0"). The wait before
it does not help, because the message was there already.

A method's ``if TEST: raise ...`` (nothing else in its body, no ``else``) is flagged when an
earlier statement of the method's body publishes or sends a goal, ``TEST`` reads a field of a
latest message (``self.X_msg``, which a callback keeps), and nothing in between sleeps or
waits on a condition that reads that message's fields. (Inside a loop that commands and
tests on every pass, the test is most often a guard, an obstacle too close, and is left
alone.) The test is then a condition to wait
for, not one to give up on: the fix waits until it no longer holds, with the skeleton's
``_wait_until``, and raises only when that does not happen in time (a run that finds the wait
too short gets more seconds; see :mod:`skillwright.validation.timeouts`).
"""

from __future__ import annotations

import ast

from skillwright.rules.behaviour import READ_RIGHT_AFTER_COMMAND
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_attribute

__all__ = ["check_settling"]

_WAIT_SECONDS = 5.0
"""How long the fix waits for the robot to answer a command."""

_COMMANDS = frozenset({"publish", "send_goal_async", "send_goal", "call_async"})
_OPPOSITE: dict[type[ast.cmpop], type[ast.cmpop]] = {
    ast.Gt: ast.LtE,
    ast.GtE: ast.Lt,
    ast.Lt: ast.GtE,
    ast.LtE: ast.Gt,
    ast.Eq: ast.NotEq,
    ast.NotEq: ast.Eq,
}


def check_settling(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``waits``) for giving up on a reading right after a command."""
    latest = set(facts.latest_messages)
    can_wait = "_wait_until" in facts.methods
    findings = []
    for method in facts.functions:
        findings += _in_block(method.body, latest, can_wait)
    return findings


def _in_block(block: list[ast.stmt], latest: set[str], can_wait: bool) -> list[Finding]:
    findings = []
    command: ast.stmt | None = None
    settled: set[str] = set()
    for statement in block:
        if _commands(statement):
            command, settled = statement, set()
            continue
        if command is None:
            continue
        settled |= _waited_on(statement, latest)
        read = _gives_up_on(statement, latest)
        if read is None or read in settled:
            continue
        assert isinstance(statement, ast.If)
        condition = _negated(statement.test)
        replacement = (
            f"self._wait_until(lambda: {condition}, {_WAIT_SECONDS}, "
            f"{f'{condition} after the command'!r})"
            if can_wait
            else None
        )
        findings.append(
            error_at(
                READ_RIGHT_AFTER_COMMAND,
                statement,
                f"`{ast.unparse(statement.test)}` is tested right after "
                f"`{ast.unparse(command).splitlines()[0]}`, on self.{read} as it was before "
                "the command: the robot has had no time to answer it, so this gives up on a "
                f"robot that is fine; wait until {condition} instead"
                + (f", for up to {_WAIT_SECONDS:g} s" if can_wait else ""),
                replacement,
            )
        )
    return findings


def _commands(statement: ast.stmt) -> bool:
    """Whether ``statement`` publishes or sends a goal or request (at its top level)."""
    return (
        isinstance(statement, ast.Expr | ast.Assign)
        and isinstance(statement.value, ast.Call)
        and isinstance(statement.value.func, ast.Attribute)
        and statement.value.func.attr in _COMMANDS
    )


def _fields_read(node: ast.AST, latest: set[str]) -> set[str]:
    """The latest messages whose fields ``node`` reads (``self.odom_msg.twist``)."""
    return {
        name
        for n in ast.walk(node)
        if isinstance(n, ast.Attribute)
        and (name := self_attribute(n.value)) is not None
        and name in latest
    }


def _waited_on(statement: ast.stmt, latest: set[str]) -> set[str]:
    """The latest messages ``statement`` gives time to change: all of them for a sleep or a
    loop, those whose fields a wait's condition reads for a wait."""
    if isinstance(statement, ast.While | ast.For):
        return set(latest)
    found: set[str] = set()
    for call in (n for n in ast.walk(statement) if isinstance(n, ast.Call)):
        name = call.func.attr if isinstance(call.func, ast.Attribute) else None
        if name == "sleep":
            return set(latest)
        if name is not None and name.startswith("_wait") and call.args:
            found |= _fields_read(call.args[0], latest)
    return found


def _gives_up_on(statement: ast.stmt, latest: set[str]) -> str | None:
    """The latest message an ``if TEST: raise`` tests a field of, when that is all it does."""
    if not (
        isinstance(statement, ast.If)
        and not statement.orelse
        and all(isinstance(s, ast.Raise) for s in statement.body)
    ):
        return None
    read = _fields_read(statement.test, latest)
    return min(read) if read else None


def _negated(test: ast.expr) -> str:
    """The condition under which ``test`` does not hold, as code."""
    if isinstance(test, ast.Compare) and len(test.ops) == 1 and type(test.ops[0]) in _OPPOSITE:
        opposite = _OPPOSITE[type(test.ops[0])]()
        return ast.unparse(
            ast.Compare(left=test.left, ops=[opposite], comparators=test.comparators)
        )
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        return ast.unparse(test.operand)
    return f"not ({ast.unparse(test)})"
