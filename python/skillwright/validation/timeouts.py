"""Where a wait that gave up takes its seconds from, and the skill with other seconds.

A run finds a state that raised "... within 5 s". Whether 5 s was too short for the motion
or the motion never comes to an end is a question a second run answers, if the number can be
found and changed: this module finds it. It follows the wait back from the statement that
raised, through the names it reads, to numbers in the code:

- the guard of the ``raise``: ``if time.monotonic() > deadline:`` reads ``deadline``, whose
  assignment ``deadline = time.monotonic() + 5.0`` holds the number; or the guard holds it
  itself (``if time.monotonic() - start > 5.0:``);
- a name that is a parameter of the function (the skeleton's ``_wait_until(condition,
  timeout, what)``) leads to the argument of the call one frame out
  (``self._wait_until(lambda: ..., 5.0, "odometry")``), and so on out to the state;
- failing all that, the one number of that value in the functions of the call stack.

Only numbers equal to the seconds the message names count. The text of the ``raise`` that
names them ("within 5 s") changes with them. :func:`with_seconds` gives the whole file with
other seconds (to run it), :func:`fixes` the statements that change, for the repair loop.
"""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from skillwright.validation.syntax import statement_holding

__all__ = [
    "TimeoutSite",
    "bound_arguments",
    "call_of",
    "fixes",
    "function_at",
    "functions_of",
    "rounded_up",
    "timeout_site",
    "with_seconds",
]

_UNITS = r"(?=\s?(?:s|sec|secs|second|seconds)\b)"


@dataclass(frozen=True)
class TimeoutSite:
    """The numbers a wait takes its seconds from, and the ``raise`` that names them."""

    seconds: float
    numbers: tuple[tuple[int, int, int], ...]
    """(line, start, end) of each number: 1-based line, byte offsets in that line."""
    raise_line: int | None
    """The first line of the ``raise`` whose text names the seconds, if it does."""
    raise_end: int | None


def timeout_site(code: str, line: int, stack: Sequence[int], seconds: float) -> TimeoutSite | None:
    """Where the wait that raised at ``line`` (``stack``: the lines of the calls that led
    there, outermost first) takes its ``seconds`` from; ``None`` when no number is found."""
    functions = functions_of(code)
    if functions is None:
        return None
    inner = function_at(functions, line)
    if inner is None:
        return None
    statement = _deepest_statement(inner, line)
    if statement is None:
        return None
    guard = _guard_of(inner, statement)
    numbers, parameters = _traced(inner, [guard.test if guard else statement], line, seconds)
    function = inner
    for outer in reversed(stack):
        if not parameters:
            break
        caller = function_at(functions, outer)
        call = call_of(caller, function.name, outer) if caller is not None else None
        if caller is None or call is None:
            break
        arguments, defaults = bound_arguments(function, call, parameters)
        numbers += [d for d in defaults if isinstance(d, ast.Constant) and _equal(d, seconds)]
        found, parameters = _traced(caller, arguments, outer, seconds)
        numbers += found
        function = caller
    if not numbers:
        framed = [f for f in (function_at(functions, n) for n in (*stack, line)) if f]
        anywhere = {id(n): n for f in framed for n in _numbers(f.body, seconds)}
        numbers = list(anywhere.values()) if len(anywhere) == 1 else []
    spans = sorted({(n.lineno, n.col_offset, n.end_col_offset or n.col_offset) for n in numbers})
    if not spans or any(n.lineno != n.end_lineno for n in numbers):
        return None
    named = isinstance(statement, ast.Raise) and _names_seconds(code, statement, seconds)
    return TimeoutSite(
        seconds=seconds,
        numbers=tuple(spans),
        raise_line=statement.lineno if named else None,
        raise_end=(statement.end_lineno or statement.lineno) if named else None,
    )


def with_seconds(code: str, site: TimeoutSite, seconds: float) -> str:
    """``code`` with ``seconds`` where the site's numbers are and in the ``raise``'s text."""
    lines = code.splitlines(keepends=True)
    for number_line, start, end in sorted(site.numbers, reverse=True):
        raw = lines[number_line - 1].encode("utf-8")
        old = raw[start:end].decode("utf-8")
        lines[number_line - 1] = (
            raw[:start].decode("utf-8") + _number_text(old, seconds) + raw[end:].decode("utf-8")
        )
    if site.raise_line is not None and site.raise_end is not None:
        said = _said(site.seconds)
        for index in range(site.raise_line - 1, site.raise_end):
            lines[index] = said.sub(f"{seconds:g}", lines[index])
    return "".join(lines)


