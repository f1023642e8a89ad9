"""Live progress of a generation: elapsed time, what is written and why, tokens/s, estimate."""

from __future__ import annotations

import pytest

from skillwright.tui.progress import Progress, clock_text


class _Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@pytest.mark.parametrize(
    ("seconds", "text"), [(3.25, "3.2 s"), (59.9, "59.9 s"), (245, "4:05"), (3723, "1:02:03")]
)
def test_a_duration_reads_as_seconds_minutes_or_hours(seconds: float, text: str) -> None:
    assert clock_text(seconds) == text


def test_a_repair_says_which_rules_it_fixes_and_its_tokens_against_the_budget() -> None:
    clock = _Clock()
    progress = Progress(clock)
    assert progress.lines() == []  # nothing runs
    progress.begin()
    clock.now += 5
    progress.stage_started("generation")
    clock.now += 2
    progress.answer_started("execute", 2, 768, ("SW301", "SW405"))
    assert progress.lines() == [
        "elapsed 7.0 s · generation 2.0 s",
        "repairing execute (answer 2) for SW301, SW405",
        "reading the prompt 0.0 s",
    ]
    clock.now += 10  # the prompt is read, then the first token comes
    progress.tokens(1)
    clock.now += 4
    progress.tokens(40)
    # 40 tokens in the 4 s after the first: 10 tokens/s, the 727 left take at most 72.7 s.
    assert progress.rate() == pytest.approx(10.0)
    assert progress.lines()[2] == "41/768 tokens · 10.0 tokens/s · at most 1:12 more"
    progress.answer_ended()
    assert progress.lines() == ["elapsed 21.0 s · generation 16.0 s"]
    progress.end()
    assert progress.lines() == []


def test_a_first_answer_says_so_and_needs_two_tokens_for_a_rate() -> None:
    clock = _Clock()
    progress = Progress(clock)
    progress.begin()
    progress.stage_started("generation")
    progress.answer_started("starting", 1, None, ())
    progress.tokens(1)
    clock.now += 1
    assert progress.rate() is None
    assert progress.lines()[1:] == ["writing starting (first answer)", "1 tokens"]
