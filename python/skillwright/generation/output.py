"""Writing a generation's results: all files or none, and never over a user's edits.

The files of one generation (``skill.py``, ``prompt.txt``, ``response.txt``,
``record.json``) are written into a temporary folder beside the output folder first, so a
failure part-way leaves nothing behind. They are then moved in one by one (each move is an
atomic rename). A file already in the output folder with different content — for example a
skill the user edited — is first moved to ``.backup/<time>/`` inside the output folder.
"""

from __future__ import annotations

import shutil
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path

from skillwright.errors import InputFileError

__all__ = ["write_outputs"]


def _backup_dir(out_dir: Path) -> Path:
    stamp = time.strftime("%Y%m%d-%H%M%S")
    candidate = out_dir / ".backup" / stamp
    counter = 1
    while candidate.exists():
        counter += 1
        candidate = out_dir / ".backup" / f"{stamp}-{counter}"
    return candidate


def write_outputs(out_dir: Path, files: Mapping[str, str | bytes]) -> list[Path]:
    """Writes ``files`` (name -> content) into ``out_dir``; returns the backups made.

    Raises :class:`InputFileError` naming the folder when it cannot be written.
    """
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    except OSError as error:
        raise InputFileError(
            f"output folder {out_dir}: cannot be created ({error.strerror}); choose another with -o"
        ) from error
    backups: list[Path] = []
    try:
        for name, content in files.items():
            payload = content.encode("utf-8") if isinstance(content, str) else content
            (staging / name).write_bytes(payload)
        backup_dir: Path | None = None
        for name in files:
            target = out_dir / name
            staged = staging / name
            if target.exists() and target.read_bytes() != staged.read_bytes():
                if backup_dir is None:
                    backup_dir = _backup_dir(out_dir)
                    backup_dir.mkdir(parents=True)
                target.replace(backup_dir / name)
                backups.append(backup_dir / name)
            staged.replace(target)
    except OSError as error:
        raise InputFileError(
            f"output folder {out_dir}: writing failed ({error.strerror}); nothing was left "
            "half-written, earlier files are in .backup/"
        ) from error
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return backups
