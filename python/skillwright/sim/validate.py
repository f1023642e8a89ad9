"""``validate_skill``: run a skill in the MuJoCo world of each scenario and judge it.

For every scenario of the capability (see :mod:`skillwright.sim.scenario`) the skill runs
in the sandboxed runtime (:func:`skillwright.runtime.run.run_skill`) with a fresh
:class:`~skillwright.sim.world.MujocoWorld` per run: once normally and, when it moved the
robot, once more with a Stop during execute. The oracles (:mod:`skillwright.sim.oracles`)
judge each run on the world's ground truth. Failed oracles become findings located at the
line of the state they concern (the state running at the first violation, else the state
that computes the outputs), so the repair loop can regenerate that state.

Nothing is printed; progress goes to an optional callback; setting ``cancel`` stops the
current run and raises :class:`~skillwright.errors.GenerationCancelledError`.
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from skillwright.capability.model import Capability
from skillwright.errors import InputFileError
from skillwright.fileio import write_atomic
from skillwright.interfaces.inventory import Inventory
from skillwright.rules.finding import Finding
from skillwright.rules.simulation import simulation_rule
from skillwright.runtime.sandbox import ChildPool
from skillwright.sim.assets import resolve_world
from skillwright.sim.bindings import Bindings, RecordedFacts, bind_interfaces, recorded_facts
from skillwright.sim.oracles import RunView, StateSpan, Verdict, judge
from skillwright.sim.report import (
    EpisodeVerdicts,
    ScenarioReport,
    ValidationProgress,
    ValidationReport,
)
from skillwright.sim.scenario import Scenario, ScenarioSet, scenarios_for
from skillwright.sim.world import MujocoWorld, Noise, WorldConfig

if TYPE_CHECKING:
    from skillwright.runtime.report import RunProgress, RunReport
    from skillwright.runtime.scenario import RunScenario

__all__ = ["runtime_scenario", "validate_skill"]

_STATE_OK = {"done", "absent"}


def _noise(scenario: Scenario) -> Noise:
    if scenario.noise == "none":
        return Noise.none()
    if scenario.noise == "default":
        return Noise()
    given = {k: v for k, v in scenario.noise.model_dump().items() if v is not None}
    return Noise(**given)


def _run_view(episode: Any, command_topic: str | None, binding: dict[str, str]) -> RunView:
    """The runtime's episode trace as the oracles see it: its outputs by the capability's
    names (``binding``: capability name -> the skill's)."""
    states = [
        StateSpan(
            name=s.name,
            start=s.started,
            end=s.ended if s.ended is not None else s.started,
            outcome="returned" if s.outcome in _STATE_OK else s.outcome,
        )
        for s in episode.states
    ]
    message = ""
    failing = next((s for s in episode.states if s.outcome not in _STATE_OK), None)
    ended: Literal["completed", "stopped", "aborted", "failed"]
    if episode.ended != "done":
        ended = "failed"
        message = f"the skill's process ended: {episode.ended}"
    elif episode.name == "stop" and any(
        s.name == "stopping" and s.outcome in _STATE_OK for s in episode.states
    ):
        ended = "stopped"
    elif failing is not None and failing.outcome == "raised":
        ended = "aborted"
        message = f"{failing.name} raised {failing.detail or 'an exception'}"
    elif failing is not None:
        ended = "failed"
        message = f"{failing.name} was {failing.outcome}" + (
            f" ({failing.detail})" if failing.detail else ""
        )
    elif all(
        any(s.name == name and s.outcome in _STATE_OK for s in episode.states)
        for name in ("starting", "execute")
    ):
        ended = "completed"
    else:
        ended = "failed"
        message = "the states did not run through"
    return RunView(
        states=states,
        outputs={
            **dict(episode.outputs),
            **{c: episode.outputs[k] for c, k in binding.items() if k in episode.outputs},
        },
        ended=ended,
        end_time=float(episode.virtual_seconds),
        message=message,
        events=list(episode.events),
        command_topic=command_topic,
    )


def _finding(
    verdict: Verdict, scenario: str, episode: str, lines: dict[str, int], fallback: int
) -> Finding:
    state = verdict.state or "execute"
    line = lines.get(state, lines.get("execute", fallback))
    run = "" if episode == "normal" else " (run stopped during execute)"
    return simulation_rule(verdict.kind).finding(
        line=line,
        message=f"scenario {scenario}{run}: {verdict.oracle} ({verdict.check}): {verdict.message}",
        data={
            "scenario": scenario,
            "episode": episode,
            "oracle": verdict.oracle,
            "check": verdict.check,
            "measured": verdict.measured,
            "tolerance": verdict.tolerance,
            "time": verdict.time,
            "state": verdict.state,
        },
    )


def _trace_document(report: Any, worlds: list[MujocoWorld]) -> dict[str, Any]:
    """The run's trace with each run's ground truth, thinned to 20 Hz."""
    document: dict[str, Any] = report.trace.model_dump(mode="json")
    for episode, world in zip(document.get("episodes", []), worlds, strict=False):
        truth = world.truth
        samples = []
        next_t = -1.0
        for sample in truth.samples:
            if sample.t + 1e-9 >= next_t:
                samples.append(
                    [
                        round(v, 5)
                        for v in (
                            sample.t,
                            sample.x,
                            sample.y,
                            sample.yaw,
                            sample.vx,
                            sample.vy,
                            sample.wz,
                        )
                    ]
                )
                next_t = sample.t + 0.05
        episode["ground_truth"] = {
            "columns": ["t", "x", "y", "yaw", "vx", "vy", "wz"],
            "samples": samples,
            "contacts": [c.__dict__ for c in truth.contacts],
            "goals": [{k: v for k, v in g.items() if k != "goal"} for g in truth.goals],
            "saved_maps": truth.saved_maps,
            "commands": [c.__dict__ for c in truth.commands],
        }
    return document


def _safe(value: Any) -> Any:
    """JSON has no infinity: ranges without a return are written as null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _safe(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_safe(v) for v in value]
    return value


@dataclass
class _Setup:
    """What every scenario of one validation shares."""

    skill: Path
    source: str | None
    capability: Capability
    inventory: Inventory
    bindings: Bindings
    facts: RecordedFacts
    recording: Path | None
    output_dir: Path | None
    folder: Path | None
    plot: bool
    lines: dict[str, int]
    fallback_line: int
    cancel: threading.Event | None
    children: ChildPool
    bind: dict[str, str]
    """The skill's name -> the capability's, as ``--bind`` gives them."""


class _Worlds:
    """Makes a fresh world for each run of one scenario and keeps them for the oracles."""

    def __init__(self, setup: _Setup, scenario: Scenario) -> None:
        self.setup = setup
        self.scenario = scenario
        self.world_file = resolve_world(scenario.world, setup.folder)
        self.made: list[MujocoWorld] = []

    def __call__(self) -> MujocoWorld:
        scenario, setup = self.scenario, self.setup
        maps = setup.output_dir / f"{scenario.name}.maps" if setup.output_dir is not None else None
        config = WorldConfig(
            world_file=self.world_file,
            start=(scenario.start.x, scenario.start.y, scenario.start.heading),
            # Each run gets its own noise, the same for the same seed.
            seed=scenario.seed + len(self.made),
            noise=_noise(scenario),
            output_dir=maps,
        )
        world = MujocoWorld(config, setup.bindings, setup.facts)
        self.made.append(world)
        return world


class _Progress:
    """Passes the runtime's progress on as the validation's, for one scenario."""

    def __init__(
        self,
        listener: Callable[[ValidationProgress], None] | None,
        name: str,
        index: int,
        total: int,
    ) -> None:
        self.listener = listener
        self.name = name
        self.index = index
        self.total = total

    def scenario(self, event: Literal["scenario-start", "scenario-end"]) -> None:
        if self.listener is not None:
            self.listener(ValidationProgress(self.name, self.index, self.total, event))

    def run(self, progress: RunProgress) -> None:
        if self.listener is not None:
            self.listener(
                ValidationProgress(
                    self.name,
                    self.index,
                    self.total,
                    progress.event,
                    episode=progress.episode,
                    state=progress.state,
                    virtual_time=progress.virtual_time,
                )
            )


def runtime_scenario(scenario: Scenario) -> RunScenario:
    """The runtime's settings for a run of ``scenario`` (inputs, seed, expectation,
    deadlines, and the scenario's own ``runtime`` settings); the world is left to the caller."""
    from skillwright.runtime.scenario import RunScenario

    return RunScenario.model_validate(
        {
            **scenario.runtime,
            "description": scenario.description,
            "inputs": scenario.inputs,
            "seed": scenario.seed,
            "stop_after": scenario.stop_after,
            "stop_run": scenario.stop_run,
            "expect": "abort" if scenario.expect == "aborted" else "complete",
            # A run's wall deadline grows with the scenario: on a busy machine a minute of
            # virtual time may take several of wall time; busy loops are caught by CPU time.
            "deadlines": {
                "state": scenario.duration,
                "run": max(120.0, 6.0 * scenario.duration),
                **scenario.runtime.get("deadlines", {}),
            },
        }
    )


def _run_scenario(
    setup: _Setup,
    scenario: Scenario,
    progress: Callable[[RunProgress], None],
    findings: list[Finding],
) -> ScenarioReport:
    from skillwright.runtime.run import run_skill
    from skillwright.runtime.waits import probe_waits

    worlds = _Worlds(setup, scenario)
    settings = runtime_scenario(scenario)

    def run_in(
        made: _Worlds, source: str | None, on_progress: Callable[[RunProgress], None] | None
    ) -> RunReport:
        return run_skill(
            setup.skill,
            setup.inventory,
            scenario=settings,
            world=made,
            source=source,
            recording=setup.recording,
            on_progress=on_progress,
            cancel=setup.cancel,
            children=setup.children,
            capability=setup.capability,
            bindings=setup.bind,
        )

    cpu_started = time.process_time()
    run = run_in(worlds, setup.source, progress)
    # A wait that gave up in MuJoCo runs once more, as in the run stage: with physics a
    # base can overshoot the heading or distance its loop waits for, and only a second run
    # with more time tells that from a timeout that was too short.
    code = setup.source if setup.source is not None else setup.skill.read_text(encoding="utf-8")
    run = probe_waits(
        run,
        code,
        lambda source: run_in(_Worlds(setup, scenario), source, None),
        settings.deadlines.state,
    )
    findings.extend(run.findings)
    report = ScenarioReport(
        host_cpu_seconds=time.process_time() - cpu_started,
        name=scenario.name,
        description=scenario.description,
        world=scenario.world,
        inputs=dict(scenario.inputs),
        notes=list(dict.fromkeys(n for w in worlds.made[:1] for n in w.notes)),
    )
    for episode, world in zip(run.trace.episodes, worlds.made, strict=False):
        view = _run_view(episode, setup.bindings.command_topic, run.trace.binding)
        expected: Literal["completed", "stopped", "aborted"] = (
            "stopped" if episode.name == "stop" else scenario.expect
        )
        verdicts = judge(setup.capability, scenario, view, world.truth, expected)
        report.episodes.append(
            EpisodeVerdicts(
                episode=episode.name,
                ended=view.ended,
                verdicts=verdicts,
                virtual_seconds=float(episode.virtual_seconds),
                wall_seconds=float(episode.wall_seconds),
                world_seconds=world.wall_seconds,
                publish_seconds=world.publish_seconds,
                child_cpu_seconds=float(episode.resources.get("cpu_seconds", 0.0)),
            )
        )
        findings.extend(
            _finding(v, scenario.name, episode.name, setup.lines, setup.fallback_line)
            for v in verdicts
            if v.passed is False
        )
    if setup.output_dir is not None:
        trace_path = setup.output_dir / f"{scenario.name}.trace.json"
        document = _safe(_trace_document(run, worlds.made))
        write_atomic(trace_path, json.dumps(document, indent=1) + "\n")
        report.trace = str(trace_path)
        if setup.plot and worlds.made:
            from skillwright.sim.plot import plot_scenario

            plot_path = setup.output_dir / f"{scenario.name}.png"
            plot_scenario(plot_path, scenario, report, worlds.made)
            report.plot = str(plot_path)
    return report


def _staging(output_dir: Path | None) -> Path | None:
    """A hidden folder in ``output_dir`` where a validation's files wait until it is done."""
    if output_dir is None:
        return None
    try:
        output_dir.mkdir(parents=True, exist_ok=True)
        return Path(tempfile.mkdtemp(prefix=".validating-", dir=output_dir))
    except OSError as error:
        raise InputFileError(
            f"{output_dir}: cannot write here: {error.strerror or error}"
        ) from error


def _publish(staging: Path, output_dir: Path, report: ValidationReport) -> None:
    """Move the finished validation's files into ``output_dir`` and point the report there
    (an interrupted validation leaves none behind)."""
    for item in sorted(staging.iterdir()):
        target = output_dir / item.name
        if target.is_dir():
            shutil.rmtree(target)
        item.replace(target)
    prefix = str(staging)
    for scenario in report.scenarios:
        if scenario.plot:
            scenario.plot = str(output_dir) + scenario.plot[len(prefix) :]
        if scenario.trace:
            scenario.trace = str(output_dir) + scenario.trace[len(prefix) :]


def validate_skill(
    skill: Path,
    capability: Capability,
    inventory: Inventory,
    *,
    scenario_file: Path | None = None,
    scenarios: ScenarioSet | None = None,
    recording: Path | None = None,
    output_dir: Path | None = None,
    only: list[str] | None = None,
    plot: bool = True,
    source: str | None = None,
    on_progress: Callable[[ValidationProgress], None] | None = None,
    cancel: threading.Event | None = None,
    children: ChildPool | None = None,
    isolated: bool = True,
    bind: Mapping[str, str] | None = None,
) -> ValidationReport:
    """Run ``skill`` in each scenario of ``capability`` and judge it with the oracles.

    The scenarios give inputs and the oracles read outputs by the capability's names; the
    skill's own are bound to them by name, by meaning, or as ``bind`` (the skill's name ->
    the capability's, ``--bind``) says (:mod:`skillwright.capability.binding`).

    ``scenarios`` (or ``scenario_file``) chooses the scenarios, else the shipped file for the
    capability or one derived from it; ``only`` keeps the scenarios with those names.
    ``recording`` is the MCAP file or rosbag2 folder to replay and to read the lidar's geometry
    from (default: the inventory's own source when it is a recording that still exists).
    ``output_dir`` receives per scenario the trajectory plot ``<name>.png`` (with ``plot``),
    the trace with ground truth ``<name>.trace.json`` and the maps the skill saved
    (``<name>.maps/``), all at once when the validation is done; without it nothing is
    written. ``source`` is the skill's text when it is not (yet) in the file ``skill``
    names (findings still refer to ``skill``). ``children`` hands out the sandboxed
    processes (default: a pool that boots each run's child while the previous run goes on,
    inside the kernel sandbox unless ``isolated`` is false: ``--unsafe-no-isolation``).
    """
    from skillwright.runtime.run import skill_binding
    from skillwright.runtime.skillinfo import SkillSourceError, read_skill

    started = time.perf_counter()
    pool = children if children is not None else ChildPool(isolated=isolated)
    # The fork server boots on another core while the scenarios are read and the first
    # world is built.
    pool.warm()
    findings: list[Finding] = []
    try:
        bindings = bind_interfaces(inventory)
        chosen = scenarios or scenarios_for(
            capability, scenario_file, localised=bindings.has_localisation
        )
        selected = [s for s in chosen.scenarios if not only or s.name in only]
        try:
            text = source if source is not None else skill.read_text(encoding="utf-8")
            info = read_skill(text, str(skill))
            lines, fallback = dict(info.states), info.class_line
            binding = skill_binding(info, capability, bind or {})
        except (OSError, UnicodeDecodeError, SkillSourceError):
            lines, fallback, binding = {}, 0, {}
        setup = _Setup(
            skill=skill,
            source=source,
            capability=capability,
            inventory=inventory,
            bindings=bindings,
            facts=recorded_facts(inventory, bindings, recording),
            recording=recording,
            output_dir=_staging(output_dir),
            folder=Path(chosen.folder) if chosen.folder else None,
            plot=plot,
            lines=lines,
            fallback_line=fallback,
            cancel=cancel,
            children=pool,
            bind=dict(bind or {}),
        )
        report = ValidationReport(
            skill=str(skill),
            capability=capability.iri,
            scenario_source=chosen.source,
            notes=list(chosen.notes),
            binding=binding,
        )
        try:
            for index, scenario in enumerate(selected):
                progress = _Progress(on_progress, scenario.name, index, len(selected))
                progress.scenario("scenario-start")
                report.scenarios.append(_run_scenario(setup, scenario, progress.run, findings))
                progress.scenario("scenario-end")
            if setup.output_dir is not None and output_dir is not None:
                _publish(setup.output_dir, output_dir, report)
        finally:
            if setup.output_dir is not None:
                shutil.rmtree(setup.output_dir, ignore_errors=True)
    finally:
        if children is None:
            pool.close()
    report.findings = sorted(dict.fromkeys(findings), key=lambda f: (f.line, f.check, f.message))
    report.wall_seconds = time.perf_counter() - started
    return report
