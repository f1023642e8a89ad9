"""The main job: capability + specification + interfaces -> a checked skill in a folder.

Stages (each timed, each announced through ``on_event``): read the inputs, retrieve the
interfaces the capability needs, write the skeleton, load the model, fit the prompt,
generate and merge the behaviour into the skeleton, run the static checks, write the
output folder. Without a model (``skeleton=True``, or the default model's file is not
installed) the skeleton is the result, and the record and a notice say so plainly.

Nothing is written until everything else succeeded; a cancel (``cancel`` set) raises
:class:`~skillwright.errors.GenerationCancelledError` and writes nothing.
"""

from __future__ import annotations

import ast
import difflib
import hashlib
import json
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Literal, cast

from skillwright.errors import (
    GenerationCancelledError,
    InvalidArgumentError,
    ModelFileMissingError,
)
from skillwright.pipeline.events import (
    Event,
    GenerationStats,
    Notice,
    PrefixCacheStatus,
    StageFinished,
    StageStarted,
    TokenChunk,
)
from skillwright.pipeline.record import (
    ChecksRecord,
    FileDigest,
    GenerationRecord,
    HitRecord,
    InputsRecord,
    InterfacesRecord,
    ModelRecord,
    RetrievalRecord,
    SkeletonRecord,
)

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityLoad
    from skillwright.generation.model import InterfaceRef, Skeleton
    from skillwright.interfaces.inventory import Interface, Inventory
    from skillwright.llm.base import TextGenerator
    from skillwright.llm.config import Registry
    from skillwright.retrieval.retrieve import Embedder, Hit
    from skillwright.spec.model import SkillSpec
    from skillwright.validation.model import CheckReport

__all__ = ["GenerationRequest", "Outcome", "RetrievalResult", "retrieve", "run_generation"]

EventSink = Callable[[Event], None]


@dataclass(frozen=True)
class GenerationRequest:
    """Everything one generation needs."""

    capability: Path
    spec: Path
    interfaces: Path
    out_dir: Path
    capability_iri: str | None = None
    model: str | None = None
    """A ``models.toml`` id or alias; ``None``: the default model, or the skeleton when its
    file is not installed."""
    skeleton: bool = False
    """Write the deterministic skeleton only, with no model."""
    k: int = 4
    include_infrastructure: bool = False
    pinned: tuple[str, ...] = ()
    dropped: tuple[str, ...] = ()
    models_file: Path | None = None
    dense: bool = True
    """Use the embedding model in retrieval (else lexical scores only)."""


@dataclass
class RetrievalResult:
    """The loaded inputs and the ranked interfaces."""

    capability: CapabilityLoad
    spec: SkillSpec | None
    inventory: Inventory
    hits: list[Hit]
    method: Literal["hybrid", "lexical"] = "hybrid"


@dataclass
class Outcome:
    """Where the result is and what it is."""

    out_dir: Path
    skill_path: Path
    record_path: Path
    record: GenerationRecord
    report: CheckReport
    mode: Literal["llm", "skeleton"]
    hits: list[Hit]
    backups: list[Path] = field(default_factory=list)


class _Stages:
    """Announces and times stages; stops at the next stage once cancelled."""

    def __init__(self, on_event: EventSink | None, cancel: threading.Event | None) -> None:
        self.on_event = on_event
        self.cancel = cancel
        self.timings: dict[str, float] = {}

    def emit(self, event: Event) -> None:
        if self.on_event is not None:
            self.on_event(event)

    def check_cancel(self) -> None:
        if self.cancel is not None and self.cancel.is_set():
            raise GenerationCancelledError("generation cancelled; nothing was written")

    @contextmanager
    def stage(self, name: str, detail: str) -> Iterator[list[str]]:
        """Runs a stage; the body may append a result summary to the yielded list."""
        self.check_cancel()
        self.emit(StageStarted(name, detail))
        started = time.perf_counter()
        summary: list[str] = []
        yield summary
        seconds = time.perf_counter() - started
        self.timings[name] = round(seconds, 4)
        self.emit(StageFinished(name, seconds, "; ".join(summary)))


def _sha256(path: Path) -> str:
    from skillwright.core import sha256_file

    return sha256_file(path)


def _registry(models_file: Path | None) -> Registry:
    from skillwright.llm.config import load_registry

    return load_registry(models_file)


