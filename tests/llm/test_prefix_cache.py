"""The prompt prefix cache: a restored state continues exactly like a fresh evaluation."""

from __future__ import annotations

import logging
import threading
from pathlib import Path

import pytest

from skillwright.errors import ModelError
from skillwright.llm import load_generator
from skillwright.llm.base import ChatMessage, GenerationOptions, Prompt
from skillwright.llm.config import Registry
from skillwright.llm.llamacpp import LlamaCppGenerator, _KeptStates, load_llamacpp
from skillwright.llm.prefix_cache import PrefixCache, PrefixState, prefix_key

GUIDE = "Framework guide. " * 40  # a long fixed prefix (several hundred byte tokens)
EXAMPLES = (
    ChatMessage("user", "Example capability: move forward."),
    ChatMessage("assistant", "def execute(self): publish cmd_vel"),
)


def skill_prompt(question: str) -> Prompt:
    return Prompt.chat(question, system=GUIDE, prefix=EXAMPLES)


def _load(registry: Registry, cache: Path, *, prefix_cache: bool = True) -> LlamaCppGenerator:
    entry = registry.generation_model("tiny")
    assert entry.backend == "llama.cpp"
    return load_llamacpp(entry, registry, cache=cache, prefix_cache=prefix_cache)


def _run(generator: LlamaCppGenerator, prompt: Prompt) -> tuple[str, str]:
    stream = generator.stream(prompt, GenerationOptions(max_tokens=24))
    return stream.text(), stream.prefix_cache


@pytest.fixture
def big_registry(tiny_registry: Registry, tmp_path: Path, tiny_gguf: Path) -> Registry:
    from skillwright.llm.config import load_registry
    from tests.llm.conftest import write_models_toml

    return load_registry(write_models_toml(tmp_path / "big.toml", tiny_gguf, context=2048))


def test_restored_prefix_gives_the_same_tokens_as_fresh_evaluation(
    big_registry: Registry, cache: Path
) -> None:
    prompt = skill_prompt("Write the skill for: drive 1 m.")
    fresh = _load(big_registry, cache, prefix_cache=False)
    expected, how = _run(fresh, prompt)
    fresh.close()
    assert how == "evaluated"

    first = _load(big_registry, cache)
    text, how = _run(first, prompt)
    first.close()
    assert (text, how) == (expected, "stored")
    assert len(list((cache / "prefix").glob("*.bin"))) == 1

    restored = _load(big_registry, cache)  # a new process would do the same
    text, how = _run(restored, prompt)
    assert (text, how) == (expected, "disk")
    # Still in the context: the next prompt with this prefix needs no disk read.
    _, how = _run(restored, skill_prompt("Write the skill for: turn left."))
    assert how == "memory"
    restored.close()


def test_prefix_is_split_at_a_message_boundary(big_registry: Registry, cache: Path) -> None:
    generator = _load(big_registry, cache)
    prefix, rest = generator.prompt_tokens(skill_prompt("Q?"))
    whole = generator.llama.tokenize(
        generator.render(skill_prompt("Q?").messages, add_generation_prompt=True).encode(),
        add_bos=True,
        special=True,
    )
    assert prefix + rest == whole  # byte-level vocabulary: splitting changes no token
    # SentencePiece-style tokenisation writes spaces as U+2581.
    text = generator.llama.detokenize(prefix).decode().replace("\u2581", " ")
    assert text.endswith("### assistant:\ndef execute(self): publish cmd_vel\n")
    generator.close()


def test_changed_prefix_uses_a_new_cache_entry(big_registry: Registry, cache: Path) -> None:
    generator = _load(big_registry, cache)
    _run(generator, skill_prompt("Q1"))
    other = Prompt.chat("Q1", system=GUIDE + "Revised.", prefix=EXAMPLES)
    _, how = _run(generator, other)
    generator.close()
    assert how == "stored"
    assert len(list((cache / "prefix").glob("*.bin"))) == 2


