"""A position taken in a filtered copy of a list and used as if it were the original's
(check ``positions``).

``valid = [r for r in scan.ranges if math.isfinite(r)]`` and then
``index = valid.index(min(valid))``: the index counts the readings the filter kept, so once a
reading before the nearest one was dropped, ``scan.angle_min + index * scan.angle_increment``
is the bearing of another reading: a LaserScan's beam angle belongs to the index into its own
``ranges``, and a scanner that reports NaN or inf for beams without a return (REP 117) makes
every filtered index after them name the wrong beam.

A method is flagged when it calls ``.index(...)`` on a name bound to a list comprehension that
keeps elements of another sequence as they are (``[r for r in A if ...]``) and uses the
position for something other than indexing that copy. The filter's condition can only look at
the element's value (a plain loop over ``A``, no ``enumerate``), so a value the copy holds
first occurs in ``A`` at a position the filter kept: the fix asks ``A`` for the position,
when ``A`` can be read again unchanged (names and attributes, no calls).
"""

from __future__ import annotations

import ast
import copy

from skillwright.rules.behaviour import FILTERED_INDEX
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at

__all__ = ["check_filtered_positions"]


def check_filtered_positions(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``positions``) for positions in a filtered copy used as positions in
    what it was filtered from."""
    findings = []
    for method in facts.functions:
        copies = _filtered_copies(method)
        for call in facts.walk(method):
            name = _copy_asked(call, copies)
            if name is None or not isinstance(call, ast.Call):
                continue
            if not _used_beyond(method, call, name):
                continue
            statement = facts.statement_holding(call, method)
            if statement is not None:
                findings.append(_finding(statement, call, name, copies[name]))
    return findings


def _filtered_copies(method: ast.FunctionDef) -> dict[str, ast.expr]:
    """Names bound to ``[v for v in A if ...]`` (each at most once in the method), with
    ``A``."""
    bound: dict[str, list[ast.expr | None]] = {}
    for node in ast.walk(method):
        if isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                if isinstance(target, ast.Name):
                    bound.setdefault(target.id, []).append(_source_of(node.value))
        elif isinstance(node, ast.For | ast.With | ast.NamedExpr):
            for loop_name in _targets(node):
                bound.setdefault(loop_name, []).append(None)
    return {
        name: sources[0]
        for name, sources in bound.items()
        if len(sources) == 1 and sources[0] is not None
    }


def _targets(node: ast.For | ast.With | ast.NamedExpr) -> list[str]:
    if isinstance(node, ast.With):
        holders = [item.optional_vars for item in node.items if item.optional_vars is not None]
    else:
        holders = [node.target]
    return [n.id for holder in holders for n in ast.walk(holder) if isinstance(n, ast.Name)]


def _source_of(value: ast.expr | None) -> ast.expr | None:
    """``A`` when ``value`` is ``[v for v in A if ...]`` (a filter that keeps elements as they
    are, deciding by their value alone)."""
    if not isinstance(value, ast.ListComp) or len(value.generators) != 1:
        return None
    generator = value.generators[0]
    if not generator.ifs or generator.is_async:
        return None
    if not (isinstance(generator.target, ast.Name) and isinstance(value.elt, ast.Name)):
        return None
    if value.elt.id != generator.target.id:
        return None
    return generator.iter


def _copy_asked(node: ast.AST, copies: dict[str, ast.expr]) -> str | None:
    """The filtered copy ``node`` asks for a position (``valid.index(x)``), if it does."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
        return None
    receiver = node.func.value
    if node.func.attr != "index" or len(node.args) != 1 or node.keywords:
        return None
    return receiver.id if isinstance(receiver, ast.Name) and receiver.id in copies else None


def _used_beyond(method: ast.FunctionDef, call: ast.Call, name: str) -> bool:
    """Whether the position ``call`` gives is used other than to index the copy ``name``
    again (``valid[valid.index(x)]``, or through a variable assigned from it)."""
    holders: list[ast.expr] = [call]
    for node in ast.walk(method):
        if (
            isinstance(node, ast.Assign)
            and node.value is call
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
        ):
            variable = node.targets[0].id
            holders = [
                n
                for n in ast.walk(method)
                if isinstance(n, ast.Name) and n.id == variable and isinstance(n.ctx, ast.Load)
            ]
    inside_copy = {
        id(node.slice)
        for node in ast.walk(method)
        if isinstance(node, ast.Subscript)
        and isinstance(node.value, ast.Name)
        and node.value.id == name
    }
    return any(id(holder) not in inside_copy for holder in holders)


def _rereadable(source: ast.expr) -> bool:
    """Whether ``source`` can be evaluated again for the same list: names and attributes
    only (``scan.ranges``, ``self.scan_msg.ranges``)."""
    return all(isinstance(n, ast.Name | ast.Attribute | ast.Load) for n in ast.walk(source))


def _finding(statement: ast.stmt, call: ast.Call, name: str, source: ast.expr) -> Finding:
    original = ast.unparse(source)
    message = (
        f"`{ast.unparse(call)}` is a position in {name}, the elements the filter kept, not in "
        f"{original}: once the filter drops an element before it, whatever the position is "
        f"used for (a bearing from angle_min and angle_increment, another array of the "
        f"message) belongs to another element. Ask {original} for the position"
    )
    replacement = None
    if _rereadable(source):
        fixed = _with_call_replaced(statement, call, source)
        replacement = ast.unparse(fixed)
        message += (
            f"; the fix does: the filter keeps elements by their value, so the first equal "
            f"element of {original} is the same one"
        )
    return error_at(FILTERED_INDEX, statement, message, replacement)


def _with_call_replaced(statement: ast.stmt, call: ast.Call, source: ast.expr) -> ast.stmt:
    """A copy of ``statement`` in which ``call`` asks ``source`` for the position."""
    where = (call.lineno, call.col_offset, call.end_lineno, call.end_col_offset)

    class _Swap(ast.NodeTransformer):
        def visit_Call(self, node: ast.Call) -> ast.AST:
            self.generic_visit(node)
            at = (node.lineno, node.col_offset, node.end_lineno, node.end_col_offset)
            if at == where and isinstance(node.func, ast.Attribute):
                node.func = ast.Attribute(value=copy.deepcopy(source), attr="index", ctx=ast.Load())
            return node

    swapped = _Swap().visit(copy.deepcopy(statement))
    assert isinstance(swapped, ast.stmt)
    return ast.fix_missing_locations(swapped)
