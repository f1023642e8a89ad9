"""The NumPy MiniLM against sentence-transformers: equal vectors, load time, texts per second.

skillwright runs all-MiniLM-L6-v2 in NumPy (``skillwright.llm.bert``) so that torch,
transformers and sentence-transformers need not be installed. This benchmark holds it to the
reference implementation on the texts retrieval really embeds: every interface document of
the MR-1 recording and of the paper's robot (its full report, and the 33 interfaces with the
paper's LLM-written descriptions), every query facet of every labelled capability and spec,
and edge cases (empty, long enough to be cut at 256 tokens, non-English, symbols).

It prints the smallest cosine and the largest absolute difference between the two vectors of
each text (required: cosine >= 0.9999, difference <= 1e-4), the time from starting a fresh
process to a loaded model, and the encoding speed (best of three rounds, no cache). The
comparison needs sentence-transformers, which skillwright no longer installs; without it only
the NumPy side is measured. Install it into the venv to compare (it brings torch):
``.venv/bin/pip install sentence-transformers``.

``--write-reference FILE`` also stores about thirty of the texts with the reference vectors
(``tests/llm/data/minilm_reference.npz``, read by ``tests/llm/test_bert.py``).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the labelled sets live with the tests

ROUNDS = 3
COSINE_FLOOR = 0.9999
DIFFERENCE_CEILING = 1e-4

EDGE_CASES = [
    "",
    " ",
    "a",
    "/cmd_vel",
    "geometry_msgs/msg/Twist linear.x angular.z",
    "Grüße aus München: Fahrgeschwindigkeit der mobilen Plattform in m/s.",
    "移動ロボットの速度指令 (cmd_vel) を送信する。",
    "Скорость базы: линейная и угловая.",
    "emoji 🤖 and symbols <=> ±0.8 m/s² ∠90°",
    "UPPER CASE NAMES: NAVIGATE_TO_POSE, SLAM_TOOLBOX/SAVE_MAP",
    "velocity " * 300,
    " ".join(f"/joint_{i}/command position velocity effort" for i in range(80)),
]


def corpus() -> list[str]:
    """Interface documents and query facets of the labelled sets, then the edge cases."""
    from tests.retrieval.labelled import SETS, load_set

    from skillwright.retrieval.documents import describe, interface_text
    from skillwright.retrieval.query import build_query

    shared = (ROOT.parent / "shared" / "data").is_dir()
    texts: list[str] = []
    for name in SETS:
        if name != "mr1" and not shared:
            continue
        labelled = load_set(name)
        texts += [interface_text(i, describe(i)) for i in labelled.inventory.interfaces]
        for case in labelled.cases:
            texts += [f.text for f in build_query(case.capability, case.spec).facets]
    return [*dict.fromkeys(texts), *EDGE_CASES]


def load_seconds(code: str) -> float:
    """Wall time of a fresh interpreter that imports and loads a model, then exits."""
    started = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)
    return time.perf_counter() - started


NUMPY_LOAD = (
    "from skillwright.llm.config import load_registry\n"
    "from skillwright.llm.embeddings import load_encoder\n"
    "load_encoder(load_registry())\n"
)
REFERENCE_LOAD = (
    "from sentence_transformers import SentenceTransformer\n"
    "from skillwright.llm.config import load_registry\n"
    "from skillwright.llm.embeddings import model_folder\n"
    "registry = load_registry(); entry = registry.embedding_model()\n"
    "SentenceTransformer(str(model_folder(entry, registry)), device='cpu')\n"
)


def best_rate(encode: Any, texts: list[str]) -> tuple[float, Any]:
    """Texts per second, best of :data:`ROUNDS`, and the vectors."""
    best, vectors = float("inf"), None
    for _ in range(ROUNDS):
        started = time.perf_counter()
        vectors = encode(texts)
        best = min(best, time.perf_counter() - started)
    return len(texts) / best, vectors


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write-reference", type=Path, help="store texts and reference vectors")
    args = parser.parse_args()
    os.environ["SKILLWRIGHT_CACHE_DIR"] = tempfile.mkdtemp(prefix="skillwright-bench-")
    os.environ["HF_HUB_OFFLINE"] = "1"  # the reference must not look for updates online
    import numpy as np

    from skillwright.llm.config import load_registry
    from skillwright.llm.embeddings import load_encoder, model_folder

    texts = corpus()
    registry = load_registry()
    ours = load_encoder(registry)
    print(f"{len(texts)} texts; {ours.model_id} from {ours.folder}")
    numpy_rate, numpy_vectors = best_rate(ours.encode, texts)
    rows = [("NumPy (skillwright.llm.bert)", load_seconds(NUMPY_LOAD), numpy_rate)]
    have_reference = importlib.util.find_spec("sentence_transformers") is not None
    if not have_reference:
        print("sentence-transformers is not installed: no comparison, NumPy speed only")
    else:
        from sentence_transformers import SentenceTransformer

        folder = model_folder(registry.embedding_model(), registry)
        reference = SentenceTransformer(str(folder), device="cpu")

        def encode(batch: list[str]) -> Any:
            return reference.encode(
                batch, batch_size=ours.batch_size, normalize_embeddings=True, convert_to_numpy=True
            )

        reference_rate, reference_vectors = best_rate(encode, texts)
        rows.append(("sentence-transformers (torch)", load_seconds(REFERENCE_LOAD), reference_rate))
        cosines = np.sum(numpy_vectors * reference_vectors, axis=1)
        differences = np.abs(numpy_vectors - reference_vectors).max(axis=1)
        worst = int(np.argmin(cosines))
        print(
            f"smallest cosine {cosines.min():.7f} (text {worst}: {texts[worst][:60]!r}), "
            f"largest absolute difference {differences.max():.2e}; required >= {COSINE_FLOOR}"
            f" and <= {DIFFERENCE_CEILING}"
        )
        if args.write_reference is not None:
            chosen = sorted({*range(0, len(texts) - len(EDGE_CASES), 25), *range(-12, 0)})
            picked = [i % len(texts) for i in chosen]
            args.write_reference.parent.mkdir(parents=True, exist_ok=True)
            np.savez_compressed(
                args.write_reference,
                texts=np.array([texts[i] for i in picked]),
                vectors=reference_vectors[picked].astype(np.float32),
            )
            print(f"wrote {len(picked)} reference texts and vectors to {args.write_reference}")
    print(f"\n{'encoder':32}{'process to loaded model':>26}{'texts/s':>10}{'vs NumPy':>10}")
    for label, seconds, rate in rows:
        print(f"{label:32}{seconds:>24.2f} s{rate:>10.1f}{rate / numpy_rate:>9.2f}x")
    if have_reference and (cosines.min() < COSINE_FLOOR or differences.max() > DIFFERENCE_CEILING):
        print("FAIL: the NumPy vectors differ from the reference")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
