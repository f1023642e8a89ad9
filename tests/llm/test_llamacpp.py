"""The llama.cpp backend on the tiny GGUF model: streaming, stops, cancel, grammars, limits."""

from __future__ import annotations

import json
import logging
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from skillwright.errors import (
    ContextOverflowError,
    InvalidArgumentError,
    ModelError,
    ModelFormatError,
)
from skillwright.llm import load_generator
from skillwright.llm.base import ChatMessage, GenerationOptions, Prompt, TextGenerator
from skillwright.llm.config import Registry, load_registry
from skillwright.llm.llamacpp import LlamaCppGenerator, _StopSplitter, load_llamacpp, render_chat
from tests.llm.conftest import write_models_toml

QUESTION = Prompt.chat("Which topic moves the robot?", system="You write ROS 2 skills.")


@pytest.fixture
def tiny(tiny_registry: Registry, cache: Path) -> Iterator[LlamaCppGenerator]:
    generator = load_generator(tiny_registry, "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    yield generator
    generator.close()


def test_loaded_model_keeps_the_backend_contract(tiny: LlamaCppGenerator) -> None:
    assert isinstance(tiny, TextGenerator)
    assert tiny.model_id == "tiny"
    assert tiny.context_length == 768
    # From models.toml, not llama-cpp-python's default (512): context_length for the prompt and
    # one answer, and room for the 3 further answers of a batch of batch_sequences (default 4)
    # answers of max_tokens 32 (llama.cpp rounds the cells up to a multiple of 256).
    assert 768 + 3 * 32 <= tiny.llama.n_ctx() < 768 + 3 * 32 + 256
    assert tiny.max_sequences == 4


def test_stream_yields_chunks_as_they_are_generated(tiny: LlamaCppGenerator) -> None:
    stream = tiny.stream(QUESTION, GenerationOptions(max_tokens=12))
    assert stream.finish_reason is None
    chunks = list(stream)
    assert len(chunks) > 1
    assert stream.completion_chunks == len(chunks)
    assert stream.finish_reason in {"stop", "length"}
    assert stream.prompt_tokens == tiny.count_tokens(QUESTION)
    assert stream.time_to_first_chunk is not None


def test_default_sampling_is_deterministic(tiny: LlamaCppGenerator) -> None:
    first = tiny.stream(QUESTION, GenerationOptions(max_tokens=20)).text()
    second = tiny.stream(QUESTION, GenerationOptions(max_tokens=20)).text()
    assert first == second
    assert first


def test_max_tokens_from_models_toml_is_the_default_limit(tiny: LlamaCppGenerator) -> None:
    stream = tiny.stream(QUESTION)  # sampling.max_tokens = 32 in the test models.toml
    stream.text()
    assert (stream.finish_reason, stream.completion_tokens) == ("length", 32)
    limited = tiny.stream(QUESTION, GenerationOptions(max_tokens=5))
    limited.text()
    assert (limited.finish_reason, limited.completion_tokens) == ("length", 5)


def test_stop_sequence_ends_the_answer_before_it(tiny: LlamaCppGenerator) -> None:
    chunks = [c for c in tiny.stream(QUESTION, GenerationOptions(max_tokens=24)) if c]
    full = "".join(chunks)
    # The random model also writes bytes that are not UTF-8 (dropped from the text), so only a
    # single chunk is sure to be contiguous in the model's bytes: stop on the third one.
    stop = chunks[2]
    stopped = tiny.stream(QUESTION, GenerationOptions(max_tokens=24, stop=(stop,)))
    text = stopped.text()
    assert text == full[: full.index(stop)]
    assert len(text) < len(full)
    assert stopped.finish_reason == "stop"


def test_cancel_stops_between_tokens(tiny: LlamaCppGenerator) -> None:
    cancel = threading.Event()
    stream = tiny.stream(QUESTION, GenerationOptions(max_tokens=40), cancel=cancel)
    received = []
    for chunk in stream:
        received.append(chunk)
        cancel.set()  # as a TUI's cancel button would, while handling a chunk
    assert len(received) == 1
    assert stream.finish_reason == "cancelled"
    # The model is free again for the next request.
    assert tiny.stream(QUESTION, GenerationOptions(max_tokens=2)).text() is not None


def test_cancel_stops_at_the_next_token(
    tiny: LlamaCppGenerator, monkeypatch: pytest.MonkeyPatch
) -> None:
    llama = tiny.llama
    cancel = threading.Event()
    sampled = 0
    real_sample = llama.sample

    def sample(*args: Any, **kwargs: Any) -> Any:
        nonlocal sampled
        sampled += 1
        if sampled == 3:
            cancel.set()  # Esc while the model writes
        return real_sample(*args, **kwargs)

    monkeypatch.setattr(llama, "sample", sample)
    stream = tiny.stream(QUESTION, GenerationOptions(max_tokens=40), cancel=cancel)
    list(stream)
    assert stream.finish_reason == "cancelled"
    assert sampled == 3
    assert stream.completion_tokens == 2


def test_bytes_that_are_not_utf8_still_stream(tiny: LlamaCppGenerator) -> None:
    # The random model writes arbitrary bytes; each token's text arrives as it is written,
    # broken characters replaced, instead of being held back until the answer ends.
    chunks: list[str] = []
    stream = tiny.stream(QUESTION, GenerationOptions(max_tokens=60, stop=()))
    for chunk in stream:
        chunks.append(chunk)
    assert stream.finish_reason in {"length", "stop"}
    assert stream.completion_tokens is not None
    assert len(chunks) >= stream.completion_tokens // 4


@pytest.mark.parametrize(
    ("pieces", "shown", "stopped"),
    [
        (["def f():\n", "    return 1\n", "\n\n", "def g"], "def f():\n    return 1", True),
        (["x = 1", "\n\\", "n# end"], "x = 1\n\\n# end", False),
        (["abc", "\n", "\n", "\nd"], "abc", True),
        (["tail\n"], "tail\n", False),
    ],
    ids=["stop over chunks", "near miss released", "stop at once", "partial stop at the end"],
)
def test_stop_strings_cut_the_text_and_hold_back_only_their_start(
    pieces: list[str], shown: str, stopped: bool
) -> None:
    splitter = _StopSplitter(["\n\n\n", "\n\n\ndef", "\ndef "])
    out = ""
    reached = False
    for piece in pieces:
        text, reached = splitter.feed(piece)
        out += text
        if reached:
            break
    if not reached:
        text, _ = splitter.feed("", final=True)
        out += text
    assert (out, reached) == (shown, stopped)


def test_cancel_before_start_generates_nothing(tiny: LlamaCppGenerator) -> None:
    cancel = threading.Event()
    cancel.set()
    stream = tiny.stream(QUESTION, GenerationOptions(max_tokens=40), cancel=cancel)
    assert list(stream) == []
    assert stream.finish_reason == "cancelled"


VERDICT = {
    "type": "object",
    "properties": {
        "relevant": {"type": "boolean"},
        "kind": {"type": "string", "enum": ["control", "logging", "introspection"]},
    },
    "required": ["relevant", "kind"],
    "additionalProperties": False,
}


def test_json_schema_constrains_the_output(tiny: LlamaCppGenerator) -> None:
    text = tiny.stream(QUESTION, GenerationOptions(max_tokens=200, json_schema=VERDICT)).text()
    answer = json.loads(text)
    assert set(answer) == {"relevant", "kind"}
    assert isinstance(answer["relevant"], bool)
    assert answer["kind"] in {"control", "logging", "introspection"}


def test_unconstrained_output_of_the_random_model_is_not_json(tiny: LlamaCppGenerator) -> None:
    # Shows the grammar test above is meaningful: without it the tiny model writes noise.
    text = tiny.stream(QUESTION, GenerationOptions(max_tokens=40)).text()
    with pytest.raises(ValueError, match=r"Expecting|Extra data|Invalid"):
        json.loads(text)


def test_prompt_that_does_not_fit_is_refused_with_both_numbers(tiny: LlamaCppGenerator) -> None:
    used = tiny.count_tokens(QUESTION)
    with pytest.raises(ContextOverflowError) as info:
        tiny.stream(QUESTION, GenerationOptions(max_tokens=700))
    message = str(info.value)
    assert f"the prompt takes {used} tokens and up to 700 may be generated" in message
    assert f"{used + 700} in all, but the context holds 768" in message
    assert "`context_length` of 'tiny'" in message
    assert "trained with up to 8192" in message


def test_long_prompt_alone_overflowing_is_refused(tiny: LlamaCppGenerator) -> None:
    long = Prompt.chat("x" * 800)
    with pytest.raises(ContextOverflowError, match="but the context holds 768"):
        tiny.stream(long, GenerationOptions(max_tokens=1))


def test_second_stream_while_one_is_open_is_refused(tiny: LlamaCppGenerator) -> None:
    first = tiny.stream(QUESTION, GenerationOptions(max_tokens=10))
    next(first)
    with pytest.raises(ModelError, match="already generating"):
        next(tiny.stream(QUESTION, GenerationOptions(max_tokens=10)))
    first.text()


def test_chat_template_comes_from_the_gguf_file(tiny: LlamaCppGenerator) -> None:
    text = tiny.render(QUESTION.messages, add_generation_prompt=True)
    assert text == (
        "### system:\nYou write ROS 2 skills.\n### user:\nWhich topic moves the robot?\n"
        "### assistant:\n"
    )


def test_chat_template_from_models_toml_overrides_the_file(tiny_gguf: Path, tmp_path: Path) -> None:
    path = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    template = 'chat_template = "{% for m in messages %}<{{ m.content }}>{% endfor %}"'
    path.write_text(path.read_text().replace("threads = 1", f"threads = 1\n{template}"))
    generator = load_generator(load_registry(path), "tiny", cache=tmp_path / "c")
    assert isinstance(generator, LlamaCppGenerator)
    assert generator.render(QUESTION.messages, add_generation_prompt=True) == (
        "<You write ROS 2 skills.><Which topic moves the robot?>"
    )
    generator.close()


def test_render_chat_reports_template_errors() -> None:
    with pytest.raises(InvalidArgumentError, match="chat template line 1"):
        render_chat("{% for %}", [ChatMessage("user", "hi")])


def test_truncated_model_file_is_refused_before_llama_cpp_sees_it(
    tiny_gguf: Path, tmp_path: Path
) -> None:
    cut = tmp_path / "cut.gguf"
    cut.write_bytes(tiny_gguf.read_bytes()[:-4096])
    registry = load_registry(write_models_toml(tmp_path / "models.toml", cut))
    with pytest.raises(ModelFormatError, match=r"model 'tiny': .*truncated"):
        load_generator(registry, "tiny", cache=tmp_path / "c")


def test_corrupted_weights_header_is_refused(tiny_gguf: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.gguf"
    data = bytearray(tiny_gguf.read_bytes())
    data[0:4] = b"GGML"
    bad.write_bytes(bytes(data))
    registry = load_registry(write_models_toml(tmp_path / "models.toml", bad))
    with pytest.raises(ModelFormatError, match=r"model 'tiny': .*not a GGUF model file"):
        load_generator(registry, "tiny", cache=tmp_path / "c")


def test_loading_without_prefix_cache_still_generates(tiny_registry: Registry, cache: Path) -> None:
    entry = tiny_registry.generation_model("tiny")
    assert entry.backend == "llama.cpp"
    generator = load_llamacpp(entry, tiny_registry, cache=cache, prefix_cache=False)
    stream = generator.stream(QUESTION, GenerationOptions(max_tokens=4))
    stream.text()
    assert stream.prefix_cache == "evaluated"
    assert not (cache / "prefix").exists()
    generator.close()


def test_gguf_that_llama_cpp_cannot_load_is_a_model_error(tmp_path: Path) -> None:
    import gguf

    odd = tmp_path / "odd.gguf"
    writer = gguf.GGUFWriter(str(odd), "no-such-architecture")
    writer.write_header_to_file()
    writer.write_kv_data_to_file()
    writer.write_tensors_to_file()
    writer.close()
    registry = load_registry(write_models_toml(tmp_path / "models.toml", odd))
    with pytest.raises(ModelError, match=r"model 'tiny': llama.cpp could not load .*odd\.gguf"):
        load_generator(registry, "tiny", cache=tmp_path / "c")


def test_a_process_that_loaded_a_model_ends_without_unclosed_file_warnings(
    tiny_gguf: Path, tmp_path: Path
) -> None:
    models = write_models_toml(tmp_path / "models.toml", tiny_gguf)
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from skillwright.llm import load_generator\n"
        "from skillwright.llm.config import load_registry\n"
        "registry = load_registry(Path(sys.argv[1]))\n"
        "load_generator(registry, 'tiny', cache=Path(sys.argv[2])).close()\n"
    )
    # -X dev shows every ResourceWarning, as pytest's own exit does.
    result = subprocess.run(
        [sys.executable, "-X", "dev", "-c", code, str(models), str(tmp_path / "cache")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert "ResourceWarning" not in result.stderr


def test_llama_cpp_log_lines_reach_python_logging_not_the_terminal(
    tiny_gguf: Path,
    tmp_path: Path,
    cache: Path,
    caplog: pytest.LogCaptureFixture,
    capfd: pytest.CaptureFixture[str],
) -> None:
    # A context longer than the model was trained with makes llama.cpp itself warn.
    models = write_models_toml(tmp_path / "long.toml", tiny_gguf, context=16384)
    with caplog.at_level(logging.DEBUG, logger="skillwright.llama_cpp"):
        generator = load_generator(load_registry(models), "tiny", cache=cache)
        generator.close()
    native = [r for r in caplog.records if r.name == "skillwright.llama_cpp"]
    warned = [r for r in native if r.levelno == logging.WARNING]
    assert any("n_ctx_train" in r.getMessage() for r in warned)
    assert all(r.getMessage().startswith("llama.cpp: ") for r in native)
    # Only a handler of the logger may print it (the CLI's prints "warning: ..." lines).
    raw = [line for line in capfd.readouterr().err.splitlines() if "n_ctx_train" in line]
    assert all(line.startswith("warning: llama.cpp: ") for line in raw)
