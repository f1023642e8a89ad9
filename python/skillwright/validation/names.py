"""Names a skill uses that nothing defines: the commonest mistakes of a small model.

The kinds, each found without running the code:

- a name that is neither imported, defined, a builtin nor one of pySkillUp's decorators
  (``Vector3`` used without its import, ``rospy``);
- an attribute of the skill read but set nowhere (``self.logger``, ``self.odom_sub``);
- a method called on the node or on a handle the code made that rclpy does not have
  (``subscription.wait_for_message``, ``self.node.get_time``);
- a method of the class called with arguments its definition does not take;
- an attribute only ever set to ``None`` but read as an object (``self.start.x``).

The rclpy, tf2 and pySkillUp names the checks accept are those of the sandbox's stand-ins
(:mod:`skillwright.runtime.standin_api` reads them from their source), so that a call the
checks pass is one the sandboxed run can make, and the two cannot disagree; the stand-ins
follow rclpy (Humble/Jazzy), tf2_ros and pySkillUp where skills use them.
"""

from __future__ import annotations

import ast
import builtins
import copy
import difflib
import importlib
import inspect
import itertools
import re
import symtable
from collections.abc import Iterator, Mapping

from skillwright.rules.api import (
    ATTRIBUTE_NEVER_SET,
    ATTRIBUTE_ONLY_NONE,
    FEEDBACK_CALLBACK_NOT_TIMEOUT,
    FUTURE_METHOD_ON_RESULT,
    HELPER_CALL_MISMATCH,
    LOCAL_HIDES_MODULE,
    LOCAL_READ_AS_ATTRIBUTE,
    METHOD_CALL_MISMATCH,
    METHOD_OVERWRITTEN,
    MODULE_AS_NUMBER,
    MODULE_SHADOWED,
    NESTED_MESSAGE_CLASS,
    NONE_RESULT_USED,
    RCLPY_CALL_ARGUMENTS,
    ROS1_API,
    UNDEFINED_NAME,
    UNKNOWN_API_ATTRIBUTE,
)
from skillwright.rules.finding import Finding
from skillwright.rules.registry import Rule
from skillwright.runtime import standin_api
from skillwright.validation.facts import SkillFacts, is_clock_now
from skillwright.validation.syntax import (
    called_name,
    self_attribute,
    self_method,
    with_node_replaced,
    with_text_in_place,
)

__all__ = ["RCLPY_API", "check_names", "without_guard"]

PYSKILLUP_NAMES = frozenset(standin_api.exported("pyskillup.decorators.decorators"))
"""What ``from pyskillup.decorators.decorators import *`` provides."""

RCLPY_API: dict[str, frozenset[str]] = {
    kind: standin_api.members(kind)
    for kind in (
        "node",
        "publisher",
        "subscription",
        "client",
        "action_client",
        "timer",
        "rate",
        "tf_listener",
        "tf_buffer",
        "time",
        "logger",
    )
}
"""Attributes of rclpy's and tf2's objects a skill may use, by the kind of object: those of
the sandbox's stand-ins (:mod:`skillwright.runtime.standin_api`)."""

_KIND_WORDS = {
    "node": "the node (rclpy Node)",
    "publisher": "a Publisher",
    "subscription": "a Subscription",
    "client": "a service Client",
    "action_client": "an ActionClient",
    "timer": "a Timer",
    "rate": "a Rate",
    "tf_listener": "a tf2 TransformListener",
    "tf_buffer": "a tf2 Buffer",
    "logger": "the logger",
    "time": "an rclpy Time",
}
_BASE_ATTRIBUTES = standin_api.members("skill_base")
"""What pySkillUp's ``ROS2Skill`` gives a skill."""


def _finding(
    rule: Rule,
    node: ast.AST,
    message: str,
    replacement: str | None = None,
    *,
    data: dict[str, object] | None = None,
) -> Finding:
    return rule.at(node, message, data=data, replacement=replacement)


def _module_names(table: symtable.SymbolTable) -> set[str]:
    names = {s.get_name() for s in table.get_symbols() if s.is_assigned() or s.is_imported()}
    return names | set(dir(builtins)) | PYSKILLUP_NAMES | {"__name__", "__file__"}


def _global_uses(table: symtable.SymbolTable) -> Iterator[tuple[str, symtable.SymbolTable]]:
    for child in table.get_children():
        if str(child.get_type()) == "function":
            for symbol in child.get_symbols():
                if symbol.is_referenced() and symbol.is_global() and not symbol.is_local():
                    yield symbol.get_name(), child
        yield from _global_uses(child)


_Scope = ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda


def _scope_uses(tree: ast.Module, name: str, line: int) -> ast.Name | None:
    """The first use of ``name`` in the function (or lambda) that starts on ``line``."""
    for scope in ast.walk(tree):
        if isinstance(scope, _Scope) and scope.lineno == line:
            for node in ast.walk(scope):
                if isinstance(node, ast.Name) and node.id == name:
                    return node
    return None


