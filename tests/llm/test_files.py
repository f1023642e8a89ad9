"""Model files: missing, damaged and checksum errors name model, path and what to do."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import pytest

from skillwright.errors import ModelChecksumError, ModelFileMissingError, ModelFormatError
from skillwright.llm.config import LlamaCppModel, load_registry
from skillwright.llm.files import ChecksumCache, inspect_model_file
from tests.llm.conftest import write_models_toml


def test_missing_shipped_model_says_where_to_put_it_and_where_to_get_it(tmp_path: Path) -> None:
    registry = load_registry()
    entry = registry.generation_model()
    assert isinstance(entry, LlamaCppModel)
    with pytest.raises(ModelFileMissingError) as info:
        inspect_model_file(entry, registry, ChecksumCache(tmp_path / "sums.json"))
    message = str(info.value)
    assert "model 'qwen2.5-coder-1.5b-instruct'" in message
    assert str(registry.models_dir / "qwen2.5-coder-1.5b-instruct-q4_k_m.gguf") in message
    assert "huggingface.co/Qwen/Qwen2.5-Coder-1.5B-Instruct-GGUF" in message
    assert "SKILLWRIGHT_MODELS_DIR" in message
    assert "never downloads" in message


def test_checksum_mismatch_names_model_path_and_both_sums(tiny_gguf: Path, tmp_path: Path) -> None:
    wrong = "0" * 64
    registry = load_registry(write_models_toml(tmp_path / "models.toml", tiny_gguf, extra=""))
    entry = registry.generation_model("tiny")
    assert isinstance(entry, LlamaCppModel)
    entry = entry.model_copy(update={"sha256": wrong})
    with pytest.raises(ModelChecksumError) as info:
        inspect_model_file(entry, registry, ChecksumCache(tmp_path / "sums.json"))
    actual = hashlib.sha256(tiny_gguf.read_bytes()).hexdigest()
    assert f"model 'tiny': {tiny_gguf} has SHA-256 {actual}" in str(info.value)
    assert wrong in str(info.value)
    assert "copy the file again" in str(info.value)


def test_matching_checksum_is_verified(tiny_gguf: Path, tmp_path: Path) -> None:
    registry = load_registry(write_models_toml(tmp_path / "models.toml", tiny_gguf))
    entry = registry.generation_model("tiny")
    assert isinstance(entry, LlamaCppModel)
    entry = entry.model_copy(update={"sha256": hashlib.sha256(tiny_gguf.read_bytes()).hexdigest()})
    checked = inspect_model_file(entry, registry, ChecksumCache(tmp_path / "sums.json"))
    assert checked.checksum == "verified"
    assert checked.info.architecture == "llama"


def test_checksum_is_cached_by_size_and_mtime(tmp_path: Path) -> None:
    model = tmp_path / "m.bin"
    model.write_bytes(b"model bytes")
    cache = ChecksumCache(tmp_path / "sums.json")
    real = hashlib.sha256(b"model bytes").hexdigest()
    assert cache.sha256(model) == real
    # Plant a different sum for the same size and mtime: a cache hit must return it unhashed.
    entries = json.loads(cache.path.read_text())
    entries[str(model.resolve())]["sha256"] = "f" * 64
    cache.path.write_text(json.dumps(entries))
    assert cache.sha256(model) == "f" * 64
    stat = model.stat()
    os.utime(model, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000_000))
    assert cache.sha256(model) == real


def test_damaged_checksum_cache_only_costs_a_rehash(tmp_path: Path) -> None:
    model = tmp_path / "m.bin"
    model.write_bytes(b"abc")
    (tmp_path / "sums.json").write_text("{not json")
    assert ChecksumCache(tmp_path / "sums.json").sha256(model) == hashlib.sha256(b"abc").hexdigest()


def test_truncated_model_error_names_the_model(tiny_gguf: Path, tmp_path: Path) -> None:
    cut = tmp_path / "cut.gguf"
    cut.write_bytes(tiny_gguf.read_bytes()[:-1000])
    registry = load_registry(write_models_toml(tmp_path / "models.toml", cut))
    entry = registry.generation_model("tiny")
    assert isinstance(entry, LlamaCppModel)
    with pytest.raises(ModelFormatError, match=r"model 'tiny': .*cut\.gguf: truncated GGUF file"):
        inspect_model_file(entry, registry, ChecksumCache(tmp_path / "sums.json"))
