"""The NumPy BERT encoder: the reference's vectors from the real model, clear errors otherwise.

``data/minilm_reference.npz`` holds texts and the vectors sentence-transformers computed for
them from the same model folder (written by ``bench/bench_embeddings.py --write-reference``).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from skillwright.errors import ModelFileMissingError, ModelFormatError
from skillwright.llm.bert import BertEncoder, gelu, gelu_tanh, pool
from skillwright.llm.config import load_registry
from skillwright.llm.embeddings import model_folder

REFERENCE = Path(__file__).resolve().parent / "data" / "minilm_reference.npz"


@pytest.fixture(scope="module")
def folder() -> Path:
    registry = load_registry()
    return model_folder(registry.embedding_model(), registry)


@pytest.fixture(scope="module")
def minilm(folder: Path) -> BertEncoder:
    return BertEncoder("all-minilm-l6-v2", folder)


@pytest.fixture
def copy_of(folder: Path, tmp_path: Path) -> Path:
    """The model folder with its small files copied and the weights linked, to be damaged."""
    target = tmp_path / "model"
    shutil.copytree(folder, target, ignore=shutil.ignore_patterns("model.safetensors"))
    (target / "model.safetensors").symlink_to(folder / "model.safetensors")
    return target


def edit_json(path: Path, **changes: Any) -> None:
    document = json.loads(path.read_text(encoding="utf-8"))
    if isinstance(document, dict):
        document.update(changes)
    else:
        document = changes["replace"]
    path.write_text(json.dumps(document), encoding="utf-8")


def test_vectors_equal_the_sentence_transformers_reference(minilm: BertEncoder) -> None:
    reference = np.load(REFERENCE)
    texts = [str(t) for t in reference["texts"]]
    vectors = minilm.encode(texts)
    assert len(texts) >= 25
    assert max(len(minilm._tokenizer.encode(t).ids) for t in texts) == 256  # one text is cut
    np.testing.assert_allclose(vectors, reference["vectors"], atol=1e-4)
    assert float(np.sum(vectors * reference["vectors"], axis=1).min()) >= 0.9999


def test_a_text_gets_the_same_vector_alone_or_padded_in_a_batch(minilm: BertEncoder) -> None:
    texts = ["stop", "Publishes velocity commands for the base of a mobile robot " * 3, "scan"]
    together = minilm.encode(texts)
    for text, row in zip(texts, together, strict=True):
        np.testing.assert_allclose(minilm.encode([text])[0], row, atol=1e-6)
    assert minilm.encode([]).shape == (0, 384)


def test_vectors_are_unit_length_and_similar_texts_are_closer(minilm: BertEncoder) -> None:
    vectors = minilm.encode(
        [
            "Publishes velocity commands to drive the mobile base.",
            "Sends linear and angular speed commands to move the robot.",
            "Reports the battery charge of the power supply.",
        ]
    )
    assert vectors.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(vectors, axis=1), 1.0, rtol=1e-5)
    assert vectors[0] @ vectors[1] > vectors[0] @ vectors[2] + 0.2


def test_gelu_follows_the_error_function() -> None:
    x = np.linspace(-12, 12, 4801, dtype=np.float32)
    exact = np.array([0.5 * v * (1 + math.erf(v / math.sqrt(2))) for v in x.tolist()])
    assert np.abs(gelu(x) - exact).max() < 1e-6
    assert np.abs(gelu_tanh(x) - exact).max() < 1e-3  # the tanh form is an approximation


def test_pooling_uses_only_the_unmasked_tokens() -> None:
    tokens = np.array([[[1.0, 2.0], [3.0, -4.0], [100.0, 100.0]]], dtype=np.float32)
    mask = np.array([[1.0, 1.0, 0.0]], dtype=np.float32)
    np.testing.assert_allclose(pool(tokens, mask, "mean"), [[2.0, -1.0]])
    np.testing.assert_allclose(pool(tokens, mask, "max"), [[3.0, 2.0]])
    np.testing.assert_allclose(pool(tokens, mask, "cls"), [[1.0, 2.0]])


def test_cls_pooling_named_by_the_folder_is_used(copy_of: Path, minilm: BertEncoder) -> None:
    edit_json(
        copy_of / "1_Pooling" / "config.json",
        pooling_mode_mean_tokens=False,
        pooling_mode_cls_token=True,
    )
    encoder = BertEncoder("cls", copy_of)
    assert encoder.pooling == "cls"
    assert float(encoder.encode(["odometry"])[0] @ minilm.encode(["odometry"])[0]) < 0.99


def test_the_tanh_gelu_named_by_the_config_is_used(copy_of: Path, minilm: BertEncoder) -> None:
    edit_json(copy_of / "config.json", hidden_act="gelu_new")
    encoder = BertEncoder("tanh", copy_of)
    assert encoder.config.activation == "gelu_tanh"
    ours, exact = encoder.encode(["odometry"])[0], minilm.encode(["odometry"])[0]
    assert 0.999 < float(ours @ exact) < 1.0 - 1e-9


@pytest.mark.parametrize(
    ("file", "changes", "message"),
    [
        ("config.json", {"model_type": "roberta"}, r"model_type 'roberta' is not supported"),
        ("config.json", {"hidden_act": "swish"}, r"hidden_act 'swish' is not supported"),
        ("config.json", {"num_attention_heads": 5}, r"not a multiple of num_attention_heads 5"),
        ("config.json", {"position_embedding_type": "relative_key"}, r"'relative_key'"),
        ("config.json", {"hidden_size": 240}, r"has shape \[384\], config.json implies \[240\]"),
        (
            "1_Pooling/config.json",
            {"pooling_mode_max_tokens": True},
            r"pooling pooling_mode_mean_tokens, pooling_mode_max_tokens is not supported",
        ),
        (
            "modules.json",
            {"replace": [{"type": "sentence_transformers.models.Dense", "path": "2_Dense"}]},
            r"module 'sentence_transformers.models.Dense' is not supported",
        ),
        (
            "modules.json",
            {"replace": [{"type": "sentence_transformers.models.Transformer", "path": ""}]},
            r"needs a Transformer and a Pooling module",
        ),
    ],
)
def test_an_unsupported_model_folder_is_refused_naming_the_file(
    copy_of: Path, file: str, changes: dict[str, Any], message: str
) -> None:
    edit_json(copy_of / file, **changes)
    with pytest.raises(ModelFormatError, match=message) as caught:
        BertEncoder("broken", copy_of)
    assert str(copy_of) in str(caught.value)


@pytest.mark.parametrize("missing", ["tokenizer.json", "config.json", "modules.json"])
def test_a_missing_file_of_the_folder_says_to_copy_it_again(copy_of: Path, missing: str) -> None:
    (copy_of / missing).unlink()
    with pytest.raises(ModelFileMissingError, match=rf"{missing} is missing; copy the whole"):
        BertEncoder("incomplete", copy_of)


def test_a_damaged_tokenizer_file_is_named(copy_of: Path) -> None:
    (copy_of / "tokenizer.json").write_text('{"version": "1.0"}', encoding="utf-8")
    with pytest.raises(ModelFormatError, match=r"tokenizer\.json: cannot be read"):
        BertEncoder("damaged", copy_of)
