"""An exact, offline vector index for retrieval, backed by the Rust core.

Every vector is normalised on insert, so a search score is the cosine between the query
and a stored vector; every search considers every (allowed) vector, so the result is
exact: it equals a NumPy brute-force reference, with ties ordered by id. (Single searches
over thousands of vectors first compare 8-bit copies, with proven error bounds, and
rescore in float32 only the vectors those bounds cannot rule out: same result, a quarter
of the memory traffic. The 8-bit copy adds a quarter to the memory and file size.)
Each vector has an integer id of the caller's choosing and two tags: a *kind* (``topic``,
``service``, ``action``, ...) and a *source* (robot, bag, document set); searches can be
restricted to some kinds and/or sources.

An index is saved to one file and opened memory-mapped, so opening even a million-vector
index costs milliseconds. Opening checks the header, layout, ids and tags; the vector data
is checked against its checksums once, before it is first used (or on :meth:`verify`).
A damaged, truncated or foreign file raises :class:`~skillwright.errors.FileFormatError`
naming the file and byte offset. Searches over large indexes release the GIL and use
every core.
"""

from __future__ import annotations

from collections.abc import Iterable
from os import PathLike
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skillwright import _core
from skillwright.errors import InvalidArgumentError

__all__ = ["BatchHits", "Hits", "Record", "VectorIndex"]

_INT64_MAX = np.iinfo(np.int64).max


class Hits(NamedTuple):
    """The result of one search, best first (highest cosine; ties by lower id)."""

    ids: NDArray[np.int64]
    """Ids of the hits, at most ``k`` of them."""
    scores: NDArray[np.float32]
    """Cosine similarity of each hit with the query, in ``[-1, 1]``."""


class BatchHits(NamedTuple):
    """The result of a batch search: row ``i`` holds the hits of query ``i``."""

    ids: NDArray[np.int64]
    """``(queries, k')`` ids, where ``k' = min(k, number of allowed vectors)``."""
    scores: NDArray[np.float32]
    """``(queries, k')`` cosine similarities."""


class Record(NamedTuple):
    """What the index stores for one id."""

    vector: NDArray[np.float32]
    """The vector as stored: normalised to unit length."""
    kind: str
    """Kind tag, e.g. ``topic``, ``service`` or ``action``."""
    source: str
    """Source tag, e.g. the robot or bag the interface came from."""


def _floats(values: ArrayLike, ndim: int, what: str) -> NDArray[np.float32]:
    if (
        type(values) is np.ndarray
        and values.dtype == np.float32
        and values.ndim == ndim
        and values.flags.c_contiguous
    ):
        return values  # already what the core reads in place: no copy
    array = np.asarray(values)
    if array.ndim != ndim or array.dtype.kind not in "fiu":
        shape = "a 1-D array" if ndim == 1 else "a 2-D array (one row per vector)"
        raise InvalidArgumentError(
            f"{what} must be {shape} of numbers, got shape {array.shape} of {array.dtype}"
        )
    return np.ascontiguousarray(array, dtype=np.float32)


def _ids(values: int | ArrayLike) -> NDArray[np.int64]:
    array = np.atleast_1d(np.asarray(values))
    if array.ndim != 1 or (array.size and array.dtype.kind not in "iu"):
        raise InvalidArgumentError(
            f"ids must be integers in a 1-D array, got shape {array.shape} of {array.dtype}"
        )
    if array.dtype.kind == "u" and array.size and int(array.max()) > _INT64_MAX:
        raise InvalidArgumentError(f"ids must fit in a signed 64-bit integer (max {_INT64_MAX})")
    return np.ascontiguousarray(array, dtype=np.int64)


def _tag_filter(tags: str | Iterable[str] | None) -> list[str] | None:
    if tags is None:
        return None
    return [tags] if isinstance(tags, str) else list(tags)


def _tag_arg(tags: str | Iterable[str]) -> str | list[str]:
    return tags if isinstance(tags, str) else list(tags)


