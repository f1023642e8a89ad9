"""What the condition of a wait that never came true did, pass by pass.

A run that gives up twice on the same wait, the second time with most of the state's
deadline, or that sits in a loop until the deadline, says that waiting longer is not the
fix; it does not say why the condition never held. There are three ways to get there, and
each needs another repair:

* the condition never changes: the loop compares a heading it read once, before the loop;
* the robot goes past its goal between two passes: a base turning 0.04 rad per pass never
  sees ``abs(remaining_angle)`` below 0.01, and turns through its target on every
  revolution (the tolerance must exceed what the robot moves between two readings);
* the robot moves away from its goal: the command's sign is wrong.

This module finds the comparison such a wait tests (:func:`watch_at`), gives the skill
with that comparison logging both of its sides on every pass (:func:`watched`, lines kept
where they were), and reads those values back into what happened (:func:`diagnose`).
"""

from __future__ import annotations

import ast
import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from skillwright.validation.timeouts import bound_arguments, call_of, function_at, functions_of

__all__ = ["LOGGER", "Watch", "diagnose", "samples", "watch_at", "watched"]

LOGGER = "skillwright.watch"
"""The logger the watched comparison writes its two sides to."""

_FUNCTION = "_skillwright_compare"
_OPERATORS: dict[type[ast.cmpop], str] = {ast.Lt: "lt", ast.LtE: "le", ast.Gt: "gt", ast.GtE: "ge"}
_SYMBOLS = {"lt": "<", "le": "<=", "gt": ">", "ge": ">="}
_NEGATED = {"lt": "ge", "le": "gt", "gt": "le", "ge": "lt"}


@dataclass(frozen=True)
class Watch:
    """The comparison a wait tests, and what ends the wait."""

    line: int
    start: int
    """Byte offset of the comparison in its line."""
    end: int
    left: str
    operator: str
    """``lt``, ``le``, ``gt`` or ``ge``."""
    right: str
    ends_when: bool
    """The wait ends when the comparison is this: ``False`` for a ``while`` condition."""
    absolute: str = ""
    """``left`` or ``right`` when that side is ``abs(...)``; the watch then logs the value
    inside, with its sign, and ``left``/``right`` hold that value's source."""

    @property
    def text(self) -> str:
        """The comparison as the skill writes it."""
        left = f"abs({self.left})" if self.absolute == "left" else self.left
        right = f"abs({self.right})" if self.absolute == "right" else self.right
        return f"{left} {_SYMBOLS[self.operator]} {right}"


def watch_at(code: str, line: int, stack: Sequence[int] = ()) -> Watch | None:
    """The comparison the wait at ``line`` tests (``stack``: the lines of the calls that led
    there, outermost first): the condition of the innermost ``while`` around ``line``, an
    ``if ...: break`` in that loop's body, or the comparison a callable parameter that the
    condition calls was given (``self._wait_until(lambda: abs(error) < 0.01, ...)``).
    ``None`` when the wait tests something else, or a comparison spread over lines."""
    functions = functions_of(code)
    if functions is None:
        return None
    function = function_at(functions, line)
    if function is None:
        return None
    loops = [
        n
        for n in ast.walk(function)
        if isinstance(n, ast.While) and n.lineno <= line <= (n.end_lineno or n.lineno)
    ]
    if not loops:
        return None
    loop = max(loops, key=lambda n: n.lineno)
    found = _compare_in(loop.test, ends_when=False)
    if found is None:
        found = _breaking_compare(loop)
    if found is None and stack:
        found = _passed_compare(functions, function, loop.test, stack[-1])
    if found is None:
        return None
    compare, ends_when = found
    return _watch(code, compare, ends_when)


def watched(code: str, watch: Watch) -> str:
    """``code`` with the watched comparison logging its two sides on every evaluation to
    :data:`LOGGER`; every other line stays where it was."""
    lines = code.splitlines(keepends=True)
    raw = lines[watch.line - 1].encode("utf-8")
    call = f'{_FUNCTION}({watch.left}, "{watch.operator}", {watch.right}, "{watch.absolute}")'
    lines[watch.line - 1] = (
        raw[: watch.start].decode("utf-8") + call + raw[watch.end :].decode("utf-8")
    )
    text = "".join(lines)
    if not text.endswith("\n"):
        text += "\n"
    return text + (
        "\n\n"
        f"def {_FUNCTION}(left, operator_name, right, absolute):\n"
        "    import operator\n"
        "    import rclpy.logging\n"
        "    try:\n"
        f'        logger = rclpy.logging.get_logger("{LOGGER}")\n'
        '        logger.info(f"{float(left)!r} {float(right)!r}")\n'
        "    except (TypeError, ValueError):\n"
        "        pass\n"
        '    if absolute == "left":\n'
        "        left = abs(left)\n"
        '    elif absolute == "right":\n'
        "        right = abs(right)\n"
        "    return getattr(operator, operator_name)(left, right)\n"
    )


