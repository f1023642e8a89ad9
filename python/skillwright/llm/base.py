"""The contract every text-generation backend keeps (llama.cpp in-process, OpenAI-style HTTP).

A backend turns a chat :class:`Prompt` into a :class:`TextStream`: an iterator of text chunks
as they arrive, so the TUI and the headless mode can show progress. The caller may stop it
between tokens by setting a :class:`threading.Event`. Structured answers ask for a JSON schema,
which the backend enforces while generating (llama.cpp grammars), not by parsing afterwards.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol, runtime_checkable

from pydantic import BaseModel, ConfigDict, Field

__all__ = [
    "ChatMessage",
    "FinishReason",
    "GenerationOptions",
    "Prompt",
    "TextGenerator",
    "TextStream",
]

FinishReason = Literal["stop", "length", "cancelled"]
"""Why a generation ended: end of answer or stop sequence, token limit, or the caller's cancel."""


@dataclass(frozen=True)
class ChatMessage:
    """One turn of a chat prompt."""

    role: Literal["system", "user", "assistant"]
    """Who speaks."""
    content: str
    """What is said."""


@dataclass(frozen=True)
class Prompt:
    """A chat prompt whose first ``prefix_messages`` turns are a fixed, reusable prefix.

    Skill prompts start with the same long text (system text, framework guide, few-shot
    examples); marking it lets the local backend evaluate it once and restore it afterwards.
    """

    messages: tuple[ChatMessage, ...]
    """All turns, prefix first."""
    prefix_messages: int = 0
    """How many leading turns are the fixed prefix (0: no prefix caching)."""
    answer_prefix: str = ""
    """The start of the answer, written for the model (e.g. a method's signature); the model
    continues it, and the stream yields only what the model adds."""

    def __post_init__(self) -> None:
        if not self.messages:
            raise ValueError("a prompt needs at least one message")
        if not 0 <= self.prefix_messages < len(self.messages):
            raise ValueError("the prefix must leave at least one message after it")

    @classmethod
    def chat(
        cls,
        user: str,
        *,
        system: str | None = None,
        prefix: Sequence[ChatMessage] = (),
        answer_prefix: str = "",
    ) -> Prompt:
        """A prompt: optional system turn and fixed turns (the cached prefix), then the question."""
        head = ((ChatMessage("system", system),) if system is not None else ()) + tuple(prefix)
        return cls(
            (*head, ChatMessage("user", user)),
            prefix_messages=len(head),
            answer_prefix=answer_prefix,
        )


class GenerationOptions(BaseModel):
    """Per-call settings; unset sampling values fall back to the model's ``models.toml`` entry."""

    model_config = ConfigDict(extra="forbid", frozen=True, use_attribute_docstrings=True)

    max_tokens: int | None = Field(default=None, gt=0)
    """Upper bound on generated tokens; prompt + this must fit the context."""
    temperature: float | None = Field(default=None, ge=0.0)
    """Sampling temperature (0: greedy)."""
    top_p: float | None = Field(default=None, gt=0.0, le=1.0)
    """Nucleus sampling mass."""
    seed: int | None = Field(default=None, ge=0)
    """Random seed."""
    stop: tuple[str, ...] = ()
    """Text that ends the answer; it is not part of the output."""
    json_schema: dict[str, Any] | None = None
    """A JSON schema the answer must follow (constrained decoding)."""
    save_prefix: bool = True
    """Save a newly evaluated prompt prefix to the disk prefix cache. ``False`` for prefixes
    used within one run only (re-ranking's per-capability prefix), which would otherwise push
    the long, costly prefixes of skill generation out of the cache."""
    prompt_lookup: bool | None = None
    """Draft tokens copied from the prompt and verify them in batches (greedy answers of a
    local model only; the answer is the same); ``None``: the model's ``models.toml``
    setting."""


@dataclass
class TextStream:
    """The chunks of one generation, iterated as they arrive, with facts known at the end."""

    chunks: Iterator[str]
    """The underlying chunk iterator (consume the stream instead)."""
    prompt_tokens: int | None = None
    """Tokens in the prompt, when the backend knows them."""
    prefix_cache: Literal["off", "memory", "disk", "stored", "evaluated"] = "off"
    """How the fixed prefix was obtained: not used, already in memory (the live context or a
    state kept from an earlier generation), restored from disk, evaluated and saved, or
    evaluated without saving."""
    reused_tokens: int | None = None
    """Leading prompt tokens whose evaluation was reused (the rest were evaluated), when the
    backend knows them."""
    finish_reason: FinishReason | None = None
    """Why generation ended; ``None`` until it has."""
    completion_chunks: int = 0
    """Text chunks produced so far."""
    completion_tokens: int | None = None
    """Tokens generated so far, when the backend reports them."""
    drafted_tokens: int | None = None
    """Tokens drafted by prompt lookup and evaluated (``None``: no drafting)."""
    accepted_tokens: int | None = None
    """Drafted tokens that greedy decoding confirmed (``None``: no drafting)."""
    started: float = field(default_factory=time.perf_counter)
    """``time.perf_counter()`` when the stream was created."""
    first_chunk_at: float | None = None
    """``time.perf_counter()`` at the first chunk."""
    finished_at: float | None = None
    """``time.perf_counter()`` when generation ended."""

    def __iter__(self) -> Iterator[str]:
        return self

    def __next__(self) -> str:
        try:
            chunk = next(self.chunks)
        except StopIteration:
            if self.finished_at is None:
                self.finished_at = time.perf_counter()
            raise
        if self.first_chunk_at is None:
            self.first_chunk_at = time.perf_counter()
        self.completion_chunks += 1
        return chunk

    def text(self) -> str:
        """Consumes the rest of the stream and returns it as one string."""
        return "".join(self)

    def close(self) -> None:
        """Stops generating now (the caller wants no more chunks); the model is free again."""
        close = getattr(self.chunks, "close", None)
        if close is not None:
            close()
        if self.finished_at is None:
            self.finished_at = time.perf_counter()

    @property
    def time_to_first_chunk(self) -> float | None:
        """Seconds from the request to the first chunk (includes prompt evaluation)."""
        return None if self.first_chunk_at is None else self.first_chunk_at - self.started


@runtime_checkable
class TextGenerator(Protocol):
    """A loaded generation model."""

    model_id: str
    """Id of the model in ``models.toml``."""
    context_length: int
    """Tokens that prompt and output share."""

    def count_tokens(self, prompt: Prompt) -> int | None:
        """Tokens the prompt takes, or ``None`` if the backend cannot tell before sending it."""
        ...

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        """Starts generating; raises :class:`~skillwright.errors.ContextOverflowError` up front
        when prompt + ``max_tokens`` exceed the context (nothing is ever truncated)."""
        ...

    def close(self) -> None:
        """Releases the model."""
        ...
