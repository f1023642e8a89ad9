"""Commands built and never sent (check ``unsent``).

A skill that builds ``command = Twist()``, sets its linear and angular speed, waits for the
odometry to show them and stores ``command.linear.x`` as an output has commanded nothing: a
message reaches the base only through ``publish``, so the base never moves and the wait gives
up. A run sees a timeout; this check says why before anything runs.

A local variable is flagged when it is assigned a message the class publishes (the type a
``create_publisher`` of the class names), an action goal (``NavigateToPose.Goal()`` for an
``ActionClient`` of the class) or a service request (``Trigger.Request()`` for a
``create_client``), and the method never uses it whole: every use reads or sets one of its
fields, none publishes it, sends it, passes it to a call, stores it or returns it, and the
method sends nothing else through the handles that take it (a left-over message beside one
that is sent is dead code, not a command lost; an empty ``Twist()`` published to stop does
not count). Such a message only ever leaves the method in pieces, so whatever it was built
to command does not happen.

When one publisher of the class publishes that type, the fix publishes the message once it
is complete: after the last plain statement that sets one of its fields, before a branch or
loop that touches it (no fix when such a loop or branch sets its first fields: what to
publish is decided in there).
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Iterator

from skillwright.rules.behaviour import BUILT_NOT_SENT
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import (
    COMPOUND_STATEMENTS,
    blocks,
    error_at,
    self_attribute,
    written_type,
)

__all__ = ["check_unsent"]


def check_unsent(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``unsent``) for messages, goals and requests a method builds and never
    sends or passes on."""
    publishers, goals, requests = _interfaces(facts)
    findings = []
    for method in facts.functions:
        whole = _used_whole(method)
        sending = _senders_called(method)
        reported: set[str] = set()
        for block, index, name, built in _built(method):
            if name in whole or name in reported:
                continue
            if built in publishers:
                what, senders = f"a {built} message", publishers[built]
                how = "publishes it"
            elif built in goals:
                what, senders = f"a {built}", goals[built]
                how = "sends it"
            elif built in requests:
                what, senders = f"a {built}", requests[built]
                how = "calls the service with it"
            else:
                continue
            if sending.intersection(senders):
                continue  # it sends something else there: the message is only left over
            reported.add(name)
            findings.append(_finding(block, index, name, what, how, built, senders))
    return findings


def _interfaces(
    facts: SkillFacts,
) -> tuple[dict[str, list[str]], dict[str, list[str]], dict[str, list[str]]]:
    """(message type -> publishers, ``T.Goal`` -> action clients, ``T.Request`` -> service
    clients) of the handles the class keeps on itself, each handle as ``self.name``, each
    type as the skill names it (``Twist``, ``NavigateToPose.Goal``)."""
    publishers: dict[str, list[str]] = defaultdict(list)
    goals: dict[str, list[str]] = defaultdict(list)
    requests: dict[str, list[str]] = defaultdict(list)
    for handle in facts.handles:
        kind = handle.made.type_written
        if handle.attribute is None or kind is None:
            continue
        if handle.made.maker == "create_publisher":
            publishers[kind].append(handle.target)
        elif handle.made.maker == "ActionClient":
            goals[f"{kind}.Goal"].append(handle.target)
        elif handle.made.maker == "create_client":
            requests[f"{kind}.Request"].append(handle.target)
    return publishers, goals, requests


def _built(method: ast.FunctionDef) -> Iterator[tuple[list[ast.stmt], int, str, str]]:
    """(block, index in it, local name, type) of each ``name = Type(...)`` in ``method``."""
    for block in blocks(method):
        for index, statement in enumerate(block):
            if (
                isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)
                and isinstance(statement.value, ast.Call)
                and (built := written_type(statement.value.func)) is not None
            ):
                yield block, index, statement.targets[0].id, built


def _senders_called(method: ast.FunctionDef) -> set[str]:
    """The handles (``self.name``) whose methods ``method`` calls: a publisher it publishes
    on (other than an empty message, ``Twist()``, which stops), a client it sends a goal or a
    request with."""
    return {
        f"self.{handle}"
        for node in ast.walk(method)
        if isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and (handle := self_attribute(node.func.value)) is not None
        and not (node.func.attr == "publish" and all(map(_empty, node.args)))
    }


def _empty(node: ast.expr) -> bool:
    return isinstance(node, ast.Call) and not node.args and not node.keywords


def _used_whole(method: ast.FunctionDef) -> set[str]:
    """Local names ``method`` reads as a whole value anywhere (not only as the object of a
    field it reads or sets)."""
    parts = {
        id(node.value)
        for node in ast.walk(method)
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
    }
    return {
        node.id
        for node in ast.walk(method)
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and id(node) not in parts
    }


def _finding(
    block: list[ast.stmt],
    index: int,
    name: str,
    what: str,
    how: str,
    built: str,
    senders: list[str],
) -> Finding:
    handles = " or ".join(dict.fromkeys(senders))
    message = (
        f"{name}, {what} built on line {block[index].lineno}, is never sent: nothing {how} "
        "or passes it on (only its fields are set or read), so what it commands never "
        "reaches the robot"
    )
    if built.endswith(".Goal"):
        return error_at(BUILT_NOT_SENT, block[index], f"{message}; send it with {handles}")
    if built.endswith(".Request"):
        return error_at(BUILT_NOT_SENT, block[index], f"{message}; call {handles} with it")
    fix = f"{senders[0]}.publish({name})"
    statement = _complete(block, index, name)
    if len(set(senders)) == 1 and statement is not None:
        return error_at(
            BUILT_NOT_SENT,
            statement,
            f"{message}; publish it with {fix} once it is complete",
            f"{ast.unparse(statement)}\n{fix}",
        )
    return error_at(BUILT_NOT_SENT, block[index], f"{message}; publish it with {handles}")


def _complete(block: list[ast.stmt], index: int, name: str) -> ast.stmt | None:
    """The statement after which the message ``block[index]`` builds is complete: the last
    plain statement setting one of its fields before anything else happens to it (a branch or
    loop that touches it, or a new value for the name). ``None`` when a loop or branch sets
    its first fields: what to publish is decided in there."""
    last = block[index]
    for later in block[index + 1 :]:
        names = [n for n in ast.walk(later) if isinstance(n, ast.Name) and n.id == name]
        if not names:
            continue
        sets = any(_sets_field(node, name) for node in ast.walk(later))
        renamed = any(isinstance(n.ctx, ast.Store) for n in names)
        if isinstance(later, COMPOUND_STATEMENTS) or renamed:
            return None if sets and last is block[index] else last
        if sets:
            last = later
    return last


def _sets_field(node: ast.AST, name: str) -> bool:
    """Whether ``node`` stores into a field of the local ``name``."""
    if not isinstance(node, ast.Attribute) or not isinstance(node.ctx, ast.Store):
        return False
    root: ast.expr = node
    while isinstance(root, ast.Attribute | ast.Subscript):
        root = root.value
    return isinstance(root, ast.Name) and root.id == name
