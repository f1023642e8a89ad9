"""Retrieval's optional second stage: the local model judges the best candidates one by one.

The first stage (:func:`~skillwright.retrieval.retrieve.rank_interfaces`) ranks every
candidate by its words and types. Here the generation model reads the capability and the
skill specification once, then answers one schema-constrained question per candidate among
the first :data:`DEPTH`: ``{"reason": "...", "needed": true|false}`` (the reason first, so the
model argues before it decides). The candidates it calls needed move ahead of the others,
each group keeping the first stage's order; the reasons are shown with the hits.

What this costs and whether it helps is measured, not assumed: ``python
bench/bench_retrieval.py --rerank MODEL``. On two CPU cores a 1.5B model reads about 16
prompt tokens a second, so the prompts are kept short, and the text every question of one
capability shares (instructions, capability, specification, the candidates' names) is the
prompt's fixed prefix: evaluated once per capability and kept in memory for the other
questions. It is not saved to the disk prefix cache, where it would push out the long
prefixes of skill generation; the answers themselves are cached on disk instead
(``rerank.sqlite`` in the cache folder, keyed by a hash of the model id and the whole
prompt), so asking again about the same capability and robot costs nothing.
"""

from __future__ import annotations

import hashlib
import json
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from skillwright.capability.model import Capability, Parameter
from skillwright.interfaces.enrich import EnrichmentCache
from skillwright.interfaces.inventory import Interface, Inventory
from skillwright.paths import cache_dir
from skillwright.retrieval.documents import describe, field_paths
from skillwright.retrieval.retrieve import Hit
from skillwright.spec.model import SkillSpec

if TYPE_CHECKING:
    from skillwright.llm.base import Prompt, TextGenerator

__all__ = [
    "DEPTH",
    "PROMPT_VERSION",
    "Judgement",
    "Reranker",
    "Reranking",
    "answer_schema",
    "candidate_text",
    "default_cache",
    "reorder",
    "skill_summary",
]

DEPTH = 8
"""How many of the first stage's hits the model judges."""

PROMPT_VERSION = 1
"""Part of every cache key: bumped when the prompt or the schema changes."""


def answer_schema(reason_chars: int | None = None) -> dict[str, Any]:
    """The JSON schema each answer follows while it is generated (a llama.cpp grammar).

    The reason's length is unbounded by default: a bound becomes a chain of optional
    characters in the grammar that slows every token, and the model is asked for one
    short sentence anyway (``max_tokens`` ends one that runs on).
    """
    reason: dict[str, Any] = {"type": "string"}
    if reason_chars is not None:
        reason.update(minLength=1, maxLength=reason_chars)
    return {
        "type": "object",
        "properties": {"reason": reason, "needed": {"type": "boolean"}},
        "required": ["reason", "needed"],
        "additionalProperties": False,
    }


Progress = Callable[[int, int, str], None]
"""Called after each candidate with (done, total, interface name)."""

_SYSTEM = """\
You pick the ROS 2 interfaces a robot skill needs.

{skill}

Candidates: {candidates}.

The user names one candidate. Answer with a JSON object:
- reason: a few words, what the skill would use it for, or why it would not;
- needed: true if a correct skill of this capability publishes, subscribes, calls or sends \
goals to it; false if the skill has no use for it."""

_FIELDS = 8


class _Answer(BaseModel):
    model_config = ConfigDict(extra="forbid")

    reason: str = Field(min_length=1)
    needed: bool


@dataclass(frozen=True)
class Judgement:
    """The model's verdict on one candidate."""

    name: str
    """The interface judged."""
    needed: bool | None
    """The verdict; ``None`` when the model gave no usable answer (see :attr:`reason`)."""
    reason: str
    """The model's reason, or why there is no verdict."""
    cached: bool = False
    """True when the answer came from the disk cache."""


@dataclass
class Reranking:
    """What the second stage did for one capability."""

    hits: list[Hit]
    """The judged hits, needed first (each with its verdict), then the rest unchanged."""
    model_id: str
    """The model that judged."""
    judgements: list[Judgement] = field(default_factory=list)
    """One per judged candidate, in the first stage's order."""
    asked: int = 0
    """Questions the model answered in this run."""
    cached: int = 0
    """Answers taken from the disk cache."""
    seconds: float = 0.0
    """Wall time of the stage."""
    notes: list[str] = field(default_factory=list)
    """One line per candidate without a usable answer."""

    def summary(self) -> str:
        """``3 of 8 judged needed; 8 asked (41.2 s)``."""
        needed = sum(j.needed is True for j in self.judgements)
        parts = [f"{needed} of {len(self.judgements)} judged needed"]
        if self.asked:
            parts.append(f"{self.asked} asked")
        if self.cached:
            parts.append(f"{self.cached} from the cache")
        return "; ".join(parts) + f" ({self.seconds:.1f} s)"


