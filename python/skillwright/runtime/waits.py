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
  motion: the loop never reads the odometry or transform it compares again), or nothing
  moving it (the loop publishes a zero ``Twist`` while it waits).

The second run also logs the comparison the wait tests on every pass
(:mod:`skillwright.validation.watch`), and when it gives up again, what those values show
takes the place of the general advice: the robot stepped over its goal between two checks,
the value never changed, or it moved away from the goal. A state that ran into the state
deadline in such a loop (no timeout of its own) runs once more with the watch for the same
reason.

The number is measured, not advised: how long a turn or a Nav2 goal takes follows from the
distance and the robot's limits (``max_vel_theta``, the controller's ``desired_linear_vel``),
which the skill's author does not see, so a finding that only says "too short" leaves the
number where it was.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import Any

from skillwright.errors import OperationCancelledError, SkillwrightError
from skillwright.rules.finding import Finding
from skillwright.rules.run import RUN_EXCEPTION, RUN_SHORT_WAIT, RUN_TIMEOUT
from skillwright.runtime.report import RunReport
from skillwright.runtime.typesys import is_zero_motion
from skillwright.validation.timeouts import fixes, rounded_up, timeout_site, with_seconds
from skillwright.validation.watch import diagnose, samples, watch_at, watched

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
        if finding.code == RUN_TIMEOUT.code:
            findings[index] = _watched_timeout(finding, code, run)
            continue
        seconds = _gave_up_after(finding)
        if seconds is None:
            continue
        state = str(finding.data["state"])
        head = _head(finding)
        if "frame" in finding.data:
            findings[index] = _missing_frame(finding, head, code)
            if findings[index].replacement is not None:
                added += _other_map_lookups(findings[index], code)
            continue
        if seconds * 2 > probe_seconds:
            continue
        site = timeout_site(code, finding.line, finding.stack, seconds)
        if site is None:
            continue
        longer = with_seconds(code, site, probe_seconds)
        watch = watch_at(longer, finding.line, finding.stack)
        try:
            probe = run(watched(longer, watch) if watch is not None else longer)
        except OperationCancelledError:
            raise
        except SkillwrightError:
            continue  # the second run is advice: the first run's finding stands as it is
        if _gave_up_again(probe, finding.line):
            moving = finding.data.get("under_way") is not None
            seen = (
                diagnose(watch, _samples(probe, state), moving=moving)
                if watch is not None
                else None
            )
            why = (
                f"watched on every pass, {seen}"
                if seen is not None
                else "the robot was moving when it gave up, yet what it waits for did not come "
                "true: check that the condition reads the robot's state again on every pass"
                if moving
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
            RUN_SHORT_WAIT.finding(
                line=line,
                column=column,
                message=message,
                replacement=text,
                data={"seconds": seconds, "timeout": allowed, "took": round(took, 3)},
            )
            for line, column, text in fixes(code, site, allowed)
        ]
    if not added and findings == report.findings:
        return report
    ordered = sorted([*findings, *added], key=lambda f: (f.line, f.check, f.message))
    return report.model_copy(update={"findings": ordered})


def _gave_up_after(finding: Finding) -> float | None:
    """The seconds after which the wait of a raised state gave up, for a run's finding of a
    state that raised because a wait ran out."""
    seconds = finding.data.get("seconds")
    if finding.code != RUN_EXCEPTION.code or not isinstance(seconds, int | float):
        return None
    return float(seconds)


def _head(finding: Finding) -> str:
    """A raised state's finding as the run first put it (the state, the exception's type
    and text), without what the run added of a motion still under way."""
    data = finding.data
    return f"{data['state']} raised {data['type']}: {data['detail']}"


