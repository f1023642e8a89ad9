"""The main job: capability + specification + interfaces -> a checked skill in a folder.

Stages (each timed, each announced through ``on_event``): read the inputs, retrieve the
interfaces the capability needs (ranked, then pinned, set aside or added by
:mod:`skillwright.retrieval.policy`), write the skeleton, load the model, have it write the
behaviour method by method (:mod:`skillwright.generation.author`) and repair what the checks
find (:mod:`skillwright.generation.repair`), run the static checks, then — when they find no
error — run the skill in the sandbox and simulate it in MuJoCo
(:mod:`skillwright.pipeline.behaviour`; their findings also feed the repair loop), and
write the output folder.
Without a model (``skeleton=True``, or the default model's file is not installed) the
skeleton is the result, and the record and a notice say so plainly.

Nothing is written until everything else succeeded; a cancel (``cancel`` set) raises
:class:`~skillwright.errors.GenerationCancelledError` and writes nothing. Ctrl-C
(``KeyboardInterrupt``, in the main thread) is a cancel too: it raises the same error, saying
in which stage it came and what was kept. The output folder's files are moved into place
with Ctrl-C held back, so an interrupt never leaves some of them new and some old.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import tempfile
import threading
import time
from collections.abc import Callable, Collection, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Literal, cast

from skillwright.errors import (
    GenerationCancelledError,
    InvalidArgumentError,
    ModelFileMissingError,
    OperationCancelledError,
)
from skillwright.llm.model_lock import note_activity
from skillwright.pipeline.behaviour import RUN_WORLD, Behaviour
from skillwright.pipeline.events import (
    Event,
    GenerationStats,
    ModelWaiting,
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
    RerankRecord,
    RetrievalRecord,
    RunRecord,
    SimulationRecord,
    SkeletonRecord,
)
from skillwright.pipeline.verdict import Verdict, behaviour_verdict, stage_verdicts, writing_verdict

if TYPE_CHECKING:
    from skillwright.capability.model import CapabilityLoad
    from skillwright.generation.model import InterfaceRef, Skeleton
    from skillwright.interfaces.inventory import Interface, Inventory
    from skillwright.llm.base import TextGenerator
    from skillwright.llm.config import Registry
    from skillwright.llm.model_lock import ModelWait
    from skillwright.retrieval.policy import Given
    from skillwright.retrieval.rerank import Reranking
    from skillwright.retrieval.retrieve import Embedder, Hit
    from skillwright.rules.finding import Finding
    from skillwright.spec.model import SkillSpec
from skillwright.rules.settings import Selection, project_selection
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
    ontologies: tuple[Path, ...] = ()
    """Local copies of ontologies the capability model imports (``--ontology``)."""
    model: str | None = None
    """A ``models.toml`` id or alias; ``None``: the default model, or the skeleton when its
    file is not installed."""
    skeleton: bool = False
    """Write the deterministic skeleton only, with no model."""
    k: int = 4
    min_share: float = 0.1
    """A hit scoring under this share of the best hit's score is set aside: the record keeps
    it, the skeleton does not get it (a small model uses every handle it is given)."""
    include_infrastructure: bool = False
    pinned: tuple[str, ...] = ()
    dropped: tuple[str, ...] = ()
    models_file: Path | None = None
    dense: bool = False
    """Use the embedding model in retrieval (else lexical scores only)."""
    rerank: bool = False
    """Have the generation model judge the best candidates after ranking
    (:mod:`skillwright.retrieval.rerank`); the model is then loaded during retrieval."""
    attempts: int = 3
    """Answers the model may give per method: the first, then repairs from the findings."""
    candidates: int = 1
    """Candidate skills of the first round, sampled in one batch and judged by every stage;
    repair starts from the best (:mod:`skillwright.generation.candidates`). 1: greedy only."""
    run: bool = True
    """Run a skill that passes the static checks in the sandbox (stage ``run``)."""
    simulate: bool = True
    """Validate a skill that passes the static checks in MuJoCo (stage ``simulate``)."""
    run_seconds: float = 120.0
    """Wall-clock budget of one run."""
    sim_seconds: float = 240.0
    """Wall-clock budget of one simulation."""
    isolated: bool = True
    """Run and simulate inside the kernel sandbox; ``False`` is ``--unsafe-no-isolation``."""
    scenario: Path | None = None
    """The scenario file the run and the simulation take their scenarios from (the first is the
    run's); ``None``: the shipped file for the capability, else scenarios derived from it."""
    select: tuple[str, ...] = ()
    """Rules to report and repair (codes, blocks, groups, names); the project's by default."""
    ignore: tuple[str, ...] = ()
    """Rules to leave out, besides the project's ignore."""


@dataclass
class RetrievalResult:
    """The loaded inputs and the ranked interfaces."""

    capability: CapabilityLoad
    spec: SkillSpec | None
    inventory: Inventory
    hits: list[Hit]
    method: Literal["hybrid", "lexical"] = "hybrid"
    reranking: Reranking | None = None
    """What the re-ranking stage did, when it ran."""


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

    @property
    def passed(self) -> bool:
        """The static checks passed, and the run and the simulation, where they ran."""
        run, simulation = self.record.run, self.record.simulation
        return (
            self.report.passed
            and (run is None or run.skipped is not None or run.passed)
            and (simulation is None or simulation.skipped is not None or simulation.passed)
        )


class _Stages:
    """Announces and times stages; stops at the next stage once cancelled."""

    def __init__(self, on_event: EventSink | None, cancel: threading.Event | None) -> None:
        note_activity(skill=None, stage=None)  # what a model lock's status says this run does
        self.on_event = on_event
        self.cancel = cancel
        self.timings: dict[str, float] = {}
        self.current: str | None = None
        """The stage running, or the last one started."""
        self.written: int | None = None
        """How many files the outputs stage wrote, once it has."""

    def interrupted(self, out_dir: Path) -> GenerationCancelledError:
        """The error for a Ctrl-C now: where it came and what was kept."""
        if self.written is not None:
            return GenerationCancelledError(
                f"generation interrupted after writing {out_dir}: its {self.written} files "
                "are complete"
            )
        when = "before its first stage" if self.current is None else f"in stage {self.current}"
        return GenerationCancelledError(
            f"generation interrupted {when}; nothing was written ({out_dir} is as it was)"
        )

    def emit(self, event: Event) -> None:
        if self.on_event is not None:
            self.on_event(event)

    def check_cancel(self) -> None:
        if self.cancel is not None and self.cancel.is_set():
            raise GenerationCancelledError("generation cancelled; nothing was written")

    @contextmanager
    def stage(self, name: str, detail: str) -> Iterator[_Summary]:
        """Runs a stage; the body may append a result summary to the yielded list and set
        its verdict (a stage that ends without a check of its own passed)."""
        self.check_cancel()
        self.current = name
        note_activity(stage=name)
        self.emit(StageStarted(name, detail))
        started = time.perf_counter()
        summary = _Summary()
        yield summary
        seconds = time.perf_counter() - started
        self.timings[name] = round(seconds, 4)
        self.emit(StageFinished(name, seconds, "; ".join(summary), summary.verdict.value))


class _Summary(list[str]):
    """A stage's result in a few phrases, and its verdict."""

    verdict = Verdict.PASSED


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
    reranker: TextGenerator | None = None,
) -> tuple[list[Hit], Literal["hybrid", "lexical"], Reranking | None]:
    """The ``k`` best hits; with ``reranker``, the first stage's best
    :data:`~skillwright.retrieval.rerank.DEPTH` judged by it, the needed ones first."""
    from skillwright.cancel import raise_if_cancelled
    from skillwright.retrieval.rerank import DEPTH, Reranker, default_cache
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
        k=k if reranker is None else max(k, DEPTH),
        include_infrastructure=include_infrastructure,
        embed=embed,
        cancel=cancel,
    )
    reranking = None
    if reranker is not None:
        reranking = Reranker(reranker, cache=default_cache()).rerank(
            pool, capability.capability, spec, hits, cancel=cancel
        )
        hits = reranking.hits
    return hits[:k], "hybrid" if dense else "lexical", reranking


