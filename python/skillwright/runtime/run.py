"""``run_skill``: run a skill's states against the simulated graph, in the sandbox.

A run is one or two *episodes*, each in a fresh sandboxed process: the normal one
(starting, execute, completing, resetting) and, when the normal one commanded motion or
sent action goals, a second one with a Stop command halfway through execute (stopping,
resetting), which is where a skill that never halts the robot shows. Findings of both
are merged and located in the skill file; the trace holds both episodes.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any, Final

from skillwright.capability.binding import Annotation, Binding, bind
from skillwright.capability.model import Capability
from skillwright.errors import InputFileError, InputFileNotFoundError, InvalidArgumentError
from skillwright.interfaces.inventory import Inventory
from skillwright.rules.finding import Finding
from skillwright.rules.run import (
    RUN_COMMAND_STILL_MOVING,
    RUN_EXCEPTION,
    RUN_EXPECTATION,
    RUN_GOAL_LEFT_ACTIVE,
    RUN_INPUT_GETTER,
    RUN_INPUT_UNBOUND,
    RUN_INPUT_UNREAD,
    RUN_NO_DATA,
    RUN_OUTPUT_UNSET,
    RUN_THREAD,
)
from skillwright.runtime.api import WorldPlugin
from skillwright.runtime.recorder import Recorder
from skillwright.runtime.report import EpisodeTrace, RunProgress, RunReport, RunTrace
from skillwright.runtime.sandbox import ChildPool
from skillwright.runtime.scenario import RunScenario
from skillwright.runtime.session import Episode, EpisodePlan, EpisodeResult
from skillwright.runtime.skillinfo import SkillInfo, SkillSourceError, read_skill
from skillwright.runtime.typesys import MOTION_TYPES, is_zero_motion, registry_for

__all__ = [
    "MOTION_TYPES",
    "WorldSpec",
    "read_skill_file",
    "recording_files",
    "run_skill",
    "skill_binding",
]

"""Message types whose non-zero values command a base to move."""

_DEFAULT_EPOCH_NS: Final = 1_767_225_600 * 1_000_000_000
"""2026-01-01T00:00:00Z: ROS time at the start of runs without a recording."""

WorldSpec = WorldPlugin | Callable[[], WorldPlugin] | str | None
"""A world for the run: a plug-in object (attached afresh for each episode), a factory
of plug-ins, the name of a built-in world (``kinematic``), or ``None``."""


def recording_files(source: Path) -> list[Path]:
    """The MCAP files of a recording: the file itself, or a rosbag2 folder's ``*.mcap``."""
    if source.is_file():
        return [source]
    if source.is_dir():
        return sorted(p for p in source.glob("*.mcap") if p.is_file())
    return []


def _default_recording(inventory: Inventory) -> list[Path]:
    for source in inventory.sources:
        if source.kind in {"mcap", "rosbag2"}:
            files = recording_files(Path(source.location))
            if files:
                return files
    return []


def _world_factory(world: WorldSpec, scenario: RunScenario) -> Callable[[], WorldPlugin | None]:
    chosen: WorldSpec = world if world is not None else scenario.world
    if chosen is None or chosen == "none":
        return lambda: None
    if isinstance(chosen, str):
        if chosen != "kinematic":
            raise InvalidArgumentError(
                f"unknown world {chosen!r}; the built-in world is 'kinematic'"
            )
        from skillwright.runtime.worlds.kinematic import KinematicWorld

        options = dict(scenario.world_options)
        return lambda: KinematicWorld(**options)
    if isinstance(chosen, WorldPlugin):
        instance = chosen
        return lambda: instance
    return chosen


def _coerce(value: float | int | bool | str, annotation: str | None, name: str) -> Any:
    if annotation in {"float", "int"} and isinstance(value, str):
        try:
            value = float(value) if annotation == "float" else int(value)
        except ValueError:
            raise InvalidArgumentError(f"input {name} takes a number, not {value!r}") from None
    if annotation == "float" and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if annotation == "int" and isinstance(value, float) and value.is_integer():
        return int(value)
    if annotation == "bool" and isinstance(value, str):
        lowered = value.strip().lower()
        if lowered not in {"true", "false"}:
            raise InvalidArgumentError(f"input {name} takes true or false, not {value!r}")
        return lowered == "true"
    if annotation == "str" and not isinstance(value, str):
        return str(value)
    return value


