"""Recorded messages: MCAP framing by the Rust core, CDR by rosbags, into dicts."""

from __future__ import annotations

import itertools
import math
import struct
from pathlib import Path

import pytest

from skillwright.errors import FileFormatError
from skillwright.interfaces.inventory import Interface, Inventory, Resource
from skillwright.interfaces.ros2msg import definition_from_text
from skillwright.runtime.recorded import MessageDecoder, RecordedMessageError, merged_messages
from skillwright.runtime.typesys import TypeRegistry
from tests.runtime.conftest import MR1_RECORDING

MCAP = MR1_RECORDING / "mr1_0.mcap"


def _registry(type_name: str, text: str, *more: tuple[str, str]) -> TypeRegistry:
    interfaces = [
        Interface(
            name=f"/x{index}",
            kind="topic",
            type_name=name,
            definitions={"message": definition_from_text(name, definition)},
        )
        for index, (name, definition) in enumerate(((type_name, text), *more))
    ]
    return TypeRegistry(Inventory(resource=Resource(name="test"), interfaces=interfaces))


def test_every_message_of_the_shipped_recording_is_read_in_time_order_per_topic() -> None:
    messages = list(merged_messages([MCAP]))
    assert len(messages) == 897
    for _, group in itertools.groupby(sorted(messages, key=lambda m: m[1]), key=lambda m: m[1]):
        times = [m[0] for m in group]
        assert times == sorted(times)


def test_a_topic_filter_keeps_only_those_topics() -> None:
    topics = {topic for _, topic, _ in merged_messages([MCAP], {"/odom", "/scan"})}
    assert topics == {"/odom", "/scan"}


def test_split_recordings_merge_by_time() -> None:
    merged = [m[0] for m in merged_messages([MCAP, MCAP], {"/odom"})]
    assert len(merged) == 300
    assert merged == sorted(merged)


def test_a_file_that_is_not_mcap_is_refused_when_opened(tmp_path: Path) -> None:
    path = tmp_path / "x.mcap"
    path.write_bytes(b"not an mcap file at all")
    with pytest.raises(FileFormatError, match=r"x\.mcap: not an MCAP file .*at byte 0"):
        merged_messages([MCAP, path])


def _first_chunk_offset(data: bytes) -> int:
    offset = 8
    while data[offset] != 0x06:
        (length,) = struct.unpack_from("<Q", data, offset + 1)
        offset += 9 + length
    return offset


def test_a_chunk_cut_short_fails_naming_where_it_breaks(tmp_path: Path) -> None:
    data = MCAP.read_bytes()
    chunk = _first_chunk_offset(data)
    path = tmp_path / "cut.mcap"
    path.write_bytes(data[: chunk + 100])
    with pytest.raises(FileFormatError, match=f"record is cut short \\(at byte {chunk}\\)"):
        list(merged_messages([path]))


def test_recorded_scans_and_odometry_decode_to_their_fields(mr1_inventory: Inventory) -> None:
    decoder = MessageDecoder(TypeRegistry(mr1_inventory))
    wanted = {"/scan": "sensor_msgs/msg/LaserScan", "/odom": "nav_msgs/msg/Odometry"}
    first = {}
    for _, topic, payload in merged_messages([MCAP], set(wanted)):
        first.setdefault(topic, decoder.decode(wanted[topic], payload))
    scan = first["/scan"]
    assert len(scan["ranges"]) == 360
    assert isinstance(scan["ranges"], list)
    assert scan["angle_min"] == pytest.approx(-math.pi)
    assert scan["header"]["frame_id"] == "laser_link"
    assert scan["header"]["stamp"].keys() == {"sec", "nanosec"}
    assert first["/odom"]["child_frame_id"] == "base_link"
    assert len(first["/odom"]["pose"]["covariance"]) == 36


@pytest.mark.parametrize(("representation", "endian"), [(b"\x00\x01", "<"), (b"\x00\x00", ">")])
def test_both_byte_orders_decode_with_alignment_strings_sequences_and_nested_types(
    representation: bytes, endian: str
) -> None:
    registry = _registry(
        "test_msgs/msg/Sample",
        "uint8 flag\nstring name\nfloat64[] values\nint16[2] pair\ntest_msgs/msg/Part[] parts",
        ("test_msgs/msg/Part", "bool on\nstring<=4 tag"),
    )
    payload = struct.pack(endian + "B3xI", 7, 4) + b"abc\x00"
    payload += struct.pack(endian + "I", 2) + struct.pack(endian + "2d", 1.5, -2.0)
    payload += struct.pack(endian + "2h", 3, -4)
    payload += struct.pack(endian + "I", 1) + b"\x01\x00\x00\x00" + struct.pack(endian + "I", 2)
    payload += b"a\x00"

    message = MessageDecoder(registry).decode(
        "test_msgs/msg/Sample", representation + b"\x00\x00" + payload
    )

    assert message == {
        "flag": 7,
        "name": "abc",
        "values": [1.5, -2.0],
        "pair": [3, -4],
        "parts": [{"on": True, "tag": "a"}],
    }


def test_truncated_foreign_or_undefined_data_is_a_recorded_message_error() -> None:
    registry = _registry("test_msgs/msg/Sample", "float64 x\nfloat64 y")
    decoder = MessageDecoder(registry)
    with pytest.raises(RecordedMessageError, match="truncated"):
        decoder.decode("test_msgs/msg/Sample", b"\x00\x01\x00\x00" + struct.pack("<d", 1.0))
    with pytest.raises(RecordedMessageError, match="not plain CDR"):
        decoder.decode("test_msgs/msg/Sample", b"\x00\x07\x00\x00" + bytes(16))
    with pytest.raises(RecordedMessageError, match="shorter than the CDR header"):
        decoder.decode("test_msgs/msg/Sample", b"\x00\x01")
    with pytest.raises(RecordedMessageError, match="no definition of test_msgs/msg/Other"):
        decoder.decode("test_msgs/msg/Other", b"\x00\x01\x00\x00")


def test_a_type_rosbags_cannot_lay_out_is_refused_every_time() -> None:
    decoder = MessageDecoder(_registry("test_msgs/msg/Wide", "wstring text"))
    for _ in range(2):
        with pytest.raises(RecordedMessageError, match="test_msgs/msg/Wide: cannot be decoded"):
            decoder.decode("test_msgs/msg/Wide", b"\x00\x01\x00\x00" + bytes(8))
