"""Stage 3: fill every interface's description and relevance verdict, with one of two engines.

- :class:`RulesEngine` — deterministic, no model: :func:`~skillwright.interfaces.description.
  describe_by_rules` and :func:`~skillwright.interfaces.relevance.relevance_by_rules`. It takes
  well under a millisecond per interface, so nothing of it is cached.
- :class:`LlmEngine` — a local model answers one JSON object per interface (description and
  verdict together), constrained by a JSON schema while it generates. The prompt starts with
  a fixed prefix (system text, instructions, two worked examples) so the llama.cpp prefix
  cache evaluates it once. Valid answers are cached on disk by the interface's content, the
  model id and :data:`PROMPT_VERSION`; an answer that fails validation falls back to the rules
  engine for that interface, with a note that names both.

:func:`enrich` drives either engine over an inventory, reporting progress through a callback
and stopping between interfaces (or between tokens) when a :class:`threading.Event` is set,
so the command line and the TUI share it.
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
import threading
import unicodedata
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Protocol

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from skillwright.interfaces.description import MODULES, describe_by_rules
from skillwright.interfaces.inventory import Description, Interface, Inventory, Relevance
from skillwright.interfaces.relevance import relevance_by_rules
from skillwright.paths import cache_dir

if TYPE_CHECKING:
    from skillwright.llm.base import Prompt, TextGenerator

__all__ = [
    "PROMPT_VERSION",
    "AnswerLimits",
    "Engine",
    "EnrichReport",
    "EnrichmentCache",
    "LlmEngine",
    "Outcome",
    "Progress",
    "RulesEngine",
    "answer_schema",
    "content_hash",
    "default_cache",
    "enrich",
    "trimmed_definition",
]

PROMPT_VERSION = 1
"""Bumped whenever the prompt or the answer schema changes, so cached answers are not reused."""

Progress = Callable[[int, int, str], None]
"""Called after each interface with (done, total, interface name)."""


@dataclass(frozen=True)
class Outcome:
    """What an engine made of one interface."""

    description: Description
    relevance: Relevance
    note: str | None = None
    """Set when the engine could not do its own work and fell back, saying why."""
    answer: str | None = None
    """The model's validated answer (JSON), to cache; ``None`` for nothing to cache."""


class Engine(Protocol):
    """Describes and judges one interface at a time."""

    name: str
    """Recorded as the description's and verdict's ``engine``: ``rules`` or a model id."""

    def cache_key(self, interface: Interface) -> str | None:
        """The key of this interface's answer in the disk cache; ``None``: never cached."""
        ...

    def from_cache(self, interface: Interface, answer: str) -> Outcome | None:
        """The outcome from a cached answer; ``None`` if the answer no longer validates."""
        ...

    def run(self, interface: Interface, cancel: threading.Event | None) -> Outcome | None:
        """The outcome for ``interface``; ``None`` when ``cancel`` stopped the work."""
        ...


def _field_paths(interface: Interface) -> list[str]:
    # The same key-field candidates retrieval derives when nothing is stored.
    from skillwright.retrieval.documents import field_paths

    return field_paths(interface, depth=2)


class RulesEngine:
    """The deterministic engine: name, kind, type, fields and ROS conventions, no model."""

    name = "rules"

    def cache_key(self, interface: Interface) -> str | None:
        """Nothing to cache: the rules take well under a millisecond."""
        return None

    def from_cache(self, interface: Interface, answer: str) -> Outcome | None:
        """Never called (see :meth:`cache_key`)."""
        return None

    def run(self, interface: Interface, cancel: threading.Event | None = None) -> Outcome:
        """The rules' description and verdict."""
        return Outcome(
            description=describe_by_rules(
                interface.kind, interface.name, interface.type_name, _field_paths(interface)
            ),
            relevance=relevance_by_rules(interface),
        )


# ---------------------------------------------------------------------- the disk cache


