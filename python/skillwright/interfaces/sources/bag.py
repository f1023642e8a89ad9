"""Interfaces from MCAP recordings: one ``.mcap`` file or a rosbag2 folder.

The Rust core reads each file (summary section when it can, a record scan when it
must); this module merges split files, adds what ``metadata.yaml`` knows (QoS, the
ROS distribution), and turns recorded channels into ROS 2 interfaces: plain topics,
services (recorded as ``<service>/_service_event``) and actions (``<action>/_action/
feedback|status`` plus the service events of ``send_goal``, ``get_result`` and
``cancel_goal``).
"""

from __future__ import annotations

import base64
import re
import threading
from collections.abc import Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from skillwright.cancel import raise_if_cancelled
from skillwright.errors import FileFormatError, InputFileNotFoundError, InvalidArgumentError
from skillwright.interfaces.infrastructure import classify
from skillwright.interfaces.inventory import (
    ChannelRef,
    Damage,
    Interface,
    InterfaceKind,
    Inventory,
    MessageDefinition,
    QosProfile,
    Resource,
    Source,
    SourceFile,
    Traffic,
)
from skillwright.interfaces.ros2msg import (
    Block,
    definition_from_text,
    find_block,
    normalize_type_name,
    parse_blocks,
    split_action,
    split_service,
)
from skillwright.interfaces.sources import InterfaceSource
from skillwright.interfaces.typestore import fill_missing_definitions, filled_note

if TYPE_CHECKING:
    from skillwright.core import McapFile

__all__ = ["BagSource", "ReadMode", "discover_bag", "resolve_recording"]

ReadMode = Literal["auto", "scan", "full"]

SERVICE_EVENT_SUFFIX = "/_service_event"
ACTION_INFIX = "/_action/"
_ACTION_SERVICES = ("send_goal", "get_result", "cancel_goal")
_ACTION_TOPICS = ("feedback", "status")
_KIND_ORDER = {"topic": 0, "service": 1, "action": 2}


@dataclass
class Recording:
    """The files of one recording and what its ``metadata.yaml`` says."""

    kind: Literal["mcap", "rosbag2"]
    location: Path
    files: list[Path]
    metadata: dict[str, Any] | None = None
    notes: list[str] = field(default_factory=list)


def _split_index(path: Path) -> tuple[int, str]:
    match = re.search(r"_(\d+)$", path.stem)
    return (int(match.group(1)) if match else -1, path.name)


def resolve_recording(path: Path) -> Recording:
    """The files to read for ``path``: an ``.mcap`` file, a rosbag2 folder (with or
    without ``metadata.yaml``) or the ``metadata.yaml`` of one."""
    if not path.exists():
        raise InputFileNotFoundError(
            f"{path}: no such file or folder; give an .mcap file or a rosbag2 folder"
        )
    if path.is_file() and path.name != "metadata.yaml":
        return Recording(kind="mcap", location=path, files=[path])
    folder = path if path.is_dir() else path.parent
    metadata_path = folder / "metadata.yaml"
    notes: list[str] = []
    metadata = _load_metadata(metadata_path) if metadata_path.is_file() else None
    files: list[Path] = []
    if metadata is not None:
        storage = metadata.get("storage_identifier")
        if storage not in (None, "mcap"):
            raise FileFormatError(
                f"{metadata_path}: the bag uses {storage!r} storage; skillwright reads MCAP "
                "only (convert it with `ros2 bag convert`)"
            )
        for relative in metadata.get("relative_file_paths") or []:
            candidate = folder / str(relative)
            if not candidate.is_file():
                # rosbag2 lists paths relative to the bag or (older) with its folder name.
                candidate = folder / Path(str(relative)).name
            if candidate.is_file():
                files.append(candidate)
            else:
                notes.append(f"{metadata_path} lists {relative}, which is missing; skipped")
    if not files:
        files = sorted(folder.glob("*.mcap"), key=_split_index)
        if metadata is None:
            notes.append(f"{folder} has no metadata.yaml; read every .mcap file in it")
    if not files:
        raise InvalidArgumentError(
            f"{folder}: no .mcap files here; give an .mcap file or a rosbag2 folder "
            "recorded with MCAP storage"
        )
    return Recording(kind="rosbag2", location=folder, files=files, metadata=metadata, notes=notes)


