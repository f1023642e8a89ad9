"""Stand-in of rclpy for skills run by skillwright: a simulated graph in virtual time.

Only the child process of ``skillwright run`` imports this. Names, signatures and errors
follow rclpy (Jazzy); callbacks run on the main thread while the skill waits, like a
single-threaded executor (see ``_skillwright_child.core``).
"""

from __future__ import annotations

from _skillwright_child.core import core

from rclpy.exceptions import NotInitializedException
from rclpy.node import Node
from rclpy.task import Future

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = [
    "Node",
    "create_node",
    "get_global_executor",
    "init",
    "ok",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
    "try_shutdown",
]

_state = {"initialized": False}


def init(
    *,
    args: Any = None,
    context: Any = None,
    domain_id: int | None = None,
    signal_handler_options: Any = None,
) -> None:
    if _state["initialized"]:
        raise RuntimeError("rclpy.init() has already been called")
    _state["initialized"] = True


def ok(*, context: Any = None) -> bool:
    return _state["initialized"]


def shutdown(*, context: Any = None, uninstall_handlers: bool | None = None) -> None:
    if not _state["initialized"]:
        raise RuntimeError("rclpy.shutdown() called before rclpy.init() or after it was shut down")
    _state["initialized"] = False


def try_shutdown(*, context: Any = None, uninstall_handlers: bool | None = None) -> None:
    _state["initialized"] = False


def create_node(node_name: str, **kwargs: Any) -> Node:
    return Node(node_name, **kwargs)


def _require_init() -> None:
    if not _state["initialized"]:
        raise NotInitializedException("before spinning")


def spin_once(
    node: Node | None = None, *, executor: Any = None, timeout_sec: float | None = None
) -> None:
    """Runs at most one callback, waiting up to ``timeout_sec`` (virtual) for one."""
    _require_init()
    c = core()
    start = c.dispatched
    until = None if timeout_sec is None or timeout_sec < 0 else c.now + timeout_sec
    c.block(until, lambda: c.dispatched > start, "spin_once")


def spin(node: Node | None = None, executor: Any = None) -> None:
    """Runs callbacks until the run ends: a state that spins forever never returns."""
    _require_init()
    core().block(None, None, "spin")


def spin_until_future_complete(
    node: Node | None, future: Future, executor: Any = None, timeout_sec: float | None = None
) -> None:
    _require_init()
    c = core()
    until = None if timeout_sec is None or timeout_sec < 0 else c.now + timeout_sec
    c.block(until, future.done, "spin_until_future_complete")


def get_global_executor() -> Any:
    from rclpy.executors import SingleThreadedExecutor

    return SingleThreadedExecutor()
