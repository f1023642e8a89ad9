"""Stage 4, retrieval: find the interfaces whose descriptions match a capability.

:class:`~skillwright.retrieval.index.VectorIndex` is the exact cosine index the stage
stores embeddings in (Rust core, memory-mapped files). Importing this package is cheap:
NumPy and the Rust extension load when one of the names below is first used.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__all__ = ["BatchHits", "Hits", "Record", "VectorIndex"]

if TYPE_CHECKING:
    from skillwright.retrieval.index import BatchHits, Hits, Record, VectorIndex


def __getattr__(name: str) -> Any:
    # Lazy re-export (PEP 562): `import skillwright.retrieval` must not import NumPy.
    if name in __all__:
        from skillwright.retrieval import index

        return getattr(index, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
