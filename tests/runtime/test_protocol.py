"""The host reads the child's frames and refuses malformed ones."""

from __future__ import annotations

import json
import socket
import struct
from collections.abc import Iterator
from typing import Any

import pytest

from skillwright.runtime.protocol import MAX_FRAME, ProtocolError, Wire


@pytest.fixture
def pair() -> Iterator[tuple[Wire, socket.socket]]:
    host, child = socket.socketpair()
    yield Wire(host), child
    host.close()
    child.close()


def _frame(payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + payload


def _receive(wire: Wire) -> dict[str, object] | None:
    frame = wire.receive()
    while frame is None:
        frame = wire.receive()
    return frame


def test_frames_arrive_whole_even_when_split_across_reads(pair: tuple[Wire, socket.socket]) -> None:
    wire, child = pair
    data = _frame(json.dumps({"op": "advance", "until": 1.5}).encode()) + _frame(b'{"op": "done"}')
    child.sendall(data[:5])
    assert wire.receive() is None
    child.sendall(data[5:])
    assert _receive(wire) == {"op": "advance", "until": 1.5}
    assert wire.pending()
    assert _receive(wire) == {"op": "done"}


def test_replies_reach_the_child(pair: tuple[Wire, socket.socket]) -> None:
    wire, child = pair
    wire.send({"now": 0.5, "deliveries": [{"data": {"x": float("inf")}}]})
    size = struct.unpack(">I", child.recv(4))[0]
    assert json.loads(child.recv(size)) == {
        "now": 0.5,
        "deliveries": [{"data": {"x": float("inf")}}],
    }


def test_an_oversized_header_is_refused_without_waiting_for_more_data(
    pair: tuple[Wire, socket.socket],
) -> None:
    wire, child = pair
    child.sendall(_frame(b'{"op": "log"}') + struct.pack(">I", MAX_FRAME + 1) + b"x" * 10)
    assert _receive(wire) == {"op": "log"}
    assert wire.pending()
    with pytest.raises(ProtocolError, match="larger than"):
        wire.receive()


@pytest.mark.parametrize(
    ("data", "problem"),
    [
        (struct.pack(">I", MAX_FRAME + 1), "larger than"),
        (_frame(b"\xff\xfe"), "not UTF-8 JSON"),
        (_frame(b"[1, 2]"), "not a JSON object"),
        (_frame(b'{"no_op": 1}'), "string 'op'"),
        (_frame(b"[" * 100_000), "not UTF-8 JSON"),
    ],
)
def test_malformed_frames_are_protocol_errors(
    pair: tuple[Wire, socket.socket], data: bytes, problem: str
) -> None:
    wire, child = pair
    child.sendall(data)
    with pytest.raises(ProtocolError, match=problem):
        _receive(wire)


def test_a_closed_child_is_end_of_file(pair: tuple[Wire, socket.socket]) -> None:
    wire, child = pair
    child.close()
    with pytest.raises(EOFError):
        wire.receive()


def _child_wire() -> Any:
    """The child's end of the wire (its module has only the standard library)."""
    import importlib.util

    from skillwright.runtime.sandbox import CHILD_ROOT

    spec = importlib.util.spec_from_file_location(
        "child_wire", CHILD_ROOT / "_skillwright_child" / "wire.py"
    )
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_childs_publishes_wait_for_its_next_request_and_arrive_in_order() -> None:
    child_end, host_end = socket.socketpair()
    child = _child_wire().Wire(child_end)
    host = Wire(host_end)
    host_end.setblocking(False)
    for step in range(3):
        child.notify("publish", id=1, msg={"x": step}, line=9)
    with pytest.raises(BlockingIOError):
        host_end.recv(1)
    host_end.setblocking(True)
    host.send({"now": 0.1, "deliveries": []})
    assert child.request("advance", until=0.1) == {"now": 0.1, "deliveries": []}
    frames = [host.receive() for _ in range(4)]
    assert [(f["op"], f.get("msg")) for f in frames] == [
        ("publish", {"x": 0}),
        ("publish", {"x": 1}),
        ("publish", {"x": 2}),
        ("advance", None),
    ]
    child.notify("state", name="execute", phase="end", outcome="done")
    assert host.receive() == {"op": "state", "name": "execute", "phase": "end", "outcome": "done"}
    child_end.close()
    host_end.close()
