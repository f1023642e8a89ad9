"""Several answers to one prompt: sampled together where the backend batches, else in turn.

Best-of-N generation asks for N answers to the same request, each with its own temperature
and seed. A local llama.cpp model decodes them as N sequences of one context that share the
prompt's evaluated cache, one token of every live sequence per ``llama_decode`` call: on a
CPU whose decoding is bound by reading the weights, N sequences cost far less than N times
one (the weights are read once per step, for all of them). A backend that cannot batch (an
OpenAI-compatible server, a scripted model in the tests) answers the same call one stream
after another, so the caller never needs to know which it has.
"""

from __future__ import annotations

import functools
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal, Protocol, runtime_checkable

from skillwright.llm.base import GenerationOptions, Prompt, TextGenerator

__all__ = ["BatchAnswer", "BatchFinish", "BatchGenerator", "ChunkSink", "generate_each"]

BatchFinish = Literal["stop", "length", "cancelled", "stopped"]
"""Why a sequence ended: :data:`~skillwright.llm.base.FinishReason`, or ``"stopped"`` by its
chunk sink."""

ChunkSink = Callable[[int, str], bool]
"""Called with a sequence's index and its next piece of text; ``True`` stops that sequence
(its answer then ends with finish reason ``"stopped"``) while the others go on."""


@dataclass(frozen=True)
class BatchAnswer:
    """One sequence's answer."""

    text: str
    """The completion, without the stop string that ended it."""
    finish_reason: BatchFinish | None
    """``"stop"`` (a stop string or the end of text), ``"length"`` (``max_tokens``),
    ``"cancelled"``, ``"stopped"`` (the chunk sink asked for it); ``None`` if unknown."""
    prompt_tokens: int | None
    """Tokens in the prompt, when the backend knows them."""
    reused_tokens: int | None
    """Leading prompt tokens served from the prefix cache, when the backend knows them."""
    completion_tokens: int | None
    """Tokens generated for this sequence (text chunks where tokens are unknown)."""
    seconds: float
    """Wall time of the whole call: batched sequences finish together, so every answer of
    one batch carries the batch's time; answered in turn, each its own."""
    prefix_cache: str = "off"
    """How the prompt's fixed prefix was obtained (see
    :attr:`~skillwright.llm.base.TextStream.prefix_cache`)."""


@runtime_checkable
class BatchGenerator(Protocol):
    """A generator that decodes several sequences of one prompt in one batch."""

    max_sequences: int
    """The most sequences one call may ask for (the context was made for that many)."""

    def generate_batch(
        self,
        prompt: Prompt,
        options: Sequence[GenerationOptions],
        *,
        on_chunk: ChunkSink | None = None,
        cancel: threading.Event | None = None,
    ) -> list[BatchAnswer]:
        """One answer per entry of ``options`` (its temperature, seed, ``max_tokens`` and
        stop strings), in order; raises :class:`ValueError` for more than
        :attr:`max_sequences` and :class:`~skillwright.errors.ContextOverflowError` when the
        prompt and every sequence's ``max_tokens`` do not fit the context."""
        ...


def generate_each(
    generator: TextGenerator,
    prompt: Prompt,
    options: Sequence[GenerationOptions],
    *,
    on_chunk: ChunkSink | None = None,
    cancel: threading.Event | None = None,
) -> list[BatchAnswer]:
    """One answer per entry of ``options``, in order: in batches when ``generator`` batches
    (one batch when they fit its width, else batches of its width one after another, the
    chunk sink told each answer's index among all ``options``), else each answer streamed in
    turn (the same answers, one after another). A cancel ends the answers: those not started
    are left out."""
    if not options:
        return []
    if isinstance(generator, BatchGenerator) and generator.max_sequences > 0:
        return _in_batches(generator, prompt, options, on_chunk=on_chunk, cancel=cancel)
    answers = []
    for index, option in enumerate(options):
        started = time.perf_counter()
        stream = generator.stream(prompt, option, cancel=cancel)
        parts: list[str] = []
        stopped = False
        for chunk in stream:
            parts.append(chunk)
            if on_chunk is not None and on_chunk(index, chunk):
                stopped = True
                stream.close()
                break
        answers.append(
            BatchAnswer(
                text="".join(parts),
                finish_reason="stopped" if stopped else stream.finish_reason,
                prompt_tokens=stream.prompt_tokens,
                reused_tokens=stream.reused_tokens,
                completion_tokens=stream.completion_tokens or stream.completion_chunks,
                seconds=round(time.perf_counter() - started, 3),
                prefix_cache=stream.prefix_cache,
            )
        )
        if cancel is not None and cancel.is_set():
            break
    return answers


def _in_batches(
    generator: BatchGenerator,
    prompt: Prompt,
    options: Sequence[GenerationOptions],
    *,
    on_chunk: ChunkSink | None,
    cancel: threading.Event | None,
) -> list[BatchAnswer]:
    """``options`` in batches of at most ``generator.max_sequences``."""
    width = generator.max_sequences
    answers: list[BatchAnswer] = []
    for start in range(0, len(options), width):
        sink = None
        if on_chunk is not None:
            sink = functools.partial(_shifted, on_chunk, start)
        answers += generator.generate_batch(
            prompt, options[start : start + width], on_chunk=sink, cancel=cancel
        )
        if cancel is not None and cancel.is_set():
            break
    return answers


def _shifted(on_chunk: ChunkSink, offset: int, index: int, text: str) -> bool:
    return on_chunk(offset + index, text)
