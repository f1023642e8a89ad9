"""A state that gives up sooner than its specification allows (check ``waits``).

A state's text may say how long the robot's interfaces have to show up: "abort if any is
missing after 5 s". A skill that waits 2 s for them gives up on a robot that is fine but
slower to answer; SLAM Toolbox, for one, publishes its map every 5 s by default. The default
model's MR-1 mapping waited 2 s for it in all six of its skills kept from the evaluations at
hand, in a starting state whose text gives 5 s, and one failed in the simulation on it.

Counted are the waits for something to appear in the state's own method: the skeleton's
``_wait_until`` whose condition reads a latest message, ``_transform``, and rclpy's
``wait_for_server`` and ``wait_for_service``. A wait given a number below the stated seconds
is an error; its fix gives the wait the stated seconds.
"""

from __future__ import annotations

import ast
import re

from skillwright.rules.behaviour import WAIT_SHORTER_THAN_SPEC
from skillwright.rules.finding import Finding
from skillwright.validation.names import self_attribute
from skillwright.validation.syntax import (
    error_at,
    self_method,
    statement_holding,
    with_text_in_place,
)

__all__ = ["check_grace", "stated_seconds"]

_STATED = re.compile(
    r"\b(?:after|within|in|at most)\s+(\d+(?:\.\d+)?)\s*(?:s|secs?|seconds?)\b", re.IGNORECASE
)
_APPEARING = re.compile(
    r"missing|available|arriv|present|ready|respond|answer|come up|\bwait", re.IGNORECASE
)
"""Words of a sentence about interfaces showing up (not about a motion's duration)."""
_SERVER_WAITS = frozenset({"wait_for_server", "wait_for_service"})


def _sentences(text: str) -> list[str]:
    return [s.strip() for s in re.split(r"(?<=[.;])\s+", text) if s.strip()]


def stated_seconds(text: str) -> tuple[float, str] | None:
    """The seconds a state's ``text`` gives its interfaces to show up, and the sentence that
    says so, where one number is given ("abort if any is missing after 5 s")."""
    found = {
        float(match.group(1)): sentence
        for sentence in _sentences(text)
        if _APPEARING.search(sentence)
        for match in _STATED.finditer(sentence)
    }
    return next(iter(found.items())) if len(found) == 1 else None


def _argument(
    call: ast.Call, method: ast.FunctionDef | None, name: str, position: int
) -> ast.expr | None:
    """The argument ``call`` passes for parameter ``name`` (at ``position`` when the
    definition of the called ``method`` is not there to tell)."""
    for keyword in call.keywords:
        if keyword.arg == name:
            return keyword.value
    if method is not None:
        parameters = [a.arg for a in method.args.args if a.arg != "self"]
        position = parameters.index(name) if name in parameters else -1
    return call.args[position] if 0 <= position < len(call.args) else None


def _timeout_of(call: ast.Call, methods: dict[str, ast.FunctionDef]) -> ast.expr | None:
    """The argument that is the seconds of ``call``, when it waits for something to appear."""
    called = self_method(call)
    if called == "_wait_until":
        condition = _argument(call, methods.get(called), "condition", 0)
        if condition is None or not any(
            (self_attribute(n) or "").endswith("_msg") for n in ast.walk(condition)
        ):
            return None
        return _argument(call, methods.get(called), "timeout", 1)
    if called == "_transform":
        return _argument(call, methods.get(called), "timeout", 2)
    if isinstance(call.func, ast.Attribute) and call.func.attr in _SERVER_WAITS:
        return _argument(call, None, "timeout_sec", 0)
    return None


def check_grace(
    cls: ast.ClassDef, states: dict[str, ast.FunctionDef], texts: dict[str, str]
) -> list[Finding]:
    """Findings for waits in the state methods ``states`` shorter than their specification's
    ``texts`` allow."""
    methods = {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef)}
    findings = []
    for state, method in states.items():
        stated = stated_seconds(texts.get(state, ""))
        if stated is None:
            continue
        seconds, sentence = stated
        for call in (n for n in ast.walk(method) if isinstance(n, ast.Call)):
            timeout = _timeout_of(call, methods)
            statement = statement_holding(method, call)
            if not (
                statement is not None
                and isinstance(timeout, ast.Constant)
                and isinstance(timeout.value, int | float)
                and not isinstance(timeout.value, bool)
                and 0 < timeout.value < seconds
            ):
                continue
            findings.append(
                error_at(
                    WAIT_SHORTER_THAN_SPEC,
                    statement,
                    f"{state} gives up after {timeout.value:g} s where its specification "
                    f'allows {seconds:g} s ("{sentence}"): a robot that answers later is '
                    f"refused; wait {seconds:g} s",
                    with_text_in_place(statement, timeout, repr(seconds)),
                )
            )
    return findings
