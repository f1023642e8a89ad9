"""``record.json``: how one skill was made, enough to repeat it and to judge it later.

It names every input with its checksum, the inventory's checksum, what retrieval chose
(and what the user pinned or dropped), the model and its file's checksum, the sampling
settings, how the prompt was fitted, what the model's answer contributed, the time each
stage took, and the check results.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Final, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from skillwright.errors import FileFormatError, InputFileError, InputFileNotFoundError
from skillwright.generation.model import Attempt, CandidateVerdict
from skillwright.rules.finding import Finding

__all__ = [
    "RECORD_SCHEMA_VERSION",
    "ChecksRecord",
    "FileDigest",
    "GenerationRecord",
    "HitRecord",
    "InputsRecord",
    "InterfacesRecord",
    "ModelRecord",
    "RerankRecord",
    "RetrievalRecord",
    "RunEpisodeRecord",
    "RunRecord",
    "SimulationRecord",
    "SkeletonRecord",
    "VerdictRecord",
]

RECORD_SCHEMA_VERSION: Final = 2
"""2: the model writes method by method (``model.attempts``); 1: one whole-file answer.
``run``, ``simulation``, ``retrieval.rerank``, ``retrieval.min_share``, a hit's
``set_aside``, ``simulation.trace`` and ``verdicts`` are optional additions to 2 (records
without them still load)."""


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class FileDigest(_Model):
    """An input file and its SHA-256."""

    path: str = Field(description="Path as given.")
    sha256: str = Field(description="SHA-256 of its bytes.")


class InterfacesRecord(_Model):
    """Where the robot's interfaces came from."""

    location: str = Field(description="The source as given (file, folder or inventory).")
    kinds: list[str] = Field(description="Source kinds in the inventory (mcap, report, ...).")
    inventory_sha256: str = Field(description="SHA-256 of the inventory as JSON.")
    interfaces: int = Field(description="How many interfaces it lists.")


class InputsRecord(_Model):
    """The inputs of the generation."""

    capability: FileDigest
    capability_iri: str = Field(description="The capability implemented.")
    spec: FileDigest
    interfaces: InterfacesRecord


class HitRecord(_Model):
    """One interface given to the generator."""

    name: str
    kind: str
    type_name: str
    score: float | None = Field(
        description="Retrieval score; null for a pinned extra or one added because a state "
        "stops the base (its reason says so)."
    )
    dense: float | None = None
    lexical: float | None = None
    reason: str
    needed: bool | None = Field(
        default=None, description="The re-ranking model's verdict; null when not asked."
    )
    judgement: str | None = Field(
        default=None, description="The re-ranking model's reason; null when not asked."
    )
    twins: list[str] = Field(
        default_factory=list,
        description="Topics of the same type the interface list cannot tell apart from this "
        "one (no endpoint counts): one of them may be the one the robot uses.",
    )
    pinned: bool = Field(default=False, description="Forced in by the user.")
    set_aside: bool = Field(
        default=False,
        description="Among the first k but scoring under the request's min_share of the best "
        "hit's score: not given to the generator.",
    )


class RerankRecord(_Model):
    """What the re-ranking stage did."""

    model: str = Field(description="The generation model that judged the candidates.")
    judged: int = Field(description="Candidates judged.")
    asked: int = Field(description="Questions answered in this run (the rest were cached).")
    cached: int = Field(description="Answers taken from the cache.")
    seconds: float
    notes: list[str] = Field(default_factory=list, description="Candidates without a verdict.")


class RetrievalRecord(_Model):
    """What retrieval chose."""

    k: int
    min_share: float = Field(
        default=0.0,
        description="Hits scoring under this share of the best were set aside (0: none).",
    )
    method: Literal["hybrid", "lexical"] = Field(description="Scores used.")
    rerank: RerankRecord | None = Field(
        default=None, description="The model's second stage, when it ran."
    )
    include_infrastructure: bool
    hits: list[HitRecord]
    pinned: list[str] = Field(default_factory=list, description="Names the user forced in.")
    dropped: list[str] = Field(default_factory=list, description="Names the user removed.")
    seconds: float | None = None


class SkeletonRecord(_Model):
    """The deterministic part."""

    class_name: str
    skill_iri: str
    unimplemented: list[str] = Field(description="States the skeleton left to be written.")
    notes: list[str] = Field(default_factory=list)


