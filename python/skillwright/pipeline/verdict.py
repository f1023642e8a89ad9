"""One verdict per stage of a generation, the same wherever it is shown.

A stage (and one answer of the model) has exactly one of five verdicts, and each has one
mark, one colour and one word: the TUI's stage list, its result header and History, the
``generate`` command's summary and ``record.json`` (``verdicts``) all take them from here, so
no view can put a green mark beside a stage another view calls failed.

- ``passed``: it ran and found no error;
- ``failed``: it ran and found an error (or could not do its job: no usable answer);
- ``fixed automatically``: the checks put their own suggested statements in place of the
  flagged ones (a rule's fix, no model time); the result is judged again after it;
- ``skipped``: deliberately not done: turned off, not needed (no model for the skeleton), or
  pointless after an earlier stage's errors (a skill with static errors is not run);
- ``not run``: it should have given a verdict and gave none: still to come, cancelled, over
  its wall-clock budget or unable to start. A stage without a verdict is never a pass.

Only the standard library is imported: the TUI reads these before its first paint.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from skillwright.generation.model import Attempt
    from skillwright.pipeline.record import (
        ChecksRecord,
        GenerationRecord,
        RunRecord,
        SimulationRecord,
    )

__all__ = [
    "StageVerdict",
    "Verdict",
    "attempt_verdict",
    "behaviour_verdict",
    "checks_verdict",
    "generation_verdict",
    "overall",
    "stage_verdicts",
    "writing_verdict",
]


class Verdict(StrEnum):
    """The verdict of one stage; its value is the word every view prints."""

    PASSED = "passed"
    FAILED = "failed"
    FIXED = "fixed automatically"
    SKIPPED = "skipped"
    NOT_RUN = "not run"

    @property
    def mark(self) -> str:
        """The one-character mark shown before the stage."""
        return _MARKS[self]

    @property
    def style(self) -> str:
        """The Rich colour of the mark and the word."""
        return _STYLES[self]

    @property
    def word(self) -> str:
        """The word shown for it."""
        return self.value

    def markup(self) -> str:
        """The word in Rich console markup, in its colour."""
        return f"[{self.style}]{self.value}[/]"


_MARKS = {
    Verdict.PASSED: "✓",
    Verdict.FAILED: "✗",
    Verdict.FIXED: "↻",
    Verdict.SKIPPED: "-",
    Verdict.NOT_RUN: "·",
}
_STYLES = {
    Verdict.PASSED: "green",
    Verdict.FAILED: "red",
    Verdict.FIXED: "cyan",
    Verdict.SKIPPED: "bright_black",
    Verdict.NOT_RUN: "yellow",
}


@dataclass(frozen=True)
class StageVerdict:
    """A verdict with what it rests on, in a few words (``""`` when nothing to add)."""

    verdict: Verdict
    reason: str = ""


def checks_verdict(checks: ChecksRecord) -> StageVerdict:
    """The static checks: failed when one finding is an error."""
    if checks.passed:
        return StageVerdict(Verdict.PASSED, f"{checks.warnings} warning(s)")
    return StageVerdict(Verdict.FAILED, f"{checks.errors} error(s), {checks.warnings} warning(s)")


def behaviour_verdict(
    part: RunRecord | SimulationRecord | None, checks_passed: bool
) -> StageVerdict:
    """The run's or the simulation's verdict.

    ``None`` (no record of it) is a stage turned off. A record with a ``skipped`` reason is
    skipped when the static checks failed (the pipeline runs no skill with static errors),
    otherwise it is a stage that should have run and gave no verdict (budget, no sandbox).
    """
    if part is None:
        return StageVerdict(Verdict.SKIPPED, "turned off")
    if part.skipped is not None:
        skipped = Verdict.NOT_RUN if checks_passed else Verdict.SKIPPED
        return StageVerdict(skipped, part.skipped)
    if part.passed:
        return StageVerdict(Verdict.PASSED)
    errors = sum(f.severity == "error" for f in part.findings)
    failed = sum(v.passed is False for v in getattr(part, "verdicts", ()))
    reason = f"{errors} error(s)" + (f", {failed} oracle verdict(s) failed" if failed else "")
    return StageVerdict(Verdict.FAILED, reason)


def attempt_verdict(attempt: Attempt) -> StageVerdict:
    """One answer of the model: failed when it ended badly or the checks found an error in
    its method, fixed when it is the checks' own fix, not run while it is not yet checked."""
    if attempt.finish == "fixed":
        codes = ", ".join(dict.fromkeys(f.code for f in attempt.fixes))
        return StageVerdict(Verdict.FIXED, codes)
    if attempt.finish == "cancelled":
        return StageVerdict(Verdict.NOT_RUN, "cancelled")
    if attempt.finish != "stop":
        return StageVerdict(Verdict.FAILED, attempt.finish)
    if attempt.errors is None:
        return StageVerdict(Verdict.NOT_RUN, "not checked yet")
    if attempt.errors:
        return StageVerdict(Verdict.FAILED, f"{attempt.errors} error(s)")
    return StageVerdict(Verdict.PASSED)


def writing_verdict(missing: Sequence[str], attempts: Sequence[Attempt]) -> StageVerdict:
    """The model's writing: failed when a method got no usable answer (``missing``), fixed
    when the final skill holds a method the checks fixed themselves (a chosen attempt)."""
    if missing:
        return StageVerdict(Verdict.FAILED, f"no usable answer for {', '.join(missing)}")
    fixed = [a.target for a in attempts if a.chosen and a.finish == "fixed"]
    if fixed:
        return StageVerdict(Verdict.FIXED, ", ".join(dict.fromkeys(fixed)))
    return StageVerdict(Verdict.PASSED)


def generation_verdict(record: GenerationRecord) -> StageVerdict:
    """The ``generation`` stage of ``record``: skipped without a model, else
    :func:`writing_verdict`."""
    if record.model is None:
        return StageVerdict(Verdict.SKIPPED, "skeleton only, no model")
    return writing_verdict(record.model.states_missing, record.model.attempts)


def stage_verdicts(record: GenerationRecord) -> dict[str, StageVerdict]:
    """Every stage of :data:`~skillwright.pipeline.events.STAGES` judged from ``record``.

    The stages without a check of their own (reading the inputs, retrieval, the skeleton,
    writing the outputs) passed: a record is only written when they did.
    """
    model = record.model
    return {
        "inputs": StageVerdict(Verdict.PASSED),
        "retrieval": StageVerdict(Verdict.PASSED),
        "skeleton": StageVerdict(Verdict.PASSED),
        "model": StageVerdict(Verdict.SKIPPED, "skeleton only, no model")
        if model is None
        else StageVerdict(Verdict.PASSED, model.id),
        "generation": generation_verdict(record),
        "checks": checks_verdict(record.checks),
        "run": behaviour_verdict(record.run, record.checks.passed),
        "simulate": behaviour_verdict(record.simulation, record.checks.passed),
        "outputs": StageVerdict(Verdict.PASSED),
    }


def overall(verdicts: dict[str, StageVerdict]) -> Verdict:
    """The result's verdict: failed when a stage failed, not run when one that should have
    judged the skill gave no verdict, else passed (skipped and fixed stages do not fail it)."""
    found = {v.verdict for v in verdicts.values()}
    if Verdict.FAILED in found:
        return Verdict.FAILED
    if Verdict.NOT_RUN in found:
        return Verdict.NOT_RUN
    return Verdict.PASSED
