"""Saved llama.cpp states of evaluated prompt prefixes, on disk.

Skill prompts share thousands of fixed tokens, which take minutes to evaluate on two CPU cores.
After the first evaluation the context's state (its KV cache) is written to
``<cache>/prefix/<model-sha>-<key>.bin``; later runs load it in a fraction of a second. The key
hashes everything the state depends on: the model's checksum, the prefix tokens, the context
size and the llama-cpp-python version, so a new model, prefix or library never reuses an old
state. A file that fails its own checksum or does not load is deleted and the prefix evaluated
again: a corrupt cache costs time, never a failure.

File layout: magic, a little-endian u32 header length, a JSON header, the prefix tokens (int32),
the llama.cpp state bytes, and a SHA-256 of everything before it.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import struct
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

__all__ = ["PrefixCache", "PrefixState", "prefix_key"]

_MAGIC = b"SWPREFIX1\n"
_DIGEST = 32
log = logging.getLogger(__name__)


def prefix_key(model_sha256: str, tokens: Sequence[int], *, context: str) -> str:
    """The file-name key of a prefix: model checksum and a hash of tokens and context facts."""
    digest = hashlib.sha256()
    digest.update(context.encode())
    digest.update(b"\0")
    digest.update(struct.pack(f"<{len(tokens)}i", *tokens))
    return f"{model_sha256[:16]}-{digest.hexdigest()[:32]}"


@dataclass(frozen=True)
class PrefixState:
    """An evaluated prefix: its tokens and the llama.cpp context state after them."""

    tokens: tuple[int, ...]
    """The prefix tokens."""
    state: bytes
    """``llama_state_get_data`` bytes."""


class PrefixCache:
    """A folder of saved prefix states, at most ``keep`` per model (least recently used go)."""

    def __init__(self, folder: Path, *, keep: int = 8) -> None:
        self.folder = folder
        """Where the ``.bin`` files live."""
        self.keep = keep
        """States kept per model; older ones are deleted when a new one is stored."""

    def path_for(self, key: str) -> Path:
        """The file of a key."""
        return self.folder / f"{key}.bin"

    def load(self, key: str, tokens: Sequence[int]) -> PrefixState | None:
        """The saved state for ``key``, or ``None`` when absent; damaged files are deleted."""
        path = self.path_for(key)
        try:
            raw = path.read_bytes()
        except FileNotFoundError:
            return None
        except OSError as error:
            log.warning("prefix cache %s unreadable (%s); evaluating the prefix", path, error)
            return None
        problem = _check(raw, tokens)
        if problem is not None:
            self.discard(key, problem)
            return None
        header_len = struct.unpack_from("<I", raw, len(_MAGIC))[0]
        start = len(_MAGIC) + 4 + header_len
        header = json.loads(raw[len(_MAGIC) + 4 : start])
        n_tokens = int(header["n_tokens"])
        state = raw[start + 4 * n_tokens : len(raw) - _DIGEST]
        os.utime(path)  # recently used: keep it longest
        return PrefixState(tuple(tokens), state)

    def discard(self, key: str, reason: str) -> None:
        """Deletes a saved state that cannot be used, with a warning saying why."""
        path = self.path_for(key)
        log.warning(
            "discarding prefix cache %s: %s; the prefix will be evaluated again", path, reason
        )
        path.unlink(missing_ok=True)

    def store(self, key: str, prefix: PrefixState) -> Path:
        """Writes a state atomically (temporary file + rename) and prunes old ones."""
        self.folder.mkdir(parents=True, exist_ok=True)
        header = json.dumps({"n_tokens": len(prefix.tokens), "state_bytes": len(prefix.state)})
        body = b"".join(
            [
                _MAGIC,
                struct.pack("<I", len(header)),
                header.encode(),
                struct.pack(f"<{len(prefix.tokens)}i", *prefix.tokens),
                prefix.state,
            ]
        )
        path = self.path_for(key)
        fd, temp = tempfile.mkstemp(dir=self.folder, prefix=".prefix-", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as stream:
                stream.write(body)
                stream.write(hashlib.sha256(body).digest())
            Path(temp).replace(path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise
        self._prune(key.split("-", 1)[0])
        return path

    def _prune(self, model_part: str) -> None:
        files = sorted(
            self.folder.glob(f"{model_part}-*.bin"),
            key=lambda p: p.stat().st_mtime_ns,
            reverse=True,
        )
        for old in files[self.keep :]:
            old.unlink(missing_ok=True)


def _check(raw: bytes, tokens: Sequence[int]) -> str | None:
    """Why a cache file cannot be used, or ``None`` if it is intact and holds ``tokens``."""
    if not raw.startswith(_MAGIC):
        return "not a skillwright prefix-cache file"
    if len(raw) < len(_MAGIC) + 4 + _DIGEST:
        return "truncated"
    if hashlib.sha256(raw[:-_DIGEST]).digest() != raw[-_DIGEST:]:
        return "checksum mismatch (the file is damaged or truncated)"
    header_len = struct.unpack_from("<I", raw, len(_MAGIC))[0]
    start = len(_MAGIC) + 4 + header_len
    try:
        header = json.loads(raw[len(_MAGIC) + 4 : start])
        n_tokens = int(header["n_tokens"])
        state_bytes = int(header["state_bytes"])
    except (ValueError, KeyError, TypeError):
        return "unreadable header"
    if start + 4 * n_tokens + state_bytes + _DIGEST != len(raw):
        return "length does not match its header"
    stored = struct.unpack_from(f"<{n_tokens}i", raw, start)
    if tuple(stored) != tuple(tokens):
        return "holds a different prefix"
    return None
