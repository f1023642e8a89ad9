"""A skill that never commands the motion its capability asks for, and a loop that waits for
the robot to move when nothing commands it to (check ``motion``).

The default model's cap2skill collision avoidance in the evaluation at d678df9 copied its
velocity inputs into its outputs, slept for the requested time and stopped the base: no
velocity was ever published, and the simulation saw a robot that never moved. A skill whose
capability takes a speed (an input in m/s or rad/s) and which has a velocity publisher is
flagged when no method of it publishes a command other than a zero one or sends a goal.

The default model's cap2skill rotate in the evaluation at d678df9 read the heading once and
then looped ``while math.degrees(abs(self._closest_reading(self.scan_msg)[1] - last_yaw)) <
self.in_degree: time.sleep(0.05)``: no velocity was published anywhere in the skill, so the
robot stood still, the reading never changed and the run gave up at the state's deadline.
The run can only say that the state did not return; this check says why before anything
runs.

A ``while`` loop of ``starting`` or ``execute`` is flagged when the skill has a velocity
publisher (a ``Twist`` or ``TwistStamped`` handle), the loop's condition, or an ``if`` in it
that leaves it, compares a measured number (see :func:`~skillwright.validation.equality.
measurements`) with ``<``, ``>``, ``<=`` or ``>=`` (it waits for progress), and neither that
state, nor ``starting`` before it, nor a method of the skill either calls, publishes a command
other than a zero one or sends a goal or a request.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping

from skillwright.capability.model import Capability
from skillwright.validation.equality import measurements
from skillwright.validation.model import Finding
from skillwright.validation.names import self_attribute
from skillwright.validation.stops import zero_velocity
from skillwright.validation.syntax import error_at, self_method

__all__ = ["check_motion"]

_VELOCITY = frozenset({"Twist", "TwistStamped"})
_SENDS = ("send_goal", "call_async", "call")
_ORDER = frozenset({ast.Lt, ast.Gt, ast.LtE, ast.GtE})


def check_motion(
    cls: ast.ClassDef, states: Mapping[str, ast.FunctionDef], capability: Capability
) -> list[Finding]:
    """Findings (check ``motion``) for a skill that never commands the velocity its
    capability asks for, and for loops that wait for progress nothing commands."""
    publishers = _velocity_publishers(cls)
    if not publishers:
        return []
    methods = {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef)}
    speeds = _speed_inputs(capability)
    execute = states.get("execute")
    if (
        speeds
        and execute is not None
        and _written(execute)
        and not any(_commands(m, methods) for m in methods.values())
    ):
        handles = ", ".join(f"self.{p}" for p in sorted(publishers))
        return [
            error_at(
                "motion",
                execute,
                f"the capability asks for a velocity ({', '.join(speeds)}), but no method of "
                f"the skill publishes one other than zero on {handles} or sends a goal: the "
                "robot never moves. Publish the command in execute (command = Twist(), its "
                f"fields from the inputs, self.{sorted(publishers)[0]}.publish(command)) and "
                "stop the base when done",
            )
        ]
    is_measured = measurements(cls)
    findings: list[Finding] = []
    for state in ("starting", "execute"):
        method = states.get(state)
        if method is None:
            continue
        if _commands(method, methods):
            return findings
        for loop in (n for n in ast.walk(method) if isinstance(n, ast.While)):
            test = _progress_test(loop, is_measured)
            if test is None:
                continue
            handles = ", ".join(f"self.{p}" for p in sorted(publishers))
            findings.append(
                error_at(
                    "motion",
                    loop,
                    f"this loop waits for the robot to move (`{ast.unparse(test)}` compares a "
                    f"reading), but nothing in {state}"
                    + (" or starting" if state == "execute" else "")
                    + f" commands a motion: no velocity is published on {handles} and no goal "
                    "is sent, so the reading never changes and the loop runs until the state "
                    "gives up. Publish the command before the loop (command = Twist(), set its "
                    f"fields, self.{sorted(publishers)[0]}.publish(command)) and stop the base "
                    "after it",
                )
            )
    return findings


_SPEEDS = frozenset({"m/s", "rad/s", "°/s", "deg/s"})


def _speed_inputs(capability: Capability) -> list[str]:
    """``inVelocityX (m/s)`` for each input of the capability that is a speed."""
    return [
        f"{component.name} ({unit})"
        for parameter in capability.inputs
        for component in parameter.components
        if (unit := (component.unit or parameter.element.unit or "").strip()) in _SPEEDS
    ]


def _written(method: ast.FunctionDef) -> bool:
    """Whether ``method`` has a statement other than a docstring, ``pass``, ``...`` or a
    ``raise NotImplementedError`` (the skeleton's placeholder, which its own check reports)."""
    for statement in method.body:
        if isinstance(statement, ast.Pass) or (
            isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant)
        ):
            continue
        if isinstance(statement, ast.Raise) and "NotImplementedError" in ast.unparse(statement):
            continue
        return True
    return False


def _velocity_publishers(cls: ast.ClassDef) -> set[str]:
    """The attributes the class keeps its velocity publishers in."""
    out = set()
    for node in ast.walk(cls):
        if (
            isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and (name := self_attribute(node.targets[0])) is not None
            and isinstance(node.value, ast.Call)
            and isinstance(node.value.func, ast.Attribute)
            and node.value.func.attr == "create_publisher"
            and node.value.args
            and ast.unparse(node.value.args[0]).rsplit(".", 1)[-1] in _VELOCITY
        ):
            out.add(name)
    return out


def _commands(
    node: ast.AST,
    methods: Mapping[str, ast.FunctionDef],
    depth: int = 3,
    seen: frozenset[str] = frozenset(),
) -> bool:
    """Whether ``node`` publishes a command other than a zero velocity, sends a goal or a
    request, or calls a method of the skill that does (``depth`` levels deep)."""
    for inner in ast.walk(node):
        if not isinstance(inner, ast.Call) or not isinstance(inner.func, ast.Attribute):
            continue
        attr = inner.func.attr
        if attr == "publish" and inner.args and not zero_velocity(inner.args[0]):
            return True
        if attr.startswith(_SENDS):
            return True
        called = self_method(inner)
        callee = methods.get(called) if called is not None else None
        if (
            callee is not None
            and called not in seen
            and depth > 0
            and _commands(callee, methods, depth - 1, seen | {called or ""})
        ):
            return True
    return False


def _progress_test(loop: ast.While, is_measured: Callable[[ast.expr], bool]) -> ast.expr | None:
    """The comparison of a reading with ``<``, ``>``, ``<=`` or ``>=`` the loop waits on: in
    its condition, or in an ``if`` of its body that leaves it."""
    tests = [loop.test] + [
        s.test
        for s in ast.walk(loop)
        if isinstance(s, ast.If) and any(isinstance(b, ast.Break | ast.Return) for b in s.body)
    ]
    for test in tests:
        for node in ast.walk(test):
            if (
                isinstance(node, ast.Compare)
                and all(type(op) in _ORDER for op in node.ops)
                and any(is_measured(side) for side in (node.left, *node.comparators))
            ):
                return node
    return None
