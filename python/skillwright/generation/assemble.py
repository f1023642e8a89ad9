"""Putting the methods a model wrote into the skeleton.

The skeleton owns the file's structure; the model wrote one method at a time (states and the
helpers they call). This module:

- puts each state's body under the skeleton's decorator, signature and docstring, with the
  skeleton's closing lines (releasing handles in ``resetting``) after it, and each helper
  before the first state;
- finds which interfaces and skeleton helpers the behaviour uses (:func:`usage`), so the
  caller can rebuild the skeleton without the ones it does not (retrieval gives ``k``
  interfaces whether or not the skill needs them all), and drops the prefilled lines that
  made their handles;
- adds what the written code needs and a model cannot be trusted to add: imports of ``time``,
  ``math`` and of message classes the interface definitions name, and an ``__init__``
  attribute for every attribute the behaviour sets, so that a state running before another
  (``stopping`` before ``execute``) does not fail on a missing attribute.
"""

from __future__ import annotations

import ast
import builtins
import re
import textwrap
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from skillwright.generation.card import latest_message_attribute
from skillwright.generation.model import InterfaceRef, Skeleton
from skillwright.generation.names import python_import
from skillwright.generation.skeleton import (
    SKELETON_NOTE,
    handle_attribute,
    helper_dependencies,
    is_tf,
    skeleton_helpers,
)
from skillwright.interfaces.inventory import Interface, MessageField

__all__ = [
    "Assembly",
    "Usage",
    "assemble",
    "message_classes",
    "method_spans",
    "parse_method",
    "usage",
]

_STDLIB = {"time", "math", "os", "datetime", "threading"}
"""Standard modules the written code may use without importing them (the import is added)."""
_KNOWN_CLASSES = {
    "GoalStatus": "action_msgs.msg",
    "Path": "pathlib",
    **dict.fromkeys(
        ("Twist", "Vector3", "Point", "Pose", "PoseStamped", "Quaternion"), "geometry_msgs.msg"
    ),
    **dict.fromkeys(("Any", "Dict", "List", "Optional", "Sequence", "Tuple"), "typing"),
}
"""Classes the written code may use beyond the interfaces' own: every ROS 2 install has the
geometry messages (a command the base helper makes, a goal's pose), and a helper's
annotations name typing's (a helper annotated ``ranges: List[float]`` failed the checks
for want of its import)."""


def parse_method(text: str) -> ast.FunctionDef | None:
    """The one method in ``text`` (class-member indentation), or ``None`` when it does not
    parse or holds something else."""
    try:
        tree = ast.parse(textwrap.dedent(text))
    except SyntaxError:
        return None
    if len(tree.body) != 1 or not isinstance(tree.body[0], ast.FunctionDef):
        return None
    return tree.body[0]


def _self_names(node: ast.AST) -> set[str]:
    return {
        n.attr
        for n in ast.walk(node)
        if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "self"
    }


def _statement_keys(code: str) -> set[str]:
    if not code.strip():
        return set()
    return {ast.unparse(s) for s in ast.parse(textwrap.dedent(code)).body}


@dataclass(frozen=True)
class Usage:
    """What the written methods use of the skeleton."""

    interfaces: tuple[InterfaceRef, ...]
    helpers: tuple[str, ...]


def usage(skeleton: Skeleton, methods: Mapping[str, str]) -> Usage:
    """The interfaces and skeleton helpers the written ``methods`` use.

    The lines the skeleton prefilled (making handles in ``starting``) do not count as use;
    an interface a used helper needs (the base's velocity command for ``_stop_base``) does,
    and so do the skeleton's own lines that are behaviour rather than making or releasing
    handles (bringing the base to rest for an asserted output, at the end of ``execute`` or
    the start of ``completing``).
    """
    prologue = _statement_keys(skeleton.prologues.get("starting", ""))
    mentioned: set[str] = set()
    own = [
        *(code for state, code in skeleton.prologues.items() if state != "starting"),
        *(code for state, code in skeleton.epilogues.items() if state != "resetting"),
    ]
    for code in own:
        mentioned |= _self_names(ast.parse(textwrap.dedent(code)))
    for text in methods.values():
        method = parse_method(text)
        if method is None:
            continue
        for statement in method.body:
            if ast.unparse(statement) not in prologue:
                mentioned |= _self_names(statement)
    offered = skeleton_helpers(skeleton.interfaces, skeleton.helpers)
    called = helper_dependencies([h for h in skeleton.helpers if h in mentioned], offered)
    helpers = tuple(h for h in skeleton.helpers if h in called)
    through_helpers = {
        name
        for helper in helpers
        for name in re.findall(r"self\.(\w+)", "\n".join(offered[helper]))
    }
    used = []
    for interface in skeleton.interfaces:
        names = {handle_attribute(interface)}
        if is_tf(interface):
            names |= {"tf_buffer", "_transform"}
        elif interface.role == "subscribe":
            names.add(latest_message_attribute(interface))
        if names & (mentioned | through_helpers):
            used.append(interface)
    return Usage(tuple(used), helpers)