def samples(events: Sequence[dict[str, Any]], state: str) -> list[tuple[float, float, float]]:
    """The (virtual time, left, right) pairs the watched comparison logged in ``state``."""
    out = []
    for event in events:
        if event.get("kind") != "log" or event.get("name") != LOGGER:
            continue
        if event.get("state") != state:
            continue
        try:
            left, right = (float(v) for v in str(event.get("text", "")).split())
        except ValueError:
            continue
        out.append((float(event.get("t", 0.0)), left, right))
    return out


def diagnose(
    watch: Watch, seen: Sequence[tuple[float, float, float]], *, moving: bool
) -> str | None:
    """What the values of a comparison that never came true say about why, in words for
    the repair; ``None`` when they say nothing clear (too few, or it did come true).
    ``moving``: whether the robot was being moved while the wait went on; a comparison that
    never changes then does not follow the robot (without motion, it has nothing to follow).
    """
    if len(seen) < 3 or not all(math.isfinite(v) for s in seen for v in s):
        return None
    goal = watch.operator if watch.ends_when else _NEGATED[watch.operator]
    # the wait ends when small <= big: the gap is how far the two still are from that
    small_is_left = goal in {"lt", "le"}
    values = [_applied(watch, left, right) for _, left, right in seen]
    gaps = [(a - b) if small_is_left else (b - a) for a, b in values]
    if any(g <= 0 for g in gaps):
        return None
    lefts, rights = [v[1] for v in seen], [v[2] for v in seen]
    moving_left = _spread(lefts) > 0 or (_spread(rights) == 0 and not _is_number(watch.left))
    shown, raw = (watch.left, lefts) if moving_left else (watch.right, rights)
    if _spread(lefts) == 0 and _spread(rights) == 0:
        if not moving:
            return None
        return (
            f"`{shown}` was {raw[0]:.4g} on every one of its {len(seen)} passes "
            f"({seen[0][0]:.1f} to {seen[-1][0]:.1f} s), so what the wait compares does not "
            "follow the robot: read the robot's state again on every pass"
        )
    band = (rights if watch.absolute == "left" else lefts)[0]
    if watch.absolute == ("left" if small_is_left else "right"):
        signed = lefts if watch.absolute == "left" else rights
        crossed = _crossings(signed)
        if crossed:
            name = watch.left if watch.absolute == "left" else watch.right
            step = max(abs(signed[j] - signed[j - 1]) for j in crossed)
            times = "once" if len(crossed) == 1 else f"{len(crossed)} times"
            return (
                f"`{name}` went past zero {times} (first at {seen[crossed[0]][0]:.1f} s) "
                f"without ever being within {band:.4g} of it: it changed by up to "
                f"{step:.3g} from one reading to the next, more than the {2 * band:.3g} wide "
                "band the wait needs it in, so the robot steps over its goal between two "
                f"checks. Also end the wait once the goal is passed (`{name}` changed sign), "
                "or slow down close to it"
            )
    closest = min(range(len(gaps)), key=gaps.__getitem__)
    if (
        0 < closest < len(gaps) - 1
        and gaps[0] > 2 * gaps[closest]
        and max(gaps[closest + 1 :]) > 2 * gaps[closest]
    ):
        return (
            f"`{watch.text}` came within {gaps[closest]:.3g} of holding at "
            f"{seen[closest][0]:.1f} s and then moved away from it again, so the robot "
            "went past its goal between two checks: also end the wait once the goal is "
            "passed, or slow down close to it"
        )
    if closest == 0 and gaps[-1] > 1.5 * gaps[0]:
        return (
            f"`{watch.text}` moved further from holding from the first pass on (`{shown}` "
            f"went from {raw[0]:.4g} to {raw[-1]:.4g}): check the direction (the sign) of "
            "what the skill commands"
        )
    return None


def _spread(values: Sequence[float]) -> float:
    return max(values) - min(values)


def _is_number(source: str) -> bool:
    try:
        float(source)
    except ValueError:
        return False
    return True


def _applied(watch: Watch, left: float, right: float) -> tuple[float, float]:
    if watch.absolute == "left":
        return abs(left), right
    if watch.absolute == "right":
        return left, abs(right)
    return left, right