def fixes(code: str, site: TimeoutSite, seconds: float) -> list[tuple[int, int, str]]:
    """The statements of ``code`` that change when the wait allows ``seconds``: (line,
    1-based column, the statement's new text without its indentation), outermost ones only
    (a changed ``if`` holds its changed ``raise``)."""
    tree = ast.parse(code)
    holders: dict[tuple[int, int], ast.stmt] = {}
    for number_line, start, _ in site.numbers:
        node = _node_at(tree, number_line, start)
        holder = statement_holding(tree, node) if node is not None else None
        if holder is not None:
            holders[(holder.lineno, holder.col_offset)] = holder
    if site.raise_line is not None:
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.lineno == site.raise_line:
                holders[(node.lineno, node.col_offset)] = node
    kept = [s for s in holders.values() if not any(_within(s, o) for o in holders.values())]
    text = with_seconds(code, site, seconds).splitlines()
    out = []
    for statement in sorted(kept, key=lambda s: (s.lineno, s.col_offset)):
        first, last = statement.lineno, statement.end_lineno or statement.lineno
        indent = text[first - 1][: len(text[first - 1]) - len(text[first - 1].lstrip())]
        body = [t[len(indent) :] if t.startswith(indent) else t for t in text[first - 1 : last]]
        out.append((first, statement.col_offset + 1, "\n".join(body)))
    return out


def rounded_up(seconds: float) -> float:
    """``seconds`` rounded up to a number an engineer would write: whole seconds up to 10,
    then fives up to 60, then tens."""
    step = 1.0 if seconds <= 10 else 5.0 if seconds <= 60 else 10.0
    return float(math.ceil(seconds / step - 1e-9) * step)


def _number_text(old: str, seconds: float) -> str:
    if seconds.is_integer() and not any(c in old for c in ".eE"):
        return str(int(seconds))
    return repr(float(seconds))


def functions_of(code: str) -> list[ast.FunctionDef] | None:
    """Every function definition in ``code``; ``None`` when it does not parse."""
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    return [n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)]


def function_at(functions: Sequence[ast.FunctionDef], line: int) -> ast.FunctionDef | None:
    holding = [f for f in functions if f.lineno <= line <= (f.end_lineno or f.lineno)]
    return max(holding, key=lambda f: f.lineno) if holding else None


def _deepest_statement(function: ast.FunctionDef, line: int) -> ast.stmt | None:
    holding = [
        s
        for s in ast.walk(function)
        if isinstance(s, ast.stmt)
        and s is not function
        and s.lineno <= line <= (s.end_lineno or s.lineno)
    ]
    return max(holding, key=lambda s: (s.lineno, -(s.end_lineno or s.lineno))) if holding else None


def _guard_of(function: ast.FunctionDef, statement: ast.stmt) -> ast.If | None:
    """The ``if`` whose body holds ``statement`` directly or a few blocks down."""
    guards = [
        node
        for node in ast.walk(function)
        if isinstance(node, ast.If) and any(s is statement for b in node.body for s in ast.walk(b))
    ]
    return (
        max(guards, key=lambda g: g.lineno) if guards and isinstance(statement, ast.Raise) else None
    )


def _equal(node: ast.expr, seconds: float) -> bool:
    return (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int | float)
        and not isinstance(node.value, bool)
        and math.isclose(float(node.value), seconds, rel_tol=1e-9, abs_tol=1e-12)
    )


def _numbers(nodes: Iterable[ast.AST], seconds: float) -> list[ast.Constant]:
    return [
        n
        for root in nodes
        for n in ast.walk(root)
        if isinstance(n, ast.Constant) and _equal(n, seconds)
    ]


def _read(node: ast.AST) -> set[str]:
    """Names and ``self`` attributes ``node`` reads, outside lambdas."""
    out: set[str] = set()
    pending = [node]
    while pending:
        current = pending.pop()
        if isinstance(current, ast.Lambda):
            continue
        name = _traced_name(current)
        if name is not None and isinstance(getattr(current, "ctx", None), ast.Load):
            out.add(name)
        if name is None or isinstance(current, ast.Name):
            pending.extend(ast.iter_child_nodes(current))
    return out


