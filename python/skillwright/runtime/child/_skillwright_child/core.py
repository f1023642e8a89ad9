"""The child's side of the simulated graph: virtual time and the executor.

One :class:`Core` exists per child. It owns the virtual clock (which only the host
advances), the handles the skill created (publishers, subscriptions, clients, timers),
and :meth:`Core.block`, the single place where the skill waits: it runs deliveries and
due timers on the main thread, asks the host to advance time when nothing is due, and
returns when the skill's condition holds or its time is up.

Threads the skill starts may sleep too (:meth:`Core.side_wait`): they wake when the
main thread's advance passes their time. Their interleaving with the main thread follows
the real scheduler, so runs with threads are not bit-for-bit reproducible.

The host stops a lockstep advance shortly after the first delivery, so that whatever the
skill does in reply reaches the world in time. When nothing the skill runs before its wait
ends can reply (a plain sleep, and every callback that may be called in it only stores
what it gets: see :func:`quiet`), the child says so and the host delivers up to the end
of the wait in one exchange; the run is the same, with fewer exchanges.
"""

from __future__ import annotations

import collections
import dis
import heapq
import itertools
import sys
import threading
import time as _time
import types

from _skillwright_child.messages import TypeCatalog, from_dict, to_dict
from _skillwright_child.wire import Wire

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

_real_sleep = _time.sleep
_real_monotonic = _time.monotonic


_QUIET_OPS = frozenset(
    {"RESUME", "NOP", "LOAD_FAST", "LOAD_CONST", "STORE_ATTR", "POP_TOP", "RETURN_VALUE"}
)
_NOT_PLAIN = 0x04 | 0x08 | 0x20 | 0x80 | 0x100 | 0x200
"""Code flags of *args, **kwargs, generators and coroutines."""


def quiet(callback: object) -> bool:
    """Whether ``callback(message)`` can do nothing but store values on its own object:
    a method whose code loads its arguments and constants and stores them as plain
    attributes of ``self`` (``self.odom = msg``), nothing else (no call, no read of an
    attribute, which could run a property). Anything else may reply to the host."""
    function = getattr(callback, "__func__", None)
    owner = getattr(callback, "__self__", None)
    if type(function) is not types.FunctionType or owner is None:
        return False
    code = function.__code__
    if code.co_argcount != 2 or code.co_kwonlyargcount or code.co_flags & _NOT_PLAIN:
        return False
    cls = type(owner)
    previous = None
    for instruction in dis.get_instructions(code):
        if instruction.opname not in _QUIET_OPS:
            return False
        if instruction.opname == "STORE_ATTR":
            on_self = (
                previous is not None
                and previous.opname == "LOAD_FAST"
                and previous.argval == code.co_varnames[0]
            )
            if not on_self or not _plain_store(cls, instruction.argval):
                return False
        previous = instruction
    return True


def _plain_store(cls: type, name: str) -> bool:
    """Whether storing attribute ``name`` on an instance of ``cls`` runs no code of the
    skill (no ``__setattr__`` of its own, no property; the runtime's own watches store)."""
    if cls.__setattr__ is not object.__setattr__:
        return False
    for klass in cls.__mro__:
        if name in vars(klass):
            found = vars(klass)[name]
            return not hasattr(type(found), "__set__") or getattr(found, "quiet", False)
    return True


