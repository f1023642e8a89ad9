"""What a second run says about a wait that gave up.

A state that raises "... not finished within 2 s" leaves two readings open: the robot needed
longer than the skill allowed, or what the state waits for never happens (its loop never
reads the new heading, it stops the base while it waits). The small models write both, and
the repair needs to know which. So when the run finds such a state and the number its wait
takes the seconds from can be found (:mod:`skillwright.validation.timeouts`), the same
scenario runs once more with the wait allowed most of the state's deadline:

* if the state gets past the wait, the timeout was too short. Findings ``run.short_wait``
  put a number in its place: what the state took in that run times :data:`MARGIN`, rounded
  up to a number an engineer would write, and never less than twice the old one. They carry the
  changed statements, so the repair loop applies them without the model, and the next run
  shows whether they hold. The simulated robot is only as fast as its world: the finding
  says so and says how long the state took.
* if it still gives up, waiting longer is not the fix, and the finding says that instead of
  blaming the timeout (the run's note about a motion still under way is dropped), and what
  the first run saw: the robot still moving (then the condition does not follow the
  motion: cap2skill rotate never read its heading again), or nothing moving it (MR-1 rotate
  published zero velocity inside its loop).

MR-1 and cap2skill rotate (ev49) allowed a turn 2 s, MR-1 navigate-to-point gave Nav2 5 s;
the 1.5B model kept those numbers through every repair that said they were too short.
"""

from __future__ import annotations

from collections.abc import Callable

from skillwright.errors import OperationCancelledError, SkillwrightError
from skillwright.runtime.report import RunReport
from skillwright.runtime.session import GAVE_UP_NOTE, gave_up
from skillwright.validation.model import Finding
from skillwright.validation.timeouts import fixes, rounded_up, timeout_site, with_seconds

__all__ = ["MARGIN", "PROBE_SHARE", "probe_waits"]

PROBE_SHARE = 0.8
"""Share of the scenario's deadline per state that the second run allows the wait."""
MARGIN = 3.0
"""How many times what the state took in the second run the fixed timeout allows."""


def probe_waits(
    report: RunReport, code: str, run: Callable[[str], RunReport], state_deadline: float
) -> RunReport:
    """``report`` of ``code``, with what running it again through ``run`` (same scenario,
    other code) says about each state whose wait gave up."""
    probe_seconds = round(state_deadline * PROBE_SHARE, 3)
    findings = list(report.findings)
    added: list[Finding] = []
    for index, finding in enumerate(report.findings):
        parsed = gave_up(finding.message) if finding.check == "run.exception" else None
        if parsed is None:
            continue
        state, seconds, head = parsed
        if seconds * 2 > probe_seconds:
            continue
        site = timeout_site(code, finding.line, finding.stack, seconds)
        if site is None:
            continue
        try:
            probe = run(with_seconds(code, site, probe_seconds))
        except OperationCancelledError:
            raise
        except SkillwrightError:
            continue  # the second run is advice: the first run's finding stands as it is
        if _gave_up_again(probe, finding.line):
            why = (
                "the robot was moving when it gave up, yet what it waits for did not come "
                "true: check that the condition reads the robot's state again on every pass"
                if GAVE_UP_NOTE in finding.message
                else "no goal was running and no velocity other than zero went out in its "
                "last second, so nothing brings about what it waits for: check what it "
                "commands while it waits"
            )
            findings[index] = finding.model_copy(
                update={
                    "message": f"{head}; given {probe_seconds:g} s instead of {seconds:g} s "
                    f"in the same run, {state} still gave up there, so a longer wait is not "
                    f"the fix: {why}"
                }
            )
            continue
        took = _took(probe, state)
        if took is None:
            continue
        allowed = max(rounded_up(took * MARGIN), rounded_up(seconds * 2))
        message = (
            f"the wait that gave up allows {seconds:g} s, less than {state} needs: given "
            f"{probe_seconds:g} s in the same run, it got past the wait and {state} took "
            f"{took:.1f} s, so the wait now allows {allowed:g} s (at least {MARGIN:g} times "
            "that, rounded up; the simulated robot is only as fast as its world, so check "
            "the number against the real one)"
        )
        added += [
            Finding(
                check="run.short_wait",
                severity="error",
                line=line,
                column=column,
                message=message,
                replacement=text,
            )
            for line, column, text in fixes(code, site, allowed)
        ]
    if not added and findings == report.findings:
        return report
    ordered = sorted([*findings, *added], key=lambda f: (f.line, f.check, f.message))
    return report.model_copy(update={"findings": ordered})


def _gave_up_again(probe: RunReport, line: int) -> bool:
    return any(
        f.check == "run.exception" and f.line == line and gave_up(f.message) is not None
        for f in probe.findings
    )


def _took(probe: RunReport, state: str) -> float | None:
    """Virtual seconds ``state`` took in the probe's normal episode, if it ended there."""
    for episode in probe.trace.episodes:
        if episode.name != "normal":
            continue
        for run in episode.states:
            if run.name == state and run.ended is not None and run.outcome in ("done", "raised"):
                return run.ended - run.started
    return None
