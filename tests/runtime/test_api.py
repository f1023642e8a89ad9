"""Action goals as a server sees them."""

from __future__ import annotations

from typing import Any

import pytest

from skillwright.runtime.api import ActionGoal, GoalStatus


class _Sink:
    def __init__(self) -> None:
        self.events: list[tuple[str, Any]] = []

    def goal_accepted(self, goal: ActionGoal, accepted: bool) -> None:
        self.events.append(("accepted", accepted))

    def goal_feedback(self, goal: ActionGoal, feedback: dict[str, Any]) -> None:
        self.events.append(("feedback", feedback))

    def goal_finished(self, goal: ActionGoal, status: int, result: dict[str, Any] | None) -> None:
        self.events.append(("finished", status))


def test_a_goal_is_accepted_gets_feedback_and_succeeds_once() -> None:
    sink = _Sink()
    goal = ActionGoal(action="/nav", goal_id=1, request={}, _sink=sink)

    goal.accept()
    goal.feedback({"distance": 1.0})
    goal.succeed()

    assert sink.events == [
        ("accepted", True),
        ("feedback", {"distance": 1.0}),
        ("finished", GoalStatus.SUCCEEDED),
    ]
    assert not goal.active
    with pytest.raises(RuntimeError, match="succeeded, it cannot finish now"):
        goal.abort()
    goal.feedback({"late": True})
    assert len(sink.events) == 3


def test_a_goal_is_answered_only_once_and_finishes_only_when_accepted() -> None:
    goal = ActionGoal(action="/nav", goal_id=2, request={}, _sink=_Sink())
    with pytest.raises(RuntimeError, match="cannot finish now"):
        goal.succeed()
    goal.reject()
    with pytest.raises(RuntimeError, match="already answered"):
        goal.accept()