class Interrupted(BaseException):
    """The host ended the current state: ``reason`` is ``stop`` (a Stop command),
    ``deadline`` (virtual time limit) or ``busy`` (it ran without waiting too long)."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


class Core:
    """Virtual time, handles and the executor of the child."""

    def __init__(self, wire: Wire, skill_file: str, epoch_ns: int) -> None:
        self.wire = wire
        self.skill_file = skill_file
        self.epoch_ns = epoch_ns
        self.now = 0.0
        self.horizon = 0.0
        """The host's virtual time: every delivery up to it is in ``pending`` already."""
        self.catalog = TypeCatalog(wire.request)
        self.pending: collections.deque[dict] = collections.deque()
        self.handles: dict[int, Any] = {}
        self.timers: dict[int, Any] = {}
        self.dispatched = 0
        self._ids = itertools.count(1)
        self._main = threading.main_thread()
        self._cond = threading.Condition()
        self._wakeups: list[float] = []
        self.in_io = False
        self.deferred_interrupt: str | None = None
        self.deferred_stack: list[list[object]] = []

    # --- identity and location ---------------------------------------------------

    def new_id(self) -> int:
        """A fresh handle id, unique in this child."""
        return next(self._ids)

    def skill_line(self) -> int:
        """The line of the skill file the main thread (or this thread) is at, or 0."""
        frame = sys._getframe(1)
        while frame is not None:
            if frame.f_code.co_filename == self.skill_file:
                return frame.f_lineno
            frame = frame.f_back
        return 0

    def on_main_thread(self) -> bool:
        """Whether the caller runs on the main thread (the executor's thread)."""
        return threading.current_thread() is self._main

    # --- talking to the host -------------------------------------------------------

    def notify(self, op: str, **fields: object) -> None:
        """A notice to the host (stamped with the skill's virtual time), sent with
        interrupts deferred."""
        fields["t"] = self.now
        self.in_io = True
        try:
            self.wire.notify(op, **fields)
        finally:
            self.in_io = False
        self._raise_deferred()

    def request(self, op: str, **fields: object) -> dict:
        """A request to the host, sent with interrupts deferred."""
        self.in_io = True
        try:
            reply = self.wire.request(op, **fields)
        finally:
            self.in_io = False
        self._raise_deferred()
        return reply

    def _raise_deferred(self) -> None:
        reason = self.deferred_interrupt
        if reason is not None and self.on_main_thread():
            # The host learns where the skill was when the signal came, as it does from an
            # interrupt that was not deferred.
            self.deferred_interrupt = None
            stack, self.deferred_stack = self.deferred_stack, []
            self.in_io = True
            try:
                self.wire.notify("stack", reason=reason, frames=stack, t=self.now)
            finally:
                self.in_io = False
            raise Interrupted(reason)

    # --- waiting -------------------------------------------------------------------

    def block(
        self,
        until: float | None,
        ready: Callable[[], bool] | None = None,
        reason: str = "wait",
    ) -> bool:
        """Runs callbacks until ``ready()`` or virtual time reaches ``until``.

        ``until=None`` waits without a time limit (the host's state deadline ends it).
        Returns whether ``ready()`` holds (``True`` when there is no condition). On a
        thread other than the main thread nothing is dispatched; the thread sleeps until
        the main thread's advances pass ``until``.
        """
        if not self.on_main_thread():
            return self.side_wait(until, ready)
        line = self.skill_line()
        while True:
            if ready is not None and ready():
                return True
            timer = self._next_timer()
            due = timer._next_due if timer is not None else None
            head = float(self.pending[0]["t"]) if self.pending else None
            if head is not None and (due is None or head <= due):
                if until is None or head <= until:
                    self._set_now(head)
                    self.dispatch(self.pending.popleft())
                    continue
            elif due is not None and due <= self.horizon and (until is None or due <= until):
                self._set_now(due)
                timer._fire()
                continue
            if until is not None and until <= self.horizon:
                self._set_now(until)
                return ready() if ready is not None else True
            target = until
            for candidate in (due, self._first_wakeup()):
                if candidate is None or candidate <= self.horizon:
                    continue
                if target is None or candidate < target:
                    target = candidate
            batch = ready is None and self._quiet()
            reply = self.request("advance", until=target, line=line, reason=reason, batch=batch)
            self.horizon = float(reply["now"])
            self.pending.extend(reply.get("deliveries", ()))
            self._wake_side_threads()
            stop = reply.get("stop")
            if stop:
                self._set_now(self.horizon)
                raise Interrupted(str(stop))

    def _quiet(self) -> bool:
        """Whether nothing that deliveries may call can reply before the main thread's
        wait ends (no other thread runs; every handle's callbacks only store)."""
        if threading.active_count() != 1:
            return False
        return all(getattr(h, "_quiet", _loud)() for h in self.handles.values())

    def side_wait(self, until: float | None, ready: Callable[[], bool] | None = None) -> bool:
        """A wait on a thread the skill started: woken by the main thread's advances."""
        limit = float("inf") if until is None else until
        with self._cond:
            heapq.heappush(self._wakeups, limit)
            try:
                while True:
                    if ready is not None and ready():
                        return True
                    if self.now >= limit:
                        return ready() if ready is not None else True
                    self._cond.wait(0.05)
            finally:
                self._wakeups.remove(limit)
                heapq.heapify(self._wakeups)

    def _set_now(self, time: float) -> None:
        if time > self.now:
            self.now = time
            if self._wakeups:
                self._wake_side_threads()

    def _first_wakeup(self) -> float | None:
        with self._cond:
            finite = [t for t in self._wakeups if t != float("inf")]
        return min(finite) if finite else None

    def _wake_side_threads(self) -> None:
        with self._cond:
            due = any(t <= self.now for t in self._wakeups)
            self._cond.notify_all()
        if due:
            # Give the woken threads a moment to run before the main thread goes on.
            _real_sleep(0.001)

    def sleep(self, seconds: float) -> None:
        """``time.sleep`` in virtual time."""
        if seconds < 0:
            raise ValueError("sleep length must be non-negative")
        self.block(self.now + seconds, None, "sleep")

    # --- timers --------------------------------------------------------------------

    def _next_timer(self) -> Any:
        best = None
        for timer in self.timers.values():
            if timer._active and (best is None or timer._next_due < best._next_due):
                best = timer
        return best

    # --- deliveries ----------------------------------------------------------------

    def dispatch(self, delivery: dict) -> None:
        """Runs the callback a delivery from the host is for."""
        handle = self.handles.get(delivery.get("id"))
        if handle is None:
            return
        self.dispatched += 1
        handle._deliver(delivery)

    def message(self, type_name: str, data: dict) -> Any:
        """A message object of ``type_name`` from the host's data."""
        return from_dict(self.catalog.get(type_name), data)  # type: ignore[arg-type]

    def data(self, message: Any) -> dict:
        """A message object as data for the host."""
        return to_dict(message)

    def ros_time_ns(self) -> int:
        """The ROS time of the current virtual time, in nanoseconds."""
        return self.epoch_ns + round(self.now * 1e9)


def _loud() -> bool:
    return False


CORE: Core | None = None


def core() -> Core:
    """The child's :class:`Core` (set up by the driver before the skill is loaded)."""
    if CORE is None:
        raise RuntimeError("the skillwright child runtime is not set up")
    return CORE
