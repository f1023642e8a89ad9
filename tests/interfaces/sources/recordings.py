"""Writes small MCAP recordings for tests with the Python ``mcap`` writer (a dev
dependency), so the Rust reader is checked against an independent implementation."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

SEPARATOR = "=" * 80


@dataclass
class Topic:
    """One channel to record: name, schema and how many messages."""

    name: str
    type_name: str
    definition: str | bytes = ""
    schema_encoding: str = "ros2msg"
    message_encoding: str = "cdr"
    messages: int = 3
    period_ns: int = 100_000_000
    metadata: dict[str, str] = field(default_factory=dict)
    schemaless: bool = False


def write_recording(path: Path, topics: list[Topic], **writer_options: Any) -> Path:
    """Writes ``topics`` to ``path`` (zstd chunks unless told otherwise); returns ``path``."""
    from mcap.writer import CompressionType, Writer

    options: dict[str, Any] = {"compression": CompressionType.ZSTD, "chunk_size": 4096}
    options.update(writer_options)
    with path.open("wb") as stream:
        writer = Writer(stream, **options)
        writer.start(profile="ros2", library="skillwright-tests")
        ids = []
        for topic in topics:
            schema_id = 0
            if not topic.schemaless:
                data = topic.definition
                schema_id = writer.register_schema(
                    name=topic.type_name,
                    encoding=topic.schema_encoding,
                    data=data if isinstance(data, bytes) else data.encode(),
                )
            ids.append(
                writer.register_channel(
                    topic=topic.name,
                    message_encoding=topic.message_encoding,
                    schema_id=schema_id,
                    metadata=topic.metadata,
                )
            )
        start = 1_700_000_000_000_000_000
        for channel_id, topic in zip(ids, topics, strict=True):
            for index in range(topic.messages):
                stamp = start + index * topic.period_ns
                writer.add_message(
                    channel_id=channel_id,
                    log_time=stamp,
                    publish_time=stamp,
                    data=bytes(16),
                    sequence=index,
                )
        writer.finish()
    return path


def event_schema(package: str, namespace: str, name: str, request: str, response: str) -> str:
    """The expanded ``<Name>_Event`` definition newer rosbag2 versions record."""
    return "\n".join(
        [
            "service_msgs/ServiceEventInfo info",
            f"{name}_Request[<=1] request",
            f"{name}_Response[<=1] response",
            SEPARATOR,
            "MSG: service_msgs/ServiceEventInfo",
            "uint8 REQUEST_SENT = 0",
            "uint8 REQUEST_RECEIVED = 1",
            "uint8 RESPONSE_SENT = 2",
            "uint8 RESPONSE_RECEIVED = 3",
            "uint8 event_type",
            "builtin_interfaces/Time stamp",
            "char[16] client_gid",
            "int64 sequence_number",
            SEPARATOR,
            "MSG: builtin_interfaces/Time",
            "int32 sec",
            "uint32 nanosec",
            SEPARATOR,
            f"MSG: {package}/{namespace}/{name}_Request",
            request,
            SEPARATOR,
            f"MSG: {package}/{namespace}/{name}_Response",
            response,
        ]
    )
