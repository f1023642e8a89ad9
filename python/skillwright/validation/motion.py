"""A skill that never commands the motion its capability asks for, and a loop that waits for
the robot to move when nothing commands it to (check ``motion``).

A skill that copies its velocity inputs into its outputs, sleeps for the requested time and
stops the base has moved nothing: a base moves only on the velocity commands it receives. A
skill whose capability takes a speed (an input in m/s or rad/s) and which has a velocity
publisher is flagged when no method of it publishes a command other than a zero one or sends
a goal.

A loop that waits for a reading to change (``while abs(self._yaw(...) - start) <
self.in_angle: time.sleep(0.05)``) while nothing in the skill commands the base waits
forever: the robot stands still, the reading never changes and the state runs into its
deadline, which a run can only report as a state that did not return.

A ``while`` loop of ``starting`` or ``execute`` is flagged when the skill has a velocity
publisher (a ``Twist`` or ``TwistStamped`` handle), the loop's condition, or an ``if`` in it
that leaves it, compares a measured number (see :attr:`~skillwright.validation.facts.SkillFacts.
is_measured`) with ``<``, ``>``, ``<=`` or ``>=`` (it waits for progress), and neither that
state, nor ``starting`` before it, nor a method of the skill either calls, publishes a command
other than a zero one or sends a goal or a request.

A forward command published once before a loop that waits for the distance moves a real
base for half a second only: ros2_control's diff_drive_controller (and the run's base, which
follows it) drops a velocity command that is not repeated within its timeout of 0.5 s, so
the robot stops and the state runs into its deadline. A ``while`` loop of any method that sleeps,
spins or calls a wait helper is flagged when the last velocity command published in its block
before it is not a stop, and the loop neither publishes on that publisher (outside the
branches that leave it) nor commands otherwise, and no timer of the skill could repeat it. The
fix publishes the same command at the start of every pass.

The same command published once and followed, in the same block and outside any loop, by a
``time.sleep`` of more than half a second (or of a duration worked out at run time) is the
open-loop drive of the paper's move forward: the robot moves for half a second of the time
asked. The fix publishes it every 0.05 s until the time is up.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping

from skillwright.capability.model import Capability
from skillwright.rules.behaviour import (
    NO_MOTION_COMMANDED,
    ONE_SHOT_COMMAND_LOOP,
    ONE_SHOT_COMMAND_SLEEP,
    UNMOVED_LOOP,
)
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.stops import loop_publishes, zero_velocity
from skillwright.validation.syntax import blocks, called_name, error_at, self_method

__all__ = ["check_motion"]

_VELOCITY = frozenset({"Twist", "TwistStamped"})
_SENDS = ("send_goal", "call_async", "call")
_ORDER = frozenset({ast.Lt, ast.Gt, ast.LtE, ast.GtE})


def check_motion(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``motion``) for a skill that never commands the velocity its
    capability asks for, and for loops that wait for progress nothing commands."""
    publishers = _velocity_publishers(facts)
    if not publishers:
        return []
    methods = facts.methods
    states = facts.states
    speeds = _speed_inputs(facts.capability)
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
                NO_MOTION_COMMANDED,
                execute,
                f"the capability asks for a velocity ({', '.join(speeds)}), but no method of "
                f"the skill publishes one other than zero on {handles} or sends a goal: the "
                "robot never moves. Publish the command in execute (command = Twist(), its "
                f"fields from the inputs, self.{sorted(publishers)[0]}.publish(command)) and "
                "stop the base when done",
            )
        ]
    findings = _repeated_nowhere(facts, publishers)
    is_measured = facts.is_measured
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
                    UNMOVED_LOOP,
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


def _repeated_nowhere(facts: SkillFacts, publishers: set[str]) -> list[Finding]:
    """Findings for loops that wait while the motion command published once before them
    is never published again (see the module's text); none when a timer of the skill could
    repeat it."""
    if facts.skill is None or any(
        isinstance(n, ast.Attribute) and n.attr == "create_timer" for n in facts.walk(facts.skill)
    ):
        return []
    methods = facts.methods
    handles = {f"self.{p}" for p in publishers}
    is_measured = facts.is_measured
    findings = []
    for method in methods.values():
        looped = {
            id(node.body) for node in ast.walk(method) if isinstance(node, ast.For | ast.While)
        }
        for block in blocks(method):
            for index, statement in enumerate(block):
                duration = _long_sleep(statement)
                if duration is not None and id(block) not in looped:
                    sent = _last_motion(block[:index], handles, methods)
                    if sent is not None:
                        findings.append(_sleep_finding(statement, duration, *sent))
                    continue
                if not isinstance(statement, ast.While):
                    continue
                if not _awaits_motion(statement, is_measured):
                    continue
                sent = _last_motion(block[:index], handles, methods)
                if (
                    sent is None
                    or _commands(statement, methods)
                    or _publishes_on(statement, sent[0])
                ):
                    continue
                findings.append(_repeat_finding(statement, *sent))
    return findings


_HOLD = 0.5
"""The longest a base driver keeps a velocity command it has not heard again (ros2_control's
diff_drive_controller's default ``cmd_vel_timeout``)."""


def _long_sleep(statement: ast.stmt) -> ast.expr | None:
    """The duration of ``time.sleep(duration)`` when that is the statement and the duration is
    not a number of at most :data:`_HOLD` seconds."""
    if not (
        isinstance(statement, ast.Expr)
        and isinstance(call := statement.value, ast.Call)
        and ast.unparse(call.func) == "time.sleep"
        and len(call.args) == 1
    ):
        return None
    duration = call.args[0]
    if isinstance(duration, ast.Constant) and isinstance(duration.value, int | float):
        return duration if duration.value > _HOLD else None
    return duration


