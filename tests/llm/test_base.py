"""The backend contract's documents: prompts, options and streams."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from skillwright.llm.base import ChatMessage, GenerationOptions, Prompt, TextStream


def test_chat_prompt_marks_system_and_examples_as_the_fixed_prefix() -> None:
    examples = (ChatMessage("user", "e1"), ChatMessage("assistant", "a1"))
    prompt = Prompt.chat("question", system="guide", prefix=examples)
    assert [m.role for m in prompt.messages] == ["system", "user", "assistant", "user"]
    assert prompt.prefix_messages == 3
    assert Prompt.chat("question").prefix_messages == 0


@pytest.mark.parametrize(
    ("messages", "prefix"),
    [((), 0), ((ChatMessage("user", "q"),), 1), ((ChatMessage("user", "q"),), -1)],
)
def test_prompt_needs_a_message_after_its_prefix(
    messages: tuple[ChatMessage, ...], prefix: int
) -> None:
    with pytest.raises(ValueError, match="message"):
        Prompt(messages, prefix_messages=prefix)


def test_options_reject_unknown_and_invalid_values() -> None:
    with pytest.raises(ValidationError, match="Extra inputs are not permitted"):
        GenerationOptions.model_validate({"max_token": 5})
    with pytest.raises(ValidationError, match="greater than 0"):
        GenerationOptions(max_tokens=0)


def test_stream_records_chunks_timing_and_text() -> None:
    stream = TextStream(iter(["a", "b", "c"]))
    assert next(stream) == "a"
    assert stream.time_to_first_chunk is not None
    assert stream.text() == "bc"
    assert stream.completion_chunks == 3
    assert stream.finished_at is not None