def _annotations(info: SkillInfo) -> list[Annotation]:
    """The skill's parameters and outputs as the binding reads them."""
    return [
        *(Annotation(v.name, "input", v.description, v.line) for v in info.parameters),
        *(Annotation(v.name, "output", v.description, v.line) for v in info.outputs),
    ]


def skill_binding(
    info: SkillInfo, capability: Capability, bindings: Mapping[str, str]
) -> dict[str, str]:
    """Capability name -> the skill's name of each input and output bound to it."""
    return {b.target: b.annotation for b in bind(_annotations(info), capability, bindings).bound}


def _skill_inputs(
    info: SkillInfo,
    given: Mapping[str, float | int | bool | str],
    binding: Binding | None,
    recorder: Recorder,
) -> dict[str, float | int | bool | str]:
    """``given`` by the skill's own names: a name the skill has stays, a capability name goes
    to the parameter bound to it; one that reaches none is a finding (with a capability) and
    is left for :func:`_inputs` to refuse (without one)."""
    own = {v.name for v in info.parameters}
    named: dict[str, float | int | bool | str] = {}
    for name, value in given.items():
        bound = binding.annotation_of(name) if binding is not None else None
        if name in own or binding is None:
            named[name] = value
        elif bound is not None:
            named[bound] = value
        else:
            candidates = [a for a, targets in binding.ambiguous.items() if name in targets]
            why = (
                f"{', '.join(candidates)} could mean it; say which with --bind "
                f"{candidates[0]}={name}"
                if candidates
                else f"none of its parameters ({', '.join(sorted(own)) or 'none'}) means it"
            )
            recorder.finding(
                RUN_INPUT_UNBOUND,
                f"input {name} of the capability reaches no parameter of the skill: {why}",
                line=info.class_line,
                data={"input": name, "candidates": candidates},
            )
    return named


def read_skill_file(path: Path) -> str:
    """The text of the skill file ``path``; the input-file errors when it cannot be read."""
    if path.is_dir():
        raise InputFileError(
            f"skill file {path}: is a folder; give the skill's .py file (the folder "
            "`skillwright generate` writes holds it as skill.py)"
        )
    if not path.is_file():
        raise InputFileNotFoundError(f"skill file {path}: no such file; check the path")
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"skill file {path}: cannot be read as UTF-8 text ({error})") from None


def _bound(
    info: SkillInfo,
    given: Mapping[str, float | int | bool | str],
    capability: Capability | None,
    bindings: Mapping[str, str] | None,
    trace: RunTrace,
    recorder: Recorder,
) -> tuple[SkillInfo, dict[str, float | int | bool | str]]:
    """The skill and ``given`` by its own names, bound to ``capability`` when there is one.
    A parameter that nothing given reaches is then no longer required: the finding about the
    input that did not reach it says what the run lacks, and the run goes on."""
    if capability is None:
        return info, dict(given)
    binding = bind(_annotations(info), capability, bindings or {})
    trace.binding = {b.target: b.annotation for b in binding.bound}
    named = _skill_inputs(info, given, binding, recorder)
    parameters = [v if v.name in named else replace(v, required=False) for v in info.parameters]
    return replace(info, parameters=parameters), named


