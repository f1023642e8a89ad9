"""Putting a model's behaviour into the skeleton, so structure stays right by construction.

The skeleton owns everything that follows from the inputs: the ``@skill`` decorator and its
IRIs, the class name, the parameter and output getters, the class constants and the
interface handles. The model owns behaviour. From the model's file this takes:

- the body of each state method the specification lists (under the skeleton's decorator,
  signature and docstring); a skeleton statement that creates or releases a handle the
  model's body never mentions is kept in front of it, so no handle is lost;
- helper methods and class constants the skeleton does not have, and the model's versions
  of the skeleton's subscription callbacks;
- attributes the model's ``__init__`` adds, and imports and module-level helpers it adds.

Everything else the model wrote (changed IRIs, renamed getters, states the specification
does not list) is left out and reported. When the model's file does not parse, there is
nothing to merge: :func:`merge_into_skeleton` returns ``None`` and the caller keeps the
model's text as it is, for the checks to report.
"""

from __future__ import annotations

import ast
from collections.abc import Sequence
from dataclasses import dataclass

from skillwright.generation.skeleton import SKELETON_NOTE
from skillwright.spec.model import PACKML_STATES

__all__ = ["Merged", "merge_into_skeleton"]

_ANNOTATIONS = {"skill_parameter", "skill_output"}


@dataclass(frozen=True)
class Merged:
    """The merged file and what went into it."""

    code: str
    written: tuple[str, ...]
    """States whose behaviour the model wrote."""
    missing: tuple[str, ...]
    """States the model did not write (the skeleton's placeholder stays)."""
    added: tuple[str, ...]
    """Other things taken from the model: helpers, attributes, imports."""
    left_out: tuple[str, ...]
    """What the model wrote that was not taken, and why."""


def _decorator_names(node: ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef) -> set[str]:
    names = set()
    for decorator in node.decorator_list:
        target = decorator.func if isinstance(decorator, ast.Call) else decorator
        if isinstance(target, ast.Name):
            names.add(target.id)
        elif isinstance(target, ast.Attribute):
            names.add(target.attr)
    return names


def _start(node: ast.stmt) -> int:
    decorators: list[ast.expr] = getattr(node, "decorator_list", [])
    return min([node.lineno, *(d.lineno for d in decorators)])


def _end(node: ast.stmt) -> int:
    return node.end_lineno or node.lineno


def _reindent(lines: Sequence[str], old: int, new: int) -> list[str]:
    """Moves lines from indentation ``old`` to ``new``; lines indented less (continuation
    lines of strings) keep their text with only the common part moved."""
    out = []
    for line in lines:
        if not line.strip():
            out.append("")
            continue
        width = len(line) - len(line.lstrip(" "))
        cut = min(width, old)
        out.append(" " * new + line[cut:])
    return out


def _self_attributes(node: ast.AST, *, assigned_only: bool) -> set[str]:
    found = set()
    for child in ast.walk(node):
        if isinstance(child, ast.Assign | ast.AnnAssign | ast.AugAssign):
            targets = child.targets if isinstance(child, ast.Assign) else [child.target]
            candidates: list[ast.AST] = [t for target in targets for t in ast.walk(target)]
        elif assigned_only:
            continue
        else:
            candidates = [child]
        for candidate in candidates:
            if (
                isinstance(candidate, ast.Attribute)
                and isinstance(candidate.value, ast.Name)
                and candidate.value.id == "self"
            ):
                found.add(candidate.attr)
    return found


def _body_without_docstring(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.stmt]:
    body = list(function.body)
    if (
        body
        and isinstance(body[0], ast.Expr)
        and isinstance(body[0].value, ast.Constant)
        and isinstance(body[0].value.value, str)
    ):
        body = body[1:]
    return body


def _is_placeholder(statement: ast.stmt) -> bool:
    if isinstance(statement, ast.Raise) and statement.exc is not None:
        target = statement.exc.func if isinstance(statement.exc, ast.Call) else statement.exc
        return isinstance(target, ast.Name) and target.id == "NotImplementedError"
    return isinstance(statement, ast.Pass) or (
        isinstance(statement, ast.Expr)
        and isinstance(statement.value, ast.Constant)
        and statement.value.value is Ellipsis
    )


