"""The Rust extension is built, typed and maps its errors into our hierarchy."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from skillwright import errors
from skillwright.core import core_version, read_mcap_messages, sha256_file


def test_core_reports_its_version() -> None:
    assert core_version().count(".") == 2


def test_sha256_file_matches_hashlib(tmp_path: Path) -> None:
    path = tmp_path / "blob.bin"
    data = bytes(range(256)) * 9000  # several read blocks
    path.write_bytes(data)
    assert sha256_file(path) == hashlib.sha256(data).hexdigest()


def test_missing_file_arrives_as_typed_not_found_error(tmp_path: Path) -> None:
    missing = tmp_path / "nope.gguf"
    with pytest.raises(errors.InputFileNotFoundError, match=r"nope\.gguf: no such file") as info:
        sha256_file(missing)
    assert isinstance(info.value, FileNotFoundError)
    assert isinstance(info.value, errors.SkillwrightError)


def test_folder_arrives_as_invalid_argument(tmp_path: Path) -> None:
    with pytest.raises(errors.InvalidArgumentError, match="is a folder"):
        sha256_file(tmp_path)


def test_mcap_messages_errors_arrive_as_typed_exceptions(tmp_path: Path) -> None:
    with pytest.raises(errors.InputFileNotFoundError, match="no such file"):
        read_mcap_messages(tmp_path / "absent.mcap")
    with pytest.raises(errors.InvalidArgumentError, match="is a folder"):
        read_mcap_messages(tmp_path)
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(b"\x89MCAP0\r\n" + b"\x04" + (1000).to_bytes(8, "little") + b"\x00" * 10)
    messages = read_mcap_messages(cut)
    with pytest.raises(errors.FileFormatError, match=r"cut\.mcap: record is cut short"):
        next(messages)
    assert list(messages) == []
