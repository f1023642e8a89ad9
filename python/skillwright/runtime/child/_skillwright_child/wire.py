"""The child's end of the connection to the host: length-prefixed JSON frames.

A frame is a 4-byte big-endian length followed by that many bytes of UTF-8 JSON holding
one object with an ``op`` key. The child sends notices (no answer) and requests (the
host answers with exactly one frame). Non-finite floats travel as JSON's ``NaN`` and
``Infinity`` extensions, which Python's json module reads and writes on both ends.

The frequent notices (a publish, a log line, printed text) are held and go out with the
next frame that is sent anyway (a request, a rarer notice), in order: the host handles
them at the same virtual time either way, since its graph only moves when asked, and it
is woken once instead of once per notice.
"""

from __future__ import annotations

import json
import socket
import struct
import threading

_HEADER = struct.Struct(">I")
MAX_REPLY = 64 * 1024 * 1024
HELD = frozenset({"publish", "log", "output"})
_ENCODE = json.JSONEncoder(separators=(",", ":")).encode
_HOLD_BYTES = 256 * 1024


class HostGone(BaseException):
    """The host closed the connection: the run is over, the child must end now."""


class Wire:
    """Sends frames to the host and reads its replies (one request at a time)."""

    def __init__(self, sock: socket.socket) -> None:
        self._sock = sock
        self._lock = threading.Lock()
        self._held: list[bytes] = []
        self._held_bytes = 0

    def _send(self, frame: dict, hold: bool = False) -> None:
        data = _ENCODE(frame).encode("utf-8")
        self._held.append(_HEADER.pack(len(data)) + data)
        self._held_bytes += len(data)
        if hold and self._held_bytes < _HOLD_BYTES:
            return
        out = b"".join(self._held)
        self._held.clear()
        self._held_bytes = 0
        try:
            self._sock.sendall(out)
        except OSError as error:
            raise HostGone(str(error)) from None

    def _read_exact(self, size: int) -> bytes:
        chunks = []
        while size:
            try:
                chunk = self._sock.recv(min(size, 1 << 20))
            except OSError as error:
                raise HostGone(str(error)) from None
            if not chunk:
                raise HostGone("the host closed the connection")
            chunks.append(chunk)
            size -= len(chunk)
        return b"".join(chunks)

    def notify(self, op: str, **fields: object) -> None:
        """Sends a frame the host does not answer."""
        fields["op"] = op
        with self._lock:
            self._send(fields, hold=op in HELD)

    def request(self, op: str, **fields: object) -> dict:
        """Sends a frame and returns the host's answer."""
        fields["op"] = op
        with self._lock:
            self._send(fields)
            (size,) = _HEADER.unpack(self._read_exact(_HEADER.size))
            if size > MAX_REPLY:
                raise HostGone(f"reply of {size} bytes is larger than allowed")
            reply = json.loads(self._read_exact(size).decode("utf-8"))
        if not isinstance(reply, dict):
            raise HostGone("the host's reply is not an object")
        return reply
