"""What the generation engine reports while it works (the TUI and the CLI show these).

Events are small frozen dataclasses passed to the caller's ``on_event`` callback from the
thread doing the work; a UI posts them on to its own thread.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from skillwright.generation.author import AttemptFinished, AttemptStarted

__all__ = [
    "STAGES",
    "AttemptFinished",
    "AttemptStarted",
    "Event",
    "GenerationStats",
    "Notice",
    "PrefixCacheStatus",
    "StageFinished",
    "StageStarted",
    "TokenChunk",
]

STAGES = ("inputs", "retrieval", "skeleton", "model", "generation", "checks", "outputs")
"""The stages of one generation, in order (``model`` and ``generation`` only with a model)."""


@dataclass(frozen=True)
class StageStarted:
    """A stage began."""

    stage: str
    detail: str


@dataclass(frozen=True)
class StageFinished:
    """A stage ended after ``seconds``."""

    stage: str
    seconds: float
    detail: str


@dataclass(frozen=True)
class Notice:
    """Something the user should know that is not an error (e.g. skeleton only)."""

    level: Literal["info", "warning"]
    message: str


@dataclass(frozen=True)
class PrefixCacheStatus:
    """How the prompt's fixed prefix was obtained: ``memory``, ``disk``, ``stored``,
    ``evaluated`` or ``off``."""

    status: str


@dataclass(frozen=True)
class TokenChunk:
    """Text the model just produced."""

    text: str


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
    | PrefixCacheStatus
    | TokenChunk
    | GenerationStats
    | AttemptStarted
    | AttemptFinished
)
"""Any event of the engine."""
