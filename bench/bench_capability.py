"""Reading capability models: time per model, and CaSk alongside a model, cold and cached.

The alternative named for comparison is plain rdflib: parsing the capability file and
the 2.7 MB CaSk ontology into one graph, which is what a user who "just loads the
imports" would do. skillwright reads the ontology's vocabulary once and caches it.
Run with ``make bench``; needs ``../shared`` beside the repository.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "data"


def timed(function: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls, in seconds."""
    samples = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples)


def main() -> int:
    if not SHARED.is_dir():
        print(f"skipped: {SHARED} not found")
        return 0
    os.environ["SKILLWRIGHT_CACHE_DIR"] = tempfile.mkdtemp(prefix="skillwright-bench-")
    import rdflib

    from skillwright.capability import load_capability

    models = sorted((SHARED / "cap2skill" / "capability-models").glob("*.ttl"))
    cask = SHARED / "ontologies" / "cask.ttl"
    largest = max(models, key=lambda p: p.stat().st_size)

    print(f"{'what':58} {'time':>10}")
    per_model = [timed(lambda m=m: load_capability(m), 5) for m in models]
    median = statistics.median(per_model)
    print(f"{'one paper model, median of 9 (parse + extract)':58} {median * 1e3:8.1f} ms")
    print(f"{'largest model ' + largest.name:58} {max(per_model) * 1e3:8.1f} ms")

    def rdflib_both() -> None:
        graph = rdflib.Graph()
        graph.parse(largest)
        graph.parse(cask)

    baseline = timed(rdflib_both, 3)
    print(f"{'rdflib: model + cask.ttl into one graph (alternative)':58} {baseline * 1e3:8.1f} ms")
    cold = timed(lambda: load_capability(largest, ontologies=[cask]), 1)
    print(f"{'skillwright: model + cask.ttl, first run (builds cache)':58} {cold * 1e3:8.1f} ms")
    warm = timed(lambda: load_capability(largest, ontologies=[cask]), 5)
    print(f"{'skillwright: model + cask.ttl, cached vocabulary':58} {warm * 1e3:8.1f} ms")
    print(f"ratio rdflib / skillwright cached: {baseline / warm:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