def _inputs(
    info: SkillInfo,
    given: Mapping[str, float | int | bool | str],
    path: str,
    recorder: Recorder,
) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    by_name = {v.name: v for v in info.parameters}
    unknown = sorted(set(given) - set(by_name))
    if unknown:
        names = ", ".join(sorted(by_name)) or "none"
        raise InvalidArgumentError(
            f"{path}: the skill has no input {unknown[0]!r} (its inputs: {names}); give the "
            "capability with --capability to give inputs by its names"
        )
    missing = [v.name for v in info.parameters if v.required and v.name not in given]
    if missing:
        example = " ".join(f"{name}=..." for name in missing)
        raise InvalidArgumentError(
            f"{path}: the skill needs input(s) {', '.join(missing)}; give them with "
            f"--inputs {example} (or in the scenario's inputs)"
        )
    resolved: list[dict[str, Any]] = []
    shown: dict[str, Any] = {}
    for variable in info.parameters:
        if variable.name not in given:
            continue
        value = _coerce(given[variable.name], variable.annotation, variable.name)
        shown[variable.name] = value
        if variable.attr is None:
            recorder.finding(
                RUN_INPUT_GETTER,
                f"the getter {variable.getter}() of input {variable.name} does not return an "
                "attribute of the skill (`return self.<name>`), so the input cannot be set: "
                "the skill runs with whatever the getter computes",
                line=variable.line,
            )
            continue
        resolved.append(
            {"name": variable.name, "attr": variable.attr, "path": variable.path, "value": value}
        )
    return resolved, shown


def run_skill(
    skill: Path | str,
    inventory: Inventory,
    *,
    inputs: Mapping[str, float | int | bool | str] | None = None,
    scenario: RunScenario | None = None,
    world: WorldSpec = None,
    source: str | None = None,
    recording: Path | None = None,
    on_progress: Callable[[RunProgress], None] | None = None,
    cancel: threading.Event | None = None,
    children: ChildPool | None = None,
    isolated: bool = True,
    capability: Capability | None = None,
    bindings: Mapping[str, str] | None = None,
) -> RunReport:
    """Runs ``skill`` against a simulated graph of ``inventory`` in a sandbox.

    With ``capability``, inputs may be given by the capability's names: each goes to the
    parameter bound to it (:mod:`skillwright.capability.binding`: by name, by meaning, or by
    ``bindings``, the skill's name -> the capability's, as ``--bind`` gives them); the trace
    records the binding, and an input that reaches no parameter is a finding.

    ``skill`` names the skill file (findings refer to it); its text is read from there
    unless ``source`` gives it. ``inputs`` are by capability name and override the
    scenario's. ``recording`` is the MCAP file or rosbag2 folder to replay (default: the
    inventory's own source, when it is a recording that still exists). Deadlines and
    limits come from ``scenario``. ``on_progress`` hears about episodes and states (from
    the calling thread); setting ``cancel`` kills the run and raises
    :class:`~skillwright.errors.GenerationCancelledError`, leaving nothing behind.
    ``children`` hands out the sandboxed processes; a caller running several skills in a
    row passes one pool to all of them (and closes it), so each run's child boots while
    the previous run goes on. Without it the run keeps its own, inside the kernel sandbox
    unless ``isolated`` is false (``--unsafe-no-isolation``).

    Raises :class:`~skillwright.errors.InvalidArgumentError` for inputs the skill does
    not take or lacks, and the input-file errors when ``skill`` cannot be read. Problems
    of the skill itself are findings in the returned report, never exceptions.
    """
    path = Path(skill)
    if source is None:
        source = read_skill_file(path)
    scenario = scenario or RunScenario()
    given = {**scenario.inputs, **dict(inputs or {})}
    world_factory = _world_factory(world, scenario)
    world_name = (
        world
        if isinstance(world, str)
        else (scenario.world if world is None else type(world).__name__)
    )
    trace = RunTrace(
        skill=str(path),
        world=None if world_name in (None, "none") else str(world_name),
        seed=scenario.seed,
        scenario=scenario.description,
    )
    try:
        info = read_skill(source, str(path))
    except SkillSourceError as error:
        finding = error.rule.finding(line=error.line, message=str(error))
        return RunReport(findings=[finding], trace=trace)
    _check_scenario_names(scenario, inventory)
    setup = Recorder()
    info, named = _bound(info, given, capability, bindings, trace, setup)
    resolved, shown = _inputs(info, named, str(path), setup)
    trace.inputs = shown
    registry = registry_for(inventory)
    files = recording_files(recording) if recording is not None else _default_recording(inventory)
    start = next((s.start_time_ns for s in inventory.sources if s.start_time_ns is not None), None)
    pool = children if children is not None else ChildPool(isolated=isolated)
    try:
        episode = Episode(
            source=source,
            skill_name=path.name if path.suffix == ".py" else "skill.py",
            info=info,
            inputs=resolved,
            inventory=inventory,
            registry=registry,
            scenario=scenario,
            recording=files or None,
            world_factory=world_factory,
            epoch_ns=start if start is not None and files else _DEFAULT_EPOCH_NS,
            on_progress=on_progress,
            cancel=cancel,
            children=pool,
        )
        findings: list[Finding] = list(setup.findings)
        # A shared pool serves the caller's next run too; an own one only a Stop run.
        more = children is not None
        normal = episode.run(
            EpisodePlan("normal"), prepare_next=more or scenario.stop_run != "never"
        )
        trace.episodes.append(normal.trace)
        given_names = {entry["name"] for entry in resolved}
        findings += _analyse(normal, info, scenario, given_names, main=True)
        plan = _stop_plan(normal, scenario)
        if plan is not None:
            stopped = episode.run(plan, prepare_next=more)
            trace.episodes.append(stopped.trace)
            findings += _analyse(stopped, info, scenario, given_names, main=False)
    finally:
        if children is None:
            pool.close()
    unique: list[Finding] = []
    for finding in findings:
        if finding not in unique:
            unique.append(finding)
    unique.sort(key=lambda f: (f.line, f.check, f.message))
    return RunReport(findings=unique, trace=trace)


