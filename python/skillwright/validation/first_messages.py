"""Giving up on a subscription's first message, or reading it, without waiting for it (check
``waits``).

The skeleton keeps a subscription's latest message in ``self.X_msg``, which is ``None`` until
the first message arrives. PySkillUp runs a state right after the one before it, so a state
that tests ``if self.X_msg is None: raise ...`` before anything waited for that message gives
up on a robot that is fine: the subscription was made a moment ago. Small models write this
guard often (and the sandboxed run finds it, one slow run later). Where the guard only
raises, the finding carries the wait that should take its place.

A state that reads a field of such a message (``self.odom_msg.twist.twist.linear.x``) before
anything waited for it raises AttributeError the same way (``None`` has no fields), also in
execute after a starting that made the subscription and waited for nothing: rclpy delivers a
message only once discovery has matched the publisher, which takes a moment. The finding
puts the wait before the statement that reads it.

A message counts as waited for once a state on the normal path (``starting``, ``execute``,
``completing``) before the guard waited for it: a ``_wait_until``, a loop whose condition
reads it, or a bounded poll (``for _ in range(n)`` that sleeps and leaves once the message is
there), directly or in a method of the class it calls.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

from skillwright.rules.behaviour import FIRST_MESSAGE_GUARD, FIRST_MESSAGE_READ
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_attribute

__all__ = ["check_first_messages"]

_NORMAL_PATH = ("starting", "execute", "completing")


def _mentions(node: ast.AST, attribute: str) -> bool:
    return any(self_attribute(n) == attribute for n in ast.walk(node))


def _waits_for(
    node: ast.AST, attribute: str, methods: Mapping[str, ast.FunctionDef], depth: int = 2
) -> bool:
    """Whether ``node`` waits until ``self.<attribute>`` is set: ``self._wait_until`` with a
    condition that reads it, a ``while`` loop whose test reads it, or a call of a method of
    the class that does (``depth`` levels deep)."""
    for inner in ast.walk(node):
        if isinstance(inner, ast.While) and _mentions(inner.test, attribute):
            return True
        if isinstance(inner, ast.For) and _polls(inner, attribute):
            return True
        if not isinstance(inner, ast.Call):
            continue
        called = self_attribute(inner.func)
        if called == "_wait_until" and any(_mentions(a, attribute) for a in inner.args):
            return True
        callee = methods.get(called) if called is not None else None
        if callee is not None and depth > 0 and _waits_for(callee, attribute, methods, depth - 1):
            return True
    return False


def _polls(loop: ast.For, attribute: str) -> bool:
    """Whether ``loop`` is a bounded poll for ``self.<attribute>``: a ``for`` over a count
    (``for _ in range(50)``) that sleeps or spins on every pass and leaves, by ``break`` or
    ``return``, in a branch whose test reads the attribute. rclpy fills a subscription's
    latest message from its executor while the state sleeps, so such a loop waits as
    ``_wait_until`` does (what happens when it runs out is the run's to judge)."""
    sleeps = any(
        isinstance(n, ast.Call)
        and isinstance(n.func, ast.Attribute | ast.Name)
        and (n.func.attr if isinstance(n.func, ast.Attribute) else n.func.id)
        in {"sleep", "spin_once"}
        for n in ast.walk(loop)
    )
    leaves = any(
        isinstance(n, ast.If)
        and _mentions(n.test, attribute)
        and any(isinstance(s, ast.Break | ast.Return) for s in n.body)
        for n in ast.walk(loop)
    )
    return sleeps and leaves


def _wait_for(attribute: str) -> str:
    """The skeleton's wait for the first message into ``self.<attribute>``."""
    return f'self._wait_until(lambda: self.{attribute} is not None, 2.0, "{attribute}")'


def _reads_parameter_fields(method: ast.FunctionDef, index: int) -> bool:
    """Whether ``method`` reads a field of its ``index``-th parameter after ``self``; past
    the named parameters, of an element of its ``*args`` (``for scan in scans: scan.ranges``
    in the skeleton's ``_closest_reading(self, *scans)``)."""
    parameters = method.args.args[1:]
    if index < len(parameters):
        names = {parameters[index].arg}
    elif method.args.vararg is not None:
        names = _elements_of(method, method.args.vararg.arg)
    else:
        return False
    for node in ast.walk(method):
        if not isinstance(node, ast.Attribute):
            continue
        holder = node.value.value if isinstance(node.value, ast.Subscript) else node.value
        if isinstance(holder, ast.Name) and holder.id in names:
            return True
    return False


def _elements_of(method: ast.FunctionDef, sequence: str) -> set[str]:
    """The names ``method`` binds to the elements of its parameter ``sequence``: the
    targets of ``for x in sequence`` and of ``x = sequence[i]``."""
    out = {sequence}  # read by index: scans[0].ranges
    for node in ast.walk(method):
        if (
            isinstance(node, ast.For | ast.comprehension)
            and isinstance(node.iter, ast.Name)
            and node.iter.id == sequence
        ):
            out |= {n.id for n in ast.walk(node.target) if isinstance(n, ast.Name)}
        elif (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Subscript)
            and isinstance(node.value.value, ast.Name)
            and node.value.value.id == sequence
        ):
            out |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return out


