"""The LLM engine: prompt, schema, validation and fallback (fake model); mechanics (tiny GGUF)."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from skillwright.errors import ContextOverflowError
from skillwright.interfaces.description import MODULES
from skillwright.interfaces.enrich import (
    AnswerLimits,
    EnrichmentCache,
    LlmEngine,
    enrich,
)
from skillwright.interfaces.inventory import Inventory
from skillwright.llm.base import TextStream
from tests.fixtures.interface_answers import InterfaceAnswers
from tests.interfaces.test_enrich import small_inventory

SCAN_LIKE = {
    "purpose": " Velocity commands for the base. ",
    "module": "base motion",
    "tasks": ["drive", " ", "stop"],
    "used_by": ["teleop"],
    "key_fields": ["linear.x", "angular.z", "invented.field"],
    "reason": "It commands the robot.",
    "category": "control",
}


RULES_ANSWERS = {
    "/rosout": {**SCAN_LIKE, "purpose": "Log messages.", "category": "infrastructure"},
    "/teleop/set_parameters": {**SCAN_LIKE, "module": "system", "category": "infrastructure"},
}


def test_a_valid_answer_becomes_description_and_verdict_by_the_model() -> None:
    generator = InterfaceAnswers({"/cmd_vel": SCAN_LIKE, **RULES_ANSWERS})
    report = enrich(small_inventory(), LlmEngine(generator))
    cmd_vel = report.inventory.interface("/cmd_vel")
    assert cmd_vel.description is not None
    assert cmd_vel.description.purpose == "Velocity commands for the base."
    assert cmd_vel.description.tasks == ["drive", "stop"]
    assert cmd_vel.description.engine == "fake-model"
    # /cmd_vel's definition has no field `invented.field`: the model made it up.
    assert cmd_vel.description.key_fields == ["linear.x", "angular.z"]
    assert cmd_vel.relevance is not None
    assert cmd_vel.relevance.category == "control"
    assert cmd_vel.relevance.engine == "fake-model"
    rosout = report.inventory.interface("/rosout")
    assert rosout.relevance is not None
    assert not rosout.relevance.relevant
    # Without a parsed definition there is nothing to check key fields against.
    assert rosout.description is not None
    assert "invented.field" in rosout.description.key_fields
    assert report.notes == []


def test_prompts_share_a_fixed_prefix_and_ask_about_one_interface() -> None:
    generator = InterfaceAnswers({"/cmd_vel": SCAN_LIKE, **RULES_ANSWERS})
    enrich(small_inventory(), LlmEngine(generator, max_tokens=300))
    first, second = generator.prompts[0], generator.prompts[1]
    assert first.prefix_messages == second.prefix_messages == 5  # system + two examples
    assert first.messages[: first.prefix_messages] == second.messages[: second.prefix_messages]
    question = first.messages[-1].content
    assert question.startswith("Interface: /cmd_vel\nKind: topic\nType: geometry_msgs/msg/Twist")
    assert "Vector3 linear" in question
    for example in first.messages[2:5:2]:
        json.loads(example.content)  # the worked answers are valid JSON
    options = generator.options[0]
    assert options.max_tokens == 300
    assert options.json_schema is not None
    properties = options.json_schema["properties"]
    assert properties["module"]["enum"] == list(MODULES)
    assert properties["category"]["enum"] == ["control", "infrastructure"]
    assert list(properties)[-2:] == ["reason", "category"]


@pytest.mark.parametrize(
    ("answer", "says"),
    [
        ("{not json", "gave an answer that is not JSON"),
        ({**SCAN_LIKE, "module": "teleportation"}, "gave an invalid answer (module"),
        ({**SCAN_LIKE, "extra": 1}, "gave an invalid answer (extra"),
        ({**SCAN_LIKE, "purpose": " \x00 "}, "gave an invalid answer (purpose"),
        ((json.dumps(SCAN_LIKE)[:40], "length"), "stopped at its max_tokens limit (models.toml)"),
        (ContextOverflowError("the prompt takes 9000 tokens"), "could not take the prompt"),
    ],
)
def test_an_unusable_answer_falls_back_to_the_rules_with_a_named_note(
    answer: Any, says: str, tmp_path: Path
) -> None:
    generator = InterfaceAnswers({"/cmd_vel": answer, **RULES_ANSWERS})
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    report = enrich(small_inventory(), LlmEngine(generator), cache=cache)
    cmd_vel = report.inventory.interface("/cmd_vel")
    assert cmd_vel.description is not None
    assert cmd_vel.description.engine == "rules"
    assert cmd_vel.relevance is not None
    assert cmd_vel.relevance.engine == "rules"
    assert len(report.notes) == 1
    assert report.notes[0].startswith("/cmd_vel: model 'fake-model' ")
    assert says in report.notes[0]
    assert "the rules engine described it" in report.notes[0]
    # Only usable answers are cached: a later run (another model setting) asks again.
    assert len(cache) == 2


def test_answers_are_cached_per_model(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    answers = {"/cmd_vel": SCAN_LIKE, **RULES_ANSWERS}
    first = InterfaceAnswers(answers)
    enrich(small_inventory(), LlmEngine(first), cache=cache)
    again = InterfaceAnswers(answers)
    report = enrich(small_inventory(), LlmEngine(again), cache=cache)
    assert (report.described, report.cached) == (0, 3)
    assert again.prompts == []
    other = InterfaceAnswers(answers, model_id="other-model")
    report = enrich(small_inventory(), LlmEngine(other), cache=cache)
    assert (report.described, report.cached) == (3, 0)


def test_a_cancelled_generation_stops_the_run_and_caches_nothing(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    generator = InterfaceAnswers({"/cmd_vel": SCAN_LIKE, "/rosout": ("", "cancelled")})
    report = enrich(small_inventory(), LlmEngine(generator), cache=cache)
    assert report.cancelled
    assert report.described == 1
    assert report.inventory.interface("/rosout").relevance is None
    assert len(cache) == 1


def test_the_cache_key_depends_on_the_answer_limits() -> None:
    interface = small_inventory().interfaces[0]
    generator = InterfaceAnswers({})
    assert LlmEngine(generator).cache_key(interface) != LlmEngine(
        generator, limits=AnswerLimits(items=2)
    ).cache_key(interface)


# ---------------------------------------------------------------- a real llama.cpp model


@pytest.fixture(scope="module")
def tiny_models_toml(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from tests.fixtures.tiny_gguf import write_tiny_llama

    folder = tmp_path_factory.mktemp("tiny")
    model = write_tiny_llama(folder / "tiny.gguf")
    path = folder / "models.toml"
    path.write_text(
        f"""