def retrieve(
    capability: Path,
    spec: Path | None,
    interfaces: Path,
    *,
    capability_iri: str | None = None,
    ontologies: Sequence[Path] = (),
    k: int = 4,
    include_infrastructure: bool = False,
    dense: bool = False,
    models_file: Path | None = None,
    dropped: Sequence[str] = (),
    cancel: threading.Event | None = None,
    rerank: bool = False,
    model: str | None = None,
) -> RetrievalResult:
    """Loads the inputs and ranks the interfaces (what the TUI's retrieval view shows);
    ``ontologies`` are local copies of ontologies the capability model imports.

    With ``rerank``, the generation model ``model`` (default: the default one) judges the
    best candidates (see :mod:`skillwright.retrieval.rerank`).

    Once ``cancel`` is set, :class:`~skillwright.errors.OperationCancelledError` is raised
    at the next step: between the inputs, around the embedding model's load, between the
    ranking's phases (see :mod:`skillwright.cancel`).
    """
    from skillwright.cancel import raise_if_cancelled
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory
    from skillwright.spec.loader import load_spec

    load = load_capability(
        capability, capability_iri=capability_iri, ontologies=ontologies, cancel=cancel
    )
    skill_spec = load_spec(spec) if spec is not None else None
    inventory = load_inventory(interfaces, cancel=cancel)
    _known_names(inventory, dropped, "dropped")
    generator = None
    if rerank:
        from skillwright.llm import load_generator

        raise_if_cancelled(cancel, "retrieval")
        generator = load_generator(_registry(models_file), model)
    try:
        hits, method, reranking = _rank(
            load,
            skill_spec,
            inventory,
            k=k,
            include_infrastructure=include_infrastructure,
            dense=dense,
            models_file=models_file,
            dropped=dropped,
            cancel=cancel,
            reranker=generator,
        )
    finally:
        if generator is not None:
            generator.close()
    return RetrievalResult(load, skill_spec, inventory, hits, method, reranking)


