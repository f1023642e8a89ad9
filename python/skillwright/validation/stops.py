"""Loops that stop the robot on every pass while they wait for it to move (check ``stops``).

A turn published once before a loop that waits for the heading, and in the loop, on every
pass, ``self.cmd_vel_publisher.publish(Twist())``: a zero velocity, which a base obeys at
once. The base stops after the first pass, the heading never arrives, and the state gives
up. A run can say that nothing was moving; this check says why, and where.

A loop is flagged when every velocity command it publishes on a publisher, outside the
branches that leave it (``if ...: publish(Twist()); raise``, the stop before giving up), is a
zero ``Twist()`` or ``TwistStamped()``, or a call of a method that only publishes those (the
skeleton's ``_stop_base()``), and
the last command published on it before the loop, in the same block, is one whose fields
were set. The fix publishes that command
in the loop instead.
"""

from __future__ import annotations

import ast

from skillwright.rules.behaviour import STOP_IN_WAIT_LOOP
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import blocks, error_at, self_method

__all__ = ["check_stops", "loop_publishes", "zero_velocity"]

_VELOCITY = frozenset({"Twist", "TwistStamped"})


def check_stops(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``stops``) for loops that command zero velocity on every pass after
    a motion command started them."""
    methods = facts.functions
    stoppers = {m.name: p for m in methods if (p := _stopper(m)) is not None}
    findings = []
    for method in methods:
        for block in blocks(method):
            for index, statement in enumerate(block):
                if isinstance(statement, ast.While):
                    findings += _stopping(statement, block[:index], stoppers)
    return findings


def _stopper(method: ast.FunctionDef) -> str | None:
    """The publisher a method of the skill only ever commands zero velocity on (the
    skeleton's ``_stop_base``), if it is one such method."""
    calls = [p for p in loop_publishes(method.body, {}) if p[0] is not None]
    publishers = {p for p, _ in calls}
    if len(publishers) != 1 or not all(_zero(call) for _, call in calls):
        return None
    return publishers.pop()


def _stopping(loop: ast.While, before: list[ast.stmt], stoppers: dict[str, str]) -> list[Finding]:
    publishes = loop_publishes(loop.body, stoppers)
    findings = []
    for publisher in {p for p, _ in publishes}:
        mine = [call for p, call in publishes if p == publisher]
        if not all(_zero(call) or _stopper_call(call, stoppers) for call in mine):
            continue
        command = _started_with(before, publisher)
        if command is None:
            continue
        for call in mine:
            statement = _statement_of(loop, call)
            if statement is None:
                continue
            findings.append(
                error_at(
                    STOP_IN_WAIT_LOOP,
                    statement,
                    f"this loop commands zero velocity on every pass ({ast.unparse(call)}), "
                    f"right after {publisher}.publish({command}) started the motion before "
                    "it: the robot stops after the first pass, so what the loop waits for "
                    f"never comes; publish the motion command, {command}, in the loop",
                    f"{publisher}.publish({command})",
                )
            )
    return findings


def loop_publishes(body: list[ast.stmt], stoppers: dict[str, str]) -> list[tuple[str, ast.Call]]:
    """(publisher, call) of the ``publish`` calls in ``body``, and of the calls of
    ``stoppers`` (method -> the publisher it commands zero on), outside the branches that
    leave the loop and outside nested functions."""
    out: list[tuple[str, ast.Call]] = []
    pending: list[ast.AST] = list(body)
    while pending:
        node = pending.pop()
        if isinstance(node, ast.FunctionDef | ast.Lambda | ast.ClassDef):
            continue
        if isinstance(node, ast.If):
            pending.append(node.test)
            pending.extend(
                b for block in (node.body, node.orelse) if not _leaves(block) for b in block
            )
            continue
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "publish"
            and len(node.args) == 1
        ):
            out.append((ast.unparse(node.func.value), node))
        elif isinstance(node, ast.Call) and _self_call(node) in stoppers:
            out.append((stoppers[_self_call(node) or ""], node))
        pending.extend(ast.iter_child_nodes(node))
    return out


def _self_call(call: ast.Call) -> str | None:
    """The method of the skill ``call`` calls without arguments, if it does."""
    return None if call.args or call.keywords else self_method(call)


def _stopper_call(call: ast.Call, stoppers: dict[str, str]) -> bool:
    return _self_call(call) in stoppers


def _leaves(block: list[ast.stmt]) -> bool:
    return bool(block) and isinstance(block[-1], ast.Raise | ast.Break | ast.Return)


def _zero(call: ast.Call) -> bool:
    return bool(call.args) and zero_velocity(call.args[0])


def zero_velocity(message: ast.expr) -> bool:
    """Whether ``message`` is a new ``Twist()`` or ``TwistStamped()``: every speed zero."""
    return (
        isinstance(message, ast.Call)
        and isinstance(message.func, ast.Name)
        and message.func.id in _VELOCITY
        and not message.args
        and not message.keywords
    )


def _started_with(before: list[ast.stmt], publisher: str) -> str | None:
    """The local name of the command ``publisher`` published in ``before`` (the last one),
    when it is a velocity message whose fields were set."""
    for statement in reversed(before):
        for node in ast.walk(statement):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "publish"
                and ast.unparse(node.func.value) == publisher
                and len(node.args) == 1
            ):
                # the last command before the loop: a stop there means the loop brakes
                message = node.args[0]
                if isinstance(message, ast.Name) and _built_and_set(before, message.id):
                    return message.id
                return None
    return None


def _built_and_set(before: list[ast.stmt], name: str) -> bool:
    built = set_fields = False
    for statement in before:
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
            target, value = statement.targets[0], statement.value
            if isinstance(target, ast.Name) and target.id == name:
                built = (
                    isinstance(value, ast.Call)
                    and isinstance(value.func, ast.Name)
                    and value.func.id in _VELOCITY
                )
            elif isinstance(target, ast.Attribute) and _root(target) == name:
                set_fields = True
    return built and set_fields


def _root(node: ast.expr) -> str | None:
    while isinstance(node, ast.Attribute):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _statement_of(loop: ast.While, call: ast.Call) -> ast.stmt | None:
    """The expression statement that is ``call``, if it is one (not part of another
    statement)."""
    for node in ast.walk(loop):
        if isinstance(node, ast.Expr) and node.value is call:
            return node
    return None
