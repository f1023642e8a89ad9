"""Python facade of the Rust extension: the only module that imports ``skillwright._core``."""

from __future__ import annotations

from pathlib import Path

from skillwright import _core

__all__ = ["core_version", "sha256_file"]


def core_version() -> str:
    """Version of the compiled Rust core."""
    return _core.__version__


def sha256_file(path: str | Path) -> str:
    """Lower-case hex SHA-256 of a file; errors name the file (see ``skillwright.errors``)."""
    return _core.sha256_file(Path(path))