def _known_names(inventory: Inventory, names: Sequence[str], what: str) -> None:
    known = {i.name for i in inventory.interfaces}
    for name in names:
        if name not in known:
            close = difflib.get_close_matches(name, sorted(known), n=3)
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise InvalidArgumentError(
                f"{what} interface {name!r} is not in the inventory{hint}; "
                "list them with `skillwright inventory show`"
            )


def _rank(
    capability: CapabilityLoad,
    spec: SkillSpec | None,
    inventory: Inventory,
    *,
    k: int,
    include_infrastructure: bool,
    dense: bool,
    models_file: Path | None,
    dropped: Sequence[str] = (),
    cancel: threading.Event | None = None,
) -> tuple[list[Hit], Literal["hybrid", "lexical"]]:
    from skillwright.cancel import raise_if_cancelled
    from skillwright.retrieval.retrieve import rank_interfaces

    pool = inventory
    if dropped:
        pool = inventory.model_copy(
            update={"interfaces": [i for i in inventory.interfaces if i.name not in dropped]}
        )
    embed: Embedder | None = None
    if dense:
        from skillwright.llm.embeddings import load_embedder

        # Loading the embedding model (torch first) takes seconds: look before and after.
        raise_if_cancelled(cancel, "retrieval")
        embed = cast("Embedder", load_embedder(_registry(models_file)).embed)
    hits = rank_interfaces(
        pool,
        capability.capability,
        spec,
        k=k,
        include_infrastructure=include_infrastructure,
        embed=embed,
        cancel=cancel,
    )
    return hits, "hybrid" if dense else "lexical"


def retrieve(
    capability: Path,
    spec: Path | None,
    interfaces: Path,
    *,
    capability_iri: str | None = None,
    k: int = 4,
    include_infrastructure: bool = False,
    dense: bool = True,
    models_file: Path | None = None,
    dropped: Sequence[str] = (),
    cancel: threading.Event | None = None,
) -> RetrievalResult:
    """Loads the inputs and ranks the interfaces (what the TUI's retrieval view shows).

    Once ``cancel`` is set, :class:`~skillwright.errors.OperationCancelledError` is raised
    at the next step: between the inputs, around the embedding model's load, between the
    ranking's phases (see :mod:`skillwright.cancel`).
    """
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.spec.loader import load_spec

    load = load_capability(capability, capability_iri=capability_iri, cancel=cancel)
    skill_spec = load_spec(spec) if spec is not None else None
    inventory = load_inventory(interfaces, cancel=cancel)
    _known_names(inventory, dropped, "dropped")
    hits, method = _rank(
        load,
        skill_spec,
        inventory,
        k=k,
        include_infrastructure=include_infrastructure,
        dense=dense,
        models_file=models_file,
        dropped=dropped,
        cancel=cancel,
    )
    return RetrievalResult(load, skill_spec, inventory, hits, method)


def _with_pins(hits: list[Hit], inventory: Inventory, pinned: Sequence[str]) -> list[HitRecord]:
    records = [
        HitRecord(
            name=h.name,
            kind=h.kind,
            type_name=h.type_name,
            score=round(h.score, 4),
            dense=None if h.dense is None else round(h.dense, 4),
            lexical=round(h.lexical, 4),
            reason=h.reason,
            pinned=h.name in pinned,
        )
        for h in hits
    ]
    chosen = {h.name for h in hits}
    for name in pinned:
        if name in chosen:
            continue
        interface = inventory.interface(name)
        records.append(
            HitRecord(
                name=name,
                kind=interface.kind,
                type_name=interface.type_name,
                score=None,
                reason="pinned by the user",
                pinned=True,
            )
        )
        chosen.add(name)
    return records


def _interface_refs(
    inventory: Inventory, chosen: Sequence[HitRecord]
) -> list[tuple[Interface, InterfaceRef]]:
    from skillwright.generation.model import InterfaceRef
    from skillwright.generation.skeleton import topic_role

    out = []
    for hit in chosen:
        interface = inventory.interface(hit.name, hit.kind)  # type: ignore[arg-type]
        role: Literal["publish", "subscribe", "call"] = (
            topic_role(hit.name, hit.type_name) if hit.kind == "topic" else "call"
        )
        ref = InterfaceRef(name=hit.name, kind=interface.kind, type_name=hit.type_name, role=role)
        out.append((interface, ref))
    return out


