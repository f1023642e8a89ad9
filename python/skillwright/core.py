"""Python facade of the Rust extension: the only module that imports ``skillwright._core``."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Literal

from skillwright import _core
from skillwright._core import McapFile, McapMessages

__all__ = [
    "McapFile",
    "McapMessages",
    "core_version",
    "read_mcap",
    "read_mcap_messages",
    "sha256_file",
]


def core_version() -> str:
    """Version of the compiled Rust core."""
    return _core.__version__


def sha256_file(path: str | Path) -> str:
    """Lower-case hex SHA-256 of a file; errors name the file (see ``skillwright.errors``)."""
    return _core.sha256_file(Path(path))


def read_mcap(path: str | Path, mode: Literal["auto", "scan", "full"] = "auto") -> McapFile:
    """What an MCAP file holds: schemas, channels, counts; see ``_core.read_mcap``."""
    return _core.read_mcap(Path(path), mode)


def read_mcap_messages(path: str | Path, topics: Iterable[str] | None = None) -> McapMessages:
    """The messages of an MCAP file (of ``topics`` only, if given) as ``(log time in ns,
    topic, payload)``, chunk by chunk; see ``_core.read_mcap_messages``."""
    return _core.read_mcap_messages(Path(path), None if topics is None else set(topics))