def _yaml_loader() -> type[Any]:
    """libyaml's safe loader when PyYAML was built with it (several times faster on the
    metadata of bags with many topics), else the pure-Python safe loader."""
    import yaml

    return getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _load_metadata(path: Path) -> dict[str, Any]:
    import yaml

    try:
        document = yaml.load(path.read_text(encoding="utf-8"), Loader=_yaml_loader())
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" (line {mark.line + 1})" if mark is not None else ""
        raise FileFormatError(f"{path}{where}: not valid YAML: {error}") from error
    except (OSError, UnicodeDecodeError) as error:
        raise FileFormatError(f"{path}: cannot be read: {error}") from error
    info = document.get("rosbag2_bagfile_information") if isinstance(document, dict) else None
    if not isinstance(info, dict):
        raise FileFormatError(
            f"{path}: no `rosbag2_bagfile_information` mapping; is this a rosbag2 metadata file?"
        )
    return info


# --- QoS -------------------------------------------------------------------------------

_HISTORY = {0: "system_default", 1: "keep_last", 2: "keep_all", 3: "unknown"}
_RELIABILITY = {
    0: "system_default",
    1: "reliable",
    2: "best_effort",
    3: "unknown",
    4: "best_available",
}
_DURABILITY = {
    0: "system_default",
    1: "transient_local",
    2: "volatile",
    3: "unknown",
    4: "best_available",
}
_LIVELINESS = {
    0: "system_default",
    1: "automatic",
    2: "manual_by_node",
    3: "manual_by_topic",
    4: "unknown",
    5: "best_available",
}
_INFINITE_SEC = 9223372036


def _policy(value: object, names: dict[int, str]) -> str | None:
    if value is None:
        return None
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, int):
        return names.get(value, str(value))
    return str(value).lower()


def _duration_ns(value: object) -> int | None:
    """``{sec, nsec}`` in ns; ``None`` for "infinite" and "not set" (both zero)."""
    if not isinstance(value, dict):
        return None
    try:
        sec, nsec = int(value.get("sec", 0)), int(value.get("nsec", 0))
    except (TypeError, ValueError):
        return None
    if sec >= _INFINITE_SEC or (sec == 0 and nsec == 0):
        return None
    return sec * 1_000_000_000 + nsec


def parse_qos_profiles(text: str) -> list[QosProfile]:
    """rosbag2's ``offered_qos_profiles`` (a YAML list) as profiles; ``[]`` if unreadable."""
    import yaml

    try:
        document = yaml.load(text, Loader=_yaml_loader())
    except yaml.YAMLError:
        return []
    if not isinstance(document, list):
        return []
    profiles: list[QosProfile] = []
    for item in document:
        if not isinstance(item, dict):
            continue
        depth = item.get("depth")
        avoid = item.get("avoid_ros_namespace_conventions")
        profiles.append(
            QosProfile(
                history=_policy(item.get("history"), _HISTORY),
                depth=depth if isinstance(depth, int) else None,
                reliability=_policy(item.get("reliability"), _RELIABILITY),
                durability=_policy(item.get("durability"), _DURABILITY),
                deadline_ns=_duration_ns(item.get("deadline")),
                lifespan_ns=_duration_ns(item.get("lifespan")),
                liveliness=_policy(item.get("liveliness"), _LIVELINESS),
                liveliness_lease_duration_ns=_duration_ns(item.get("liveliness_lease_duration")),
                avoid_ros_namespace_conventions=avoid if isinstance(avoid, bool) else None,
            )
        )
    return profiles


