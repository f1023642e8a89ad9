"""Benchmark of the vector index against NumPy and FAISS (exact inner-product search).

Measures, in one run and on the same data (random unit vectors, dimension 384, k = 10):
single-query latency including the Python call (median over many queries, best of three
rounds), batch throughput (queries per second for a batch of 128), and the time to open a
saved index of the largest size (plus its first search, which verifies the vector
checksums and builds the 8-bit copy single searches start with).

NumPy: a pre-normalised matrix, ``X @ q`` and ``argpartition``; FAISS: ``IndexFlatIP`` on
the same normalised vectors (install with ``pip install -e '.[bench]'``; skipped when
missing). Both normalise the query in the timed call, as the index does.

Run: ``python bench/bench_index.py [--sizes 200,10000] [--quick]``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from skillwright._core import index_isa
from skillwright.retrieval import VectorIndex

DIM = 384
K = 10
BATCH = 128


def unit_rows(rng: np.random.Generator, n: int) -> np.ndarray:
    out = np.empty((n, DIM), dtype=np.float32)
    for start in range(0, n, 100_000):  # in chunks, to bound the temporary memory
        block = rng.standard_normal((min(100_000, n - start), DIM), dtype=np.float32)
        block /= np.linalg.norm(block, axis=1, keepdims=True)
        out[start : start + len(block)] = block
    return out


ROUNDS = 3


def median_calls_us(calls: list[Callable[[np.ndarray], Any]], queries: np.ndarray) -> list[float]:
    """Median latency of each call over ``queries``, in microseconds.

    Each call runs all queries in a block (the libraries' thread pools spin after work,
    which would slow whichever call ran next if they took turns per query); the blocks
    repeat ``ROUNDS`` times and the best median counts, so a burst of load from other
    processes on a shared machine does not decide the result.
    """
    best = [float("inf")] * len(calls)
    for _ in range(ROUNDS):
        for i, call in enumerate(calls):
            call(queries[0])  # warm up caches and lazy work
            spent = []
            for q in queries:
                start = time.perf_counter()
                call(q)
                spent.append(time.perf_counter() - start)
            best[i] = min(best[i], statistics.median(spent))
    return [b * 1e6 for b in best]


def best_rates(calls: list[Callable[[], Any]], queries: int, repeats: int) -> list[float]:
    """Best queries-per-second of each call over ``ROUNDS`` blocks of ``repeats`` runs."""
    best = [float("inf")] * len(calls)
    for _ in range(ROUNDS):
        for i, call in enumerate(calls):
            call()
            for _ in range(repeats):
                best[i] = min(best[i], timed(call))
    return [queries / b for b in best]


def timed(call: Callable[[], Any]) -> float:
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def numpy_single(matrix: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    k = min(K, len(matrix))

    def search(q: np.ndarray) -> np.ndarray:
        scores = matrix @ (q / np.linalg.norm(q))
        top = np.argpartition(-scores, k - 1)[:k]
        return top[np.argsort(-scores[top], kind="stable")]

    return search


def numpy_batch(matrix: np.ndarray, queries: np.ndarray) -> Callable[[], np.ndarray]:
    k = min(K, len(matrix))

    def search() -> np.ndarray:
        q = queries / np.linalg.norm(queries, axis=1, keepdims=True)
        scores = q @ matrix.T
        top = np.argpartition(-scores, k - 1, axis=1)[:, :k]
        order = np.argsort(-np.take_along_axis(scores, top, axis=1), axis=1, kind="stable")
        return np.take_along_axis(top, order, axis=1)

    return search


def load_faiss() -> Any:
    try:
        import faiss  # type: ignore[import-not-found]
    except ImportError:
        return None
    return faiss


def row(*cells: object) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def ratio(a: float, b: float) -> str:
    return f"{a / b:.2f}x"


def single_row(n: int, matrix: np.ndarray, ours: VectorIndex, flat: Any, count: int) -> str:
    queries = np.random.default_rng(n).standard_normal((count, DIM), dtype=np.float32)
    # The index and NumPy must agree (up to float rounding at the k-th place).
    expected = numpy_single(matrix)(queries[0])
    agree = len(set(expected.tolist()) ^ set(ours.search(queries[0], K).ids.tolist())) <= 2

    def faiss_single(q: np.ndarray) -> Any:
        return flat.search((q / np.linalg.norm(q))[None, :], K)

    calls = [lambda q: ours.search(q, K), numpy_single(matrix)]
    if flat is not None:
        calls.append(faiss_single)
    t_ours, t_numpy, t_faiss, *_ = [*median_calls_us(calls, queries), float("nan")]
    return row(
        f"{n:,}",
        f"{t_ours:,.1f}",
        f"{t_numpy:,.1f}",
        f"{t_faiss:,.1f}",
        ratio(t_numpy, t_ours),
        ratio(t_faiss, t_ours),
        "yes" if agree else "NO",
    )


def batch_row(n: int, matrix: np.ndarray, ours: VectorIndex, flat: Any) -> str:
    batch = np.random.default_rng(n + 1).standard_normal((BATCH, DIM), dtype=np.float32)
    repeats = 2 if n >= 1_000_000 else 4

    def faiss_batch() -> Any:
        return flat.search(batch / np.linalg.norm(batch, axis=1, keepdims=True), K)

    calls = [lambda: ours.search_batch(batch, K), numpy_batch(matrix, batch)]
    if flat is not None:
        calls.append(faiss_batch)
    r_ours, r_numpy, r_faiss, *_ = [*best_rates(calls, BATCH, repeats), float("nan")]
    return row(
        f"{n:,}",
        f"{r_ours:,.0f}",
        f"{r_numpy:,.0f}",
        f"{r_faiss:,.0f}",
        ratio(r_ours, r_numpy),
        ratio(r_ours, r_faiss),
    )


def open_lines(ours: VectorIndex) -> list[str]:
    queries = np.random.default_rng(7).standard_normal((2, DIM), dtype=np.float32)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.swv"
        t_save = timed(lambda: ours.save(path))
        opens = [timed(lambda: VectorIndex.open(path)) for _ in range(5)]
        opened = VectorIndex.open(path)
        t_first = timed(lambda: opened.search(queries[0], K))
        t_next = timed(lambda: opened.search(queries[1], K))
        again = VectorIndex.open(path)
        t_verify = timed(again.verify)
        size_mb = path.stat().st_size / 1e6
    return [
        f"saved index: {len(ours):,} vectors, {size_mb:,.0f} MB, saved in {t_save:.2f} s",
        f"open (memory-mapped; header, layout, ids and tags checked): "
        f"median of 5 {statistics.median(opens) * 1e3:.2f} ms",
        f"first search after open (includes verifying the vector checksums): "
        f"{t_first * 1e3:.1f} ms; next search {t_next * 1e3:.1f} ms",
        f"verify() alone after a fresh open: {t_verify * 1e3:.1f} ms",
    ]


def run_size(n: int, faiss: Any, quick: bool, with_open: bool) -> tuple[str, str, list[str]]:
    matrix = unit_rows(np.random.default_rng(0), n)
    ours = VectorIndex(DIM)
    ours.add(np.arange(n, dtype=np.int64), matrix, kind="topic", source="bench")
    flat = None
    if faiss:
        flat = faiss.IndexFlatIP(DIM)
        flat.add(matrix)
    count = 20 if n >= 1_000_000 else 100 if n >= 100_000 else 1000
    if quick:
        count = max(5, count // 10)
    return (
        single_row(n, matrix, ours, flat, count),
        batch_row(n, matrix, ours, flat),
        open_lines(ours) if with_open else [],
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--sizes", default="200,10000,100000,1000000")
    parser.add_argument("--quick", action="store_true", help="fewer queries per size")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    faiss = load_faiss()
    print(f"vector index benchmark: dim {DIM}, k {K}, batch {BATCH}, kernel {index_isa()}")
    print("FAISS: " + (f"faiss-cpu {faiss.__version__}" if faiss else "not installed, skipped"))
    singles, batches, opening = [], [], []
    for n in sizes:
        single, batch, lines = run_size(n, faiss, args.quick, n == max(sizes))
        singles.append(single)
        batches.append(batch)
        opening += lines

    print()
    print("Single query, median latency per call in microseconds (lower is better)")
    print(row("vectors", "index", "NumPy", "FAISS flat", "vs NumPy", "vs FAISS", "same top-k"))
    print(row(*["---"] * 7))
    print("\n".join(singles))
    print()
    print(f"Batch of {BATCH} queries, queries per second (higher is better)")
    print(row("vectors", "index", "NumPy", "FAISS flat", "vs NumPy", "vs FAISS"))
    print(row(*["---"] * 6))
    print("\n".join(batches))
    if opening:
        print()
        print("\n".join(opening))


if __name__ == "__main__":
    main()
