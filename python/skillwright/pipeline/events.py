"""What the generation engine reports while it works (the TUI and the CLI show these).

Events are small frozen dataclasses passed to the caller's ``on_event`` callback from the
thread doing the work; a UI posts them on to its own thread.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

from skillwright.generation.author import AttemptFinished, AttemptStarted

__all__ = [
    "STAGES",
    "AttemptFinished",
    "AttemptStarted",
    "ChunkBatcher",
    "Event",
    "GenerationStats",
    "ModelWaiting",
    "Notice",
    "PrefixCacheStatus",
    "StageFinished",
    "StageStarted",
    "TokenChunk",
]

STAGES = (
    "inputs",
    "retrieval",
    "skeleton",
    "model",
    "generation",
    "checks",
    "run",
    "simulate",
    "outputs",
)
"""The stages of one generation, in order (``model`` and ``generation`` only with a model,
``run`` and ``simulate`` only when the static checks found no error and not turned off)."""


@dataclass(frozen=True)
class StageStarted:
    """A stage began."""

    stage: str
    detail: str


@dataclass(frozen=True)
class StageFinished:
    """A stage ended after ``seconds``; ``verdict`` is its
    :class:`~skillwright.pipeline.verdict.Verdict`'s word (a stage without a check of its
    own passed when it ended)."""

    stage: str
    seconds: float
    detail: str
    verdict: str = "passed"


@dataclass(frozen=True)
class Notice:
    """Something the user should know that is not an error (e.g. skeleton only)."""

    level: Literal["info", "warning"]
    message: str


@dataclass(frozen=True)
class ModelWaiting:
    """The model is in use by another generation (another process or thread) and this one
    waits for it (:mod:`skillwright.llm.model_lock`); sent every half second while it does."""

    model: str
    """The model's id."""
    place: int
    """1: next to get the model; 2: one more waiter before this one; ..."""
    seconds: float
    """How long this generation has waited."""
    holder: str | None
    """What the holder said it is doing (pid, command, skill, stage, tokens), if it said."""
    message: str
    """All of it in one line."""


@dataclass(frozen=True)
class PrefixCacheStatus:
    """How the prompt's fixed prefix was obtained: ``memory``, ``disk``, ``stored``,
    ``evaluated`` or ``off``."""

    status: str


@dataclass(frozen=True)
class TokenChunk:
    """Text the model just produced, in ``pieces`` chunks of its stream (one token each for
    llama.cpp; :class:`ChunkBatcher` joins several into one event)."""

    text: str
    pieces: int = 1


@dataclass(frozen=True)
class GenerationStats:
    """Totals of the model's answer."""

    prompt_tokens: int | None
    completion_tokens: int | None
    tokens_per_second: float | None
    seconds: float


Event = (
    StageStarted
    | StageFinished
    | Notice
    | ModelWaiting
    | PrefixCacheStatus
    | TokenChunk
    | GenerationStats
    | AttemptStarted
    | AttemptFinished
)
"""Any event of the engine."""


class ChunkBatcher:
    """Passes events on to ``send``, joining the model's text chunks into one per
    ``interval`` seconds.

    A small model writes hundreds of chunks a second; a UI that redraws for each falls behind
    on a busy machine, and the keys the user presses wait behind the queued text. Other events
    go on at once, after the text that came before them. Call :meth:`flush` when the work ends.
    """

    def __init__(
        self,
        send: Callable[[object], None],
        interval: float = 0.05,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.send = send
        self.interval = interval
        self.clock = clock
        self.pending: list[str] = []
        self.pieces = 0
        self.sent_at: float | None = None

    def __call__(self, event: object) -> None:
        if isinstance(event, TokenChunk):
            self.pending.append(event.text)
            self.pieces += event.pieces
            now = self.clock()
            if self.sent_at is None or now - self.sent_at >= self.interval:
                self.sent_at = now
                self.flush()
            return
        self.flush()
        self.send(event)

    def flush(self) -> None:
        """Sends the text held back, if any."""
        if self.pending:
            text, pieces = "".join(self.pending), self.pieces
            self.pending.clear()
            self.pieces = 0
            self.send(TokenChunk(text, pieces))