# --- merging the files of a recording --------------------------------------------------


@dataclass
class _SchemaData:
    name: str
    encoding: str
    data: bytes


@dataclass
class _Channel:
    """A recorded topic, merged over the files of a recording."""

    topic: str
    type_name: str
    message_encoding: str
    schema: _SchemaData | None
    metadata: dict[str, str]
    message_count: int = 0
    first: int | None = None
    last: int | None = None
    times_exact: bool = True
    from_metadata_only: bool = False

    def add(self, count: int, first: int | None, last: int | None, exact: bool) -> None:
        self.message_count += count
        if first is not None:
            self.first = first if self.first is None else min(self.first, first)
        if last is not None:
            self.last = last if self.last is None else max(self.last, last)
        self.times_exact = self.times_exact and exact


def _read_files(
    files: Sequence[Path], mode: ReadMode, cancel: threading.Event | None = None
) -> tuple[list[tuple[Path, McapFile]], list[SourceFile]]:
    """Reads every file; returns the readable ones and a record of the unreadable ones.

    In a split bag one file that is not MCAP at all (typically the last split, left
    empty when the recorder died just after opening it) must not hide the others, so
    its error becomes a note; a lone file's error, or every file failing, is raised.
    """
    from skillwright.core import read_mcap

    def read(path: Path) -> McapFile | FileFormatError:
        raise_if_cancelled(cancel, f"reading {path}")
        try:
            return read_mcap(path, mode)
        except FileFormatError as error:
            return error

    if len(files) == 1:
        outcomes = [read(files[0])]
    else:
        # The core releases the GIL, so split files are read in parallel.
        with ThreadPoolExecutor(max_workers=min(4, len(files))) as pool:
            outcomes = list(pool.map(read, files))
    readable = [
        (p, o) for p, o in zip(files, outcomes, strict=True) if not isinstance(o, Exception)
    ]
    failed = [(p, o) for p, o in zip(files, outcomes, strict=True) if isinstance(o, Exception)]
    if failed and not readable:
        raise failed[0][1]
    unreadable = [
        SourceFile(
            path=str(path),
            size_bytes=path.stat().st_size,
            read_method="unreadable",
            message_count=0,
            partial=True,
            stopped_at=Damage(offset=0, message=str(error)),
        )
        for path, error in failed
    ]
    return readable, unreadable


def _merge_channels(results: Iterable[McapFile]) -> list[_Channel]:
    merged: dict[tuple[str, str, str], _Channel] = {}
    for result in results:
        schemas = {s.id: s for s in result.schemas}
        for channel in result.channels:
            schema = schemas.get(channel.schema_id)
            type_name = normalize_type_name(schema.name) if schema is not None else ""
            key = (channel.topic, type_name, channel.message_encoding)
            entry = merged.get(key)
            if entry is None:
                entry = merged[key] = _Channel(
                    topic=channel.topic,
                    type_name=type_name,
                    message_encoding=channel.message_encoding,
                    schema=_SchemaData(schema.name, schema.encoding, schema.data)
                    if schema is not None
                    else None,
                    metadata=dict(channel.metadata),
                )
            entry.add(
                channel.message_count,
                channel.first_log_time,
                channel.last_log_time,
                channel.times_exact,
            )
    return list(merged.values())


