"""Embeddings with the real all-MiniLM-L6-v2 (from its PyPI package) and the disk cache."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from skillwright.errors import ModelFileMissingError
from skillwright.llm.config import EmbeddingModel, Registry, load_registry
from skillwright.llm.embeddings import (
    Embedder,
    EmbeddingCache,
    Encoder,
    SentenceTransformerEncoder,
    load_embedder,
    model_folder,
)

TEXTS = [
    "Publishes velocity commands to drive the mobile base.",
    "Sends linear and angular speed commands to move the robot.",
    "Reports the battery charge of the power supply.",
]


@pytest.fixture(scope="module")
def minilm() -> SentenceTransformerEncoder:
    registry = load_registry()
    entry = registry.embedding_model()
    return SentenceTransformerEncoder(entry.id, model_folder(entry, registry))


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


def test_vectors_are_normalised_and_similar_texts_are_closer(
    minilm: SentenceTransformerEncoder,
) -> None:
    vectors = minilm.encode(TEXTS)
    assert vectors.shape == (3, 384)
    assert vectors.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(vectors, axis=1), 1.0, rtol=1e-5)
    similarity = vectors @ vectors.T
    assert similarity[0, 1] > similarity[0, 2] + 0.2


def test_second_run_over_the_same_texts_computes_nothing(
    minilm: SentenceTransformerEncoder, tmp_path: Path
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
    minilm: SentenceTransformerEncoder, tmp_path: Path
) -> None:
    counting = CountingEncoder(minilm)
    embedder = Embedder(counting, EmbeddingCache(tmp_path / "e.sqlite"))
    embedder.embed(TEXTS[:2])
    vectors = embedder.embed([TEXTS[2], TEXTS[0], TEXTS[2]])
    assert counting.calls == [TEXTS[:2], [TEXTS[2]]]
    assert (embedder.last.texts, embedder.last.cached, embedder.last.computed) == (3, 1, 1)
    np.testing.assert_array_equal(vectors[0], vectors[2])
    np.testing.assert_allclose(vectors, minilm.encode([TEXTS[2], TEXTS[0], TEXTS[2]]), atol=1e-5)


def test_cache_is_keyed_by_model_id(minilm: SentenceTransformerEncoder, tmp_path: Path) -> None:
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


def test_missing_package_says_how_to_install_it(tmp_path: Path) -> None:
    registry = load_registry()
    entry = EmbeddingModel(id="ghost", package="no-such-embedding-package")
    with pytest.raises(ModelFileMissingError, match=r"'ghost': Python package .* is not installed"):
        model_folder(entry, registry)


def test_missing_model_folder_names_it(tmp_path: Path) -> None:
    registry: Registry = load_registry()
    entry = EmbeddingModel(id="local", path=tmp_path / "nothing")
    with pytest.raises(ModelFileMissingError, match=r"'local': no sentence-transformers model in"):
        model_folder(entry, registry)