def _missing_frame(finding: Finding, head: str, code: str) -> Finding:
    """``finding`` (a wait that gave up on a frame tf does not have) told so; when the frame
    is ``map``, the robot has ``odom`` and the line asks for ``map`` once, with the line
    asking for ``odom`` instead: the pose a robot without localisation has. REP 105 puts
    ``map`` above ``odom`` only where a localisation publishes ``map -> odom``, and tf2's
    ``lookup_transform`` into a frame the tree lacks fails however long it waits, so the fix
    is the frame, not the wait."""
    message = (
        f"{head}; the frame is not in the robot's tf tree, so no longer wait brings it: ask "
        "for one of the frames /tf has (named above)"
    )
    frames = {str(f) for f in finding.data.get("frames", [])}
    # a helper's raise is reported with the state's call of it outermost in the stack
    at = finding.stack[0] if finding.stack else finding.line
    lines = code.splitlines()
    fixed = _in_odom(lines[at - 1]) if 0 < at <= len(lines) else None
    if finding.data.get("frame") != "map" or "odom" not in frames or fixed is None:
        return finding.model_copy(update={"message": message})
    return finding.model_copy(
        update={
            "message": f"{message}; this robot has no map (no localisation runs), so its pose "
            "is in odom, which drifts with the wheels: the line now asks for odom",
            "replacement": fixed,
            "line": at,
            "column": 0,
            "stack": (),
        }
    )


def _other_map_lookups(fixed: Finding, code: str) -> list[Finding]:
    """The same fix for every other line of the file that asks tf for ``map`` the same way
    (the run stops at the first; cap2skill get-position asked for x and y in two lookups)."""
    return [
        fixed.model_copy(update={"line": number, "replacement": replacement})
        for number, text in enumerate(code.splitlines(), start=1)
        if number != fixed.line
        and "self._transform(" in text
        and (replacement := _in_odom(text)) is not None
    ]


def _in_odom(text: str) -> str | None:
    """The statement on the line ``text`` with its one ``'map'`` (or ``"map"``) asking for
    ``odom``, when the line is a whole simple statement that names map once."""
    line = text.strip()
    asked = [quote for quote in ("'map'", '"map"') if line.count(quote) == 1]
    if len(asked) != 1:
        return None
    try:
        body = ast.parse(line).body
    except SyntaxError:
        return None
    if len(body) != 1 or isinstance(body[0], ast.If | ast.For | ast.While | ast.Try):
        return None
    return line.replace(asked[0], asked[0].replace("map", "odom"))


def _watched_timeout(finding: Finding, code: str, run: Callable[[str], RunReport]) -> Finding:
    """``finding`` (a state that ran into the deadline in a loop), with what the loop's
    condition did on every pass of a second run, when that says why it never held."""
    state = str(finding.data.get("state", ""))
    watch = watch_at(code, finding.line, finding.stack)
    if watch is None:
        return finding
    try:
        probe = run(watched(code, watch))
    except OperationCancelledError:
        raise
    except SkillwrightError:
        return finding
    seen = diagnose(watch, _samples(probe, state), moving=_moved(probe, state))
    if seen is None:
        return finding
    return finding.model_copy(
        update={"message": f"{finding.message}; watched on every pass in a second run, {seen}"}
    )


def _samples(probe: RunReport, state: str) -> list[tuple[float, float, float]]:
    """What the watched comparison logged in ``state`` of the probe's normal episode."""
    return samples(_normal_events(probe), state)


def _moved(probe: RunReport, state: str) -> bool:
    """Whether ``state`` moved the robot in the probe's normal episode: a goal sent, or a
    velocity command other than zero in its last second."""
    events = [e for e in _normal_events(probe) if e.get("state") == state]
    if any(e.get("kind") == "goal" for e in events):
        return True
    since = float(events[-1].get("t", 0.0)) - 1.0 if events else 0.0
    for event in events:
        if float(event.get("t", 0.0)) < since:
            continue
        message = event.get("message")
        if (
            event.get("kind") == "publish"
            and isinstance(message, dict)
            and {"linear", "angular", "twist"} & set(message)
            and not is_zero_motion(message)
        ):
            return True
    return False


def _normal_events(probe: RunReport) -> list[dict[str, Any]]:
    for episode in probe.trace.episodes:
        if episode.name == "normal":
            return episode.events
    return []


def _gave_up_again(probe: RunReport, line: int) -> bool:
    return any(f.line == line and _gave_up_after(f) is not None for f in probe.findings)


def _took(probe: RunReport, state: str) -> float | None:
    """Virtual seconds ``state`` took in the probe's normal episode, if it ended there."""
    for episode in probe.trace.episodes:
        if episode.name != "normal":
            continue
        for run in episode.states:
            if run.name == state and run.ended is not None and run.outcome in ("done", "raised"):
                return run.ended - run.started
    return None
