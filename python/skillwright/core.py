"""Python facade of the Rust extension: the only module that imports ``skillwright._core``."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from skillwright import _core
from skillwright._core import McapFile

__all__ = ["McapFile", "core_version", "read_mcap", "sha256_file"]


def core_version() -> str:
    """Version of the compiled Rust core."""
    return _core.__version__


def sha256_file(path: str | Path) -> str:
    """Lower-case hex SHA-256 of a file; errors name the file (see ``skillwright.errors``)."""
    return _core.sha256_file(Path(path))


def read_mcap(path: str | Path, mode: Literal["auto", "scan", "full"] = "auto") -> McapFile:
    """What an MCAP file holds: schemas, channels, counts; see ``_core.read_mcap``."""
    return _core.read_mcap(Path(path), mode)
