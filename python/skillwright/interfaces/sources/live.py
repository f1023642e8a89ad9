"""Interfaces of the running ROS 2 graph: snapshots until two agree, then one inventory.

Discovery on a live graph is eventually consistent: a node that starts a moment later, or
DDS discovery still in progress, makes one listing differ from the next. So the graph is
listed repeatedly (a bounded number of times, within a timeout) until two consecutive
snapshots agree on every name, type and publisher/subscriber count; if they never do,
the last snapshot is used and the source says so.

All the logic works on :class:`GraphAnswers`, the few questions asked of the graph. The
only implementation that talks to ROS 2 is
:mod:`~skillwright.interfaces.sources.rclpy_graph`; tests replay recorded answers.
Definitions are read from the installed interface files (``.msg``, ``.srv``,
``.action``) with every nested type expanded into ``MSG:`` blocks, the same text the bag
source parses; what cannot be fetched comes from the offline type store or is marked
unknown.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import TYPE_CHECKING, Final, Protocol

from skillwright.errors import InvalidArgumentError
from skillwright.interfaces.infrastructure import classify
from skillwright.interfaces.inventory import (
    Endpoints,
    Interface,
    InterfaceKind,
    Inventory,
    MessageDefinition,
    Resource,
    Source,
)
from skillwright.interfaces.ros2msg import (
    BUILTIN_TYPES,
    definition_from_text,
    normalize_type_name,
    parse_blocks,
    split_action,
    split_service,
)
from skillwright.interfaces.sources import InterfaceSource
from skillwright.interfaces.typestore import TypeStore, fill_missing_definitions, filled_note

if TYPE_CHECKING:
    from collections.abc import Iterable

__all__ = [
    "NOT_SETTLED",
    "GraphAnswers",
    "LiveSource",
    "Settled",
    "Snapshot",
    "discover_live",
    "interfaces_from_snapshot",
    "is_hidden",
    "settle",
    "take_snapshot",
]

NOT_SETTLED: Final = "the graph did not settle"
"""How the source note begins when no two consecutive snapshots agreed."""

ACTION_INFIX: Final = "/_action/"
_ACTION_TOPICS = ("feedback", "status")
_ACTION_SERVICES = ("send_goal", "get_result", "cancel_goal")
# The part of an action whose type names the action: pkg/action/T + suffix.
_ACTION_TYPE_SUFFIX = {
    "feedback": "_FeedbackMessage",
    "send_goal": "_SendGoal",
    "get_result": "_GetResult",
}
_ROLES: dict[InterfaceKind, tuple[tuple[str, str], ...]] = {
    "topic": (("message", ""),),
    "service": (("request", "_Request"), ("response", "_Response")),
    "action": (("goal", "_Goal"), ("result", "_Result"), ("feedback", "_Feedback")),
}
_KIND_ORDER = {"topic": 0, "service": 1, "action": 2}
_SEPARATOR_LINE = "=" * 80


class GraphAnswers(Protocol):
    """What discovery asks of a ROS 2 graph (rclpy's answers, or recorded ones)."""

    @property
    def location(self) -> str:
        """Which graph this is, for the inventory (domain id, middleware)."""
        ...

    @property
    def distro(self) -> str | None:
        """The ROS distribution of the installation asked (``ROS_DISTRO``), if known."""
        ...

    def topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every topic, hidden ones included, with its types."""
        ...

    def service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service, hidden ones included, with its types."""
        ...

    def action_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every action with its types."""
        ...

    def count_publishers(self, topic: str) -> int:
        """Publishers on ``topic`` now."""
        ...

    def count_subscribers(self, topic: str) -> int:
        """Subscribers of ``topic`` now."""
        ...

    def interface_text(self, type_name: str) -> str | None:
        """The installed ``.msg`` / ``.srv`` / ``.action`` file of ``pkg/ns/T``, or
        ``None`` when this installation does not have it."""
        ...


def is_hidden(name: str) -> bool:
    """Whether ROS 2 tools hide a name: one of its parts starts with ``_``."""
    return any(part.startswith("_") for part in name.split("/"))


# --- snapshots -------------------------------------------------------------------------


@dataclass(frozen=True)
class Snapshot:
    """One listing of the graph: names with their sorted types, and topic counts."""

    topics: dict[str, tuple[str, ...]]
    services: dict[str, tuple[str, ...]]
    actions: dict[str, tuple[str, ...]]
    counts: dict[str, tuple[int, int]]
    """``(publishers, subscribers)`` per topic, hidden ones included."""

    @property
    def empty(self) -> bool:
        """True when the graph showed nothing at all."""
        return not (self.topics or self.services or self.actions)


def _names_and_types(answer: Iterable[tuple[str, list[str]]]) -> dict[str, tuple[str, ...]]:
    merged: dict[str, set[str]] = {}
    for name, types in answer:
        merged.setdefault(name, set()).update(normalize_type_name(t) for t in types)
    return {name: tuple(sorted(types)) for name, types in sorted(merged.items())}


def take_snapshot(graph: GraphAnswers) -> Snapshot:
    """Lists topics, services and actions once, and counts each topic's endpoints."""
    topics = _names_and_types(graph.topic_names_and_types())
    return Snapshot(
        topics=topics,
        services=_names_and_types(graph.service_names_and_types()),
        actions=_names_and_types(graph.action_names_and_types()),
        counts={
            name: (graph.count_publishers(name), graph.count_subscribers(name)) for name in topics
        },
    )


@dataclass(frozen=True)
class Settled:
    """The outcome of :func:`settle`."""

    snapshot: Snapshot
    """The last snapshot taken."""
    attempts: int
    """Snapshots taken."""
    agreed: bool
    """Whether the last two agreed (and were not empty)."""
    elapsed: float
    """Seconds spent."""


def settle(
    graph: GraphAnswers,
    *,
    timeout: float,
    interval: float,
    max_attempts: int,
    clock: Callable[[], float] = time.monotonic,
    sleep: Callable[[float], None] = time.sleep,
) -> Settled:
    """Takes snapshots ``interval`` seconds apart until two consecutive ones agree, at most
    ``max_attempts`` of them and no longer than ``timeout`` seconds.

    Two empty snapshots do not count as agreement: right after start-up DDS discovery
    may not have seen anyone yet, so an empty graph is given the whole time to appear.
    """
    if timeout <= 0 or interval <= 0 or max_attempts < 2:
        raise InvalidArgumentError(
            f"live discovery needs a positive timeout and interval and at least 2 attempts "
            f"(got timeout {timeout}, interval {interval}, attempts {max_attempts})"
        )
    start = clock()
    previous: Snapshot | None = None
    attempts = 0
    while True:
        current = take_snapshot(graph)
        attempts += 1
        if previous is not None and current == previous and not current.empty:
            return Settled(current, attempts, True, clock() - start)
        previous = current
        remaining = timeout - (clock() - start)
        if attempts >= max_attempts or remaining <= 0:
            return Settled(current, attempts, False, clock() - start)
        sleep(min(interval, remaining))


# --- definitions -----------------------------------------------------------------------


def _base_type(type_text: str) -> str:
    """``geometry_msgs/Point[<=3]`` -> ``geometry_msgs/Point``; ``string<=5`` -> ``string``."""
    return type_text.split("[", 1)[0].split("<=", 1)[0]


@dataclass
class _Definitions:
    """Fetches interface files (each once) and expands nested types into ``MSG:`` blocks."""

    graph: GraphAnswers
    store: TypeStore
    texts: dict[str, str | None] = field(default_factory=dict)

    def text(self, type_name: str) -> str | None:
        if type_name not in self.texts:
            self.texts[type_name] = self.graph.interface_text(type_name)
        return self.texts[type_name]

    def _dependencies(self, type_name: str, text: str) -> tuple[dict[str, str], list[str]]:
        """Text of every type ``text`` uses, directly or not, and notes on fallbacks."""
        blocks: dict[str, str] = {}
        notes: list[str] = []
        queue = [(type_name, text)]
        while queue:
            current, current_text = queue.pop(0)
            main, _ = parse_blocks(current, current_text)
            package = current.split("/", 1)[0]
            for type_text, _, _ in main.fields:
                base = _base_type(type_text)
                if base in BUILTIN_TYPES:
                    continue
                nested = normalize_type_name(base, package)
                if nested in blocks:
                    continue
                nested_text = self.text(nested)
                if nested_text is not None:
                    blocks[nested] = nested_text
                    queue.append((nested, nested_text))
                    continue
                stored = self.store.text(nested)
                if stored is None:
                    continue  # left unresolved; definition_from_text notes the field
                stored_main, stored_blocks = parse_blocks(nested, stored[0])
                blocks[nested] = stored_main.text
                for name, block in stored_blocks.items():
                    blocks.setdefault(name, block.text)
                notes.append(
                    f"{nested} could not be fetched; taken from the offline ROS 2 "
                    f"{stored[1].capitalize()} type store"
                )
        return blocks, notes

    def definitions(
        self, kind: InterfaceKind, type_name: str
    ) -> tuple[dict[str, MessageDefinition], list[str]]:
        """Definitions by role and notes for the interface (empty when not fetched)."""
        text = self.text(type_name)
        if text is None:
            return {}, [f"the definition of {type_name} could not be fetched from ROS 2 here"]
        parts: tuple[str, ...] | None
        if kind == "service":
            parts = split_service(text)
        elif kind == "action":
            parts = split_action(text)
        else:
            parts = (text,)
        if parts is None:
            return {}, [f"the installed definition of {type_name} is not a valid {kind} file"]
        definitions: dict[str, MessageDefinition] = {}
        for (role, suffix), part in zip(_ROLES[kind], parts, strict=True):
            part_type = type_name + suffix
            blocks, notes = self._dependencies(part_type, part)
            full = part + "".join(
                f"\n{_SEPARATOR_LINE}\nMSG: {name}\n{block}" for name, block in blocks.items()
            )
            definition = definition_from_text(part_type, full)
            definition.notes = list(dict.fromkeys([*notes, *definition.notes]))
            definitions[role] = definition
        return definitions, []


# --- snapshot -> interfaces ------------------------------------------------------------


def _action_part(name: str, parts: tuple[str, ...]) -> tuple[str, str] | None:
    head, separator, tail = name.rpartition(ACTION_INFIX)
    if separator and head and tail in parts:
        return head, tail
    return None


def _actions(snapshot: Snapshot) -> dict[str, set[str]]:
    """Actions by name with their types: the graph's own list, plus any action whose
    hidden ``/_action/`` topics or services are seen without it."""
    actions: dict[str, set[str]] = {name: set(types) for name, types in snapshot.actions.items()}
    for names, parts in (
        (snapshot.topics, _ACTION_TOPICS),
        (snapshot.services, _ACTION_SERVICES),
    ):
        for name, types in names.items():
            found = _action_part(name, parts)
            if found is None:
                continue
            action, role = found
            known = actions.setdefault(action, set())
            suffix = _ACTION_TYPE_SUFFIX.get(role)
            for type_name in types:
                if suffix and type_name.endswith(suffix):
                    known.add(type_name.removesuffix(suffix))
    return actions


def interfaces_from_snapshot(
    snapshot: Snapshot, graph: GraphAnswers, store: TypeStore
) -> tuple[list[Interface], list[str]]:
    """Inventory entries for a snapshot (definitions fetched from ``graph``), and notes
    for the source."""
    fetch = _Definitions(graph, store)
    interfaces: list[Interface] = []

    def add(
        kind: InterfaceKind, name: str, types: Iterable[str], endpoints: Endpoints | None
    ) -> None:
        ordered = sorted(types) or [""]
        for type_name in ordered:
            definitions: dict[str, MessageDefinition] = {}
            notes: list[str] = []
            if type_name:
                definitions, notes = fetch.definitions(kind, type_name)
            else:
                notes.append(f"the type of {kind} {name} could not be told from the graph")
            if len(ordered) > 1:
                notes.append(f"{name}: offered with {len(ordered)} types")
            interfaces.append(
                Interface(
                    name=name,
                    kind=kind,
                    type_name=type_name,
                    definitions=definitions,
                    endpoints=endpoints.model_copy() if endpoints is not None else None,
                    infrastructure=classify(kind, name, type_name),
                    notes=notes,
                )
            )

    hidden = 0
    for name, types in snapshot.topics.items():
        if is_hidden(name):
            hidden += _action_part(name, _ACTION_TOPICS) is None
            continue
        publishers, subscribers = snapshot.counts.get(name, (0, 0))
        add("topic", name, types, Endpoints(publishers=publishers, subscribers=subscribers))
    for name, types in snapshot.services.items():
        if is_hidden(name):
            hidden += _action_part(name, _ACTION_SERVICES) is None
            continue
        add("service", name, types, None)
    for name, action_types in _actions(snapshot).items():
        status = snapshot.counts.get(f"{name}{ACTION_INFIX}status")
        endpoints = Endpoints(servers=status[0], clients=status[1]) if status else None
        add("action", name, action_types, endpoints)
    interfaces.sort(key=lambda i: (_KIND_ORDER[i.kind], i.name, i.type_name))
    notes = []
    if hidden:
        notes.append(
            f"{hidden} hidden topic(s) and service(s) (a name part starting with `_`) left "
            "out, as `ros2 topic list` and `ros2 service list` do"
        )
    return interfaces, notes


# --- discovery -------------------------------------------------------------------------


def discover_live(
    graph: GraphAnswers,
    *,
    timeout: float = 10.0,
    interval: float = 1.0,
    max_attempts: int = 10,
    resource_name: str | None = None,
    clock: Callable[[], float] = time.monotonic,
    sleep: Callable[[float], None] = time.sleep,
) -> Inventory:
    """The inventory of a live graph once it has settled (see :func:`settle`)."""
    captured = datetime.now(UTC).isoformat(timespec="seconds")
    outcome = settle(
        graph,
        timeout=timeout,
        interval=interval,
        max_attempts=max_attempts,
        clock=clock,
        sleep=sleep,
    )
    store = TypeStore(graph.distro)
    interfaces, notes = interfaces_from_snapshot(outcome.snapshot, graph, store)
    filled = fill_missing_definitions(interfaces, store=store)
    if filled:
        notes.append(filled_note(filled))
    if outcome.agreed:
        notes.insert(
            0,
            f"settled: snapshots {outcome.attempts - 1} and {outcome.attempts} agreed "
            f"({outcome.elapsed:.1f} s)",
        )
    else:
        notes.insert(
            0,
            f"{NOT_SETTLED}: no two consecutive of {outcome.attempts} snapshots agreed in "
            f"{outcome.elapsed:.1f} s; this is the last one (a longer --timeout waits more)",
        )
    if outcome.snapshot.empty:
        notes.append(
            "no topics, services or actions were seen: is the robot's ROS 2 system running, "
            "with the same ROS_DOMAIN_ID and middleware as this shell?"
        )
    return Inventory(
        resource=Resource(name=resource_name or "ros2_graph"),
        sources=[
            Source(
                kind="ros2_live",
                location=graph.location,
                ros_distro=graph.distro,
                captured_at=captured,
                notes=notes,
            )
        ],
        interfaces=interfaces,
    )


@dataclass
class LiveSource(InterfaceSource):
    """The running ROS 2 graph, through rclpy (which must be importable)."""

    timeout: float = 10.0
    interval: float = 1.0
    max_attempts: int = 10
    resource_name: str | None = None

    kind = "ros2_live"

    def discover(self) -> Inventory:
        """Starts a short-lived introspection node and discovers (see :func:`discover_live`).

        Raises :class:`~skillwright.errors.Ros2UnavailableError` when ROS 2 is not sourced.
        """
        from skillwright.interfaces.sources.rclpy_graph import open_graph

        with open_graph() as graph:
            return discover_live(
                graph,
                timeout=self.timeout,
                interval=self.interval,
                max_attempts=self.max_attempts,
                resource_name=self.resource_name,
            )
