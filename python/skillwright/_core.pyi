"""Typed stubs of the Rust extension ``skillwright._core`` (checked by ``make lint``)."""

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Literal, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "McapChannel",
    "McapDamage",
    "McapFile",
    "McapMessages",
    "McapSchema",
    "VectorIndex",
    "__version__",
    "confine_child",
    "index_isa",
    "read_mcap",
    "read_mcap_messages",
    "seccomp_programs",
    "sha256_file",
]
__version__: str

def sha256_file(path: str | PathLike[str]) -> str:
    """Lower-case hex SHA-256 of the file at ``path``.

    Raises ``InputFileNotFoundError`` when it does not exist, ``InputFileError`` when it
    cannot be read and ``InvalidArgumentError`` when it is a folder.
    """

# --- vector index (rust/python/src/index.rs) ---

def index_isa() -> str:
    """Instruction set the index's scoring loops use on this CPU (``avx2+fma`` or ``baseline``)."""

@final
class VectorIndex:
    """Exact cosine index over float32 vectors with int64 ids and kind/source tags.

    Array arguments must already be C-contiguous float32 / int64 arrays; the facade
    ``skillwright.retrieval.VectorIndex`` converts other input.
    """

    def __new__(cls, dim: int) -> VectorIndex: ...
    @staticmethod
    def open(path: str | PathLike[str]) -> VectorIndex:
        """Opens a saved index memory-mapped; ``FileFormatError`` if it is not valid."""

    def save(self, path: str | PathLike[str]) -> None:
        """Writes the index atomically (temporary file, then rename)."""

    def verify(self) -> None:
        """Checks a mapped index's vector data against its checksums now."""

    @property
    def dim(self) -> int: ...
    @property
    def mapped(self) -> bool: ...
    def __len__(self) -> int: ...
    def __contains__(self, key: int, /) -> bool: ...
    def ids(self) -> NDArray[np.int64]:
        """Ids of all rows, in storage order."""

    def kinds(self) -> list[str]:
        """Every kind tag the index knows."""

    def sources(self) -> list[str]:
        """Every source tag the index knows."""

    def get(self, id: int) -> tuple[NDArray[np.float32], str, str]:
        """The stored (normalised) vector, kind and source of one id."""

    def add(
        self,
        ids: NDArray[np.int64],
        vectors: NDArray[np.float32],
        kind: str | list[str],
        source: str | list[str],
    ) -> None: ...
    def update(
        self,
        ids: NDArray[np.int64],
        vectors: NDArray[np.float32] | None = None,
        kind: str | list[str] | None = None,
        source: str | list[str] | None = None,
    ) -> None: ...
    def remove(self, ids: NDArray[np.int64]) -> None: ...
    def search(
        self,
        query: NDArray[np.float32],
        k: int,
        kinds: list[str] | None = None,
        sources: list[str] | None = None,
    ) -> tuple[NDArray[np.int64], NDArray[np.float32]]: ...
    def search_batch(
        self,
        queries: NDArray[np.float32],
        k: int,
        kinds: list[str] | None = None,
        sources: list[str] | None = None,
    ) -> tuple[NDArray[np.int64], NDArray[np.float32]]: ...

# --- MCAP discovery (rust/python/src/mcap.rs) ---