def _apply_metadata(channels: list[_Channel], metadata: dict[str, Any]) -> None:
    """Fills types and QoS from ``metadata.yaml`` and adds topics only it lists."""
    by_topic: dict[str, list[_Channel]] = {}
    for channel in channels:
        by_topic.setdefault(channel.topic, []).append(channel)
    for item in metadata.get("topics_with_message_count") or []:
        topic = (item or {}).get("topic_metadata") or {}
        name = topic.get("name")
        if not isinstance(name, str):
            continue
        type_name = normalize_type_name(str(topic.get("type", "")))
        qos = topic.get("offered_qos_profiles")
        known = by_topic.get(name)
        if known is None:
            count = item.get("message_count")
            channels.append(
                _Channel(
                    topic=name,
                    type_name=type_name,
                    message_encoding=str(topic.get("serialization_format", "")),
                    schema=None,
                    metadata={"offered_qos_profiles": qos} if isinstance(qos, str) else {},
                    message_count=count if isinstance(count, int) else 0,
                    times_exact=False,
                    from_metadata_only=True,
                )
            )
            continue
        for channel in known:
            if not channel.type_name:
                channel.type_name = type_name
            if isinstance(qos, str) and qos and not channel.metadata.get("offered_qos_profiles"):
                channel.metadata["offered_qos_profiles"] = qos


# --- definitions -----------------------------------------------------------------------


def _schema_text(schema: _SchemaData) -> tuple[str, str | None]:
    """Schema bytes as text, and a note when they had to be base64-encoded."""
    try:
        return schema.data.decode("utf-8"), None
    except UnicodeDecodeError:
        return (
            base64.b64encode(schema.data).decode("ascii"),
            f"schema {schema.name!r} ({schema.encoding}) is binary; kept as base64",
        )


def _raw_definition(type_name: str, schema: _SchemaData) -> MessageDefinition:
    text, note = _schema_text(schema)
    notes = [note] if note else []
    notes.append(
        f"schema encoding {schema.encoding or 'unknown'!r} is not ros2msg; kept as raw text "
        "without a field tree"
    )
    return MessageDefinition(
        type_name=type_name, encoding=schema.encoding or "unknown", raw=text, notes=notes
    )


def _all_blocks(schema: _SchemaData) -> tuple[Block, dict[str, Block]]:
    text, _ = _schema_text(schema)
    return parse_blocks(schema.name, text)


def _message_definition(channel: _Channel) -> MessageDefinition | None:
    if channel.schema is None:
        return None
    if channel.schema.encoding != "ros2msg":
        return _raw_definition(channel.type_name, channel.schema)
    text, _ = _schema_text(channel.schema)
    definition = definition_from_text(channel.schema.name, text)
    if not text.strip():
        # rosbag2 stores an empty text when the recorder could not find the definition.
        definition.fields = None
        definition.notes.append("the recording stored an empty definition for this type")
    return definition


def _service_definitions(
    channel: _Channel, service_type: str
) -> tuple[dict[str, MessageDefinition], list[str]]:
    """Request and response definitions from a ``_service_event`` channel's schema,
    which is either the raw ``.srv`` text or the expanded ``..._Event`` message."""
    schema = channel.schema
    if schema is None:
        return {}, [f"{channel.topic}: no schema recorded, so no request/response definition"]
    if schema.encoding != "ros2msg":
        return {"event": _raw_definition(channel.type_name, schema)}, []
    text, _ = _schema_text(schema)
    request_type, response_type = f"{service_type}_Request", f"{service_type}_Response"
    halves = split_service(text)
    if halves is not None:
        _, dependencies = parse_blocks(schema.name, text)
        return {
            "request": definition_from_text(
                request_type, halves[0], extra_dependencies=dependencies
            ),
            "response": definition_from_text(
                response_type, halves[1], extra_dependencies=dependencies
            ),
        }, []
    _, dependencies = parse_blocks(schema.name, text)
    definitions: dict[str, MessageDefinition] = {}
    for role, type_name in (("request", request_type), ("response", response_type)):
        block = find_block(dependencies, type_name)
        if block is not None:
            definitions[role] = definition_from_text(
                block.type_name, block.text, extra_dependencies=dependencies
            )
    if len(definitions) == 2:
        return definitions, []
    return {"event": definition_from_text(schema.name, text)}, [
        f"{channel.topic}: the event schema does not define {request_type} and "
        f"{response_type}; kept the whole event definition"
    ]