def test_corrupt_cache_file_is_discarded_with_a_warning_not_fatal(
    big_registry: Registry, cache: Path, caplog: pytest.LogCaptureFixture
) -> None:
    prompt = skill_prompt("Write the skill for: drive 1 m.")
    generator = _load(big_registry, cache)
    expected, _ = _run(generator, prompt)
    generator.close()
    [saved] = (cache / "prefix").glob("*.bin")
    data = bytearray(saved.read_bytes())
    data[len(data) // 2] ^= 0xFF
    saved.write_bytes(bytes(data))

    generator = _load(big_registry, cache)
    with caplog.at_level(logging.WARNING, logger="skillwright.llm.prefix_cache"):
        text, how = _run(generator, prompt)
    prefix_tokens = generator.prompt_tokens(prompt)[0]
    generator.close()
    assert (text, how) == (expected, "stored")
    assert "discarding prefix cache" in caplog.text
    assert "checksum mismatch" in caplog.text
    assert PrefixCache(cache / "prefix").load(saved.stem, prefix_tokens)  # rewritten, intact


def test_closed_model_refuses_instead_of_crashing(tiny_registry: Registry, cache: Path) -> None:
    generator = _load(tiny_registry, cache)
    generator.close()
    generator.close()  # idempotent
    with pytest.raises(ModelError, match="'tiny' was closed"):
        generator.count_tokens(skill_prompt("Q"))


def test_cache_key_changes_with_model_tokens_and_context() -> None:
    base = prefix_key("a" * 64, [1, 2, 3], context="n_ctx=512")
    assert base.startswith("a" * 16 + "-")
    assert prefix_key("b" * 64, [1, 2, 3], context="n_ctx=512") != base
    assert prefix_key("a" * 64, [1, 2, 4], context="n_ctx=512") != base
    assert prefix_key("a" * 64, [1, 2, 3], context="n_ctx=1024") != base
    assert prefix_key("a" * 64, [1, 2, 3], context="n_ctx=512") == base


def test_store_and_load_round_trip(tmp_path: Path) -> None:
    cache = PrefixCache(tmp_path)
    state = PrefixState((5, 6, 7), b"\x00state\xff" * 100)
    path = cache.store("k-1", state)
    assert path == tmp_path / "k-1.bin"
    assert cache.load("k-1", [5, 6, 7]) == state
    assert cache.load("absent", [5, 6, 7]) is None
    assert not list(tmp_path.glob(".prefix-*"))  # no temporary file left behind


@pytest.mark.parametrize(
    ("damage", "reason"),
    [
        (lambda raw: raw[: len(raw) // 2], "checksum mismatch"),
        (lambda raw: b"garbage", "not a skillwright prefix-cache file"),
        (lambda raw: raw, "holds a different prefix"),
    ],
)
def test_unusable_cache_file_is_deleted(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, damage: object, reason: str
) -> None:
    cache = PrefixCache(tmp_path)
    path = cache.store("k-1", PrefixState((1, 2), b"xyz" * 100))
    path.write_bytes(damage(path.read_bytes()))  # type: ignore[operator]
    asked = [1, 3] if reason == "holds a different prefix" else [1, 2]
    with caplog.at_level(logging.WARNING):
        assert cache.load("k-1", asked) is None
    assert reason in caplog.text
    assert not path.exists()


def test_old_states_of_a_model_are_pruned(tmp_path: Path) -> None:
    cache = PrefixCache(tmp_path, keep=2)
    for index in range(4):
        cache.store(f"model-{index}", PrefixState((index,), b"s"))
    cache.store("other-0", PrefixState((9,), b"s"))
    assert sorted(p.stem for p in tmp_path.glob("*.bin")) == ["model-2", "model-3", "other-0"]


def test_default_loader_uses_the_prefix_cache(tiny_registry: Registry, cache: Path) -> None:
    generator = load_generator(tiny_registry, "tiny", cache=cache)
    assert isinstance(generator, LlamaCppGenerator)
    stream = generator.stream(Prompt.chat("hi", system="sys"), GenerationOptions(max_tokens=2))
    stream.text()
    assert stream.prefix_cache == "stored"
    generator.close()


class CancelAfter(threading.Event):
    """A cancel flag that turns itself on after being looked at ``checks`` times."""

    def __init__(self, checks: int) -> None:
        super().__init__()
        self.checks = checks

    def is_set(self) -> bool:
        self.checks -= 1
        if self.checks < 0:
            self.set()
        return super().is_set()


def test_cancel_during_prefix_evaluation_stops_between_batches(
    big_registry: Registry, cache: Path
) -> None:
    prompt = skill_prompt("Write the skill for: drive 1 m.")
    generator = _load(big_registry, cache)
    assert len(generator.prompt_tokens(prompt)[0]) > 3 * 64  # several batches of 64 tokens
    stream = generator.stream(prompt, GenerationOptions(max_tokens=24), cancel=CancelAfter(2))
    assert list(stream) == []
    assert stream.finish_reason == "cancelled"
    assert generator.llama.n_tokens == 0  # the half-evaluated prefix was dropped
    assert not (cache / "prefix").exists()  # and not saved
    text, how = _run(generator, prompt)
    generator.close()
    fresh = _load(big_registry, cache, prefix_cache=False)
    assert (text, how) == (_run(fresh, prompt)[0], "stored")
    fresh.close()


def _conversation(*turns: str) -> Prompt:
    """A prompt after earlier turns (user, assistant, ...) ending with a question."""
    roles = ("user", "assistant")
    messages = tuple(ChatMessage(roles[i % 2], text) for i, text in enumerate(turns[:-1]))
    fixed = (ChatMessage("system", GUIDE), *EXAMPLES)
    return Prompt((*fixed, *messages, ChatMessage("user", turns[-1])), prefix_messages=len(fixed))


def test_a_prompt_that_branches_back_continues_from_the_state_it_shares_most_with(
    big_registry: Registry, cache: Path
) -> None:
    # As a repair does: turns asked in order, then one asked again differently, then the
    # conversation continued where the first pass ended.
    first = ("Write starting. " * 6, "def starting(self): wait " * 6)
    second = ("Write execute. " * 6, "def execute(self): drive " * 6)
    later = _conversation(*first, *second, "Write the helper.")
    generator = _load(big_registry, cache)
    options = GenerationOptions(max_tokens=4)
    for prompt in (
        _conversation(first[0]),
        _conversation(*first, second[0]),
        _conversation(*first, "Write execute again, it had problems."),
    ):
        generator.stream(prompt, options).text()
    stream = generator.stream(later, options)
    text = stream.text()
    asked_second = generator.count_tokens(_conversation(*first, second[0]))
    whole = generator.count_tokens(later)
    generator.close()
    # Everything up to the second turn's question came from the state kept after it.
    assert stream.prefix_cache == "memory"
    assert stream.reused_tokens is not None
    assert asked_second - 8 < stream.reused_tokens < whole
    # A model that never saw the earlier prompts reuses only the fixed prefix, and the answer
    # is the same.
    fresh = _load(big_registry, cache)
    alone = fresh.stream(later, options)
    assert (alone.text(), alone.prefix_cache) == (text, "disk")
    assert alone.reused_tokens == len(fresh.prompt_tokens(later)[0])
    assert alone.reused_tokens < asked_second - 100
    fresh.close()


def test_kept_states_stay_within_their_budget_least_recently_used_going_first() -> None:
    kept = _KeptStates(budget=10)
    kept.keep(PrefixState((1, 2, 3), b"aaaa"))
    kept.keep(PrefixState((1, 2, 4), b"bbbb"))
    assert kept.closest([1, 2, 3, 9]) == (PrefixState((1, 2, 3), b"aaaa"), 3)
    kept.keep(PrefixState((1, 2, 3), b"aaaa"))  # used again: now the most recent
    kept.keep(PrefixState((5,), b"cccc"))  # over budget: (1, 2, 4) goes
    assert kept.closest([1, 2, 4]) == (PrefixState((1, 2, 3), b"aaaa"), 2)
    assert kept.closest([5, 6]) == (PrefixState((5,), b"cccc"), 1)
    assert kept.closest([7]) is None
    kept.keep(PrefixState((8,), b"x" * 11))  # larger than the whole budget: not kept
    assert kept.closest([8]) is None
