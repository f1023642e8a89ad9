"""Typed stubs of the Rust extension ``skillwright._core`` (checked by ``make lint``)."""

from os import PathLike
from typing import final

import numpy as np
from numpy.typing import NDArray

__all__ = ["VectorIndex", "__version__", "index_isa", "sha256_file"]
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
