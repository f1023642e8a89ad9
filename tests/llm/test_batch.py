"""Several answers to one prompt: batched on the tiny GGUF model, in turn on a scripted one."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path

import llama_cpp
import pytest

from skillwright.errors import ContextOverflowError, InvalidArgumentError, ModelError
from skillwright.llm import load_generator
from skillwright.llm.base import GenerationOptions, Prompt, TextStream
from skillwright.llm.batch import BatchAnswer, BatchGenerator, ChunkSink, generate_each
from skillwright.llm.config import Registry, load_registry
from skillwright.llm.llamacpp import LlamaCppGenerator
from tests.fixtures.scripted import MethodScript
from tests.llm.conftest import write_models_toml

QUESTION = Prompt.chat("Which topic moves the robot?", system="You write ROS 2 skills.")
GREEDY = GenerationOptions(max_tokens=24, temperature=0.0)


def sampled(seed: int, max_tokens: int = 24) -> GenerationOptions:
    return GenerationOptions(max_tokens=max_tokens, temperature=1.0, seed=seed)


@pytest.fixture
def tiny(tiny_registry: Registry, cache: Path) -> Iterator[LlamaCppGenerator]:
    generator = load_generator(tiny_registry, "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    yield generator
    generator.close()


def streamed(generator: LlamaCppGenerator, options: GenerationOptions) -> str:
    return generator.stream(QUESTION, options).text()


# --- the llama.cpp batch -------------------------------------------------------------------


def test_llama_cpp_generator_batches_as_wide_as_models_toml_says(
    tiny: LlamaCppGenerator,
) -> None:
    assert isinstance(tiny, BatchGenerator)
    assert tiny.max_sequences == 4  # batch_sequences' default
    assert tiny.generate_batch(QUESTION, []) == []


def test_greedy_sequences_answer_what_stream_answers(tiny: LlamaCppGenerator) -> None:
    alone = streamed(tiny, GREEDY)
    answers = tiny.generate_batch(QUESTION, [GREEDY, sampled(1), GREEDY, sampled(2)])
    assert len(answers) == 4
    assert answers[0].text == answers[2].text == alone
    assert answers[0].finish_reason == "length"
    assert answers[0].completion_tokens == 24
    assert answers[0].prompt_tokens == tiny.count_tokens(QUESTION)
    # One batch, one wall time for every answer.
    assert len({answer.seconds for answer in answers}) == 1


def test_longer_greedy_answers_beside_sampled_ones_stay_those_of_stream(
    tiny_gguf: Path, tmp_path: Path, cache: Path
) -> None:
    registry = load_registry(
        write_models_toml(tmp_path / "models.toml", tiny_gguf, context=1024, max_tokens=160)
    )
    generator = load_generator(registry, "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    try:
        for number in range(3):
            prompt = Prompt.chat(f"Question {number}: which topic?", system="You write skills.")
            alone = generator.stream(prompt, GenerationOptions(temperature=0.0)).text()
            options = [GenerationOptions(temperature=0.0), *(sampled(s, 160) for s in range(3))]
            answers = generator.generate_batch(prompt, options)
            assert answers[0].text == alone
    finally:
        generator.close()


def test_seeds_are_honoured_per_sequence(tiny: LlamaCppGenerator) -> None:
    answers = tiny.generate_batch(QUESTION, [sampled(7), sampled(8), sampled(7), sampled(9)])
    texts = [answer.text for answer in answers]
    assert texts[0] == texts[2]  # the same seed, the same answer
    assert len({texts[0], texts[1], texts[3]}) == 3  # other seeds, other answers
    assert texts[0] != streamed(tiny, GREEDY)
    # A sequence samples what stream() samples with the same temperature and seed.
    assert texts[1] == streamed(tiny, sampled(8))


def test_the_same_batch_twice_gives_the_same_answers(tiny: LlamaCppGenerator) -> None:
    options = [sampled(3), GREEDY, sampled(4)]
    first = [answer.text for answer in tiny.generate_batch(QUESTION, options)]
    second = [answer.text for answer in tiny.generate_batch(QUESTION, options)]
    assert first == second


def test_chunk_sink_stops_one_sequence_while_the_others_go_on(tiny: LlamaCppGenerator) -> None:
    alone = streamed(tiny, GREEDY)
    seen: dict[int, list[str]] = {}

    def sink(index: int, text: str) -> bool:
        seen.setdefault(index, []).append(text)
        return index == 1 and len(seen[index]) == 2

    answers = tiny.generate_batch(QUESTION, [GREEDY, GREEDY, GREEDY], on_chunk=sink)
    assert [answer.finish_reason for answer in answers] == ["length", "stopped", "length"]
    assert answers[1].text == "".join(seen[1])  # what the sink was shown, and no more
    assert alone.startswith(answers[1].text)
    assert len(answers[1].text) < len(alone)
    assert answers[1].completion_tokens is not None
    assert answers[1].completion_tokens < 24
    assert answers[0].text == answers[2].text == alone
    assert "".join(seen[0]) == alone  # every piece of text passed through the sink


def test_stop_strings_end_each_sequence_before_them(tiny: LlamaCppGenerator) -> None:
    chunks = [chunk for chunk in tiny.stream(QUESTION, GREEDY) if chunk]
    full = "".join(chunks)
    # Only a single chunk is sure to be contiguous in the random model's bytes (see
    # test_llamacpp): stop on the third one.
    stop = chunks[2]
    stopping = GenerationOptions(max_tokens=24, temperature=0.0, stop=(stop,))
    answers = tiny.generate_batch(QUESTION, [stopping, GREEDY])
    assert answers[0].text == full[: full.index(stop)]
    assert answers[0].finish_reason == "stop"
    assert answers[1].text == full
    assert answers[1].finish_reason == "length"


def test_max_tokens_is_per_sequence(tiny: LlamaCppGenerator) -> None:
    limits = [3, 17, 8]
    options = [GenerationOptions(max_tokens=n, temperature=0.0) for n in limits]
    answers = tiny.generate_batch(QUESTION, options)
    assert [answer.completion_tokens for answer in answers] == limits
    assert {answer.finish_reason for answer in answers} == {"length"}
    default = tiny.generate_batch(QUESTION, [GenerationOptions(temperature=0.0)])
    assert default[0].completion_tokens == 32  # sampling.max_tokens of the test models.toml


def test_cancel_ends_every_sequence_and_leaves_the_model_usable(
    tiny: LlamaCppGenerator,
) -> None:
    alone = streamed(tiny, GREEDY)
    cancel = threading.Event()
    shown: list[tuple[int, str]] = []

    def sink(index: int, text: str) -> bool:
        shown.append((index, text))
        if len(shown) == 5:
            cancel.set()  # as the TUI's Esc would, while a chunk is handled
        return False

    options = [GenerationOptions(max_tokens=40, temperature=0.0)] * 3
    answers = tiny.generate_batch(QUESTION, options, on_chunk=sink, cancel=cancel)
    assert [answer.finish_reason for answer in answers] == ["cancelled"] * 3
    assert all(answer.completion_tokens is not None for answer in answers)
    assert max(answer.completion_tokens or 0 for answer in answers) <= 3
    assert streamed(tiny, GREEDY) == alone


def test_cancel_before_the_batch_decodes_nothing(tiny: LlamaCppGenerator) -> None:
    cancel = threading.Event()
    cancel.set()
    answers = tiny.generate_batch(QUESTION, [GREEDY, GREEDY], cancel=cancel)
    assert [(a.text, a.finish_reason, a.completion_tokens) for a in answers] == [
        ("", "cancelled", 0)
    ] * 2


def test_more_sequences_than_the_context_was_made_for_are_refused(
    tiny: LlamaCppGenerator,
) -> None:
    with pytest.raises(InvalidArgumentError) as info:
        tiny.generate_batch(QUESTION, [GREEDY] * 5)
    message = str(info.value)
    assert "5 answers asked for in one batch" in message
    assert "made for at most 4" in message
    assert "`batch_sequences = 5` for 'tiny' in your models.toml" in message
    # The model was not touched: it still answers.
    assert tiny.generate_batch(QUESTION, [GREEDY])[0].completion_tokens == 24


def test_answers_that_do_not_fit_the_context_together_are_refused(
    tiny: LlamaCppGenerator,
) -> None:
    used = tiny.count_tokens(QUESTION)
    # Each fits beside the prompt (768 tokens), but four of them do not fit its cells.
    long = GenerationOptions(max_tokens=600)
    assert used + 600 <= tiny.context_length
    with pytest.raises(ContextOverflowError) as info:
        tiny.generate_batch(QUESTION, [long] * 4)
    message = str(info.value)
    assert f"the prompt takes {used} tokens and 4 answers of up to 600" in message
    assert f"{used + 2400} in all, but the context has room for {tiny.llama.n_ctx()}" in message
    with pytest.raises(ContextOverflowError, match="but the context holds 768"):
        tiny.generate_batch(QUESTION, [GenerationOptions(max_tokens=700)])


def test_a_batch_while_a_stream_is_open_is_refused(tiny: LlamaCppGenerator) -> None:
    first = tiny.stream(QUESTION, GenerationOptions(max_tokens=10))
    next(first)
    with pytest.raises(ModelError, match="already generating"):
        tiny.generate_batch(QUESTION, [GREEDY])
    first.text()


def test_stream_and_its_prefix_reuse_still_work_after_a_batch(tiny: LlamaCppGenerator) -> None:
    other = Prompt.chat("Which service resets it?", system="You write ROS 2 skills.")
    before = tiny.stream(other, GREEDY).text()
    tiny.generate_batch(QUESTION, [GREEDY, sampled(1), sampled(2), sampled(3)])
    after = tiny.stream(other, GREEDY)
    assert after.text() == before
    assert after.prefix_cache == "memory"  # the system turn, shared with the batch's prompt
    assert after.reused_tokens is not None
    assert after.reused_tokens > 0
    # The batch's extra sequences are gone from the cache; the prompt alone is sequence 0.
    tiny.generate_batch(QUESTION, [GREEDY, sampled(1), sampled(2)])
    memory = tiny.llama._ctx.memory
    assert llama_cpp.llama_memory_seq_pos_max(memory, 0) == tiny.count_tokens(QUESTION) - 1
    assert [llama_cpp.llama_memory_seq_pos_max(memory, seq) for seq in (1, 2, 3)] == [-1] * 3
    assert tiny.llama.n_tokens == tiny.count_tokens(QUESTION)


def test_batch_reuses_and_fills_the_disk_prefix_cache(tiny_registry: Registry, cache: Path) -> None:
    options = [GREEDY, sampled(5)]
    first = load_generator(tiny_registry, "tiny", cache=cache)
    assert isinstance(first, LlamaCppGenerator)
    try:
        stored = first.generate_batch(QUESTION, options)
    finally:
        first.close()
    again = load_generator(tiny_registry, "tiny", cache=cache)
    assert isinstance(again, LlamaCppGenerator)
    try:
        restored = again.generate_batch(QUESTION, options)
        alone = streamed(again, GREEDY)
    finally:
        again.close()
    assert {answer.prefix_cache for answer in stored} == {"stored"}
    assert {answer.prefix_cache for answer in restored} == {"disk"}
    assert restored[0].reused_tokens is not None
    assert restored[0].reused_tokens > 0
    assert [a.text for a in restored] == [a.text for a in stored]
    assert restored[0].text == alone


def test_a_json_schema_constrains_its_sequence_only(tiny: LlamaCppGenerator) -> None:
    schema = {
        "type": "object",
        "properties": {"relevant": {"type": "boolean"}},
        "required": ["relevant"],
        "additionalProperties": False,
    }
    constrained = GenerationOptions(max_tokens=60, temperature=0.0, json_schema=schema)
    answers = tiny.generate_batch(QUESTION, [constrained, GREEDY])
    assert isinstance(json.loads(answers[0].text)["relevant"], bool)
    assert answers[1].text == streamed(tiny, GREEDY)


def test_one_sequence_context_when_models_toml_says_so(
    tiny_gguf: Path, tmp_path: Path, cache: Path
) -> None:
    toml = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    text = toml.read_text(encoding="utf-8").replace(
        "threads = 1\n", "threads = 1\nbatch_sequences = 1\n"
    )
    toml.write_text(text, encoding="utf-8")
    generator = load_generator(load_registry(toml), "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    try:
        assert generator.max_sequences == 1
        assert generator.llama.n_ctx() == 768
        with pytest.raises(InvalidArgumentError, match="made for at most 1"):
            generator.generate_batch(QUESTION, [GREEDY, GREEDY])
        answers = generate_each(generator, QUESTION, [GREEDY, sampled(1)])
        assert [a.text for a in answers] == [
            streamed(generator, GREEDY),
            streamed(generator, sampled(1)),
        ]
    finally:
        generator.close()


def test_the_room_for_answers_stops_at_the_trained_context(
    tiny_gguf: Path, tmp_path: Path, cache: Path, caplog: pytest.LogCaptureFixture
) -> None:
    # The tiny model was trained with 8192 tokens; 8000 + 3 * 100 more cells would pass it.
    registry = load_registry(
        write_models_toml(tmp_path / "models.toml", tiny_gguf, context=8000, max_tokens=100)
    )
    generator = load_generator(registry, "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    try:
        assert generator.llama.n_ctx() == 8192
        assert not any("n_ctx_train" in record.getMessage() for record in caplog.records)
        answers = generator.generate_batch(QUESTION, [GREEDY] * 4)
        assert [a.completion_tokens for a in answers] == [24] * 4
    finally:
        generator.close()


def test_generate_each_batches_a_batching_generator(tiny: LlamaCppGenerator) -> None:
    answers = generate_each(tiny, QUESTION, [GREEDY, sampled(1)])
    assert len({answer.seconds for answer in answers}) == 1  # one batch
    assert answers[0].text == streamed(tiny, GREEDY)


def test_generate_each_batches_beyond_the_batch_width_in_turn(tiny: LlamaCppGenerator) -> None:
    options = [sampled(seed) for seed in range(5)]
    shown: dict[int, str] = {}

    def sink(index: int, text: str) -> bool:
        shown[index] = shown.get(index, "") + text
        return False

    answers = generate_each(tiny, QUESTION, options, on_chunk=sink)
    assert [a.text for a in answers] == [streamed(tiny, option) for option in options]
    assert len({a.seconds for a in answers[:4]}) == 1  # a batch of 4, then one of 1
    assert shown == {index: answer.text for index, answer in enumerate(answers) if answer.text}


# --- answers in turn (a generator that cannot batch) ------------------------------------------


SCRIPT = {"execute": ["        self.speed = 1.0\n        return None\n"]}
EXECUTE = Prompt.chat("Write execute.", answer_prefix="    def execute(self) -> None:\n")


def test_a_scripted_model_answers_each_option_in_turn() -> None:
    model = MethodScript(dict(SCRIPT))
    assert not isinstance(model, BatchGenerator)
    options = [GenerationOptions(seed=1), GenerationOptions(seed=2, stop=("return",))]
    answers = generate_each(model, EXECUTE, options)
    assert [a.text for a in answers] == [SCRIPT["execute"][0], "        self.speed = 1.0\n        "]
    assert [a.finish_reason for a in answers] == ["stop", "stop"]
    assert model.options == options  # each option reached the model, in order
    assert all(a.prompt_tokens == model.count_tokens(EXECUTE) for a in answers)


def test_in_turn_the_sink_stops_one_answer_and_the_next_is_still_asked() -> None:
    model = MethodScript(dict(SCRIPT), chunk=5)
    pieces: list[tuple[int, str]] = []

    def sink(index: int, text: str) -> bool:
        pieces.append((index, text))
        return index == 0

    answers = generate_each(
        model, EXECUTE, [GenerationOptions(), GenerationOptions()], on_chunk=sink
    )
    assert [a.finish_reason for a in answers] == ["stopped", "stop"]
    assert answers[0].text == SCRIPT["execute"][0][:5]
    assert answers[1].text == SCRIPT["execute"][0]
    assert "".join(text for index, text in pieces if index == 1) == answers[1].text


def test_in_turn_a_cancel_ends_the_answers() -> None:
    model = MethodScript(dict(SCRIPT), cancel_after=1)
    cancel = threading.Event()
    answers = generate_each(model, EXECUTE, [GenerationOptions()] * 3, cancel=cancel)
    assert [a.finish_reason for a in answers] == ["cancelled"]
    assert len(model.prompts) == 1  # the other two were never asked
    assert generate_each(model, EXECUTE, []) == []


class _Wide:
    """A batching generator that records how it was asked (for generate_each's choice)."""

    model_id = "wide"
    context_length = 10_000
    max_sequences = 2

    def __init__(self) -> None:
        self.inner = MethodScript(dict(SCRIPT))
        self.batches: list[int] = []

    def count_tokens(self, prompt: Prompt) -> int | None:
        return self.inner.count_tokens(prompt)

    def stream(
        self,
        prompt: Prompt,
        options: GenerationOptions | None = None,
        cancel: threading.Event | None = None,
    ) -> TextStream:
        return self.inner.stream(prompt, options, cancel)

    def generate_batch(
        self,
        prompt: Prompt,
        options: Sequence[GenerationOptions],
        *,
        on_chunk: ChunkSink | None = None,
        cancel: threading.Event | None = None,
    ) -> list[BatchAnswer]:
        self.batches.append(len(options))
        return [BatchAnswer("x", "stop", 1, 0, 1, 0.5) for _ in options]

    def close(self) -> None:
        pass


def test_generate_each_batches_a_batching_generator_in_batches_of_its_width() -> None:
    wide = _Wide()
    assert isinstance(wide, BatchGenerator)
    assert [a.text for a in generate_each(wide, EXECUTE, [GenerationOptions()] * 2)] == ["x", "x"]
    assert wide.batches == [2]
    beyond = generate_each(wide, EXECUTE, [GenerationOptions()] * 5)
    assert wide.batches == [2, 2, 2, 1]
    assert len(beyond) == 5
    assert wide.inner.prompts == []  # nothing streamed


def test_a_cancelled_batch_ends_the_batches() -> None:
    wide = _Wide()
    cancel = threading.Event()
    cancel.set()
    answers = generate_each(wide, EXECUTE, [GenerationOptions()] * 5, cancel=cancel)
    assert wide.batches == [2]
    assert len(answers) == 2