def _interface_type(kind: InterfaceKind, channel: _Channel, role: str) -> str:
    """``pkg/srv/X`` from ``pkg/srv/X_Event``; ``pkg/action/X`` from an action part."""
    type_name = channel.type_name
    if kind == "service":
        return type_name.removesuffix("_Event")
    if kind == "action":
        for suffix in ("_FeedbackMessage", "_SendGoal_Event", "_GetResult_Event"):
            if role in {"feedback", "send_goal", "get_result"} and type_name.endswith(suffix):
                return type_name.removesuffix(suffix)
    return type_name


def _traffic(channels: Sequence[_Channel]) -> Traffic | None:
    if not channels or all(c.from_metadata_only and c.message_count == 0 for c in channels):
        return None
    count = sum(c.message_count for c in channels)
    firsts = [c.first for c in channels if c.first is not None]
    lasts = [c.last for c in channels if c.last is not None]
    first = min(firsts) if firsts else None
    last = max(lasts) if lasts else None
    rate = None
    if count >= 2 and first is not None and last is not None and last > first:
        rate = (count - 1) / ((last - first) / 1e9)
    return Traffic(
        message_count=count,
        first_time_ns=first,
        last_time_ns=last,
        rate_hz=rate,
        times_exact=all(c.times_exact for c in channels),
    )


def _channel_notes(channel: _Channel) -> list[str]:
    notes: list[str] = []
    if channel.schema is None and not channel.from_metadata_only:
        notes.append(f"{channel.topic}: recorded without a schema")
    if channel.from_metadata_only:
        notes.append(
            f"{channel.topic}: listed in metadata.yaml but not in the readable .mcap files"
        )
    if channel.message_encoding and channel.message_encoding != "cdr":
        notes.append(
            f"{channel.topic}: messages are encoded as {channel.message_encoding!r}, not "
            "CDR; ROS 2 tools may not decode them"
        )
    return notes


def _qos(channels: Sequence[_Channel]) -> list[QosProfile]:
    for channel in channels:
        text = channel.metadata.get("offered_qos_profiles")
        if text:
            return parse_qos_profiles(text)
    return []


def _channel_ref(channel: _Channel, role: str) -> ChannelRef:
    return ChannelRef(
        topic=channel.topic,
        role=role,
        type_name=channel.type_name,
        message_encoding=channel.message_encoding,
        message_count=channel.message_count,
    )


def _classify_channel(topic: str) -> tuple[InterfaceKind, str, str]:
    """``(kind, interface name, role)`` of a recorded topic."""
    if topic.endswith(SERVICE_EVENT_SUFFIX):
        service = topic.removesuffix(SERVICE_EVENT_SUFFIX)
        head, _, tail = service.rpartition(ACTION_INFIX)
        if head and tail in _ACTION_SERVICES:
            return "action", head, tail
        return "service", service, "service_events"
    head, _, tail = topic.rpartition(ACTION_INFIX)
    if head and tail in _ACTION_TOPICS:
        return "action", head, tail
    return "topic", topic, "messages"