def _hit_record(given: Given) -> HitRecord:
    """The record of one interface of the retrieval's result."""
    from skillwright.retrieval.policy import SCORE_PLACES

    hit = given.hit
    return HitRecord(
        name=given.name,
        kind=given.kind,
        type_name=given.type_name,
        score=given.score,
        dense=None if hit is None or hit.dense is None else round(hit.dense, SCORE_PLACES),
        lexical=None if hit is None else round(hit.lexical, SCORE_PLACES),
        reason=given.reason,
        needed=None if hit is None else hit.needed,
        judgement=None if hit is None else hit.judgement,
        twins=[] if hit is None else list(hit.twins),
        pinned=given.pinned,
        set_aside=given.set_aside,
    )


def _interface_refs(
    inventory: Inventory, chosen: Sequence[HitRecord]
) -> list[tuple[Interface, InterfaceRef]]:
    from skillwright.generation.model import InterfaceRef
    from skillwright.generation.skeleton import subscription_qos, topic_role

    out = []
    for hit in chosen:
        interface = inventory.interface(hit.name, hit.kind)  # type: ignore[arg-type]
        role: Literal["publish", "subscribe", "call"] = (
            topic_role(hit.name, hit.type_name) if hit.kind == "topic" else "call"
        )
        ref = InterfaceRef(
            name=hit.name,
            kind=interface.kind,
            type_name=hit.type_name,
            role=role,
            qos=subscription_qos(role, interface.qos),
        )
        out.append((interface, ref))
    return out


def _inventory_digest(inventory: Inventory) -> str:
    return hashlib.sha256(inventory.model_dump_json().encode("utf-8")).hexdigest()


@dataclass
class _ModelResult:
    code: str
    transcript: str
    record: ModelRecord
    skeleton: Skeleton
    """The skeleton the skill is built on: only the interfaces and helpers it uses."""
    notes: list[str] = field(default_factory=list)


def _load_model(
    request: GenerationRequest, stages: _Stages
) -> tuple[TextGenerator | None, Registry | None]:
    """The generator, or ``None`` when the skeleton is all that can be written. While another
    generation holds the model, this one waits and says so (:class:`ModelWaiting`)."""
    from skillwright.llm import load_generator

    def waiting(wait: ModelWait) -> None:
        holder = None if wait.holder is None else wait.holder.describe()
        stages.emit(ModelWaiting(wait.model, wait.place, wait.seconds, holder, wait.message()))

    registry = _registry(request.models_file)
    try:
        return (
            load_generator(registry, request.model, on_wait=waiting, cancel=stages.cancel),
            registry,
        )
    except OperationCancelledError as error:
        raise GenerationCancelledError(
            f"generation stopped: {error}; nothing was written ({request.out_dir} is as it was)"
        ) from None
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


