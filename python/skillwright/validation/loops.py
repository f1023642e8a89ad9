"""Loops that wait for the robot without ever waiting (check ``waits``).

A state that loops until odometry shows a distance, a deadline passes or a goal ends expects
time to pass inside the loop. Without a sleep (or a helper that sleeps) in it, the loop spins
a CPU core, publishes its command as fast as Python can, and on a single-threaded executor
keeps the very callbacks it waits for from running. Small models write such loops often; the
sandboxed run finds them too, but only after a slow run, and a reader of the file should not
have to.

A loop counts as waiting for the robot when its condition or body reads the clock, calls
``publish``, reads an attribute that a callback of the class sets (a subscription's latest
message, an action's feedback) or asks a future whether it is done. It waits when it calls
``time.sleep``, a rate's ``sleep``, a ``wait_for_*``/``spin*`` function, or a method of the
class that does one of these (the skeleton's ``_wait_until``, ``_result_of``, ``_transform``).
"""

from __future__ import annotations

import ast

from skillwright.validation.model import Finding

__all__ = ["check_waits", "waits_error"]

_CLOCK = frozenset({"monotonic", "time", "perf_counter", "now", "get_clock"})
_WAITING = frozenset({"sleep", "spin", "spin_once", "spin_until_future_complete"})


def waits_error(statement: ast.stmt, message: str, replacement: str | None) -> Finding:
    """An error of the ``waits`` check at ``statement``."""
    return Finding(
        check="waits",
        severity="error",
        line=statement.lineno,
        column=statement.col_offset + 1,
        message=message,
        replacement=replacement,
    )


def _called_name(call: ast.Call) -> str | None:
    func = call.func
    if isinstance(func, ast.Attribute):
        return func.attr
    if isinstance(func, ast.Name):
        return func.id
    return None


def _self_method(call: ast.Call) -> str | None:
    func = call.func
    if (
        isinstance(func, ast.Attribute)
        and isinstance(func.value, ast.Name)
        and func.value.id == "self"
    ):
        return func.attr
    return None


def _waiting_methods(methods: dict[str, ast.FunctionDef]) -> set[str]:
    """Methods of the class that wait, directly or through another method of the class."""
    waiting: set[str] = set()
    changed = True
    while changed:
        changed = False
        for name, method in methods.items():
            if name not in waiting and _waits(method, waiting):
                waiting.add(name)
                changed = True
    return waiting


def _waits(node: ast.AST, waiting: set[str]) -> bool:
    for call in ast.walk(node):
        if not isinstance(call, ast.Call):
            continue
        name = _called_name(call)
        if name is None:
            continue
        if name in _WAITING or name.startswith("wait_for") or _self_method(call) in waiting:
            return True
    return False


def _callback_attributes(methods: dict[str, ast.FunctionDef]) -> set[str]:
    """Attributes that methods handed over as callbacks (``self._on_odom`` given to
    ``create_subscription``) assign."""
    handed: set[str] = set()
    for method in methods.values():
        for call in ast.walk(method):
            if not isinstance(call, ast.Call):
                continue
            for argument in [*call.args, *(k.value for k in call.keywords)]:
                if (
                    isinstance(argument, ast.Attribute)
                    and isinstance(argument.value, ast.Name)
                    and argument.value.id == "self"
                    and argument.attr in methods
                ):
                    handed.add(argument.attr)
    out: set[str] = set()
    for name in handed:
        for node in ast.walk(methods[name]):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.ctx, ast.Store)
                and isinstance(node.value, ast.Name)
                and node.value.id == "self"
            ):
                out.add(node.attr)
    return out


def _expects_time(loop: ast.While, changing: set[str]) -> str | None:
    """What the loop waits for, when it waits for the robot or the clock."""
    for node in ast.walk(loop):
        if isinstance(node, ast.Call):
            name = _called_name(node)
            if name in _CLOCK:
                return "the clock"
            if name == "publish":
                return "the robot while it publishes"
            if name == "done":
                return "a future"
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and isinstance(node.value, ast.Name)
            and node.value.id == "self"
            and node.attr in changing
        ):
            return f"self.{node.attr}, which a callback sets"
    return None


def check_waits(cls: ast.ClassDef) -> list[Finding]:
    """Findings (check ``waits``) for loops that wait for the robot without waiting."""
    methods = {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef)}
    waiting = _waiting_methods(methods)
    changing = _callback_attributes(methods)
    findings = []
    for method in methods.values():
        for loop in ast.walk(method):
            if not isinstance(loop, ast.While) or _waits(loop, waiting):
                continue
            what = _expects_time(loop, changing)
            if what is None:
                continue
            findings.append(
                waits_error(
                    loop,
                    f"this loop in {method.name} waits for {what} but never sleeps: it "
                    "spins a CPU core and keeps callbacks from running; sleep in it, e.g. "
                    "time.sleep(0.05) at the end of its body",
                    _with_sleep(loop),
                )
            )
    return findings


def _continues(loop: ast.While) -> bool:
    """Whether a ``continue`` of this loop (not of a loop inside it) skips its last line."""
    pending: list[ast.AST] = [*loop.body, *loop.orelse]
    while pending:
        node = pending.pop()
        if isinstance(node, ast.Continue):
            return True
        if not isinstance(node, ast.While | ast.For | ast.FunctionDef | ast.Lambda):
            pending.extend(ast.iter_child_nodes(node))
    return False


def _with_sleep(loop: ast.While) -> str | None:
    """The loop with a short sleep as its last statement, unless a ``continue`` would skip
    it."""
    if _continues(loop):
        return None
    sleep = ast.parse("time.sleep(0.05)").body[0]
    fixed = ast.While(test=loop.test, body=[*loop.body, sleep], orelse=loop.orelse)
    return ast.unparse(ast.fix_missing_locations(fixed))