def _inventory_digest(inventory: Inventory) -> str:
    return hashlib.sha256(inventory.model_dump_json().encode("utf-8")).hexdigest()


@dataclass
class _ModelResult:
    code: str
    response: str
    prompt_text: str
    record: ModelRecord
    answer: str | None = None
    """The model's code when it could not be merged (written as ``answer.py``)."""
    note: str | None = None


def _load_model(
    request: GenerationRequest, stages: _Stages
) -> tuple[TextGenerator | None, Registry | None]:
    """The generator, or ``None`` when the skeleton is all that can be written."""
    from skillwright.llm import load_generator

    registry = _registry(request.models_file)
    try:
        return load_generator(registry, request.model), registry
    except ModelFileMissingError as error:
        if request.model is not None:
            raise
        stages.emit(
            Notice(
                "warning",
                f"no model: {error} Writing the skeleton only; its states still raise "
                f"NotImplementedError. Use --skeleton to skip the model on purpose.",
            )
        )
        return None, registry


def _generate(
    generator: TextGenerator,
    registry: Registry,
    request: GenerationRequest,
    load: CapabilityLoad,
    spec: SkillSpec,
    chosen: Sequence[tuple[Interface, InterfaceRef]],
    skeleton: Skeleton,
    stages: _Stages,
) -> _ModelResult:
    from skillwright.generation.examples import few_shot_examples
    from skillwright.generation.extract import extract_code
    from skillwright.generation.merge import merge_into_skeleton
    from skillwright.generation.prompt import PROMPT_VERSION, fit_prompt
    from skillwright.llm.base import GenerationOptions

    entry = registry.generation_model(request.model)
    answer_tokens = entry.sampling.max_tokens
    with stages.stage("prompt", "fitting the prompt to the model's context") as summary:
        build = fit_prompt(
            load.capability,
            spec,
            [(interface, ref.role) for interface, ref in chosen],
            skeleton,
            few_shot_examples(),
            count_tokens=generator.count_tokens,
            context_length=generator.context_length,
            answer_tokens=answer_tokens,
            model_id=generator.model_id,
        )
        summary.append(f"{build.tokens} tokens, {build.examples} examples")
        if build.shortened:
            summary.append("shortened: " + ", ".join(build.shortened))
    with stages.stage("generation", f"{generator.model_id} writes the behaviour") as summary:
        started = time.perf_counter()
        stream = generator.stream(
            build.prompt, GenerationOptions(max_tokens=answer_tokens), cancel=stages.cancel
        )
        parts: list[str] = []
        for chunk in stream:
            if not parts:
                stages.emit(PrefixCacheStatus(stream.prefix_cache))
            parts.append(chunk)
            stages.emit(TokenChunk(chunk))
        stages.check_cancel()
        seconds = time.perf_counter() - started
        tokens = stream.completion_tokens or stream.completion_chunks
        rate = None
        if stream.first_chunk_at is not None and stream.finished_at is not None and tokens > 1:
            span = stream.finished_at - stream.first_chunk_at
            rate = (tokens - 1) / span if span > 0 else None
        stages.emit(GenerationStats(stream.prompt_tokens, tokens, rate, seconds))
        summary.append(f"{tokens} tokens" + (f", {rate:.1f} tokens/s" if rate else ""))
        if stream.finish_reason == "length":
            stages.emit(
                Notice(
                    "warning",
                    f"the answer hit max_tokens ({answer_tokens}); it may be cut short — raise "
                    f"`max_tokens` of {generator.model_id!r} in models.toml",
                )
            )
    response = "".join(parts)
    extracted = extract_code(response)
    merged = merge_into_skeleton(
        skeleton.code,
        skeleton.class_name,
        list(spec.states),
        extracted.code,
        author=f"the local model {generator.model_id}",
    )
    model_file = getattr(generator, "model_file", None)
    record = ModelRecord(
        id=generator.model_id,
        backend=entry.backend,
        file=None if model_file is None else str(model_file.path),
        sha256=None if model_file is None else model_file.sha256,
        context_length=generator.context_length,
        sampling=entry.sampling.model_dump(),
        prompt_version=PROMPT_VERSION,
        prompt_tokens=stream.prompt_tokens,
        completion_tokens=tokens,
        tokens_per_second=None if rate is None else round(rate, 2),
        finish_reason=stream.finish_reason,
        prefix_cache=stream.prefix_cache,
        definition_style=build.definition_style,
        examples=build.examples,
        shortened=list(build.shortened),
        extraction=extracted.method,
        merged=merged is not None,
        states_written=list(merged.written) if merged else [],
        states_missing=list(merged.missing) if merged else [],
        added=list(merged.added) if merged else [],
        left_out=list(merged.left_out) if merged else [],
    )
    if merged is not None:
        return _ModelResult(merged.code, response, build.text(), record)
    return _ModelResult(
        skeleton.code,
        response,
        build.text(),
        record,
        answer=extracted.code or None,
        note=_unmerged_note(extracted.code, extracted.method),
    )