class _StaticChecks:
    """The static checks of a candidate skill, against the interfaces its skeleton kept, as
    far as the project's rule selection reports them."""

    def __init__(
        self,
        load: CapabilityLoad,
        spec: SkillSpec,
        inventory: Inventory,
        path: Path,
        selection: Selection,
    ) -> None:
        from skillwright.validation.catalog import catalog_from_inventory

        self.load, self.spec, self.path, self.selection = load, spec, path, selection
        self.catalog = catalog_from_inventory(inventory)

    def report(self, code: str, skeleton: Skeleton) -> CheckReport:
        """The report of ``code``'s checks."""
        from skillwright.validation.static import check_skill

        report = check_skill(
            code,
            capability=self.load.capability,
            spec=self.spec,
            catalog=self.catalog,
            retrieved=[i.name for i in skeleton.interfaces],
            path=str(self.path),
        )
        return report.model_copy(update={"findings": self.selection.filter(report.findings)})

    def __call__(self, code: str, skeleton: Skeleton) -> list[Finding]:
        return self.report(code, skeleton).findings


def _static_validator(
    load: CapabilityLoad, spec: SkillSpec, inventory: Inventory, path: Path, selection: Selection
) -> _StaticChecks:
    """The static checks of a candidate skill (see :class:`_StaticChecks`)."""
    return _StaticChecks(load, spec, inventory, path, selection)


def _generate(
    generator: TextGenerator,
    registry: Registry,
    request: GenerationRequest,
    load: CapabilityLoad,
    spec: SkillSpec,
    inventory: Inventory,
    chosen: Sequence[tuple[Interface, InterfaceRef]],
    stages: _Stages,
    behaviour: Behaviour,
) -> _ModelResult:
    from skillwright.generation.author import (
        AttemptFinished,
        AttemptStarted,
        AuthorSettings,
        author_skill,
    )
    from skillwright.generation.card import CardInterface
    from skillwright.generation.conversation import PROMPT_VERSION
    from skillwright.generation.skeleton import build_skeleton
    from skillwright.generation.wiring import wire

    entry = registry.generation_model(request.model)
    wiring = wire(load.capability, spec, [ref for _, ref in chosen], pinned=request.pinned)
    wired = {ref.name for ref in wiring.wired}
    settings = AuthorSettings(
        attempts=request.attempts,
        max_tokens=entry.sampling.max_tokens,
        candidates=request.candidates,
    )
    written = 0
    seconds_writing = 0.0
    first_cache: list[str] = []

    def forward(event: object) -> None:
        nonlocal written, seconds_writing
        if isinstance(event, str):
            stages.emit(TokenChunk(event))
        elif isinstance(event, AttemptStarted):
            stages.emit(event)
        elif isinstance(event, AttemptFinished):
            attempt = event.attempt
            written += attempt.completion_tokens or 0
            seconds_writing += attempt.seconds
            if not first_cache and attempt.prefix_cache:
                first_cache.append(attempt.prefix_cache)
                stages.emit(PrefixCacheStatus(attempt.prefix_cache))
            stages.emit(event)

    def skeleton_for(refs: Sequence[InterfaceRef], helpers: Collection[str] | None) -> Skeleton:
        # Only the interfaces the specification or the capability calls for get handles
        # (generation.wiring); the card lists the others as not wired.
        return build_skeleton(
            load.capability,
            spec,
            [ref for ref in refs if ref.name in wired],
            source_note=f"Inputs: {request.capability.name}, {request.spec.name}.",
            helpers=helpers,
            unwired=wiring.unwired,
        )

    with stages.stage(
        "generation", f"{generator.model_id} writes {len(spec.states)} states, one at a time"
    ) as summary:
        started = time.perf_counter()
        authored = author_skill(
            generator,
            skeleton_for,
            load.capability,
            spec,
            [CardInterface(interface, ref) for interface, ref in chosen],
            behaviour.validator(
                _static_validator(
                    load, spec, inventory, request.out_dir / "skill.py", behaviour.selection
                )
            ),
            settings=settings,
            on_event=forward,
            cancel=stages.cancel,
        )
        seconds = time.perf_counter() - started
        rate = written / seconds_writing if seconds_writing > 0 else None
        prompt_tokens = max((a.prompt_tokens or 0 for a in authored.attempts), default=0)
        stages.emit(GenerationStats(prompt_tokens or None, written, rate, seconds))
        answers = [a for a in authored.attempts if a.finish != "fixed"]
        repairs = sum(a.number > 1 and a.candidate is None for a in answers)
        fixes = len(authored.attempts) - len(answers)
        summary.append(
            f"{len(answers)} answers ({repairs} repairs), {written} tokens"
            + (f", {fixes} fixed by the checks" if fixes else "")
            + (f", {rate:.1f} tokens/s" if rate else "")
            + (f", {behaviour.repair_runs} runs" if behaviour.repair_runs else "")
            + (f", {behaviour.repair_sims} simulations" if behaviour.repair_sims else "")
        )
        summary.verdict = writing_verdict(authored.assembly.missing, authored.attempts).verdict
        for attempt in authored.attempts:
            if attempt.finish == "length":
                stages.emit(
                    Notice(
                        "warning",
                        f"the answer for {attempt.target} (attempt {attempt.number}) hit the "
                        f"limit of {settings.budget(attempt.kind, attempt.target)} tokens"
                        + (
                            f"; raise `max_tokens` of {generator.model_id!r} in models.toml if "
                            "methods need more"
                            if attempt.target == "execute"
                            else " (every method but execute gets at most "
                            f"{settings.short_max_tokens}: a longer one should be split into "
                            "helpers)"
                        ),
                    )
                )
    model_file = getattr(generator, "model_file", None)
    final = authored.attempts[-1] if authored.attempts else None
    record = ModelRecord(
        id=generator.model_id,
        backend=entry.backend,
        file=None if model_file is None else str(model_file.path),
        sha256=None if model_file is None else model_file.sha256,
        context_length=generator.context_length,
        sampling=entry.sampling.model_dump(),
        prompt_version=PROMPT_VERSION,
        prompt_tokens=prompt_tokens or None,
        completion_tokens=written,
        tokens_per_second=None if rate is None else round(rate, 2),
        finish_reason=None if final is None else final.finish,
        prefix_cache=first_cache[0] if first_cache else "off",
        max_tokens=settings.max_tokens,
        short_max_tokens=settings.short_budget,
        attempts_allowed=settings.attempts,
        candidates_asked=settings.candidates,
        candidates=authored.candidates,
        run_repairs_allowed=settings.run_repairs,
        card=authored.card,
        attempts=authored.attempts,
        states_written=list(authored.assembly.written),
        states_missing=list(authored.assembly.missing),
        added=list(authored.assembly.added),
    )
    return _ModelResult(
        authored.code, authored.transcript, record, authored.skeleton, authored.notes
    )


