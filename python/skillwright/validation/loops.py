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
class that does one of these on every call. The skeleton's ``_wait_until``, ``_result_of`` and
``_transform`` do not: they sleep only until their data is there, and return at once after
that: a control loop paced with ``_wait_until(lambda: self.odom_msg is not None, ...)`` or
``_transform`` spins a core once the first odometry or transform has come.

A loop's timeout must be a deadline. ``time.monotonic() > 5.0`` compares the clock's reading,
seconds since an arbitrary start (the machine's boot), with a duration: it is true at once, so
the loop gives up on its first pass. The fix takes ``deadline = time.monotonic() + 5.0``
before the loop and compares with that.
"""

from __future__ import annotations

import ast
import copy
from collections.abc import Iterable, Iterator, Mapping
from collections.abc import Set as AbstractSet

from skillwright.rules.behaviour import CLOCK_COMPARED_WITH_DURATION, LOOP_NEVER_SLEEPS
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import called_name, error_at, self_method, skips_its_end

__all__ = ["check_waits"]

_CLOCK = frozenset({"monotonic", "time", "perf_counter", "now", "get_clock"})
_READINGS = frozenset({"monotonic", "time", "perf_counter"})
"""``time`` functions that return seconds since an arbitrary start."""
_MOMENTS = ("DEADLINE", "START", "END", "STAMP", "BEGIN")
_WAITING = frozenset({"sleep", "spin", "spin_once", "spin_until_future_complete"})


def _waiting_methods(methods: Mapping[str, ast.FunctionDef]) -> set[str]:
    """Methods of the class that wait on every call, directly or through another such
    method: a wait that only a loop of the method reaches (one that waits for data) does
    not count."""
    waiting: set[str] = set()
    changed = True
    while changed:
        changed = False
        for name, method in methods.items():
            if name not in waiting and _waits(method, waiting, _own_nodes(method)):
                waiting.add(name)
                changed = True
    return waiting


def _waits(node: ast.AST, waiting: set[str], nodes: Iterable[ast.AST] | None = None) -> bool:
    """Whether ``node`` waits: one of ``nodes`` (all nodes under it by default) calls a
    wait function or one of the ``waiting`` methods."""
    for call in ast.walk(node) if nodes is None else nodes:
        if not isinstance(call, ast.Call):
            continue
        name = called_name(call)
        if name in _WAITING or name.startswith("wait_for") or self_method(call) in waiting:
            return True
    return False


def _expects_time(loop: ast.While, changing: AbstractSet[str]) -> str | None:
    """What the loop waits for, when it waits for the robot or the clock."""
    for node in ast.walk(loop):
        if isinstance(node, ast.Call):
            name = called_name(node)
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


def check_waits(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``waits``) for loops that wait for the robot without waiting, and
    for timeouts that compare the clock's reading with a duration."""
    methods = facts.methods
    waiting = _waiting_methods(methods)
    changing = facts.callback_stores
    findings = []
    for method in methods.values():
        owners = _loops_of_durations(method)
        taken = {n.id for n in facts.walk(method) if isinstance(n, ast.Name)}
        for loop in facts.walk(method):
            if not isinstance(loop, ast.While):
                continue
            durations = owners.pop(loop, [])
            what = None if _waits(loop, waiting) else _expects_time(loop, changing)
            if not durations and what is None:
                continue
            fixed = _fixed_loop(loop, durations, taken, sleep=what is not None)
            for compare in durations:
                findings.append(
                    error_at(CLOCK_COMPARED_WITH_DURATION, loop, _duration_message(compare), fixed)
                )
            if what is not None:
                findings.append(
                    error_at(
                        LOOP_NEVER_SLEEPS,
                        loop,
                        f"this loop in {method.name} waits for {what} but never sleeps: it "
                        "spins a CPU core and keeps callbacks from running; sleep in it, e.g. "
                        "time.sleep(0.05) at the end of its body",
                        fixed,
                    )
                )
        for compares in owners.values():  # in a for loop or in no loop: the model is told
            for compare in compares:
                findings.append(
                    error_at(
                        CLOCK_COMPARED_WITH_DURATION,
                        facts.statement_holding(compare, method) or method,
                        _duration_message(compare),
                        None,
                    )
                )
    return findings


def _is_reading(node: ast.expr) -> bool:
    """``time.monotonic()`` and the like: seconds since an arbitrary start."""
    return (
        isinstance(node, ast.Call)
        and not node.args
        and isinstance(node.func, ast.Attribute)
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == "time"
        and node.func.attr in _READINGS
    )


def _is_duration(node: ast.expr, moments: AbstractSet[str] = frozenset()) -> bool:
    """A number of seconds rather than a moment: a number, or a name that says
    timeout or duration, or a constant's name that does not say deadline or start; never a
    name in ``moments`` (one the method gave a clock reading: ``timeout = time.time() + 3.0``
    is a deadline, whatever its name)."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, int | float) and not isinstance(node.value, bool)
    name = (
        node.id
        if isinstance(node, ast.Name)
        else node.attr
        if isinstance(node, ast.Attribute)
        else None
    )
    if name is None or ast.unparse(node) in moments:
        return False
    if "timeout" in name.lower() or "duration" in name.lower():
        return True
    return name.isupper() and not any(moment in name for moment in _MOMENTS)


def _duration_compare(node: ast.AST, moments: AbstractSet[str] = frozenset()) -> ast.Compare | None:
    """``node`` when it compares a clock reading with a duration, alone (``a < b < c``
    chains are left alone)."""
    if not isinstance(node, ast.Compare) or len(node.ops) != 1:
        return None
    if not isinstance(node.ops[0], ast.Lt | ast.LtE | ast.Gt | ast.GtE):
        return None
    left, right = node.left, node.comparators[0]
    if (_is_reading(left) and _is_duration(right, moments)) or (
        _is_reading(right) and _is_duration(left, moments)
    ):
        return node
    return None


def _loops_of_durations(method: ast.FunctionDef) -> dict[ast.AST, list[ast.Compare]]:
    """Each clock-against-duration comparison of ``method`` under the innermost loop that
    holds it (the method itself when no loop does)."""
    owners: dict[ast.AST, list[ast.Compare]] = {}
    moments = _moments(method)
    for owner in [method, *(n for n in ast.walk(method) if isinstance(n, ast.While | ast.For))]:
        for node in _own_nodes(owner):
            compare = _duration_compare(node, moments)
            if compare is not None:
                owners.setdefault(owner, []).append(compare)
    return owners


def _moments(method: ast.FunctionDef) -> set[str]:
    """Names (``timeout``, ``self.stop_at``) ``method`` assigns a value worked out from a
    clock reading: moments, to compare a reading with."""
    found: set[str] = set()
    for node in ast.walk(method):
        if (
            isinstance(node, ast.Assign | ast.AnnAssign)
            and node.value is not None
            and any(isinstance(n, ast.expr) and _is_reading(n) for n in ast.walk(node.value))
        ):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            found |= {ast.unparse(t) for t in targets}
    return found


def _own_nodes(owner: ast.AST) -> Iterator[ast.AST]:
    """The nodes under ``owner`` that no loop or function inside it holds."""
    pending = list(ast.iter_child_nodes(owner))
    while pending:
        node = pending.pop()
        yield node
        if not isinstance(node, ast.While | ast.For | ast.FunctionDef | ast.Lambda):
            pending.extend(ast.iter_child_nodes(node))


def _duration_message(compare: ast.Compare) -> str:
    reading, duration = (
        (compare.left, compare.comparators[0])
        if _is_reading(compare.left)
        else (compare.comparators[0], compare.left)
    )
    clock, seconds = ast.unparse(reading), ast.unparse(duration)
    return (
        f"{ast.unparse(compare)} compares the clock's reading (seconds since an arbitrary "
        f"start, such as the machine's boot) with a duration of {seconds} s: it is decided at "
        "once, not after that time. Take a deadline where the wait begins, "
        f"`deadline = {clock} + {seconds}`, and compare {clock} with it"
    )


def _fixed_loop(
    loop: ast.While, durations: list[ast.Compare], taken: set[str], *, sleep: bool
) -> str | None:
    """The statements that replace ``loop``: a deadline taken before it for each duration
    its timeouts compare the clock with, the comparisons made with the deadlines, and a
    sleep at the end when it never waits. ``None`` when a sleep is needed but a
    ``continue`` would skip it."""
    if sleep and skips_its_end(loop):
        return None
    fixed = copy.deepcopy(loop)
    before: list[str] = []
    deadlines: dict[str, str] = {}
    wanted = {ast.unparse(compare) for compare in durations}
    compares = [
        node
        for node in _own_nodes(fixed)
        if isinstance(node, ast.Compare) and ast.unparse(node) in wanted
    ]
    for node in sorted(compares, key=lambda n: (n.lineno, n.col_offset)):
        reading_left = _is_reading(node.left)
        reading = node.left if reading_left else node.comparators[0]
        duration = node.comparators[0] if reading_left else node.left
        key = f"{ast.unparse(reading)} + {ast.unparse(duration)}"
        if key not in deadlines:
            deadlines[key] = _free_name("deadline", taken)
            before.append(f"{deadlines[key]} = {key}")
        name = ast.Name(id=deadlines[key], ctx=ast.Load())
        if reading_left:
            node.comparators = [name]
        else:
            node.left = name
    if sleep:
        fixed.body = [*fixed.body, ast.parse("time.sleep(0.05)").body[0]]
    return "\n".join([*before, ast.unparse(ast.fix_missing_locations(fixed))])


def _free_name(stem: str, taken: set[str]) -> str:
    """``stem``, or ``stem_2``, ``stem_3``... : the first name not in ``taken`` (added)."""
    name, number = stem, 1
    while name in taken:
        number += 1
        name = f"{stem}_{number}"
    taken.add(name)
    return name
