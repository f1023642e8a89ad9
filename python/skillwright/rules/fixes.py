"""Putting rules' fixes into a skill's file (``skillwright check --fix``).

A finding's fix (``replacement``) is the statements that take the place of the statement
the finding stands at: the innermost statement that starts at the finding's place, or else
holds it (a made-up field of an expression is fixed by its whole statement). An empty
fix removes the statement (a block it leaves empty gets ``pass``). Of two fixes for one
statement, or for a statement and one inside it, only the first goes in; the caller checks
the file again and the other rule, if it still applies, offers its fix for the statement as
it now is. Safe fixes only, unless ``unsafe`` (see :data:`~skillwright.rules.finding.FixSafety`).
"""

from __future__ import annotations

import ast
import textwrap
from collections.abc import Sequence

from skillwright.rules.finding import Finding

__all__ = ["apply_fixes", "fixable"]


def fixable(finding: Finding, *, unsafe: bool) -> bool:
    """Whether ``finding`` has a fix that may go in (safe, or any with ``unsafe``)."""
    if finding.replacement is None or finding.fix_safety is None:
        return False
    return unsafe or finding.fix_safety == "safe"


def _statement_at(tree: ast.Module, line: int, column: int) -> ast.stmt | None:
    """The statement a finding at ``line``:``column`` (1-based; 0 for none) stands at."""
    starting: list[ast.stmt] = []
    holding: list[ast.stmt] = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.stmt):
            continue
        if node.lineno == line and (column == 0 or node.col_offset + 1 == column):
            starting.append(node)
        end = node.end_lineno or node.lineno
        if node.lineno <= line <= end and not isinstance(
            node, ast.FunctionDef | ast.ClassDef | ast.AsyncFunctionDef
        ):
            holding.append(node)
    if starting:
        return max(starting, key=lambda s: s.col_offset)
    if not holding:
        return None
    # the innermost: the one that starts last (and ends first)
    return max(holding, key=lambda s: (s.lineno, s.col_offset, -(s.end_lineno or s.lineno)))


def apply_fixes(
    source: str, findings: Sequence[Finding], *, unsafe: bool = False
) -> tuple[str, list[Finding]]:
    """``source`` with the fixes of ``findings`` that may go in, and those findings; the
    source as it was (and none) when nothing applies or the result would not parse."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return source, []
    lines = source.splitlines(keepends=True)
    spans: dict[tuple[int, int], tuple[str, Finding, int]] = {}
    for finding in findings:
        if not fixable(finding, unsafe=unsafe):
            continue
        statement = _statement_at(tree, finding.line, finding.column)
        if statement is None:
            continue
        first, last = statement.lineno, statement.end_lineno or statement.lineno
        text = lines[first - 1]
        # the statement must have its lines to itself (no `a = 1; b = 2`)
        if text[: statement.col_offset].strip() or any(
            first <= end and start <= last for start, end in spans
        ):
            continue
        spans[(first, last)] = (finding.replacement or "", finding, statement.col_offset)
    applied: list[Finding] = []
    for first, last in sorted(spans, reverse=True):
        replacement, finding, indent = spans[(first, last)]
        body = textwrap.indent(replacement, " " * indent) + "\n" if replacement else ""
        if not body and _alone_in_block(tree, first, last):
            body = " " * indent + "pass\n"
        lines[first - 1 : last] = [body]
        applied.append(finding)
    fixed = "".join(lines)
    try:
        ast.parse(fixed)
    except SyntaxError:
        return source, []
    return (fixed, applied[::-1]) if fixed != source else (source, [])


def _alone_in_block(tree: ast.Module, first: int, last: int) -> bool:
    """Whether the statement on lines ``first``..``last`` is the only one of its block."""
    for node in ast.walk(tree):
        for name in ("body", "orelse", "finalbody"):
            block = getattr(node, name, None)
            if not isinstance(block, list) or not block:
                continue
            statements = [s for s in block if isinstance(s, ast.stmt)]
            if len(statements) == 1 and statements[0].lineno == first:
                return (statements[0].end_lineno or first) == last
    return False
