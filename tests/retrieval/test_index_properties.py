"""The index's searches equal a NumPy brute-force reference, whatever the shapes."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from skillwright.retrieval import VectorIndex

KINDS = ["topic", "service", "action"]
SOURCES = ["robot-a", "robot-b"]
TOLERANCE = 1e-5


@dataclass
class Case:
    vectors: np.ndarray
    ids: np.ndarray
    kinds: list[str]
    sources: list[str]
    queries: np.ndarray
    k: int
    kind_filter: list[str] | None
    source_filter: list[str] | None


@st.composite
def cases(draw: st.DrawFn, max_n: int = 300, min_n: int = 0, cluster: bool = False) -> Case:
    n = draw(st.integers(min_n, max_n))
    dim = draw(st.integers(1, 70))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    vectors = rng.standard_normal((n, dim)).astype(np.float32)
    if cluster and draw(st.booleans()):
        # Nearly parallel vectors: scores closer together than the 8-bit first pass of
        # large searches can tell apart.
        spread = draw(st.sampled_from([1e-1, 1e-3, 1e-5]))
        vectors = (rng.standard_normal(dim) + spread * vectors).astype(np.float32)
    if n > 1 and draw(st.booleans()):
        # Exact duplicates tie exactly; their order must then come from the ids.
        copies = rng.integers(0, n, size=n // 3)
        vectors[copies] = vectors[rng.integers(0, n)]
    ids = rng.permutation(np.arange(-n, 4 * n + 1, dtype=np.int64))[:n]
    queries = rng.standard_normal((draw(st.integers(1, 9)), dim)).astype(np.float32)
    if n and draw(st.booleans()):
        queries[0] = vectors[rng.integers(0, n)]
    return Case(
        vectors=vectors,
        ids=ids,
        kinds=[KINDS[i] for i in rng.integers(0, 3, size=n)],
        sources=[SOURCES[i] for i in rng.integers(0, 2, size=n)],
        queries=queries,
        k=draw(st.integers(1, n + 5) if n < 1000 else st.integers(1, 150)),
        kind_filter=draw(st.none() | st.lists(st.sampled_from([*KINDS, "parameter"]))),
        source_filter=draw(st.none() | st.lists(st.sampled_from(SOURCES), min_size=1)),
    )


def build(case: Case) -> VectorIndex:
    index = VectorIndex(case.vectors.shape[1])
    index.add(case.ids, case.vectors, kind=case.kinds, source=case.sources)
    return index


def allowed(case: Case) -> np.ndarray:
    mask = np.ones(len(case.ids), dtype=bool)
    if case.kind_filter is not None:
        mask &= np.isin(case.kinds, case.kind_filter)
    if case.source_filter is not None:
        mask &= np.isin(case.sources, case.source_filter)
    return mask


def check_against_reference(
    case: Case, query: np.ndarray, ids: np.ndarray, scores: np.ndarray
) -> None:
    mask = allowed(case)
    x = case.vectors[mask].astype(np.float64)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    q = query.astype(np.float64) / np.linalg.norm(query)
    reference = dict(zip(case.ids[mask].tolist(), (x @ q).tolist(), strict=True))

    assert len(ids) == min(case.k, int(mask.sum()))
    assert len(set(ids.tolist())) == len(ids)
    got = [reference[i] for i in ids.tolist()]  # KeyError: a filtered-out row came back
    np.testing.assert_allclose(scores, got, atol=TOLERANCE)
    # Best first; exact ties by lower id.
    for i in range(len(ids) - 1):
        assert scores[i] >= scores[i + 1]
        if scores[i] == scores[i + 1]:
            assert ids[i] < ids[i + 1]
    # Nothing left out scores higher than what came back.
    rest = [s for i, s in reference.items() if i not in set(ids.tolist())]
    if rest and len(ids):
        assert max(rest) <= min(got) + TOLERANCE


@settings(max_examples=150, deadline=None)
@given(cases())
def test_search_equals_numpy_reference(case: Case) -> None:
    index = build(case)
    for query in case.queries:
        hits = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        check_against_reference(case, query, hits.ids, hits.scores)


@settings(max_examples=60, deadline=None)
@given(cases())
def test_batch_search_equals_single_searches_exactly(case: Case) -> None:
    index = build(case)
    batch = index.search_batch(
        case.queries, case.k, kinds=case.kind_filter, sources=case.source_filter
    )
    assert batch.ids.shape[0] == len(case.queries)
    for row, query in enumerate(case.queries):
        single = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        np.testing.assert_array_equal(batch.ids[row], single.ids)
        np.testing.assert_array_equal(batch.scores[row], single.scores)


@settings(max_examples=40, deadline=None)
@given(cases())
def test_identical_vectors_come_back_in_id_order(case: Case) -> None:
    index = build(case)
    twins: dict[bytes, list[int]] = {}
    for row in np.flatnonzero(allowed(case)):
        twins.setdefault(case.vectors[row].tobytes(), []).append(int(case.ids[row]))
    for query in case.queries:
        hits = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        returned = set(hits.ids.tolist())
        # Of identical allowed vectors, those returned are the ones with the lowest ids.
        for ids in twins.values():
            kept = [i in returned for i in sorted(ids)]
            assert kept == sorted(kept, reverse=True), sorted(ids)


@settings(max_examples=25, deadline=None)
@given(case=cases())
def test_saved_and_opened_index_answers_the_same(
    case: Case, tmp_path_factory: pytest.TempPathFactory
) -> None:
    index = build(case)
    path: Path = tmp_path_factory.mktemp("idx") / "index.swv"
    index.save(path)
    opened = VectorIndex.open(path)
    assert opened.mapped
    np.testing.assert_array_equal(opened.ids(), index.ids())
    for query in case.queries:
        a = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        b = opened.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        np.testing.assert_array_equal(a.ids, b.ids)
        np.testing.assert_array_equal(a.scores, b.scores)


@settings(max_examples=40, deadline=None)
@given(cases(), st.data())
def test_after_removes_and_updates_search_still_equals_reference(
    case: Case, data: st.DataObject
) -> None:
    index = build(case)
    n = len(case.ids)
    if n == 0:
        return
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    gone = rng.choice(n, size=data.draw(st.integers(0, n)), replace=False)
    index.remove(case.ids[gone])
    keep = np.setdiff1d(np.arange(n), gone)
    changed = keep[: len(keep) // 2]
    new_vectors = rng.standard_normal((len(changed), case.vectors.shape[1])).astype(np.float32)
    new_kinds = [KINDS[i] for i in rng.integers(0, 3, size=len(changed))]
    index.update(case.ids[changed], new_vectors, kind=new_kinds)
    vectors = case.vectors.copy()
    vectors[changed] = new_vectors
    kinds = list(case.kinds)
    for row, kind in zip(changed, new_kinds, strict=True):
        kinds[row] = kind
    after = Case(
        vectors=vectors[keep],
        ids=case.ids[keep],
        kinds=[kinds[i] for i in keep],
        sources=[case.sources[i] for i in keep],
        queries=case.queries,
        k=case.k,
        kind_filter=case.kind_filter,
        source_filter=case.source_filter,
    )
    assert len(index) == len(keep)
    for query in case.queries:
        hits = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        check_against_reference(after, query, hits.ids, hits.scores)


@settings(max_examples=30, deadline=None)
@given(cases(min_n=2048, max_n=6000, cluster=True))
def test_large_searches_with_a_first_pass_equal_the_reference_and_the_full_scan(
    case: Case,
) -> None:
    # From 2048 allowed vectors a single search first scores 8-bit copies, then rescores;
    # a batch always scans everything in f32. Both must agree exactly.
    index = build(case)
    for query in case.queries:
        hits = index.search(query, case.k, kinds=case.kind_filter, sources=case.source_filter)
        check_against_reference(case, query, hits.ids, hits.scores)
        full = index.search_batch(
            query[None, :], case.k, kinds=case.kind_filter, sources=case.source_filter
        )
        np.testing.assert_array_equal(hits.ids, full.ids[0])
        np.testing.assert_array_equal(hits.scores, full.scores[0])
