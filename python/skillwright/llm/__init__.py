"""Local models: the ``models.toml`` registry, text generation and embeddings.

Every LLM and embedding call of skillwright goes through this package. Importing it is cheap:
llama-cpp-python and the embedding model load only inside the functions that use them.

- :mod:`~skillwright.llm.config` reads and merges ``models.toml``;
- :mod:`~skillwright.llm.base` is the backend contract (:class:`TextGenerator`, :class:`Prompt`,
  :class:`TextStream`, :class:`GenerationOptions`);
- :mod:`~skillwright.llm.llamacpp` runs GGUF models in-process with a prompt prefix cache;
- :mod:`~skillwright.llm.openai_http` uses an OpenAI-compatible server when one is configured;
- :mod:`~skillwright.llm.embeddings` embeds texts on the CPU with a disk cache.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import threading
    from collections.abc import Callable

    from skillwright.llm.base import (
        ChatMessage,
        GenerationOptions,
        Prompt,
        TextGenerator,
        TextStream,
    )
    from skillwright.llm.config import Registry, load_registry
    from skillwright.llm.model_lock import ModelWait

__all__ = [
    "ChatMessage",
    "GenerationOptions",
    "Prompt",
    "Registry",
    "TextGenerator",
    "TextStream",
    "load_generator",
    "load_registry",
]

# The command module ``skillwright.llm.commands`` is imported by ``skillwright --help``, which
# must not load pydantic; so the package's names are resolved on first use.
_LAZY = {
    "ChatMessage": "skillwright.llm.base",
    "GenerationOptions": "skillwright.llm.base",
    "Prompt": "skillwright.llm.base",
    "TextGenerator": "skillwright.llm.base",
    "TextStream": "skillwright.llm.base",
    "Registry": "skillwright.llm.config",
    "load_registry": "skillwright.llm.config",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def load_generator(
    registry: Registry,
    model_id: str | None = None,
    *,
    cache: Path | None = None,
    on_wait: Callable[[ModelWait], None] | None = None,
    cancel: threading.Event | None = None,
) -> TextGenerator:
    """The generation model ``model_id`` (default: the registry's), ready to stream.

    A local model is checked and loaded now, once no other generation holds it (see
    :mod:`skillwright.llm.model_lock`; ``on_wait`` hears about the wait, ``cancel`` ends it);
    a server model is not contacted until it is used.
    """
    entry = registry.generation_model(model_id)
    if entry.backend == "openai":
        from skillwright.llm.openai_http import OpenAIGenerator

        return OpenAIGenerator(entry)
    from skillwright.llm.llamacpp import load_llamacpp

    return load_llamacpp(entry, registry, cache=cache, on_wait=on_wait, cancel=cancel)