def _stores_of(method: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    names = []
    for node in ast.walk(method):
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            name = self_attribute(node)
            if name is not None and f"self.{name}" not in names:
                names.append(f"self.{name}")
    return names


def _undefined_message(name: str, tree: ast.Module) -> str:
    for cls in tree.body:
        if isinstance(cls, ast.ClassDef):
            local = _locals_by_method(cls)
            if name in local:
                method, _ = local[name]
                owner = method.name
                stored = _stores_of(method)
                kept = f" (it keeps {', '.join(stored[:6])})" if stored else ""
                return (
                    f"{name} is a local variable of {owner} and does not exist here: use what "
                    f"{owner} stored on the skill{kept}, or get the value again here"
                )
    if name[:1].islower():
        # A variable, not a class: a local read before any statement of the method assigns it
        # (a fix may have taken out an assignment from a method that returns nothing).
        return (
            f"{name} is not defined: no statement of this method assigns it before it is "
            f"read; assign {name} first, or use what the skeleton defines"
        )
    return (
        f"{name} is not defined: import it (message classes come from the interfaces' "
        "packages, e.g. geometry_msgs.msg) or use what the skeleton defines"
    )


def _undefined_names(facts: SkillFacts) -> list[Finding]:
    table = symtable.symtable(facts.source, "skill.py", "exec")
    known = _module_names(table)
    tree = facts.tree
    uses = [(name, child) for name, child in _global_uses(table) if name not in known]
    # Names a class body reads (its decorators' arguments, constants); a module-level
    # function's parameters are its own.
    class_level = {
        s.get_name()
        for child in table.get_children()
        if str(child.get_type()) == "class"
        for s in child.get_symbols()
        if s.is_referenced() and not s.is_assigned() and s.get_name() not in known
    } - {c.get_name() for c in table.get_children()}
    findings = []
    seen: set[str] = set()
    for name, child in uses:
        use = _scope_uses(tree, name, child.get_lineno())
        if use is not None and name not in seen:
            seen.add(name)
            ros1 = _from_ros1(facts, use) if name == "rospy" else None
            if ros1 is not None:
                findings.append(_finding(ROS1_API, use, *ros1, data={"name": "rospy"}))
                continue
            findings.append(
                _finding(
                    UNDEFINED_NAME,
                    use,
                    _undefined_message(name, tree),
                    _read_from_skill(facts, use, {n for n, c in uses if c is child}),
                    data={"name": name},
                )
            )
    for node in facts.walk(tree):
        if isinstance(node, ast.Name) and node.id in class_level and node.id not in seen:
            seen.add(node.id)
            findings.append(
                _finding(
                    UNDEFINED_NAME, node, _undefined_message(node.id, tree), data={"name": node.id}
                )
            )
    return findings


def _read_from_skill(facts: SkillFacts, use: ast.Name, undefined: set[str]) -> str | None:
    """The statement holding ``use`` with the name read from the skill (``self.name``), when
    the name is a local variable of another method of the class: rotate's completing logged
    ``remaining_angle``, which only execute had. The checks then have execute keep it. Every
    such name the statement reads (of ``undefined``, the names its method reads but never
    assigns) is read from the skill at once: one fix, not one per name."""
    owners = [_locals_by_method(cls) for cls in facts.tree.body if isinstance(cls, ast.ClassDef)]
    theirs = {name for name in undefined if any(name in local for local in owners)}
    if use.id not in theirs:
        return None
    innermost = facts.statement_holding(use)
    if innermost is None:
        return None
    statement = copy.deepcopy(innermost)

    class _ToAttribute(ast.NodeTransformer):
        def visit_Name(self, node: ast.Name) -> ast.AST:
            if node.id in theirs and isinstance(node.ctx, ast.Load):
                return ast.Attribute(ast.Name("self", ast.Load()), node.id, ast.Load())
            return node

    return ast.unparse(_ToAttribute().visit(statement))


_ROS1_LOGGING = {
    "logdebug": "debug",
    "loginfo": "info",
    "logwarn": "warning",
    "logerr": "error",
    "logfatal": "fatal",
}


def _ros2_call(call: ast.expr) -> str | None:
    """The ROS 2 (rclpy) expression for a call of rospy's API, where there is one plain
    counterpart: ``rospy.Duration(0.5)`` is ``rclpy.duration.Duration(seconds=0.5)``."""
    if not isinstance(call, ast.Call):
        return None
    func = call.func
    if not isinstance(func, ast.Attribute):
        return None
    arguments = [ast.unparse(a) for a in call.args]
    if isinstance(func.value, ast.Attribute):  # rospy.Time.now()
        inner = func.value
        if (
            isinstance(inner.value, ast.Name)
            and inner.value.id == "rospy"
            and (inner.attr, func.attr) == ("Time", "now")
            and not arguments
        ):
            return "self.node.get_clock().now()"
        return None
    if not isinstance(func.value, ast.Name) or func.value.id != "rospy" or call.keywords:
        return None
    name = func.attr
    if name in ("Duration", "Time") and len(arguments) <= 2:
        module = "rclpy.duration" if name == "Duration" else "rclpy.time"
        if name == "Time" and arguments in ([], ["0"], ["0.0"]):
            return "rclpy.time.Time()"  # rospy.Time(0): the latest transform
        keywords = [
            f"seconds={a}" if i == 0 else f"nanoseconds={a}" for i, a in enumerate(arguments)
        ]
        return f"{module}.{name}({', '.join(keywords)})"
    if name == "sleep" and len(arguments) == 1:
        return f"time.sleep({arguments[0]})"
    if name in _ROS1_LOGGING and arguments:
        return f"self.node.get_logger().{_ROS1_LOGGING[name]}({', '.join(arguments)})"
    if name == "get_time" and not arguments:
        return "time.time()"
    if name == "is_shutdown" and not arguments:
        return "(not rclpy.ok())"
    return None


def _from_ros1(facts: SkillFacts, use: ast.Name) -> tuple[str, str | None] | None:
    """The message (and, when every use of rospy in the statement has a plain ROS 2
    counterpart, the statement so translated) for ``rospy`` used in a ROS 2 skill
    (``rospy.Duration(0.0)`` for a lookup's timeout): rospy is ROS 1's client library, which
    a ROS 2 robot does not have."""
    statement = facts.statement_holding(use)
    if statement is None:
        return None
    said: list[str] = []

    class _ToRos2(ast.NodeTransformer):
        def visit_UnaryOp(self, node: ast.UnaryOp) -> ast.AST:
            if isinstance(node.op, ast.Not) and _ros2_call(node.operand) == "(not rclpy.ok())":
                said.append(f"{ast.unparse(node)} is rclpy.ok()")
                return ast.parse("rclpy.ok()", mode="eval").body
            return self.generic_visit(node)

        def visit_Call(self, node: ast.Call) -> ast.AST:
            ros2 = _ros2_call(node)
            if ros2 is None:
                return self.generic_visit(node)
            said.append(f"{ast.unparse(node)} is {ros2}")
            return ast.parse(ros2, mode="eval").body

    translated = _ToRos2().visit(copy.deepcopy(statement))
    whole = not any(isinstance(n, ast.Name) and n.id == "rospy" for n in ast.walk(translated))
    message = (
        "rospy is ROS 1's client library, and this skill runs on ROS 2 through rclpy and the "
        "skeleton's node (self.node): "
        + (
            "; ".join(said)
            if said
            else "durations are rclpy.duration.Duration(seconds=...), times "
            "self.node.get_clock().now(), sleeps time.sleep(...), logging "
            "self.node.get_logger().info(...)"
        )
    )
    return message, ast.unparse(translated) if whole and said else None


def _defined(facts: SkillFacts) -> set[str]:
    """The attributes the skill has: what pySkillUp's ``ROS2Skill`` gives it, those pySkillUp
    sets for its parameters, and those the class defines or sets itself."""
    return set(_BASE_ATTRIBUTES) | facts.parameter_attributes | facts.set_attributes


def _latest_messages(facts: SkillFacts) -> list[str]:
    """The skeleton's latest messages, as ``self.odom_msg (Odometry)``."""
    return [f"self.{name} ({type_name})" for name, type_name in facts.latest_messages.items()]


def _hint(name: str, defined: set[str], methods: set[str], latest: list[str]) -> str:
    if name in {"logger", "get_logger", "log"}:
        return "; log with self.node.get_logger()"
    if name in {"get_clock", "create_publisher", "create_subscription", "create_timer"}:
        return f"; it belongs to the node: self.node.{name}(...)"
    close = difflib.get_close_matches(name, sorted(defined), n=1, cutoff=0.75)
    if close and close[0] in methods:
        return f"; did you mean the method self.{close[0]}(...)?"
    if close:
        return f"; did you mean self.{close[0]}?"
    inputs = sorted(f"self.{d}" for d in defined if d.startswith("in_"))
    wanted = name.lower().removeprefix("in_")
    if wanted != name.lower() and inputs:
        # A model asks for an input the capability does not have (a timeout, a tolerance);
        # the class body is the skeleton's, so the value belongs in the method.
        return (
            f"; the capability's inputs are {', '.join(inputs)} and none gives {wanted}: give "
            f"it a value in a local variable of this method ({wanted} = ...)"
        )
    if name.isupper():
        # The worked examples clamp to the skeleton's constants (the resource's requirements),
        # and a model copies the idiom where the capability states no limit. A value it made
        # up would be a limit nobody gave (and may break outVelocity = inVelocity).
        constants = sorted(f"self.{d}" for d in defined if d.isupper())
        if constants:
            return (
                f"; the skeleton's constants (the resource's requirements) are "
                f"{', '.join(constants)} and none is {name}: use one of them, or leave the "
                "limit out"
            )
        return (
            "; the capability states no limits, so the skeleton defines no constants: leave "
            f"the limit out (a value made up for {name} is one nobody gave), and work with the "
            "inputs and the messages"
        )
    if latest:
        # A small model invents attributes for values it means to read from a message.
        return f"; the latest messages are in {', '.join(latest)}: read the field from there"
    return ""


_Method = ast.FunctionDef | ast.AsyncFunctionDef


def _locals_by_method(cls: ast.ClassDef) -> dict[str, tuple[_Method, ast.AST]]:
    """Local variable name -> (the method, its first assignment) over the class's methods."""
    found: dict[str, tuple[_Method, ast.AST]] = {}
    for member in cls.body:
        if not isinstance(member, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        for node in ast.walk(member):
            if isinstance(node, ast.Assign):
                for target in node.targets:
                    if isinstance(target, ast.Name):
                        found.setdefault(target.id, (member, node))
    return found


def _last_assigning_statement(facts: SkillFacts, method: _Method, name: str) -> ast.stmt | None:
    """Where the method is done changing the local variable ``name``: its last assignment,
    or the outermost ``if`` around it, so that the value is kept whichever branch ran (a
    loop that updates it keeps it on every pass); ``None`` if the method assigns it
    nowhere."""
    assignments = [
        node
        for node in facts.walk(method)
        if isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign)
        and any(
            isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store)
            for n in ast.walk(node)
        )
    ]
    if not assignments:
        return None
    found: ast.stmt = max(assignments, key=lambda n: (n.lineno, n.col_offset))
    while isinstance(parent := facts.parent(found), ast.If):
        found = parent
    return found


