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
from dataclasses import dataclass

from skillwright.interfaces.inventory import Interface
from skillwright.retrieval.semantics import split_view
from skillwright.rules.behaviour import SCANNER_UNREAD
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import self_attribute

__all__ = ["check_views"]


@dataclass(frozen=True)
class _Subscription:
    """A subscription of the class to a message topic, the method it hands the messages to
    and the attributes that method keeps them in."""

    interface: Interface
    callback: str
    kept: frozenset[str]


def check_views(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``views``) for the parts of a split view a skill subscribes to and
    never reads while it reads another part."""
    subscriptions = _subscriptions(facts)
    if len(subscriptions) < 2:
        return []
    reads = {s.interface.name: _first_read(facts, s) for s in subscriptions}
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
        fix = _fix(facts, where, kept)
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


def _fix(facts: SkillFacts, read: ast.Attribute, kept: str) -> tuple[str, str] | None:
    """Where ``read`` is the one argument of the skeleton's ``self._closest_reading(...)`` in
    a statement of its own: the call with ``self.<kept>`` added, and the statement with that
    call, after the wait for its first message."""
    if _CLOSEST not in facts.methods or facts.skill is None:
        return None
    statement_of = facts.statement_of
    for call in facts.walk(facts.skill):
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


def _subscriptions(facts: SkillFacts) -> list[_Subscription]:
    """The class's subscriptions to a topic of a message type it imports, named by a literal,
    whose messages go to a method of the class."""
    return [
        _Subscription(
            Interface(name=made.name, kind="topic", type_name=made.type_name),
            made.callback,
            facts.kept_messages(made.callback),
        )
        for made in facts.made
        if made.maker == "create_subscription"
        and made.name is not None
        and made.type_name is not None
        and "/msg/" in made.type_name
        and made.callback is not None
        and made.callback in facts.methods
    ]


def _first_read(facts: SkillFacts, subscription: _Subscription) -> ast.Attribute | None:
    """The first place (by line and column; ``ast.walk`` goes breadth first) a method other
    than the callback reads a kept attribute other than to test it against ``None``."""
    reads = []
    for name, method in facts.methods.items():
        if name == subscription.callback:
            continue
        tested = {
            id(side)
            for node in facts.walk(method)
            if isinstance(node, ast.Compare)
            and all(isinstance(op, ast.Is | ast.IsNot) for op in node.ops)
            for side in (node.left, *node.comparators)
        }
        reads += [
            node
            for node in facts.walk(method)
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and self_attribute(node) in subscription.kept
            and id(node) not in tested
        ]
    return min(reads, key=lambda node: (node.lineno, node.col_offset), default=None)
