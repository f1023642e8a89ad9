"""The inventory: every ROS 2 interface a resource offers, the document later stages read.

One inventory describes one resource (a robot, or a part of one). Each source — an MCAP
recording or rosbag2 folder today, the live ROS 2 graph and the Cap2Skill report import
later — produces this same model. Enrichment fills :attr:`Interface.description` and
:attr:`Interface.relevance`; retrieval and validation read the definitions.

The JSON schema of this model is checked in next to this module
(``inventory.schema.json``) and a test fails when the two drift apart; regenerate it
with ``python -m skillwright.interfaces.inventory``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Final, Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue

__all__ = [
    "INVENTORY_SCHEMA_VERSION",
    "SCHEMA_PATH",
    "ArrayKind",
    "ChannelRef",
    "Constant",
    "Damage",
    "Endpoints",
    "InfrastructureFlag",
    "Interface",
    "InterfaceKind",
    "Inventory",
    "MessageDefinition",
    "MessageField",
    "QosProfile",
    "Relevance",
    "Resource",
    "Source",
    "SourceFile",
    "Traffic",
    "inventory_json_schema",
    "schema_text",
]

INVENTORY_SCHEMA_VERSION: Final = 1
"""Bumped whenever a change to the model would make old documents read differently."""

SCHEMA_PATH = Path(__file__).with_name("inventory.schema.json")
"""The checked-in JSON schema of :class:`Inventory`."""

InterfaceKind = Literal["topic", "service", "action"]
ArrayKind = Literal["none", "fixed", "bounded", "unbounded"]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Constant(_Model):
    """A constant declared in a message definition (``int32 MAX=5``)."""

    name: str = Field(description="Constant name, upper case by convention.")
    type: str = Field(description="Its type as written, e.g. `uint8` or `string`.")
    value: JsonValue = Field(description="The value, parsed to a number, bool or string.")


class MessageField(_Model):
    """One field of a message, with nested message types expanded."""

    name: str = Field(description="Field name.")
    type: str = Field(description="Type as written in the definition, e.g. `int32[<=5]`.")
    base_type: str = Field(
        description="Element type without array or bound: a builtin (`int32`, `string`) or "
        "a full message type name (`geometry_msgs/msg/Point`)."
    )
    builtin: bool = Field(description="True for ROS 2 builtin types (numbers, bool, strings).")
    array: ArrayKind = Field(
        default="none",
        description="`none`, `fixed` (`T[3]`), `bounded` (`T[<=5]`) or `unbounded` (`T[]`).",
    )
    array_size: int | None = Field(
        default=None, description="Length of a fixed array or bound of a bounded one."
    )
    string_bound: int | None = Field(
        default=None, description="Maximum length of a bounded string (`string<=10`)."
    )
    default: JsonValue = Field(
        default=None, description="Default value when the definition gives one (parsed)."
    )
    fields: list[MessageField] = Field(
        default_factory=list, description="Fields of a nested message type, expanded."
    )
    constants: list[Constant] = Field(
        default_factory=list, description="Constants of a nested message type."
    )
    resolved: bool = Field(
        default=True,
        description="False when the field's message type is not defined in the source, "
        "so `fields` could not be expanded.",
    )


class MessageDefinition(_Model):
    """The full definition of one message type: raw text and parsed field tree."""

    type_name: str = Field(description="Full type name, e.g. `std_msgs/msg/String`.")
    encoding: str = Field(
        description="Definition language: `ros2msg`, `ros2idl`, `omgidl`, `protobuf`, "
        "`jsonschema`, or `unknown`."
    )
    raw: str = Field(
        description="The definition as recorded (for ros2msg: main block, then `MSG:` "
        "dependency blocks); binary schemas are base64."
    )
    fields: list[MessageField] | None = Field(
        default=None, description="Parsed field tree; null when the encoding is not ros2msg."
    )
    constants: list[Constant] = Field(default_factory=list, description="Top-level constants.")
    origin: Literal["source", "type_store"] = Field(
        default="source",
        description="`source` when the source carried the definition; `type_store` when the "
        "source named the type only and the standard definition was filled in offline.",
    )
    notes: list[str] = Field(
        default_factory=list, description="What could not be parsed or resolved, and why."
    )


class QosProfile(_Model):
    """A QoS profile offered by a publisher, as recorded (policy names, durations in ns)."""

    history: str | None = Field(default=None, description="`keep_last`, `keep_all`, ...")
    depth: int | None = Field(default=None, description="Queue depth for `keep_last`.")
    reliability: str | None = Field(default=None, description="`reliable`, `best_effort`, ...")
    durability: str | None = Field(default=None, description="`volatile`, `transient_local`, ...")
    deadline_ns: int | None = Field(default=None, description="Deadline; null when infinite.")
    lifespan_ns: int | None = Field(default=None, description="Lifespan; null when infinite.")
    liveliness: str | None = Field(default=None, description="`automatic`, `manual_by_topic`.")
    liveliness_lease_duration_ns: int | None = Field(
        default=None, description="Liveliness lease; null when infinite."
    )
    avoid_ros_namespace_conventions: bool | None = Field(
        default=None, description="Whether the topic name bypasses ROS naming."
    )


class Traffic(_Model):
    """What a recording says about the messages of an interface."""

    message_count: int = Field(description="Messages recorded (service/action: events).")
    first_time_ns: int | None = Field(default=None, description="Earliest log time (ns).")
    last_time_ns: int | None = Field(default=None, description="Latest log time (ns).")
    rate_hz: float | None = Field(
        default=None, description="Mean rate over the recorded span; null below 2 messages."
    )
    times_exact: bool = Field(
        default=True,
        description="False when first/last are bounds from chunk indexes, not exact times.",
    )


class ChannelRef(_Model):
    """A recorded topic that contributes to an interface (actions have several)."""

    topic: str = Field(description="Recorded topic name.")
    role: str = Field(
        description="What the topic is for this interface: `messages`, `service_events`, "
        "`feedback`, `status`, `send_goal`, `get_result` or `cancel_goal`."
    )
    type_name: str = Field(description="Type of the recorded messages.")
    message_encoding: str = Field(description="Serialization, `cdr` for ROS 2.")
    message_count: int = Field(description="Messages recorded on this topic.")


class Endpoints(_Model):
    """Who offered or used an interface on the live graph when it was discovered."""

    publishers: int | None = Field(default=None, description="Publishers of a topic.")
    subscribers: int | None = Field(default=None, description="Subscribers of a topic.")
    servers: int | None = Field(
        default=None, description="Servers of an action (publishers of its status topic)."
    )
    clients: int | None = Field(
        default=None, description="Clients of an action (subscribers of its status topic)."
    )


class InfrastructureFlag(_Model):
    """Marks an interface that belongs to ROS 2 or tooling plumbing, not the robot's task."""

    rule: str = Field(description="Identifier of the rule that matched (see infrastructure.py).")
    reason: str = Field(description="Why such interfaces are infrastructure.")