def default_cache() -> EnrichmentCache:
    """The per-user answer cache: ``rerank.sqlite`` in the cache folder."""
    return EnrichmentCache(cache_dir() / "rerank.sqlite", what="re-ranking cache")


def _parameter_line(parameter: Parameter) -> str:
    first = parameter.element
    line = f"{parameter.name} ({parameter.describe()})"
    definition = parameter.comment or first.definition
    return f"{line}: {definition}" if definition else line


def skill_summary(capability: Capability, spec: SkillSpec | None) -> str:
    """The capability and the specification, as short as the model can still use them."""
    lines = [f"Capability: {capability.label}."]
    if capability.comment:
        lines[0] += f" {' '.join(capability.comment.split())}"
    for title, parameters in (("Inputs", capability.inputs), ("Outputs", capability.outputs)):
        if parameters:
            lines.append(f"{title}: " + "; ".join(_parameter_line(p) for p in parameters))
    if capability.constraints:
        lines.append("Constraints: " + "; ".join(c.text for c in capability.constraints))
    if spec is not None:
        description = " ".join(spec.description.split())
        if description.lower() not in lines[0].lower():
            lines.append(f"Skill: {description}")
        for state, text in spec.states.items():
            lines.append(f"- {state}: {' '.join(text.split())}")
    return "\n".join(lines)


def candidate_text(interface: Interface) -> str:
    """One candidate as the model reads it: name, kind, type, fields, what it is for."""
    lines = [
        f"Interface: {interface.name}",
        f"Kind: {interface.kind}",
        f"Type: {interface.type_name}",
    ]
    paths = field_paths(interface, depth=1)
    if paths:
        more = ", ..." if len(paths) > _FIELDS else ""
        lines.append(f"Fields: {', '.join(paths[:_FIELDS])}{more}")
    purpose = describe(interface).purpose
    if purpose:
        lines.append(f"About: {purpose}")
    return "\n".join(lines)


def reorder(hits: Sequence[Hit], judgements: Sequence[Judgement]) -> list[Hit]:
    """The judged hits with their verdicts, needed first, then without a verdict, then not
    needed, each group in the first stage's order; unjudged hits follow unchanged."""
    verdicts = {j.name: j for j in judgements}
    judged = [
        replace(h, needed=verdicts[h.name].needed, judgement=verdicts[h.name].reason)
        for h in hits
        if h.name in verdicts
    ]
    group = {True: 0, None: 1, False: 2}
    judged.sort(key=lambda h: group[h.needed])  # stable: the first stage's order stays
    return judged + [h for h in hits if h.name not in verdicts]