class EnrichmentCache:
    """Validated model answers in SQLite, keyed by :meth:`LlmEngine.cache_key`.

    Each answer is written in its own transaction, so an interrupted run keeps what it
    finished and a re-run resumes there.
    """

    def __init__(self, path: Path, *, what: str = "enrichment cache") -> None:
        self.path = path
        """The SQLite file."""
        self.what = what
        """What the file is, for error messages."""

    def _connect(self) -> sqlite3.Connection:
        from skillwright.errors import InputFileError

        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            connection = sqlite3.connect(self.path, timeout=30)
            connection.execute(
                "CREATE TABLE IF NOT EXISTS answers (key TEXT PRIMARY KEY, model TEXT NOT NULL,"
                " answer TEXT NOT NULL)"
            )
        except (OSError, sqlite3.DatabaseError) as error:
            raise InputFileError(
                f"{self.path}: the {self.what} cannot be opened ({error}); delete the "
                "file or set SKILLWRIGHT_CACHE_DIR to a writable folder"
            ) from error
        return connection

    def get(self, key: str) -> str | None:
        """The answer stored under ``key``, if any."""
        connection = self._connect()
        try:
            row = connection.execute("SELECT answer FROM answers WHERE key = ?", (key,)).fetchone()
        finally:
            connection.close()
        return None if row is None else str(row[0])

    def put(self, key: str, model_id: str, answer: str) -> None:
        """Stores ``answer`` under ``key``."""
        connection = self._connect()
        try:
            with connection:
                connection.execute(
                    "INSERT OR REPLACE INTO answers VALUES (?, ?, ?)", (key, model_id, answer)
                )
        finally:
            connection.close()

    def __len__(self) -> int:
        connection = self._connect()
        try:
            return int(connection.execute("SELECT COUNT(*) FROM answers").fetchone()[0])
        finally:
            connection.close()


def default_cache() -> EnrichmentCache:
    """The per-user cache: ``enrich.sqlite`` in :func:`~skillwright.paths.cache_dir`."""
    return EnrichmentCache(cache_dir() / "enrich.sqlite")


