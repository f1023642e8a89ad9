"""Loading an interface source: saved inventories, recordings and bad input."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import FileFormatError, InputFileNotFoundError
from skillwright.interfaces.load import load_inventory


def test_missing_source_names_what_is_accepted(tmp_path: Path) -> None:
    with pytest.raises(InputFileNotFoundError, match=r"give an \.mcap file, a rosbag2 folder"):
        load_inventory(tmp_path / "nothing")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"a": ', r"bad\.json:1:7: JSON syntax error"),
        ('{"a": 1}', r"neither a skillwright inventory .* nor a report"),
        (
            '{"resource": {"name": "r"}, "interfaces": [{"name": 3}]}',
            r"not a valid inventory at interfaces\.0",
        ),
    ],
)
def test_bad_inventory_json_is_explained(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(FileFormatError, match=message):
        load_inventory(path)