class ModelRecord(_Model):
    """The model that wrote the behaviour, and how it was asked."""

    id: str
    backend: str
    file: str | None = Field(default=None, description="Model file (local models).")
    sha256: str | None = Field(default=None, description="SHA-256 of the model file.")
    context_length: int
    sampling: dict[str, Any] = Field(description="Sampling settings used.")
    prompt_version: int
    prompt_tokens: int | None = Field(
        default=None, description="Tokens of the longest prompt (the last answer's context)."
    )
    completion_tokens: int | None = Field(default=None, description="Tokens written in all.")
    tokens_per_second: float | None = Field(
        default=None, description="Written tokens per second of generation, over all answers."
    )
    finish_reason: str | None = None
    prefix_cache: str = Field(description="How the cached prefix was obtained.")
    max_tokens: int | None = Field(
        default=None, description="Token budget of one answer of execute."
    )
    short_max_tokens: int | None = Field(
        default=None, description="Token budget of one answer of another state or a helper."
    )
    attempts_allowed: int | None = Field(
        default=None, description="Answers per method at most (first + repairs)."
    )
    run_repairs_allowed: int | None = Field(
        default=None,
        description="Repairs beyond attempts_allowed once only the run's or simulation's "
        "findings are left.",
    )
    candidates_asked: int | None = Field(
        default=None,
        description="Candidate skills asked for in the first round (1: the greedy answer).",
    )
    candidates: list[CandidateVerdict] = Field(
        default_factory=list,
        description="Every candidate of a best-of-N first round, its verdict and the winner.",
    )
    card: str | None = Field(default=None, description="The task card the model was given.")
    attempts: list[Attempt] = Field(
        default_factory=list, description="Every answer, in the order asked, with its verdict."
    )
    states_written: list[str] = Field(default_factory=list)
    states_missing: list[str] = Field(default_factory=list)
    added: list[str] = Field(default_factory=list, description="Imports and attributes added.")
    # Records of schema 1 (one whole-file answer) also have these:
    definition_style: str | None = None
    examples: int | None = None
    shortened: list[str] = Field(default_factory=list)
    extraction: str | None = None
    merged: bool | None = None
    left_out: list[str] = Field(default_factory=list)


class ChecksRecord(_Model):
    """The static checks' verdict."""

    passed: bool
    errors: int
    warnings: int
    findings: list[Finding]


class RunEpisodeRecord(_Model):
    """One episode of the run stage, in short (the runtime's trace, summarised)."""

    name: str = Field(description="`normal`, or `stop` (a Stop during execute).")
    ended: str = Field(description="How the sandboxed process ended (`done`, `killed`, ...).")
    states: list[str] = Field(
        default_factory=list, description="`state outcome` in the order run, e.g. `execute done`."
    )
    virtual_seconds: float
    wall_seconds: float
    outputs: dict[str, Any] = Field(default_factory=dict, description="Outputs read at the end.")
    published: dict[str, int] = Field(
        default_factory=dict, description="Messages the skill published, by topic."
    )
    goals: int = Field(default=0, description="Action goals the skill sent.")


class RunRecord(_Model):
    """The run stage: the skill's states in the sandbox against the simulated graph."""

    passed: bool = Field(description="Ran, and no finding is an error.")
    skipped: str | None = Field(default=None, description="Why it did not run, if it did not.")
    world: str | None = Field(default=None, description="The world the run used.")
    inputs: dict[str, Any] = Field(default_factory=dict, description="Inputs by name.")
    errors: int = 0
    warnings: int = 0
    findings: list[Finding] = Field(default_factory=list, description="At the skill's lines.")
    episodes: list[RunEpisodeRecord] = Field(default_factory=list)
    isolation: dict[str, str] = Field(
        default_factory=dict,
        description="How the sandbox held the skill: its namespaces (or `none "
        "(--unsafe-no-isolation)`), the seccomp programs, Landlock, the uid it ran as.",
    )
    seconds: float | None = Field(default=None, description="Wall time of the run.")
    repair_runs: int = Field(
        default=0, description="Runs made while the model repaired its answers."
    )


