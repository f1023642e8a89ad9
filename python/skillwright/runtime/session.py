"""One episode: a sandboxed child runs the skill while the host serves the graph.

The host reads the child's frames, answers its requests, advances the graph when the
child waits, enforces the deadlines (virtual per state, wall per episode, "busy" for a
state that runs without ever waiting) and turns what it sees into trace entries and
findings. It never trusts the child: unknown operations, wrong field types and
oversized frames end the episode with a ``run.protocol`` finding.
"""

from __future__ import annotations
import __future__

import base64
import marshal
import re
import select
import signal
import threading
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from skillwright.errors import GenerationCancelledError
from skillwright.rules.run import (
    RUN_BLOCKED,
    RUN_BUSY,
    RUN_CPU,
    RUN_EXCEPTION,
    RUN_FIELD,
    RUN_IMPORT,
    RUN_MEMORY,
    RUN_PROCESS_DIED,
    RUN_PROTOCOL,
    RUN_SANDBOX,
    RUN_STRUCTURE,
    RUN_SYNTAX,
    RUN_SYS_EXIT,
    RUN_TIMEOUT,
)
from skillwright.runtime.graph import GraphHost, SentMessageError
from skillwright.runtime.isolation import layout
from skillwright.runtime.protocol import ProtocolError, Wire
from skillwright.runtime.recorder import Recorder
from skillwright.runtime.report import EpisodeTrace, RunProgress, StateRun
from skillwright.runtime.sandbox import ChildPool, SandboxProcess, limits_config
from skillwright.runtime.typesys import MOTION_TYPES, is_zero_motion

if TYPE_CHECKING:
    from skillwright.interfaces.inventory import Inventory
    from skillwright.runtime.api import ActionGoal, WorldPlugin
    from skillwright.runtime.scenario import RunScenario
    from skillwright.runtime.skillinfo import SkillInfo
    from skillwright.runtime.typesys import TypeRegistry

__all__ = ["GAVE_UP_NOTE", "Episode", "EpisodePlan", "EpisodeResult"]

_POLL_SECONDS = 0.05
_GRACE_SECONDS = 5.0
"""Wall seconds a child gets to report where it was after an interrupt, before the kill
(generous: on a loaded machine the child may wait that long for a core)."""
_STALL_SECONDS = 30.0
"""A state that uses no CPU and sends nothing for this long (wall; at least ten busy
deadlines) is blocked in a wait the simulation cannot see (a lock, ``input()``)."""
_SPIN_FRAMES = 200
"""Frames a child may send without waiting in the busy deadline before it counts as spinning
(one that starts up or sets up its handles sends far fewer)."""
_WAITING_OPS = frozenset({"advance", "state", "phase", "stack", "hello"})
"""Frames that show the child waited for virtual time or began something new."""
_IMPORT_NAME = re.compile(
    r"cannot import name '(?P<name>\w+)' from '(?P<package>\w+)\.(?P<namespace>\w+)'"
)
_NO_MODULE = re.compile(r"No module named '(?P<module>[\w.]+)'")
_GAVE_UP = re.compile(
    r"(?:no result of the (?P<action>\S+) goal )?within (?P<timeout>\d+(?:\.\d+)?) ?s\b"
)
"""A state giving up after a time: the skeleton's result helper (``_result_of``'s
RuntimeError names the action) or the model's own words ("not finished within 2 s")."""
GAVE_UP_NOTE = "; it gave up after "
"""How the note begins that a run adds to a state's giving up while its motion was under way."""
_LOAD_DEADLINE = 30.0
"""Virtual seconds the module import and ``__init__`` may wait."""


def _field_data(frame: dict[str, Any]) -> dict[str, object]:
    """The field, its type and the given value's type the message stand-ins attach to a
    value rosidl's setter refuses; empty for an unknown field (rosidl names it itself)."""
    extra = frame.get("data")
    if not isinstance(extra, dict):
        return {}
    keys = ("field", "expected", "given")
    if not all(isinstance(extra.get(k), str) for k in keys):
        return {}
    return {k: str(extra[k]) for k in keys}


