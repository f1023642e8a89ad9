"""Streaming the messages of MCAP recordings, chunk by chunk, for replay.

Only what replay needs: channels (topic by id) and message records, in and outside
chunks (zstd or lz4 compressed, or not at all), read front to back so memory stays at
about one chunk. Messages of a chunk are yielded in log-time order; the chunks of a
recording follow each other in time, as rosbag2 writes them. Several files (a split
rosbag2 recording) are merged by time. Discovery's own reader (the Rust core) reads
summaries and indexes; it does not hand out message payloads.

Replay reads the same recording again for every run and every loop of it, so decoded
chunks are kept (up to :data:`CHUNK_MEMORY` bytes of payload, the least recently read
dropped first), keyed by file, size, modification time and offset: a short recording is
decompressed once per process, a long one streams as before.
"""

from __future__ import annotations

import heapq
import os
import struct
import threading
from collections import OrderedDict
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import BinaryIO, Final, NamedTuple

__all__ = [
    "CHUNK_MEMORY",
    "MAGIC",
    "McapMessage",
    "McapReadError",
    "merged_messages",
    "read_messages",
]

MAGIC: Final = b"\x89MCAP0\r\n"
_OP_SCHEMA, _OP_CHANNEL, _OP_MESSAGE, _OP_CHUNK = 0x03, 0x04, 0x05, 0x06
_OP_FOOTER, _OP_DATA_END = 0x02, 0x0F
_RECORD = struct.Struct("<BQ")
_MESSAGE = struct.Struct("<HIQQ")
_CHUNK = struct.Struct("<QQQI")

McapMessage = tuple[int, str, bytes]
"""``(log time in ns, topic, CDR payload)``."""

CHUNK_MEMORY: Final = 64 * 1024 * 1024
"""Bytes of message payload kept from decoded chunks."""


class _Decoded(NamedTuple):
    """A chunk as replay needs it: the channels it defines and its messages in time order
    (their topics resolved with the channels known where the chunk starts)."""

    channels: tuple[tuple[int, str], ...]
    messages: tuple[McapMessage, ...]
    size: int


class _ChunkMemory:
    """Decoded chunks, least recently read dropped first beyond :data:`CHUNK_MEMORY`."""

    def __init__(self) -> None:
        self._chunks: OrderedDict[tuple[str, int, int, int], _Decoded] = OrderedDict()
        self._size = 0
        # Validations may run in worker threads side by side.
        self._lock = threading.Lock()

    def get(self, key: tuple[str, int, int, int]) -> _Decoded | None:
        with self._lock:
            found = self._chunks.get(key)
            if found is not None:
                self._chunks.move_to_end(key)
            return found

    def put(self, key: tuple[str, int, int, int], decoded: _Decoded) -> None:
        with self._lock:
            if key in self._chunks or decoded.size > CHUNK_MEMORY:
                return
            self._chunks[key] = decoded
            self._size += decoded.size
            while self._size > CHUNK_MEMORY:
                _, dropped = self._chunks.popitem(last=False)
                self._size -= dropped.size


_MEMORY = _ChunkMemory()


class McapReadError(ValueError):
    """The file is not MCAP, or a record is broken; the message names file and offset."""


def _decompress(compression: str, data: bytes, size: int) -> bytes:
    if compression == "":
        return data
    if compression == "zstd":
        try:
            from compression import zstd  # type: ignore[import-not-found]
        except ImportError:
            from backports import zstd
        return bytes(zstd.decompress(data))
    if compression == "lz4":
        import lz4.frame  # type: ignore[import-untyped]

        return bytes(lz4.frame.decompress(data))
    raise McapReadError(f"chunk compression {compression!r} is not supported")


def _string(data: bytes | memoryview, offset: int) -> tuple[str, int]:
    (length,) = struct.unpack_from("<I", data, offset)
    offset += 4
    return bytes(data[offset : offset + length]).decode("utf-8"), offset + length