def _readers(facts: SkillFacts, name: str) -> list[str]:
    return [
        member.name
        for member in facts.definitions
        if any(
            self_attribute(node) == name and isinstance(node.ctx, ast.Load)
            for node in facts.walk(member)
            if isinstance(node, ast.Attribute)
        )
    ]


def _unset_attributes(facts: SkillFacts, cls: ast.ClassDef) -> list[Finding]:
    defined = _defined(facts)
    methods = {m.name for m in facts.definitions}
    latest = _latest_messages(facts)
    local = _locals_by_method(cls)
    called = {id(c.func) for c in facts.calls(cls)}
    findings = []
    seen: set[str] = set()
    for node in facts.nodes:
        name = self_attribute(node)
        if (
            name is None
            or not isinstance(node, ast.Attribute)
            or not isinstance(node.ctx, ast.Load)
            or name in defined
            or name in seen
        ):
            continue
        seen.add(name)
        if name in local:
            # One method keeps in a local variable what others read from the skill: the fix
            # is where it is made, so the finding goes there.
            method, assignment = local[name]
            readers = " and ".join(_readers(facts, name))
            # The value kept on the skill once the method is done changing it.
            last = _last_assigning_statement(facts, method, name)
            keep = (
                f"{ast.unparse(last)}\nself.{name} = {name}"
                if last is not None and isinstance(assignment, ast.Assign)
                else None
            )
            findings.append(
                _finding(
                    LOCAL_READ_AS_ATTRIBUTE,
                    last or assignment,
                    f"{name} is a local variable of {method.name}, but {readers} read self.{name}: "
                    f"assign it as self.{name} = ... here",
                    keep,
                    data={"name": name, "method": method.name},
                )
            )
            continue
        hint = _hint(name, defined, methods, latest)
        message = f"self.{name} is never set in this class{hint}"
        if id(node) in called and not hint.startswith("; did you mean"):
            # A call of a method nobody wrote, e.g. a worked example's goal helper copied
            # along with its state: the class's own helpers are what it can call.
            helpers = sorted(
                f"self.{m}()"
                for m in methods
                if m.startswith("_") and not m.startswith(("__", "_on_"))
            )
            message = (
                f"self.{name}() is not a method of this class; the helpers it has are "
                f"{', '.join(helpers) or 'none'}"
            )
        unlimited = name.isupper() and not any(d.isupper() for d in defined)
        fix = (
            _without_limit(facts, cls, node, name)
            if unlimited
            else _underscored(facts, node, defined) or _unlogged(facts, node)
        )
        findings.append(_finding(ATTRIBUTE_NEVER_SET, node, message, fix, data={"attribute": name}))
    return findings


_LOG_CALLS = frozenset({"debug", "info", "warning", "warn", "error", "fatal", "print"})
_LABEL_ENDS = (", ", "; ", " (", "\n")


def _unlogged(facts: SkillFacts, node: ast.Attribute) -> str | None:
    """The log line holding ``node`` in an f-string's field without that field and its label
    (``f"heading: {self.out_heading:.2f}, timestamp: {self._transform_time:.2f}"``, with an
    attribute nothing sets): a log line reports, and one value less is better than a state
    that raises AttributeError. The text after the field up
    to the next separator (its unit) goes with it."""
    statement = facts.statement_of.get(id(node))
    if not (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Call)):
        return None
    if called_name(statement.value) not in _LOG_CALLS:
        return None
    where = (node.lineno, node.col_offset, node.end_lineno, node.end_col_offset)

    def holds(field: ast.expr) -> bool:
        return any(
            (n.lineno, n.col_offset, n.end_lineno, n.end_col_offset) == where
            for n in ast.walk(field)
            if isinstance(n, ast.Attribute)
        )

    fixed = copy.deepcopy(statement)
    for text in (n for n in ast.walk(fixed) if isinstance(n, ast.JoinedStr)):
        for index, part in enumerate(text.values):
            if not (isinstance(part, ast.FormattedValue) and holds(part.value)):
                continue
            label = text.values[index - 1] if index else None
            if isinstance(label, ast.Constant) and isinstance(label.value, str):
                cut = max(label.value.rfind(end) for end in _LABEL_ENDS)
                label.value = label.value[:cut] if cut >= 0 else ""
            unit = text.values[index + 1] if index + 1 < len(text.values) else None
            if isinstance(unit, ast.Constant) and isinstance(unit.value, str):
                ends = [at for end in _LABEL_ENDS if (at := unit.value.find(end)) >= 0]
                unit.value = unit.value[min(ends) :] if ends else ""
            del text.values[index]
            return ast.unparse(fixed)
    return None


def _underscored(facts: SkillFacts, node: ast.Attribute, defined: set[str]) -> str | None:
    """The simple statement holding ``node`` (``self._map_saver_client``) with the attribute
    the class does set when the two differ only in leading underscores
    (``self._map_saver_save_map_client`` for the skeleton's ``self.map_saver_save_map_client``):
    Python's attribute names are exact, and the misspelt one raises AttributeError."""
    bare = node.attr.lstrip("_")
    meant = [d for d in defined if d != node.attr and d.lstrip("_") == bare]
    statement = facts.statement_of.get(id(node))
    if len(meant) != 1 or statement is None:
        return None
    fixed = copy.deepcopy(statement)
    for part in ast.walk(fixed):
        if isinstance(part, ast.Attribute) and self_attribute(part) == node.attr:
            part.attr = meant[0]
    return ast.unparse(fixed)


class _DropLimit(ast.NodeTransformer):
    """``min(x, self.<name>)`` or ``max(...)`` of two becomes ``x``."""

    def __init__(self, name: str) -> None:
        self.name = name

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        if (
            isinstance(node.func, ast.Name)
            and node.func.id in {"min", "max"}
            and len(node.args) == 2
            and not node.keywords
        ):
            others = [a for a in node.args if self_attribute(a) != self.name]
            if len(others) == 1:
                return others[0]
        return node