def _record(
    request: GenerationRequest,
    *,
    load: CapabilityLoad,
    spec: SkillSpec,
    inventory: Inventory,
    method: Literal["hybrid", "lexical"],
    reranking: Reranking | None,
    chosen_hits: list[HitRecord],
    skeleton: Skeleton,
    model_result: _ModelResult | None,
    report: CheckReport,
    stages: _Stages,
    files: list[str],
    notes: list[str],
    run: RunRecord | None,
    simulation: SimulationRecord | None,
) -> GenerationRecord:
    from skillwright import __version__

    errors = sum(f.severity == "error" for f in report.findings)
    record = GenerationRecord(
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
            min_share=request.min_share,
            method=method,
            rerank=None
            if reranking is None
            else RerankRecord(
                model=reranking.model_id,
                judged=len(reranking.judgements),
                asked=reranking.asked,
                cached=reranking.cached,
                seconds=round(reranking.seconds, 3),
                notes=reranking.notes,
            ),
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
        run=run,
        simulation=simulation,
        files=files,
        notes=notes,
    )
    record.verdicts = {stage: v.verdict.word for stage, v in stage_verdicts(record).items()}
    return record


def _model_stages(
    request: GenerationRequest,
    stages: _Stages,
    load: CapabilityLoad,
    spec: SkillSpec,
    inventory: Inventory,
    chosen: Sequence[tuple[Interface, InterfaceRef]],
    behaviour: Behaviour,
    loaded: tuple[TextGenerator | None, Registry | None] | None = None,
) -> _ModelResult | None:
    """Loads the model (unless re-ranking ``loaded`` it) and has it write the behaviour;
    ``None`` when there is no model."""
    if request.skeleton:
        if loaded is not None and loaded[0] is not None:
            loaded[0].close()
        return None
    generator: TextGenerator | None = None
    registry: Registry | None = None
    with stages.stage("model", f"loading {request.model or 'the default model'}") as s:
        if loaded is None:
            generator, registry = _load_model(request, stages)
        else:
            generator, registry = loaded
            s.append("loaded for re-ranking")
        s.append(generator.model_id if generator is not None else "not installed")
    model_result: _ModelResult | None = None
    try:
        if generator is not None and registry is not None:
            model_result = _generate(
                generator, registry, request, load, spec, inventory, chosen, stages, behaviour
            )
    finally:
        if generator is not None:
            generator.close()
    return model_result


