"""Fixtures of the pipeline tests: isolated configuration, a tiny model, a scripted model."""

from __future__ import annotations

import threading
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest

from skillwright.llm.base import GenerationOptions, Prompt, TextStream
from tests.conftest import SHIPPED_CAPABILITIES
from tests.llm.conftest import isolated_config, tiny_gguf, write_models_toml

__all__ = ["ScriptedModel", "isolated_config", "tiny_gguf"]

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"


class ScriptedModel:
    """A generator that answers with a fixed text, in chunks (tests only)."""

    def __init__(self, answer: str, *, model_id: str = "tiny", context_length: int = 10**6):
        self.answer = answer
        self.model_id = model_id
        self.context_length = context_length
        self.prompts: list[Prompt] = []
        self.closed = False

    def count_tokens(self, prompt: Prompt) -> int | None:
        return sum(len(m.content) for m in prompt.messages) // 4

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        self.prompts.append(prompt)
        stream = TextStream(iter(()), prompt_tokens=self.count_tokens(prompt))

        def chunks() -> Iterator[str]:
            for start in range(0, len(self.answer), 40):
                if cancel is not None and cancel.is_set():
                    stream.finish_reason = "cancelled"
                    return
                yield self.answer[start : start + 40]
            stream.finish_reason = "stop"

        stream.chunks = chunks()
        return stream

    def close(self) -> None:
        self.closed = True


@pytest.fixture
def models_file(tmp_path: Path, tiny_gguf: Path) -> Path:
    """A models.toml whose default generation model is the tiny GGUF (large context)."""
    return write_models_toml(tmp_path / "models.toml", tiny_gguf, context=8192)


def use_model(monkeypatch: pytest.MonkeyPatch, model: ScriptedModel) -> None:
    """Makes the pipeline load ``model`` whatever the registry says."""
    import skillwright.llm

    def load(_registry: object, _model_id: str | None = None, **_: object) -> ScriptedModel:
        return model

    monkeypatch.setattr(skillwright.llm, "load_generator", load)


def stems(events: Sequence[object], kind: type) -> list[str]:
    return [getattr(e, "stage", "") for e in events if isinstance(e, kind)]