def _without_limit(facts: SkillFacts, cls: ast.ClassDef, node: ast.AST, name: str) -> str | None:
    """What the statement that reads the made-up limit ``self.<name>`` at ``node`` comes to
    without the limit, where that is plain: a clamp ``if x > self.<name>: x = self.<name>``
    goes, ``min(x, self.<name>)`` is ``x``; ``None`` otherwise. The capability states no
    limits, so the skill has none to apply, and the attribute would fail when read."""

    def reads(part: ast.AST) -> bool:
        return any(self_attribute(n) == name for n in ast.walk(part))

    statement = facts.statement_holding(node, cls)
    if (
        isinstance(statement, ast.If)
        and not statement.orelse
        and reads(statement.test)
        and all(isinstance(s, ast.Assign) and reads(s.value) for s in statement.body)
    ):
        return ""
    if not isinstance(statement, ast.Assign | ast.AnnAssign | ast.AugAssign | ast.Expr):
        return None
    kept = _DropLimit(name).visit(copy.deepcopy(statement))
    return None if reads(kept) else ast.unparse(kept)


def _none_only_attributes(facts: SkillFacts) -> list[Finding]:
    """Attributes the class only ever sets to ``None`` but reads as an object (``self.start.x``
    after ``self.start = None`` in ``__init__`` and ``resetting``, with the assignment the
    specification asked for forgotten): the read fails whenever it runs."""
    assigned: dict[str, list[int]] = {}
    set_otherwise: set[str] = set()
    for node in facts.nodes:
        if isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                name = self_attribute(target)
                if name is None:
                    set_otherwise |= {n for part in ast.walk(target) if (n := self_attribute(part))}
                elif isinstance(node.value, ast.Constant) and node.value.value is None:
                    assigned.setdefault(name, []).append(node.lineno)
                else:
                    set_otherwise.add(name)
        elif isinstance(node, ast.AugAssign | ast.For | ast.With | ast.NamedExpr):
            set_otherwise |= {
                n
                for part in ast.walk(node.target if not isinstance(node, ast.With) else node)
                if isinstance(part, ast.Attribute)
                and isinstance(part.ctx, ast.Store)
                and (n := self_attribute(part))
            }
    tested = {
        name
        for node in facts.nodes
        if isinstance(node, ast.If | ast.While | ast.IfExp | ast.Assert)
        for part in ast.walk(node.test)
        if (name := self_attribute(part)) is not None
    }
    findings = []
    reported: set[str] = set()
    for node in facts.nodes:
        inner = node.value if isinstance(node, ast.Attribute | ast.Subscript) else None
        if isinstance(node, ast.Call):
            inner = node.func
        name = self_attribute(inner) if inner is not None else None
        if (
            name is None
            or name not in assigned
            or name in set_otherwise | tested | reported
            or (
                isinstance(node, ast.Attribute | ast.Subscript)
                and not isinstance(node.ctx, ast.Load)
            )
        ):
            continue
        reported.add(name)
        lines = ", ".join(str(line) for line in assigned[name])
        findings.append(
            _finding(
                ATTRIBUTE_ONLY_NONE,
                node,
                f"self.{name} is only ever set to None (line {lines}), so {ast.unparse(node)} "
                f"fails whenever it runs: set self.{name} to what it should hold before it is "
                "read (where the specification says to remember it)",
                data={"attribute": name},
            )
        )
    return findings


def _receiver_kind(node: ast.expr, kinds: Mapping[str, str]) -> str | None:
    """The rclpy kind of the object ``node`` evaluates to, where the code makes it plain."""
    name = self_attribute(node)
    if name is not None:
        return kinds.get(name)
    if is_clock_now(node):
        return "time"
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "get_logger"
    ):
        return "logger"
    return None


_KIND_HINTS = {
    "subscription": "; a Subscription only hands each message to its callback, which keeps the "
    "latest one in an attribute: wait until that attribute is set (time.sleep in a loop, or "
    "the skeleton's self._wait_until)",
    "node": "; the time is self.node.get_clock().now(), handles come from create_publisher, "
    "create_subscription, create_client and ActionClient",
    "action_client": "; send a goal with send_goal_async(goal), which gives a future of the goal "
    "handle",
    "client": "; call the service with call_async(request), which gives a future of the response",
    "tf_listener": "; a TransformListener only fills its buffer: look transforms up in the "
    "buffer (lookup_transform)",
    "tf_buffer": "; a Buffer holds the transforms its listener receives: lookup_transform and "
    "can_transform read them",
}


def _latest_message_wait(receiver: ast.expr, defined: set[str]) -> tuple[str, str, str] | None:
    """For ``self.X_subscription`` whose callback keeps ``self.X_msg`` (the skeleton's way):
    a hint, the statement that waits for the first message (which a small model copies more
    readily than advice) and the attribute that holds the latest message."""
    name = self_attribute(receiver)
    if name is None or not name.endswith("_subscription"):
        return None
    latest = name.removesuffix("_subscription") + "_msg"
    if latest not in defined:
        return None
    statement = f'self._wait_until(lambda: self.{latest} is not None, 2.0, "{latest}")'
    return (
        f"; its callback keeps the latest message in self.{latest}: wait for the first one with "
        f"{statement}",
        statement,
        latest,
    )


def _latest_message_fix(
    node: ast.Attribute,
    wait: tuple[str, str, str],
    waited: bool,
    guard: ast.If | None,
    statement: ast.stmt | None,
) -> str | None:
    """What takes the place of the statement that asks a subscription for its message
    (``node``): the wait for the first message, unless the method ``waited`` already, then
    the statement with the latest message in place of the made-up call (``scan =
    self.scan_subscription.get_last_message()`` keeps ``scan``)."""
    ready = "" if waited else wait[1]
    if guard is not None:
        return without_guard(guard, ready)
    if statement is None:
        return None
    if (
        isinstance(statement, ast.Expr)
        and isinstance(statement.value, ast.Call)
        and statement.value.func is node
    ):
        return ready
    asked: ast.expr = node
    for inner in ast.walk(statement):
        if isinstance(inner, ast.Call) and inner.func is node:
            asked = inner
    text = ast.unparse(statement).replace(ast.unparse(asked), f"self.{wait[2]}")
    return "\n".join(filter(None, [ready, text]))


_GOAL_HANDLE = standin_api.members("goal_handle") - standin_api.members("action_client")
"""What rclpy's ClientGoalHandle has that a model asks of the ActionClient."""


_LOGGER_CALLS = RCLPY_API["logger"] - {"name"}
"""The logger's methods: its one data attribute, ``name``, means something else on a handle
(a topic's or a service's name), so a made-up ``X.name`` is not sent to the logger."""


def _owner_of(attribute: str, kind: str) -> str | None:
    """Where ``attribute`` lives when it is the node's or the logger's, not ``kind``'s."""
    if kind != "node" and attribute in RCLPY_API["node"]:
        return "the node: self.node"
    if kind != "logger" and attribute in _LOGGER_CALLS:
        return "the logger: self.node.get_logger()"
    return None


def _goal_handle_hint(receiver: ast.expr) -> str:
    client = ast.unparse(receiver)
    return (
        "; it belongs to the goal handle that sending the goal gives: self.goal_handle = "
        f'self._result_of({client}.send_goal_async(goal), 5.0, "goal acceptance"), then '
        "self.goal_handle.get_result_async() or self.goal_handle.cancel_goal_async()"
    )