@final
class McapSchema:
    """A schema record: how the messages of the channels that use it are laid out."""

    @property
    def id(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def encoding(self) -> str: ...
    @property
    def data(self) -> bytes:
        """The schema's bytes as stored (for ``ros2msg``, the message definition text)."""

@final
class McapChannel:
    """A channel record with its message count and log-time range (nanoseconds)."""

    @property
    def id(self) -> int: ...
    @property
    def schema_id(self) -> int: ...
    @property
    def topic(self) -> str: ...
    @property
    def message_encoding(self) -> str: ...
    @property
    def metadata(self) -> dict[str, str]: ...
    @property
    def message_count(self) -> int: ...
    @property
    def first_log_time(self) -> int | None: ...
    @property
    def last_log_time(self) -> int | None: ...
    @property
    def times_exact(self) -> bool:
        """False when the times are chunk-index bounds (summary reading), not exact."""

@final
class McapDamage:
    """A place in the file where something was wrong."""

    @property
    def offset(self) -> int: ...
    @property
    def message(self) -> str: ...

@final
class McapFile:
    """What one MCAP file holds, as ``read_mcap`` found it."""

    @property
    def path(self) -> Path: ...
    @property
    def file_size(self) -> int: ...
    @property
    def profile(self) -> str | None: ...
    @property
    def library(self) -> str | None: ...
    @property
    def method(self) -> Literal["summary", "scan", "full"]: ...
    @property
    def schemas(self) -> list[McapSchema]: ...
    @property
    def channels(self) -> list[McapChannel]: ...
    @property
    def message_count(self) -> int: ...
    @property
    def message_start_time(self) -> int | None: ...
    @property
    def message_end_time(self) -> int | None: ...
    @property
    def attachment_count(self) -> int: ...
    @property
    def metadata_count(self) -> int: ...
    @property
    def chunk_count(self) -> int: ...
    @property
    def compressions(self) -> list[str]: ...
    @property
    def orphan_message_count(self) -> int: ...
    @property
    def stopped(self) -> McapDamage | None:
        """Where reading stopped before the end of the file (cut short, broken frame)."""
    @property
    def damaged(self) -> list[McapDamage]:
        """Records skipped as damaged; reading went on after them."""
    @property
    def notes(self) -> list[str]: ...
    @property
    def partial(self) -> bool:
        """True when part of the file could not be read (``stopped`` or ``damaged``)."""

def read_mcap(
    path: str | PathLike[str], mode: Literal["auto", "scan", "full"] = "auto"
) -> McapFile:
    """Reads what the MCAP file at ``path`` holds, without holding the GIL.

    ``auto`` reads the summary section when it is complete and scans otherwise; ``scan``
    always scans (message indexes let it skip chunk bodies); ``full`` decompresses every
    chunk. A damaged or truncated file gives a partial result. Raises
    ``InputFileNotFoundError``, ``InputFileError``, ``InvalidArgumentError`` (a folder, an
    unknown mode) and ``FileFormatError`` (empty or not an MCAP file; names the offset).
    """

@final
class McapMessages:
    """The messages of one MCAP file, front to back: ``(log time in ns, topic, payload)``.

    One chunk is in memory at a time and its messages come in log-time order. A broken
    record or a chunk that does not decompress raises ``FileFormatError`` (naming the file
    and the offset) from ``__next__``; the iteration ends there.
    """

    def __iter__(self) -> McapMessages: ...
    def __next__(self) -> tuple[int, str, bytes]: ...

def read_mcap_messages(path: str | PathLike[str], topics: set[str] | None = None) -> McapMessages:
    """Opens the MCAP file at ``path`` for reading its messages (of ``topics`` only, if
    given); each step reads without holding the GIL. Raises ``InputFileNotFoundError``,
    ``InputFileError``, ``InvalidArgumentError`` (a folder) and ``FileFormatError`` (not an
    MCAP file)."""

def seccomp_programs() -> tuple[bytes, bytes]:
    """The sandbox's seccomp allow-list and its fallbacks (``clone3`` answers ``ENOSYS``),
    as ``struct sock_filter`` records in native byte order (bubblewrap's ``--seccomp FD``).
    Linux only."""

def confine_child(
    pid: int,
    readable: Sequence[str | PathLike[str]],
    writable: Sequence[str | PathLike[str]],
    with_base: bool,
) -> dict[str, object]:
    """Confines the calling process for good (Landlock where the kernel has it, then the
    child's seccomp program, after the base ones when ``with_base``); returns
    ``{"landlock": "enforced" | "partly enforced" | "unavailable", "seccomp": [names]}``.
    Raises ``OSError`` when the kernel refuses. Linux only; for the sandboxed child."""
