"""The types a world plug-in and a responder use (see the package docstring for the API)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final, Protocol, runtime_checkable

if TYPE_CHECKING:
    from skillwright.runtime.graph import GraphHost

__all__ = [
    "STATUS_NAMES",
    "ActionGoal",
    "ActionHandler",
    "GoalStatus",
    "ServiceHandler",
    "ServiceReply",
    "WorldPlugin",
]

Message = dict[str, Any]


class GoalStatus:
    """The values of ``action_msgs/msg/GoalStatus.status``."""

    UNKNOWN: Final = 0
    ACCEPTED: Final = 1
    EXECUTING: Final = 2
    CANCELING: Final = 3
    SUCCEEDED: Final = 4
    CANCELED: Final = 5
    ABORTED: Final = 6


STATUS_NAMES: Final = {
    0: "unknown",
    1: "accepted",
    2: "executing",
    3: "canceling",
    4: "succeeded",
    5: "canceled",
    6: "aborted",
}
"""Readable names of the goal states, for the trace."""


@runtime_checkable
class WorldPlugin(Protocol):
    """A simulated world that publishes sensor data and serves interfaces (e.g. MuJoCo)."""

    def attach(self, host: GraphHost) -> None:
        """Called once before the skill starts: claim topics, register handlers."""

    def next_event(self) -> float | None:
        """Virtual time at which the world next has something to publish, or ``None``."""

    def advance(self, until: float) -> None:
        """Step the world to ``until`` (never less than the last call), publishing through
        ``host.publish`` what is due; publications are stamped ``until``."""

    def close(self) -> None:
        """Release what the world holds; called once, also after errors."""


@dataclass(frozen=True)
class ServiceReply:
    """How a service answers one request.

    ``response=None`` means the server never answers (the client's future never
    completes), as when a server hangs.
    """

    response: Message | None
    delay: float = 0.0
    """Virtual seconds between the request and the response."""


ServiceHandler = Callable[[Message], "ServiceReply | Message"]
"""Called with the request dict at the time of the call."""


@runtime_checkable
class ActionHandler(Protocol):
    """Serves one action: decides about goals and cancel requests."""

    def on_goal(self, goal: ActionGoal) -> None:
        """A goal arrived: call ``goal.accept()`` or ``goal.reject()`` now or later."""

    def on_cancel(self, goal: ActionGoal) -> bool:
        """The skill asked to cancel ``goal``; return whether the request is accepted (then
        call ``goal.canceled(...)`` now or later)."""


class _GoalSink(Protocol):
    def goal_accepted(self, goal: ActionGoal, accepted: bool) -> None: ...
    def goal_feedback(self, goal: ActionGoal, feedback: Message) -> None: ...
    def goal_finished(self, goal: ActionGoal, status: int, result: Message | None) -> None: ...


@dataclass(eq=False)
class ActionGoal:
    """One goal the skill sent, as its server sees it.

    The methods act at the host's current virtual time. Finishing a goal twice, or
    before it was accepted, raises ``RuntimeError``: a server that does so is broken.
    """

    action: str
    goal_id: int
    request: Message
    _sink: _GoalSink = field(repr=False)
    status: int = GoalStatus.UNKNOWN
    cancel_requested: bool = False

    @property
    def active(self) -> bool:
        """Accepted and not yet finished."""
        return self.status in (GoalStatus.ACCEPTED, GoalStatus.EXECUTING, GoalStatus.CANCELING)

    def accept(self) -> None:
        """Accept the goal (the skill's goal future completes with ``accepted=True``)."""
        if self.status != GoalStatus.UNKNOWN:
            raise RuntimeError(f"goal {self.goal_id} of {self.action} was already answered")
        self.status = GoalStatus.EXECUTING
        self._sink.goal_accepted(self, True)

    def reject(self) -> None:
        """Reject the goal (the skill's goal future completes with ``accepted=False``)."""
        if self.status != GoalStatus.UNKNOWN:
            raise RuntimeError(f"goal {self.goal_id} of {self.action} was already answered")
        self.status = GoalStatus.ABORTED
        self._sink.goal_accepted(self, False)

    def feedback(self, feedback: Message) -> None:
        """Send feedback (the type's ``Feedback`` part) to the skill's feedback callback."""
        if self.active:
            self._sink.goal_feedback(self, feedback)

    def succeed(self, result: Message | None = None) -> None:
        """Finish with status SUCCEEDED and ``result`` (defaults for missing fields)."""
        self._finish(GoalStatus.SUCCEEDED, result)

    def abort(self, result: Message | None = None) -> None:
        """Finish with status ABORTED."""
        self._finish(GoalStatus.ABORTED, result)

    def canceled(self, result: Message | None = None) -> None:
        """Finish with status CANCELED (after a cancel request was accepted)."""
        self._finish(GoalStatus.CANCELED, result)

    def _finish(self, status: int, result: Message | None) -> None:
        if not self.active:
            raise RuntimeError(
                f"goal {self.goal_id} of {self.action} is {STATUS_NAMES[self.status]}, "
                "it cannot finish now"
            )
        self.status = status
        self._sink.goal_finished(self, status, result)
