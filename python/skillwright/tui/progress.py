"""Live progress of a generation: elapsed time, the answer being written and why, tokens/s.

A generation takes minutes on a quiet machine and can take most of an hour on a loaded
one; most of it is the model writing. :class:`Progress` follows the pipeline's events and
says at any moment how long the whole run and the current stage have taken, which method
the model writes and whether it is a first answer or a repair (with the rules of the
findings the repair is asked to fix), the tokens written so far against the answer's budget,
the rate they come at, and the longest the answer can still take at that rate (it may stop
earlier: a method ends when it is complete). Only the standard library is used.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Progress", "clock_text"]


def clock_text(seconds: float) -> str:
    """``seconds`` as ``12.3 s`` under a minute, ``4:05`` under an hour, ``1:02:03`` above."""
    if seconds < 60:
        return f"{seconds:.1f} s"
    whole = int(seconds)
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


@dataclass
class _Answer:
    target: str
    number: int
    budget: int | None
    codes: tuple[str, ...]
    started: float
    first_token: float | None = None
    tokens: int = 0


class Progress:
    """What the generation is doing now, from its events (see the module docstring)."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self.started: float | None = None
        self.stage: str | None = None
        self.stage_since = 0.0
        self.answer: _Answer | None = None

    def begin(self) -> None:
        """The generation starts now."""
        self.started = self.clock()
        self.stage = None
        self.answer = None

    def end(self) -> None:
        """The generation ended (finished, failed or cancelled): nothing is running."""
        self.started = None
        self.stage = None
        self.answer = None

    def stage_started(self, stage: str) -> None:
        """A stage began."""
        self.stage = stage
        self.stage_since = self.clock()
        self.answer = None

    def answer_started(
        self, target: str, number: int, budget: int | None, codes: tuple[str, ...]
    ) -> None:
        """The model starts an answer for ``target``; ``codes``: the rules a repair fixes."""
        self.answer = _Answer(target, number, budget, codes, self.clock())

    def tokens(self, pieces: int) -> None:
        """The model wrote ``pieces`` more tokens."""
        if self.answer is None:
            return
        now = self.clock()
        if self.answer.first_token is None:
            # The first token comes after the prompt is read: the rate counts from here.
            self.answer.first_token = now
        self.answer.tokens += pieces

    def answer_ended(self) -> None:
        """The answer ended; the checks judge it next."""
        self.answer = None

    def rate(self) -> float | None:
        """Tokens per second of the current answer since its first token."""
        answer = self.answer
        if answer is None or answer.first_token is None or answer.tokens < 2:
            return None
        seconds = self.clock() - answer.first_token
        return (answer.tokens - 1) / seconds if seconds > 0 else None

    def lines(self) -> list[str]:
        """The progress in a few short lines; none when nothing runs."""
        if self.started is None:
            return []
        now = self.clock()
        head = f"elapsed {clock_text(now - self.started)}"
        if self.stage is not None:
            head += f" · {self.stage} {clock_text(now - self.stage_since)}"
        lines = [head]
        answer = self.answer
        if answer is None:
            return lines
        if answer.number == 1:
            lines.append(f"writing {answer.target} (first answer)")
        else:
            why = f" for {', '.join(answer.codes)}" if answer.codes else ""
            lines.append(f"repairing {answer.target} (answer {answer.number}){why}")
        if answer.first_token is None:
            lines.append(f"reading the prompt {clock_text(now - answer.started)}")
            return lines
        budget = f"/{answer.budget}" if answer.budget else ""
        counted = f"{answer.tokens}{budget} tokens"
        rate = self.rate()
        if rate is None:
            lines.append(counted)
            return lines
        counted += f" · {rate:.1f} tokens/s"
        if answer.budget and answer.budget > answer.tokens:
            left = (answer.budget - answer.tokens) / rate
            counted += f" · at most {clock_text(left)} more"
        lines.append(counted)
        return lines
