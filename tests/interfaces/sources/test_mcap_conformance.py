"""Every MCAP file of the upstream conformance suite reads as its expected JSON says.

The expected JSON lists every record the streamed reader sees (numbers as strings,
bytes as lists of decimal strings). We compare what discovery extracts: schemas,
channels, message counts per channel, attachment and metadata counts, in every read mode.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from skillwright.core import read_mcap
from tests.conftest import SHARED

CONFORMANCE = SHARED / "data" / "mcap" / "conformance"
FILES = sorted(CONFORMANCE.glob("*/*.mcap"))


def _expected(mcap_path: Path) -> dict[str, Any]:
    records = json.loads(mcap_path.with_suffix(".json").read_text())["records"]
    schemas: dict[int, tuple[str, str, bytes]] = {}
    channels: dict[int, tuple[str, str, int, dict[str, str]]] = {}
    messages: Counter[int] = Counter()
    kinds: Counter[str] = Counter()
    for record in records:
        fields = dict(record["fields"])
        kinds[record["type"]] += 1
        if record["type"] == "Schema":
            data = bytes(int(b) for b in fields["data"])
            schemas[int(fields["id"])] = (fields["name"], fields["encoding"], data)
        elif record["type"] == "Channel":
            channels[int(fields["id"])] = (
                fields["topic"],
                fields["message_encoding"],
                int(fields["schema_id"]),
                fields["metadata"],
            )
        elif record["type"] == "Message":
            messages[int(fields["channel_id"])] += 1
    return {
        "schemas": schemas,
        "channels": channels,
        "messages": dict(messages),
        "message_count": kinds["Message"],
        "attachments": kinds["Attachment"],
        "metadata": kinds["Metadata"],
    }


def test_the_whole_conformance_suite_is_present(shared_data: Path) -> None:
    assert len(FILES) == 171, f"expected 171 .mcap files in {CONFORMANCE}"


@pytest.mark.parametrize("mode", ["auto", "scan", "full"])
@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_conformance_file_reads_as_expected(path: Path, mode: str, shared_data: Path) -> None:
    expected = _expected(path)
    result = read_mcap(path, mode)  # type: ignore[arg-type]

    assert not result.partial, (result.stopped, result.damaged)
    assert {s.id: (s.name, s.encoding, s.data) for s in result.schemas} == expected["schemas"]
    assert {
        c.id: (c.topic, c.message_encoding, c.schema_id, c.metadata) for c in result.channels
    } == expected["channels"]
    counts = {c.id: c.message_count for c in result.channels if c.message_count}
    assert counts == expected["messages"]
    assert result.message_count == expected["message_count"]
    assert result.attachment_count == expected["attachments"]
    assert result.metadata_count == expected["metadata"]
    if mode != "auto":
        assert result.method == mode
    elif "-st" in path.stem and "-rch" in path.stem and "-rsh" in path.stem:
        # Statistics plus repeated schemas and channels: the summary is enough.
        assert result.method == "summary"