class Description(_Model):
    """What an interface is for, in a fixed structure."""

    purpose: str = Field(description="One sentence: what the interface does.")
    module: str = Field(
        description="Module of the resource, e.g. `base motion` (see description.MODULES)."
    )
    tasks: list[str] = Field(default_factory=list, description="Tasks it serves.")
    used_by: list[str] = Field(default_factory=list, description="Who publishes or calls it.")
    key_fields: list[str] = Field(default_factory=list, description="Its most telling fields.")
    engine: str = Field(description="What wrote it: `rules`, `report` or a model id.")

    def text(self) -> str:
        """The description as one paragraph (what retrieval embeds)."""
        parts = [self.purpose, f"Module: {self.module}."]
        if self.tasks:
            parts.append(f"Tasks: {', '.join(self.tasks)}.")
        if self.used_by:
            parts.append(f"Used by: {', '.join(self.used_by)}.")
        if self.key_fields:
            parts.append(f"Key fields: {', '.join(self.key_fields)}.")
        return " ".join(parts)


class Relevance(_Model):
    """A relevance verdict for skill generation (filled by enrichment)."""

    relevant: bool = Field(description="Whether skills may use this interface.")
    category: Literal["control", "infrastructure"] = Field(
        description="`control`: commands, senses or plans for the resource; `infrastructure`: "
        "ROS 2 or tooling plumbing (parameters, logging, introspection, clock, ...)."
    )
    reason: str = Field(description="Why, in one sentence.")
    engine: str | None = Field(
        default=None, description="What produced the verdict (rule set or model id)."
    )


class Interface(_Model):
    """One topic, service or action of the resource."""

    name: str = Field(description="Fully qualified name, e.g. `/cmd_vel`.")
    kind: InterfaceKind = Field(description="`topic`, `service` or `action`.")
    type_name: str = Field(
        description="Interface type: `pkg/msg/T`, `pkg/srv/T` or `pkg/action/T`."
    )
    definitions: dict[str, MessageDefinition] = Field(
        default_factory=dict,
        description="Definitions by role: `message` (topic); `request`, `response` "
        "(service); `goal`, `result`, `feedback` (action) where the source has them.",
    )
    qos: list[QosProfile] = Field(
        default_factory=list, description="Offered QoS profiles, where known."
    )
    traffic: Traffic | None = Field(default=None, description="Message statistics, where known.")
    channels: list[ChannelRef] = Field(
        default_factory=list, description="Recorded topics this interface was built from."
    )
    endpoints: Endpoints | None = Field(
        default=None, description="Publishers, subscribers, servers, clients (live graph)."
    )
    infrastructure: InfrastructureFlag | None = Field(
        default=None, description="Set when the interface is ROS 2 / tooling infrastructure."
    )
    description: Description | None = Field(
        default=None, description="Uniform description (filled by enrichment or a report)."
    )
    relevance: Relevance | None = Field(
        default=None, description="Relevance verdict (filled by enrichment)."
    )
    notes: list[str] = Field(
        default_factory=list, description="Caveats about this entry, for the user."
    )


