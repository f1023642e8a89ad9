"""The host's end of the wire to the child: length-prefixed JSON frames, validated.

A frame is a 4-byte big-endian length and that many bytes of UTF-8 JSON holding one
object with a string ``op``. The child is untrusted: a frame that is too large, not
JSON, not an object or without ``op`` raises :class:`ProtocolError`, which the host
reports as a finding and ends the run; nothing the child sends is ever executed
(no pickle, no eval). The child's side is ``child/_skillwright_child/wire.py``.
"""

from __future__ import annotations

import json
import socket
import struct
from typing import Any, Final

__all__ = ["MAX_FRAME", "ProtocolError", "Wire"]

_HEADER: Final = struct.Struct(">I")
MAX_FRAME: Final = 32 * 1024 * 1024
"""Largest frame the host accepts from the child (a big map plus room)."""
_CHUNK: Final = 64 * 1024
_ENCODE: Final = json.JSONEncoder(separators=(",", ":")).encode
"""``json.dumps`` with these options makes a new encoder for every frame."""


class ProtocolError(Exception):
    """The child sent something that is not a valid frame; the message says what."""


class Wire:
    """Reads the child's frames and writes replies, on a connected stream socket."""

    def __init__(self, sock: socket.socket) -> None:
        self._sock = sock
        self._buffer = bytearray()
        # Read into one reused buffer: recv(n) allocates n bytes per call, and a large n
        # costs a fresh mapping of memory for every frame.
        self._chunk = memoryview(bytearray(_CHUNK))

    @property
    def sock(self) -> socket.socket:
        """The socket, for waiting on it."""
        return self._sock

    def send(self, frame: dict[str, Any]) -> None:
        """Writes one frame."""
        data = _ENCODE(frame).encode("utf-8")
        self._sock.sendall(_HEADER.pack(len(data)) + data)

    def receive(self) -> dict[str, Any] | None:
        """Reads bytes that are ready and returns the next complete frame, if any.

        Raises ``EOFError`` when the child closed its end, :class:`ProtocolError` for a
        malformed frame.
        """
        frame = self._take()
        if frame is not None:
            return frame
        size = self._sock.recv_into(self._chunk)
        if not size:
            raise EOFError("the child closed the connection")
        self._buffer += self._chunk[:size]
        return self._take()

    def pending(self) -> bool:
        """Whether :meth:`receive` has something to return (or to refuse) without reading:
        a complete frame, or a header announcing a frame too large to accept."""
        if len(self._buffer) < _HEADER.size:
            return False
        (size,) = _HEADER.unpack_from(self._buffer)
        return size > MAX_FRAME or len(self._buffer) >= _HEADER.size + int(size)

    def _take(self) -> dict[str, Any] | None:
        if len(self._buffer) < _HEADER.size:
            return None
        (size,) = _HEADER.unpack_from(self._buffer)
        if size > MAX_FRAME:
            raise ProtocolError(f"a frame of {size} bytes is larger than {MAX_FRAME}")
        end = _HEADER.size + size
        if len(self._buffer) < end:
            return None
        payload = bytes(self._buffer[_HEADER.size : end])
        del self._buffer[:end]
        try:
            frame = json.loads(payload.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError) as error:
            raise ProtocolError(f"a frame is not UTF-8 JSON: {error}") from None
        if not isinstance(frame, dict) or not isinstance(frame.get("op"), str):
            raise ProtocolError("a frame is not a JSON object with a string 'op'")
        return frame