[defaults]
generation = "tiny"

[[llm]]
id = "tiny"
file = "{model.as_posix()}"
context_length = 8192
batch_size = 256
threads = 1

[llm.sampling]
max_tokens = 48
""",
        encoding="utf-8",
    )
    return path


@pytest.fixture
def isolated(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    home = tmp_path / "home"
    monkeypatch.setenv("XDG_CONFIG_HOME", str(home / "config"))
    monkeypatch.setenv("XDG_DATA_HOME", str(home / "data"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(home / "cache"))
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(home / "cache" / "skillwright"))
    monkeypatch.delenv("SKILLWRIGHT_MODELS", raising=False)
    monkeypatch.delenv("SKILLWRIGHT_MODELS_DIR", raising=False)
    return home


@pytest.fixture
def tiny(tiny_models_toml: Path, isolated: Path) -> Iterator[Any]:
    from skillwright.llm import load_generator, load_registry

    generator = load_generator(load_registry(tiny_models_toml), "tiny", cache=isolated / "prefix")
    yield generator
    generator.close()


# Small bounds keep a random-weight model's longest possible answer well inside max_tokens,
# so every answer is complete, grammar-valid JSON.
TINY_LIMITS = AnswerLimits(text_chars=10, item_chars=6, items=1)


def test_tiny_model_answers_validate_and_a_second_run_is_all_cached(
    tiny: Any, tmp_path: Path
) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    engine = LlmEngine(tiny, max_tokens=1500, limits=TINY_LIMITS)
    calls: list[tuple[int, int, str]] = []
    first = enrich(small_inventory(), engine, cache=cache, progress=lambda *a: calls.append(a))
    assert first.notes == []
    assert (first.described, first.cached) == (3, 0)
    assert [c[0] for c in calls] == [1, 2, 3]
    for interface in first.inventory.interfaces:
        assert interface.description is not None
        assert interface.description.engine == "tiny"
        assert interface.description.module in MODULES
        assert interface.relevance is not None
        assert interface.relevance.engine == "tiny"
    second = enrich(small_inventory(), engine, cache=cache)
    assert (second.described, second.cached) == (0, 3)
    assert second.inventory == first.inventory


def test_tiny_model_run_stops_when_cancelled_between_tokens(tiny: Any, tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "enrich.sqlite")
    cancel = threading.Event()
    engine = LlmEngine(tiny, max_tokens=1500, limits=TINY_LIMITS)

    def cancel_after_first(done: int, _total: int, _name: str) -> None:
        if done == 1:
            cancel.set()

    report = enrich(
        small_inventory(), engine, cache=cache, progress=cancel_after_first, cancel=cancel
    )
    assert report.cancelled
    assert report.described == 1
    assert len(cache) == 1


def test_tiny_model_stream_cancelled_mid_answer_leaves_the_interface_undone(tiny: Any) -> None:
    cancel = threading.Event()
    engine = LlmEngine(tiny, max_tokens=1500, limits=TINY_LIMITS)
    original = tiny.stream

    def stream_then_cancel(*args: Any, **kwargs: Any) -> TextStream:
        stream = original(*args, **kwargs)
        chunks = stream.chunks

        def cancelling() -> Iterator[str]:
            for chunk in chunks:
                cancel.set()  # after the first token: the backend stops before the next
                yield chunk

        stream.chunks = cancelling()
        return stream

    tiny.stream = stream_then_cancel
    try:
        assert engine.run(small_inventory().interfaces[0], cancel) is None
    finally:
        tiny.stream = original


def test_describe_command_with_the_llm_engine_notes_every_fallback(
    tiny_models_toml: Path, isolated: Path, tmp_path: Path
) -> None:
    saved = tmp_path / "inventory.json"
    saved.write_text(small_inventory().model_dump_json(), encoding="utf-8")
    command = ["inventory", "describe", str(saved), "--engine", "llm", "--models"]
    result = CliRunner().invoke(main_cli(), [*command, str(tiny_models_toml), "--model", "tiny"])
    assert result.exit_code == 0, result.output
    assert "3 interfaces: 3 described by tiny" in result.output
    described = Inventory.model_validate_json(saved.read_text())
    assert all(i.relevance is not None for i in described.interfaces)
    # 48 tokens (models.toml) are too few for a random model to close its JSON answer.
    fell_back = [
        i.name for i in described.interfaces if i.description and i.description.engine == "rules"
    ]
    assert len(fell_back) == 3
    assert "3 fell back to the rules engine" in result.output
    for name in fell_back:
        assert f"note: {name}: model 'tiny' stopped at its max_tokens limit" in result.output


def test_describe_command_names_a_missing_model(isolated: Path, tmp_path: Path) -> None:
    saved = tmp_path / "inventory.json"
    saved.write_text(small_inventory().model_dump_json(), encoding="utf-8")
    result = CliRunner().invoke(
        main_cli(), ["inventory", "describe", str(saved), "--engine", "llm", "--model", "nope"]
    )
    assert result.exit_code == 2
    assert "nope" in result.output
    assert "Traceback" not in result.output
    assert Inventory.model_validate_json(saved.read_text()) == small_inventory()


def main_cli() -> Any:
    from skillwright.cli import main

    return main
