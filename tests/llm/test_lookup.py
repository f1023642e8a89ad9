"""Prompt-lookup decoding: the drafter, and answers identical to plain greedy decoding."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from skillwright.llm import load_generator
from skillwright.llm.base import GenerationOptions, Prompt
from skillwright.llm.config import load_registry
from skillwright.llm.llamacpp import LlamaCppGenerator
from skillwright.llm.lookup import draft_from_history
from tests.llm.conftest import write_models_toml

CODE = (
    "def execute(self):\n"
    "    speed = min(self.speed, 0.5)\n"
    "    self.publisher.publish(Twist())\n"
    "    return self.speed\n"
)
REPAIR = Prompt.chat(
    f"The method below fails a check. Write it again.\n{CODE}\nFix: the speed is not clipped.",
    system="You write ROS 2 skills.",
    answer_prefix="def execute(self):\n",
)
QUESTION = Prompt.chat("Which topic moves the robot?", system="You write ROS 2 skills.")


def _generator(model_file: Path, folder: Path, *, lookup: bool) -> LlamaCppGenerator:
    extra = f"[llm.prompt_lookup]\nenabled = {str(lookup).lower()}\nmin_ngram = 1\n"
    models = write_models_toml(
        folder / f"models-{lookup}.toml", model_file, extra=extra, context=2048, max_tokens=400
    )
    generator = load_generator(load_registry(models), "tiny", cache=folder / "cache")
    assert isinstance(generator, LlamaCppGenerator)
    return generator


@pytest.fixture
def echo(echo_gguf: Path, tmp_path: Path) -> Iterator[LlamaCppGenerator]:
    generator = _generator(echo_gguf, tmp_path, lookup=True)
    yield generator
    generator.close()


def test_draft_follows_the_latest_earlier_occurrence_of_the_longest_run() -> None:
    history = [5, 1, 2, 9, 9, 7, 1, 2, 3, 4, 8, 1, 2]
    # [1, 2] occurred twice before; the later occurrence (followed by 3, 4) is copied.
    assert draft_from_history(history, max_ngram=3, min_ngram=1, size=2) == [3, 4]
    # A longer run wins over a more recent shorter one: [9, 7] only once, after [9, 9].
    assert draft_from_history([9, 7, 4, 0, 7, 5, 9, 7], max_ngram=2, min_ngram=1, size=3) == [
        4,
        0,
        7,
    ]


def test_draft_is_cut_at_the_text_so_far_and_at_its_size() -> None:
    assert draft_from_history([1, 2, 3, 1, 2], max_ngram=2, min_ngram=2, size=5) == [3, 1, 2]
    assert draft_from_history([1, 2, 3, 1, 2], max_ngram=2, min_ngram=2, size=1) == [3]
    assert draft_from_history([1, 2, 3, 1, 2], max_ngram=2, min_ngram=2, size=0) == []


def test_no_draft_without_a_recurring_run() -> None:
    assert draft_from_history([1, 2, 3, 4], max_ngram=3, min_ngram=1, size=4) == []
    # A run only shorter than min_ngram recurs.
    assert draft_from_history([1, 2, 3, 1], max_ngram=3, min_ngram=2, size=4) == []
    assert draft_from_history([7], max_ngram=3, min_ngram=1, size=4) == []


@pytest.mark.parametrize("model", ["echo_gguf", "wordy_gguf"])
@pytest.mark.parametrize("prompt", [REPAIR, QUESTION], ids=["repair", "question"])
def test_answers_are_those_of_plain_greedy_decoding(
    model: str, prompt: Prompt, tmp_path: Path, request: pytest.FixtureRequest
) -> None:
    model_file: Path = request.getfixturevalue(model)
    answers = {}
    for lookup in (False, True):
        generator = _generator(model_file, tmp_path, lookup=lookup)
        try:
            stream = generator.stream(prompt)
            answers[lookup] = (stream.text(), stream.completion_tokens, stream.finish_reason)
            drafted, accepted = stream.drafted_tokens, stream.accepted_tokens
        finally:
            generator.close()
    assert answers[True] == answers[False]
    assert drafted is not None
    assert accepted is not None
    assert drafted > accepted  # some drafts were wrong and their cache entries removed
    if model == "echo_gguf":
        assert accepted > 20  # and many were right


def test_later_answers_that_reuse_the_context_stay_identical(
    echo_gguf: Path, tmp_path: Path
) -> None:
    # Each answer leaves its tokens in the context (and a kept state) for the next prompt that
    # shares them: what a drafted answer leaves must serve it as a plain one's does.
    prompts = [
        REPAIR,
        QUESTION,
        Prompt.chat(f"{REPAIR.messages[-1].content}\nAgain.", system="You write ROS 2 skills."),
    ]
    answers: dict[bool, list[str]] = {}
    for lookup in (False, True):
        generator = _generator(echo_gguf, tmp_path, lookup=lookup)
        try:
            answers[lookup] = [generator.stream(p).text() for p in prompts]
        finally:
            generator.close()
    assert answers[True] == answers[False]


def test_stopping_early_leaves_the_context_as_plain_decoding_does(
    echo: LlamaCppGenerator,
) -> None:
    stream = echo.stream(REPAIR, GenerationOptions(max_tokens=300))
    pieces = iter(stream)
    for _ in range(60):
        next(pieces)
    stream.close()
    # The prompt and every token chosen before the last one given out, as after plain
    # decoding (whose last token is never evaluated).
    prompt = echo.count_tokens(REPAIR)
    assert echo.llama.n_tokens == prompt + 60 - 1
    again = echo.stream(REPAIR, GenerationOptions(max_tokens=300, prompt_lookup=False)).text()
    assert echo.stream(REPAIR, GenerationOptions(max_tokens=300)).text() == again


def test_stop_strings_and_limits_end_a_drafted_answer_where_a_plain_one_ends(
    echo: LlamaCppGenerator,
) -> None:
    plain = GenerationOptions(max_tokens=37, prompt_lookup=False)
    drafted = GenerationOptions(max_tokens=37)
    for options in (plain, drafted):
        stream = echo.stream(REPAIR, options)
        stream.text()
        assert (stream.completion_tokens, stream.finish_reason) == (37, "length")
    full = echo.stream(REPAIR, plain).text()
    stop = full[len(full) // 2 : len(full) // 2 + 3]
    stopped = {
        lookup: echo.stream(
            REPAIR, GenerationOptions(stop=(stop,), max_tokens=37, prompt_lookup=lookup)
        ).text()
        for lookup in (False, True)
    }
    assert stopped[True] == stopped[False] == full[: full.index(stop)]


def test_sampled_constrained_or_unasked_answers_are_not_drafted(
    echo: LlamaCppGenerator,
) -> None:
    sampled = echo.stream(REPAIR, GenerationOptions(max_tokens=20, temperature=0.7, seed=3))
    sampled.text()
    constrained = echo.stream(
        REPAIR,
        GenerationOptions(max_tokens=20, json_schema={"type": "object", "properties": {}}),
    )
    constrained.text()
    unasked = echo.stream(REPAIR, GenerationOptions(max_tokens=20, prompt_lookup=False))
    unasked.text()
    for stream in (sampled, constrained, unasked):
        assert stream.drafted_tokens is None
    drafted = echo.stream(REPAIR, GenerationOptions(max_tokens=20))
    drafted.text()
    assert drafted.drafted_tokens is not None
