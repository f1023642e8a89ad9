"""What the host reads from a skill's source before running it (never by executing it).

The ``@skill`` class, its ``@skill_parameter`` and ``@skill_output`` getters with the
attribute each returns (the driver sets inputs there and watches outputs there), the
getter's return annotation (to give inputs their type), and the state methods present.
"""

from __future__ import annotations

import ast
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field

from skillwright.rules.run import RUN_STRUCTURE, RUN_SYNTAX

__all__ = [
    "SkillInfo",
    "SkillSourceError",
    "Variable",
    "decorator_name",
    "read_skill",
    "returned_path",
]

_STATES = frozenset(
    {
        "starting",
        "execute",
        "completing",
        "holding",
        "unholding",
        "suspending",
        "unsuspending",
        "stopping",
        "aborting",
        "clearing",
        "resetting",
    }
)


class SkillSourceError(ValueError):
    """The source has no skill to run; ``line`` says where the problem is (0: anywhere)."""

    def __init__(self, message: str, line: int = 0, *, syntax: bool = False) -> None:
        super().__init__(message)
        self.line = line
        self.rule = RUN_SYNTAX if syntax else RUN_STRUCTURE
        """The rule the run reports it under."""


@dataclass(frozen=True)
class Variable:
    """A skill input or output as its getter declares it."""

    name: str
    getter: str
    attr: str | None
    """The ``self.<attr>`` the getter returns (the first of ``self.goal.x``); ``None`` when it
    returns something else."""
    annotation: str | None
    required: bool
    line: int
    path: str | None = None
    """Where the getter reads its value (``goal.x`` for ``return self.goal.x``; ``attr`` for
    ``return self.attr``): an input is set there, as the getter will read it."""
    description: str = ""
    """The decorator's ``description``: what binds the variable to its capability by meaning
    when its name is not the capability's."""


@dataclass
class SkillInfo:
    """The runnable shape of a skill."""

    class_name: str
    class_line: int
    parameters: list[Variable] = field(default_factory=list)
    outputs: list[Variable] = field(default_factory=list)
    states: dict[str, int] = field(default_factory=dict)
    """State name -> line of its method."""
    callback_stores: frozenset[str] = frozenset()
    """The attributes its callbacks assign (see :func:`callback_stores`)."""


def decorator_name(node: ast.expr) -> str:
    """The name a decorator is called by: ``skill`` for ``@skill(...)`` and for
    ``@decorators.skill(...)``."""
    target = node.func if isinstance(node, ast.Call) else node
    if isinstance(target, ast.Name):
        return target.id
    if isinstance(target, ast.Attribute):
        return target.attr
    return ""


def _keyword(call: ast.Call, name: str) -> ast.expr | None:
    return next((k.value for k in call.keywords if k.arg == name), None)


def returned_path(function: ast.FunctionDef) -> str | None:
    """``x`` (or ``goal.x``) when every ``return`` of the getter gives ``self.x``
    (``self.goal.x``), possibly converted (``float(self.x)``)."""
    found: set[str] = set()
    returns = [n for n in ast.walk(function) if isinstance(n, ast.Return)]
    if not returns:
        return None
    for node in returns:
        if node.value is None:
            return None
        inner = {id(n.value) for n in ast.walk(node.value) if isinstance(n, ast.Attribute)}
        paths = {
            path
            for n in ast.walk(node.value)
            if isinstance(n, ast.Attribute) and id(n) not in inner
            for path in [_self_path(n)]
            if path is not None
        }
        if len(paths) != 1:
            return None
        found |= paths
    return found.pop() if len(found) == 1 else None


def _self_path(node: ast.Attribute) -> str | None:
    """``goal.x`` for the expression ``self.goal.x``."""
    parts: list[str] = []
    current: ast.expr = node
    while isinstance(current, ast.Attribute):
        parts.append(current.attr)
        current = current.value
    if isinstance(current, ast.Name) and current.id == "self":
        return ".".join(reversed(parts))
    return None


