"""Loading an interface source: saved inventories, recordings and bad input."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

import pytest

from skillwright.errors import FileFormatError, InputFileNotFoundError, OperationCancelledError
from skillwright.interfaces.load import load_inventory, read_warnings
from tests.conftest import SHIPPED_CAPABILITIES

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


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


def test_a_cancelled_recording_stops_after_the_file_is_read(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from skillwright import core
    from skillwright.interfaces.sources import bag

    cancel = threading.Event()
    real_read = core.read_mcap

    def read_then_cancel(*args: Any) -> Any:
        result = real_read(*args)
        cancel.set()  # Esc while the Rust core reads the file
        return result

    filled: list[object] = []
    monkeypatch.setattr(core, "read_mcap", read_then_cancel)
    monkeypatch.setattr(bag, "fill_missing_definitions", lambda *a, **k: filled.append(a) or 0)
    with pytest.raises(OperationCancelledError):
        load_inventory(RECORDING, cancel=cancel)
    assert cancel.is_set()
    assert filled == [], "the interfaces were built and filled in after the cancel"


def test_a_cancelled_inventory_is_not_validated(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from skillwright.interfaces import load

    saved = tmp_path / "mr1.inventory.json"
    saved.write_text(load_inventory(RECORDING).model_dump_json(), encoding="utf-8")
    cancel = threading.Event()
    real_read = load._read_json
    monkeypatch.setattr(load, "_read_json", lambda path: (real_read(path), cancel.set())[0])
    validated: list[Path] = []
    monkeypatch.setattr(load, "_inventory_from_json", lambda path, doc: validated.append(path))
    with pytest.raises(OperationCancelledError, match=r"mr1\.inventory\.json cancelled"):
        load_inventory(saved, cancel=cancel)
    assert validated == []


def test_without_a_cancel_the_same_source_loads_in_full() -> None:
    assert load_inventory(RECORDING, cancel=threading.Event()).interfaces


def cut_recording(tmp_path: Path) -> Path:
    """The shipped MR-1 recording without its last 20 KB, as a copy stopped early leaves it."""
    [recording] = RECORDING.glob("*.mcap")
    data = recording.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) - 20_000])
    return cut


def test_a_recording_cut_short_is_said_with_what_it_costs(tmp_path: Path) -> None:
    cut = cut_recording(tmp_path)
    [warning] = read_warnings(load_inventory(cut))
    assert warning.startswith(f"{cut}: read only up to byte ")
    assert warning.endswith("interfaces recorded after it are missing")


def test_a_whole_recording_has_no_read_warnings() -> None:
    assert read_warnings(load_inventory(RECORDING)) == []
