"""CDR decoding of recorded messages."""

from __future__ import annotations

import math
import struct

import pytest

from skillwright.interfaces.inventory import Interface, Inventory, Resource
from skillwright.interfaces.ros2msg import definition_from_text
from skillwright.runtime.cdr import CdrDecoder, CdrError
from skillwright.runtime.mcapread import read_messages
from skillwright.runtime.typesys import TypeRegistry
from tests.runtime.conftest import MR1_RECORDING


def _registry(type_name: str, text: str) -> TypeRegistry:
    interface = Interface(
        name="/x",
        kind="topic",
        type_name=type_name,
        definitions={"message": definition_from_text(type_name, text)},
    )
    return TypeRegistry(Inventory(resource=Resource(name="test"), interfaces=[interface]))


def test_recorded_scans_and_odometry_decode_to_their_fields(mr1_inventory: Inventory) -> None:
    decoder = CdrDecoder(TypeRegistry(mr1_inventory))
    wanted = {"/scan": "sensor_msgs/msg/LaserScan", "/odom": "nav_msgs/msg/Odometry"}
    first = {}
    for _, topic, payload in read_messages(MR1_RECORDING / "mr1_0.mcap", set(wanted)):
        first.setdefault(topic, decoder.decode(wanted[topic], payload))
    scan = first["/scan"]
    assert len(scan["ranges"]) == 360
    assert scan["angle_min"] == pytest.approx(-math.pi)
    assert scan["header"]["frame_id"] == "laser_link"
    assert first["/odom"]["child_frame_id"] == "base_link"
    assert len(first["/odom"]["pose"]["covariance"]) == 36


@pytest.mark.parametrize(("representation", "endian"), [(b"\x00\x01", "<"), (b"\x00\x00", ">")])
def test_both_byte_orders_decode_with_alignment_strings_and_sequences(
    representation: bytes, endian: str
) -> None:
    registry = _registry(
        "test_msgs/msg/Sample", "uint8 flag\nstring name\nfloat64[] values\nint16[2] pair"
    )
    payload = struct.pack(endian + "B3xI", 7, 4) + b"abc\x00"
    payload += struct.pack(endian + "I", 2) + struct.pack(endian + "2d", 1.5, -2.0)
    payload += struct.pack(endian + "2h", 3, -4)

    message = CdrDecoder(registry).decode(
        "test_msgs/msg/Sample", representation + b"\x00\x00" + payload
    )

    assert message == {"flag": 7, "name": "abc", "values": [1.5, -2.0], "pair": [3, -4]}


def test_truncated_or_foreign_data_is_a_cdr_error() -> None:
    registry = _registry("test_msgs/msg/Sample", "float64 x\nfloat64 y")
    decoder = CdrDecoder(registry)
    with pytest.raises(CdrError, match="truncated"):
        decoder.decode("test_msgs/msg/Sample", b"\x00\x01\x00\x00" + struct.pack("<d", 1.0))
    with pytest.raises(CdrError, match="not plain CDR"):
        decoder.decode("test_msgs/msg/Sample", b"\x00\x07\x00\x00" + bytes(16))
    with pytest.raises(CdrError, match="no definition"):
        decoder.decode("test_msgs/msg/Other", b"\x00\x01\x00\x00")