def _variable(function: ast.FunctionDef, call: ast.Call) -> Variable:
    path = returned_path(function)
    name_node = _keyword(call, "name")
    name = (
        name_node.value
        if isinstance(name_node, ast.Constant) and isinstance(name_node.value, str)
        else function.name
    )
    described = _keyword(call, "description")
    required_node = _keyword(call, "is_required")
    required = not (isinstance(required_node, ast.Constant) and required_node.value is False)
    return Variable(
        name=name,
        getter=function.name,
        attr=path.split(".")[0] if path is not None else None,
        path=path,
        annotation=ast.unparse(function.returns) if function.returns is not None else None,
        required=required,
        line=function.lineno,
        description=described.value
        if isinstance(described, ast.Constant) and isinstance(described.value, str)
        else "",
    )


def _self_method(node: ast.expr, methods: AbstractSet[str]) -> str | None:
    if (
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
        and node.attr in methods
    ):
        return node.attr
    return None


def _stores(node: ast.AST) -> set[str]:
    return {
        n.attr
        for n in ast.walk(node)
        if isinstance(n, ast.Attribute)
        and isinstance(n.ctx, ast.Store)
        and isinstance(n.value, ast.Name)
        and n.value.id == "self"
    }


def callback_stores(cls: ast.ClassDef) -> frozenset[str]:
    """The attributes the class's callbacks assign: rclpy runs a callback handed to
    ``create_subscription``, ``create_timer``, ``send_goal_async(feedback_callback=...)`` or
    a future's ``add_done_callback`` while the states run, so what it stores is set by the
    skill even when no state assigns it. A callback is a method passed as an argument of
    any call (``self._on_odom``), a lambda passed so (the methods it calls) or a function
    defined in a method and passed by name; methods a callback calls count too."""
    methods = {
        item.name: item
        for item in cls.body
        if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef)
    }
    called: set[str] = set()
    stores: set[str] = set()
    for method in methods.values():
        nested = {
            n.name: n
            for n in ast.walk(method)
            if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef) and n is not method
        }
        for call in (n for n in ast.walk(method) if isinstance(n, ast.Call)):
            for argument in [*call.args, *(k.value for k in call.keywords)]:
                name = _self_method(argument, methods.keys())
                if name is not None:
                    called.add(name)
                elif isinstance(argument, ast.Lambda):
                    stores |= _stores(argument)
                    called |= {
                        m
                        for n in ast.walk(argument.body)
                        if isinstance(n, ast.Call)
                        for m in [_self_method(n.func, methods.keys())]
                        if m is not None
                    }
                elif isinstance(argument, ast.Name) and argument.id in nested:
                    stores |= _stores(nested[argument.id])
    pending = list(called)
    while pending:
        method = methods[pending.pop()]
        stores |= _stores(method)
        for n in ast.walk(method):
            if isinstance(n, ast.Call):
                name = _self_method(n.func, methods.keys())
                if name is not None and name not in called:
                    called.add(name)
                    pending.append(name)
    return frozenset(stores)


def read_skill(source: str, filename: str = "skill.py") -> SkillInfo:
    """The skill class of ``source``; :class:`SkillSourceError` when there is none."""
    try:
        tree = ast.parse(source, filename)
    except SyntaxError as error:
        raise SkillSourceError(
            f"the file does not parse: {error.msg}", error.lineno or 0, syntax=True
        ) from None
    for node in tree.body:
        if not isinstance(node, ast.ClassDef):
            continue
        if not any(decorator_name(d) == "skill" for d in node.decorator_list):
            continue
        info = SkillInfo(class_name=node.name, class_line=node.lineno)
        for item in node.body:
            if not isinstance(item, ast.FunctionDef):
                continue
            for decorator in item.decorator_list:
                name = decorator_name(decorator)
                if name in _STATES and not isinstance(decorator, ast.Call):
                    info.states[name] = item.lineno
                elif name == "skill_parameter" and isinstance(decorator, ast.Call):
                    info.parameters.append(_variable(item, decorator))
                elif name == "skill_output" and isinstance(decorator, ast.Call):
                    info.outputs.append(_variable(item, decorator))
        info.callback_stores = callback_stores(node)
        if "execute" not in info.states:
            raise SkillSourceError(
                f"class {node.name} has no @execute method, so there is nothing to run",
                node.lineno,
            )
        return info
    raise SkillSourceError(
        "no class decorated with @skill(...) at the top level of the file, so there is no "
        "skill to run"
    )
