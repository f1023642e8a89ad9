"""Streaming messages out of MCAP recordings for replay."""

from __future__ import annotations

import itertools
import struct
from pathlib import Path

import pytest

from skillwright.runtime.mcapread import McapReadError, merged_messages, read_messages
from tests.runtime.conftest import MR1_RECORDING

MCAP = MR1_RECORDING / "mr1_0.mcap"


def test_every_message_of_the_shipped_recording_is_read_in_time_order_per_topic() -> None:
    messages = list(read_messages(MCAP))
    assert len(messages) == 897
    for _, group in itertools.groupby(sorted(messages, key=lambda m: m[1]), key=lambda m: m[1]):
        times = [m[0] for m in group]
        assert times == sorted(times)


def test_a_topic_filter_keeps_only_those_topics() -> None:
    topics = {topic for _, topic, _ in read_messages(MCAP, {"/odom", "/scan"})}
    assert topics == {"/odom", "/scan"}


def test_split_recordings_merge_by_time(tmp_path: Path) -> None:
    merged = [m[0] for m in merged_messages([MCAP, MCAP], {"/odom"})]
    assert len(merged) == 300
    assert merged == sorted(merged)


def test_a_file_that_is_not_mcap_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "x.mcap"
    path.write_bytes(b"not an mcap file at all")
    with pytest.raises(McapReadError, match="not an MCAP file"):
        list(read_messages(path))


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
    with pytest.raises(McapReadError, match=f"record at byte {chunk} is cut short"):
        list(read_messages(path))


def test_a_recording_read_again_is_not_decompressed_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.runtime import mcapread

    copy = tmp_path / "copy.mcap"
    copy.write_bytes(MCAP.read_bytes())
    calls: list[int] = []
    real = mcapread._decompress

    def counting(compression: str, data: bytes, size: int) -> bytes:
        calls.append(size)
        return real(compression, data, size)

    monkeypatch.setattr(mcapread, "_decompress", counting)
    first = list(read_messages(copy, {"/odom"}))
    chunks = len(calls)
    assert chunks > 0
    assert list(read_messages(copy, {"/odom"})) == first
    assert len(calls) == chunks
    assert len(list(read_messages(copy))) == 897
    assert len(calls) == chunks, "the kept chunks hold every topic's messages"