def _crossings(raw: Sequence[float]) -> list[int]:
    """Indices where the value changed sign by about one pass's motion (not by a jump, as
    an angle wrapped into [-pi, pi] makes when it passes pi)."""
    steps = [abs(raw[j] - raw[j - 1]) for j in range(1, len(raw))]
    changes = [j for j in range(1, len(raw)) if raw[j] * raw[j - 1] < 0]
    # passes between two readings of a slower topic (a 5 Hz map pose) see no change
    same = [steps[j - 1] for j in range(1, len(raw)) if raw[j] * raw[j - 1] > 0 and steps[j - 1]]
    if not same:
        return changes
    usual = statistics.median(same)
    return [j for j in changes if steps[j - 1] <= 3 * usual]


def _watch(code: str, compare: ast.Compare, ends_when: bool) -> Watch | None:
    if compare.lineno != compare.end_lineno or compare.end_col_offset is None:
        return None
    raw = code.splitlines()[compare.lineno - 1].encode("utf-8")

    def source(node: ast.expr) -> str:
        return raw[node.col_offset : node.end_col_offset].decode("utf-8")

    left, right = compare.left, compare.comparators[0]
    absolute = ""
    if _is_abs(left):
        absolute, left = "left", left.args[0]  # type: ignore[attr-defined]
    elif _is_abs(right):
        absolute, right = "right", right.args[0]  # type: ignore[attr-defined]
    return Watch(
        line=compare.lineno,
        start=compare.col_offset,
        end=compare.end_col_offset,
        left=source(left),
        operator=_OPERATORS[type(compare.ops[0])],
        right=source(right),
        ends_when=ends_when,
        absolute=absolute,
    )


def _is_abs(node: ast.expr) -> bool:
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in {"abs", "fabs"}
        and len(node.args) == 1
        and not node.keywords
    ) or (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "fabs"
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == "math"
        and len(node.args) == 1
    )


def _compare_in(test: ast.expr, *, ends_when: bool) -> tuple[ast.Compare, bool] | None:
    """The one comparison of a quantity that ``test`` is, or that ``not test`` is, or the
    first such one among the conditions of an ``and`` (a loop that also checks a clock)."""
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        return _compare_in(test.operand, ends_when=not ends_when)
    if isinstance(test, ast.BoolOp) and isinstance(test.op, ast.And) and not ends_when:
        for value in test.values:
            found = _compare_in(value, ends_when=ends_when)
            if found is not None and not _reads_clock(found[0]):
                return found
        return None
    if (
        isinstance(test, ast.Compare)
        and len(test.ops) == 1
        and type(test.ops[0]) in _OPERATORS
        and not _reads_clock(test)
    ):
        return test, ends_when
    return None


def _reads_clock(node: ast.AST) -> bool:
    """Whether ``node`` reads a clock or a deadline: that comparison is the wait's limit, not
    what it waits for."""
    for part in ast.walk(node):
        if isinstance(part, ast.Attribute) and part.attr in {"monotonic", "time", "now"}:
            return True
        name = part.id if isinstance(part, ast.Name) else getattr(part, "attr", "")
        if isinstance(name, str) and any(w in name for w in ("deadline", "timeout")):
            return True
    return False


def _breaking_compare(loop: ast.While) -> tuple[ast.Compare, bool] | None:
    """The comparison of the first ``if ...: ... break`` directly in the loop's body."""
    for statement in loop.body:
        if (
            isinstance(statement, ast.If)
            and not statement.orelse
            and any(isinstance(s, ast.Break) for s in statement.body)
        ):
            found = _compare_in(statement.test, ends_when=True)
            if found is not None:
                return found
    return None


def _passed_compare(
    functions: Sequence[ast.FunctionDef], function: ast.FunctionDef, test: ast.expr, outer: int
) -> tuple[ast.Compare, bool] | None:
    """For a loop that tests a callable parameter (``while not condition():``), the
    comparison of the lambda the call at line ``outer`` passed for it."""
    ends_when = False
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        test, ends_when = test.operand, True
    if not (isinstance(test, ast.Call) and isinstance(test.func, ast.Name) and not test.args):
        return None
    caller = function_at(functions, outer)
    call = call_of(caller, function.name, outer) if caller is not None else None
    if call is None:
        return None
    given, _ = bound_arguments(function, call, {test.func.id})
    if len(given) != 1 or not isinstance(given[0], ast.Lambda):
        return None
    found = _compare_in(given[0].body, ends_when=True)
    if found is None:
        return None
    compare, truth = found
    return compare, truth == ends_when
