"""The simulated ROS 2 graph on the host, and :class:`GraphHost`, the API worlds use.

The graph knows every topic, service and action of the robot's inventory. Messages on a
topic come from, in this order of precedence: a world plug-in that owns the topic, a
scenario's scripted publisher, the replayed recording (looped by default), or, for
inventories without a recording, a publisher of default messages at the topic's rate.
Services and actions are served by the world where it serves them, else by scripted
responders. Everything is scheduled in virtual time and delivered to the child when it
waits (see :meth:`GraphHost.advance`).

QoS is honoured where it decides whether messages arrive at all: a reliable subscription
to a best-effort publisher, or a transient-local one to a volatile publisher, gets
nothing (as in ROS 2), and a latched (transient-local) topic's last message reaches a
transient-local subscription created later.
"""

from __future__ import annotations

import difflib
import heapq
import itertools
import math
import random
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from skillwright.errors import FileFormatError
from skillwright.rules.run import (
    RUN_ACTION_UNKNOWN,
    RUN_QOS,
    RUN_SERVICE_UNKNOWN,
    RUN_TOPIC_UNKNOWN,
    RUN_TYPE,
    WORLD_REPORT,
)
from skillwright.runtime.api import (
    STATUS_NAMES,
    ActionGoal,
    ActionHandler,
    GoalStatus,
    ServiceHandler,
    ServiceReply,
    WorldPlugin,
)
from skillwright.runtime.recorded import MessageDecoder, RecordedMessageError, merged_messages
from skillwright.runtime.responders import ScriptedAction, ScriptedService
from skillwright.runtime.scenario import ActionScript, RunScenario, ServiceScript

if TYPE_CHECKING:
    from skillwright.interfaces.inventory import Inventory
    from skillwright.runtime.recorder import Recorder
    from skillwright.runtime.typesys import TypeRegistry

__all__ = ["Endpoint", "GraphHost", "Replay", "SentMessageError"]

Message = dict[str, Any]
_DEFAULT_RATE_HZ: Final = 10.0
_WORLD_CHECKS: Final = 5
"""Messages per topic of a world that are checked against the topic's type."""
_BATCH: Final = 64
"""Deliveries one batched advance gathers before it stops as a lockstep one would."""
_MAX_STEPS: Final = 200_000
"""Events one advance may process before the graph calls a world broken (a world whose
``next_event`` never moves on)."""


class SentMessageError(ValueError):
    """A message, request or goal of the skill that does not fit its ROS 2 type: the skill's
    field or type error (named with the field's path, the type expected and the value's
    type), not a break of the runtime's protocol."""


@dataclass
class Endpoint:
    """A publisher, subscription, client or action client the skill created."""

    id: int
    kind: str
    name: str
    type_name: str
    qos: dict[str, Any]
    line: int
    created: float
    connected: bool = True
    """False when its type or QoS means no traffic reaches it (a finding says why)."""
    received: int = 0
    destroyed: float | None = None


@dataclass
class _Topic:
    name: str
    type_name: str
    reliability: str | None = None
    durability: str | None = None
    recorded: int = 0
    rate_hz: float | None = None
    latched: tuple[Message | bytes, int] | None = None
    """The last message of a transient-local topic (decoded, or raw CDR) and its loop."""


@dataclass(order=True)
class _Scheduled:
    time: float
    sequence: int
    callback: Callable[[], None] = field(compare=False)


@dataclass
class _GoalRecord:
    client: int
    sequence: int
    goal: ActionGoal
    feedback: bool
    line: int


def _article(kind: str) -> str:
    return f"an {kind}" if kind[0] in "aeiou" else f"a {kind}"


