"""Model files on disk: where they are, whether they are complete, and their checksums.

Hashing a gigabyte model takes seconds, so a verified checksum is remembered in the cache
folder together with the file's size and modification time; a file that changes either is
hashed again. The hashing itself runs in the Rust core.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from skillwright.errors import (
    ModelChecksumError,
    ModelFileMissingError,
    ModelFormatError,
)
from skillwright.llm.config import ENV_MODELS_DIR, LlamaCppModel, Registry
from skillwright.llm.gguf_info import GGUFInfo, read_gguf_info

__all__ = ["ChecksumCache", "ModelFile", "check_model_file", "inspect_model_file"]

ChecksumState = Literal["verified", "mismatch", "not configured", "not checked"]


class ChecksumCache:
    """SHA-256 sums of files, valid while a file's size and mtime stay the same."""

    def __init__(self, path: Path) -> None:
        self.path = path
        """The JSON file holding the sums."""

    def _load(self) -> dict[str, dict[str, int | str]]:
        try:
            data = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}  # a missing or damaged cache only costs a re-hash
        return data if isinstance(data, dict) else {}

    def sha256(self, file: Path) -> str:
        """The file's SHA-256, from the cache when size and mtime still match."""
        from skillwright.core import sha256_file

        stat = file.stat()
        key = str(file.resolve())
        entries = self._load()
        entry = entries.get(key)
        if (
            isinstance(entry, dict)
            and entry.get("size") == stat.st_size
            and entry.get("mtime_ns") == stat.st_mtime_ns
            and isinstance(entry.get("sha256"), str)
        ):
            return str(entry["sha256"])
        digest = sha256_file(file)
        entries[key] = {"size": stat.st_size, "mtime_ns": stat.st_mtime_ns, "sha256": digest}
        self._store(entries)
        return digest

    def _store(self, entries: dict[str, dict[str, int | str]]) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, temp = tempfile.mkstemp(dir=self.path.parent, prefix=".checksums-", suffix=".tmp")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as stream:
                json.dump(entries, stream, indent=1, sort_keys=True)
            Path(temp).replace(self.path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise


@dataclass(frozen=True)
class ModelFile:
    """A checked GGUF model file."""

    path: Path
    """Absolute path of the file."""
    info: GGUFInfo
    """What its header says."""
    sha256: str | None
    """Its SHA-256 when it was computed (always when one is configured)."""
    checksum: ChecksumState
    """Outcome of the checksum check."""


def _missing_message(entry: LlamaCppModel, path: Path, registry: Registry) -> str:
    where = (
        f" (obtain it on a machine with internet access: {entry.source})" if entry.source else ""
    )
    return (
        f"model {entry.id!r}: file {path} not found. Copy the GGUF file there{where}, or change "
        f"`file` of {entry.id!r} in your models.toml, or set ${ENV_MODELS_DIR} to the folder "
        f"that holds it (settings from {registry.origin}). skillwright never downloads models."
    )


def inspect_model_file(
    entry: LlamaCppModel, registry: Registry, checksums: ChecksumCache, *, verify: bool = True
) -> ModelFile:
    """Checks a model's file: present, a complete GGUF, and (if configured) the right SHA-256.

    Raises :class:`ModelFileMissingError`, :class:`ModelFormatError` or
    :class:`ModelChecksumError`, each naming the model id, the path and what to do.
    """
    path = registry.resolve(entry.file)
    if not path.is_file():
        raise ModelFileMissingError(_missing_message(entry, path, registry))
    try:
        info = read_gguf_info(path)
    except ModelFormatError as error:
        raise ModelFormatError(
            f"model {entry.id!r}: {error} (check `file` of {entry.id!r} in {registry.origin})"
        ) from None
    if entry.sha256 is None or not verify:
        return ModelFile(path, info, None, "not configured" if verify else "not checked")
    digest = checksums.sha256(path)
    if digest != entry.sha256:
        raise ModelChecksumError(
            f"model {entry.id!r}: {path} has SHA-256 {digest} but models.toml expects "
            f"{entry.sha256}; the copy is damaged or a different build: copy the file again, "
            f"or update `sha256` of {entry.id!r} if you meant to switch files"
        )
    return ModelFile(path, info, digest, "verified")


def check_model_file(
    entry: LlamaCppModel, registry: Registry, checksums: ChecksumCache
) -> ModelFile:
    """Like :func:`inspect_model_file`, and always knows the file's SHA-256 afterwards.

    The prefix cache keys saved states by the model's checksum, so loading needs it even when
    ``models.toml`` configures none (it is computed once and cached).
    """
    checked = inspect_model_file(entry, registry, checksums)
    if checked.sha256 is None:
        return ModelFile(
            checked.path, checked.info, checksums.sha256(checked.path), "not configured"
        )
    return checked