class VerdictRecord(_Model):
    """One oracle's verdict on one run in the simulation."""

    scenario: str | None = Field(default=None, description="The scenario it was judged in.")
    episode: str = Field(description="`normal`, or `stop` (a Stop during execute).")
    oracle: str
    kind: str = Field(description="Family: outcome, constraint, truth, limit, contact, rest, ...")
    check: str = Field(description="What it checks.")
    passed: bool | None = Field(description="None when it does not apply.")
    message: str
    measured: dict[str, Any] = Field(default_factory=dict)
    tolerance: float | None = None
    time: float | None = Field(default=None, description="Virtual time of the violation.")
    state: str | None = Field(default=None, description="The state running at a violation.")


class SimulationRecord(_Model):
    """The simulate stage: the skill in MuJoCo in every scenario of the capability."""

    passed: bool = Field(
        description="Simulated, every oracle of every scenario passed and no error was found."
    )
    skipped: str | None = Field(default=None, description="Why it did not run, if it did not.")
    scenario: str | None = Field(
        default=None,
        description="The default scenario's name (the first): world, inputs and plot are its.",
    )
    others: list[str] = Field(
        default_factory=list,
        description="The capability's other scenarios, simulated too (their verdicts name them).",
    )
    scenario_source: str | None = Field(default=None, description="Where it came from.")
    world: str | None = None
    inputs: dict[str, Any] = Field(default_factory=dict)
    verdicts: list[VerdictRecord] = Field(default_factory=list)
    findings: list[Finding] = Field(
        default_factory=list, description="Run findings and failed oracles, at the skill's lines."
    )
    plot: str | None = Field(
        default=None, description="The trajectory plot, a file in the output folder."
    )
    trace: str | None = Field(
        default=None,
        description="The default scenario's trace with the base's ground truth at 20 Hz (JSON), "
        "a file in the output folder: what the plot is drawn from.",
    )
    speed: float | None = Field(default=None, description="Virtual per wall seconds, normal run.")
    seconds: float | None = Field(default=None, description="Wall time of the validation.")
    repair_runs: int = Field(
        default=0, description="Simulations made while the model repaired its answers."
    )

    @property
    def where(self) -> str:
        """The scenarios simulated, for a summary line."""
        if not self.others:
            return str(self.scenario)
        return f"{self.scenario} and {len(self.others)} more scenario(s)"

    def verdict_place(self, verdict: VerdictRecord) -> str:
        """Where ``verdict`` was given, for a line of its own: the episode, after the
        scenario's name when there were several."""
        if self.others and verdict.scenario:
            return f"{verdict.scenario} {verdict.episode}"
        return verdict.episode


class GenerationRecord(_Model):
    """Everything about one generation."""

    schema_version: Literal[1, 2] = RECORD_SCHEMA_VERSION
    skillwright_version: str
    created: str = Field(description="ISO 8601 time the generation finished.")
    mode: Literal["llm", "skeleton"]
    skill_name: str
    inputs: InputsRecord
    retrieval: RetrievalRecord
    skeleton: SkeletonRecord
    model: ModelRecord | None = None
    timings: dict[str, float] = Field(description="Seconds per stage.")
    checks: ChecksRecord
    run: RunRecord | None = Field(default=None, description="The run stage, when it ran.")
    simulation: SimulationRecord | None = Field(
        default=None, description="The simulate stage, when it ran."
    )
    files: list[str] = Field(description="Files written into the output folder.")
    notes: list[str] = Field(default_factory=list, description="What the user should know.")
    verdicts: dict[str, str] = Field(
        default_factory=dict,
        description="Each stage's verdict (passed, failed, fixed automatically, skipped, not "
        "run; skillwright.pipeline.verdict), as the TUI and the generate command show it.",
    )

    @classmethod
    def load(cls, path: Path) -> GenerationRecord:
        """Reads a ``record.json``; errors name the file and what is wrong."""
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise InputFileNotFoundError(f"record {path}: no such file") from None
        except (OSError, UnicodeDecodeError) as error:
            raise InputFileError(f"record {path}: cannot be read ({error})") from None
        try:
            return cls.model_validate(json.loads(text))
        except json.JSONDecodeError as error:
            raise FileFormatError(
                f"{path}:{error.lineno}:{error.colno}: JSON syntax error: {error.msg}"
            ) from None
        except ValidationError as error:
            first = error.errors()[0]
            where = ".".join(str(p) for p in first["loc"])
            raise FileFormatError(
                f"{path}: not a generation record at {where}: {first['msg']}"
            ) from None