def _authorship(author: str, missing: Sequence[str]) -> str:
    lines = [
        "Structure, annotations and interface handles: skillwright's skeleton.",
        f"Behaviour: written by {author}; review it before it runs on hardware.",
    ]
    if missing:
        lines.append(f"Still to be written (raise NotImplementedError): {', '.join(missing)}.")
    return "\n".join(lines)


class _Source:
    def __init__(self, code: str) -> None:
        self.lines = code.splitlines()

    def span(self, first: int, last: int) -> list[str]:
        return self.lines[first - 1 : last]

    def node(self, node: ast.stmt) -> list[str]:
        return self.span(_start(node), _end(node))


def _find_class(tree: ast.Module, name: str, states: Sequence[str]) -> ast.ClassDef | None:
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef)]
    for candidate in classes:
        if candidate.name == name:
            return candidate

    def state_methods(cls: ast.ClassDef) -> int:
        return sum(
            isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef) and n.name in states
            for n in cls.body
        )

    ranked = sorted(classes, key=state_methods, reverse=True)
    return ranked[0] if ranked and state_methods(ranked[0]) else None


def _methods(cls: ast.ClassDef) -> dict[str, ast.FunctionDef | ast.AsyncFunctionDef]:
    return {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)}


def _import_key(node: ast.stmt) -> str:
    return ast.unparse(node)


class _Merger:
    def __init__(self, skeleton_code: str, model_code: str, states: Sequence[str]) -> None:
        self.sk = _Source(skeleton_code)
        self.model = _Source(model_code)
        self.states = list(states)
        self.written: list[str] = []
        self.missing: list[str] = []
        self.added: list[str] = []
        self.left_out: list[str] = []

    def state_body(
        self,
        sk_method: ast.FunctionDef | ast.AsyncFunctionDef,
        model_method: ast.FunctionDef | ast.AsyncFunctionDef,
    ) -> list[str] | None:
        model_body = _body_without_docstring(model_method)
        skeleton_statements = {ast.unparse(s) for s in _body_without_docstring(sk_method)}
        if all(_is_placeholder(s) or ast.unparse(s) in skeleton_statements for s in model_body):
            return None
        mentioned = _self_attributes(model_method, assigned_only=False)
        kept: list[str] = []
        for statement in _body_without_docstring(sk_method):
            if _is_placeholder(statement):
                continue
            handles = _self_attributes(statement, assigned_only=True)
            if handles and not handles & mentioned:
                kept += self.sk.node(statement)
        first, last = _start(model_body[0]), _end(model_body[-1])
        body = _reindent(self.model.span(first, last), model_body[0].col_offset, 8)
        return kept + body

    def state_method(
        self,
        sk_method: ast.FunctionDef | ast.AsyncFunctionDef,
        model_method: ast.FunctionDef | ast.AsyncFunctionDef | None,
    ) -> list[str]:
        body = None if model_method is None else self.state_body(sk_method, model_method)
        if body is None:
            self.missing.append(sk_method.name)
            return self.sk.node(sk_method)
        self.written.append(sk_method.name)
        sk_body = _body_without_docstring(sk_method)
        head_end = (sk_body[0].lineno - 1) if sk_body else _end(sk_method)
        head = self.sk.span(_start(sk_method), head_end)
        while head and not head[-1].strip():
            head.pop()
        return head + body

    def init_method(
        self,
        sk_method: ast.FunctionDef | ast.AsyncFunctionDef,
        model_method: ast.FunctionDef | ast.AsyncFunctionDef | None,
    ) -> list[str]:
        lines = self.sk.node(sk_method)
        if model_method is None:
            return lines
        known = _self_attributes(sk_method, assigned_only=True)
        for statement in model_method.body:
            if not isinstance(statement, ast.Assign | ast.AnnAssign):
                continue
            new = _self_attributes(statement, assigned_only=True) - known
            if new:
                lines += _reindent(self.model.node(statement), statement.col_offset, 8)
                self.added += [f"attribute self.{name}" for name in sorted(new)]
                known |= new
        return lines

    def whole(self, node: ast.stmt, what: str) -> list[str]:
        self.added.append(what)
        return _reindent(self.model.node(node), node.col_offset, 4)