def _result_files(
    skeleton: Skeleton, model_result: _ModelResult | None, notes: list[str]
) -> dict[str, str | bytes]:
    """The files of the output folder but the record; adds what the user must know to
    ``notes``."""
    if model_result is None:
        notes.append(
            "skeleton only: no model wrote behaviour; the states listed as unimplemented raise "
            "NotImplementedError until you write them"
        )
        return {"skill.py": skeleton.code}
    notes += model_result.notes
    if model_result.record.states_missing:
        notes.append(
            "the model wrote no usable answer for "
            + ", ".join(model_result.record.states_missing)
            + "; those states still raise NotImplementedError (see conversation.txt)"
        )
    return {"skill.py": model_result.code, "conversation.txt": model_result.transcript}


PLOT_FILE = "simulation.png"
"""The simulation's trajectory plot in the output folder."""


TRACE_FILE = "simulation.trace.json"
"""The default scenario's trace with the base's ground truth in the output folder (what the
plot shows, as numbers: the TUI draws it in the terminal)."""


def _took(seconds: float | None) -> str:
    """How long the run or the simulation itself took: the repair loop may have run the
    same code already, and then the stage only reuses that result."""
    return "" if seconds is None else f"; took {seconds:.1f} s"


def _run_summary(run: RunRecord) -> str:
    if run.skipped is not None:
        return run.skipped
    normal = next((e for e in run.episodes if e.name == "normal"), None)
    verdict = f"{behaviour_verdict(run, True).verdict.word}, {run.errors} error(s)"
    if normal is not None:
        verdict += f"; {normal.virtual_seconds:.1f} s simulated in {normal.wall_seconds:.1f} s"
    return verdict + _took(run.seconds)


def _sim_summary(simulation: SimulationRecord) -> str:
    if simulation.skipped is not None:
        return simulation.skipped
    judged = [v for v in simulation.verdicts if v.passed is not None]
    failed = sorted({v.oracle for v in judged if v.passed is False})
    speed = f", {simulation.speed:.0f}x real time" if simulation.speed else ""
    head = f"{simulation.where}: {len(judged) - len(failed)}/{len(judged)} verdicts passed"
    return (
        head
        + speed
        + (f"; failed {', '.join(failed)}" if failed else "")
        + _took(simulation.seconds)
    )


def _behaviour_stages(
    behaviour: Behaviour,
    stages: _Stages,
    code: str,
    errors: int,
    files: dict[str, str | bytes],
    notes: list[str],
) -> tuple[RunRecord | None, SimulationRecord | None]:
    """The run and simulate stages, when the static checks found no error; a simulation's
    plot joins ``files``."""
    if not behaviour.enabled:
        return None, None
    if errors:
        skipped = f"the static checks found {errors} error(s)"
        run = RunRecord(passed=False, skipped=skipped) if behaviour.run_enabled else None
        sim = SimulationRecord(passed=False, skipped=skipped) if behaviour.sim_enabled else None
        return run, sim
    run_record: RunRecord | None = None
    sim_record: SimulationRecord | None = None
    if behaviour.run_enabled:
        with stages.stage(
            "run", f"the states in the sandbox against the simulated graph ({RUN_WORLD} world)"
        ) as s:
            run_record = behaviour.run_record(behaviour.run(code))
            s.verdict = behaviour_verdict(run_record, True).verdict
            s.append(_run_summary(run_record))
        stages.check_cancel()
    if behaviour.sim_enabled:
        with stages.stage(
            "simulate", "MuJoCo, every scenario of the capability and its oracles"
        ) as s:
            result = behaviour.simulate(code)
            for made, name in ((result.plot, PLOT_FILE), (result.trace, TRACE_FILE)):
                if made is not None and made.is_file():
                    files[name] = made.read_bytes()
            sim_record = behaviour.sim_record(
                result,
                PLOT_FILE if PLOT_FILE in files else None,
                TRACE_FILE if TRACE_FILE in files else None,
            )
            s.verdict = behaviour_verdict(sim_record, True).verdict
            s.append(_sim_summary(sim_record))
        stages.check_cancel()
    for name, record in (("run", run_record), ("simulation", sim_record)):
        if record is not None and record.skipped is not None:
            message = f"the {name} gave no verdict: {record.skipped}"
            notes.append(message)
            stages.emit(Notice("warning", message))
    return run_record, sim_record


