"""Offline, provably: model load, generation and embedding with every socket refused."""

from __future__ import annotations

import socket
from pathlib import Path
from typing import Any

import pytest

from skillwright.llm import load_generator
from skillwright.llm.base import GenerationOptions, Prompt
from skillwright.llm.config import Registry
from skillwright.llm.embeddings import load_embedder


def test_load_generate_and_embed_open_no_socket(
    tiny_registry: Registry, cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    attempts: list[Any] = []

    def refuse(sock: socket.socket, address: Any) -> None:
        attempts.append(address)
        raise OSError("network disabled by the test")

    # Stricter than the suite's guard: loopback and name lookups are refused as well.
    monkeypatch.setattr(socket.socket, "connect", refuse)
    monkeypatch.setattr(socket.socket, "connect_ex", refuse)
    monkeypatch.setattr(socket, "getaddrinfo", lambda *a, **k: attempts.append(a) or [])

    generator = load_generator(tiny_registry, "tiny", cache=cache)
    text = generator.stream(Prompt.chat("hi"), GenerationOptions(max_tokens=8)).text()
    generator.close()
    vectors = load_embedder(tiny_registry, cache=cache).embed(["a velocity command topic"])

    assert text
    assert vectors.shape == (1, 384)
    assert attempts == []