def _traced_name(node: ast.AST) -> str | None:
    """``x`` for a local name, ``self.x`` for an attribute of the skill, else ``None``."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
        return f"self.{node.attr}" if node.value.id == "self" else None
    return None


def _target_names(statement: ast.stmt) -> set[str]:
    targets: list[ast.expr] = []
    if isinstance(statement, ast.Assign):
        targets = list(statement.targets)
    elif isinstance(statement, ast.AnnAssign | ast.AugAssign):
        targets = [statement.target]
    return {n for n in map(_traced_name, targets) if n is not None}


def _traced(
    function: ast.FunctionDef, roots: Sequence[ast.AST], before: int, seconds: float
) -> tuple[list[ast.Constant], set[str]]:
    """Numbers equal to ``seconds`` in ``roots`` (outside lambdas) and in the assignments
    before line ``before`` of the names they read, followed through ``function``; and the
    parameters of ``function`` among those names."""
    found = [n for root in roots for n in _numbers_outside_lambdas(root, seconds)]
    wanted = set().union(*(_read(root) for root in roots)) if roots else set()
    seen: set[str] = set()
    assignments = [
        s
        for s in ast.walk(function)
        if isinstance(s, ast.Assign | ast.AnnAssign | ast.AugAssign) and s.lineno < before
    ]
    while wanted - seen:
        name = (wanted - seen).pop()
        seen.add(name)
        for assignment in assignments:
            if name in _target_names(assignment) and assignment.value is not None:
                found += _numbers_outside_lambdas(assignment.value, seconds)
                wanted |= _read(assignment.value)
    parameters = {a.arg for a in (*function.args.args, *function.args.kwonlyargs)} - {"self"}
    return found, seen & parameters


def _numbers_outside_lambdas(root: ast.AST, seconds: float) -> list[ast.Constant]:
    out: list[ast.Constant] = []
    pending = [root]
    while pending:
        node = pending.pop()
        if isinstance(node, ast.Lambda):
            continue
        if isinstance(node, ast.Constant) and _equal(node, seconds):
            out.append(node)
        pending.extend(ast.iter_child_nodes(node))
    return out


def call_of(function: ast.FunctionDef, name: str, line: int) -> ast.Call | None:
    """The call of ``name`` (``self.name(...)`` or ``name(...)``) spanning ``line``."""
    for node in ast.walk(function):
        if not isinstance(node, ast.Call) or not node.lineno <= line <= (node.end_lineno or 0):
            continue
        callee = node.func
        if (isinstance(callee, ast.Attribute) and callee.attr == name) or (
            isinstance(callee, ast.Name) and callee.id == name
        ):
            return node
    return None


def bound_arguments(
    function: ast.FunctionDef, call: ast.Call, parameters: set[str]
) -> tuple[list[ast.expr], list[ast.expr]]:
    """The arguments ``call`` passes for ``parameters`` of ``function``, and the defaults of
    those it leaves out."""
    positional = [a.arg for a in function.args.args]
    if positional and positional[0] == "self":
        positional = positional[1:]
    given: dict[str, ast.expr] = dict(zip(positional, call.args, strict=False))
    given.update({k.arg: k.value for k in call.keywords if k.arg is not None})
    defaults = dict(
        zip(
            positional[len(positional) - len(function.args.defaults) :],
            function.args.defaults,
            strict=True,
        )
    )
    for argument, default in zip(function.args.kwonlyargs, function.args.kw_defaults, strict=True):
        if default is not None:
            defaults[argument.arg] = default
    arguments = [given[p] for p in parameters if p in given]
    left_out = [defaults[p] for p in parameters if p not in given and p in defaults]
    return arguments, left_out


def _said(seconds: float) -> re.Pattern[str]:
    """The seconds as a text says them: "5 s", "5.0 seconds", not "15 s" or "0.5 s"."""
    return re.compile(rf"(?<![\w.]){re.escape(f'{seconds:g}')}(?:\.0+)?{_UNITS}")


def _names_seconds(code: str, statement: ast.Raise, seconds: float) -> bool:
    return _said(seconds).search(ast.get_source_segment(code, statement) or "") is not None


def _node_at(tree: ast.AST, line: int, column: int) -> ast.AST | None:
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and node.lineno == line and node.col_offset == column:
            return node
    return None


def _within(inner: ast.stmt, outer: ast.stmt) -> bool:
    return inner is not outer and any(n is inner for n in ast.walk(outer))