def build_interfaces(
    channels: Sequence[_Channel], cancel: threading.Event | None = None
) -> list[Interface]:
    """Groups recorded channels into topic, service and action entries; ``cancel`` is
    looked at before each entry's definitions are parsed."""
    groups: dict[tuple[InterfaceKind, str], list[tuple[str, _Channel]]] = {}
    for channel in channels:
        kind, name, role = _classify_channel(channel.topic)
        # Topics recorded under one name with different types stay separate entries.
        key_name = name if kind != "topic" else f"{name}\0{channel.type_name}"
        groups.setdefault((kind, key_name), []).append((role, channel))

    interfaces: list[Interface] = []
    for (kind, key_name), members in groups.items():
        raise_if_cancelled(cancel, "reading the recording")
        name = key_name.split("\0", 1)[0]
        chans = [c for _, c in members]
        notes = [note for c in chans for note in _channel_notes(c)]
        definitions: dict[str, MessageDefinition] = {}
        if kind == "topic":
            type_name = chans[0].type_name
            definition = _message_definition(chans[0])
            if definition is not None:
                definitions["message"] = definition
        elif kind == "service":
            type_name = _interface_type(kind, chans[0], "service_events")
            definitions, extra = _service_definitions(chans[0], type_name)
            notes.extend(extra)
        else:
            type_name, definitions, extra = _action_definitions(members)
            notes.extend(extra)
        interfaces.append(
            Interface(
                name=name,
                kind=kind,
                type_name=type_name,
                definitions=definitions,
                qos=_qos(chans),
                traffic=_traffic(chans),
                channels=[_channel_ref(c, role) for role, c in members],
                infrastructure=classify(kind, name, type_name),
                notes=list(dict.fromkeys(notes)),
            )
        )
    names = [(i.kind, i.name) for i in interfaces]
    for entry in interfaces:
        if names.count((entry.kind, entry.name)) > 1:
            entry.notes.append(f"{entry.name}: recorded with more than one type")
    interfaces.sort(key=lambda i: (_KIND_ORDER[i.kind], i.name, i.type_name))
    return interfaces


def _raw_action(
    type_name: str, members: Sequence[tuple[str, _Channel]]
) -> dict[str, MessageDefinition] | None:
    """Goal, result and feedback from a schema holding the raw ``.action`` text, as some
    recorders store for the feedback and goal/result service events."""
    for _, channel in members:
        schema = channel.schema
        if schema is None or schema.encoding != "ros2msg":
            continue
        text, _ = _schema_text(schema)
        parts = split_action(text)
        if parts is None:
            continue
        _, dependencies = parse_blocks(schema.name, text)
        return {
            role: definition_from_text(
                f"{type_name}_{suffix}", part, extra_dependencies=dependencies
            )
            for role, suffix, part in zip(
                ("goal", "result", "feedback"), ("Goal", "Result", "Feedback"), parts, strict=True
            )
        }
    return None


def _action_definitions(
    members: Sequence[tuple[str, _Channel]],
) -> tuple[str, dict[str, MessageDefinition], list[str]]:
    roles = dict(members)
    type_name = ""
    for role in ("feedback", "send_goal", "get_result"):
        if role in roles:
            candidate = _interface_type("action", roles[role], role)
            if candidate != roles[role].type_name:
                type_name = candidate
                break
    notes: list[str] = []
    if not type_name:
        notes.append("the action type could not be told from the recorded topics")
        return "", {}, notes
    blocks: dict[str, Block] = {}
    for _, channel in members:
        if channel.schema is not None and channel.schema.encoding == "ros2msg":
            main, dependencies = _all_blocks(channel.schema)
            blocks.update(dependencies)
            blocks.setdefault(main.type_name, main)
    definitions: dict[str, MessageDefinition] = {}
    raw = _raw_action(type_name, members)
    if raw is not None:
        return type_name, raw, notes
    for role, suffix, fallback_service in (
        ("goal", "_Goal", "send_goal"),
        ("result", "_Result", "get_result"),
        ("feedback", "_Feedback", None),
    ):
        block = find_block(blocks, type_name + suffix)
        if block is not None:
            definitions[role] = definition_from_text(
                f"{type_name}{suffix}", block.text, extra_dependencies=blocks
            )
            continue
        service_channel = roles.get(fallback_service) if fallback_service else None
        if service_channel is not None:
            halves, _ = _service_definitions(service_channel, service_channel.type_name)
            half = halves.get("request" if role == "goal" else "response")
            if half is not None:
                definitions[role] = half
                notes.append(
                    f"{role}: given as the {fallback_service} "
                    f"{'request' if role == 'goal' else 'response'} (the recording has no "
                    f"separate {type_name}{suffix} definition)"
                )
                continue
        notes.append(f"{role}: the recording does not define {type_name}{suffix}")
    return type_name, definitions, notes


