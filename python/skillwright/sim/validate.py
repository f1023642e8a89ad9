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
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, Literal

from skillwright.capability.model import Capability
from skillwright.fileio import write_atomic
from skillwright.interfaces.inventory import Inventory
from skillwright.sim.assets import resolve_world
from skillwright.sim.bindings import bind_interfaces, recorded_facts
from skillwright.sim.oracles import RunView, StateSpan, Verdict, judge
from skillwright.sim.report import (
    EpisodeVerdicts,
    ScenarioReport,
    ValidationProgress,
    ValidationReport,
)
from skillwright.sim.scenario import Scenario, ScenarioSet, scenarios_for
from skillwright.sim.world import MujocoWorld, Noise, WorldConfig
from skillwright.validation.model import Finding

__all__ = ["validate_skill"]

_STATE_OK = {"done", "absent"}


def _noise(scenario: Scenario) -> Noise:
    if scenario.noise == "none":
        return Noise.none()
    if scenario.noise == "default":
        return Noise()
    given = {k: v for k, v in scenario.noise.model_dump().items() if v is not None}
    return Noise(**given)


def _run_view(episode: Any) -> RunView:
    """The runtime's episode trace as the oracles see it."""
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
        outputs=dict(episode.outputs),
        ended=ended,
        end_time=float(episode.virtual_seconds),
        message=message,
    )


def _finding(verdict: Verdict, scenario: str, episode: str, lines: dict[str, int], fallback: int) -> Finding:
    state = verdict.state or "execute"
    line = lines.get(state, lines.get("execute", fallback))
    run = "" if episode == "normal" else " (run stopped during execute)"
    return Finding(
        check=f"behaviour.{verdict.kind}",
        severity="error",
        line=line,
        message=f"scenario {scenario}{run}: {verdict.oracle} ({verdict.check}): {verdict.message}",
    )