def _article(word: str) -> str:
    return "an" if word[:1].lower() in "aeiou" else "a"


def _outer(frames: list[Any]) -> tuple[int, ...]:
    """The lines of the calls that led to the innermost of the skill's ``frames``
    (``[line, function]``, outermost first)."""
    return tuple(int(f[0]) for f in frames[:-1] if isinstance(f[0], int))


class _Watch:
    """When the host interrupts a child's state: it spins (uses CPU, or keeps talking without
    ever waiting for virtual time) or it is blocked (silent and idle) for too long."""

    def __init__(self, child: SandboxProcess, busy: float, stall: float) -> None:
        self.child = child
        self.busy = busy
        self.stall = stall
        self.last = self.sampled = self.waited = time.monotonic()
        self.last_cpu = child.cpu_seconds()
        self.talked = 0
        self.interrupted_at: float | None = None

    def overdue(self, now: float) -> str | None:
        """``"busy"`` or ``"blocked"`` when the child's state should be interrupted now."""
        if self.interrupted_at is not None:
            return None
        if now - self.waited > self.busy and self.talked > _SPIN_FRAMES:
            # It keeps talking (publishing, logging) but never waits, so virtual time stands
            # still: a loop without a sleep.
            return "busy"
        if now - self.last > self.busy:
            # CPU time, not wall time, decides: on a busy machine a waiting child can go
            # seconds without a turn on a core.
            cpu = self.child.cpu_seconds()
            if cpu is None or self.last_cpu is None or cpu - self.last_cpu > self.busy:
                return "busy"
            if now - self.last > self.stall:
                return "blocked"
        return None

    def quiet(self) -> None:
        """The child has gone quiet: its CPU time is noted once, as the base the busy check
        compares with. A child that keeps talking is never sampled (reading /proc costs more
        than an exchange)."""
        if self.sampled < self.last:
            self.sampled, self.last_cpu = time.monotonic(), self.child.cpu_seconds()

    def heard(self, op: str) -> None:
        """A frame of ``op`` came from the child."""
        if op == "stack":
            self.interrupted_at = None
        self.last = time.monotonic()
        if op in _WAITING_OPS:
            self.waited, self.talked = self.last, 0
        else:
            self.talked += 1


@dataclass(frozen=True)
class EpisodePlan:
    """Which episode to run."""

    name: str
    stop_after: float | None = None
    """Virtual seconds into execute at which a Stop command arrives."""
    stop_at_complete: bool = False
    """Send Stop at Complete when execute ends before ``stop_after``."""


@dataclass
class EpisodeResult:
    """An episode's trace, findings, and the graph state the later checks read."""

    trace: EpisodeTrace
    recorder: Recorder
    graph: GraphHost
    reads: set[str] = field(default_factory=set)
    writes: set[str] = field(default_factory=set)
    threads: list[dict[str, Any]] = field(default_factory=list)
    publish_marks: dict[str, int] = field(default_factory=dict)
    """State -> how many messages the skill had published when it ended (or was absent)."""
    goals_after: dict[str, list[tuple[ActionGoal, int]]] = field(default_factory=dict)
    """State -> goals active and not being cancelled when it ended, with their lines."""