_Loaded = tuple["TextGenerator | None", "Registry | None"]


def _retrieval_stage(
    request: GenerationRequest,
    stages: _Stages,
    load: CapabilityLoad,
    spec: SkillSpec,
    inventory: Inventory,
) -> tuple[
    list[Hit], Literal["hybrid", "lexical"], Reranking | None, list[HitRecord], _Loaded | None
]:
    """Ranks (and with ``request.rerank`` loads the model and re-ranks); the model loaded
    for re-ranking is returned for generation."""
    from skillwright.retrieval.policy import given_interfaces
    from skillwright.retrieval.retrieve import twin_notes

    # A model may be loaded from here on: its lock's status names the skill.
    note_activity(skill=spec.name)
    method = "hybrid" if request.dense else "lexical"
    loaded: _Loaded | None = None
    detail = f"top {request.k} interfaces ({method}{', re-ranked' if request.rerank else ''})"
    with stages.stage("retrieval", detail) as s:
        if request.rerank:
            loaded = _load_model(request, stages)
        try:
            hits, method, reranking = _rank(
                load,
                spec,
                inventory,
                k=request.k,
                include_infrastructure=request.include_infrastructure,
                dense=request.dense,
                models_file=request.models_file,
                dropped=request.dropped,
                cancel=stages.cancel,
                reranker=None if loaded is None else loaded[0],
            )
        except BaseException:
            if loaded is not None and loaded[0] is not None:
                loaded[0].close()
            raise
        result = given_interfaces(
            hits,
            inventory,
            spec,
            pinned=request.pinned,
            dropped=request.dropped,
            min_share=request.min_share,
        )
        chosen_hits = [_hit_record(g) for g in result]
        s.append(", ".join(h.name for h in chosen_hits if not h.set_aside) or "none")
        weak = [h.name for h in chosen_hits if h.set_aside]
        if weak:
            s.append(f"set aside, under {request.min_share:g} of the best score: {', '.join(weak)}")
        if reranking is not None:
            s.append(f"re-ranked: {reranking.summary()}")
            for note in reranking.notes:
                stages.emit(Notice("warning", note))
        given = {c.name for c in chosen_hits if not c.set_aside}
        pinned = set(request.pinned)
        undecided = [h for h in hits if h.name in given and not {h.name, *h.twins} & pinned]
        for note in twin_notes(undecided):
            stages.emit(Notice("warning", note))
    return hits, method, reranking, chosen_hits, loaded


def run_generation(
    request: GenerationRequest,
    *,
    on_event: EventSink | None = None,
    cancel: threading.Event | None = None,
) -> Outcome:
    """Runs the whole pipeline and writes the output folder; see the module docstring."""
    stages = _Stages(on_event, cancel)
    try:
        return _run_stages(request, stages, cancel)
    except KeyboardInterrupt:
        raise stages.interrupted(request.out_dir) from None


def _skeleton_stage(
    request: GenerationRequest,
    load: CapabilityLoad,
    spec: SkillSpec,
    refs: Sequence[InterfaceRef],
    say: Callable[[str], None],
) -> Skeleton:
    """The skeleton of the pipeline's skill: handles only for the interfaces the
    specification or the capability calls for (:mod:`skillwright.generation.wiring`), the
    others listed as not wired; ``say`` takes the stage's summary lines."""
    from skillwright.generation.skeleton import build_skeleton
    from skillwright.generation.wiring import wire

    wiring = wire(load.capability, spec, refs, pinned=request.pinned)
    skeleton = build_skeleton(
        load.capability,
        spec,
        wiring.wired,
        source_note=f"Inputs: {request.capability.name}, {request.spec.name}.",
        unwired=wiring.unwired,
    )
    say(f"{skeleton.class_name}, {len(skeleton.unimplemented)} states to write")
    if wiring.unwired:
        say("not wired: " + ", ".join(u.interface.name for u in wiring.unwired))
    if skeleton.assured:
        say("outputs set by the skeleton: " + ", ".join(skeleton.assured))
    return skeleton


