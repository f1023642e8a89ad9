"""Small questions about a skill's syntax tree that several checks ask."""

from __future__ import annotations

import ast
import copy
from collections.abc import Callable

from skillwright.rules.finding import Finding
from skillwright.rules.registry import Rule

__all__ = [
    "COMPOUND_STATEMENTS",
    "blocks",
    "called_name",
    "error_at",
    "keyword_argument",
    "self_attribute",
    "self_method",
    "skips_its_end",
    "statement_holding",
    "string_value",
    "with_node_replaced",
    "with_text_in_place",
    "written_type",
]

COMPOUND_STATEMENTS = (
    ast.If,
    ast.For,
    ast.While,
    ast.With,
    ast.Try,
    ast.FunctionDef,
    ast.ClassDef,
    ast.Match,
)
"""Statements that hold other statements."""


def error_at(
    rule: Rule,
    statement: ast.stmt,
    message: str,
    replacement: str | None = None,
    *,
    data: dict[str, object] | None = None,
) -> Finding:
    """A finding of ``rule`` at ``statement``, with the statements to put in its place when
    the rule knows them (its fix)."""
    return rule.finding(
        line=statement.lineno,
        column=statement.col_offset + 1,
        message=message,
        data=data,
        replacement=replacement,
    )


def blocks(root: ast.AST) -> list[list[ast.stmt]]:
    """Every statement list under ``root``: bodies, ``else`` and ``finally`` blocks, handlers'
    bodies."""
    out = []
    for node in ast.walk(root):
        for field in ("body", "orelse", "finalbody"):
            block = getattr(node, field, None)
            if isinstance(block, list) and block and isinstance(block[0], ast.stmt):
                out.append(block)
    return out


def statement_holding(root: ast.AST, node: ast.AST) -> ast.stmt | None:
    """The innermost statement under ``root`` (not a definition) that holds ``node``."""
    # ast.walk goes breadth first: the innermost holder comes last.
    holding = [
        s
        for s in ast.walk(root)
        if isinstance(s, ast.stmt)
        and not isinstance(s, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)
        and any(n is node for n in ast.walk(s))
    ]
    return holding[-1] if holding else None


def skips_its_end(loop: ast.While | ast.For) -> bool:
    """Whether a ``continue`` of ``loop`` (not of a loop inside it) may skip the end of its
    body, where a check would add a statement."""
    pending: list[ast.AST] = [*loop.body, *loop.orelse]
    while pending:
        node = pending.pop()
        if isinstance(node, ast.Continue):
            return True
        if not isinstance(node, ast.While | ast.For | ast.FunctionDef | ast.Lambda):
            pending.extend(ast.iter_child_nodes(node))
    return False


def self_attribute(node: ast.AST) -> str | None:
    """``x`` for the expression ``self.x``, else ``None``."""
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
        return node.attr if node.value.id == "self" else None
    return None


def keyword_argument(call: ast.Call, name: str) -> ast.expr | None:
    """What ``call`` passes by the keyword ``name``."""
    return next((k.value for k in call.keywords if k.arg == name), None)


def string_value(node: ast.expr | None) -> str | None:
    """The text of a string literal."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return None


def written_type(node: ast.expr | None) -> str | None:
    """``Twist`` for ``Twist`` and ``geometry_msgs.msg.Twist``; ``NavigateToPose.Goal`` for
    ``NavigateToPose.Goal`` (a type and its part, as the skill writes them)."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        if node.attr in {"Goal", "Request"}:
            owner = written_type(node.value)
            return f"{owner}.{node.attr}" if owner is not None else None
        return node.attr
    return None


def called_name(call: ast.Call) -> str:
    """The name ``call`` calls: ``publish`` for ``self.pub.publish(...)``, ``min`` for
    ``min(...)``; empty for anything else (``f()(...)``)."""
    func = call.func
    if isinstance(func, ast.Attribute):
        return func.attr
    if isinstance(func, ast.Name):
        return func.id
    return ""


def self_method(call: ast.Call) -> str | None:
    """The method's name when ``call`` calls a method of the skill (``self.name(...)``)."""
    func = call.func
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        return func.attr if func.value.id == "self" else None
    return None


def with_node_replaced(
    statement: ast.stmt, node: ast.expr, new: Callable[[ast.expr], ast.expr]
) -> str:
    """The text of ``statement`` with ``node`` (an expression in it) replaced by what ``new``
    makes of a copy of it."""
    where = (node.lineno, node.col_offset, node.end_lineno, node.end_col_offset)

    class _Replace(ast.NodeTransformer):
        def visit(self, part: ast.AST) -> ast.AST:
            if (
                isinstance(part, ast.expr)
                and (
                    part.lineno,
                    part.col_offset,
                    part.end_lineno,
                    part.end_col_offset,
                )
                == where
                and type(part) is type(node)
            ):
                return new(part)
            return self.generic_visit(part)

    return ast.unparse(_Replace().visit(copy.deepcopy(statement)))


def with_text_in_place(statement: ast.stmt, node: ast.expr, text: str) -> str:
    """The text of ``statement`` with the expression ``text`` in the place of ``node``."""
    expression = ast.parse(text, mode="eval").body
    return with_node_replaced(statement, node, lambda _: expression)
