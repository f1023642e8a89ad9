"""A scanner of a split view subscribed to and never read (check ``views``).

Retrieval gives a skill both scanners of a split view (the MMO-700's ``/scan`` on one corner
and ``/scan2`` on the opposite one, see :func:`~skillwright.retrieval.semantics.split_view`),
and the skeleton subscribes to both. The default model's get-distance-to-nearest-object on
the paper's robot then took the closest reading of ``self.scan_msg`` alone: ``scan2_msg``
was kept by its callback and read by nothing, so an obstacle only the second scanner sees
goes unnoticed. A simulation whose scanners both see all around cannot tell; this check
says so before anything runs.

A subscription counts as read when a method other than its callback reads the attribute the
callback keeps the message in, other than to test it against ``None`` (waiting for a first
message is not using it). It is an error when another part of the same view is read and
this one is not: the skill measures one side only. The finding stands where the part that
is read is first read, which is where the other belongs too.
"""

from __future__ import annotations

import ast

from skillwright.interfaces.inventory import Interface
from skillwright.retrieval.semantics import split_view
from skillwright.rules.behaviour import SCANNER_UNREAD
from skillwright.rules.finding import Finding
from skillwright.validation.names import self_attribute, simple_statements

__all__ = ["check_views"]


class _Subscription:
    """A ``create_subscription`` of the class, the statement that makes it and the
    attributes its callback keeps the message in."""

    def __init__(self, statement: ast.stmt, interface: Interface, callback: str) -> None:
        self.statement = statement
        self.interface = interface
        self.callback = callback
        self.kept: set[str] = set()


def check_views(cls: ast.ClassDef, tree: ast.Module) -> list[Finding]:
    """Findings (check ``views``) for the parts of a split view a skill subscribes to and
    never reads while it reads another part."""
    subscriptions = _subscriptions(cls, _message_types(tree))
    if len(subscriptions) < 2:
        return []
    methods = {m.name: m for m in cls.body if isinstance(m, ast.FunctionDef)}
    for subscription in subscriptions:
        callback = methods.get(subscription.callback)
        if callback is not None:
            subscription.kept = _kept(callback)
    reads = {s.interface.name: _first_read(s, methods) for s in subscriptions}
    findings = []
    for unread in subscriptions:
        if reads[unread.interface.name] is not None or not unread.kept:
            continue
        parts = [
            (s.interface.name, read)
            for s in subscriptions
            if (read := reads[s.interface.name]) is not None
            and split_view(unread.interface, s.interface)
        ]
        if not parts:
            continue
        kept = sorted(unread.kept)[0]
        names = ", ".join(name for name, _ in parts)
        where = min((read for _, read in parts), key=lambda node: (node.lineno, node.col_offset))
        fix = _fix(cls, where, kept)
        advice = (
            f"wait for self.{kept} too and pass it to the same call, "
            f"{fix[0]}, which gives the closest reading of both"
            if fix is not None
            else f"wait for self.{kept} too and use the nearer of the two closest readings"
        )
        findings.append(
            SCANNER_UNREAD.finding(
                line=where.lineno,
                column=where.col_offset + 1,
                data={"attribute": kept, "interface": unread.interface.name},
                message=f"{unread.interface.name} and {names} are two scanners of one split "
                f"view, each seeing a side the other does not, but only {names} is read here "
                f"and nothing reads self.{kept}: an obstacle only {unread.interface.name} sees "
                f"goes unnoticed; {advice}",
                replacement=None if fix is None else fix[1],
            )
        )
    return findings


def _fix(cls: ast.ClassDef, read: ast.Attribute, kept: str) -> tuple[str, str] | None:
    """Where ``read`` is the one argument of the skeleton's ``self._closest_reading(...)`` in
    a statement of its own: the call with ``self.<kept>`` added, and the statement with that
    call, after the wait for its first message."""
    if not any(isinstance(n, ast.FunctionDef) and n.name == _CLOSEST for n in cls.body):
        return None
    statement_of = simple_statements(cls)
    for call in ast.walk(cls):
        if (
            isinstance(call, ast.Call)
            and self_attribute(call.func) == _CLOSEST
            and call.args == [read]
            and not call.keywords
        ):
            old = ast.unparse(call)
            new = f"self.{_CLOSEST}({ast.unparse(read)}, self.{kept})"
            statement = statement_of.get(id(call))
            if statement is None or ast.unparse(statement).count(old) != 1:
                return None
            wait = f'self._wait_until(lambda: self.{kept} is not None, 2.0, "{kept}")'
            return new, f"{wait}\n{ast.unparse(statement).replace(old, new)}"
    return None


_CLOSEST = "_closest_reading"
"""The skeleton's helper for the nearest reading of one scan or several."""


def _message_types(tree: ast.Module) -> dict[str, str]:
    """Class name -> ROS type name of the message classes the module imports
    (``from sensor_msgs.msg import LaserScan`` -> ``sensor_msgs/msg/LaserScan``)."""
    out = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.endswith(".msg"):
            package = node.module.replace(".", "/")
            for alias in node.names:
                out[alias.asname or alias.name] = f"{package}/{alias.name}"
    return out


def _subscriptions(cls: ast.ClassDef, types: dict[str, str]) -> list[_Subscription]:
    """``self.x = self.node.create_subscription(Type, "/topic", self._on_x, ...)``."""
    out = []
    for statement in ast.walk(cls):
        if not isinstance(statement, ast.stmt):
            continue
        call = getattr(statement, "value", None)
        if not (
            isinstance(call, ast.Call)
            and isinstance(call.func, ast.Attribute)
            and call.func.attr == "create_subscription"
            and len(call.args) >= 3
        ):
            continue
        kind, topic, callback = call.args[:3]
        name = self_attribute(callback)
        if not (
            isinstance(kind, ast.Name)
            and kind.id in types
            and isinstance(topic, ast.Constant)
            and isinstance(topic.value, str)
            and name is not None
        ):
            continue
        interface = Interface(name=topic.value, kind="topic", type_name=types[kind.id])
        out.append(_Subscription(statement, interface, name))
    return out


def _kept(callback: ast.FunctionDef) -> set[str]:
    """The ``self`` attributes ``callback`` assigns its message parameter to."""
    parameters = callback.args.args[1:]
    if not parameters:
        return set()
    message = parameters[0].arg
    kept = set()
    for node in ast.walk(callback):
        if (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Name)
            and node.value.id == message
        ):
            kept |= {a for t in node.targets if (a := self_attribute(t)) is not None}
    return kept


def _first_read(
    subscription: _Subscription, methods: dict[str, ast.FunctionDef]
) -> ast.Attribute | None:
    """The first place (by line and column; ``ast.walk`` goes breadth first) a method other
    than the callback reads a kept attribute other than to test it against ``None``."""
    reads = []
    for name, method in methods.items():
        if name == subscription.callback:
            continue
        tested = {
            id(side)
            for node in ast.walk(method)
            if isinstance(node, ast.Compare)
            and all(isinstance(op, ast.Is | ast.IsNot) for op in node.ops)
            for side in (node.left, *node.comparators)
        }
        reads += [
            node
            for node in ast.walk(method)
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and self_attribute(node) in subscription.kept
            and id(node) not in tested
        ]
    return min(reads, key=lambda node: (node.lineno, node.col_offset), default=None)
