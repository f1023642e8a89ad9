"""Stand-in of ``rclpy.task``: the future of a service call or an action step."""

from __future__ import annotations

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any


class Future:
    """The eventual outcome of an asynchronous operation.

    As in rclpy, :meth:`result` does not wait: it returns ``None`` until the future is
    done. Wait with ``rclpy.spin_until_future_complete``.
    """

    def __init__(self, *, executor: object = None) -> None:
        self._state = "pending"
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future], None]] = []

    def cancel(self) -> None:
        if self._state == "pending":
            self._state = "cancelled"
            self._run_callbacks()

    def cancelled(self) -> bool:
        return self._state == "cancelled"

    def done(self) -> bool:
        return self._state in ("finished", "cancelled")

    def result(self) -> Any:
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        return self._exception

    def set_result(self, result: Any) -> None:
        self._result = result
        self._state = "finished"
        self._run_callbacks()

    def set_exception(self, exception: BaseException) -> None:
        self._exception = exception
        self._state = "finished"
        self._run_callbacks()

    def _has_callbacks(self) -> bool:
        """Whether finishing this future runs callbacks (the runtime's own question)."""
        return bool(self._callbacks)

    def add_done_callback(self, callback: Callable[[Future], None]) -> None:
        if self.done():
            callback(self)
        else:
            self._callbacks.append(callback)

    def _run_callbacks(self) -> None:
        callbacks, self._callbacks = self._callbacks, []
        for callback in callbacks:
            callback(self)

    def __await__(self):
        while not self.done():
            yield
        return self.result()
