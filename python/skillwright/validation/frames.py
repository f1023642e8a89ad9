"""The robot's pose asked of tf the wrong way round (check ``frames``).

The skeleton's ``self._transform(target_frame, source_frame, timeout)`` gives the transform
that takes ``source_frame`` into ``target_frame``: ``self._transform("map", "base_link", 2.0)``
is where the robot stands in the map (tf2's ``lookup_transform(target, source, ...)``).
``self.out_position_x = self._transform("base_link", "map").transform.translation.x`` is the
map's origin seen from the robot, which is the robot's position only while it stands at the
origin facing along x, and its negative when it stands elsewhere facing that way.

An error stands at each statement that stores in an output (``self.out_...``) the translation
or rotation of a transform asked with the robot's base frame as the target and a world frame
(``map``, ``odom``, ``world``) as the source, read from the call itself or from a local the
method gave its result. The finding stands at the statement that asks tf; the fix swaps the
two frames there.
"""

from __future__ import annotations

import ast

from skillwright.rules.behaviour import TRANSFORM_REVERSED
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_attribute, self_method, with_node_replaced

__all__ = ["check_frames"]

_TRANSFORM = "_transform"
_BASE_FRAMES = frozenset({"base_link", "base_footprint", "base"})
_WORLD_FRAMES = frozenset({"map", "odom", "world"})
_PARTS = frozenset({"translation", "rotation"})


def check_frames(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``frames``) for the robot's pose asked of tf the wrong way round and
    stored in an output."""
    statement_of = facts.statement_of
    findings = []
    for method in facts.functions:
        reversed_locals = {
            target.id: node.value
            for node in facts.walk(method)
            if isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(target := node.targets[0], ast.Name)
            and isinstance(node.value, ast.Call)
            and _reversed(facts, node.value)
        }
        flagged: set[int] = set()
        for node in facts.walk(method):
            if not (isinstance(node, ast.Assign) and len(node.targets) == 1):
                continue
            output = self_attribute(node.targets[0])
            if output is None or not output.startswith("out_"):
                continue
            call = _pose_read(facts, node.value, reversed_locals)
            statement = None if call is None else statement_of.get(id(call))
            if call is None or statement is None or id(call) in flagged:
                continue
            flagged.add(id(call))
            target, source = (ast.literal_eval(a) for a in _frames(facts, call) if a is not None)
            findings.append(
                error_at(
                    TRANSFORM_REVERSED,
                    statement,
                    f"self.{_TRANSFORM}({target!r}, {source!r}, ...) is the transform "
                    f"from {source} into {target}: its translation is where {source}'s origin "
                    f"lies seen from the robot, not where the robot stands in {source} (read "
                    f"for self.{output}). Ask self.{_TRANSFORM}({source!r}, {target!r}, ...) "
                    f"for the robot's pose in {source}",
                    with_node_replaced(statement, call, lambda copy: _swapped(facts, copy)),
                )
            )
    return findings


def _reversed(facts: SkillFacts, call: ast.Call) -> bool:
    """Whether ``call`` is ``self._transform(<base frame>, <world frame>, ...)``."""
    if self_method(call) != _TRANSFORM:
        return False
    target, source = _frames(facts, call)
    return (
        isinstance(target, ast.Constant)
        and target.value in _BASE_FRAMES
        and isinstance(source, ast.Constant)
        and source.value in _WORLD_FRAMES
    )


def _pose_read(
    facts: SkillFacts, value: ast.expr, reversed_locals: dict[str, ast.Call]
) -> ast.Call | None:
    """The reversed call whose ``.transform.translation`` or ``.transform.rotation`` the
    expression ``value`` reads, if it reads one."""
    for node in ast.walk(value):
        if not (
            isinstance(node, ast.Attribute)
            and node.attr in _PARTS
            and isinstance(node.value, ast.Attribute)
            and node.value.attr == "transform"
        ):
            continue
        held = node.value.value
        if isinstance(held, ast.Call) and _reversed(facts, held):
            return held
        if isinstance(held, ast.Name) and held.id in reversed_locals:
            return reversed_locals[held.id]
    return None


def _frames(facts: SkillFacts, call: ast.Call) -> tuple[ast.expr | None, ast.expr | None]:
    """What ``call`` of ``_transform`` passes for its target and its source frame."""
    return (
        facts.helper_argument(call, "target_frame"),
        facts.helper_argument(call, "source_frame"),
    )


def _swapped(facts: SkillFacts, call: ast.expr) -> ast.expr:
    """``call`` (a copy) with the two frames it passes swapped."""
    if not isinstance(call, ast.Call):
        return call
    target, source = _frames(facts, call)
    if target is None or source is None:
        return call
    call.args = [source if a is target else target if a is source else a for a in call.args]
    for keyword in call.keywords:
        if keyword.value is target or keyword.value is source:
            keyword.value = source if keyword.value is target else target
    return call
