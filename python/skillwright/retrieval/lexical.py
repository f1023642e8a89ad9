"""BM25 lexical scoring over interface documents (exact, in memory).

Used beside dense embeddings: names, types and field names of ROS interfaces are words a
small embedding model never saw together, but they match a capability's words exactly
once both are split and expanded (see :mod:`skillwright.retrieval.text`).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence

__all__ = ["BM25"]


class BM25:
    """Okapi BM25 over documents given as weighted term lists."""

    def __init__(
        self, documents: Sequence[Mapping[str, float]], k1: float = 1.2, b: float = 0.75
    ) -> None:
        self.documents = [dict(d) for d in documents]
        self.k1 = k1
        self.b = b
        self.lengths = [sum(d.values()) for d in self.documents]
        self.average = (sum(self.lengths) / len(self.lengths)) if self.lengths else 0.0
        frequency: Counter[str] = Counter()
        for document in self.documents:
            frequency.update(document.keys())
        count = len(self.documents)
        self.idf = {
            term: math.log(1.0 + (count - n + 0.5) / (n + 0.5)) for term, n in frequency.items()
        }
        # term -> (document, its saturated, length-normalised, idf-weighted frequency)
        self._postings: dict[str, list[tuple[int, float]]] = {}
        for row, (document, length) in enumerate(zip(self.documents, self.lengths, strict=True)):
            norm = k1 * (1.0 - b + b * (length / self.average if self.average else 0.0))
            for term, tf in document.items():
                value = self.idf[term] * tf * (k1 + 1.0) / (tf + norm)
                self._postings.setdefault(term, []).append((row, value))

    def scores(self, query: Mapping[str, float]) -> list[float]:
        """The score of every document for ``query`` (term -> weight)."""
        out = [0.0] * len(self.documents)
        for term, weight in query.items():
            for row, value in self._postings.get(term, ()):
                out[row] += weight * value
        return out

    def scores_many(self, queries: Sequence[Mapping[str, float]]) -> list[list[float]]:
        """:meth:`scores` for each query."""
        return [self.scores(query) for query in queries]
