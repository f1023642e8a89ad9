"""Scripted servers for the robot's services and actions.

Without a world serving them, services answer and actions run as a
:class:`~skillwright.runtime.scenario.ServiceScript` or
:class:`~skillwright.runtime.scenario.ActionScript` says; by default they succeed.

"Success" is read from the response type, by ROS conventions rather than per robot:
boolean fields named ``success``, ``succeeded``, ``result``, ``ok`` or ``accepted`` are
true, and a nested code message with a ``SUCCESS`` constant (MoveIt's
``MoveItErrorCodes``) holds that constant; every other field keeps its default.
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING, Any, Final

from skillwright.runtime.api import ActionGoal, ServiceReply
from skillwright.runtime.scenario import ActionScript, ServiceScript

if TYPE_CHECKING:
    from skillwright.runtime.graph import GraphHost
    from skillwright.runtime.typesys import TypeRegistry

__all__ = ["ScriptedAction", "ScriptedService", "success_message"]

_SUCCESS_FLAGS: Final = frozenset({"success", "succeeded", "result", "ok", "accepted"})


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


def success_message(registry: TypeRegistry, type_name: str) -> dict[str, Any]:
    """A message of ``type_name`` that reads as success (see the module docstring)."""
    message = registry.message(type_name)
    value = registry.default(type_name)
    if message is None:
        return value
    for field in message.fields:
        if field.array != "none":
            continue
        if field.base == "bool" and field.name in _SUCCESS_FLAGS:
            value[field.name] = True
        elif not field.builtin:
            nested = registry.message(field.base)
            if nested is None:
                continue
            code = dict(nested.constants).get("SUCCESS")
            numbers = [f for f in nested.fields if f.builtin and f.base not in {"string", "bool"}]
            if code is not None and len(numbers) == 1:
                value[field.name][numbers[0].name] = code
            else:
                value[field.name] = success_message(registry, field.base)
    return value


class ScriptedService:
    """A service handler that answers as its script says."""

    def __init__(self, registry: TypeRegistry, type_name: str, script: ServiceScript) -> None:
        self._script = script
        self._registry = registry
        self._type_name = type_name

    @cached_property
    def _response(self) -> dict[str, Any]:
        # Made on the first call: a robot has dozens of services, a run calls a few.
        response = success_message(self._registry, self._type_name + "_Response")
        return _merge(response, self._script.response)

    def __call__(self, request: dict[str, Any]) -> ServiceReply:
        if not self._script.respond:
            return ServiceReply(None)
        return ServiceReply(dict(self._response), self._script.delay)


class ScriptedAction:
    """An action server that accepts, reports feedback and finishes as its script says."""

    def __init__(
        self, host: GraphHost, registry: TypeRegistry, type_name: str, script: ActionScript
    ) -> None:
        self._host = host
        self._script = script
        self._registry = registry
        self._type_name = type_name

    @cached_property
    def _result(self) -> dict[str, Any]:
        result = success_message(self._registry, self._type_name + "_Result")
        return _merge(result, self._script.result)

    @cached_property
    def _feedback(self) -> dict[str, Any]:
        feedback = self._registry.default(self._type_name + "_Feedback")
        return _merge(feedback, self._script.feedback)

    def on_goal(self, goal: ActionGoal) -> None:
        script = self._script

        def answer() -> None:
            if not script.accept:
                goal.reject()
                return
            goal.accept()
            if script.feedback_hz > 0 and script.duration > 0:
                self._schedule_feedback(goal, 1.0 / script.feedback_hz)
            if script.outcome != "never":
                self._host.call_later(script.duration, lambda: self._finish(goal))

        self._host.call_later(script.accept_delay, answer)

    def _schedule_feedback(self, goal: ActionGoal, period: float) -> None:
        def send() -> None:
            if goal.active and not goal.cancel_requested:
                goal.feedback(dict(self._feedback))
                self._host.call_later(period, send)

        self._host.call_later(min(period, self._script.duration / 2 or period), send)

    def _finish(self, goal: ActionGoal) -> None:
        if not goal.active or goal.cancel_requested:
            return
        if self._script.outcome == "succeed":
            goal.succeed(dict(self._result))
        else:
            goal.abort(dict(self._result))

    def on_cancel(self, goal: ActionGoal) -> bool:
        if self._script.cancel == "reject" or not goal.active:
            return False

        def cancelled() -> None:
            if goal.active:
                goal.canceled()

        self._host.call_later(self._script.accept_delay, cancelled)
        return True