def _shift_stamps(value: Any, offset_ns: int) -> Any:
    """Moves every ``stamp`` (builtin_interfaces/Time) in a message by ``offset_ns``."""
    if isinstance(value, dict):
        stamp = value.get("stamp")
        if isinstance(stamp, dict) and set(stamp) == {"sec", "nanosec"}:
            total = stamp["sec"] * 1_000_000_000 + stamp["nanosec"] + offset_ns
            value["stamp"] = {"sec": total // 1_000_000_000, "nanosec": total % 1_000_000_000}
        for key, item in value.items():
            if key != "stamp":
                _shift_stamps(item, offset_ns)
    elif isinstance(value, list) and value and isinstance(value[0], dict):
        for item in value:
            _shift_stamps(item, offset_ns)
    return value


class Replay:
    """The recorded messages of the topics someone listens to, in virtual time, looped if
    asked.

    Only topics asked for with :meth:`want` are replayed: a topic nobody subscribes to
    costs nothing, and a topic asked for later starts where its recording is at that
    time, as if it had been replayed all along. Reads lazily (one chunk at a time);
    payloads stay CDR until someone needs them.
    """

    def __init__(
        self, files: list[Path], topics: set[str], start_ns: int, end_ns: int, loop: bool
    ) -> None:
        merged_messages(files, set())  # refuses a file that is not MCAP now, not mid-run
        self._files = files
        self._topics = topics
        self._wanted: frozenset[str] = frozenset()
        self._start_ns = start_ns
        duration = max(0.0, (end_ns - start_ns) / 1e9)
        # The loop restarts on the next tenth of a second, so periodic topics keep
        # (nearly) their period across the seam.
        self.span = math.floor(duration * 10 + 1) / 10
        self._loop = loop
        self._round = 0
        self.damage: str | None = None
        """Where the recording broke, when replay got there (replay stops there)."""
        self._messages: Iterator[tuple[int, str, bytes]] = iter(())
        self._head: tuple[float, str, bytes, int] | None = None

    def want(self, topic: str, after: float | None) -> None:
        """Replays ``topic`` from now on, with the others wanted so far: the messages later
        than ``after`` (``None``: from the start), the earlier ones being gone already."""
        if topic not in self._topics or topic in self._wanted:
            return
        self._wanted = self._wanted | {topic}
        # Start again in the loop round before the one holding `after` (a margin for the
        # rounding of the times) and skip what the wanted topics have had already.
        looping = self._loop and self.span > 0
        self._round = max(0, math.floor(after / self.span) - 1) if after and looping else 0
        self._messages = self._open()
        head = self._pull()
        while head is not None and after is not None and max(0.0, head[0]) <= after:
            head = self._pull()
        self._head = head

    def _open(self) -> Iterator[tuple[int, str, bytes]]:
        return merged_messages(self._files, set(self._wanted))

    def _pull(self) -> tuple[float, str, bytes, int] | None:
        for _ in range(2):
            try:
                for log_time, topic, payload in self._messages:
                    offset = self._round * self.span
                    return (log_time - self._start_ns) / 1e9 + offset, topic, payload, self._round
            except FileFormatError as error:
                # A damaged recording is replayed as far as it is intact, like discovery
                # keeps what is intact.
                self.damage = str(error)
            if not self._loop or self.span <= 0:
                return None
            self._round += 1
            self._messages = self._open()
        return None

    def peek(self) -> float | None:
        """Virtual time of the next message, or ``None`` when the recording is over."""
        return None if self._head is None else max(0.0, self._head[0])

    def pop(self) -> tuple[str, bytes, int]:
        """The next message: topic, CDR payload and loop round."""
        assert self._head is not None
        _, topic, payload, round_ = self._head
        self._head = self._pull()
        return topic, payload, round_

    def offset_ns(self, round_: int) -> int:
        """How far the stamps of loop ``round_`` are moved."""
        return round(round_ * self.span * 1e9)


class GraphHost:
    """The simulated graph: what a world plug-in talks to, and what the child waits on.

    The public methods without a leading ``child_`` are the plug-in API documented in
    :mod:`skillwright.runtime`; the ``child_`` methods and :meth:`advance` serve the
    sandboxed skill.
    """

    def __init__(
        self,
        inventory: Inventory,
        registry: TypeRegistry,
        recorder: Recorder,
        scenario: RunScenario,
        *,
        recording: list[Path] | None = None,
        epoch_ns: int = 1_767_225_600 * 1_000_000_000,
    ) -> None:
        self.registry = registry
        self.inventory = inventory
        self.rng = random.Random(scenario.seed)
        self._recorder = recorder
        self._scenario = scenario
        self.lookahead = scenario.lookahead
        """Virtual seconds the graph may run ahead of the skill after a delivery."""
        self._epoch_ns = epoch_ns
        self._now = 0.0
        self._heap: list[_Scheduled] = []
        self._sequence = itertools.count()
        self._outbox: list[Message] = []
        self._decoder = MessageDecoder(registry)
        self.endpoints: dict[int, Endpoint] = {}
        self._topics: dict[str, _Topic] = {}
        self._services: dict[str, str] = {}
        self._actions: dict[str, str] = {}
        self._service_handlers: dict[str, ServiceHandler] = {}
        self._action_handlers: dict[str, ActionHandler] = {}
        self._world_services: set[str] = set()
        self._world_actions: set[str] = set()
        self._owned: set[str] = set()
        self._world_checked: dict[str, int] = {}
        self._watchers: dict[str, list[Callable[[float, Message], None]]] = {}
        self._publishers_running: set[str] = set()
        self._goals: dict[int, _GoalRecord] = {}
        self._goal_ids = itertools.count(1)
        self.published: dict[str, list[tuple[float, Message, int, str | None, int]]] = {}
        """Topic -> every message the skill published: (time, message, line, state, number)."""
        self.publish_count = 0
        """How many messages the skill has published so far (numbers them)."""
        self._published_types: dict[str, str] = {}
        self._world: WorldPlugin | None = None
        for interface in inventory.interfaces:
            if interface.kind == "topic":
                qos = interface.qos[0] if interface.qos else None
                traffic = interface.traffic
                self._topics[interface.name] = _Topic(
                    name=interface.name,
                    type_name=interface.type_name,
                    reliability=qos.reliability if qos else None,
                    durability=qos.durability if qos else None,
                    recorded=traffic.message_count if traffic else 0,
                    rate_hz=traffic.rate_hz if traffic else None,
                )
            elif interface.kind == "service":
                self._services[interface.name] = interface.type_name
            else:
                self._actions[interface.name] = interface.type_name
        for name, type_name in self._services.items():
            script = scenario.services.get(name, ServiceScript())
            self._service_handlers[name] = ScriptedService(registry, type_name, script)
        for name, type_name in self._actions.items():
            action_script = scenario.actions.get(name, ActionScript())
            self._action_handlers[name] = ScriptedAction(self, registry, type_name, action_script)
        self._replay = (
            self._open_replay(recording, inventory)
            if recording and scenario.replay != "off"
            else None
        )
        self._replay_started = False
        self._traffic_all = scenario.traffic == "all"
        self._listening: dict[str, list[Endpoint]] = {}
        # Virtual time up to which everything due has run (None: nothing has yet).
        self._consumed: float | None = None

    def _open_replay(self, files: list[Path], inventory: Inventory) -> Replay | None:
        source = next((s for s in inventory.sources if s.start_time_ns is not None), None)
        if source is None or source.start_time_ns is None or source.end_time_ns is None:
            return None
        topics = {
            name
            for name, topic in self._topics.items()
            if topic.recorded and self._scenario.topics.get(name) is None
        }
        try:
            return Replay(
                files,
                topics,
                source.start_time_ns,
                source.end_time_ns,
                self._scenario.replay == "loop",
            )
        except (OSError, FileFormatError) as error:
            self._recorder.record("note", text=f"recording not replayed: {error}")
            return None

    # --- the plug-in API ------------------------------------------------------------

    @property
    def now(self) -> float:
        """Virtual seconds since the run started."""
        return self._now

    def stamp(self, t: float | None = None) -> dict[str, int]:
        """ROS time of virtual time ``t`` (default: now) as ``{"sec", "nanosec"}``."""
        total = self._epoch_ns + round((self._now if t is None else t) * 1e9)
        return {"sec": total // 1_000_000_000, "nanosec": total % 1_000_000_000}

    def own_topic(self, topic: str) -> None:
        """The world publishes ``topic`` from now on; replay and defaults on it stop."""
        self._owned.add(topic)

    def wants(self, topic: str) -> bool:
        """Whether a message published on ``topic`` now would reach anyone: a subscription
        of the skill, or the last-message slot of a latched (transient-local) topic.

        A world may skip making messages nobody wants (its own state must still advance).
        Unknown topics are wanted, so that :meth:`publish` reports them. With the scenario's
        ``traffic: all`` every topic is wanted.
        """
        info = self._topics.get(topic)
        return (
            info is None
            or self._traffic_all
            or bool(self._listening.get(topic))
            or info.durability == "transient_local"
        )

    def publish(self, topic: str, message: Message) -> None:
        """Delivers ``message`` on ``topic`` to the skill's subscriptions at ``now``.

        The first messages on each topic are checked against its type (a ``ValueError``
        names a field that does not fit); later ones are trusted to keep their shape,
        since checking every 50 Hz message would cost more than simulating it.
        """
        info = self._topics.get(topic)
        if info is None:
            raise ValueError(f"the robot has no topic {topic}; worlds publish on its topics only")
        checked = self._world_checked.get(topic, 0)
        if checked < _WORLD_CHECKS:
            self._world_checked[topic] = checked + 1
            message = self.registry.conform(info.type_name, message, topic)
        self._deliver_topic(topic, message)

    def on_publish(self, topic: str, callback: Callable[[float, Message], None]) -> None:
        """Calls ``callback(time, message)`` for every message the skill publishes on ``topic``
        with the robot's type for it."""
        self._watchers.setdefault(topic, []).append(callback)

    def serve_service(self, name: str, handler: ServiceHandler) -> None:
        """Replaces the scripted responder of service ``name``."""
        if name not in self._services:
            raise ValueError(f"the robot has no service {name}")
        self._service_handlers[name] = handler
        self._world_services.add(name)

    def serve_action(self, name: str, handler: ActionHandler) -> None:
        """Replaces the scripted server of action ``name``."""
        if name not in self._actions:
            raise ValueError(f"the robot has no action {name}")
        self._action_handlers[name] = handler
        self._world_actions.add(name)

    def call_later(self, delay: float, callback: Callable[[], None]) -> None:
        """Runs ``callback()`` at ``now + delay`` (virtual)."""
        self._schedule(self._now + max(0.0, float(delay)), callback)

    def message(self, type_name: str) -> Message:
        """A message of ``type_name`` with every field at its default."""
        return self.registry.default(type_name)

    def has_interface(self, name: str, kind: str | None = None) -> bool:
        """Whether the robot has ``name`` (as a ``topic``, ``service`` or ``action``)."""
        kinds = {
            "topic": name in self._topics,
            "service": name in self._services,
            "action": name in self._actions,
        }
        return kinds.get(kind, False) if kind is not None else any(kinds.values())

    def type_of(self, name: str) -> str | None:
        """The type of topic, service or action ``name``, or ``None``."""
        topic = self._topics.get(name)
        if topic is not None:
            return topic.type_name
        return self._services.get(name) or self._actions.get(name)

    def topics(self, type_name: str) -> list[str]:
        """The robot's topics of ``type_name``, sorted."""
        return sorted(name for name, topic in self._topics.items() if topic.type_name == type_name)

    def scripted(self, topic: str) -> bool:
        """Whether the scenario's script publishes ``topic``."""
        return topic in self._topics and topic in self._scenario.topics

    def provided(self, topic: str) -> bool:
        """Whether the scenario's script or the replayed recording publishes ``topic``."""
        info = self._topics.get(topic)
        if info is None:
            return False
        return topic in self._scenario.topics or (self._replay is not None and bool(info.recorded))

    def report(
        self, check: str, message: str, severity: str = "error", line: int | None = None
    ) -> None:
        """A finding of the world; ``line`` defaults to the skill's latest call's line."""
        self._recorder.finding(
            WORLD_REPORT,
            f"{check}: {message}",
            line=line,
            severity="warning" if severity == "warning" else "error",
            data={"check": check},
        )

    def record(self, kind: str, data: dict[str, Any]) -> None:
        """A trace entry of the world."""
        self._recorder.record(f"world.{kind}", **data)

    # --- world ------------------------------------------------------------------------

    def attach_world(self, world: WorldPlugin) -> None:
        """Connects a world plug-in (it claims topics and servers in ``attach``)."""
        self._world = world
        world.attach(self)

    def close(self) -> None:
        """Closes the world, if any, and notes a recording that broke during replay."""
        if self._replay is not None and self._replay.damage is not None:
            self._recorder.record("note", text=f"replay stopped early: {self._replay.damage}")
        if self._world is not None:
            world, self._world = self._world, None
            world.close()

    # --- scheduling -----------------------------------------------------------------

    def _schedule(self, time: float, callback: Callable[[], None]) -> None:
        heapq.heappush(self._heap, _Scheduled(time, next(self._sequence), callback))

    def _next_time(self) -> float | None:
        candidates = []
        if self._heap:
            candidates.append(self._heap[0].time)
        if self._replay is not None:
            head = self._replay.peek()
            if head is not None:
                candidates.append(head)
        if self._world is not None:
            world_next = self._world.next_event()
            if world_next is not None:
                candidates.append(max(world_next, self._now))
        return min(candidates) if candidates else None

    def _move_to(self, time: float) -> None:
        if time > self._now:
            self._now = time
            self._recorder.now = time
        if self._world is not None:
            self._world.advance(self._now)

    def _run_due(self) -> None:
        while self._heap and self._heap[0].time <= self._now:
            heapq.heappop(self._heap).callback()
        while self._replay is not None:
            head = self._replay.peek()
            if head is None or head > self._now:
                break
            topic, payload, round_ = self._replay.pop()
            self._replayed(topic, payload, round_)

    def advance(self, until: float | None, cap: float, *, batch: bool = False) -> list[Message]:
        """Steps the graph towards ``until`` (``None``: the next event, whenever it is),
        never beyond ``cap``, and returns the deliveries on the way, each with its time
        ``t``, in time order.

        The graph stops :attr:`lookahead` after the first delivery, so that the skill's
        reaction to it comes back in time; deliveries waiting from the skill's own calls
        (an immediate service answer) come back at once without moving time. With
        ``batch`` (the skill cannot react before ``until``) it goes on to ``until``,
        stopping early only once :data:`_BATCH` deliveries are waiting.
        """
        if self._outbox:
            return self._take()
        if not self._replay_started:
            self._start_replay()
        target = cap if until is None else min(until, cap)
        target = max(target, self._now)
        for _ in range(_MAX_STEPS):
            due = self._next_time()
            if due is None or due > target:
                self._move_to(target)
                self._consumed = self._now
                return self._take()
            self._move_to(due)
            self._run_due()
            if self._outbox and (not batch or len(self._outbox) >= _BATCH):
                # Run ahead of the skill by at most the lookahead: what it does in reply to
                # these deliveries reaches the graph that much later at most.
                target = min(target, self._now + self.lookahead)
        raise RuntimeError(
            f"the simulation made {_MAX_STEPS} steps at {self._now:.3f} s without moving on "
            "(a world whose next_event() does not advance)"
        )

    def _start_replay(self) -> None:
        """Replays the latched topics the world does not own from the start (their last
        message waits for transient-local subscriptions made later); with ``traffic: all``,
        every recorded topic."""
        self._replay_started = True
        if self._replay is None:
            return
        for name, info in self._topics.items():
            if self._traffic_all or (
                info.durability == "transient_local" and name not in self._owned
            ):
                self._replay.want(name, None)

    def _out(self, delivery: Message) -> None:
        delivery["t"] = self._now
        self._outbox.append(delivery)

    def _take(self) -> list[Message]:
        out, self._outbox = self._outbox, []
        return out

    # --- topics ---------------------------------------------------------------------

    def _subscribers(self, topic: str) -> list[Endpoint]:
        return self._listening.get(topic, [])

    def _deliver_topic(self, topic: str, data: Message | bytes, round_: int = 0) -> None:
        info = self._topics.get(topic)
        if info is not None and info.durability == "transient_local":
            info.latched = (data, round_)
        subscribers = self._subscribers(topic)
        if not subscribers:
            return
        message = self._decoded(topic, data, round_)
        if message is None:
            return
        for endpoint in subscribers:
            endpoint.received += 1
            self._out({"id": endpoint.id, "data": message})

    def _decoded(self, topic: str, data: Message | bytes, round_: int) -> Message | None:
        if isinstance(data, dict):
            return data
        info = self._topics[topic]
        try:
            message = self._decoder.decode(info.type_name, data)
        except RecordedMessageError as error:
            self._recorder.record("note", text=f"{topic}: recorded message not replayed: {error}")
            return None
        if round_ and self._replay is not None:
            _shift_stamps(message, self._replay.offset_ns(round_))
        return message

    def _replayed(self, topic: str, payload: bytes, round_: int) -> None:
        if topic in self._owned:
            return
        self._deliver_topic(topic, payload, round_)

    def _scripted(self, topic: str) -> tuple[float, Message] | None:
        """The rate and message of a scripted or default publisher of ``topic``, if any."""
        info = self._topics.get(topic)
        if info is None or topic in self._owned:
            return None
        script = self._scenario.topics.get(topic)
        if script is not None:
            if script.silent or script.rate_hz is None:
                return None
            message = self.registry.conform(
                info.type_name, script.message, f"scenario topic {topic}"
            )
            return script.rate_hz, message
        if self._replay is not None and info.recorded:
            return None
        recorded_source = any(s.start_time_ns is not None for s in self.inventory.sources)
        if recorded_source and not info.recorded:
            # The recording saw nobody publish it; the simulation does not invent traffic.
            return None
        if self.registry.message(info.type_name) is None:
            return None
        return info.rate_hz or _DEFAULT_RATE_HZ, self.registry.default(info.type_name)

    def _start_publisher(self, topic: str) -> None:
        if topic in self._publishers_running:
            return
        scripted = self._scripted(topic)
        if scripted is None:
            return
        rate, message = scripted
        period = 1.0 / rate
        self._publishers_running.add(topic)

        def publish() -> None:
            if topic in self._owned:
                return
            data = dict(message)
            if "header" in data and isinstance(data["header"], dict):
                data["header"] = {**data["header"], "stamp": self.stamp()}
            self._deliver_topic(topic, data)
            self._schedule(self._now + period, publish)

        first = (math.floor(self._now / period) + 1) * period
        self._schedule(first, publish)

    def _publishes(self, topic: str) -> bool:
        """Whether anything in this run publishes ``topic`` (besides the skill)."""
        info = self._topics.get(topic)
        if info is None:
            return False
        if topic in self._owned:
            return True
        script = self._scenario.topics.get(topic)
        if script is not None:
            return not script.silent and script.rate_hz is not None
        if self._replay is not None and info.recorded:
            return True
        return self._scripted(topic) is not None

    # --- the child's calls ----------------------------------------------------------

    def _suggest(self, name: str, names: list[str]) -> str:
        close = difflib.get_close_matches(name, names, n=1, cutoff=0.6)
        return f" (did you mean {close[0]}?)" if close else ""

    def _kind_of(self, name: str) -> str | None:
        if name in self._topics:
            return "topic"
        if name in self._services:
            return "service"
        if name in self._actions:
            return "action"
        return None

    def child_endpoint(self, frame: dict[str, Any]) -> Endpoint:
        """The skill created a publisher, subscription, client, service or action client."""
        endpoint = Endpoint(
            id=int(frame["id"]),
            kind=str(frame["kind"]),
            name=str(frame["name"]),
            type_name=str(frame["type"]),
            qos=dict(frame.get("qos") or {}),
            line=int(frame.get("line") or 0),
            created=self._now,
        )
        replaced = self.endpoints.get(endpoint.id)
        if replaced is not None and replaced in self._listening.get(replaced.name, []):
            self._listening[replaced.name].remove(replaced)
        self.endpoints[endpoint.id] = endpoint
        self._recorder.record(
            "endpoint",
            endpoint=endpoint.kind,
            name=endpoint.name,
            type=endpoint.type_name,
            line=endpoint.line,
        )
        if endpoint.kind in {"publisher", "subscription"}:
            self._check_topic_endpoint(endpoint)
        elif endpoint.kind == "client":
            self._check_named(endpoint, "service", self._services)
        elif endpoint.kind == "action_client":
            self._check_named(endpoint, "action", self._actions)
        if endpoint.kind == "subscription" and endpoint.connected:
            # Kept in creation order: deliveries go out in that order.
            self._listening.setdefault(endpoint.name, []).append(endpoint)
            if self._replay is not None and endpoint.name not in self._owned:
                self._replay.want(endpoint.name, self._consumed)
            self._start_publisher(endpoint.name)
            self._deliver_latched(endpoint)
        return endpoint

    def _check_topic_endpoint(self, endpoint: Endpoint) -> None:
        verb = "publishes on" if endpoint.kind == "publisher" else "subscribes to"
        info = self._topics.get(endpoint.name)
        if info is None:
            other = self._kind_of(endpoint.name)
            if other is not None:
                problem = f"{endpoint.name} is {_article(other)} of the robot, not a topic"
            else:
                problem = f"the robot has no topic {endpoint.name}" + self._suggest(
                    endpoint.name, list(self._topics)
                )
            self._recorder.finding(
                RUN_TOPIC_UNKNOWN, f"{verb} {endpoint.name}: {problem}", line=endpoint.line
            )
            endpoint.connected = endpoint.kind == "publisher"
            return
        if endpoint.type_name != info.type_name:
            self._recorder.finding(
                RUN_TYPE,
                f"{verb} {endpoint.name} with {endpoint.type_name}, but its type is "
                f"{info.type_name}: "
                + (
                    "the robot never receives these messages"
                    if endpoint.kind == "publisher"
                    else "no message will arrive"
                ),
                line=endpoint.line,
            )
            endpoint.connected = False
            return
        if endpoint.kind == "subscription":
            wanted_reliable = endpoint.qos.get("reliability") == "reliable"
            wanted_latched = endpoint.qos.get("durability") == "transient_local"
            if wanted_reliable and info.reliability == "best_effort":
                self._recorder.finding(
                    RUN_QOS,
                    f"subscribes to {endpoint.name} as reliable (an int depth means reliable), but "
                    "the robot publishes it best-effort, so no message will arrive: subscribe "
                    "with rclpy.qos.qos_profile_sensor_data or a best-effort QoSProfile",
                    line=endpoint.line,
                )
                endpoint.connected = False
            elif wanted_latched and info.durability == "volatile":
                self._recorder.finding(
                    RUN_QOS,
                    f"subscribes to {endpoint.name} as transient-local, but the robot publishes it "
                    "volatile, so no message will arrive: use a volatile QoS",
                    line=endpoint.line,
                )
                endpoint.connected = False

    def _check_named(self, endpoint: Endpoint, kind: str, known: dict[str, str]) -> None:
        what = "a client of" if kind == "service" else "an action client of"
        robot_type = known.get(endpoint.name)
        if robot_type is None:
            other = self._kind_of(endpoint.name)
            problem = (
                f"{endpoint.name} is {_article(other)} of the robot, not {_article(kind)}"
                if other is not None
                else f"the robot has no {kind} {endpoint.name}"
                + self._suggest(endpoint.name, list(known))
            )
            self._recorder.finding(
                (RUN_SERVICE_UNKNOWN if kind == "service" else RUN_ACTION_UNKNOWN),
                f"creates {what} {endpoint.name}: {problem}",
                line=endpoint.line,
            )
            endpoint.connected = False
        elif robot_type != endpoint.type_name:
            self._recorder.finding(
                RUN_TYPE,
                f"creates {what} {endpoint.name} with {endpoint.type_name}, "
                f"but its type is {robot_type}",
                line=endpoint.line,
            )
            endpoint.connected = False

    def _deliver_latched(self, endpoint: Endpoint) -> None:
        info = self._topics.get(endpoint.name)
        if (
            info is None
            or info.latched is None
            or endpoint.qos.get("durability") != "transient_local"
        ):
            return
        data, round_ = info.latched
        message = self._decoded(endpoint.name, data, round_)
        if message is not None:
            endpoint.received += 1
            self._out({"id": endpoint.id, "data": message})

    def child_destroy(self, handle: int) -> None:
        """The skill destroyed a handle."""
        endpoint = self.endpoints.get(handle)
        if endpoint is not None and endpoint.destroyed is None:
            endpoint.destroyed = self._now
            listening = self._listening.get(endpoint.name, [])
            if endpoint in listening:
                listening.remove(endpoint)
            self._recorder.record("destroy", endpoint=endpoint.kind, name=endpoint.name)

    def _endpoint(self, handle: Any, kind: str) -> Endpoint:
        endpoint = self.endpoints.get(handle) if isinstance(handle, int) else None
        if endpoint is None or endpoint.kind != kind:
            raise ValueError(f"no {kind} with id {handle!r}")
        return endpoint

    def _sent(self, type_name: str, value: Any, where: str) -> dict[str, Any]:
        """A message the skill sent, checked against its type: :class:`SentMessageError`
        names the field that does not fit (rclpy's publish, call and send_goal refuse such
        a message in the skill's own process)."""
        try:
            return self.registry.conform(type_name, value, where)
        except ValueError as error:
            raise SentMessageError(str(error)) from error

    def child_publish(self, handle: Any, message: Any, line: int, state: str | None) -> None:
        """The skill published a message."""
        endpoint = self._endpoint(handle, "publisher")
        data = self._sent(endpoint.type_name, message, f"message on {endpoint.name}")
        self._recorder.record("publish", topic=endpoint.name, message=data, line=line)
        self.published.setdefault(endpoint.name, []).append(
            (self._now, data, line, state, self.publish_count)
        )
        self.publish_count += 1
        self._published_types[endpoint.name] = endpoint.type_name
        info = self._topics.get(endpoint.name)
        if info is not None and info.type_name == endpoint.type_name:
            for callback in self._watchers.get(endpoint.name, []):
                callback(self._now, data)
        for subscriber in self._subscribers(endpoint.name):
            if subscriber.type_name == endpoint.type_name:
                subscriber.received += 1
                self._out({"id": subscriber.id, "data": data})

    def exists(self, kind: str, name: str) -> bool:
        """Whether a server of service or action ``name`` is up."""
        if kind == "service":
            script = self._scenario.services.get(name)
            return name in self._services and (
                name in self._world_services or script is None or script.available
            )
        action_script = self._scenario.actions.get(name)
        return name in self._actions and (
            name in self._world_actions or action_script is None or action_script.available
        )

    def count(self, what: str, name: str) -> int:
        """Publishers or subscribers of a topic, as the skill's node would count them."""
        own_kind = "publisher" if what == "publishers" else "subscription"
        own = sum(
            1
            for e in self.endpoints.values()
            if e.kind == own_kind and e.name == name and e.destroyed is None
        )
        if what == "publishers":
            return own + (1 if self._publishes(name) else 0)
        return own + (1 if name in self._topics else 0)

    def robot_endpoints(self, what: str, name: str) -> list[dict[str, Any]]:
        """The robot's publishers or subscribers of a topic (those :meth:`count` adds to the
        skill's own): their type and the QoS that discovery shares (reliability and
        durability; a recorded subscriber's QoS is not known)."""
        info = self._topics.get(name)
        if info is None or (what == "publishers" and not self._publishes(name)):
            return []
        if what == "publishers":
            return [
                {
                    "type": info.type_name,
                    "reliability": info.reliability,
                    "durability": info.durability,
                }
            ]
        return [{"type": info.type_name, "reliability": None, "durability": None}]

    def names_and_types(self, kind: str) -> list[list[Any]]:
        """``[[name, [type]], ...]`` of the robot's topics or services."""
        known = (
            {t.name: t.type_name for t in self._topics.values()}
            if kind == "topic"
            else self._services
        )
        return [[name, [type_name]] for name, type_name in sorted(known.items())]

    def child_call(self, handle: Any, sequence: Any, request: Any, line: int) -> None:
        """The skill called a service."""
        endpoint = self._endpoint(handle, "client")
        data = self._sent(endpoint.type_name + "_Request", request, f"request to {endpoint.name}")
        self._recorder.record("call", service=endpoint.name, request=data, line=line)
        if not endpoint.connected or not self.exists("service", endpoint.name):
            self._recorder.record(
                "note", text=f"nobody serves {endpoint.name}; the call is never answered"
            )
            return
        try:
            reply = self._service_handlers[endpoint.name](data)
        except Exception as error:
            self.report("service", f"the server of {endpoint.name} failed: {error}", line=line)
            return
        if not isinstance(reply, ServiceReply):
            reply = ServiceReply(reply)
        if reply.response is None:
            return
        response = self.registry.conform(
            endpoint.type_name + "_Response", reply.response, f"response of {endpoint.name}"
        )

        def answer() -> None:
            self._recorder.record("response", service=endpoint.name, response=response)
            self._out({"id": endpoint.id, "seq": sequence, "data": response})

        self.call_later(reply.delay, answer)

    def child_goal(
        self, handle: Any, sequence: Any, request: Any, feedback: bool, line: int
    ) -> None:
        """The skill sent an action goal."""
        endpoint = self._endpoint(handle, "action_client")
        data = self._sent(endpoint.type_name + "_Goal", request, f"goal to {endpoint.name}")
        goal = ActionGoal(
            action=endpoint.name, goal_id=next(self._goal_ids), request=data, _sink=self
        )
        self._goals[goal.goal_id] = _GoalRecord(
            endpoint.id, int(sequence), goal, bool(feedback), line
        )
        self._recorder.record(
            "goal", action=endpoint.name, goal=data, goal_id=goal.goal_id, line=line
        )
        if not endpoint.connected or not self.exists("action", endpoint.name):
            self._recorder.record(
                "note", text=f"no server of {endpoint.name}; the goal is never answered"
            )
            return
        try:
            self._action_handlers[endpoint.name].on_goal(goal)
        except Exception as error:
            self.report("action", f"the server of {endpoint.name} failed: {error}", line=line)

    def child_cancel(self, handle: Any, sequence: Any, line: int) -> None:
        """The skill asked to cancel one of its goals."""
        endpoint = self._endpoint(handle, "action_client")
        record = next(
            (r for r in self._goals.values() if r.client == endpoint.id and r.sequence == sequence),
            None,
        )
        running = record is not None and record.goal.active and not record.goal.cancel_requested
        self._recorder.record("cancel", action=endpoint.name, line=line, running=running)
        if record is None:
            self._out({"id": endpoint.id, "kind": "cancel", "goal": sequence, "return_code": 2})
            return
        goal = record.goal
        code = 3
        if goal.active:
            goal.cancel_requested = True
            accepted = False
            try:
                accepted = bool(self._action_handlers[endpoint.name].on_cancel(goal))
            except Exception as error:
                self.report(
                    "action", f"the server of {endpoint.name} failed to cancel: {error}", line=line
                )
            if accepted and goal.active:
                goal.status = GoalStatus.CANCELING
            code = 0 if accepted else 1
        self._out({"id": endpoint.id, "kind": "cancel", "goal": sequence, "return_code": code})

    # --- the goal sink (ActionGoal calls these) -------------------------------------

    def goal_accepted(self, goal: ActionGoal, accepted: bool) -> None:
        record = self._goals[goal.goal_id]
        self._recorder.record(
            "goal_response", action=goal.action, goal_id=goal.goal_id, accepted=accepted
        )
        self._out(
            {
                "id": record.client,
                "kind": "accepted",
                "goal": record.sequence,
                "accepted": accepted,
                "stamp": self.stamp(),
            }
        )

    def goal_feedback(self, goal: ActionGoal, feedback: Message) -> None:
        record = self._goals[goal.goal_id]
        type_name = self._actions[goal.action] + "_Feedback"
        data = self.registry.conform(type_name, feedback, f"feedback of {goal.action}")
        self._recorder.record("feedback", action=goal.action, goal_id=goal.goal_id, feedback=data)
        if record.feedback:
            self._out(
                {"id": record.client, "kind": "feedback", "goal": record.sequence, "data": data}
            )

    def goal_finished(self, goal: ActionGoal, status: int, result: Message | None) -> None:
        record = self._goals[goal.goal_id]
        type_name = self._actions[goal.action] + "_Result"
        data = self.registry.conform(type_name, result or {}, f"result of {goal.action}")
        self._recorder.record(
            "result",
            action=goal.action,
            goal_id=goal.goal_id,
            status=STATUS_NAMES.get(status, status),
            result=data,
        )
        self._out(
            {
                "id": record.client,
                "kind": "result",
                "goal": record.sequence,
                "status": status,
                "data": data,
            }
        )

    def published_type(self, topic: str) -> str | None:
        """The type the skill published ``topic`` with, if it published on it."""
        return self._published_types.get(topic)

    def active_goals(self) -> list[tuple[ActionGoal, int]]:
        """Goals still accepted or running, with the skill line that sent them."""
        return [(r.goal, r.line) for r in self._goals.values() if r.goal.active]

    def silent_subscriptions(self) -> list[Endpoint]:
        """Subscriptions that got nothing because nobody publishes their topic."""
        return [
            e
            for e in self.endpoints.values()
            if e.kind == "subscription"
            and e.connected
            and e.received == 0
            and not self._publishes(e.name)
        ]