@lru_cache(maxsize=8)
def compiled(source: str) -> str | None:
    """The skill's code as the child compiles it (the child's ``annotations`` future, no
    optimisation), marshalled and in base64, or ``None`` when it does not compile (the child
    then compiles it itself and reports why). A validation runs one skill many times; the
    child then only renames the code to its own copy of the file."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            code = compile(
                source,
                "skill.py",
                "exec",
                flags=__future__.annotations.compiler_flag,
                dont_inherit=True,
                optimize=0,
            )
    except (SyntaxError, ValueError, RecursionError, MemoryError, OverflowError):
        return None
    return base64.b64encode(marshal.dumps(code)).decode("ascii")


_INTERRUPTED: Final = {"busy": RUN_BUSY, "blocked": RUN_BLOCKED, "cpu": RUN_CPU}
"""The rule of a state the host interrupted, by why."""

_CHILD_ERRORS: Final = {
    "syntax": RUN_SYNTAX,
    "import": RUN_IMPORT,
    "field": RUN_FIELD,
    "sandbox": RUN_SANDBOX,
    "memory": RUN_MEMORY,
    "exit": RUN_SYS_EXIT,
    "structure": RUN_STRUCTURE,
}
"""The rule of an error the child reports, by its kind (anything else is RUN_EXCEPTION)."""


def _signal_name(signum: int) -> str:
    try:
        return f"{signal.Signals(signum).name} (signal {signum})"
    except ValueError:
        return f"signal {signum}"


class Episode:
    """Runs one episode of a skill; see :meth:`run`."""

    def __init__(
        self,
        *,
        source: str,
        skill_name: str,
        info: SkillInfo,
        inputs: list[dict[str, Any]],
        inventory: Inventory,
        registry: TypeRegistry,
        scenario: RunScenario,
        recording: list[Path] | None,
        world_factory: Callable[[], WorldPlugin | None],
        epoch_ns: int,
        on_progress: Callable[[RunProgress], None] | None,
        cancel: threading.Event | None,
        children: ChildPool,
    ) -> None:
        self._source = source
        self._skill_name = skill_name
        self._info = info
        self._inputs = inputs
        self._inventory = inventory
        self._registry = registry
        self._scenario = scenario
        self._recording = recording
        self._world_factory = world_factory
        self._epoch_ns = epoch_ns
        self._on_progress = on_progress
        self._cancel = cancel
        self._children = children

    def _progress(
        self, plan: EpisodePlan, event: str, state: str | None = None, detail: str | None = None
    ) -> None:
        if self._on_progress is not None:
            self._on_progress(
                RunProgress(plan.name, event, state, self._recorder.now, detail)  # type: ignore[arg-type]
            )

    def run(self, plan: EpisodePlan, *, prepare_next: bool = False) -> EpisodeResult:
        """Runs the episode to its end; raises ``GenerationCancelledError`` when cancelled.

        With ``prepare_next`` the pool starts the next run's child once this run's has
        booted, so that one boots while this one runs.
        """
        self._plan = plan
        self._prepare_next = prepare_next
        self._recorder = Recorder()
        self._graph = GraphHost(
            self._inventory,
            self._registry,
            self._recorder,
            self._scenario,
            recording=self._recording,
            epoch_ns=self._epoch_ns,
        )
        trace = EpisodeTrace(name=plan.name, ended="done")  # type: ignore[arg-type]
        result = EpisodeResult(trace=trace, recorder=self._recorder, graph=self._graph)
        self._result = result
        self._states: list[StateRun] = []
        self._state_wall = 0.0
        self._state_start = 0.0
        self._execute_start: float | None = None
        self._stop_sent = False
        self._settling = False
        self._done = False
        self._startup: float | None = None
        self._output_tail = ""
        started = time.monotonic()
        child: SandboxProcess | None = None
        try:
            # The child boots while the world is built (on the other core, if idle). A
            # sandbox the kernel refuses stops the run here, before anything says it began.
            child = self._children.take(self._source, self._skill_name)
            self._child = child
            self._progress(plan, "episode-start")
            world = self._world_factory()
            if world is not None:
                self._graph.attach_world(world)
            self._loop(child)
        finally:
            self._graph.close()
            if child is not None:
                # Read before close() removes the folder the output is in.
                self._output_tail = child.output_tail()
                child.close()
                trace.resources = child.rusage
            trace.wall_seconds = round(time.monotonic() - started, 3)
            trace.startup_seconds = round(self._startup or 0.0, 3)
            trace.states = self._states
            trace.events = self._recorder.entries
            trace.dropped_events = self._recorder.dropped
            trace.virtual_seconds = round(self._graph.now, 6)
        if child is not None and not self._done and trace.ended == "done":
            self._child_died(child)
        self._progress(plan, "episode-end", detail=trace.ended)
        return result

    # --- the frame loop --------------------------------------------------------------

    def _loop(self, child: SandboxProcess) -> None:
        wire = Wire(child.sock)
        deadlines = self._scenario.deadlines
        run_deadline = child.started + deadlines.run
        watch = _Watch(child, deadlines.busy, max(_STALL_SECONDS, 10 * deadlines.busy))
        self._interrupt_reason = "busy"
        self._stall_seconds = watch.stall
        while not self._done:
            if self._cancel is not None and self._cancel.is_set():
                raise GenerationCancelledError("the run was cancelled; nothing was kept")
            now = time.monotonic()
            if now > run_deadline:
                self._kill("run", f"the episode took longer than {deadlines.run:g} s of wall time")
                return
            if watch.interrupted_at is not None and now - watch.interrupted_at > _GRACE_SECONDS:
                self._kill("busy", self._busy_message(None))
                return
            reason = watch.overdue(now)
            if reason is not None:
                self._interrupt_reason = reason
                child.interrupt()
                watch.interrupted_at = now
                continue
            if not wire.pending():
                ready, _, _ = select.select([child.sock], [], [], _POLL_SECONDS)
                if not ready:
                    watch.quiet()
                    continue
            try:
                frame = wire.receive()
            except (EOFError, ConnectionError):
                return
            except ProtocolError as error:
                self._protocol(str(error))
                return
            if frame is None:
                continue
            try:
                reply = self._handle(frame)
            except SentMessageError as error:
                self._sent_wrong(str(frame.get("op")), str(error))
                reply = None
            except (KeyError, TypeError, ValueError) as error:
                self._protocol(f"a {frame.get('op')!r} frame is malformed: {error}")
                return
            if reply is not None:
                try:
                    wire.send(reply)
                except OSError:
                    return
            watch.heard(str(frame["op"]))

    def _kill(self, reason: str, message: str) -> None:
        self._result.trace.ended = "killed"
        state = self._recorder.state or "load"
        rule = RUN_TIMEOUT if reason == "run" else _INTERRUPTED[self._interrupt_reason]
        self._recorder.finding(rule, f"{state}: {message}", data={"state": state})
        self._end_state("killed", reason)

    def _sent_wrong(self, op: str, message: str) -> None:
        """A message the skill sent that does not fit its type: the run's field error, and
        the message is dropped (rclpy raises in the sending call; the run goes on, since the
        child sent the frame without waiting)."""
        state = self._recorder.state or "load"
        verb = {"publish": "published", "call": "sent", "goal": "sent"}.get(op, "sent")
        self._recorder.finding(
            RUN_FIELD,
            f"{state} {verb} a message that does not fit its type ({message}); rclpy refuses "
            "it and nothing reaches the robot: give each field a value of the type its "
            "message definition has",
        )

    def _protocol(self, message: str) -> None:
        self._result.trace.ended = "protocol"
        self._recorder.finding(
            RUN_PROTOCOL,
            f"the sandboxed process broke the runtime's protocol ({message}); the skill may "
            "have written to the runtime's socket or replaced its modules",
        )
        self._end_state("killed", "protocol")

    def _child_died(self, child: SandboxProcess) -> None:
        trace = self._result.trace
        trace.ended = "crashed"
        status = child.exit_status
        if status is not None and status < 0:
            how = f"was killed by {_signal_name(-status)} ({self._kill_cause(child, -status)})"
        else:
            how = f"exited with status {status} (os._exit, or a crash)"
        where = f"during {self._recorder.state}" if self._recorder.state else "while it loaded"
        line = self._recorder.line
        seen = f"; the last line it reported was {line}" if line else ""
        tail = self._output_tail.strip()
        detail = f"; its last output: {tail[-300:]}" if tail else ""
        self._recorder.finding(RUN_PROCESS_DIED, f"the skill's process {how} {where}{seen}{detail}")
        self._end_state("killed", "crashed")

    def _kill_cause(self, child: SandboxProcess, signum: int) -> str:
        """What the resource use says of why the child got ``signum``."""
        limits = self._scenario.limits
        cpu = child.rusage.get("cpu_seconds")
        if signum in (signal.SIGKILL, signal.SIGXCPU) and cpu is not None:
            if cpu >= 0.9 * limits.cpu_seconds:
                return f"the CPU-time limit of {limits.cpu_seconds} s"
            if signum == signal.SIGKILL:
                return (
                    f"no limit: it used {cpu:.2f} of {limits.cpu_seconds} s of CPU; a signal "
                    "it sent itself (os.kill, os.killpg) or the machine's out-of-memory killer"
                )
        if signum in (signal.SIGSEGV, signal.SIGBUS, signal.SIGABRT, signal.SIGILL):
            return (
                f"a crash in native code, such as the memory limit of {limits.memory_mb} MB "
                "hit outside Python"
            )
        return "a signal it sent itself, or a limit"

    def _busy_message(self, frames: list[Any] | None) -> str:
        where = ""
        if frames:
            inner = frames[-1]
            where = f" at line {inner[0]} in {inner[1]}()"
        if self._interrupt_reason == "blocked":
            return (
                f"it waited {self._stall_seconds:g} s of wall time{where} in a way the "
                "simulation cannot see (a lock, input(), a raw socket or file), so virtual "
                "time stood still; "
                "wait with time.sleep, rclpy.spin_once or a future instead"
            )
        return (
            f"it ran for {self._scenario.deadlines.busy:g} s of CPU time without waiting{where}: "
            "a loop that never sleeps, spins or waits on a future keeps callbacks from running "
            "and burns a core on the robot; wait with time.sleep or rclpy.spin_once inside it"
        )

    def _end_state(self, outcome: str, detail: str | None) -> None:
        if self._states and self._states[-1].ended is None:
            current = self._states[-1]
            current.outcome = outcome
            current.detail = detail
            current.ended = round(self._graph.now, 6)
            current.wall_seconds = round(time.monotonic() - self._state_wall, 3)

    # --- frames ---------------------------------------------------------------------

    def _config(self) -> dict[str, Any]:
        limits = limits_config(self._scenario.limits)
        return {
            "skill": self._child.skill_path,
            "source": self._source,
            "code": compiled(self._source),
            "class": self._info.class_name,
            "inputs": self._inputs,
            "outputs": [{"name": v.name, "attr": v.attr} for v in self._info.outputs],
            "epoch_ns": self._epoch_ns,
            "limits": limits,
            "read_roots": layout().readable(),
            "message_packages": self._registry.packages(),
            "settle": self._scenario.settle,
            "stop_at_complete": self._plan.stop_at_complete,
        }

    def _handle(self, frame: dict[str, Any]) -> dict[str, Any] | None:
        # The trace shows the skill's own time for what it did; the graph may be up to a
        # lookahead ahead of it.
        t = frame.get("t")
        if isinstance(t, (int, float)) and not isinstance(t, bool):
            self._recorder.now = min(max(float(t), 0.0), self._graph.now)
        try:
            return self._dispatch(frame)
        finally:
            self._recorder.now = self._graph.now

    def _dispatch(self, frame: dict[str, Any]) -> dict[str, Any] | None:
        op = frame["op"]
        graph = self._graph
        recorder = self._recorder
        line = frame.get("line")
        if isinstance(line, int) and line > 0:
            recorder.line = line
        if op == "hello":
            # What the child says of its own confinement, then what the host knows itself.
            reported = {
                k: v
                for k, v in dict(frame.get("isolation") or {}).items()
                if isinstance(v, (str, bool)) and k in ("landlock", "seccomp", "uid")
            }
            self._result.trace.isolation = {
                **reported,
                "namespaces": "user, mount, pid, network, ipc, uts"
                if self._child.isolated
                else "none (--unsafe-no-isolation)",
                "sandbox": self._child.marker,
                "folder": str(self._child.temp),
            }
            if self._prepare_next:
                self._children.prepare()
            return {"config": self._config()}
        if op == "package":
            return {"ok": self._registry.has_package(str(frame["name"]))}
        if op == "type":
            return self._registry.describe_with_nested(str(frame["name"]))
        if op == "exists":
            return {"ok": graph.exists(str(frame["kind"]), str(frame["name"]))}
        if op == "count":
            return {"count": graph.count(str(frame["what"]), str(frame["name"]))}
        if op == "endpoints":
            return {"endpoints": graph.robot_endpoints(str(frame["what"]), str(frame["name"]))}
        if op == "graph":
            return {"names": graph.names_and_types(str(frame["kind"]))}
        if op == "advance":
            return self._advance(frame)
        self._notice(op, frame)
        return None

    def _notice(self, op: str, frame: dict[str, Any]) -> None:
        graph = self._graph
        recorder = self._recorder
        line = int(frame.get("line") or 0)
        if op == "endpoint":
            graph.child_endpoint(frame)
        elif op == "destroy":
            graph.child_destroy(int(frame["id"]))
        elif op == "publish":
            graph.child_publish(frame["id"], frame["msg"], line, recorder.state)
        elif op == "call":
            graph.child_call(frame["id"], frame["seq"], frame["request"], line)
        elif op == "goal":
            graph.child_goal(
                frame["id"], frame["goal"], frame["request"], bool(frame.get("feedback")), line
            )
        elif op == "cancel":
            graph.child_cancel(frame["id"], frame["goal"], line)
        elif op == "log":
            recorder.record(
                "log",
                level=str(frame["level"]),
                name=str(frame["name"]),
                text=str(frame["text"]),
                line=line,
            )
        elif op == "output":
            recorder.record(
                "output", stream=str(frame["stream"]), text=str(frame["text"]), line=line
            )
        elif op == "node":
            recorder.record("node", name=str(frame["name"]), line=line)
        elif op == "phase":
            self._phase(str(frame["name"]))
        elif op == "state":
            self._state(frame)
        elif op == "error":
            self._error(frame)
        elif op == "stack":
            frames = [f for f in frame.get("frames", []) if isinstance(f, list) and len(f) == 2]
            where = int(frames[-1][0]) if frames else recorder.line
            state = recorder.state or "load"
            if frame.get("reason") == "cpu":
                rule, message = RUN_CPU, "it used up the CPU-time limit of the sandbox"
            else:
                rule = _INTERRUPTED[self._interrupt_reason]
                message = self._busy_message(frames)
            recorder.finding(
                rule,
                f"{state}: {message}",
                line=where,
                stack=_outer(frames),
                data={"state": state},
            )
        elif op == "outputs":
            values = frame.get("values")
            if isinstance(values, dict):
                self._result.trace.outputs = {str(k): v for k, v in values.items()}
                recorder.record("outputs", values=self._result.trace.outputs)
        elif op == "watch":
            self._result.reads = {str(x) for x in frame.get("read", [])}
            self._result.writes = {str(x) for x in frame.get("written", [])}
            self._result.threads = [t for t in frame.get("threads", []) if isinstance(t, dict)]
        elif op == "done":
            self._done = True
        else:
            raise ValueError(f"unknown operation {op!r}")

    def _phase(self, name: str) -> None:
        self._recorder.record("phase", name=name)
        self._state_start = self._graph.now
        self._settling = name == "settle"

    def _state(self, frame: dict[str, Any]) -> None:
        name = str(frame["name"])
        phase = str(frame["phase"])
        recorder = self._recorder
        now = round(self._graph.now, 6)
        if phase == "begin":
            if self._startup is None:
                self._startup = time.monotonic() - self._child.started
            recorder.state = name
            self._state_start = self._graph.now
            self._state_wall = time.monotonic()
            if name == "execute":
                self._execute_start = self._graph.now
            self._states.append(StateRun(name=name, outcome="running", started=now))
            recorder.record("state", name=name, phase="begin")
            self._progress(self._plan, "state-start", name)
        elif phase == "absent":
            self._states.append(StateRun(name=name, outcome="absent", started=now, ended=now))
            recorder.record("state", name=name, phase="absent")
            self._mark(name)
        else:
            outcome = str(frame.get("outcome"))
            detail = frame.get("detail")
            self._end_state(outcome, str(detail) if detail is not None else None)
            self._mark(name)
            recorder.record("state", name=name, phase="end", outcome=outcome, detail=detail)
            self._progress(self._plan, "state-end", name, outcome)
            recorder.state = None
            self._state_start = self._graph.now

    def _mark(self, name: str) -> None:
        self._result.publish_marks[name] = self._graph.publish_count
        self._result.goals_after[name] = [
            (goal, line) for goal, line in self._graph.active_goals() if not goal.cancel_requested
        ]

    def _error(self, frame: dict[str, Any]) -> None:
        phase = str(frame["phase"])
        kind = str(frame["kind"])
        type_name = str(frame["type"])
        message = str(frame["message"])
        line = int(frame.get("line") or 0)
        self._recorder.record("error", phase=phase, type=type_name, message=message, line=line)
        rule = _CHILD_ERRORS.get(kind, RUN_EXCEPTION)
        if kind == "exit":
            text = (
                f"{phase} called sys.exit ({message or 'no code'}): a skill must not end the "
                "process; raise an exception to abort"
            )
        elif kind == "memory":
            limit = self._scenario.limits.memory_mb
            text = (
                f"{phase} ran out of memory (the sandbox allows {limit} MB): {type_name} {message}"
            )
        elif kind == "sandbox":
            text = f"{phase}: {message}"
        elif kind == "import":
            text = f"{phase}: {self._import_problem(message)}"
        else:
            text = (
                f"{phase} raised {type_name}: {message}"
                if message
                else f"{phase} raised {type_name}"
            )
            text += self._still_running(message)
        frames = [f for f in frame.get("frames", []) if isinstance(f, list) and len(f) == 2]
        data: dict[str, object] = {}
        if rule is RUN_EXCEPTION:
            data = self._error_data(frame, phase, type_name, message)
        elif rule is RUN_FIELD:
            data = _field_data(frame)
            if data:
                text += (
                    f" ({data['field']} is {data['expected']}; the value given is "
                    f"{_article(str(data['given']))} {data['given']})"
                )
        self._recorder.finding(rule, text, line=line, stack=_outer(frames), data=data)

    def _error_data(
        self, frame: dict[str, Any], phase: str, type_name: str, message: str
    ) -> dict[str, object]:
        """What a raised state's finding carries for the run's probes: the state, the
        exception's type and text, the seconds a wait gave up after (the skeleton's helpers
        and most hand-written waits say "within N s"), the motion still under way then, and
        what the runtime's stand-ins add (tf2's missing frame and the frames it has)."""
        data: dict[str, object] = {"state": phase, "type": type_name, "detail": message}
        wait = _GAVE_UP.search(message)
        if wait is not None:
            data["seconds"] = float(wait["timeout"])
            data["action"] = wait["action"]
            data["under_way"] = self._motion_under_way(wait["action"])
        extra = frame.get("data")
        if isinstance(extra, dict):
            if isinstance(extra.get("frame"), str):
                data["frame"] = extra["frame"]
            if isinstance(extra.get("frames"), list):
                data["frames"] = [str(f) for f in extra["frames"]]
        return data

    def _still_running(self, message: str) -> str:
        """What to add when a state gave up "within N s" while the motion it waited for was
        still under way: the timeout, not the robot, was too short.

        The motion is a goal the server was still working on (or that the skill cancelled
        while it was), or, for a skill that drives the base itself, a velocity command other
        than zero in the last second before it gave up.
        """
        wait = _GAVE_UP.search(message)
        if wait is None:
            return ""
        what = self._motion_under_way(wait["action"])
        if what is None:
            return ""
        timeout = wait["timeout"]
        if wait["action"] is not None:
            return (
                f"{GAVE_UP_NOTE}{timeout} s while {what}: the result wait was too short, not "
                "the robot too slow; a result wait has to last as long as the whole goal can "
                "take (for a motion, its distance over the robot's speed, with a margin)"
            )
        return (
            f"{GAVE_UP_NOTE}{timeout} s while {what}: its timeout was too short, not the "
            "robot too slow; a wait for a motion has to last as long as the motion can take "
            "(its distance over the robot's speed, with a margin)"
        )

    def _motion_under_way(self, action: str | None) -> str | None:
        """What was still moving the robot for the state that is ending, if anything."""
        graph, since = self._graph, self._state_start
        running = [
            goal.action
            for goal, _ in graph.active_goals()
            if not goal.cancel_requested and action in (None, goal.action)
        ]
        if running:
            return f"the {running[0]} goal was still running"
        cancelled = [
            entry["action"]
            for entry in self._recorder.entries
            if entry["kind"] == "cancel"
            and entry.get("running")
            and entry["t"] >= since
            and action in (None, entry["action"])
        ]
        if cancelled:
            return f"the {cancelled[-1]} goal was still running (the skill cancelled it)"
        if action is not None:
            return None
        for topic, sent in graph.published.items():
            recent = [m for t, m, *_ in sent if t >= max(since, graph.now - 1.0)]
            if graph.published_type(topic) in MOTION_TYPES and any(
                not is_zero_motion(m) for m in recent
            ):
                return f"the base was still moving on its commands on {topic}"
        return None

    def _import_problem(self, message: str) -> str:
        """What an ImportError means here: a type or package the robot does not have, or a
        library the sandbox does not offer."""
        wanted = _IMPORT_NAME.match(message)
        if wanted is not None and wanted["namespace"] in {"msg", "srv", "action"}:
            type_name = f"{wanted['package']}/{wanted['namespace']}/{wanted['name']}"
            answer = self._registry.describe(type_name)
            if not answer.get("ok"):
                return str(answer["error"])
        missing = _NO_MODULE.match(message)
        if missing is not None:
            package = missing["module"].split(".")[0]
            return (
                f"{message}: the robot has no ROS 2 package {package}, and a skill may use only "
                "rclpy, tf2_ros, tf2_geometry_msgs, tf_transformations, pySkillUp, the robot's "
                "message packages, the Python standard library and numpy"
            )
        return message

    def _advance(self, frame: dict[str, Any]) -> dict[str, Any]:
        until = frame.get("until")
        if until is not None and not isinstance(until, (int, float)):
            raise TypeError("'until' must be a number or null")
        state = self._recorder.state
        if state is not None:
            deadline = self._scenario.deadlines.state
        elif self._settling:
            deadline = self._scenario.settle
        else:
            deadline = _LOAD_DEADLINE
        cap = self._state_start + deadline
        stop_cap = None
        if (
            state == "execute"
            and self._plan.stop_after is not None
            and self._execute_start is not None
        ):
            stop_cap = self._execute_start + self._plan.stop_after
            cap = min(cap, stop_cap)
        # The child says when nothing it runs can reply before `until` (plain sleeps, callbacks
        # that only store): then everything up to `until` goes out in one exchange. A child
        # that claims so wrongly only makes its own replies late.
        batch = frame.get("batch") is True
        deliveries = self._graph.advance(
            float(until) if until is not None else None, cap, batch=batch
        )
        reply: dict[str, Any] = {"now": self._graph.now, "deliveries": deliveries}
        if not deliveries and self._graph.now >= cap and (until is None or until > cap):
            if stop_cap is not None and cap >= stop_cap:
                reply["stop"] = "stop"
                if not self._stop_sent:
                    self._stop_sent = True
                    self._recorder.record("stop", line=self._recorder.line)
            elif state is not None:
                reply["stop"] = "deadline"
                reason = str(frame.get("reason") or "waiting")
                self._recorder.finding(
                    RUN_TIMEOUT,
                    f"{state} did not return within {self._scenario.deadlines.state:g} s of "
                    f"virtual time; it was waiting at line {self._recorder.line} ({reason})",
                    data={"state": state, "seconds": self._scenario.deadlines.state},
                )
            else:
                reply["stop"] = "deadline"
        return reply