def _unknown_api(facts: SkillFacts, guards: Mapping[int, ast.If]) -> list[Finding]:
    defined, kinds = _defined(facts), facts.kinds
    statement_of = facts.statement_of
    method_of = {
        id(node): method.name for method in facts.definitions for node in facts.walk(method)
    }
    # (method, latest-message attribute) whose wait a fix has put in already
    waited: set[tuple[str | None, str]] = set()
    findings = []
    attributes = [n for n in facts.nodes if isinstance(n, ast.Attribute)]
    for node in sorted(attributes, key=lambda n: (n.lineno, n.col_offset)):
        if not isinstance(node.ctx, ast.Load):
            continue
        kind = _receiver_kind(node.value, kinds)
        if kind is None or node.attr in RCLPY_API[kind]:
            continue
        owner = _owner_of(node.attr, kind)
        close = difflib.get_close_matches(node.attr, sorted(RCLPY_API[kind]), n=1, cutoff=0.6)
        wait = None if close or owner else _latest_message_wait(node.value, defined)
        if owner is not None:
            hint = f"; {node.attr} belongs to {owner}.{node.attr}(...)"
        elif kind == "action_client" and node.attr in _GOAL_HANDLE:
            hint = _goal_handle_hint(node.value)
        elif kind == "time" and node.attr in _SECONDS:
            seconds = f"{ast.unparse(node.value)}.nanoseconds / 1e9"
            hint = f"; its seconds are {seconds}"
        elif close:
            hint = f"; did you mean {close[0]}?"
        elif wait is not None:
            hint = wait[0]
        else:
            hint = _KIND_HINTS.get(kind, "")
        replacement = None
        guard = guards.get(id(node))
        if kind == "publisher" and guard is not None:
            hint = "; a publisher is ready from create_publisher until it is destroyed"
            replacement = without_guard(guard, "")
        elif wait is not None:
            key = (method_of.get(id(node)), wait[2])
            replacement = _latest_message_fix(
                node, wait, key in waited, guard, statement_of.get(id(node))
            )
            waited.add(key)
        elif kind == "time" and node.attr in _SECONDS and id(node) in statement_of:
            statement = ast.unparse(statement_of[id(node)])
            seconds = f"({ast.unparse(node.value)}.nanoseconds / 1e9)"
            for made_up in (f"{ast.unparse(node)}()", ast.unparse(node)):
                statement = statement.replace(made_up, seconds)
            replacement = statement
        elif owner is not None and id(node) in statement_of:
            right = f"{owner.split(': ', 1)[1]}.{node.attr}"
            replacement = ast.unparse(statement_of[id(node)]).replace(ast.unparse(node), right)
        elif _called_alone(node, statement_of):
            instead = _teardown_instead(node, kind, defined)
            if instead is not None:
                hint, replacement = instead
        findings.append(
            _finding(
                UNKNOWN_API_ATTRIBUTE,
                node,
                f"{ast.unparse(node.value)} is {_KIND_WORDS[kind]}, which has no "
                f"{node.attr!r} in rclpy{hint}",
                replacement,
                data={"receiver": ast.unparse(node.value), "kind": kind, "attribute": node.attr},
            )
        )
    return findings


_SECONDS = frozenset({"seconds", "sec", "secs", "to_sec", "to_seconds", "total_seconds"})
"""What a model reads for the seconds of an rclpy Time (ROS 1's and datetime's names)."""
_TEARDOWN = frozenset({"destroy", "shutdown", "unregister", "close", "stop", "cleanup"})
"""Methods a model calls to tear a handle down that has no such method."""
_CANCEL_ALL = frozenset({"cancel_all_goals", "cancel_goal", "cancel_goals", "cancel", "stop"})
"""What a model calls on an ActionClient to cancel what it sent (ROS 1's actionlib names)."""


def _called_alone(node: ast.Attribute, statement_of: Mapping[int, ast.stmt]) -> bool:
    """Whether ``node`` is called as a statement of its own (``X.m(...)``, result unused)."""
    statement = statement_of.get(id(node))
    return (
        isinstance(statement, ast.Expr)
        and isinstance(statement.value, ast.Call)
        and statement.value.func is node
    )


def _teardown_instead(node: ast.Attribute, kind: str, defined: set[str]) -> tuple[str, str] | None:
    """The hint and the statement(s) that do what a made-up teardown call meant: nothing for
    a TransformListener or a tf2 Buffer (they hold no goal or resource of their own to end;
    rclpy's Buffer has no destroy, and a skill that called it failed its cleanup), the skeleton's
    cancel helper for an ActionClient whose helper the class has."""
    if kind in ("tf_listener", "tf_buffer") and node.attr in _TEARDOWN:
        return "; it needs no teardown of its own: leave the call out", ""
    client = self_attribute(node.value)
    if kind != "action_client" or node.attr not in _CANCEL_ALL or client is None:
        return None
    helper = f"_cancel_{client.removesuffix('_client')}_goal"
    if helper not in defined:
        return None
    return (
        f"; the skeleton's self.{helper}(timeout) cancels the goal this client sent",
        f"self.{helper}(5.0)",
    )


def _guards(facts: SkillFacts) -> dict[int, ast.If]:
    """``if X.m():`` and ``if not X.m():`` without ``else``, by the ``X.m`` they test."""
    out: dict[int, ast.If] = {}
    for node in facts.nodes:
        if not isinstance(node, ast.If) or node.orelse:
            continue
        test = node.test.operand if isinstance(node.test, ast.UnaryOp) else node.test
        if isinstance(test, ast.Call) and isinstance(test.func, ast.Attribute) and not test.args:
            out[id(test.func)] = node
    return out


def without_guard(guard: ast.If, readying: str) -> str | None:
    """What ``guard`` comes to once ``readying`` (statements; empty when the handle is always
    ready) has run: those and the body for ``if X.m():``, those alone for ``if not X.m():
    raise ...``; ``None`` for other guards."""
    negated = isinstance(guard.test, ast.UnaryOp) and isinstance(guard.test.op, ast.Not)
    if not negated:
        return "\n".join([*filter(None, [readying]), *(ast.unparse(s) for s in guard.body)])
    if all(isinstance(statement, ast.Raise) for statement in guard.body):
        return readying
    return None


_NESTED = frozenset({"Request", "Response", "Goal", "Result", "Feedback", "Event", "Impl"})


_FIELD_CLASSES = {
    ("Twist", "linear"): "Vector3",
    ("Twist", "angular"): "Vector3",
    ("Pose", "position"): "Point",
    ("Pose", "orientation"): "Quaternion",
    ("Transform", "translation"): "Vector3",
    ("Transform", "rotation"): "Quaternion",
    ("PoseStamped", "pose"): "Pose",
    ("TwistStamped", "twist"): "Twist",
}
"""The geometry messages' fields whose type a model turns into a nested class
(``Twist.Linear`` for a Vector3): every ROS 2 install has these types."""


def _nested_class(node: ast.AST, imports: Mapping[str, str]) -> tuple[str, str] | None:
    """(class, made-up nested class) for ``Twist.Linear``; ``None`` for anything else."""
    if (
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id in imports
        and node.attr[:1].isupper()
        and not node.attr.isupper()
        and node.attr not in _NESTED
    ):
        return node.value.id, node.attr
    return None


class _FieldClasses(ast.NodeTransformer):
    """Puts the field's own class in place of made-up nested ones it knows."""

    def __init__(self, imports: Mapping[str, str]) -> None:
        self.imports = imports
        self.unknown = False

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        nested = _nested_class(node, self.imports)
        if nested is None:
            return self.generic_visit(node)
        known = _FIELD_CLASSES.get((nested[0], nested[1].lower()))
        if known is None:
            self.unknown = True
            return node
        return ast.copy_location(ast.Name(id=known, ctx=node.ctx), node)