class Damage(_Model):
    """A place in a source file where something was wrong."""

    offset: int = Field(description="Byte offset in the file.")
    message: str = Field(description="What was wrong there.")


class SourceFile(_Model):
    """One file read for a source."""

    path: str = Field(description="Path as given or as listed in metadata.yaml.")
    size_bytes: int = Field(description="File size.")
    read_method: Literal["summary", "scan", "full", "unreadable"] = Field(
        description="`summary` (footer and summary section only), `scan` (records, chunk "
        "bodies skipped where message indexes suffice), `full` (every chunk inflated) or "
        "`unreadable` (not an MCAP file; skipped, `stopped_at` says why)."
    )
    profile: str | None = Field(default=None, description="MCAP header profile, e.g. `ros2`.")
    library: str | None = Field(default=None, description="MCAP header library (the writer).")
    message_count: int = Field(description="Messages in the readable part of the file.")
    chunk_count: int = Field(default=0, description="Chunks.")
    attachment_count: int = Field(default=0, description="Attachments.")
    metadata_count: int = Field(default=0, description="Metadata records.")
    compressions: list[str] = Field(
        default_factory=list, description="Chunk compressions (`` for none)."
    )
    partial: bool = Field(default=False, description="True when part of it was unreadable.")
    stopped_at: Damage | None = Field(
        default=None, description="Where reading stopped early (cut short, broken record)."
    )
    damaged: list[Damage] = Field(
        default_factory=list, description="Damaged records skipped; reading went on."
    )
    notes: list[str] = Field(default_factory=list, description="Remarks, e.g. no summary.")


class Source(_Model):
    """Where interfaces came from."""

    kind: Literal["mcap", "rosbag2", "ros2_live", "report"] = Field(
        description="`mcap` (one file), `rosbag2` (a bag folder), `ros2_live`, `report`."
    )
    location: str = Field(description="Path (or graph / report identifier) that was read.")
    files: list[SourceFile] = Field(default_factory=list, description="Files read.")
    start_time_ns: int | None = Field(default=None, description="First message time (ns).")
    end_time_ns: int | None = Field(default=None, description="Last message time (ns).")
    message_count: int | None = Field(default=None, description="Messages in the source.")
    ros_distro: str | None = Field(default=None, description="ROS distribution, when recorded.")
    captured_at: str | None = Field(
        default=None,
        description="When the source was captured, as it says: a report's `timestamp`, or "
        "the time of live discovery (ISO 8601).",
    )
    notes: list[str] = Field(default_factory=list, description="Remarks about the source.")

    @property
    def duration_ns(self) -> int | None:
        """Span between the first and last message, when both are known."""
        if self.start_time_ns is None or self.end_time_ns is None:
            return None
        return self.end_time_ns - self.start_time_ns

    @property
    def partial(self) -> bool:
        """True when any file of the source was only partly readable."""
        return any(f.partial for f in self.files)


class Resource(_Model):
    """The robot or device whose interfaces the inventory lists."""

    name: str = Field(description="Resource name (default: the recording's name).")
    description: str | None = Field(default=None, description="Free text about the resource.")


class Inventory(_Model):
    """Every interface of one resource, with where it was found."""

    schema_version: Literal[1] = Field(
        default=INVENTORY_SCHEMA_VERSION, description="Version of this document's layout."
    )
    resource: Resource = Field(description="What the interfaces belong to.")
    sources: list[Source] = Field(default_factory=list, description="Where they were found.")
    interfaces: list[Interface] = Field(
        default_factory=list, description="One entry per interface, sorted by kind and name."
    )

    def interface(self, name: str, kind: InterfaceKind | None = None) -> Interface:
        """The interface called ``name`` (of ``kind`` if given); ``KeyError`` if absent."""
        for entry in self.interfaces:
            if entry.name == name and (kind is None or entry.kind == kind):
                return entry
        raise KeyError(name if kind is None else f"{kind} {name}")


def inventory_json_schema() -> dict[str, Any]:
    """The JSON schema of :class:`Inventory`, as checked in at :data:`SCHEMA_PATH`."""
    return Inventory.model_json_schema()


def schema_text() -> str:
    """The checked-in form of the schema: sorted keys, two-space indent, final newline."""
    return json.dumps(inventory_json_schema(), indent=2, sort_keys=True) + "\n"


if __name__ == "__main__":  # pragma: no cover - maintenance entry point
    from skillwright.fileio import write_atomic

    write_atomic(SCHEMA_PATH, schema_text())
    print(f"wrote {SCHEMA_PATH}")
