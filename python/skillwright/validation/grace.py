"""A state that gives up sooner than its specification allows (check ``waits``).

A state's text may say how long the robot's interfaces have to show up: "abort if any is
missing after 5 s". A skill that waits 2 s for them gives up on a robot that is fine but
slower to answer; SLAM Toolbox, for one, publishes its map every 5 s by default
(``map_update_interval``), so a 2 s wait for its first map can end before the map comes.

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
from skillwright.runtime import standin_api
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_attribute, self_method, with_text_in_place

__all__ = ["check_grace", "stated_seconds"]

_STATED = re.compile(
    r"\b(?:after|within|in|at most)\s+(\d+(?:\.\d+)?)\s*(?:s|secs?|seconds?)\b", re.IGNORECASE
)
_APPEARING = re.compile(
    r"missing|available|arriv|present|ready|respond|answer|come up|\bwait", re.IGNORECASE
)
"""Words of a sentence about interfaces showing up (not about a motion's duration)."""
_SERVER_WAITS = {"wait_for_server": "action_client", "wait_for_service": "client"}
"""rclpy's waits for a server, by the kind of handle that has them."""


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


def _timeout_of(facts: SkillFacts, call: ast.Call) -> ast.expr | None:
    """The argument that is the seconds of ``call``, when it waits for something to appear."""
    called = self_method(call)
    if called == "_wait_until":
        condition = facts.helper_argument(call, "condition")
        if condition is None or not any(
            (self_attribute(n) or "").endswith("_msg") for n in ast.walk(condition)
        ):
            return None
        return facts.helper_argument(call, "timeout")
    if called == "_transform":
        return facts.helper_argument(call, "timeout")
    if isinstance(call.func, ast.Attribute) and call.func.attr in _SERVER_WAITS:
        signature = standin_api.signature(_SERVER_WAITS[call.func.attr], call.func.attr)
        keywords = {k.arg: k.value for k in call.keywords if k.arg is not None}
        try:
            return signature.bind(*call.args, **keywords).arguments.get("timeout_sec")
        except TypeError:
            return None
    return None


def check_grace(facts: SkillFacts) -> list[Finding]:
    """Findings for waits in the state methods shorter than their specification's texts
    allow."""
    findings = []
    for state, method in facts.states.items():
        stated = stated_seconds(facts.spec.states.get(state, ""))
        if stated is None:
            continue
        seconds, sentence = stated
        for call in facts.calls(method):
            timeout = _timeout_of(facts, call)
            statement = facts.statement_holding(call, method)
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