def _check_scenario_names(scenario: RunScenario, inventory: Inventory) -> None:
    kinds = {(i.kind, i.name) for i in inventory.interfaces}
    for kind, names in (
        ("topic", scenario.topics),
        ("service", scenario.services),
        ("action", scenario.actions),
    ):
        for name in names:
            if (kind, name) not in kinds:
                raise InvalidArgumentError(
                    f"the scenario scripts {kind} {name}, which the robot does not have; "
                    f"`skillwright inventory show` lists its {kind}s"
                )


def _state(trace: EpisodeTrace, name: str) -> Any:
    return next((s for s in trace.states if s.name == name), None)


def _moved(result: EpisodeResult) -> bool:
    graph = result.graph
    motion = any(
        graph.published_type(topic) in MOTION_TYPES
        and any(not is_zero_motion(m[1]) for m in messages)
        for topic, messages in graph.published.items()
    )
    return motion or any(e.get("kind") == "goal" for e in result.trace.events)


def _stop_plan(normal: EpisodeResult, scenario: RunScenario) -> EpisodePlan | None:
    if scenario.stop_run == "never":
        return None
    execute = _state(normal.trace, "execute")
    executed = execute is not None and execute.outcome == "done"
    if scenario.stop_run == "auto" and not (executed and _moved(normal)):
        return None
    if scenario.stop_after is not None:
        after = scenario.stop_after
    elif executed and execute.ended is not None:
        after = max(0.05, (execute.ended - execute.started) / 2)
    else:
        after = 1.0
    return EpisodePlan("stop", stop_after=after, stop_at_complete=True)


