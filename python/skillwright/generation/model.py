"""Documents of the generation stage."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["InterfaceRef", "Skeleton", "SkeletonParameter", "Unwired"]

InterfaceKind = Literal["topic", "service", "action"]


class InterfaceRef(BaseModel):
    """A robot interface the skill will use, as far as code generation needs it."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Full ROS 2 name, e.g. /cmd_vel.")
    kind: InterfaceKind = Field(description="topic, service or action.")
    type_name: str = Field(description="ROS 2 type, e.g. geometry_msgs/msg/Twist.")
    role: Literal["publish", "subscribe", "call"] = Field(
        description="publish / subscribe for topics; call for services and actions."
    )
    qos: Literal["default", "sensor_data", "latched"] = Field(
        default="default",
        description="QoS a subscription needs to receive what the robot's publishers offer: "
        "sensor_data (best effort) when they publish best effort, latched (transient local) "
        "when they keep their last message for late subscribers, else default (reliable, 10).",
    )


class Unwired(BaseModel):
    """A given interface nothing in the specification or the capability calls for: the
    skeleton makes no handle for it (:mod:`skillwright.generation.wiring`)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    interface: InterfaceRef = Field(description="The interface.")
    reason: str = Field(description="Why it is not wired.")


class SkeletonParameter(BaseModel):
    """One ``@skill_parameter`` or ``@skill_output`` of the skeleton."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(description="Name in the annotation: the capability's name for it.")
    attribute: str = Field(description="Attribute of the skill object holding the value.")
    python_type: str = Field(description="Python type of the value: float, int, bool or str.")
    direction: Literal["input", "output"] = Field(description="Parameter or output.")
    description: str = Field(description="Description in the annotation.")
    turn: str | None = Field(
        default=None,
        description="For an angle the capability bounds to [0, one turn): the turn as Python "
        "(`math.tau`, `360.0`); the getter reports the angle in that range.",
    )


class Skeleton(BaseModel):
    """The deterministic part of a skill: structure, annotations and interface handles."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    code: str = Field(description="The Python source.")
    class_name: str = Field(description="Name of the skill class.")
    skill_iri: str = Field(description="The minted skill IRI.")
    parameters: list[SkeletonParameter] = Field(description="Parameters and outputs.")
    interfaces: list[InterfaceRef] = Field(description="Interfaces with handles in the code.")
    unimplemented: list[str] = Field(
        description="States whose behaviour the skeleton leaves to be written."
    )
    notes: list[str] = Field(default_factory=list, description="Decisions the user should know.")
    helpers: list[str] = Field(
        default_factory=list, description="Helper methods the skeleton offers the behaviour."
    )
    prologues: dict[str, str] = Field(
        default_factory=dict,
        description="Per state, the skeleton's code at the start of its body (creating handles).",
    )
    epilogues: dict[str, str] = Field(
        default_factory=dict,
        description="Per state, the skeleton's code at the end of its body (releasing handles).",
    )
    unwired: list[Unwired] = Field(
        default_factory=list,
        description="Given interfaces without a handle: nothing calls for them.",
    )
    assured: list[str] = Field(
        default_factory=list,
        description="Output attributes the skeleton sets itself: velocities the capability "
        "asserts zero for, set once the base is at rest (generation.assured).",
    )


AttemptFinish = Literal["stop", "length", "repetition", "unparsable", "cancelled", "fixed"]
"""How an attempt ended: a complete method, the token limit, a loop the guard stopped, an
answer that is not one method of Python, the user's cancel; or ``fixed``: no model answer but
the previous answer with the statements the checks suggested put in place."""


class AppliedFix(BaseModel):
    """A rule's fix the checks put into an answer themselves (no model involved)."""

    model_config = ConfigDict(extra="forbid")

    code: str = Field(description="The rule whose fix it is (`skillwright rules`).")
    safety: Literal["safe", "unsafe"] = Field(
        description="`unsafe`: the fix decides something the code did not say (a timeout, a "
        "wait, a command repeated), which can change what the robot does."
    )
    line: int = Field(description="The line of the judged file it replaced.")