def _replacement(statement: ast.stmt, imports: Mapping[str, str]) -> str | None:
    """The simple ``statement`` with the field classes in place, when all are known."""
    fixer = _FieldClasses(imports)
    fixed = fixer.visit(copy.deepcopy(statement))
    return None if fixer.unknown else ast.unparse(fixed)


def _missing_nested_classes(facts: SkillFacts) -> list[Finding]:
    """``Odometry.Pose``: message classes have constants and, for services and actions, the
    request/goal classes, but no classes for their fields. Where the field's type is a known
    geometry message, the finding carries its simple statement with that class in place."""
    statement_of = facts.statement_of
    imports = facts.imports
    findings = []
    for node in facts.walk(facts.tree):
        nested = _nested_class(node, imports)
        if nested is None:
            continue
        owner, made_up = nested
        known = _FIELD_CLASSES.get((owner, made_up.lower()))
        replacement = None
        if known is None:
            hint = "use the field's own type, or no annotation"
        else:
            hint = f"{made_up.lower()} is a {known}: use {known}(...)"
            statement = statement_of.get(id(node))
            replacement = None if statement is None else _replacement(statement, imports)
        findings.append(
            _finding(
                NESTED_MESSAGE_CLASS,
                node,
                f"{owner}.{made_up} does not exist: message classes have no classes for their "
                f"fields; {hint}",
                replacement,
                data={"owner": owner, "name": made_up},
            )
        )
    return findings


_RENAMABLE_MODULES = frozenset({"time", "math", "datetime", "random", "os", "threading"})
"""Standard modules a skill uses whose hiding local variable is renamed; the check imports
them to tell their attributes from the variable's."""


def _module_uses(method: ast.AST, module: str) -> set[tuple[int, int]]:
    """Positions of ``module`` in ``method`` where it is the standard module: the object of an
    attribute the module has (``time.sleep``)."""
    real = importlib.import_module(module)
    return {
        (node.value.lineno, node.value.col_offset)
        for node in ast.walk(method)
        if isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == module
        and hasattr(real, node.attr)
    }


class _Rename(ast.NodeTransformer):
    """Renames the Name nodes at ``where`` to ``new``."""

    def __init__(self, where: set[tuple[int, int]], new: str) -> None:
        self.where = where
        self.new = new

    def visit_Name(self, node: ast.Name) -> ast.Name:
        if (node.lineno, node.col_offset) in self.where:
            return ast.Name(id=self.new, ctx=node.ctx)
        return node


def _renamed_local(method: ast.FunctionDef | ast.AsyncFunctionDef, module: str) -> list[Finding]:
    """Findings that rename a local variable hiding the standard ``module`` everywhere in
    ``method`` (each statement of the method that uses it, with the statement renamed); empty
    when a statement cannot be replaced whole."""
    modules = _module_uses(method, module)
    local = {
        (node.lineno, node.col_offset)
        for node in ast.walk(method)
        if isinstance(node, ast.Name) and node.id == module
    } - modules
    taken = {n.id for n in ast.walk(method) if isinstance(n, ast.Name)} | {
        a.arg for a in ast.walk(method) if isinstance(a, ast.arg)
    }
    new = f"{module}_value"
    for number in itertools.count(2):
        if new not in taken:
            break
        new = f"{module}_value{number}"
    findings = []
    for statement in method.body:
        mine = {
            (n.lineno, n.col_offset) for n in ast.walk(statement) if isinstance(n, ast.Name)
        } & local
        if not mine:
            continue
        if not isinstance(statement, ast.Assign | ast.AnnAssign | ast.Expr | ast.While | ast.If):
            return []
        renamed = _Rename(mine, new).visit(copy.deepcopy(statement))
        findings.append(
            _finding(
                LOCAL_HIDES_MODULE,
                statement,
                f"the local variable {module} hides the module {module} in {method.name}; "
                f"renamed to {new} here",
                ast.unparse(renamed),
                data={"module": module, "method": method.name, "local": new},
            )
        )
    return findings


def _shadowed_modules(facts: SkillFacts) -> list[Finding]:
    """A local variable named like a module the same method uses (``time = distance /
    speed`` then ``time.sleep(...)``): the module is gone inside that method. For the standard
    modules skills use, the variable is renamed in every statement that uses it."""
    modules = facts.modules
    findings = []
    for method in facts.definitions:
        used = {
            node.value.id
            for node in facts.walk(method)
            if isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in modules
        }
        for node in ast.walk(method):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store) and node.id in used:
                used.discard(node.id)
                if node.id in _RENAMABLE_MODULES:
                    renamed = _renamed_local(method, node.id)
                    if renamed:
                        findings += renamed
                        continue
                findings.append(
                    _finding(
                        MODULE_SHADOWED,
                        node,
                        f"{node.id} is the module {node.id}, which {method.name} also uses; a "
                        "local variable of that name hides it in the whole method: name the "
                        "variable differently",
                        data={"module": node.id, "method": method.name},
                    )
                )
    return findings


def _operands(node: ast.AST) -> list[ast.expr]:
    """The operands of a comparison or of arithmetic."""
    if isinstance(node, ast.Compare):
        return [node.left, *node.comparators]
    if isinstance(node, ast.BinOp):
        return [node.left, node.right]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        return [node.operand]
    return []


def _stand_in(
    method: ast.FunctionDef | ast.AsyncFunctionDef, module: str, defined: set[str]
) -> str | None:
    """What a module used as a number most likely stands for in ``method``: its one local
    named after the module (``time_value``) or copied from the input of the module's name
    (``= self.in_time``), else that input."""
    named = {
        target.id
        for node in ast.walk(method)
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name)
        and (
            target.id.startswith(f"{module}_")
            or (self_attribute(node.value) == f"in_{module}" if node.value else False)
        )
    }
    if len(named) == 1:
        return named.pop()
    return f"self.in_{module}" if not named and f"in_{module}" in defined else None


def _modules_as_numbers(facts: SkillFacts) -> list[Finding]:
    """A module compared or computed with (``while time.monotonic() - start < time:``, after a
    local ``time`` was renamed in one statement and not the next): it raises TypeError when
    it runs. When the method has one local that
    stands for it, or the capability an input of its name, the statement uses that."""
    modules = facts.modules
    defined = _defined(facts)
    findings = []
    for method in facts.definitions:
        stored = {
            n.id
            for n in facts.walk(method)
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)
        }
        for node in facts.walk(method):
            for operand in _operands(node):
                if not (
                    isinstance(operand, ast.Name)
                    and operand.id in modules
                    and operand.id not in stored
                ):
                    continue
                message = (
                    f"`{ast.unparse(node)}` uses the module {operand.id} as a number, which "
                    "raises TypeError when it runs"
                )
                stand_in = _stand_in(method, operand.id, defined)
                statement = facts.statement_holding(operand, method)
                if stand_in is None or statement is None:
                    findings.append(
                        _finding(
                            MODULE_AS_NUMBER,
                            operand,
                            message + ": use the value meant",
                            data={"module": operand.id},
                        )
                    )
                    continue
                where = {(operand.lineno, operand.col_offset)}
                renamed = _Rename(where, stand_in).visit(copy.deepcopy(statement))
                findings.append(
                    _finding(
                        MODULE_AS_NUMBER,
                        operand,
                        f"{message}; the fix uses {stand_in}",
                        ast.unparse(renamed),
                        data={"module": operand.id},
                    )
                )
    return findings