def _hands_over(node: ast.AST, attribute: str, methods: Mapping[str, ast.FunctionDef]) -> bool:
    """Whether ``node`` calls a method of the class with ``self.<attribute>`` for a parameter
    whose fields it reads (``self._closest_reading(self.scan_msg)``)."""
    if not isinstance(node, ast.Call) or not isinstance(node.func, ast.Attribute):
        return False
    method = methods.get(node.func.attr) if self_attribute(node.func) is not None else None
    return method is not None and any(
        self_attribute(argument) == attribute and _reads_parameter_fields(method, index)
        for index, argument in enumerate(node.args)
    )


def _reads_field(
    statement: ast.stmt, attribute: str, methods: Mapping[str, ast.FunctionDef]
) -> bool:
    """Whether ``statement`` reads a field of ``self.<attribute>`` (``self.odom_msg.pose``),
    or hands it to a method that does, outside lambdas and outside a test of that message
    (``if self.odom_msg is not None``, ``self.odom_msg and self.odom_msg.pose``)."""
    tests = [
        n.test if isinstance(n, ast.If | ast.IfExp | ast.While) else n
        for n in ast.walk(statement)
        if isinstance(n, ast.If | ast.IfExp | ast.While | ast.BoolOp)
    ]
    if any(_mentions(test, attribute) for test in tests):
        return False
    pending: list[ast.AST] = [statement]
    while pending:
        node = pending.pop()
        if isinstance(node, ast.Lambda | ast.FunctionDef):
            continue
        if isinstance(node, ast.Attribute) and self_attribute(node.value) == attribute:
            return True
        if _hands_over(node, attribute, methods):
            return True
        pending.extend(ast.iter_child_nodes(node))
    return False


def _tested(test: ast.expr, aliases: Mapping[str, str]) -> str | None:
    """The latest-message attribute ``test`` finds missing: ``X is None`` or ``not X``, with
    X ``self.<attribute>`` or a local variable set from it."""
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        subject: ast.expr = test.operand
    elif (
        isinstance(test, ast.Compare)
        and len(test.ops) == 1
        and isinstance(test.ops[0], ast.Is)
        and isinstance(test.comparators[0], ast.Constant)
        and test.comparators[0].value is None
    ):
        subject = test.left
    else:
        return None
    if isinstance(subject, ast.Name):
        return aliases.get(subject.id)
    return self_attribute(subject)


def _read_too_soon(statement: ast.stmt, reads: list[str], state: str) -> Finding:
    """The finding for ``statement`` reading the fields of the first messages ``reads``
    before anything waited for them, with the waits put before it."""
    waits = [_wait_for(read) for read in reads]
    named = " and ".join(f"self.{read}" for read in reads)
    stays = "stays None" if len(reads) == 1 else "stay None"
    return error_at(
        FIRST_MESSAGE_READ,
        statement,
        f"{named} {stays} until the first message arrives, and nothing waited for "
        f"{'it' if len(reads) == 1 else 'them'} before {state} reads "
        f"{'its' if len(reads) == 1 else 'their'} fields here: on a robot that is fine the "
        "state raises AttributeError when it runs before the first message. Wait first: "
        + "; ".join(waits),
        "\n".join([*waits, ast.unparse(statement)]),
    )


def check_first_messages(facts: SkillFacts) -> list[Finding]:
    """Findings for guards that give up on a first message nothing waited for, with the wait
    (and the local variables set from the message again after it) in their place."""
    latest = set(facts.latest_messages)
    methods = facts.methods
    states = facts.states
    waited: set[str] = set()
    reported: set[str] = set()
    findings = []
    for state in _NORMAL_PATH:
        method = states.get(state)
        if method is None:
            continue
        aliases: dict[str, str] = {}
        # messages a guard before here tested, leaving the state when they were missing
        checked: set[str] = set()
        for statement in method.body:
            attribute = _tested(statement.test, aliases) if isinstance(statement, ast.If) else None
            gives_up = (
                isinstance(statement, ast.If)
                and not statement.orelse
                and all(isinstance(s, ast.Raise) for s in statement.body)
            )
            if gives_up and attribute in latest and attribute not in waited:
                wait = _wait_for(attribute)
                again = [
                    f"{local} = self.{attribute}" for local, a in aliases.items() if a == attribute
                ]
                findings.append(
                    error_at(
                        FIRST_MESSAGE_GUARD,
                        statement,
                        f"self.{attribute} stays None until the first message arrives, and "
                        f"nothing waited for it before this guard in {state}: the state gives up "
                        "on a robot that is fine. Wait for it (the wait raises after its "
                        f"timeout): {wait}",
                        "\n".join([wait, *again]),
                    )
                )
                waited.add(attribute)
            if (
                isinstance(statement, ast.If)
                and statement.body
                and isinstance(statement.body[-1], ast.Return | ast.Raise)
            ):
                checked |= {a for a in latest if _mentions(statement.test, a)}
            unready = [
                read
                for read in sorted(latest - waited - reported - checked)
                if _reads_field(statement, read, methods)
                and not _waits_for(statement, read, methods)
            ]
            if unready:
                findings.append(_read_too_soon(statement, unready, state))
                reported |= set(unready)
            if (
                isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)
                and (source := self_attribute(statement.value)) in latest
            ):
                aliases[statement.targets[0].id] = str(source)
            waited |= {a for a in latest if _waits_for(statement, a, methods)}
    return findings