class Attempt(BaseModel):
    """One answer of the model for one method: a state, or a helper a state calls."""

    model_config = ConfigDict(extra="forbid")

    target: str = Field(description="The method asked for.")
    kind: Literal["state", "helper"] = Field(description="A PackML state or a helper method.")
    number: int = Field(description="1 for the first answer, then one more per repair.")
    temperature: float = Field(description="Sampling temperature (0: greedy).")
    seed: int = Field(description="Sampling seed.")
    finish: AttemptFinish = Field(description="How the answer ended.")
    note: str | None = Field(default=None, description="Why it failed, when it did.")
    code: str | None = Field(
        default=None, description="The method (class-member indentation), when it parsed."
    )
    response: str = Field(description="What the model wrote after the prefilled start.")
    prompt_tokens: int | None = Field(default=None, description="Tokens of the whole prompt.")
    reused_tokens: int | None = Field(
        default=None,
        description="Leading prompt tokens not evaluated again (a cached prefix, the context "
        "or a state kept from an earlier answer); the rest were evaluated for this answer.",
    )
    completion_tokens: int | None = Field(default=None, description="Tokens the model wrote.")
    seconds: float = Field(description="Wall time of the answer, prompt evaluation included.")
    prefix_cache: str | None = Field(
        default=None, description="How the prompt's fixed prefix was obtained for this answer."
    )
    problems: list[str] = Field(
        default_factory=list, description="What it was asked to fix (repair attempts)."
    )
    problem_codes: list[str] = Field(
        default_factory=list,
        description="The rules of the findings it was asked to fix, in the order of `problems`.",
    )
    fixes: list[AppliedFix] = Field(
        default_factory=list,
        description="For an answer the checks fixed themselves (finish `fixed`): each fix put "
        "in, with its rule and safety.",
    )
    kept_lines: int = Field(
        default=0,
        description="Lines of the earlier answer (before its first error) this repair was "
        "given to continue from.",
    )
    errors: int | None = Field(
        default=None, description="Errors the checks found in this method (null: not checked)."
    )
    warnings: int | None = Field(default=None, description="Warnings found in this method.")
    behaviour_errors: int | None = Field(
        default=None,
        description="Of its errors, those the sandboxed run or the simulation found (an answer "
        "that got that far beats one the static checks stopped); null when its file did not "
        "get that far (a static error anywhere in it).",
    )
    chosen: bool = Field(default=False, description="Whether the final skill holds it.")
    candidate: int | None = Field(
        default=None,
        description="The candidate skill it belongs to, when several were sampled for the "
        "first round (0: the greedy one); null for a single first answer, a repair or a fix.",
    )


class CandidateVerdict(BaseModel):
    """One candidate skill of a best-of-N first round, as the judge saw it."""

    model_config = ConfigDict(extra="forbid")

    index: int = Field(description="0 for the greedy candidate, then one per sampled sequence.")
    temperature: float = Field(description="Sampling temperature of its answers (0: greedy).")
    seed: int = Field(description="Sampling seed of its answers.")
    duplicate_of: int | None = Field(
        default=None,
        description="The earlier candidate whose file it assembles to, character for "
        "character (then it was not judged again).",
    )
    unusable: int = Field(
        default=0,
        description="Methods whose answer in it could not be used (cut off, looping, not "
        "Python): the file holds the skeleton's placeholder there.",
    )
    errors: int | None = Field(
        default=None, description="Errors the static checks found in its file."
    )
    behaviour_errors: int | None = Field(
        default=None,
        description="Errors the run and the simulation found (null: the static checks "
        "stopped it, so it did not run).",
    )
    warnings: int | None = Field(default=None, description="Warnings in its file.")
    codes: list[str] = Field(
        default_factory=list, description="The rules of its errors, sorted, each once."
    )
    won: bool = Field(default=False, description="Whether repair started from this one.")
