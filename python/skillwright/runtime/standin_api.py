"""The API of the sandbox's stand-ins of rclpy, tf2_ros and pySkillUp, read from their source.

A skill runs in the sandbox against the stand-ins under ``runtime/child/`` (``rclpy``,
``tf2_ros``, ``pyskillup``), which follow the real packages (rclpy Humble/Jazzy) where
skills use them. The static checks accept the same API: rather than keep a second list
that drifts from the first, they ask this module, which parses the stand-ins' files with
:mod:`ast` once. The host never imports the stand-ins (they import the child's core, which
exists only inside the sandbox, and would shadow a real rclpy).

What counts as a class's API: every name defined in its body (methods, properties, class
attributes and aliases such as ``warn = warning``) and every ``self.<name>`` its
``__init__`` assigns, except names with a leading underscore. The stand-ins keep what the
sandbox's own machinery uses (handle ids, deliveries, quiet checks, timers' due times)
under such names, so the public names are rclpy's, tf2's and pySkillUp's. Base classes are
not followed: no stand-in class a skill holds inherits API from another.
"""

from __future__ import annotations

import ast
import inspect
from functools import cache
from typing import Final

from skillwright.runtime.isolation import CHILD_ROOT

__all__ = ["HANDLES", "exported", "members", "signature"]

HANDLES: Final[dict[str, tuple[str, str]]] = {
    "node": ("rclpy.node", "Node"),
    "publisher": ("rclpy.node", "Publisher"),
    "subscription": ("rclpy.node", "Subscription"),
    "client": ("rclpy.node", "Client"),
    "action_client": ("rclpy.action.client", "ActionClient"),
    "goal_handle": ("rclpy.action.client", "ClientGoalHandle"),
    "future": ("rclpy.task", "Future"),
    "timer": ("rclpy.timer", "Timer"),
    "rate": ("rclpy.timer", "Rate"),
    "time": ("rclpy.time", "Time"),
    "logger": ("rclpy.logging", "RcutilsLogger"),
    "tf_listener": ("tf2_ros.transform_listener", "TransformListener"),
    "tf_buffer": ("tf2_ros.buffer", "Buffer"),
    "skill_base": ("pyskillup.decorator_check.decorator_check", "ROS2Skill"),
}
"""The kinds of object a skill holds, by the stand-in module and class that make them."""


class _Default:
    """A parameter's default as its source text (``None``, ``qos_profile_services_default``):
    the checks bind calls to signatures and print them, and never need the value."""

    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return self.text


@cache
def _module(module: str) -> ast.Module:
    """The parsed source of a stand-in module, by its dotted name (``rclpy.node``)."""
    path = CHILD_ROOT.joinpath(*module.split("."))
    file = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
    return ast.parse(file.read_text(encoding="utf-8"), str(file))


def _class(kind: str) -> ast.ClassDef:
    module, name = HANDLES[kind]
    for node in _module(module).body:
        if isinstance(node, ast.ClassDef) and node.name == name:
            return node
    raise LookupError(f"the stand-in module {module} has no class {name}")


def _targets(node: ast.stmt) -> list[ast.expr]:
    if isinstance(node, ast.Assign):
        return node.targets
    if isinstance(node, ast.AnnAssign):
        return [node.target]
    return []


@cache
def members(kind: str) -> frozenset[str]:
    """The public names an object of ``kind`` (a key of :data:`HANDLES`) has."""
    names: set[str] = set()
    for node in _class(kind).body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(node.name)
            if node.name == "__init__":
                for inner in ast.walk(node):
                    if not isinstance(inner, ast.stmt):
                        continue
                    names.update(
                        target.attr
                        for target in _targets(inner)
                        if isinstance(target, ast.Attribute)
                        and isinstance(target.value, ast.Name)
                        and target.value.id == "self"
                    )
        names.update(t.id for t in _targets(node) if isinstance(t, ast.Name))
    return frozenset(n for n in names if not n.startswith("_"))


@cache
def signature(kind: str, method: str) -> inspect.Signature:
    """What ``method`` of an object of ``kind`` takes, without ``self``."""
    for node in _class(kind).body:
        if isinstance(node, ast.FunctionDef) and node.name == method:
            return _signature(node.args)
    raise LookupError(f"the stand-in of {kind} has no method {method}")


def _default(node: ast.expr | None) -> object:
    return inspect.Parameter.empty if node is None else _Default(ast.unparse(node))


def _signature(arguments: ast.arguments) -> inspect.Signature:
    parameter = inspect.Parameter
    positional: list[tuple[ast.arg, inspect._ParameterKind]] = [
        (a, parameter.POSITIONAL_ONLY) for a in arguments.posonlyargs
    ]
    positional += [(a, parameter.POSITIONAL_OR_KEYWORD) for a in arguments.args]
    # the defaults belong to the last positional parameters
    defaults: list[ast.expr | None] = [None] * (len(positional) - len(arguments.defaults))
    defaults += arguments.defaults
    parameters = [
        parameter(a.arg, kind, default=_default(d))
        for (a, kind), d in zip(positional, defaults, strict=True)
    ][1:]
    if arguments.vararg is not None:
        parameters.append(parameter(arguments.vararg.arg, parameter.VAR_POSITIONAL))
    parameters += [
        parameter(a.arg, parameter.KEYWORD_ONLY, default=_default(d))
        for a, d in zip(arguments.kwonlyargs, arguments.kw_defaults, strict=True)
    ]
    if arguments.kwarg is not None:
        parameters.append(parameter(arguments.kwarg.arg, parameter.VAR_KEYWORD))
    return inspect.Signature(parameters)


@cache
def exported(module: str) -> tuple[str, ...]:
    """The names a stand-in module's ``__all__`` lists (what its star import gives)."""
    for node in _module(module).body:
        if not isinstance(node, ast.Assign | ast.AnnAssign) or node.value is None:
            continue
        if any(isinstance(t, ast.Name) and t.id == "__all__" for t in _targets(node)):
            return tuple(str(n) for n in ast.literal_eval(node.value))
    raise LookupError(f"the stand-in module {module} has no __all__")
