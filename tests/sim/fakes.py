"""A graph host for testing worlds without the runtime's sandboxed child.

It keeps virtual time, records what the world publishes, lets a test publish as the skill
would, call services and send action goals, and builds default messages from the
inventory's definitions (as the runtime's host does).
"""

from __future__ import annotations

import heapq
import itertools
import math
import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from skillwright.interfaces.inventory import Inventory, MessageField
from skillwright.runtime.api import ActionGoal, ActionHandler, ServiceReply

Message = dict[str, Any]

_NUMBERS = {
    "bool": False,
    "string": "",
    "wstring": "",
    "float32": 0.0,
    "float64": 0.0,
}


def _default(field_: MessageField) -> Any:
    if field_.array == "fixed":
        single = field_.model_copy(update={"array": "none"})
        return [_default(single) for _ in range(field_.array_size or 0)]
    if field_.array != "none":
        return []
    if field_.builtin:
        base = field_.base_type.split("<=")[0]
        return _NUMBERS.get(base, 0)
    return {f.name: _default(f) for f in field_.fields}


@dataclass
class GoalEvents:
    """What happened to one goal the test sent."""

    accepted: bool | None = None
    feedback: list[Message] = field(default_factory=list)
    status: int | None = None
    result: Message | None = None
    finished_at: float | None = None


class FakeHost:
    """The graph host's API (see skillwright.runtime), driven by a test."""

    def __init__(self, inventory: Inventory, seed: int = 0) -> None:
        self.inventory = inventory
        self.now = 0.0
        self.rng = random.Random(seed)
        self.owned: set[str] = set()
        self.published: list[tuple[float, str, Message]] = []
        self.listeners: dict[str, list[Callable[[float, Message], None]]] = {}
        self.services: dict[str, Callable[[Message], ServiceReply | Message]] = {}
        self.actions: dict[str, ActionHandler] = {}
        self.records: list[tuple[str, Any]] = []
        self.findings: list[tuple[str, str]] = []
        self.goals: dict[int, GoalEvents] = {}
        self._later: list[tuple[float, int, Callable[[], None]]] = []
        self._ids = itertools.count(1)
        self.world: Any = None
        self.listening: set[str] | None = None
        """Topics someone receives (``None``: all); the world makes no other messages."""

    # --- the API a world uses ---------------------------------------------------------
    def stamp(self, t: float | None = None) -> Message:
        t = self.now if t is None else t
        whole = math.floor(t)
        return {"sec": int(whole), "nanosec": round((t - whole) * 1e9) % 1_000_000_000}

    def own_topic(self, topic: str) -> None:
        self.owned.add(topic)

    def wants(self, topic: str) -> bool:
        return self.listening is None or topic in self.listening

    def publish(self, topic: str, message: Message) -> None:
        self.published.append((self.now, topic, message))

    def on_publish(self, topic: str, callback: Callable[[float, Message], None]) -> None:
        self.listeners.setdefault(topic, []).append(callback)

    def serve_service(
        self, name: str, handler: Callable[[Message], ServiceReply | Message]
    ) -> None:
        self.services[name] = handler

    def serve_action(self, name: str, handler: ActionHandler) -> None:
        self.actions[name] = handler

    def call_later(self, delay: float, callback: Callable[[], None]) -> None:
        heapq.heappush(self._later, (self.now + delay, next(self._ids), callback))

    def message(self, type_name: str) -> Message:
        package, kind, rest = type_name.split("/")
        base, _, part = rest.partition("_")
        role = {
            "Goal": "goal",
            "Result": "result",
            "Feedback": "feedback",
            "Request": "request",
            "Response": "response",
            "": "message",
        }[part]
        wanted = f"{package}/{kind}/{base}"
        for interface in self.inventory.interfaces:
            if interface.type_name == wanted and role in interface.definitions:
                definition = interface.definitions[role]
                return {f.name: _default(f) for f in definition.fields or []}
        raise KeyError(type_name)

    def has_interface(self, name: str, kind: str | None = None) -> bool:
        return any(
            i.name == name and (kind is None or i.kind == kind) for i in self.inventory.interfaces
        )

    def type_of(self, name: str) -> str | None:
        for interface in self.inventory.interfaces:
            if interface.name == name:
                return interface.type_name
        return None

    def report(
        self, check: str, message: str, severity: str = "error", line: int | None = None
    ) -> None:
        self.findings.append((check, message))

    def record(self, kind: str, data: Any) -> None:
        self.records.append((kind, data))

    # --- goal sink ----------------------------------------------------------------------
    def goal_accepted(self, goal: ActionGoal, accepted: bool) -> None:
        self.goals[goal.goal_id].accepted = accepted

    def goal_feedback(self, goal: ActionGoal, feedback: Message) -> None:
        self.goals[goal.goal_id].feedback.append(feedback)

    def goal_finished(self, goal: ActionGoal, status: int, result: Message | None) -> None:
        events = self.goals[goal.goal_id]
        events.status = status
        events.result = result
        events.finished_at = self.now

    # --- what a test does as the skill ------------------------------------------------
    def attach(self, world: Any) -> None:
        self.world = world
        world.attach(self)

    def skill_publishes(self, topic: str, message: Message) -> None:
        for callback in self.listeners.get(topic, []):
            callback(self.now, message)

    def call(self, name: str, request: Message) -> Message:
        reply = self.services[name](request)
        return reply.response if isinstance(reply, ServiceReply) else reply  # type: ignore[return-value]

    def send_goal(self, action: str, request: Message) -> ActionGoal:
        goal = ActionGoal(action=action, goal_id=next(self._ids), request=request, _sink=self)
        self.goals[goal.goal_id] = GoalEvents()
        self.actions[action].on_goal(goal)
        return goal

    def cancel(self, goal: ActionGoal) -> bool:
        goal.cancel_requested = True
        return self.actions[goal.action].on_cancel(goal)

    def run_until(self, t: float) -> None:
        """Advance the world (and callbacks due) in event order up to ``t``."""
        while True:
            candidates = [t]
            due = self.world.next_event()
            if due is not None:
                candidates.append(due)
            if self._later:
                candidates.append(self._later[0][0])
            step = min(candidates)
            self.now = step
            self.world.advance(step)
            while self._later and self._later[0][0] <= step + 1e-12:
                heapq.heappop(self._later)[2]()
            if step >= t:
                return

    def messages(self, topic: str) -> list[tuple[float, Message]]:
        return [(t, m) for t, name, m in self.published if name == topic]
