"""Loops whose condition nothing in them changes (check ``stale``).

``last_angle = self._yaw()`` before ``while abs(last_angle - target) > 0.05:`` and no new
reading inside the loop: the condition is decided once, so the loop turns the robot until its
timeout raises, every time, and a run can only say that the state gave up.

A loop is flagged when its condition reads local names (and nothing a callback or another
method may change), calls nothing but pure arithmetic, and its body assigns none of those
names and has no ``break`` or ``return``: it can only end by raising. A name that is used as
an object anywhere in the method (``msgs.append`` handed to a subscription, ``queue[0]``) may
change without an assignment, and is left alone.

When each such name was last assigned, before the loop, by an expression that calls a method
of the skill (a reading: ``self._yaw()``, ``self._transform(...)``), the fix repeats that
assignment at the end of the loop's body, so the condition sees a fresh reading after each
pass; otherwise the model is told which name to read again.
"""

from __future__ import annotations

import ast
import copy

from skillwright.rules.behaviour import STALE_LOOP, STALE_READING
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import blocks, error_at, skips_its_end

__all__ = ["check_stale_conditions"]

_PURE = frozenset(
    {"abs", "min", "max", "float", "int", "round", "len", "bool"}
    | {f"math.{f}" for f in ("fabs", "sqrt", "hypot", "atan2", "degrees", "radians", "cos")}
    | {f"math.{f}" for f in ("sin", "tan", "isclose", "copysign", "fmod", "remainder")}
)
"""Calls a condition may make and still be decided by its names alone."""
_MODULES = frozenset({"math", "time", "abs", "min", "max", "float", "int", "round", "len", "bool"})


