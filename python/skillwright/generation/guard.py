"""Ends a model's answer that has started to loop.

Small models at greedy decoding fall into loops: the same line or block of lines again and
again until the token limit. On two cores that wastes minutes per state, so the answer is
watched as it streams and ended as soon as it repeats itself; the attempt then counts as
failed (finish reason ``repetition``) and the repair loop tries again.
"""

from __future__ import annotations

from collections import Counter
from itertools import pairwise

__all__ = ["RepetitionGuard"]


class RepetitionGuard:
    """Watches streamed text; :meth:`feed` returns ``True`` once the text loops.

    A loop is one of: a substantial line (at least ``min_line`` characters) seen
    ``line_repeats`` times after the same line among the last ``window`` lines, or twice as
    often after any lines; a block of 2 to 8 lines repeated ``block_repeats`` times in a row,
    or twice in a row when it is ``long_block`` or more substantial lines (a short method's
    budget ends before a third copy of a long block: the model had repeated the five lines
    of an f-string twice when 320 tokens ran out); or the tail of an unbroken line that is
    one short pattern repeated (``...x = x = x = x``).
    A line alone is not enough: real code repeats ``self._stop_base()`` under each condition
    that ends a motion, and it was cut off as a loop.
    """

    def __init__(
        self,
        *,
        line_repeats: int = 4,
        window: int = 40,
        min_line: int = 12,
        block_repeats: int = 3,
        long_block: int = 4,
    ) -> None:
        self.line_repeats = line_repeats
        self.window = window
        self.min_line = min_line
        self.block_repeats = block_repeats
        self.long_block = long_block
        self.lines: list[str] = []
        self.partial = ""
        self.reason: str | None = None
        """What was repeated, once a loop was found."""

    def feed(self, chunk: str) -> bool:
        """Adds streamed text; ``True`` when the answer now loops."""
        if self.reason is not None:
            return True
        text = self.partial + chunk
        *complete, self.partial = text.split("\n")
        for line in complete:
            self.lines.append(line.rstrip())
            if self._line_loop() or self._block_loop():
                return True
        return self._tail_loop()

    def _line_loop(self) -> bool:
        recent = [line.strip() for line in self.lines[-self.window - 1 :]]
        pairs = [(before, line) for before, line in pairwise(recent) if len(line) >= self.min_line]
        for (_, line), count in Counter(pairs).items():
            if count >= self.line_repeats:
                self.reason = f"the line {line!r} {count} times"
                return True
        for line, count in Counter(line for _, line in pairs).items():
            if count >= 2 * self.line_repeats:
                self.reason = f"the line {line!r} {count} times"
                return True
        return False

    def _block_loop(self) -> bool:
        for size in range(2, 9):
            block = self.lines[-size:]
            long = size >= self.long_block and all(
                len(line.strip()) >= self.min_line for line in block
            )
            repeats = 2 if long else self.block_repeats
            needed = size * repeats
            if len(self.lines) < needed or not any(line.strip() for line in block):
                continue
            tail = self.lines[-needed:]
            if all(tail[i * size : (i + 1) * size] == block for i in range(repeats)):
                self.reason = f"a block of {size} lines {repeats} times"
                return True
        return False

    def _tail_loop(self) -> bool:
        tail = self.partial[-240:]
        for period in range(4, 61):
            reps = len(tail) // period
            if reps < 4 or period * reps < 60:
                continue
            unit = tail[-period:]
            if tail[-period * reps :] == unit * reps:
                self.reason = f"{unit!r} {reps} times in one line"
                return True
        return False