def _run_stages(
    request: GenerationRequest, stages: _Stages, cancel: threading.Event | None
) -> Outcome:
    from skillwright.cancel import interrupts_held
    from skillwright.capability.reader import load_capability
    from skillwright.generation.output import write_outputs
    from skillwright.generation.skeleton import unstated_limits
    from skillwright.interfaces.load import load_inventory, read_warnings
    from skillwright.spec.loader import load_spec

    if request.k < 0:
        raise InvalidArgumentError(f"-k must be 0 or more, not {request.k}")
    selection = project_selection(Path.cwd()).narrowed(request.select, request.ignore)
    notes: list[str] = []
    with stages.stage(
        "inputs", "reading the capability, the specification and the interfaces"
    ) as s:
        load = load_capability(
            request.capability,
            capability_iri=request.capability_iri,
            ontologies=request.ontologies,
        )
        spec = load_spec(request.spec)
        inventory = load_inventory(request.interfaces)
        _known_names(inventory, request.pinned, "pinned")
        _known_names(inventory, request.dropped, "dropped")
        notes += read_warnings(inventory)
        notes += load.warnings
        notes += unstated_limits(load.capability, spec)
        s.append(f"{load.capability.name}, {spec.name}, {len(inventory.interfaces)} interfaces")
        if request.isolated and (request.run or request.simulate):
            # Before minutes of generation: a kernel that refuses the sandbox stops it here.
            from skillwright.runtime.sandbox import check_isolation

            check_isolation()
    retrieved = _retrieval_stage(request, stages, load, spec, inventory)
    hits, method, reranking, chosen_hits, loaded = retrieved
    chosen = _interface_refs(inventory, [h for h in chosen_hits if not h.set_aside])
    with stages.stage("skeleton", "structure, annotations and interface handles") as s:
        skeleton = _skeleton_stage(request, load, spec, [ref for _, ref in chosen], s.append)

    with tempfile.TemporaryDirectory(prefix="skillwright-behaviour-") as work:
        behaviour = Behaviour(
            load.capability,
            inventory,
            request.out_dir / "skill.py",
            Path(work),
            run=request.run,
            simulate=request.simulate,
            run_seconds=request.run_seconds,
            sim_seconds=request.sim_seconds,
            cancel=cancel,
            isolated=request.isolated,
            selection=selection,
            scenario_file=request.scenario,
        )
        model_result = _model_stages(
            request, stages, load, spec, inventory, chosen, behaviour, loaded
        )
        files = _result_files(skeleton, model_result, notes)
        code = skeleton.code if model_result is None else model_result.code
        kept = skeleton if model_result is None else model_result.skeleton

        with stages.stage("checks", "static checks") as s:
            report = _static_validator(
                load, spec, inventory, request.out_dir / "skill.py", selection
            ).report(code, kept)
            errors = sum(f.severity == "error" for f in report.findings)
            s.verdict = Verdict.PASSED if report.passed else Verdict.FAILED
            s.append(f"{s.verdict.word}, {errors} error(s)")
        stages.check_cancel()
        run_record, sim_record = _behaviour_stages(behaviour, stages, code, errors, files, notes)

    record = _record(
        request,
        load=load,
        spec=spec,
        inventory=inventory,
        method=method,
        reranking=reranking,
        chosen_hits=chosen_hits,
        skeleton=skeleton,
        model_result=model_result,
        report=report,
        stages=stages,
        files=[*files, "record.json"],
        notes=notes,
        run=run_record,
        simulation=sim_record,
    )
    with stages.stage("outputs", f"writing {request.out_dir}") as s:
        files["record.json"] = json.dumps(record.model_dump(mode="json"), indent=2) + "\n"
        with interrupts_held():
            backups = write_outputs(request.out_dir, files)
            stages.written = len(files)
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