def _sleep_finding(sleep: ast.stmt, duration: ast.expr, handle: str, call: ast.Call) -> Finding:
    command = ast.unparse(call.args[0])
    publish = f"{handle}.publish({command})"
    return error_at(
        ONE_SHOT_COMMAND_SLEEP,
        sleep,
        f"the velocity command goes out once ({publish} on line {call.lineno}) and the state "
        f"then sleeps for {ast.unparse(duration)} s: a base driver stops when a command is not "
        f"repeated within its timeout (half a second for ros2_control's "
        "diff_drive_controller), so the robot moves for half a second at most. Publish the "
        "command every 0.05 s until the time is up",
        f"deadline = time.monotonic() + {ast.unparse(duration)}\n"
        f"while time.monotonic() < deadline:\n    {publish}\n    time.sleep(0.05)",
    )


def _repeat_finding(loop: ast.While, handle: str, call: ast.Call) -> Finding:
    command = ast.unparse(call.args[0])
    publish = f"{handle}.publish({command})"
    first = loop.body[0]
    plain = isinstance(first, ast.Expr | ast.Assign | ast.AugAssign | ast.AnnAssign)
    return error_at(
        ONE_SHOT_COMMAND_LOOP,
        first if plain else loop,
        f"the velocity command goes out once, before this loop ({publish} on line "
        f"{call.lineno}), and never again while the loop waits: a base driver stops when a "
        "command is not repeated within its timeout (half a second for ros2_control's "
        "diff_drive_controller), so the robot halts and what the loop waits for never comes. "
        "Publish the command again at the start of every pass",
        f"{publish}\n{ast.unparse(first)}" if plain else None,
    )


def _awaits_motion(loop: ast.While, is_measured: Callable[[ast.expr], bool]) -> bool:
    """Whether ``loop`` waits for the robot to get somewhere: it sleeps, spins or calls a
    wait helper, and it compares a reading for progress or runs ``while True`` until a
    branch leaves it (a loop that waits for a first message is not one)."""
    waits = False
    for node in ast.walk(loop):
        if isinstance(node, ast.Call):
            name = called_name(node)
            waits = waits or name in {"sleep", "spin_once"} or name.startswith("_wait")
    forever = isinstance(loop.test, ast.Constant) and loop.test.value is True
    return waits and (forever or _progress_test(loop, is_measured) is not None)


def _last_motion(
    before: list[ast.stmt], handles: set[str], methods: Mapping[str, ast.FunctionDef]
) -> tuple[str, ast.Call] | None:
    """(handle, call) of the last velocity command published in ``before``, when it is not a
    stop. A call of a method of the skill that publishes only zero velocities on these
    handles (the skeleton's ``_stop_base``, a model's ``_publish_zero``) is a stop too: after
    it the base is told to stand still, which it also does when no command follows (the
    driver's timeout), so a loop that waits for it to come to rest needs no repetition."""
    calls: list[tuple[str, ast.Call, bool]] = []
    for statement in before:
        for node in ast.walk(statement):
            if not isinstance(node, ast.Call):
                continue
            if (
                isinstance(node.func, ast.Attribute)
                and node.func.attr == "publish"
                and (handle := ast.unparse(node.func.value)) in handles
                and len(node.args) == 1
            ):
                calls.append((handle, node, _is_stop(node.args[0])))
            elif (
                (called := self_method(node)) is not None
                and called in methods
                and _stops_only(methods[called], handles)
            ):
                calls.append(("", node, True))
    if not calls:
        return None
    handle, last, stop = max(calls, key=lambda c: (c[1].lineno, c[1].col_offset))
    return None if stop else (handle, last)


def _stops_only(method: ast.FunctionDef, handles: set[str]) -> bool:
    """Whether ``method`` publishes on ``handles`` and every message it publishes there is a
    zero velocity."""
    published = [
        node.args[0]
        for node in ast.walk(method)
        if isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "publish"
        and ast.unparse(node.func.value) in handles
        and len(node.args) == 1
    ]
    return bool(published) and all(_is_stop(message) for message in published)


def _is_stop(message: ast.expr) -> bool:
    """A zero ``Twist()``, or ``Twist(linear=Vector3(x=0.0))`` and the like: a velocity
    message built with zeros only."""
    if zero_velocity(message):
        return True
    numbers = [
        n.value
        for n in ast.walk(message)
        if isinstance(n, ast.Constant) and isinstance(n.value, int | float)
    ]
    names = [n for n in ast.walk(message) if isinstance(n, ast.Name)]
    return (
        bool(numbers)
        and all(v == 0 for v in numbers)
        and all(n.id in _VELOCITY or n.id == "Vector3" for n in names)
    )


def _publishes_on(loop: ast.While, handle: str) -> bool:
    """Whether ``loop`` publishes on ``handle`` outside the branches that leave it (a stop
    on every pass included: the check ``stops`` judges those)."""
    return any(publisher == handle for publisher, _ in loop_publishes(loop.body, {}))


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


def _velocity_publishers(facts: SkillFacts) -> set[str]:
    """The attributes the class keeps its velocity publishers in."""
    return {
        h.attribute
        for h in facts.handles
        if h.attribute is not None
        and h.made.maker == "create_publisher"
        and h.made.type_written in _VELOCITY
    }


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
        if attr == "publish" and inner.args and not _is_stop(inner.args[0]):
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