# --- the source ------------------------------------------------------------------------


def _source_file(path: Path, result: McapFile) -> SourceFile:
    return SourceFile(
        path=str(path),
        size_bytes=result.file_size,
        read_method=result.method,
        profile=result.profile,
        library=result.library,
        message_count=result.message_count,
        chunk_count=result.chunk_count,
        attachment_count=result.attachment_count,
        metadata_count=result.metadata_count,
        compressions=list(result.compressions),
        partial=result.partial,
        stopped_at=Damage(offset=result.stopped.offset, message=result.stopped.message)
        if result.stopped is not None
        else None,
        damaged=[Damage(offset=d.offset, message=d.message) for d in result.damaged],
        notes=list(result.notes),
    )


@dataclass
class BagSource(InterfaceSource):
    """Interfaces recorded in an ``.mcap`` file or a rosbag2 folder."""

    path: Path
    mode: ReadMode = "auto"
    resource_name: str | None = None
    cancel: threading.Event | None = field(default=None, compare=False, repr=False)
    """Looked at between files, between interfaces and before filling in definitions."""

    kind = "rosbag2"

    def discover(self) -> Inventory:
        """Reads the recording (see :func:`discover_bag`)."""
        recording = resolve_recording(self.path)
        readable, unreadable = _read_files(recording.files, self.mode, self.cancel)
        results = [r for _, r in readable]
        channels = _merge_channels(results)
        if recording.metadata is not None:
            _apply_metadata(channels, recording.metadata)
        files = [_source_file(p, r) for p, r in readable]
        # Keep the files in recording order, unreadable ones included.
        files = sorted([*files, *unreadable], key=lambda f: recording.files.index(Path(f.path)))
        starts = [r.message_start_time for r in results if r.message_start_time is not None]
        ends = [r.message_end_time for r in results if r.message_end_time is not None]
        notes = list(recording.notes)
        distro = None
        if recording.metadata is not None:
            distro = recording.metadata.get("ros_distro") or None
            expected = recording.metadata.get("message_count")
            found = sum(r.message_count for r in results)
            if isinstance(expected, int) and expected != found:
                notes.append(
                    f"metadata.yaml counts {expected} messages, the files hold {found} "
                    "readable ones"
                )
        source = Source(
            kind=recording.kind,
            location=str(recording.location),
            files=files,
            start_time_ns=min(starts) if starts else None,
            end_time_ns=max(ends) if ends else None,
            message_count=sum(r.message_count for r in results),
            ros_distro=str(distro) if distro else None,
            notes=notes,
        )
        name = self.resource_name or (
            recording.location.stem if recording.kind == "mcap" else recording.location.name
        )
        interfaces = build_interfaces(channels, self.cancel)
        # Channels without a schema (or with an empty one) still name their type.
        filled = fill_missing_definitions(interfaces, source.ros_distro, cancel=self.cancel)
        if filled:
            source.notes.append(filled_note(filled))
        return Inventory(resource=Resource(name=name), sources=[source], interfaces=interfaces)


def discover_bag(
    path: str | Path,
    mode: ReadMode = "auto",
    resource_name: str | None = None,
    *,
    cancel: threading.Event | None = None,
) -> Inventory:
    """The inventory of an ``.mcap`` file or rosbag2 folder.

    ``mode`` is passed to the Rust reader: ``auto`` (summary when complete, else scan),
    ``scan`` or ``full``. Damaged files give a partial inventory; the source's files say
    where they broke. Raises ``InputFileNotFoundError``, ``InvalidArgumentError`` (no
    .mcap files) or ``FileFormatError`` (not MCAP, bad metadata.yaml); with ``cancel``
    set, ``OperationCancelledError`` before the next file or interface.
    """
    return BagSource(Path(path), mode, resource_name, cancel).discover()
