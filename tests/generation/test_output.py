"""Outputs are written whole, and a user's edits are backed up, never overwritten."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.errors import InputFileError
from skillwright.generation.output import write_outputs


def test_files_are_written_and_no_staging_folder_remains(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert write_outputs(out, {"skill.py": "x = 1\n", "record.json": b"{}"}) == []
    assert (out / "skill.py").read_text() == "x = 1\n"
    assert (out / "record.json").read_bytes() == b"{}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_identical_rewrite_makes_no_backup(tmp_path: Path) -> None:
    write_outputs(tmp_path / "out", {"skill.py": "x = 1\n"})
    assert write_outputs(tmp_path / "out", {"skill.py": "x = 1\n"}) == []
    assert not (tmp_path / "out" / ".backup").exists()


def test_edited_file_is_backed_up_before_it_is_replaced(tmp_path: Path) -> None:
    out = tmp_path / "out"
    write_outputs(out, {"skill.py": "generated\n", "record.json": "{}"})
    (out / "skill.py").write_text("edited by hand\n")
    backups = write_outputs(out, {"skill.py": "generated again\n", "record.json": "{}"})
    assert len(backups) == 1
    assert backups[0].read_text() == "edited by hand\n"
    assert backups[0].parent.parent == out / ".backup"
    assert (out / "skill.py").read_text() == "generated again\n"


def test_failure_while_staging_leaves_the_folder_untouched(tmp_path: Path) -> None:
    out = tmp_path / "out"
    write_outputs(out, {"skill.py": "old\n"})
    with pytest.raises(InputFileError, match="writing failed"):
        write_outputs(out, {"skill.py": "new\n", "bad/name.txt": "x"})
    assert (out / "skill.py").read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_unwritable_location_is_reported(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(InputFileError, match="cannot be created"):
        write_outputs(blocker / "out", {"skill.py": ""})
