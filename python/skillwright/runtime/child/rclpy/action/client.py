"""Stand-in of ``rclpy.action.client``: goals, feedback, results and cancels on the
simulated graph; the host's responders (or a world) play the action server."""

from __future__ import annotations

from types import SimpleNamespace

from _skillwright_child.core import core

from rclpy.task import Future

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

_STATUS_UNKNOWN = 0


def _uuid(sequence: int) -> SimpleNamespace:
    return SimpleNamespace(uuid=[(sequence >> (8 * i)) & 0xFF for i in range(16)])


class ClientGoalHandle:
    """The skill's handle of one goal."""

    def __init__(self, client: ActionClient, sequence: int, accepted: bool, stamp: dict) -> None:
        self._client = client
        self._sequence = sequence
        self._accepted = accepted
        self._status = 1 if accepted else _STATUS_UNKNOWN
        self._stamp = SimpleNamespace(sec=stamp.get("sec", 0), nanosec=stamp.get("nanosec", 0))
        self._result_future: Future | None = None

    def __repr__(self) -> str:
        return (
            f"ClientGoalHandle(goal_id={self._sequence}, accepted={self._accepted}, "
            f"status={self._status})"
        )

    @property
    def goal_id(self) -> SimpleNamespace:
        return _uuid(self._sequence)

    @property
    def stamp(self) -> SimpleNamespace:
        return self._stamp

    @property
    def accepted(self) -> bool:
        return self._accepted

    @property
    def status(self) -> int:
        return self._status

    def get_result_async(self) -> Future:
        if not self._accepted:
            raise RuntimeError("Cannot get result from a goal that was not accepted")
        return self._client._result_future(self._sequence)

    def get_result(self) -> Any:
        future = self.get_result_async()
        core().block(None, future.done, "get_result")
        return future.result()

    def cancel_goal_async(self) -> Future:
        return self._client._cancel_goal_async(self._sequence)

    def cancel_goal(self) -> Any:
        future = self.cancel_goal_async()
        core().block(None, future.done, "cancel_goal")
        return future.result()


class ActionClient:
    """An action client of the skill's node."""

    def __init__(
        self,
        node: Any,
        action_type: type,
        action_name: str,
        *,
        callback_group: object = None,
        goal_service_qos_profile: object = None,
        result_service_qos_profile: object = None,
        cancel_service_qos_profile: object = None,
        feedback_sub_qos_profile: object = None,
        status_sub_qos_profile: object = None,
    ) -> None:
        from rclpy.node import _type_name

        c = core()
        self._node = node
        self._action_type = action_type
        self._type_name = _type_name(action_type, "action_type action")
        self._action_name = node._expand(action_name, "service")
        self._id = c.new_id()
        self._sequence = 0
        self._goal_futures: dict[int, Future] = {}
        self._feedback: dict[int, Callable[[Any], object]] = {}
        self._results: dict[int, Future] = {}
        self._finished: dict[int, Any] = {}
        self._cancels: dict[int, list[Future]] = {}
        self._handles: dict[int, ClientGoalHandle] = {}
        c.handles[self._id] = self
        c.notify(
            "endpoint",
            id=self._id,
            kind="action_client",
            name=self._action_name,
            type=self._type_name,
            qos={},
            line=c.skill_line(),
        )

    def server_is_ready(self) -> bool:
        return bool(core().request("exists", kind="action", name=self._action_name)["ok"])

    def wait_for_server(self, timeout_sec: float | None = None) -> bool:
        if self.server_is_ready():
            return True
        c = core()
        until = None if timeout_sec is None or timeout_sec < 0 else c.now + timeout_sec
        c.block(until, None, f"wait for action server {self._action_name}")
        return self.server_is_ready()

    def send_goal_async(
        self,
        goal: Any,
        feedback_callback: Callable[[Any], object] | None = None,
        goal_uuid: Any = None,
    ) -> Future:
        goal_class = self._action_type.Goal  # type: ignore[attr-defined]
        if not isinstance(goal, goal_class):
            raise TypeError(f"Expected {goal_class}, got {type(goal)}")
        c = core()
        if self._id not in c.handles:
            raise RuntimeError(f"the action client of {self._action_name} was destroyed")
        self._sequence += 1
        sequence = self._sequence
        future = Future()
        self._goal_futures[sequence] = future
        if feedback_callback is not None:
            self._feedback[sequence] = feedback_callback
        c.notify(
            "goal",
            id=self._id,
            goal=sequence,
            request=c.data(goal),
            feedback=feedback_callback is not None,
            line=c.skill_line(),
        )
        return future

    def send_goal(
        self,
        goal: Any,
        feedback_callback: Callable[[Any], object] | None = None,
        goal_uuid: Any = None,
    ) -> Any:
        future = self.send_goal_async(goal, feedback_callback, goal_uuid)
        c = core()
        c.block(None, future.done, f"send_goal {self._action_name}")
        handle = future.result()
        if not handle.accepted:
            return None
        return handle.get_result()

    def _result_future(self, sequence: int) -> Future:
        future = self._results.get(sequence)
        if future is None:
            future = Future()
            self._results[sequence] = future
            if sequence in self._finished:
                future.set_result(self._finished[sequence])
        return future

    def _cancel_goal_async(self, sequence: int) -> Future:
        c = core()
        future = Future()
        self._cancels.setdefault(sequence, []).append(future)
        c.notify("cancel", id=self._id, goal=sequence, line=c.skill_line())
        return future

    def _deliver(self, delivery: dict) -> None:
        c = core()
        sequence = int(delivery["goal"])
        kind = delivery["kind"]
        if kind == "accepted":
            handle = ClientGoalHandle(
                self, sequence, bool(delivery["accepted"]), delivery.get("stamp", {})
            )
            self._handles[sequence] = handle
            future = self._goal_futures.pop(sequence, None)
            if future is not None:
                future.set_result(handle)
        elif kind == "feedback":
            callback = self._feedback.get(sequence)
            if callback is not None:
                feedback = c.message(self._type_name + "_Feedback", delivery["data"])
                callback(SimpleNamespace(goal_id=_uuid(sequence), feedback=feedback))
        elif kind == "result":
            status = int(delivery["status"])
            handle = self._handles.get(sequence)
            if handle is not None:
                handle._status = status
            result = SimpleNamespace(
                status=status, result=c.message(self._type_name + "_Result", delivery["data"])
            )
            self._finished[sequence] = result
            self._feedback.pop(sequence, None)
            future = self._results.get(sequence)
            if future is not None and not future.done():
                future.set_result(result)
        elif kind == "cancel":
            response = SimpleNamespace(
                return_code=int(delivery["return_code"]),
                goals_canceling=[SimpleNamespace(goal_id=_uuid(sequence))]
                if delivery["return_code"] == 0
                else [],
            )
            for future in self._cancels.pop(sequence, []):
                future.set_result(response)

    def _quiet(self) -> bool:
        if self._feedback:
            return False
        futures = [*self._goal_futures.values(), *self._results.values()]
        futures += [future for waiting in self._cancels.values() for future in waiting]
        return not any(future._has_callbacks() for future in futures)

    def destroy(self) -> None:
        c = core()
        if c.handles.pop(self._id, None) is not None:
            c.notify("destroy", id=self._id, line=c.skill_line())