def _records(data: bytes | memoryview) -> Iterator[tuple[int, memoryview]]:
    view = memoryview(data)
    offset = 0
    while offset + _RECORD.size <= len(view):
        op, length = _RECORD.unpack_from(view, offset)
        offset += _RECORD.size
        yield op, view[offset : offset + length]
        offset += length


def read_messages(path: Path, topics: set[str] | None = None) -> Iterator[McapMessage]:
    """The messages of one MCAP file (of ``topics`` only, if given), chunk by chunk."""
    channels: dict[int, str] = {}
    with path.open("rb") as stream:
        status = os.fstat(stream.fileno())
        if stream.read(len(MAGIC)) != MAGIC:
            raise McapReadError(f"{path}: not an MCAP file (wrong magic bytes)")
        while True:
            offset = stream.tell()
            head = stream.read(_RECORD.size)
            if len(head) < _RECORD.size:
                return
            op, length = _RECORD.unpack(head)
            if op in (_OP_FOOTER, _OP_DATA_END):
                return
            if op not in (_OP_CHANNEL, _OP_MESSAGE, _OP_CHUNK):
                stream.seek(length, 1)
                continue
            if op == _OP_CHUNK:
                key = (str(path), status.st_size, status.st_mtime_ns, offset)
                decoded = _MEMORY.get(key)
                if decoded is None:
                    body = _read_exact(stream, length, path, offset)
                    decoded = _chunk(body, channels, path, offset)
                    _MEMORY.put(key, decoded)
                else:
                    stream.seek(length, 1)
                channels.update(decoded.channels)
                for chunked in decoded.messages:
                    if topics is None or chunked[1] in topics:
                        yield chunked
            else:
                body = _read_exact(stream, length, path, offset)
                message = _record(op, memoryview(body), channels, topics)
                if message is not None:
                    yield message


def _read_exact(stream: BinaryIO, length: int, path: Path, offset: int) -> bytes:
    body = stream.read(length)
    if len(body) != length:
        raise McapReadError(f"{path}: record at byte {offset} is cut short")
    return body


def _record(
    op: int, body: memoryview, channels: dict[int, str], topics: set[str] | None
) -> McapMessage | None:
    if op == _OP_CHANNEL:
        (channel_id,) = struct.unpack_from("<H", body, 0)
        topic, _ = _string(body, 4)
        channels[channel_id] = topic
        return None
    if op == _OP_MESSAGE:
        channel_id, _, log_time, _ = _MESSAGE.unpack_from(body, 0)
        known = channels.get(channel_id)
        if known is None or (topics is not None and known not in topics):
            return None
        return log_time, known, bytes(body[_MESSAGE.size :])
    return None


def _chunk(body: bytes, channels: dict[int, str], path: Path, offset: int) -> _Decoded:
    try:
        _, _, size, _ = _CHUNK.unpack_from(body, 0)
        compression, position = _string(body, _CHUNK.size)
        (length,) = struct.unpack_from("<Q", body, position)
        position += 8
        records = _decompress(compression, body[position : position + length], size)
    except (struct.error, UnicodeDecodeError) as error:
        raise McapReadError(f"{path}: chunk at byte {offset} is broken ({error})") from None
    except McapReadError as error:
        raise McapReadError(f"{path}: chunk at byte {offset}: {error}") from None
    except Exception as error:
        raise McapReadError(
            f"{path}: chunk at byte {offset} does not decompress ({error})"
        ) from None
    known = dict(channels)
    messages = []
    for op, record in _records(records):
        message = _record(op, record, known, None)
        if message is not None:
            messages.append(message)
    messages.sort(key=lambda m: m[0])
    defined = tuple((k, v) for k, v in known.items() if channels.get(k) != v)
    return _Decoded(defined, tuple(messages), sum(len(m[2]) for m in messages))


def merged_messages(paths: Iterable[Path], topics: set[str] | None = None) -> Iterator[McapMessage]:
    """The messages of several files (a split recording) in log-time order."""
    return heapq.merge(*(read_messages(p, topics) for p in paths), key=lambda m: m[0])
