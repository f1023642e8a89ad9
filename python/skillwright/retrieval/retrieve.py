"""Stage 4: rank a robot's interfaces for a capability.

Two scores per interface, each scaled to [0, 1] over the candidates and then mixed: the
cosine between the capability query's embedding and the interface text's (when an
embedder is given), and BM25 between their weighted terms. Infrastructure interfaces
(logging, parameters, lifecycle plumbing) are left out unless asked for.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from skillwright.capability.model import Capability
from skillwright.interfaces.inventory import Interface, Inventory
from skillwright.retrieval.documents import describe, interface_terms, interface_text
from skillwright.retrieval.lexical import BM25
from skillwright.retrieval.query import build_query
from skillwright.spec.model import SkillSpec

__all__ = ["DENSE_WEIGHT", "Embedder", "Hit", "rank_interfaces"]

Embedder = Callable[[Sequence[str]], Sequence[Sequence[float]]]
"""Texts -> unit-length vectors (the local embedding model)."""

DENSE_WEIGHT = 0.3
"""Share of the dense score in the mix when an embedder is given."""

DUPLICATE_TYPE_FACTOR = 0.5
"""Score factor for a candidate whose type an already chosen hit has."""


@dataclass(frozen=True)
class Hit:
    """One ranked interface."""

    name: str
    kind: str
    type_name: str
    score: float
    dense: float | None
    lexical: float
    reason: str


def _scaled(values: Sequence[float]) -> list[float]:
    low, high = min(values), max(values)
    if high - low <= 1e-12:
        return [0.0 for _ in values]
    return [(v - low) / (high - low) for v in values]


def _reason(query: dict[str, float], terms: dict[str, float]) -> str:
    shared = sorted((t for t in query if t in terms), key=lambda t: -(query[t] * terms[t]))[:4]
    return f"shares {', '.join(shared)}" if shared else "semantic match only"


def _cosines(
    embed: Embedder, query: str, texts: Sequence[str], kinds: Sequence[str]
) -> list[float]:
    """Cosine of the query with every text, through the exact Rust index."""
    import numpy as np

    from skillwright.retrieval.index import VectorIndex

    vectors = np.asarray(embed([query, *texts]), dtype=np.float32)
    index = VectorIndex(vectors.shape[1])
    ids = np.arange(len(texts), dtype=np.int64)
    index.add(ids, vectors[1:], kind=list(kinds), source="inventory")
    hits = index.search(vectors[0], k=len(texts))
    cosines = [0.0] * len(texts)
    for row, score in zip(hits.ids.tolist(), hits.scores.tolist(), strict=True):
        cosines[row] = float(score)
    return cosines


def candidates(inventory: Inventory, include_infrastructure: bool = False) -> list[Interface]:
    """The interfaces retrieval may return."""
    out = []
    for interface in inventory.interfaces:
        if include_infrastructure:
            out.append(interface)
        elif interface.relevance is not None:
            if interface.relevance.relevant:
                out.append(interface)
        elif interface.infrastructure is None:
            out.append(interface)
    return out


def rank_interfaces(
    inventory: Inventory,
    capability: Capability,
    spec: SkillSpec | None = None,
    *,
    k: int = 4,
    include_infrastructure: bool = False,
    embed: Embedder | None = None,
) -> list[Hit]:
    """The ``k`` best interfaces for the capability, best first."""
    pool = candidates(inventory, include_infrastructure)
    if not pool or k <= 0:
        return []
    query = build_query(capability, spec)
    descriptions = [describe(i) for i in pool]
    documents = [interface_terms(i, d) for i, d in zip(pool, descriptions, strict=True)]
    lexical_raw = BM25(documents).scores(query.terms)
    lexical = _scaled(lexical_raw)
    dense: list[float] | None = None
    if embed is not None:
        texts = [interface_text(i, d) for i, d in zip(pool, descriptions, strict=True)]
        dense = _scaled(_cosines(embed, query.text, texts, [i.kind for i in pool]))
    hits = []
    for index, interface in enumerate(pool):
        d = dense[index] if dense is not None else None
        score = (
            lexical[index] if d is None else DENSE_WEIGHT * d + (1 - DENSE_WEIGHT) * lexical[index]
        )
        hits.append(
            Hit(
                name=interface.name,
                kind=interface.kind,
                type_name=interface.type_name,
                score=score,
                dense=d,
                lexical=lexical[index],
                reason=_reason(query.terms, documents[index]),
            )
        )
    return _diverse(hits, k)


def _diverse(hits: list[Hit], k: int) -> list[Hit]:
    """Picks ``k`` hits greedily, discounting a candidate of a type already picked.

    Robots often expose near-duplicates (``/cmd_vel`` and ``/cmd_vel_nav``, a global and a
    local costmap); a skill rarely needs both, and a second copy would push a different,
    needed interface out of the top ``k``.
    """
    remaining = sorted(hits, key=lambda h: (-h.score, h.name))
    chosen: list[Hit] = []
    while remaining and len(chosen) < k:
        taken = {h.type_name for h in chosen}
        best = max(
            remaining,
            key=lambda h: (
                h.score * (DUPLICATE_TYPE_FACTOR if h.type_name in taken else 1.0),
                -remaining.index(h),
            ),
        )
        remaining.remove(best)
        chosen.append(best)
    return chosen