@dataclass(frozen=True)
class Assembly:
    """The assembled file and what went into it."""

    code: str
    written: tuple[str, ...]
    """States whose behaviour was written."""
    missing: tuple[str, ...]
    """States still raising NotImplementedError."""
    added: tuple[str, ...]
    """Imports and attributes added for the written code."""


def _span(node: ast.stmt) -> tuple[int, int]:
    decorators: list[ast.expr] = getattr(node, "decorator_list", [])
    first = min([node.lineno, *(d.lineno for d in decorators)])
    return first, node.end_lineno or node.lineno


def _body_lines(text: str, method: ast.FunctionDef, drop: set[str]) -> list[str]:
    """The method's statements re-indented to a method body, without a docstring and the
    statements in ``drop``."""
    lines = textwrap.dedent(text).splitlines()
    out: list[str] = []
    for index, statement in enumerate(method.body):
        is_docstring = (
            index == 0
            and isinstance(statement, ast.Expr)
            and isinstance(statement.value, ast.Constant)
            and isinstance(statement.value.value, str)
        )
        if is_docstring or ast.unparse(statement) in drop:
            continue
        first, last = _span(statement)
        out += lines[first - 1 : last]
    return textwrap.indent(textwrap.dedent("\n".join(out)), " " * 8).splitlines()


def _authorship(author: str, missing: Sequence[str]) -> str:
    lines = [
        "Structure, annotations and interface handles: skillwright's skeleton.",
        f"Behaviour: written by {author}, one method at a time; review it before it runs on",
        "hardware.",
    ]
    if missing:
        lines.append(f"Still to be written (raise NotImplementedError): {', '.join(missing)}.")
    return "\n".join(lines)


def assemble(
    skeleton: Skeleton,
    methods: Mapping[str, str],
    helpers: Mapping[str, str],
    *,
    prefilled: Iterable[str] = (),
    author: str | None = None,
    classes: Mapping[str, str] | None = None,
) -> Assembly:
    """The skeleton with the written state ``methods`` and ``helpers`` in it.

    ``prefilled`` is code the model was given at the start of ``starting`` (the handles of the
    skeleton it was asked with); statements of it whose handle this skeleton no longer has
    are dropped. ``classes`` maps message class names to their modules
    (:func:`message_classes`), for imports the written code needs.
    """
    tree = ast.parse(skeleton.code)
    cls = next(
        n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == skeleton.class_name
    )
    lines = skeleton.code.splitlines()
    kept = _statement_keys(skeleton.prologues.get("starting", ""))
    dropped = {key for text in prefilled for key in _statement_keys(text)} - kept
    # The skeleton releases the handles at the end of resetting; a model's own
    # ``self.handle = None`` before that would skip the release and leak the handle.
    released = {f"self.{handle_attribute(i)} = None" for i in skeleton.interfaces}
    state_nodes = {
        n.name: n
        for n in cls.body
        if isinstance(n, ast.FunctionDef) and n.name in skeleton.unimplemented
    }
    written: list[str] = []
    replacements: dict[int, tuple[int, list[str]]] = {}
    for name, node in state_nodes.items():
        method = parse_method(methods[name]) if name in methods else None
        if method is None:
            continue
        first, last = _span(node)
        docstring = node.body[0]
        head = lines[first - 1 : docstring.end_lineno or docstring.lineno]
        drop = dropped | released if name == "resetting" else dropped
        body = _body_lines(methods[name], method, drop)
        epilogue = skeleton.epilogues.get(name, "")
        new = head + (body or ["        pass"]) + (epilogue.splitlines() if epilogue else [])
        replacements[first] = (last, new)
        written.append(name)

    helper_lines: list[str] = []
    for text in helpers.values():
        if parse_method(text) is not None:
            helper_lines += [
                "",
                *textwrap.indent(textwrap.dedent(text).rstrip(), "    ").splitlines(),
            ]
    first_state = min((_span(n)[0] for n in state_nodes.values()), default=None)

    out: list[str] = []
    index = 1
    while index <= len(lines):
        if index == first_state and helper_lines:
            out += [*helper_lines[1:], "", ""]
        if index in replacements:
            last, new = replacements[index]
            out += new
            index = last + 1
            continue
        out.append(lines[index - 1])
        index += 1
    code = "\n".join(out) + "\n"
    missing = [s for s in skeleton.unimplemented if s not in written]
    if author is not None:
        code = code.replace("\n".join(SKELETON_NOTE), _authorship(author, missing), 1)
    code, added = _complete(code, skeleton, classes or _KNOWN_CLASSES)
    return Assembly(code, tuple(written), tuple(missing), tuple(added))


