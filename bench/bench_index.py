"""Benchmark of the vector index against NumPy and FAISS (exact inner-product search).

Measures, in one run and on the same data (random unit vectors, dimension 384, k = 10):
single-query latency including the Python call (median over many queries), batch
throughput (queries per second for a batch of 128), and the time to open a saved index
of a million vectors (plus its first search, which verifies the vector checksums).

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


def median_call_us(call: Callable[[np.ndarray], Any], queries: np.ndarray) -> float:
    call(queries[0])  # warm up caches and lazy work
    times = []
    for q in queries:
        start = time.perf_counter()
        call(q)
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e6


def best_rate(call: Callable[[], Any], queries: int, repeats: int) -> float:
    call()
    best = min(timed(call) for _ in range(repeats))
    return queries / best


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="200,10000,100000,1000000")
    parser.add_argument("--quick", action="store_true", help="fewer queries per size")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    faiss = load_faiss()
    rng = np.random.default_rng(0)
    print(f"vector index benchmark: dim {DIM}, k {K}, batch {BATCH}, kernel {index_isa()}")
    print("FAISS: " + (f"faiss-cpu {faiss.__version__}" if faiss else "not installed, skipped"))
    single_rows = []
    batch_rows = []
    open_lines = []
    for n in sizes:
        matrix = unit_rows(rng, n)
        ids = np.arange(n, dtype=np.int64)
        ours = VectorIndex(DIM)
        ours.add(ids, matrix, kind="topic", source="bench")
        flat = None
        if faiss:
            flat = faiss.IndexFlatIP(DIM)
            flat.add(matrix)
        count = 20 if n >= 1_000_000 else 100 if n >= 100_000 else 2000
        if args.quick:
            count = max(5, count // 10)
        queries = rng.standard_normal((count, DIM), dtype=np.float32)

        # The three must agree (up to float rounding at the k-th place).
        check = queries[0]
        expected = numpy_single(matrix)(check)
        got = ours.search(check, K).ids
        agree = len(set(expected.tolist()) ^ set(got.tolist())) <= 2

        t_ours = median_call_us(lambda q: ours.search(q, K), queries)
        t_numpy = median_call_us(numpy_single(matrix), queries)
        t_faiss = (
            median_call_us(lambda q: flat.search((q / np.linalg.norm(q))[None, :], K), queries)
            if flat is not None
            else float("nan")
        )
        single_rows.append(
            row(
                f"{n:,}",
                f"{t_ours:,.1f}",
                f"{t_numpy:,.1f}",
                f"{t_faiss:,.1f}",
                ratio(t_numpy, t_ours),
                ratio(t_faiss, t_ours),
                "yes" if agree else "NO",
            )
        )

        batch = rng.standard_normal((BATCH, DIM), dtype=np.float32)
        repeats = 2 if n >= 1_000_000 else 5
        r_ours = best_rate(lambda: ours.search_batch(batch, K), BATCH, repeats)
        r_numpy = best_rate(numpy_batch(matrix, batch), BATCH, repeats)

        def faiss_batch() -> Any:
            q = batch / np.linalg.norm(batch, axis=1, keepdims=True)
            return flat.search(q, K)  # type: ignore[union-attr]

        r_faiss = best_rate(faiss_batch, BATCH, repeats) if flat is not None else float("nan")
        batch_rows.append(
            row(
                f"{n:,}",
                f"{r_ours:,.0f}",
                f"{r_numpy:,.0f}",
                f"{r_faiss:,.0f}",
                ratio(r_ours, r_numpy),
                ratio(r_ours, r_faiss),
            )
        )

        if n == max(sizes):
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
                open_lines = [
                    f"saved index: {n:,} vectors, {size_mb:,.0f} MB, saved in {t_save:.2f} s",
                    f"open (memory-mapped, header/ids/tags checked): "
                    f"median {statistics.median(opens) * 1e3:.2f} ms",
                    f"first search after open (verifies vector checksums): "
                    f"{t_first * 1e3:.1f} ms; next search {t_next * 1e3:.1f} ms",
                    f"verify() alone on a fresh open: {t_verify * 1e3:.1f} ms",
                ]
                del opened, again
        del ours, flat, matrix

    print()
    print("Single query, median latency per call in microseconds (lower is better)")
    print(row("vectors", "index", "NumPy", "FAISS flat", "vs NumPy", "vs FAISS", "same top-k"))
    print(row(*["---"] * 7))
    print("\n".join(single_rows))
    print()
    print(f"Batch of {BATCH} queries, queries per second (higher is better)")
    print(row("vectors", "index", "NumPy", "FAISS flat", "vs NumPy", "vs FAISS"))
    print(row(*["---"] * 6))
    print("\n".join(batch_rows))
    if open_lines:
        print()
        print("\n".join(open_lines))


if __name__ == "__main__":
    main()
