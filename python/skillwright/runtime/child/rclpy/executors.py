"""Stand-in of ``rclpy.executors``: every executor spins on the skill's main thread."""

from __future__ import annotations

import rclpy
from rclpy.node import Node
from rclpy.task import Future

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any


class ExternalShutdownException(Exception):
    pass


class ShutdownException(Exception):
    pass


class TimeoutException(Exception):
    pass


class Executor:
    """Runs the callbacks of its nodes while it spins.

    Spinning on a thread the skill started only waits: callbacks run on the main thread
    whenever the skill waits there, as with the background executor pySkillUp starts.
    """

    def __init__(self, *, context: Any = None) -> None:
        self._nodes: list[Node] = []

    def add_node(self, node: Node) -> bool:
        if node in self._nodes:
            return False
        self._nodes.append(node)
        return True

    def remove_node(self, node: Node) -> None:
        if node in self._nodes:
            self._nodes.remove(node)

    def get_nodes(self) -> list[Node]:
        return list(self._nodes)

    def spin(self) -> None:
        rclpy.spin(None, self)

    def spin_once(self, timeout_sec: float | None = None) -> None:
        rclpy.spin_once(None, executor=self, timeout_sec=timeout_sec)

    def spin_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        rclpy.spin_until_future_complete(None, future, self, timeout_sec)

    def spin_once_until_future_complete(
        self, future: Future, timeout_sec: float | None = None
    ) -> None:
        rclpy.spin_until_future_complete(None, future, self, timeout_sec)

    def wake(self) -> None:
        return None

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        return True

    def create_task(self, callback: Any, *args: Any, **kwargs: Any) -> Future:
        future = Future()
        try:
            future.set_result(callback(*args, **kwargs))
        except Exception as error:
            future.set_exception(error)
        return future


class SingleThreadedExecutor(Executor):
    pass


class MultiThreadedExecutor(Executor):
    def __init__(self, num_threads: int | None = None, *, context: Any = None) -> None:
        super().__init__(context=context)
        self.num_threads = num_threads or 1
