"""The vector index's behaviour: arguments, errors, persistence and the GIL."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from skillwright import errors
from skillwright.retrieval import Hits, VectorIndex


def unit(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    return rng.standard_normal((n, dim)).astype(np.float32)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(42)


@pytest.fixture
def index(rng: np.random.Generator) -> VectorIndex:
    index = VectorIndex(16)
    index.add(
        np.arange(30),
        unit(rng, 30, 16),
        kind=["topic", "service", "action"] * 10,
        source=["robot-a"] * 15 + ["robot-b"] * 15,
    )
    return index


def test_importing_the_package_loads_neither_numpy_nor_the_extension() -> None:
    code = (
        "import sys, json, skillwright.retrieval\n"
        "print(json.dumps([m for m in ('numpy', 'skillwright._core') if m in sys.modules]))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert json.loads(result.stdout) == []


def test_a_stored_vector_is_its_own_best_hit_with_cosine_one(
    index: VectorIndex, rng: np.random.Generator
) -> None:
    vector = unit(rng, 1, 16)[0] * 7.5
    index.add([1000], vector[None, :], kind="action", source="robot-a")
    hits = index.search(vector, 3)
    assert hits.ids[0] == 1000
    assert hits.scores[0] == pytest.approx(1.0, abs=1e-6)
    assert hits.ids.dtype == np.int64
    assert hits.scores.dtype == np.float32


def test_vectors_are_stored_normalised(index: VectorIndex) -> None:
    record = index.get(4)
    assert np.linalg.norm(record.vector) == pytest.approx(1.0, abs=1e-6)
    assert (record.kind, record.source) == ("service", "robot-a")


@pytest.mark.parametrize(
    ("kinds", "sources", "expected"),
    [
        ("action", None, {i for i in range(30) if i % 3 == 2}),
        (["topic", "action"], None, {i for i in range(30) if i % 3 != 1}),
        (None, "robot-b", set(range(15, 30))),
        ("service", ["robot-b"], {i for i in range(15, 30) if i % 3 == 1}),
        ("parameter", None, set()),
        ([], None, set()),
    ],
)
def test_filters_restrict_hits_to_matching_tags(
    index: VectorIndex,
    rng: np.random.Generator,
    kinds: str | list[str] | None,
    sources: str | list[str] | None,
    expected: set[int],
) -> None:
    hits = index.search(unit(rng, 1, 16)[0], 100, kinds=kinds, sources=sources)
    assert set(hits.ids.tolist()) == expected


def test_k_above_the_size_returns_every_vector_and_empty_index_returns_nothing(
    index: VectorIndex, rng: np.random.Generator
) -> None:
    assert len(index.search(unit(rng, 1, 16)[0], 1000).ids) == 30
    empty = VectorIndex(16)
    hits = empty.search(unit(rng, 1, 16)[0], 4)
    assert (len(hits.ids), len(hits.scores)) == (0, 0)
    batch = empty.search_batch(unit(rng, 3, 16), 4)
    assert batch.ids.shape == (3, 0)


def test_other_dtypes_lists_and_strided_arrays_are_accepted(
    index: VectorIndex, rng: np.random.Generator
) -> None:
    query = unit(rng, 1, 16)[0]
    expected = index.search(query, 5)
    for variant in (query.astype(np.float64), query.tolist(), np.repeat(query, 2)[::2]):
        got = index.search(variant, 5)
        np.testing.assert_array_equal(got.ids, expected.ids)
    wide = np.asfortranarray(unit(rng, 4, 16).astype(np.float64))
    index.add(np.arange(100, 104, dtype=np.uint8), wide, kind="topic", source="x")
    assert 103 in index
    assert np.int64(101) in index
    assert "101" not in index


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda ix: ix.search(np.ones(15, np.float32), 3), "dimension 15"),
        (lambda ix: ix.search(np.ones(16, np.float32), 0), "k must be at least 1"),
        (lambda ix: ix.search(np.ones(16, np.float32), -2), "k must be at least 1"),
        (lambda ix: ix.search(np.zeros(16, np.float32), 3), "all zeros"),
        (lambda ix: ix.search(np.full(16, np.nan, np.float32), 3), "NaN or infinite"),
        (lambda ix: ix.search(np.ones((2, 16), np.float32), 3), "1-D array"),
        (lambda ix: ix.search_batch(np.ones((2, 8), np.float32), 3), "dimension 16"),
        (lambda ix: ix.search(np.array(["a"] * 16), 3), "of numbers"),
        (lambda ix: ix.add([0], np.ones((1, 16)), kind="t", source="s"), "already in"),
        (lambda ix: ix.add([90, 90], np.ones((2, 16)), kind="t", source="s"), "given twice"),
        (lambda ix: ix.add([90], np.ones((1, 8)), kind="t", source="s"), "expected (1, 16)"),
        (lambda ix: ix.add([90], np.ones((1, 16)), kind="", source="s"), "kind"),
        (lambda ix: ix.add([90], np.ones((1, 16)), kind=["a", "b"], source="s"), "2 kinds"),
        (lambda ix: ix.add([1.5], np.ones((1, 16)), kind="t", source="s"), "integers"),
        (lambda ix: ix.add([2**63], np.ones((1, 16)), kind="t", source="s"), "64-bit"),
        (lambda ix: ix.add([90], np.full((1, 16), np.inf), kind="t", source="s"), "id 90"),
        (lambda ix: ix.remove([3, 999]), "id 999 is not in"),
        (lambda ix: ix.update([999], kind="topic"), "id 999 is not in"),
        (lambda ix: ix.get(999), "id 999 is not in"),
    ],
)
def test_bad_arguments_raise_invalid_argument_naming_the_problem(
    index: VectorIndex, call: object, message: str
) -> None:
    assert callable(call)
    with pytest.raises(errors.InvalidArgumentError, match=re.escape(message)) as info:
        call(index)
    assert isinstance(info.value, ValueError)
    assert len(index) == 30, "a failed call changes nothing"


def test_zero_or_huge_dimension_is_refused() -> None:
    for dim in (0, -1, 1 << 20):
        with pytest.raises(errors.InvalidArgumentError, match="dimension"):
            VectorIndex(dim)


def test_remove_update_and_contains(index: VectorIndex, rng: np.random.Generator) -> None:
    index.remove([0, 29, 7])
    assert len(index) == 27
    assert 7 not in index
    assert 8 in index
    assert sorted(index.ids().tolist()) == [i for i in range(30) if i not in {0, 7, 29}]
    target = unit(rng, 1, 16)
    index.update(12, target, kind="action", source="robot-c")
    hits = index.search(target[0], 1, sources="robot-c")
    assert hits.ids.tolist() == [12]
    assert index.get(12).kind == "action"
    assert "robot-c" in index.sources()
    index.update([13], source="robot-c")
    assert set(index.search(target[0], 10, sources="robot-c").ids.tolist()) == {12, 13}


def assert_same(a: Hits, b: Hits) -> None:
    np.testing.assert_array_equal(a.ids, b.ids)
    np.testing.assert_array_equal(a.scores, b.scores)


def test_save_and_open_give_a_mapped_index_with_the_same_answers(
    index: VectorIndex, rng: np.random.Generator, tmp_path: Path
) -> None:
    path = tmp_path / "interfaces.swv"
    index.save(path)
    opened = VectorIndex.open(path)
    assert opened.mapped
    assert (opened.dim, len(opened)) == (16, 30)
    assert opened.kinds() == index.kinds()
    queries = unit(rng, 5, 16)
    for query in queries:
        assert_same(opened.search(query, 4, kinds="topic"), index.search(query, 4, kinds="topic"))
    opened.verify()
    # A change copies the data into memory; the file on disk is untouched.
    opened.add([500], queries[:1], kind="topic", source="s")
    assert not opened.mapped
    assert len(VectorIndex.open(path)) == 30
    assert [p.name for p in tmp_path.iterdir()] == ["interfaces.swv"]


def test_saving_over_the_file_an_index_was_opened_from_is_safe(
    index: VectorIndex, rng: np.random.Generator, tmp_path: Path
) -> None:
    path = tmp_path / "i.swv"
    index.save(path)
    opened = VectorIndex.open(path)
    query = unit(rng, 1, 16)[0]
    before = opened.search(query, 5)
    bigger = VectorIndex(16)
    bigger.add(np.arange(1000), unit(rng, 1000, 16), kind="topic", source="s")
    bigger.save(path)  # replaced by rename: the open map still sees the old file
    assert_same(opened.search(query, 5), before)
    assert len(VectorIndex.open(path)) == 1000


def corrupt(path: Path, offset: int) -> None:
    data = bytearray(path.read_bytes())
    data[offset] ^= 0x01
    path.write_bytes(bytes(data))


def test_damaged_files_raise_file_format_errors_naming_file_and_offset(
    rng: np.random.Generator, tmp_path: Path
) -> None:
    path = tmp_path / "i.swv"
    index = VectorIndex(384)
    index.add(np.arange(4000), unit(rng, 4000, 384), kind="topic", source="s")
    index.save(path)
    pristine = path.read_bytes()

    path.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(500))
    with pytest.raises(errors.FileFormatError, match=r"i\.swv: not a skillwright vector index"):
        VectorIndex.open(path)

    path.write_bytes(pristine[: len(pristine) // 2])
    with pytest.raises(errors.FileFormatError, match=rf"truncated.*at byte {len(pristine) // 2}"):
        VectorIndex.open(path)

    path.write_bytes(pristine)
    corrupt(path, 30)
    with pytest.raises(errors.FileFormatError, match="header checksum"):
        VectorIndex.open(path)

    # Vector data past the first checksum block is checked on first use, not on open.
    path.write_bytes(pristine)
    corrupt(path, len(pristine) - 5000)
    opened = VectorIndex.open(path)
    with pytest.raises(errors.FileFormatError, match=r"i\.swv: checksum mismatch .*at byte \d+"):
        opened.search(unit(rng, 1, 384)[0], 4)
    with pytest.raises(errors.FileFormatError):
        opened.verify()


def test_missing_file_raises_input_file_not_found(tmp_path: Path) -> None:
    with pytest.raises(errors.InputFileNotFoundError, match=r"nope\.swv: no such file"):
        VectorIndex.open(tmp_path / "nope.swv")


def test_long_searches_let_other_python_threads_run(rng: np.random.Generator) -> None:
    index = VectorIndex(128)
    index.add(np.arange(60_000), unit(rng, 60_000, 128), kind="topic", source="s")
    queries = unit(rng, 64, 128)
    index.search_batch(queries, 4)  # warm up
    ticks = 0
    done = threading.Event()

    def search() -> None:
        for _ in range(3):
            index.search_batch(queries, 4)
        done.set()

    worker = threading.Thread(target=search)
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0)
    worker.join()
    # Had the search held the GIL, this thread could not have looped while it ran.
    assert ticks > 20