class Reranker:
    """Asks a loaded generation model about each of the first :data:`DEPTH` hits."""

    def __init__(
        self,
        generator: TextGenerator,
        *,
        cache: EnrichmentCache | None = None,
        depth: int = DEPTH,
        max_tokens: int = 80,
        reason_chars: int | None = None,
    ) -> None:
        self.generator = generator
        """The loaded model."""
        self.cache = cache
        """Where answers are kept (``None``: ask every time)."""
        self.depth = depth
        """How many hits are judged."""
        self.max_tokens = max_tokens
        """Token budget of one answer; an answer cut off there gives no verdict."""
        self.schema = answer_schema(reason_chars)
        """The answers' JSON schema."""

    def prompt(
        self,
        capability: Capability,
        spec: SkillSpec | None,
        candidates: Sequence[Interface],
        interface: Interface,
    ) -> Prompt:
        """The question about ``interface``; everything before it is the shared prefix."""
        from skillwright.llm.base import Prompt

        names = ", ".join(f"{c.name} ({c.type_name.rsplit('/', 1)[-1]})" for c in candidates)
        system = _SYSTEM.format(skill=skill_summary(capability, spec), candidates=names)
        return Prompt.chat(candidate_text(interface), system=system)

    def cache_key(self, prompt: Prompt) -> str:
        """A hash of the model id, the prompt version, the schema and every prompt turn."""
        document = {
            "model": self.generator.model_id,
            "version": PROMPT_VERSION,
            "schema": self.schema,
            "max_tokens": self.max_tokens,
            "messages": [[m.role, m.content] for m in prompt.messages],
        }
        text = json.dumps(document, sort_keys=True, ensure_ascii=False)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    def rerank(
        self,
        inventory: Inventory,
        capability: Capability,
        spec: SkillSpec | None,
        hits: Sequence[Hit],
        *,
        progress: Progress | None = None,
        cancel: threading.Event | None = None,
    ) -> Reranking:
        """Judges the first :attr:`depth` of ``hits`` and puts the needed ones first.

        Raises :class:`~skillwright.errors.OperationCancelledError` once ``cancel`` is set.
        """
        from skillwright.cancel import raise_if_cancelled

        started = time.perf_counter()
        judged = list(hits[: self.depth])
        interfaces = [inventory.interface(h.name, h.kind) for h in judged]  # type: ignore[arg-type]
        result = Reranking(hits=list(hits), model_id=self.generator.model_id)
        for done, interface in enumerate(interfaces, 1):
            raise_if_cancelled(cancel, "re-ranking the interfaces")
            prompt = self.prompt(capability, spec, interfaces, interface)
            judgement = self._judge(interface, prompt, result, cancel)
            result.judgements.append(judgement)
            if progress is not None:
                progress(done, len(interfaces), interface.name)
        result.hits = reorder(hits, result.judgements)
        result.seconds = time.perf_counter() - started
        return result

    def _judge(
        self,
        interface: Interface,
        prompt: Prompt,
        result: Reranking,
        cancel: threading.Event | None,
    ) -> Judgement:
        from skillwright.cancel import raise_if_cancelled
        from skillwright.errors import ContextOverflowError
        from skillwright.llm.base import GenerationOptions

        key = self.cache_key(prompt)
        stored = None if self.cache is None else _stored(self.cache.get(key))
        if isinstance(stored, _Answer):
            result.cached += 1
            return Judgement(interface.name, stored.needed, stored.reason, cached=True)
        if isinstance(stored, str):
            result.cached += 1
            return self._no_verdict(interface, stored, result)
        options = GenerationOptions(
            max_tokens=self.max_tokens,
            temperature=0.0,
            json_schema=self.schema,
            save_prefix=False,
        )
        try:
            stream = self.generator.stream(prompt, options, cancel)
            text = stream.text()
        except ContextOverflowError as error:
            return self._no_verdict(interface, f"could not take the prompt ({error})", result)
        if stream.finish_reason == "cancelled":
            raise_if_cancelled(cancel, "re-ranking the interfaces")
        result.asked += 1
        if stream.finish_reason == "length":
            answer: _Answer | str = (
                f"stopped at the {self.max_tokens}-token limit before finishing its answer"
            )
        else:
            answer = _parse(text)
        if self.cache is not None:
            # At temperature 0 the same prompt gets the same answer: one the model cannot
            # finish or gets wrong is kept too, so that asking again costs nothing either.
            document = {"no_verdict": answer} if isinstance(answer, str) else answer.model_dump()
            self.cache.put(key, self.generator.model_id, json.dumps(document))
        if isinstance(answer, str):
            return self._no_verdict(interface, answer, result)
        return Judgement(interface.name, answer.needed, answer.reason)

    def _no_verdict(self, interface: Interface, why: str, result: Reranking) -> Judgement:
        note = f"{interface.name}: model {self.generator.model_id!r} {why}; its place is kept"
        result.notes.append(note)
        return Judgement(interface.name, None, f"no verdict: the model {why}")


def _stored(text: str | None) -> _Answer | str | None:
    """A cached answer, the reason a cached question got no verdict, or ``None`` (nothing
    usable stored)."""
    if text is None:
        return None
    try:
        document = json.loads(text)
    except json.JSONDecodeError:
        return None
    if isinstance(document, dict) and isinstance(document.get("no_verdict"), str):
        return str(document["no_verdict"])
    answer = _parse(text)
    return answer if isinstance(answer, _Answer) else None


def _parse(text: str) -> _Answer | str:
    """The answer, or what is wrong with it."""
    try:
        document = json.loads(text, strict=False)
    except json.JSONDecodeError as error:
        return f"gave an answer that is not JSON ({error.msg} at character {error.pos})"
    try:
        answer = _Answer.model_validate(document)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(p) for p in first["loc"]) or "the answer"
        return f"gave an invalid answer ({where}: {first['msg']})"
    return answer.model_copy(update={"reason": " ".join(answer.reason.split())})