class VectorIndex:
    """An exact cosine index over float32 vectors with int64 ids and kind/source tags.

    Concurrent searches from several threads are fine; a change while another thread
    searches raises ``RuntimeError`` (the index is borrowed) rather than racing.
    """

    __slots__ = ("_index",)

    def __init__(self, dim: int) -> None:
        """An empty index for vectors of dimension ``dim`` (e.g. 384 for MiniLM)."""
        self._index = _core.VectorIndex(dim)

    @classmethod
    def open(cls, path: str | PathLike[str]) -> VectorIndex:
        """Opens an index written by :meth:`save`, memory-mapped (cheap even when large).

        Raises ``InputFileNotFoundError`` if the file is missing and ``FileFormatError``
        (naming the byte offset) if it is not a valid index.
        """
        index = cls.__new__(cls)
        index._index = _core.VectorIndex.open(Path(path))
        return index

    def save(self, path: str | PathLike[str]) -> None:
        """Writes the index to ``path`` atomically (temporary file, then rename)."""
        self._index.save(Path(path))

    def verify(self) -> None:
        """Checks the vector data of an opened index against its checksums now.

        Otherwise this happens once, before the data is first used.
        """
        self._index.verify()

    @property
    def dim(self) -> int:
        """Dimension of every vector."""
        return self._index.dim

    @property
    def mapped(self) -> bool:
        """Whether the data is still read from the opened file (no change made since)."""
        return self._index.mapped

    def __len__(self) -> int:
        return len(self._index)

    def __contains__(self, id_: object) -> bool:
        if not isinstance(id_, int | np.integer):
            return False
        return int(id_) in self._index

    def __repr__(self) -> str:
        return repr(self._index)

    def ids(self) -> NDArray[np.int64]:
        """Ids of all vectors, in storage order (which changes as vectors are removed)."""
        return self._index.ids()

    def kinds(self) -> list[str]:
        """Every kind tag the index has seen."""
        return self._index.kinds()

    def sources(self) -> list[str]:
        """Every source tag the index has seen."""
        return self._index.sources()

    def get(self, id_: int) -> Record:
        """The stored vector and tags of ``id_``; ``InvalidArgumentError`` if absent."""
        vector, kind, source = self._index.get(int(id_))
        return Record(vector, kind, source)

    def add(
        self,
        ids: int | ArrayLike,
        vectors: ArrayLike,
        *,
        kind: str | Iterable[str],
        source: str | Iterable[str],
    ) -> None:
        """Adds vectors (one row each) under new ``ids``; all or nothing.

        ``kind`` and ``source`` are one tag for all rows or one per row. Float32
        C-contiguous input is read in place; other input is converted first. Raises
        ``InvalidArgumentError`` for a shape mismatch, a duplicate or existing id, or a
        vector that is zero or not finite.
        """
        matrix = _floats(vectors, 2, "vectors")
        self._index.add(_ids(ids), matrix, _tag_arg(kind), _tag_arg(source))

    def update(
        self,
        ids: int | ArrayLike,
        vectors: ArrayLike | None = None,
        *,
        kind: str | Iterable[str] | None = None,
        source: str | Iterable[str] | None = None,
    ) -> None:
        """Replaces the vectors and/or tags of existing ``ids``; all or nothing."""
        self._index.update(
            _ids(ids),
            None if vectors is None else _floats(vectors, 2, "vectors"),
            None if kind is None else _tag_arg(kind),
            None if source is None else _tag_arg(source),
        )

    def remove(self, ids: int | ArrayLike) -> None:
        """Removes ``ids``; all or nothing (``InvalidArgumentError`` if one is absent)."""
        self._index.remove(_ids(ids))

    def search(
        self,
        query: ArrayLike,
        k: int = 4,
        *,
        kinds: str | Iterable[str] | None = None,
        sources: str | Iterable[str] | None = None,
    ) -> Hits:
        """The ``k`` vectors most similar to ``query``, best first.

        ``kinds`` / ``sources`` restrict the search to vectors with those tags. Fewer
        than ``k`` hits come back when fewer vectors are allowed (none from an empty
        index). ``k < 1``, a query of another dimension, or a zero or non-finite query
        raise ``InvalidArgumentError``.
        """
        ids, scores = self._index.search(
            _floats(query, 1, "query"), k, _tag_filter(kinds), _tag_filter(sources)
        )
        return Hits(ids, scores)

    def search_batch(
        self,
        queries: ArrayLike,
        k: int = 4,
        *,
        kinds: str | Iterable[str] | None = None,
        sources: str | Iterable[str] | None = None,
    ) -> BatchHits:
        """:meth:`search` for each row of ``queries``, faster than one call per query.

        The scores equal those of single searches exactly.
        """
        ids, scores = self._index.search_batch(
            _floats(queries, 2, "queries"), k, _tag_filter(kinds), _tag_filter(sources)
        )
        return BatchHits(ids, scores)