def _unmerged_note(code: str, method: str) -> str:
    """Why the model's answer could not be merged, for the record and the user."""
    if method == "empty":
        return "the model's answer held no Python code (see response.txt); skill.py is the skeleton"
    try:
        ast.parse(code)
    except SyntaxError as error:
        return (
            f"the model's code does not parse (answer.py line {error.lineno}: {error.msg}); "
            "skill.py is the skeleton, answer.py the model's code to fix by hand"
        )
    return (
        "the model's code has no skill class with the specified states (see answer.py); "
        "skill.py is the skeleton"
    )


def _record(
    request: GenerationRequest,
    *,
    load: CapabilityLoad,
    spec: SkillSpec,
    inventory: Inventory,
    method: Literal["hybrid", "lexical"],
    chosen_hits: list[HitRecord],
    skeleton: Skeleton,
    model_result: _ModelResult | None,
    report: CheckReport,
    stages: _Stages,
    files: list[str],
    notes: list[str],
) -> GenerationRecord:
    from skillwright import __version__

    errors = sum(f.severity == "error" for f in report.findings)
    return GenerationRecord(
        skillwright_version=__version__,
        created=datetime.now(UTC).isoformat(timespec="seconds"),
        mode="skeleton" if model_result is None else "llm",
        skill_name=spec.name,
        inputs=InputsRecord(
            capability=FileDigest(path=str(request.capability), sha256=_sha256(request.capability)),
            capability_iri=load.capability.iri,
            spec=FileDigest(path=str(request.spec), sha256=_sha256(request.spec)),
            interfaces=InterfacesRecord(
                location=str(request.interfaces),
                kinds=sorted({s.kind for s in inventory.sources}),
                inventory_sha256=_inventory_digest(inventory),
                interfaces=len(inventory.interfaces),
            ),
        ),
        retrieval=RetrievalRecord(
            k=request.k,
            method=method,
            include_infrastructure=request.include_infrastructure,
            hits=chosen_hits,
            pinned=list(request.pinned),
            dropped=list(request.dropped),
            seconds=stages.timings.get("retrieval"),
        ),
        skeleton=SkeletonRecord(
            class_name=skeleton.class_name,
            skill_iri=skeleton.skill_iri,
            unimplemented=skeleton.unimplemented,
            notes=skeleton.notes,
        ),
        model=None if model_result is None else model_result.record,
        timings=stages.timings,
        checks=ChecksRecord(
            passed=report.passed,
            errors=errors,
            warnings=len(report.findings) - errors,
            findings=report.findings,
        ),
        files=files,
        notes=notes,
    )


def _model_stages(
    request: GenerationRequest,
    stages: _Stages,
    load: CapabilityLoad,
    spec: SkillSpec,
    chosen: Sequence[tuple[Interface, InterfaceRef]],
    skeleton: Skeleton,
) -> _ModelResult | None:
    """Loads the model and has it write the behaviour; ``None`` when there is no model."""
    if request.skeleton:
        return None
    generator: TextGenerator | None = None
    registry: Registry | None = None
    with stages.stage("model", f"loading {request.model or 'the default model'}") as s:
        generator, registry = _load_model(request, stages)
        s.append(generator.model_id if generator is not None else "not installed")
    model_result: _ModelResult | None = None
    try:
        if generator is not None and registry is not None:
            model_result = _generate(
                generator, registry, request, load, spec, chosen, skeleton, stages
            )
    finally:
        if generator is not None:
            generator.close()
    return model_result