def check_stale_conditions(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``stale``) for loops whose condition cannot change while they run."""
    findings = []
    for method in facts.functions:
        for loop in facts.walk(method):
            if isinstance(loop, ast.While):
                finding = _stale(facts, method, loop) or _stale_exit(facts, method, loop)
                if finding is not None:
                    findings.append(finding)
    return findings


def _stale_exit(facts: SkillFacts, method: ast.FunctionDef, loop: ast.While) -> Finding | None:
    """``while True:`` whose ``if TEST: break`` decides on names nothing in the loop reads
    again: TEST's own names, through the values the loop works out from others before it
    (``remaining = (target - current) % (2 * math.pi)`` from ``current`` read once before
    the loop). The fix reads again, first thing
    in each pass, the names last read from the skill before the loop."""
    if not (isinstance(loop.test, ast.Constant) and loop.test.value is True):
        return None
    for index, statement in enumerate(loop.body):
        if not (
            isinstance(statement, ast.If)
            and not statement.orelse
            and any(isinstance(s, ast.Break | ast.Return) for s in statement.body)
        ):
            continue
        worked_out = {
            s.targets[0].id: s
            for s in loop.body[:index]
            if isinstance(s, ast.Assign)
            and len(s.targets) == 1
            and isinstance(s.targets[0], ast.Name)
        }
        roots = _roots(statement.test, worked_out)
        if roots is None:
            continue
        names, attributes = roots
        if not names or names & _assigned(loop.body) or names & _used_as_objects(method):
            continue
        if attributes & _set_meanwhile(facts, loop):
            continue
        ordered = sorted(names)
        readings = [r for name in ordered if (r := _reading_before(method, loop, name))]
        message = (
            f"the test that leaves this loop, `{ast.unparse(statement.test)}`, comes from "
            f"{', '.join(ordered)}, which nothing in the loop changes: every pass tests the "
            "same values, so the loop ends only by raising (its timeout). Read them again "
            "inside the loop"
        )
        replacement = None
        if readings:
            fixed = copy.deepcopy(loop)
            fixed.body = [*(copy.deepcopy(r) for r in readings), *fixed.body]
            replacement = ast.unparse(ast.fix_missing_locations(fixed))
            message += (
                "; the fix repeats "
                + ", ".join(f"`{ast.unparse(r)}`" for r in readings)
                + " at the start of each pass"
            )
        return error_at(STALE_LOOP, loop, message, replacement)
    return None


def _roots(test: ast.expr, worked_out: dict[str, ast.Assign]) -> tuple[set[str], set[str]] | None:
    """The local names and skill attributes ``test`` decides on once the values the loop
    works out before it (``worked_out``) are followed back; None when it reads anything
    else."""
    names, attributes = _condition_names(test)
    if not names and not attributes:
        return None
    roots: set[str] = set()
    pending = list(names)
    seen: set[str] = set()
    while pending:
        name = pending.pop()
        if name in seen:
            continue
        seen.add(name)
        assignment = worked_out.get(name)
        if assignment is None:
            roots.add(name)
            continue
        more, more_attributes = _condition_names(assignment.value)
        if not more and not more_attributes and not _constant(assignment.value):
            return None
        pending.extend(more)
        attributes |= more_attributes
    return roots, attributes


def _constant(value: ast.expr) -> bool:
    """Whether ``value`` is worked out from literals alone."""
    return not any(isinstance(n, ast.Name | ast.Attribute | ast.Call) for n in ast.walk(value))


def _stale(facts: SkillFacts, method: ast.FunctionDef, loop: ast.While) -> Finding | None:
    names, attributes = _condition_names(loop.test)
    if not names or _ends_otherwise(loop) or names & _assigned(loop.body):
        return None
    if names & _used_as_objects(method) or attributes & _set_meanwhile(facts, loop):
        return None
    ordered = sorted(names)
    readings = [_reading_before(method, loop, name) for name in ordered]
    condition = ast.unparse(loop.test)
    which = ", ".join(ordered)
    message = (
        f"the condition of this loop, `{condition}`, reads {which}, which nothing in the loop "
        "changes: it is decided before the first pass, so the loop ends only by raising (its "
        f"timeout). Read {which} again inside the loop, after each wait"
    )
    replacement = None
    if all(r is not None for r in readings) and not skips_its_end(loop):
        fixed = copy.deepcopy(loop)
        fixed.body = [*fixed.body, *(copy.deepcopy(r) for r in readings if r is not None)]
        replacement = ast.unparse(ast.fix_missing_locations(fixed))
        message += (
            "; the fix repeats "
            + ", ".join(f"`{ast.unparse(r)}`" for r in readings if r is not None)
            + " at the end of the loop"
        )
    return error_at(STALE_READING, loop, message, replacement)


def _condition_names(test: ast.expr) -> tuple[set[str], set[str]]:
    """The local names and the skill's attributes ``test`` decides on; nothing when it
    reads anything else (another object's attribute, a call that is not arithmetic) or
    nothing at all (``while True``)."""
    names: set[str] = set()
    attributes: set[str] = set()
    for node in ast.walk(test):
        if isinstance(node, ast.Call):
            if ast.unparse(node.func) not in _PURE:
                return set(), set()
        elif isinstance(node, ast.Attribute):
            if isinstance(node.value, ast.Name) and node.value.id == "self":
                attributes.add(node.attr)
            elif not (isinstance(node.value, ast.Name) and node.value.id == "math"):
                return set(), set()
        elif isinstance(node, ast.Subscript | ast.Await | ast.NamedExpr):
            return set(), set()
        elif isinstance(node, ast.Name) and node.id not in _MODULES and node.id != "self":
            names.add(node.id)
    return names, attributes


def _set_meanwhile(facts: SkillFacts, loop: ast.While) -> set[str]:
    """Attributes of the skill that may change while ``loop`` runs: set by a callback, by
    the loop, or by a method the loop calls (directly or through another)."""
    methods = facts.methods
    out = set(facts.callback_stores)
    pending: list[ast.AST] = [loop]
    seen: set[str] = set()
    while pending:
        root = pending.pop()
        for node in facts.walk(root):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id == "self"
            ):
                if isinstance(node.ctx, ast.Store | ast.Del):
                    out.add(node.attr)
                elif node.attr in methods and node.attr not in seen:
                    seen.add(node.attr)
                    pending.append(methods[node.attr])
    return out


def _ends_otherwise(loop: ast.While) -> bool:
    """Whether a ``break`` of this loop or a ``return`` may end it without raising."""
    pending: list[ast.AST] = [*loop.body, *loop.orelse]
    while pending:
        node = pending.pop()
        if isinstance(node, ast.Return | ast.Yield | ast.YieldFrom):
            return True
        if isinstance(node, ast.Break):
            return True
        if isinstance(node, ast.FunctionDef | ast.Lambda | ast.ClassDef):
            continue
        if isinstance(node, ast.While | ast.For):
            # their own breaks end them, not this loop; a return still ends this one
            pending.extend(n for n in ast.walk(node) if isinstance(n, ast.Return))
            continue
        pending.extend(ast.iter_child_nodes(node))
    return False


def _assigned(body: list[ast.stmt]) -> set[str]:
    names: set[str] = set()
    for statement in body:
        for node in ast.walk(statement):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store | ast.Del):
                names.add(node.id)
            elif isinstance(node, ast.Global | ast.Nonlocal):
                names.update(node.names)
    return names


def _used_as_objects(method: ast.FunctionDef) -> set[str]:
    """Names of ``method`` something may change without assigning them: the base of an
    attribute or subscript, or an argument of a call that is not arithmetic."""
    out: set[str] = set()
    for node in ast.walk(method):
        if isinstance(node, ast.Attribute | ast.Subscript) and isinstance(node.value, ast.Name):
            out.add(node.value.id)
        elif isinstance(node, ast.Call) and ast.unparse(node.func) not in _PURE:
            arguments = [*node.args, *(k.value for k in node.keywords)]
            out.update(a.id for a in arguments if isinstance(a, ast.Name))
    return out


def _reading_before(method: ast.FunctionDef, loop: ast.While, name: str) -> ast.Assign | None:
    """The last plain ``name = ...`` before ``loop`` in the block that holds it, when its
    value calls a method of the skill (a reading of the robot's state)."""
    block = _block_of(method, loop)
    if block is None:
        return None
    found: ast.Assign | None = None
    for statement in block[: block.index(loop)]:
        if isinstance(statement, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == name for t in statement.targets
        ):
            single = len(statement.targets) == 1 and _reads_the_skill(statement.value)
            found = statement if single else None
        elif name in _assigned([statement]):
            found = None
    return found


def _reads_the_skill(value: ast.expr) -> bool:
    return any(
        isinstance(n, ast.Call)
        and isinstance(n.func, ast.Attribute)
        and isinstance(n.func.value, ast.Name)
        and n.func.value.id == "self"
        for n in ast.walk(value)
    )


def _block_of(root: ast.AST, statement: ast.stmt) -> list[ast.stmt] | None:
    return next((b for b in blocks(root) if any(s is statement for s in b)), None)