def _trace_document(report: Any, worlds: list[MujocoWorld]) -> dict[str, Any]:
    """The run's trace with each run's ground truth, thinned to 20 Hz."""
    document = json.loads(report.trace.model_dump_json())
    for episode, world in zip(document.get("episodes", []), worlds, strict=False):
        truth = world.truth
        samples = []
        next_t = -1.0
        for sample in truth.samples:
            if sample.t + 1e-9 >= next_t:
                samples.append(
                    [round(v, 5) for v in (sample.t, sample.x, sample.y, sample.yaw, sample.vx, sample.vy, sample.wz)]
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
    on_progress: Callable[[ValidationProgress], None] | None = None,
    cancel: threading.Event | None = None,
) -> ValidationReport:
    """Run ``skill`` in each scenario of ``capability`` and judge it with the oracles.

    ``scenarios`` (or ``scenario_file``) chooses the scenarios, else the shipped file for the
    capability or one derived from it; ``only`` keeps the scenarios with those names.
    ``recording`` is the MCAP file or rosbag2 folder to replay and to read the lidar's geometry
    from (default: the inventory's own source when it is a recording that still exists).
    ``output_dir`` receives per scenario the trajectory plot ``<name>.png`` (with ``plot``),
    the trace with ground truth ``<name>.trace.json`` and maps the skill saved; without it
    nothing is written.
    """
    from skillwright.runtime.run import run_skill
    from skillwright.runtime.scenario import RunScenario
    from skillwright.runtime.skillinfo import SkillSourceError, read_skill

    started = time.perf_counter()
    chosen = scenarios or scenarios_for(capability, scenario_file)
    selected = [s for s in chosen.scenarios if not only or s.name in only]
    bindings = bind_interfaces(inventory)
    facts = recorded_facts(inventory, bindings, recording)
    report = ValidationReport(
        skill=str(skill),
        capability=capability.iri,
        scenario_source=chosen.source,
        notes=[*chosen.notes],
    )
    try:
        info = read_skill(skill.read_text(encoding="utf-8"), str(skill))
        lines, fallback = dict(info.states), info.class_line
    except (OSError, UnicodeDecodeError, SkillSourceError):
        lines, fallback = {}, 0
    folder = Path(chosen.folder) if chosen.folder else None
    for index, scenario in enumerate(selected):

        def progress(event: Any, name: str = scenario.name, position: int = index) -> None:
            if on_progress is not None:
                on_progress(
                    ValidationProgress(
                        scenario=name,
                        index=position,
                        total=len(selected),
                        event=event.event,
                        episode=event.episode,
                        state=event.state,
                        virtual_time=event.virtual_time,
                    )
                )

        if on_progress is not None:
            on_progress(ValidationProgress(scenario.name, index, len(selected), "scenario-start"))
        world_file = resolve_world(scenario.world, folder)
        worlds: list[MujocoWorld] = []
        maps = output_dir / f"{scenario.name}.maps" if output_dir is not None else None

        def make_world(world_file: Path = world_file, scenario: Scenario = scenario, maps: Path | None = maps) -> MujocoWorld:
            config = WorldConfig(
                world_file=world_file,
                start=(scenario.start.x, scenario.start.y, scenario.start.heading),
                seed=scenario.seed + len(worlds),
                noise=_noise(scenario),
                output_dir=maps,
            )
            world = MujocoWorld(config, bindings, facts)
            worlds.append(world)
            return world

        run_scenario = RunScenario.model_validate(
            {
                **scenario.runtime,
                "description": scenario.description,
                "inputs": scenario.inputs,
                "seed": scenario.seed,
                "stop_after": scenario.stop_after,
                "stop_run": scenario.stop_run,
                "expect": "abort" if scenario.expect == "aborted" else "complete",
                "deadlines": {"state": scenario.duration, **scenario.runtime.get("deadlines", {})},
            }
        )
        run = run_skill(
            skill,
            inventory,
            scenario=run_scenario,
            world=make_world,
            recording=recording,
            on_progress=progress,
            cancel=cancel,
        )
        report.findings.extend(run.findings)
        scenario_report = ScenarioReport(
            name=scenario.name,
            description=scenario.description,
            world=scenario.world,
            inputs=dict(scenario.inputs),
            notes=list(dict.fromkeys(n for w in worlds[:1] for n in w.notes)),
        )
        for episode, world in zip(run.trace.episodes, worlds, strict=False):
            view = _run_view(episode)
            expected: Literal["completed", "stopped", "aborted"] = (
                "stopped" if episode.name == "stop" else scenario.expect
            )
            verdicts = judge(capability, scenario, view, world.truth, expected)
            scenario_report.episodes.append(
                EpisodeVerdicts(
                    episode=episode.name,
                    ended=view.ended,
                    verdicts=verdicts,
                    virtual_seconds=float(episode.virtual_seconds),
                    wall_seconds=float(episode.wall_seconds),
                    world_seconds=world.wall_seconds,
                )
            )
            report.findings.extend(
                _finding(v, scenario.name, episode.name, lines, fallback)
                for v in verdicts
                if v.passed is False
            )
        if output_dir is not None:
            trace_path = output_dir / f"{scenario.name}.trace.json"
            document = _safe(_trace_document(run, worlds))
            write_atomic(trace_path, json.dumps(document, indent=1) + "\n")
            scenario_report.trace = str(trace_path)
            if plot and worlds:
                from skillwright.sim.plot import plot_scenario

                plot_path = output_dir / f"{scenario.name}.png"
                plot_scenario(plot_path, scenario, scenario_report, worlds)
                scenario_report.plot = str(plot_path)
        report.scenarios.append(scenario_report)
        if on_progress is not None:
            on_progress(ValidationProgress(scenario.name, index, len(selected), "scenario-end"))
    unique: list[Finding] = []
    for finding in report.findings:
        if finding not in unique:
            unique.append(finding)
    report.findings = sorted(unique, key=lambda f: (f.line, f.check, f.message))
    report.wall_seconds = time.perf_counter() - started
    return report
