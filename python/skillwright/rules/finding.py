"""A finding: one problem a rule found in a skill, with its code, its data and its fix."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["Finding", "FixSafety", "Severity", "Stage"]

Severity = Literal["error", "warning"]
Stage = Literal["static", "run", "simulation"]
FixSafety = Literal["safe", "unsafe"]
"""``safe``: the fix cannot change what the skill does on the robot (a name rclpy has in
place of one it lacks, a call's arguments in the order rclpy takes them). ``unsafe``: it
can (a wait made longer, a command repeated, a state's value measured instead of assumed),
so it is applied only when asked for (``check --unsafe-fixes``) or where the generation
record says so, fix by fix."""


class Finding(BaseModel):
    """One problem found in a skill, with where it is and why it matters."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    code: str = Field(
        default="",
        description="The rule's stable code, e.g. SW301 (`skillwright rules` lists them, "
        "`skillwright check --explain CODE` explains one); empty only in records written "
        "before rules had codes.",
    )
    check: str = Field(
        description="The rule's group, e.g. 'annotations', 'names', 'run.exception' (several "
        "rules share one)."
    )
    severity: Severity = Field(description="Errors fail the check.")
    line: int = Field(description="1-based line (0 when it concerns the whole file).")
    column: int = Field(default=0, description="1-based column, 0 when unknown.")
    message: str = Field(description="What is wrong, in plain words, and what to do.")
    data: dict[str, Any] = Field(
        default_factory=dict,
        description="What the rule found, as data the repair loop, the run's probes and "
        "`make eval` read instead of the message (attribute, state, seconds, candidates, "
        "...); each rule's documentation names its keys.",
    )
    replacement: str | None = Field(
        default=None,
        description="A statement that does what the flagged one meant, when the check knows "
        "it (e.g. the wait for a subscription's first message): the rule's fix.",
    )
    fix_safety: FixSafety | None = Field(
        default=None, description="How safe applying `replacement` is (see FixSafety)."
    )
    stack: tuple[int, ...] = Field(
        default=(),
        description="For a run's finding: the lines of the skill's calls that led to `line`, "
        "outermost first (a state's call of the helper that raised); empty otherwise.",
    )

    def __hash__(self) -> int:
        # ``data`` may hold lists and dicts; equal findings still hash alike without it.
        place = (self.code, self.check, self.severity, self.line, self.column)
        return hash((*place, self.message, self.replacement, self.fix_safety, self.stack))

    @property
    def label(self) -> str:
        """``SW301 names`` (or the group alone for a finding without a code)."""
        return f"{self.code} {self.check}" if self.code else self.check