def _signature(method: ast.FunctionDef) -> inspect.Signature | None:
    """The signature of a method of the class without ``self`` (defaults stand in as
    ``None``); None for a static or class method or a property."""
    if any(
        ast.unparse(d) in {"staticmethod", "classmethod", "property"} for d in method.decorator_list
    ):
        return None
    arguments = method.args
    positional = [*arguments.posonlyargs, *arguments.args][1:]
    first_default = len(positional) - len(arguments.defaults)
    kind = inspect.Parameter
    parameters = [
        kind(
            a.arg,
            kind.POSITIONAL_ONLY if a in arguments.posonlyargs else kind.POSITIONAL_OR_KEYWORD,
            default=None if index >= first_default else kind.empty,
        )
        for index, a in enumerate(positional)
    ]
    if arguments.vararg is not None:
        parameters.append(kind(arguments.vararg.arg, kind.VAR_POSITIONAL))
    parameters += [
        kind(a.arg, kind.KEYWORD_ONLY, default=kind.empty if d is None else None)
        for a, d in zip(arguments.kwonlyargs, arguments.kw_defaults, strict=True)
    ]
    if arguments.kwarg is not None:
        parameters.append(kind(arguments.kwarg.arg, kind.VAR_KEYWORD))
    return inspect.Signature(parameters)


def _used_nothing(facts: SkillFacts) -> list[Finding]:
    """Results used of the class's own methods that are annotated to return None (``result =
    self._send_x_goal(goal, 5.0)`` and then ``result.success``): the value is always None.
    An assignment of it is fixed to the call alone."""
    nothing = {
        node.name: node
        for node in facts.functions
        if isinstance(node.returns, ast.Constant) and node.returns.value is None
    }
    methods = {node.name for node in facts.definitions}
    findings = []
    for method in facts.functions:
        # A statement's own call, a callback's lambda and a return pass the None on harmlessly.
        plain = {
            id(n.value if isinstance(n, ast.Expr | ast.Return) else n.body)
            for n in facts.walk(method)
            if isinstance(n, ast.Expr | ast.Return | ast.Lambda)
        }
        assigned = {
            id(s.value): s.targets[0]
            for s in facts.walk(method)
            if isinstance(s, ast.Assign) and len(s.targets) == 1
        }
        tested = _tested_calls(method)
        for call in facts.walk(method):
            name = self_attribute(call.func) if isinstance(call, ast.Call) else None
            if name not in nothing or id(call) in plain:
                continue
            doc = (ast.get_docstring(nothing[name]) or "").split(";")[0].replace("``", "")
            about = f" ({' '.join(doc.split())})" if doc else ""
            message = (
                f"self.{name}() returns nothing (its definition, line {nothing[name].lineno}, "
                f"says -> None){about}, so its value is always None: call it as a statement "
                "of its own"
            )
            fix = ast.unparse(call) if id(call) in assigned else None
            wait = _result_wait(name, methods, assigned.get(id(call)), method)
            if fix is not None and wait is not None:
                message += f", then wait for the result: {wait}"
                fix += f"\n{wait}"
            guard = tested.get(id(call))
            if guard is not None and _raises(nothing[name]):
                statement, negated = guard
                message += (
                    f". It raises when it fails, so once it returns, what it waits for has "
                    f"happened: the fix calls it and goes on with the "
                    f"{'else branch' if negated else 'body'} of this `if`"
                )
                kept = statement.orelse if negated else statement.body
                fix = "\n".join([ast.unparse(call), *(ast.unparse(s) for s in kept)])
            findings.append(_finding(NONE_RESULT_USED, call, message, fix, data={"method": name}))
    return findings


def _tested_calls(method: ast.FunctionDef) -> dict[int, tuple[ast.If, bool]]:
    """Calls that are the whole test of an ``if`` (``if self._wait_until(...):``, or with
    ``not``), with their statement and whether the test negates them."""
    tested: dict[int, tuple[ast.If, bool]] = {}
    for statement in ast.walk(method):
        if not isinstance(statement, ast.If):
            continue
        test, negated = statement.test, False
        if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
            test, negated = test.operand, True
        if isinstance(test, ast.Call):
            tested[id(test)] = (statement, negated)
    return tested


def _raises(method: ast.FunctionDef) -> bool:
    """Whether ``method`` raises on some path of its own: a helper that returns nothing and
    raises when what it waits for does not come (the skeleton's ``_wait_until``) has
    succeeded when it returns."""
    return any(isinstance(node, ast.Raise) for node in ast.walk(method))


RESULT_WAIT_SECONDS = 60.0
"""The timeout of a result wait that the checks write in place of a goal send's value: long
enough for a motion across a room, short enough that a lost goal ends the skill."""


def _result_wait(
    name: str, methods: set[str], target: ast.expr | None, method: ast.FunctionDef
) -> str | None:
    """``result = self._x_result(60.0)`` when ``name`` is the skeleton's goal send of an
    action (``_send_x_goal``) with a result helper, and the method reads the variable
    ``target`` that was meant to hold the result (``result = self._send_x_goal(...)`` and
    then ``result.success``)."""
    sent = re.fullmatch(r"_send_(\w+)_goal", name)
    if sent is None or f"_{sent.group(1)}_result" not in methods:
        return None
    if not isinstance(target, ast.Name):
        return None
    read = any(
        isinstance(n, ast.Name) and n.id == target.id and isinstance(n.ctx, ast.Load)
        for n in ast.walk(method)
    )
    if not read:
        return None
    return f"{target.id} = self._{sent.group(1)}_result({RESULT_WAIT_SECONDS!r})"


def _mismatched_calls(facts: SkillFacts) -> list[Finding]:
    """Calls of the class's own methods with arguments their definitions do not take (a helper
    written with a parameter more than the call that asked for it gives): found at the
    definition of an undocumented helper, at the call of a documented one (the skeleton's)."""
    signatures = {
        node.name: (node, signature)
        for node in facts.functions
        if (signature := _signature(node)) is not None
    }
    statement_of = facts.statement_of
    findings = []
    for call in (n for n in facts.nodes if isinstance(n, ast.Call)):
        name = self_attribute(call.func)
        if name not in signatures:
            continue
        starred = any(isinstance(a, ast.Starred) for a in call.args)
        if starred or any(k.arg is None for k in call.keywords):
            continue
        method, signature = signatures[name]
        try:
            signature.bind(*call.args, **{str(k.arg): k.value for k in call.keywords})
        except TypeError as error:
            if ast.get_docstring(method) is None:
                # A helper written for this call (as generation asks for them) should take
                # what the call gives; the skeleton's documented helpers stay as they are.
                findings.append(
                    _finding(
                        HELPER_CALL_MISMATCH,
                        method,
                        f"{name}{signature} does not take what its call at line {call.lineno} "
                        f"gives ({ast.unparse(call)}: {error}); take the arguments the call "
                        "gives, with a default for any other",
                        data={"method": name, "signature": str(signature)},
                    )
                )
            else:
                findings.append(
                    _finding(
                        METHOD_CALL_MISMATCH,
                        call,
                        f"self.{name}() is called with arguments its definition (line "
                        f"{method.lineno}: {name}{signature}) does not take: {error}; make the "
                        "call and the definition agree",
                        _with_timeout(call, signature, statement_of),
                        data={"method": name, "signature": str(signature)},
                    )
                )
    return findings


HELPER_TIMEOUT = 2.0
"""The seconds the checks give a skeleton helper's wait whose call left its timeout out."""