def _class_blocks(
    merger: _Merger, sk_class: ast.ClassDef, model_class: ast.ClassDef, states: Sequence[str]
) -> list[tuple[bool, list[str]]]:
    """The merged class body as blocks; ``True`` marks a class constant."""
    sk_methods = _methods(sk_class)
    model_methods = _methods(model_class)
    blocks: list[tuple[bool, list[str]]] = []
    helpers: list[tuple[bool, list[str]]] = []
    sk_constants = {
        ast.unparse(t) for n in sk_class.body if isinstance(n, ast.Assign) for t in n.targets
    }
    for node in model_class.body:
        if isinstance(node, ast.Assign) and not {ast.unparse(t) for t in node.targets} & (
            sk_constants
        ):
            label = f"class constant {ast.unparse(node.targets[0])}"
            helpers.append((True, merger.whole(node, label)))
    for name, method in model_methods.items():
        if name in sk_methods:
            continue
        if name in PACKML_STATES or name in states:
            merger.left_out.append(f"state {name}: the specification does not list it")
        elif _decorator_names(method) & _ANNOTATIONS:
            merger.left_out.append(
                f"getter {name}: parameters and outputs come from the capability"
            )
        else:
            helpers.append((False, merger.whole(method, f"helper {name}")))

    helpers_placed = False
    for node in sk_class.body:
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            blocks.append((isinstance(node, ast.Assign), merger.sk.node(node)))
            continue
        model_method = model_methods.get(node.name)
        if node.name in states:
            if not helpers_placed:
                blocks += helpers
                helpers_placed = True
            blocks.append((False, merger.state_method(node, model_method)))
        elif node.name == "__init__":
            blocks.append((False, merger.init_method(node, model_method)))
        elif (
            model_method is not None
            and node.name.startswith("_on_")
            and ast.unparse(model_method) != ast.unparse(node)
        ):
            blocks.append((False, merger.whole(model_method, f"callback {node.name}")))
        else:
            blocks.append((False, merger.sk.node(node)))
    if not helpers_placed:
        blocks += helpers

    return blocks


def merge_into_skeleton(
    skeleton_code: str,
    class_name: str,
    states: Sequence[str],
    model_code: str,
    *,
    author: str | None = None,
) -> Merged | None:
    """The skeleton with the model's behaviour in it, or ``None`` when ``model_code`` does
    not parse or has no skill class to take behaviour from.

    ``author`` (e.g. the model id) replaces the skeleton's note in the module docstring.
    """
    try:
        model_tree = ast.parse(model_code)
    except SyntaxError:
        return None
    sk_tree = ast.parse(skeleton_code)
    sk_class = _find_class(sk_tree, class_name, states)
    model_class = _find_class(model_tree, class_name, states)
    if sk_class is None or model_class is None:
        return None
    merger = _Merger(skeleton_code, model_code, states)

    blocks = _class_blocks(merger, sk_class, model_class, states)

    sk_imports = {
        _import_key(n) for n in sk_tree.body if isinstance(n, ast.Import | ast.ImportFrom)
    }
    extra_imports: list[str] = []
    module_helpers: list[str] = []
    for node in model_tree.body:
        if isinstance(node, ast.Import | ast.ImportFrom):
            if _import_key(node) not in sk_imports:
                extra_imports += merger.model.node(node)
                merger.added.append(_import_key(node))
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Assign):
            label = node.name if not isinstance(node, ast.Assign) else ast.unparse(node.targets[0])
            merger.added.append(f"module-level {label}")
            module_helpers += [*merger.model.node(node), "", ""]

    last_import = max(
        (_end(n) for n in sk_tree.body if isinstance(n, ast.Import | ast.ImportFrom)), default=0
    )
    out: list[str] = merger.sk.span(1, last_import) + extra_imports
    out += merger.sk.span(last_import + 1, _start(sk_class) - 1)
    out += module_helpers
    out += merger.sk.span(_start(sk_class), _start(sk_class.body[0]) - 1)
    previous_constant: bool | None = None
    for constant, block in blocks:
        if previous_constant is not None and not (constant and previous_constant):
            out.append("")
        out += block
        previous_constant = constant
    out += merger.sk.span(_end(sk_class) + 1, len(merger.sk.lines))
    code = "\n".join(out).rstrip() + "\n"
    if author is not None:
        code = code.replace("\n".join(SKELETON_NOTE), _authorship(author, merger.missing), 1)
    try:
        ast.parse(code)
    except SyntaxError:
        return None
    return Merged(
        code=code,
        written=tuple(merger.written),
        missing=tuple(merger.missing),
        added=tuple(merger.added),
        left_out=tuple(merger.left_out),
    )