def _defined_names(tree: ast.Module) -> set[str]:
    names: set[str] = set(dir(builtins))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            names |= {(a.asname or a.name).split(".")[0] for a in node.names}
        elif isinstance(node, ast.FunctionDef | ast.ClassDef | ast.AsyncFunctionDef):
            names.add(node.name)
            names |= (
                {a.arg for a in [*node.args.args, *node.args.kwonlyargs]}
                if not isinstance(node, ast.ClassDef)
                else set()
            )
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
        elif isinstance(node, ast.ExceptHandler) and node.name:
            names.add(node.name)
    return names


def _nested(fields: Sequence[MessageField] | None) -> Iterable[str]:
    for field in fields or []:
        if not field.builtin and field.base_type.count("/") >= 1:
            yield field.base_type
            yield from _nested(field.fields)


def message_classes(interfaces: Iterable[Interface]) -> dict[str, str]:
    """Class name -> module of every type the interfaces are or their definitions mention
    (``Vector3`` -> ``geometry_msgs.msg``), for the imports the written code needs."""
    known = dict(_KNOWN_CLASSES)
    for interface in interfaces:
        module, name = python_import(interface.type_name, interface.kind)
        known.setdefault(name, module)
        for definition in interface.definitions.values():
            for type_name in _nested(definition.fields):
                try:
                    module, name = python_import(type_name, "topic")
                except ValueError:
                    continue
                known.setdefault(name, module)
    return known


def _complete(code: str, skeleton: Skeleton, classes: Mapping[str, str]) -> tuple[str, list[str]]:
    """Adds imports and ``__init__`` attributes the written code needs."""
    tree = ast.parse(code)
    defined = _defined_names(tree)
    used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
    missing = sorted(used - defined)
    stdlib = [f"import {name}" for name in missing if name in _STDLIB]
    messages = [
        f"from {classes[name]} import {name}"
        for name in missing
        if name not in _STDLIB and name in classes
    ]
    added: list[str] = [*stdlib, *messages]
    lines = code.splitlines()
    cls = next(
        n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == skeleton.class_name
    )
    init = next(
        (n for n in cls.body if isinstance(n, ast.FunctionDef) and n.name == "__init__"), None
    )
    methods = {n.name for n in cls.body if isinstance(n, ast.FunctionDef)}
    constants = {
        t.id
        for n in cls.body
        if isinstance(n, ast.Assign)
        for t in n.targets
        if isinstance(t, ast.Name)
    }
    if init is not None:
        initialised = {
            t.attr
            for n in ast.walk(init)
            if isinstance(n, ast.Assign | ast.AnnAssign)
            for t in (n.targets if isinstance(n, ast.Assign) else [n.target])
            if isinstance(t, ast.Attribute)
            and isinstance(t.value, ast.Name)
            and t.value.id == "self"
        }
        assigned = sorted(
            {
                t.attr
                for n in ast.walk(cls)
                if isinstance(n, ast.Assign | ast.AnnAssign | ast.AugAssign)
                for target in (n.targets if isinstance(n, ast.Assign) else [n.target])
                for t in ast.walk(target)
                if isinstance(t, ast.Attribute)
                and isinstance(t.value, ast.Name)
                and t.value.id == "self"
            }
            - initialised
            - methods
            - constants
        )
        if assigned:
            at = init.end_lineno or init.lineno
            lines[at:at] = [f"        self.{name} = None" for name in assigned]
            added += [f"attribute self.{name}" for name in assigned]
    module_imports = [n for n in tree.body if isinstance(n, ast.Import | ast.ImportFrom)]
    if messages:
        at = (module_imports[-1].end_lineno or 0) if module_imports else 0
        lines[at:at] = messages
    if stdlib:
        at = (module_imports[0].lineno - 1) if module_imports else 0
        lines[at:at] = stdlib
    return "\n".join(lines) + "\n", added


def method_spans(code: str, class_name: str) -> dict[str, tuple[int, int]]:
    """Each method of the class: (first line with its decorators, last line)."""
    tree = ast.parse(code)
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == class_name:
            return {n.name: _span(n) for n in node.body if isinstance(n, ast.FunctionDef)}
    return {}
