"""Fixtures of the model-layer tests: an isolated configuration and a tiny GGUF model."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from skillwright.llm.config import Registry, load_registry
from tests.fixtures.tiny_gguf import GENERATION_WORDS, TinyLlamaSpec, write_tiny_llama


@pytest.fixture(autouse=True)
def isolated_config(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Points every configuration and cache location into the test's own folder."""
    home = tmp_path / "home"
    monkeypatch.setenv("XDG_CONFIG_HOME", str(home / "config"))
    monkeypatch.setenv("XDG_DATA_HOME", str(home / "data"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(home / "cache"))
    monkeypatch.delenv("SKILLWRIGHT_CACHE_DIR", raising=False)
    monkeypatch.delenv("SKILLWRIGHT_MODELS", raising=False)
    monkeypatch.delenv("SKILLWRIGHT_MODELS_DIR", raising=False)
    return home


@pytest.fixture(scope="session")
def tiny_gguf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A tiny random-weight llama GGUF file (see ``tests.fixtures.tiny_gguf``), built once."""
    return write_tiny_llama(tmp_path_factory.mktemp("models") / "tiny.gguf")


@pytest.fixture(scope="session")
def wordy_gguf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The tiny model with a generation prompt's words in its vocabulary, for tests that run
    whole generations: their 14 KB prompt is then about 6,000 tokens instead of 16,000."""
    spec = TinyLlamaSpec(words=GENERATION_WORDS)
    return write_tiny_llama(tmp_path_factory.mktemp("models") / "wordy.gguf", spec)


def write_models_toml(
    path: Path, model_file: Path, *, extra: str = "", context: int = 768, max_tokens: int = 32
) -> Path:
    """A user models.toml that adds the tiny model as ``tiny`` and makes it the default."""
    path.write_text(
        f"""
[defaults]
generation = "tiny"

[[llm]]
id = "tiny"
aliases = ["t"]
file = "{model_file.as_posix()}"
context_length = {context}
batch_size = 64
threads = 1

[llm.sampling]
max_tokens = {max_tokens}
{extra}
""",
        encoding="utf-8",
    )
    return path


@pytest.fixture
def tiny_registry(tmp_path: Path, tiny_gguf: Path) -> Registry:
    """The shipped models plus ``tiny`` (the default generation model)."""
    return load_registry(write_models_toml(tmp_path / "models.toml", tiny_gguf))


@pytest.fixture
def cache(tmp_path: Path) -> Iterator[Path]:
    """A fresh cache folder."""
    folder = tmp_path / "cache"
    folder.mkdir()
    return folder


@pytest.fixture(scope="session")
def echo_gguf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wordy model with blocks that add little to the residual stream: its next token
    depends mostly on the last one, so greedy answers soon repeat themselves and prompt-lookup
    drafts are often right (and, as context still matters a little, often wrong)."""
    spec = TinyLlamaSpec(words=GENERATION_WORDS, residual_scale=0.003)
    return write_tiny_llama(tmp_path_factory.mktemp("models") / "echo.gguf", spec)
