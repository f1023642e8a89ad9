"""What a behaviour validation returns: verdicts per scenario and run, findings, speed."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from skillwright.rules.finding import Finding
from skillwright.sim.oracles import Verdict

__all__ = ["EpisodeVerdicts", "ScenarioReport", "ValidationProgress", "ValidationReport"]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class EpisodeVerdicts(_Model):
    """One run of the skill in a scenario (the runtime runs it normally, then stops it)."""

    episode: Literal["normal", "stop"] = Field(description="Which run.")
    ended: str = Field(description="completed, stopped, aborted or failed.")
    verdicts: list[Verdict] = Field(default_factory=list, description="One per oracle.")
    virtual_seconds: float = Field(default=0.0, description="Virtual time the run took.")
    wall_seconds: float = Field(default=0.0, description="Wall time of the run, child included.")
    world_seconds: float = Field(
        default=0.0, description="Wall time in the world's advance, publishing included."
    )
    publish_seconds: float = Field(
        default=0.0, description="Of that, wall time the host took to take its messages."
    )
    child_cpu_seconds: float = Field(default=0.0, description="CPU time of the skill's process.")

    @property
    def passed(self) -> bool:
        """No oracle failed."""
        return not any(v.passed is False for v in self.verdicts)

    @property
    def speed(self) -> float | None:
        """Virtual seconds per wall second of the whole run (x real time)."""
        return self.virtual_seconds / self.wall_seconds if self.wall_seconds > 0 else None

    @property
    def world_speed(self) -> float | None:
        """Virtual seconds per wall second of the world alone (physics, sensors, controllers;
        not the host's taking of its messages); on a quiet machine that is its CPU time."""
        own = self.world_seconds - self.publish_seconds
        return self.virtual_seconds / own if own > 0 else None


class ScenarioReport(_Model):
    """A scenario, how the skill fared in it and where its artefacts are."""

    name: str = Field(description="The scenario's name.")
    description: str = Field(default="", description="What it checks.")
    world: str = Field(description="The world it ran in.")
    inputs: dict[str, Any] = Field(default_factory=dict, description="The skill's inputs.")
    episodes: list[EpisodeVerdicts] = Field(default_factory=list, description="In run order.")
    plot: str | None = Field(default=None, description="The trajectory plot (PNG).")
    trace: str | None = Field(default=None, description="The run's trace and ground truth (JSON).")
    notes: list[str] = Field(default_factory=list, description="What the world assumed.")
    host_cpu_seconds: float = Field(
        default=0.0, description="CPU time of this process for the scenario's runs."
    )

    @property
    def passed(self) -> bool:
        """Every run passed every oracle."""
        return all(e.passed for e in self.episodes) and bool(self.episodes)


class ValidationReport(_Model):
    """The result of :func:`~skillwright.sim.validate.validate_skill`."""

    skill: str = Field(description="The skill file.")
    capability: str = Field(description="IRI of the capability.")
    scenario_source: str = Field(description="Where the scenarios came from.")
    scenarios: list[ScenarioReport] = Field(default_factory=list, description="In order.")
    findings: list[Finding] = Field(
        default_factory=list,
        description="Run findings and failed oracles, located at the skill's lines.",
    )
    notes: list[str] = Field(default_factory=list, description="What was derived or assumed.")
    binding: dict[str, str] = Field(
        default_factory=dict,
        description="Capability name -> the skill's name of each input and output bound to it.",
    )
    wall_seconds: float = Field(default=0.0, description="Wall time of the whole validation.")

    @property
    def passed(self) -> bool:
        """Every scenario passed and no finding is an error."""
        return all(s.passed for s in self.scenarios) and not any(
            f.severity == "error" for f in self.findings
        )

    def failed_oracles(self) -> list[str]:
        """``scenario/episode/oracle`` of every failed verdict."""
        return [
            f"{s.name}/{e.episode}/{v.oracle}"
            for s in self.scenarios
            for e in s.episodes
            for v in e.verdicts
            if v.passed is False
        ]


@dataclass(frozen=True)
class ValidationProgress:
    """Progress of a validation, for a UI."""

    scenario: str
    index: int
    """0-based position of the scenario."""
    total: int
    event: Literal[
        "scenario-start", "episode-start", "state-start", "state-end", "episode-end", "scenario-end"
    ]
    episode: str | None = None
    state: str | None = None
    virtual_time: float = 0.0