def _analyse(
    result: EpisodeResult, info: SkillInfo, scenario: RunScenario, given: set[str], *, main: bool
) -> list[Finding]:
    """Findings that need the whole episode: motion left running, goals left active,
    outputs never written, inputs never read, threads never ended, silent topics."""
    recorder = result.recorder
    trace = result.trace
    graph = result.graph
    for state in ("stopping", "aborting"):
        run = _state(trace, state)
        if run is None:
            continue
        marker = result.publish_marks.get(state)
        _check_motion_after(
            recorder, graph, state, marker, info if run.outcome == "absent" else None
        )
        for goal, line in result.goals_after.get(state, []):
            recorder.finding(
                RUN_GOAL_LEFT_ACTIVE,
                f"after {state}, the goal sent to {goal.action} here is still active: cancel it "
                "in the state (goal_handle.cancel_goal_async()) so the robot halts",
                line=line,
            )
    resetting = result.publish_marks.get("resetting")
    if resetting is not None:
        _check_left_moving(recorder, graph, resetting)
    for goal, line in graph.active_goals():
        if not goal.cancel_requested and _state(trace, "resetting") is not None:
            recorder.finding(
                RUN_GOAL_LEFT_ACTIVE,
                f"the goal sent to {goal.action} here is still active at the end of the run; "
                "stopping and resetting must cancel the goals they leave behind",
                line=line,
            )
    for thread in result.threads:
        recorder.finding(
            RUN_THREAD,
            f"a thread started here ({thread.get('name')}) is still running after resetting; "
            "a skill must end the threads it starts, or they outlive it on the robot",
            line=int(thread.get("line") or 0),
        )
    completed = all(
        (run := _state(trace, s)) is not None and run.outcome in {"done", "absent"}
        for s in ("starting", "execute", "completing")
    )
    if main and completed:
        if scenario.expect == "abort":
            recorder.finding(
                RUN_EXPECTATION,
                "the scenario expects the skill to abort"
                + (f" ({scenario.description})" if scenario.description else "")
                + ", but it completed",
                line=info.states.get("execute", info.class_line),
            )
        for variable in info.outputs:
            if (
                variable.attr is not None
                and variable.attr not in result.writes
                and variable.attr not in info.callback_stores
            ):
                recorder.finding(
                    RUN_OUTPUT_UNSET,
                    f"output {variable.name} is never set: no state assigns self.{variable.attr}, "
                    "so the getter returns what __init__ put there",
                    line=variable.line,
                )
        for variable in info.parameters:
            if (
                variable.attr is not None
                and variable.attr not in result.reads
                and variable.name in given
            ):
                recorder.finding(
                    RUN_INPUT_UNREAD,
                    f"input {variable.name} is never read: no state uses self.{variable.attr}, "
                    "so the skill ignores the value it is given (a hard-coded value in its place?)",
                    line=variable.line,
                )
    failed = not completed or trace.ended != "done"
    if failed:
        for endpoint in graph.silent_subscriptions():
            recorder.finding(
                RUN_NO_DATA,
                f"nothing arrived on {endpoint.name} during the run: nobody publishes it here "
                "(no recorded messages, no world); a skill that waits for it waits forever",
                line=endpoint.line,
                severity="warning",
            )
    findings = list(recorder.findings)
    if main and scenario.expect == "abort":
        findings = [f for f in findings if f.code != RUN_EXCEPTION.code]
    return findings


def _check_motion_after(
    recorder: Recorder, graph: Any, state: str, marker: int | None, missing: SkillInfo | None
) -> None:
    if marker is None:
        return
    for topic, messages in graph.published.items():
        if graph.published_type(topic) not in MOTION_TYPES:
            continue
        before = [m for m in messages if m[4] < marker]
        if not before:
            continue
        _, message, line, _, _ = before[-1]
        if is_zero_motion(message):
            continue
        if missing is not None:
            cause = "Stop" if state == "stopping" else "fault"
            recorder.finding(
                RUN_COMMAND_STILL_MOVING,
                f"the skill has no {state} state, so after a {cause} the last command on "
                f"{topic} (published at line {line}) keeps the base moving: add a @{state} "
                "method that publishes a zero velocity",
                line=missing.class_line,
            )
        else:
            recorder.finding(
                RUN_COMMAND_STILL_MOVING,
                f"after {state}, the last command on {topic} still moves the base (published "
                f"here): {state} must publish a zero velocity",
                line=line,
            )


def _check_left_moving(recorder: Recorder, graph: Any, marker: int) -> None:
    for topic, messages in graph.published.items():
        if graph.published_type(topic) not in MOTION_TYPES or not messages:
            continue
        late = [m for m in messages if m[4] >= marker and not is_zero_motion(m[1])]
        if late:
            recorder.finding(
                RUN_COMMAND_STILL_MOVING,
                f"after resetting, the skill still publishes non-zero commands on {topic} "
                "(here): a timer or thread it started keeps driving the base; cancel it in "
                "stopping and resetting",
                line=late[0][2],
            )
            continue
        _, message, line, _, _ = messages[-1]
        if not is_zero_motion(message):
            recorder.finding(
                RUN_COMMAND_STILL_MOVING,
                f"at the end of the run the last command on {topic} (published here) still moves "
                "the base: resetting must leave it at zero",
                line=line,
            )
