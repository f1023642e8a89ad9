"""What a run returns: findings located in the skill file, and the trace."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from skillwright.rules.finding import Finding

__all__ = ["EpisodeTrace", "RunProgress", "RunReport", "RunTrace", "StateRun"]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class StateRun(_Model):
    """One PackML state as it ran."""

    name: str = Field(description="The state, e.g. `execute`.")
    outcome: str = Field(
        description="`done`, `raised`, `interrupted` (by a Stop, a deadline or for running "
        "without waiting), `absent` (the skill has no method for it) or `killed`."
    )
    detail: str | None = Field(default=None, description="Exception type or interrupt reason.")
    started: float = Field(description="Virtual time it began (s).")
    ended: float | None = Field(default=None, description="Virtual time it ended (s).")
    wall_seconds: float = Field(default=0.0, description="Wall time it took.")


class EpisodeTrace(_Model):
    """One run of the skill in its own sandboxed process."""

    name: Literal["normal", "stop"] = Field(
        description="`normal`: starting, execute, completing, resetting; `stop`: a Stop "
        "command during execute."
    )
    ended: str = Field(
        description="`done`, `killed` (deadline, busy), `crashed` (the process died), "
        "`protocol` (the child broke the protocol) or `failed` (the skill did not load)."
    )
    states: list[StateRun] = Field(default_factory=list, description="In order.")
    outputs: dict[str, Any] = Field(
        default_factory=dict, description="Outputs read through the getters after completing."
    )
    events: list[dict[str, Any]] = Field(
        default_factory=list,
        description="What happened, in virtual-time order: endpoints, publishes, calls, "
        "responses, goals, feedback, results, cancels, logs, output, states, errors.",
    )
    dropped_events: int = Field(default=0, description="Events beyond the trace's limit.")
    virtual_seconds: float = Field(default=0.0, description="Virtual time at the end.")
    wall_seconds: float = Field(default=0.0, description="Wall time of the episode.")
    startup_seconds: float = Field(
        default=0.0, description="Wall time until the child had loaded and was ready to run."
    )
    resources: dict[str, float] = Field(
        default_factory=dict, description="`cpu_seconds`, `max_rss_mb` of the child."
    )
    isolation: dict[str, Any] = Field(
        default_factory=dict,
        description="How the child was isolated: `network` (`namespace` or `audit-hook`), "
        "`pid_namespace`, `user_namespace`.",
    )


class RunTrace(_Model):
    """Everything the runs did (JSON-serialisable)."""

    skill: str = Field(description="The skill file that ran.")
    inputs: dict[str, Any] = Field(default_factory=dict, description="Inputs by the skill's names.")
    binding: dict[str, str] = Field(
        default_factory=dict,
        description="Capability name -> the skill's name of each input and output bound to it "
        "(with a capability; by name, by meaning or by --bind).",
    )
    world: str | None = Field(default=None, description="The world plug-in, if one ran.")
    seed: int = Field(default=0, description="The scenario's seed.")
    scenario: str = Field(default="", description="The scenario's description.")
    episodes: list[EpisodeTrace] = Field(default_factory=list, description="In the order run.")


class RunReport(_Model):
    """The result of :func:`~skillwright.runtime.run.run_skill`."""

    findings: list[Finding] = Field(
        default_factory=list, description="Located in the skill file, sorted by line."
    )
    trace: RunTrace = Field(description="What happened.")

    @property
    def passed(self) -> bool:
        """True when no finding is an error."""
        return not any(f.severity == "error" for f in self.findings)


@dataclass(frozen=True)
class RunProgress:
    """Progress of a run, for a UI: an episode or a state began or ended."""

    episode: str
    event: Literal["episode-start", "state-start", "state-end", "episode-end"]
    state: str | None = None
    virtual_time: float = 0.0
    detail: str | None = None
