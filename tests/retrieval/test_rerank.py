"""The model's second stage: prompts, verdicts, order, cache (scripted model); mechanics (tiny GGUF)."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from skillwright.capability import load_capability
from skillwright.errors import OperationCancelledError
from skillwright.interfaces.enrich import EnrichmentCache
from skillwright.llm.base import TextStream
from skillwright.retrieval.rerank import Reranker, Reranking, reorder
from skillwright.retrieval.retrieve import Hit, rank_interfaces
from skillwright.spec import load_spec
from tests.conftest import SHIPPED_CAPABILITIES
from tests.fixtures.interface_answers import InterfaceAnswers
from tests.retrieval.test_retrieve import mr1

NEEDED = {"reason": "It commands the base velocity.", "needed": True}
NOT_NEEDED = {"reason": "The skill never reads images.", "needed": False}


class ScriptedModel(InterfaceAnswers):
    """Answers as the table says, and "not needed" for every other interface."""

    def __init__(self, answers: dict[str, Any], model_id: str = "scripted") -> None:
        super().__init__(answers, model_id, default=NOT_NEEDED)


def first_stage(stem: str = "move-forward", k: int = 8) -> tuple[Any, Any, list[Hit]]:
    capability = load_capability(SHIPPED_CAPABILITIES / f"{stem}.ttl").capability
    spec = load_spec(SHIPPED_CAPABILITIES / f"{stem}.spec.yaml")
    return capability, spec, rank_interfaces(mr1(), capability, spec, k=k)


def rerank(model: ScriptedModel, hits: list[Hit] | None = None, **kwargs: Any) -> Reranking:
    capability, spec, ranked = first_stage()
    reranker = Reranker(model, **kwargs)
    return reranker.rerank(mr1(), capability, spec, ranked if hits is None else hits)


def test_the_needed_candidates_move_first_keeping_the_first_stage_order() -> None:
    _, _, hits = first_stage()
    favoured = [hits[6].name, hits[2].name]
    result = rerank(ScriptedModel(dict.fromkeys(favoured, NEEDED)))
    assert [h.name for h in result.hits[:2]] == [hits[2].name, hits[6].name]
    assert {h.name for h in result.hits} == {h.name for h in hits}
    assert all(h.needed is True for h in result.hits[:2])
    assert all(h.needed is False for h in result.hits[2:])
    assert result.hits[0].judgement == "It commands the base velocity."
    assert (result.asked, result.cached) == (8, 0)
    assert result.summary().startswith("2 of 8 judged needed; 8 asked")


def test_only_the_first_depth_hits_are_judged_and_the_rest_follow_unchanged() -> None:
    _, _, hits = first_stage(k=10)
    model = ScriptedModel({hits[9].name: NEEDED})
    result = rerank(model, hits, depth=3)
    assert len(model.prompts) == 3
    assert [h.name for h in result.hits[3:]] == [h.name for h in hits[3:]]
    assert result.hits[9].needed is None
    assert result.hits[9].judgement is None


def test_questions_share_the_capability_prefix_and_name_one_candidate_each() -> None:
    model = ScriptedModel({})
    rerank(model, depth=3)
    first, second = model.prompts[0], model.prompts[1]
    assert first.prefix_messages == second.prefix_messages == 1
    assert first.messages[0] == second.messages[0]
    system = first.messages[0].content
    assert "Capability: Move forward." in system
    assert "- execute:" in system  # the specification's states
    assert "inDistance" in system
    question = first.messages[-1].content
    assert question.startswith("Interface: ")
    assert "\nType: " in question
    assert "\nAbout: " in question
    options = model.options[0]
    assert options.temperature == 0.0
    assert not options.save_prefix  # a per-capability prefix must not evict generation's
    assert options.json_schema is not None
    assert options.json_schema["required"] == ["reason", "needed"]


@pytest.mark.parametrize(
    ("answer", "why"),
    [
        ("not json at all", "not JSON"),
        ({"reason": "", "needed": True}, "invalid answer (reason"),
        ({"reason": "Fine.", "needed": "maybe"}, "invalid answer (needed"),
        (('{"reason": "It goes on and on', "length"), "80-token limit"),
    ],
)
def test_an_unusable_answer_keeps_the_candidate_in_place_with_a_note(answer: Any, why: str) -> None:
    _, _, hits = first_stage()
    model = ScriptedModel({hits[0].name: answer, hits[1].name: NEEDED})
    result = rerank(model, hits)
    assert [h.name for h in result.hits[:2]] == [hits[1].name, hits[0].name]
    assert result.hits[1].needed is None
    assert why in (result.hits[1].judgement or "")
    assert len(result.notes) == 1
    assert result.notes[0].startswith(f"{hits[0].name}: model 'scripted' ")


def test_valid_answers_are_cached_so_a_second_run_asks_nothing(tmp_path: Path) -> None:
    cache = EnrichmentCache(tmp_path / "rerank.sqlite")
    _, _, hits = first_stage()
    model = ScriptedModel({hits[3].name: NEEDED})
    first = rerank(model, cache=cache)
    again = rerank(ScriptedModel({}), cache=cache)
    assert (again.asked, again.cached) == (0, 8)
    assert [h.name for h in again.hits] == [h.name for h in first.hits]
    # another model is another key
    other = rerank(ScriptedModel({}, model_id="other"), cache=cache)
    assert (other.asked, other.cached) == (8, 0)


@pytest.mark.parametrize(
    ("answer", "why"),
    [
        (('{"reason": "It goes on and on', "length"), "80-token limit"),
        ({"reason": "Fine.", "needed": "maybe"}, "invalid answer (needed"),
    ],
    ids=["cut off", "invalid"],
)
def test_an_unusable_answer_is_cached_too(tmp_path: Path, answer: Any, why: str) -> None:
    # at temperature 0 the same question gets the same answer: asking again costs 10 s
    # per question on 2 cores for the same 'no verdict' (20 of 280 in the bench's run)
    cache = EnrichmentCache(tmp_path / "rerank.sqlite")
    _, _, hits = first_stage()
    rerank(ScriptedModel({hits[0].name: answer}), cache=cache)
    again = rerank(ScriptedModel({hits[0].name: NEEDED}), cache=cache)
    assert (again.asked, again.cached) == (0, 8)
    assert again.hits[0].name == hits[0].name
    assert again.hits[0].needed is None
    assert why in (again.hits[0].judgement or "")
    assert len(again.notes) == 1


def test_a_cancel_stops_before_the_next_question() -> None:
    capability, spec, hits = first_stage()
    cancel = threading.Event()
    model = ScriptedModel({})

    def cancel_after_two(done: int, _total: int, _name: str) -> None:
        if done == 2:
            cancel.set()

    with pytest.raises(OperationCancelledError):
        Reranker(model).rerank(
            mr1(), capability, spec, hits, progress=cancel_after_two, cancel=cancel
        )
    assert len(model.prompts) == 2


def test_reorder_puts_no_verdict_between_needed_and_not_needed() -> None:
    from skillwright.retrieval.rerank import Judgement

    hits = [Hit(n, "topic", "t/msg/T", 1.0, None, 1.0, "r") for n in "abcd"]
    judged = [Judgement("a", False, "no"), Judgement("b", None, "?"), Judgement("c", True, "yes")]
    assert [h.name for h in reorder(hits, judged)] == ["c", "b", "a", "d"]


# ---------------------------------------------------------------- a real llama.cpp model


@pytest.fixture(scope="module")
def tiny_gguf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from tests.fixtures.tiny_gguf import write_tiny_llama

    return write_tiny_llama(tmp_path_factory.mktemp("models") / "tiny.gguf")


@pytest.fixture
def tiny(tmp_path: Path, tiny_gguf: Path) -> Iterator[Any]:
    from skillwright.llm import load_generator, load_registry
    from tests.llm.conftest import write_models_toml

    registry = load_registry(
        write_models_toml(tmp_path / "models.toml", tiny_gguf, context=4096, max_tokens=64)
    )
    generator = load_generator(registry, "tiny", cache=tmp_path / "cache")
    yield generator
    generator.close()


def test_tiny_model_judges_every_candidate_shares_the_prefix_and_saves_no_prefix_state(
    tiny: Any, tmp_path: Path
) -> None:
    cache = EnrichmentCache(tmp_path / "rerank.sqlite")
    capability, spec, hits = first_stage(k=3)
    streams: list[TextStream] = []
    original = tiny.stream

    def recording(*args: Any, **kwargs: Any) -> TextStream:
        streams.append(original(*args, **kwargs))
        return streams[-1]

    tiny.stream = recording
    reranker = Reranker(tiny, cache=cache, max_tokens=400, reason_chars=8)
    first = reranker.rerank(mr1(), capability, spec, hits)
    assert first.notes == []
    assert all(isinstance(h.needed, bool) and h.judgement for h in first.hits)
    assert [s.prefix_cache for s in streams] == ["evaluated", "memory", "memory"]
    assert not list((tmp_path / "cache").glob("prefix/*.bin"))
    again = reranker.rerank(mr1(), capability, spec, hits)
    assert (again.asked, again.cached) == (0, 3)
    assert again.hits == first.hits