def _with_timeout(
    call: ast.Call, signature: inspect.Signature, statement_of: Mapping[int, ast.stmt]
) -> str | None:
    """The statement holding ``call`` with :data:`HELPER_TIMEOUT` added as its last argument,
    when the timeout is all the call leaves out (``self._transform("map", "base_link")``):
    the skeleton's waits take their timeout without a default, so that none waits forever."""
    statement = statement_of.get(id(call))
    parameters = list(signature.parameters)
    if statement is None or "timeout" not in parameters or call.keywords:
        return None
    if len(call.args) != parameters.index("timeout") or len(call.args) + 1 != len(parameters):
        return None

    def timed(node: ast.expr) -> ast.expr:
        if isinstance(node, ast.Call):
            node.args.append(ast.Constant(HELPER_TIMEOUT))
        return node

    return with_node_replaced(statement, call, timed)


def check_names(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``names``) for names, attributes and rclpy calls nothing defines, and
    modules a local variable hides."""
    findings = _undefined_names(facts) + _missing_nested_classes(facts)
    cls = facts.skill
    if cls is not None:
        guards = _guards(facts)
        findings += _unset_attributes(facts, cls) + _unknown_api(facts, guards)
        findings += _shadowed_modules(facts) + _modules_as_numbers(facts)
        findings += _mismatched_calls(facts) + _none_only_attributes(facts) + _used_nothing(facts)
        findings += _overwritten_methods(facts) + _rclpy_calls(facts)
        findings += _waited_futures(facts, cls, guards)
    return findings


_FUTURE_API = standin_api.members("future")
"""What an rclpy Future has and the response or result it gives does not."""


def _waited_futures(
    facts: SkillFacts, cls: ast.ClassDef, guards: Mapping[int, ast.If]
) -> list[Finding]:
    """A future's methods asked of what the skeleton's ``self._result_of(future, ...)``
    returned: the response (or result) itself, a message, which has none of them
    (``if not response.done(): raise ...`` raises AttributeError when it runs). A guard that
    only raises goes; ``X.result()`` becomes ``X``."""
    calls = {id(n.func): n for n in facts.calls(cls) if not n.args}
    statement_of = facts.statement_of
    findings = []
    for method in facts.functions:
        # what a self attribute holds counts in every method, a local in its own
        waited = {
            ast.unparse(node.targets[0]): node.lineno
            for root in (cls, method)
            for node in facts.walk(root)
            if isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and (root is method or self_attribute(node.targets[0]) is not None)
            and isinstance(node.value, ast.Call)
            and self_method(node.value) == "_result_of"
        }
        for node in facts.walk(method):
            if not (
                isinstance(node, ast.Attribute)
                and node.attr in _FUTURE_API
                and id(node) in calls
                and ast.unparse(node.value) in waited
            ):
                continue
            held = ast.unparse(node.value)
            replacement = None
            guard = guards.get(id(node))
            statement = statement_of.get(id(node))
            if guard is not None and node.attr == "done":
                replacement = without_guard(guard, "")
            elif node.attr == "result" and statement is not None:
                replacement = with_text_in_place(statement, calls[id(node)], held)
            findings.append(
                _finding(
                    FUTURE_METHOD_ON_RESULT,
                    node,
                    f"{held} holds what self._result_of(...) waited for at line {waited[held]}: "
                    f"the response or result itself, not a future, and it has no {node.attr!r}; "
                    f"read its fields ({held}.<field>)",
                    replacement,
                    data={"name": held},
                )
            )
    return findings


_RCLPY_SIGNATURES = {
    (kind, method): standin_api.signature(kind, method)
    for kind, method in (
        ("client", "call_async"),
        ("client", "call"),
        ("client", "wait_for_service"),
        ("action_client", "send_goal_async"),
        ("action_client", "send_goal"),
        ("action_client", "wait_for_server"),
        ("publisher", "publish"),
    )
}
"""What rclpy's methods take (Humble and Jazzy), for the calls a model gets wrong."""


def _rclpy_calls(facts: SkillFacts) -> list[Finding]:
    """Calls of rclpy handles' methods with arguments the methods do not take, above all a
    timeout handed to a call that gives a future at once (``client.call_async(request, 5.0)``:
    rclpy's call_async takes the request only, and raises TypeError), and a number where
    send_goal_async takes its feedback callback. A service call's timeout moves to the
    skeleton's ``self._result_of``, which waits for the response."""
    defined, kinds = _defined(facts), facts.kinds
    statement_of = facts.statement_of
    findings = []
    for call in (n for n in facts.nodes if isinstance(n, ast.Call)):
        if not isinstance(call.func, ast.Attribute):
            continue
        kind = _receiver_kind(call.func.value, kinds)
        signature = _RCLPY_SIGNATURES.get((kind or "", call.func.attr))
        if signature is None or any(isinstance(a, ast.Starred) for a in call.args):
            continue
        if any(k.arg is None for k in call.keywords):
            continue
        handle = ast.unparse(call.func.value)
        method = call.func.attr
        try:
            bound = signature.bind(*call.args, **{str(k.arg): k.value for k in call.keywords})
        except TypeError as error:
            message = f"{handle}.{method}{signature} does not take these arguments ({error})"
            replacement = None
            if method == "call_async" and len(call.args) == 2 and not call.keywords:
                request, timeout = (ast.unparse(a) for a in call.args)
                waited = 'self._result_of({}.call_async({}), {}, "the response")'
                message = (
                    f"{handle}.call_async(request) takes the request only, not {timeout}: it "
                    "gives a future at once; wait for the response with "
                    + waited.format(handle, "request", timeout)
                )
                statement = statement_of.get(id(call))
                if "_result_of" in defined and statement is not None:
                    replacement = with_text_in_place(
                        statement, call, waited.format(handle, request, timeout)
                    )
            findings.append(
                _finding(
                    RCLPY_CALL_ARGUMENTS,
                    call,
                    message,
                    replacement,
                    data={"handle": handle, "method": method},
                )
            )
            continue
        feedback = bound.arguments.get("feedback_callback")
        if isinstance(feedback, ast.Constant) and isinstance(feedback.value, int | float):
            findings.append(
                _finding(
                    FEEDBACK_CALLBACK_NOT_TIMEOUT,
                    call,
                    f"{handle}.{method}() takes the goal and a feedback callback, not a "
                    f"timeout ({ast.unparse(feedback)}): send the goal with "
                    f"{handle}.{method}(goal) and wait for the goal handle with "
                    "self._result_of(future, timeout, what)",
                    data={"handle": handle, "method": method, "argument": ast.unparse(feedback)},
                )
            )
    return findings


def _overwritten_methods(facts: SkillFacts) -> list[Finding]:
    """A method of the class replaced by a value (``self._closest_reading =
    self._closest_reading(self.scan_msg)``): every later call of it raises TypeError
    ('tuple' object is not callable). The
    fix keeps the value in a local of the method's name."""
    methods = {n.name for n in facts.definitions}
    findings = []
    for node in facts.nodes:
        if not isinstance(node, ast.Assign) or len(node.targets) != 1:
            continue
        name = self_attribute(node.targets[0])
        if name not in methods:
            continue
        local = name.strip("_") or "value"
        findings.append(
            _finding(
                METHOD_OVERWRITTEN,
                node,
                f"self.{name} is a method of the skill, and this assignment replaces it with a "
                f"value: every later self.{name}(...) raises TypeError (the value is not "
                f"callable). Keep the value in a local: {local} = {ast.unparse(node.value)}",
                f"{local} = {ast.unparse(node.value)}",
                data={"method": name, "local": local},
            )
        )
    return findings