def _result_files(
    skeleton: Skeleton, model_result: _ModelResult | None, notes: list[str]
) -> dict[str, str]:
    """The files of the output folder but the record; adds what the user must know to
    ``notes``."""
    if model_result is None:
        notes.append(
            "skeleton only: no model wrote behaviour; the states listed as unimplemented raise "
            "NotImplementedError until you write them"
        )
        return {"skill.py": skeleton.code}
    files = {
        "skill.py": model_result.code,
        "prompt.txt": model_result.prompt_text,
        "response.txt": model_result.response,
    }
    if model_result.answer is not None:
        files["answer.py"] = model_result.answer
    if model_result.note is not None:
        notes.append(model_result.note)
    return files


def run_generation(
    request: GenerationRequest,
    *,
    on_event: EventSink | None = None,
    cancel: threading.Event | None = None,
) -> Outcome:
    """Runs the whole pipeline and writes the output folder; see the module docstring."""
    from skillwright.capability.reader import load_capability
    from skillwright.generation.output import write_outputs
    from skillwright.generation.skeleton import build_skeleton
    from skillwright.interfaces.load import load_inventory
    from skillwright.spec.loader import load_spec
    from skillwright.validation.catalog import catalog_from_inventory
    from skillwright.validation.static import check_skill

    if request.k < 0:
        raise InvalidArgumentError(f"-k must be 0 or more, not {request.k}")
    stages = _Stages(on_event, cancel)
    notes: list[str] = []
    with stages.stage(
        "inputs", "reading the capability, the specification and the interfaces"
    ) as s:
        load = load_capability(request.capability, capability_iri=request.capability_iri)
        spec = load_spec(request.spec)
        inventory = load_inventory(request.interfaces)
        _known_names(inventory, request.pinned, "pinned")
        _known_names(inventory, request.dropped, "dropped")
        notes += load.warnings
        s.append(f"{load.capability.name}, {spec.name}, {len(inventory.interfaces)} interfaces")
    method = "hybrid" if request.dense else "lexical"
    with stages.stage("retrieval", f"top {request.k} interfaces ({method})") as s:
        hits, method = _rank(
            load,
            spec,
            inventory,
            k=request.k,
            include_infrastructure=request.include_infrastructure,
            dense=request.dense,
            models_file=request.models_file,
            dropped=request.dropped,
        )
        chosen_hits = _with_pins(hits, inventory, request.pinned)
        s.append(", ".join(h.name for h in chosen_hits) or "none")
    chosen = _interface_refs(inventory, chosen_hits)
    with stages.stage("skeleton", "structure, annotations and interface handles") as s:
        skeleton = build_skeleton(
            load.capability,
            spec,
            [ref for _, ref in chosen],
            source_note=f"Inputs: {request.capability.name}, {request.spec.name}.",
        )
        s.append(f"{skeleton.class_name}, {len(skeleton.unimplemented)} states to write")

    model_result = _model_stages(request, stages, load, spec, chosen, skeleton)
    files = _result_files(skeleton, model_result, notes)
    code = files["skill.py"]

    with stages.stage("checks", "static checks") as s:
        report = check_skill(
            code,
            capability=load.capability,
            spec=spec,
            catalog=catalog_from_inventory(inventory),
            retrieved=[h.name for h in chosen_hits],
            path=str(request.out_dir / "skill.py"),
        )
        errors = sum(f.severity == "error" for f in report.findings)
        s.append(f"{'passed' if report.passed else 'failed'}, {errors} error(s)")
    stages.check_cancel()

    record = _record(
        request,
        load=load,
        spec=spec,
        inventory=inventory,
        method=method,
        chosen_hits=chosen_hits,
        skeleton=skeleton,
        model_result=model_result,
        report=report,
        stages=stages,
        files=[*files, "record.json"],
        notes=notes,
    )
    with stages.stage("outputs", f"writing {request.out_dir}") as s:
        files["record.json"] = json.dumps(record.model_dump(mode="json"), indent=2) + "\n"
        backups = write_outputs(request.out_dir, files)
        s.append(f"{len(files)} files" + (f", {len(backups)} backed up" if backups else ""))
    record.timings = stages.timings
    return Outcome(
        out_dir=request.out_dir,
        skill_path=request.out_dir / "skill.py",
        record_path=request.out_dir / "record.json",
        record=record,
        report=report,
        mode=record.mode,
        hits=hits,
        backups=backups,
    )