def content_hash(interface: Interface) -> str:
    """SHA-256 of what an engine reads: name, kind, type and the raw definitions.

    Enrichment results, traffic and QoS are left out, so describing an inventory does not
    change the hash of its interfaces.
    """
    document = {
        "name": interface.name,
        "kind": interface.kind,
        "type": interface.type_name,
        "definitions": {role: d.raw for role, d in sorted(interface.definitions.items())},
    }
    text = json.dumps(document, sort_keys=True, ensure_ascii=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


# ---------------------------------------------------------------------- the LLM engine

_ROLE_ORDER = ("message", "goal", "request", "response", "result", "feedback")
_DEFINITION_LINES = 24
_DEFINITION_CHARS = 1600


def _main_block(raw: str) -> str:
    # A ros2msg definition lists its dependencies after the main block, each behind a line of
    # '=' and 'MSG: pkg/Type'; the model needs the interface's own fields, not theirs.
    lines = []
    for line in raw.splitlines():
        if line.startswith(("=====", "MSG: ")):
            break
        lines.append(line)
    return "\n".join(lines)


def trimmed_definition(interface: Interface) -> str:
    """The definitions a prompt shows: main blocks only, comments and deep nesting removed.

    Nested fields that a source expanded in place (indented by tabs, as ``ros2 interface
    show`` prints them) are kept one level deep; each role is cut at a fixed number of lines
    and the whole at a fixed number of characters, so one huge message cannot crowd out the
    prompt.
    """
    roles = sorted(
        interface.definitions,
        key=lambda r: (_ROLE_ORDER.index(r) if r in _ROLE_ORDER else len(_ROLE_ORDER), r),
    )
    parts = []
    for role in roles:
        definition = interface.definitions[role]
        if definition.encoding not in {"ros2msg", "unknown"}:
            continue
        kept = []
        for line in _main_block(definition.raw).splitlines():
            depth = len(line) - len(line.lstrip("\t"))
            text = line.split("#", 1)[0].rstrip()
            if not text.strip() or depth > 1:
                continue
            kept.append(text)
        if len(kept) > _DEFINITION_LINES:
            kept = [*kept[:_DEFINITION_LINES], "\t..."]
        if kept:
            parts.append(f"[{role}]\n" + "\n".join(kept))
    text = "\n".join(parts)
    if len(text) > _DEFINITION_CHARS:
        text = text[:_DEFINITION_CHARS].rsplit("\n", 1)[0] + "\n..."
    return text or "(no definition available)"


@dataclass(frozen=True)
class AnswerLimits:
    """Bounds on the model's answer, enforced by the JSON schema while it generates.

    String lengths are unbounded by default: a length bound becomes a long chain of
    optional characters in the llama.cpp grammar, which makes every sampled token several
    times slower, and a model that writes one sentence ends its strings long before
    ``max_tokens`` anyway.
    """

    text_chars: int | None = None
    """Longest ``purpose`` and ``reason`` (``None``: unbounded)."""
    item_chars: int | None = None
    """Longest entry of ``tasks``, ``used_by`` and ``key_fields`` (``None``: unbounded)."""
    items: int = 6
    """Most entries in each of those lists."""


class _Answer(BaseModel):
    model_config = ConfigDict(extra="forbid")

    purpose: str = Field(min_length=1)
    module: Literal[MODULES]  # type: ignore[valid-type]
    tasks: list[str]
    used_by: list[str]
    key_fields: list[str]
    reason: str = Field(min_length=1)
    category: Literal["control", "infrastructure"]


def answer_schema(limits: AnswerLimits) -> dict[str, Any]:
    """The JSON schema the model's answer must follow."""

    def text(max_length: int | None) -> dict[str, Any]:
        schema: dict[str, Any] = {"type": "string"}
        if max_length is not None:
            schema.update(minLength=1, maxLength=max_length)
        return schema

    def items() -> dict[str, Any]:
        return {"type": "array", "items": text(limits.item_chars), "maxItems": limits.items}

    properties = {
        "purpose": text(limits.text_chars),
        "module": {"type": "string", "enum": list(MODULES)},
        "tasks": items(),
        "used_by": items(),
        "key_fields": items(),
        # The reason comes before the verdict: the model argues, then decides.
        "reason": text(limits.text_chars),
        "category": {"type": "string", "enum": ["control", "infrastructure"]},
    }
    return {
        "type": "object",
        "properties": properties,
        "required": list(properties),
        "additionalProperties": False,
    }


_SYSTEM = f"""\
You describe the ROS 2 interfaces of one robot for engineers who write robot skills.
For the interface you are given, answer with one JSON object and nothing else:
- purpose: one sentence, what the interface does. Use only what its name, type and fields
  show and what the ROS 2 convention for that type is; never invent robot details.
- module: the module of the robot it belongs to, one of: {", ".join(MODULES)}.
- tasks: short verb phrases, the tasks a skill would use it for (empty if none).
- used_by: who publishes, subscribes, calls or serves it (nodes, tools, people).
- key_fields: the field paths that matter most, exactly as in the definition.
- reason: one sentence: does it command, sense or plan for the robot, or is it plumbing?
- category: "control" if it commands, senses or plans for the robot; "infrastructure" for
  ROS 2 and tooling plumbing: parameter services, type descriptions, lifecycle transitions
  and bring-up, logging (rosout), parameter events, clock, performance metrics, robot model
  text, visualisation, and services of the simulator itself."""

_EXAMPLES: tuple[tuple[str, dict[str, Any]], ...] = (
    (
        "Interface: /scan\nKind: topic\nType: sensor_msgs/msg/LaserScan\nDefinition:\n"
        "[message]\nstd_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\n"
        "float32 angle_increment\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\n"
        "float32[] intensities",
        {
            "purpose": "2-D range measurements around the robot from a laser scanner.",
            "module": "perception",
            "tasks": ["detect obstacles", "find the nearest object", "mapping"],
            "used_by": ["lidar driver", "SLAM", "costmaps"],
            "key_fields": ["ranges", "angle_min", "angle_increment", "range_max"],
            "reason": "It senses the robot's surroundings.",
            "category": "control",
        },
    ),
    (
        "Interface: /arm_controller/set_parameters\nKind: service\n"
        "Type: rcl_interfaces/srv/SetParameters\nDefinition:\n[request]\n"
        "Parameter[] parameters\n\tstring name\n\tParameterValue value\n[response]\n"
        "SetParametersResult[] results\n\tbool successful\n\tstring reason",
        {
            "purpose": "Sets parameters of the arm_controller node, each on its own.",
            "module": "system",
            "tasks": ["configuration", "tuning"],
            "used_by": ["ros2 param CLI", "rqt"],
            "key_fields": ["parameters", "results"],
            "reason": "A parameter service every node offers: configuration, not control.",
            "category": "infrastructure",
        },
    ),
)


def _clean(value: Any) -> Any:
    """Strings with control characters removed and whitespace collapsed, recursively."""
    if isinstance(value, str):
        return " ".join("".join(c for c in value if unicodedata.category(c) != "Cc").split())
    if isinstance(value, list):
        return [_clean(v) for v in value]
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    return value


def _question(interface: Interface) -> str:
    return (
        f"Interface: {interface.name}\nKind: {interface.kind}\nType: {interface.type_name}\n"
        f"Definition:\n{trimmed_definition(interface)}"
    )


def _all_paths(interface: Interface) -> set[str] | None:
    """Every field path of the parsed definitions, or ``None`` when none was parsed."""
    from skillwright.retrieval.documents import field_paths

    if not any(d.fields for d in interface.definitions.values()):
        return None
    return set(field_paths(interface, depth=6))


class LlmEngine:
    """Describes and judges interfaces with a local model, one JSON answer per interface."""

    def __init__(
        self,
        generator: TextGenerator,
        *,
        max_tokens: int | None = None,
        limits: AnswerLimits | None = None,
    ) -> None:
        self.generator = generator
        """The loaded model."""
        self.name = generator.model_id
        self.max_tokens = max_tokens
        """Token budget of one answer (``None``: the model's ``max_tokens`` in models.toml);
        an answer cut off there falls back to the rules."""
        self.limits = limits or AnswerLimits()
        """Bounds on the answer, part of its JSON schema."""
        self.schema = answer_schema(self.limits)
        """The answer's JSON schema."""

    def prompt(self, interface: Interface) -> Prompt:
        """The chat prompt for ``interface``: the fixed prefix, then its question."""
        from skillwright.llm.base import ChatMessage, Prompt

        prefix = []
        for question, answer in _EXAMPLES:
            prefix.append(ChatMessage("user", question))
            prefix.append(ChatMessage("assistant", json.dumps(answer)))
        return Prompt.chat(_question(interface), system=_SYSTEM, prefix=prefix)

    def cache_key(self, interface: Interface) -> str:
        """Interface content, model id, prompt version and answer limits, hashed."""
        limits = self.limits
        parts = [
            content_hash(interface),
            self.name,
            f"prompt-v{PROMPT_VERSION}",
            f"limits-{limits.text_chars}-{limits.item_chars}-{limits.items}",
        ]
        return hashlib.sha256("\n".join(parts).encode("utf-8")).hexdigest()

    def _fallback(self, interface: Interface, why: str) -> Outcome:
        rules = RulesEngine().run(interface)
        note = f"{interface.name}: model {self.name!r} {why}; the rules engine described it"
        return Outcome(rules.description, rules.relevance, note=note)

    def _outcome(self, interface: Interface, answer: _Answer) -> Outcome:
        known = _all_paths(interface)
        key_fields = [f for f in answer.key_fields if f]
        if known is not None:
            # A key field the definition does not have is an invented one: drop it.
            key_fields = [f for f in key_fields if f in known]
        limit = self.limits.items

        def clean(values: Iterable[str]) -> list[str]:
            return [v for v in values if v][:limit]

        return Outcome(
            description=Description(
                purpose=answer.purpose,
                module=answer.module,
                tasks=clean(answer.tasks),
                used_by=clean(answer.used_by),
                key_fields=key_fields[:limit],
                engine=self.name,
            ),
            relevance=Relevance(
                relevant=answer.category == "control",
                category=answer.category,
                reason=answer.reason,
                engine=self.name,
            ),
            answer=answer.model_dump_json(),
        )

    def _validate(self, text: str) -> _Answer | str:
        """The parsed answer, or what is wrong with it."""
        try:
            # Lenient about raw control characters inside strings: llama.cpp's JSON grammar
            # lets them through, and they are cleaned out below.
            document = json.loads(text, strict=False)
        except json.JSONDecodeError as error:
            return f"gave an answer that is not JSON ({error.msg} at character {error.pos})"
        try:
            answer = _Answer.model_validate(_clean(document))
        except ValidationError as error:
            first = error.errors()[0]
            where = ".".join(str(p) for p in first["loc"]) or "the answer"
            return f"gave an invalid answer ({where}: {first['msg']})"
        return answer

    def from_cache(self, interface: Interface, answer: str) -> Outcome | None:
        """The outcome from a cached answer (validated again: the cache is only a file)."""
        parsed = self._validate(answer)
        return None if isinstance(parsed, str) else self._outcome(interface, parsed)

    def run(self, interface: Interface, cancel: threading.Event | None = None) -> Outcome | None:
        """Asks the model; falls back to the rules (with a note) when its answer is unusable."""
        from skillwright.errors import ContextOverflowError
        from skillwright.llm.base import GenerationOptions

        options = GenerationOptions(max_tokens=self.max_tokens, json_schema=self.schema)
        try:
            stream = self.generator.stream(self.prompt(interface), options, cancel)
            text = stream.text()
        except ContextOverflowError as error:
            return self._fallback(interface, f"could not take the prompt ({error})")
        if stream.finish_reason == "cancelled":
            return None
        if stream.finish_reason == "length":
            limit = (
                f"the {self.max_tokens}-token limit"
                if self.max_tokens is not None
                else "its max_tokens limit (models.toml)"
            )
            return self._fallback(interface, f"stopped at {limit} before finishing its answer")
        parsed = self._validate(text)
        if isinstance(parsed, str):
            return self._fallback(interface, parsed)
        return self._outcome(interface, parsed)


# ---------------------------------------------------------------------- driving an engine


@dataclass
class EnrichReport:
    """What :func:`enrich` did."""

    inventory: Inventory
    """The inventory with descriptions and verdicts filled in (a copy; the input is kept)."""
    engine: str
    """The engine's name."""
    described: int = 0
    """Interfaces the engine worked out in this run."""
    cached: int = 0
    """Interfaces whose answer came from the disk cache."""
    kept: int = 0
    """Interfaces whose description came with the source and was kept (verdict filled)."""
    notes: list[str] = field(default_factory=list)
    """One line per fallback: which interface, which model, what went wrong."""
    cancelled: bool = False
    """True when the cancel event stopped the run; later interfaces are unchanged."""

    @property
    def control(self) -> int:
        """Interfaces with a ``control`` verdict."""
        return sum(
            i.relevance is not None and i.relevance.category == "control"
            for i in self.inventory.interfaces
        )

    @property
    def infrastructure(self) -> int:
        """Interfaces with an ``infrastructure`` verdict."""
        return sum(
            i.relevance is not None and i.relevance.category == "infrastructure"
            for i in self.inventory.interfaces
        )

    def summary(self) -> list[str]:
        """What happened, as short phrases for a status line or a summary."""
        parts = [f"{self.described} described by {self.engine}"]
        if self.cached:
            parts.append(f"{self.cached} from the cache")
        if self.kept:
            parts.append(f"{self.kept} report descriptions kept (verdicts filled)")
        if self.notes:
            parts.append(f"{len(self.notes)} fell back to the rules engine")
        return parts


def enrich(
    inventory: Inventory,
    engine: Engine,
    *,
    cache: EnrichmentCache | None = None,
    progress: Progress | None = None,
    cancel: threading.Event | None = None,
    replace_source_descriptions: bool = False,
) -> EnrichReport:
    """Describes and judges every interface of ``inventory`` with ``engine``.

    Descriptions that came with the source (a report's, ``engine == "report"``) are kept
    unless ``replace_source_descriptions``; their verdicts are still filled. ``cache`` is
    read and written for engines that cache (the LLM engine); ``None`` disables it.
    """
    result = inventory.model_copy(deep=True)
    report = EnrichReport(inventory=result, engine=engine.name)
    total = len(result.interfaces)
    for index, interface in enumerate(result.interfaces):
        if cancel is not None and cancel.is_set():
            report.cancelled = True
            break
        outcome = _outcome_for(interface, engine, cache, cancel, report)
        if outcome is None:
            report.cancelled = True
            break
        keep = (
            interface.description is not None
            and interface.description.engine == "report"
            and not replace_source_descriptions
        )
        if keep:
            report.kept += 1
        else:
            interface.description = outcome.description
        interface.relevance = outcome.relevance
        if outcome.note is not None:
            report.notes.append(outcome.note)
        if progress is not None:
            progress(index + 1, total, interface.name)
    return report


def _outcome_for(
    interface: Interface,
    engine: Engine,
    cache: EnrichmentCache | None,
    cancel: threading.Event | None,
    report: EnrichReport,
) -> Outcome | None:
    key = engine.cache_key(interface) if cache is not None else None
    if key is not None and cache is not None:
        stored = cache.get(key)
        if stored is not None:
            outcome = engine.from_cache(interface, stored)
            if outcome is not None:
                report.cached += 1
                return outcome
    outcome = engine.run(interface, cancel)
    if outcome is None:
        return None
    report.described += 1
    if key is not None and cache is not None and outcome.answer is not None:
        cache.put(key, engine.name, outcome.answer)
    return outcome
