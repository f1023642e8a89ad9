"""Run scenarios: what the simulated robot does differently from its defaults.

By default every service answers with success after a short delay, every action accepts
its goal, sends feedback and succeeds, recorded topics are replayed in a loop and a
world (when chosen) moves the robot. A scenario changes that, per interface::

    description: Nav2 rejects every goal
    inputs: {inPositionX: 2.0, inPositionY: 1.0}
    world: kinematic
    actions:
      /navigate_to_pose: {accept: false}
    services:
      /map_saver/save_map: {response: {result: false}, delay: 0.5}
    topics:
      /scan: {silent: true}
    expect: abort

Scenarios are YAML (or JSON) files; :func:`load_scenario` reports every mistake with
the file and the field's path.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from skillwright.errors import FileFormatError, InputFileError, InputFileNotFoundError

__all__ = [
    "ActionScript",
    "Deadlines",
    "Limits",
    "RunScenario",
    "ServiceScript",
    "TopicScript",
    "load_scenario",
]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class TopicScript(_Model):
    """What is published on one topic."""

    silent: bool = Field(default=False, description="Nobody publishes it: no replay, no defaults.")
    rate_hz: float | None = Field(
        default=None, gt=0, description="Publish `message` at this rate instead of the replay."
    )
    message: dict[str, Any] = Field(
        default_factory=dict, description="Fields of the scripted message; defaults for the rest."
    )


class ServiceScript(_Model):
    """How one service answers."""

    available: bool = Field(default=True, description="False: no server (wait_for_service fails).")
    respond: bool = Field(default=True, description="False: requests are never answered.")
    delay: float = Field(default=0.05, ge=0, description="Virtual seconds before the response.")
    response: dict[str, Any] = Field(
        default_factory=dict, description="Fields of the response, over the success defaults."
    )


class ActionScript(_Model):
    """How one action server behaves."""

    available: bool = Field(default=True, description="False: no server (wait_for_server fails).")
    accept: bool = Field(default=True, description="False: every goal is rejected.")
    accept_delay: float = Field(default=0.05, ge=0, description="Seconds to accept or reject.")
    duration: float = Field(default=1.0, ge=0, description="Seconds from acceptance to result.")
    feedback_hz: float = Field(default=2.0, ge=0, description="Feedback rate; 0 for none.")
    feedback: dict[str, Any] = Field(default_factory=dict, description="Fields of the feedback.")
    outcome: Literal["succeed", "abort", "never"] = Field(
        default="succeed", description="How goals end; `never`: they run until cancelled."
    )
    result: dict[str, Any] = Field(
        default_factory=dict, description="Fields of the result, over the success defaults."
    )
    cancel: Literal["accept", "reject"] = Field(
        default="accept", description="Whether cancel requests are accepted."
    )


class Deadlines(_Model):
    """How long a run may take."""

    state: float = Field(default=120.0, gt=0, description="Virtual seconds per state.")
    busy: float = Field(
        default=5.0,
        gt=0,
        description="Wall seconds a state may run without waiting (sleep, spin, a future) "
        "before it is interrupted and reported as busy.",
    )
    run: float = Field(default=120.0, gt=0, description="Wall seconds for one episode.")


class Limits(_Model):
    """Resource limits of the sandboxed process."""

    memory_mb: int = Field(default=1024, ge=128, description="Address space.")
    cpu_seconds: int = Field(default=60, ge=1, description="CPU time of the process.")
    open_files: int = Field(default=64, ge=16, description="Open file descriptors.")
    processes: int = Field(default=64, ge=1, description="Processes of the user (not root).")
    file_size_mb: int = Field(default=16, ge=1, description="Largest file it may write.")


class RunScenario(_Model):
    """Everything that shapes one run of a skill besides the skill itself."""

    description: str = Field(default="", description="What the scenario checks.")
    inputs: dict[str, float | int | bool | str] = Field(
        default_factory=dict, description="Skill inputs by capability name; --inputs overrides."
    )
    seed: int = Field(default=0, description="Seed of the world's and the responders' noise.")
    world: Literal["none", "kinematic"] | None = Field(
        default=None, description="The built-in world; `none` replays recordings only."
    )
    world_options: dict[str, Any] = Field(
        default_factory=dict, description="Options of the world (see its documentation)."
    )
    replay: Literal["loop", "once", "off"] = Field(
        default="loop", description="Replay of the recording the inventory came from."
    )
    topics: dict[str, TopicScript] = Field(default_factory=dict, description="By topic name.")
    services: dict[str, ServiceScript] = Field(default_factory=dict, description="By name.")
    actions: dict[str, ActionScript] = Field(default_factory=dict, description="By name.")
    deadlines: Deadlines = Field(default_factory=Deadlines, description="Time limits.")
    limits: Limits = Field(default_factory=Limits, description="Sandbox limits.")
    stop_after: float | None = Field(
        default=None,
        gt=0,
        description="Virtual seconds into execute at which the stop run sends Stop; by "
        "default half of execute's duration in the normal run.",
    )
    stop_run: Literal["auto", "always", "never"] = Field(
        default="auto",
        description="Whether to run the skill a second time and stop it during execute; "
        "`auto`: when the normal run commanded motion or sent goals.",
    )
    expect: Literal["complete", "abort"] = Field(
        default="complete", description="How the normal run should end."
    )
    settle: float = Field(default=0.5, ge=0, description="Virtual seconds watched after resetting.")
    traffic: Literal["subscribed", "all"] = Field(
        default="subscribed",
        description="`subscribed`: a world makes, and the replay reads, only the messages "
        "someone receives (the run is the same, faster); `all`: every sensor and recorded "
        "message is produced whether or not anyone listens, as on the robot (for comparison).",
    )
    lookahead: float = Field(
        default=0.02,
        ge=0,
        le=1.0,
        description="Virtual seconds the simulation may run ahead of the skill between two "
        "exchanges: 0 is strict lockstep (slowest); more is faster, and the skill's commands "
        "reach the world up to that much later.",
    )


def _where(location: tuple[int | str, ...]) -> str:
    return ".".join(str(part) for part in location) or "(top level)"


def load_scenario(path: Path) -> RunScenario:
    """Reads a scenario file (YAML or JSON); errors name the file and the field."""
    import yaml

    if not path.is_file():
        raise InputFileNotFoundError(f"scenario {path}: no such file; check the path")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"scenario {path}: cannot be read as UTF-8 text ({error})") from None
    try:
        document = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f":{mark.line + 1}:{mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or str(error)
        raise FileFormatError(f"{path}{where}: YAML syntax error: {problem}") from None
    if document is None:
        document = {}
    if not isinstance(document, dict):
        raise FileFormatError(
            f"{path}: a scenario is a mapping of settings, not a {type(document).__name__}"
        )
    try:
        return RunScenario.model_validate(document)
    except ValidationError as error:
        first = error.errors()[0]
        more = f" (and {error.error_count() - 1} more)" if error.error_count() > 1 else ""
        raise FileFormatError(
            f"{path}: {_where(first['loc'])}: {first['msg']}{more}; see `skillwright run --help`"
        ) from None
