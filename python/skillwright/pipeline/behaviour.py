"""The run and simulate stages of a generation, and what they tell the repair loop.

Static checks cannot tell whether a skill works. Once a candidate passes them, it is

* **run** (:func:`skillwright.runtime.run.run_skill`): its states in the sandbox against the
  robot's simulated graph, with the kinematic world moving the base, in the capability's
  default scenario (the first of :func:`skillwright.sim.scenario.scenarios_for`: the shipped
  scenario file for the capability, else one derived from its parameters), and
* **simulated** (:func:`skillwright.sim.validate.validate_skill`): in MuJoCo in that
  scenario and the capability's others (a skill that only works where the default scenario
  puts the robot is not one to trust: a ``sensor_msgs/LaserScan`` range ``i`` lies at
  ``angle_min + i * angle_increment``, so a skill that takes the index of the nearest range
  among the valid ones for its index in the scan is right in a walled room, where every
  range is valid, and wrong where some look into open space), judged by the oracles derived
  from the capability model.

Both report findings at the skill's lines, so :func:`Behaviour.validator` hands them to the
repair loop exactly like static findings: the method holding the line is asked for again.
To keep the cost bounded the simulation only runs when the run found no error, each is
bounded by a wall-clock budget, and results are kept by the code's digest, so the file the
repair loop last judged is not run again by the stages after the checks.
"""

from __future__ import annotations

import hashlib
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from skillwright.errors import GenerationCancelledError, SandboxUnavailableError, SkillwrightError
from skillwright.pipeline.record import (
    RunEpisodeRecord,
    RunRecord,
    SimulationRecord,
    VerdictRecord,
)
from skillwright.rules.finding import Finding
from skillwright.rules.settings import Selection

if TYPE_CHECKING:
    from skillwright.capability.model import Capability
    from skillwright.generation.author import Validator
    from skillwright.generation.model import Skeleton
    from skillwright.interfaces.inventory import Inventory
    from skillwright.runtime.report import RunReport
    from skillwright.sim.report import ValidationReport
    from skillwright.sim.scenario import Scenario, ScenarioSet

__all__ = ["Behaviour", "RunResult", "SimResult"]

RUN_WORLD = "kinematic"
"""The runtime's built-in world for the run stage: it moves the base as commanded."""


SIM_REFERENCE_SECONDS = 120.0
"""The virtual seconds of scenarios the simulation budget (``sim_seconds``) is meant for:
about what a capability's shipped scenario files add up to."""


def _digest(code: str) -> str:
    return hashlib.sha256(code.encode("utf-8")).hexdigest()


def _isolation(report: RunReport) -> dict[str, str]:
    """How the sandbox held the skill's first episode, for the record."""
    held = report.trace.episodes[0].isolation if report.trace.episodes else {}
    kept = ("namespaces", "seccomp", "landlock", "uid")
    return {key: str(value) for key, value in held.items() if key in kept}


def _errors(findings: list[Finding]) -> int:
    return sum(f.severity == "error" for f in findings)


@dataclass
class RunResult:
    """One run of a candidate (``report`` is ``None`` when it could not run)."""

    report: RunReport | None
    seconds: float
    skipped: str | None = None

    @property
    def findings(self) -> list[Finding]:
        """The run's findings, located in the skill."""
        return [] if self.report is None else list(self.report.findings)


@dataclass
class SimResult:
    """One simulation of a candidate (``report`` is ``None`` when it could not run)."""

    report: ValidationReport | None
    seconds: float
    skipped: str | None = None

    @property
    def findings(self) -> list[Finding]:
        """Run findings in the world and failed oracles, located in the skill."""
        return [] if self.report is None else list(self.report.findings)

    @property
    def plot(self) -> Path | None:
        """The trajectory plot, while the generation's work folder exists."""
        if self.report is None or not self.report.scenarios:
            return None
        plot = self.report.scenarios[0].plot
        return Path(plot) if plot else None

    @property
    def trace(self) -> Path | None:
        """The default scenario's trace with ground truth, while the work folder exists."""
        if self.report is None or not self.report.scenarios:
            return None
        trace = self.report.scenarios[0].trace
        return Path(trace) if trace else None


class _Budget:
    """A cancel event for one stage: set by the caller's cancel, or when ``seconds`` pass."""

    def __init__(self, seconds: float, outer: threading.Event | None) -> None:
        self.seconds = seconds
        self.outer = outer
        self.event = threading.Event()
        self.expired = False
        self._done = threading.Event()

    def _watch(self) -> None:
        end = time.monotonic() + self.seconds
        while not self._done.is_set():
            if self.outer is not None and self.outer.is_set():
                self.event.set()
                return
            left = end - time.monotonic()
            if left <= 0:
                self.expired = True
                self.event.set()
                return
            self._done.wait(min(0.1, left))

    @contextmanager
    def running(self) -> Iterator[threading.Event]:
        watcher = threading.Thread(target=self._watch, name="stage-budget", daemon=True)
        watcher.start()
        try:
            yield self.event
        finally:
            self._done.set()
            watcher.join()


class Behaviour:
    """Runs and simulates the candidates of one generation, each code once.

    ``work_dir`` receives the simulations' plots and traces (the caller removes it);
    ``run_seconds`` and ``sim_seconds`` bound each run and each simulation in wall time, for
    scenarios of the default length; longer scenarios get proportionally more
    (:meth:`run_budget`, :meth:`sim_budget`).
    """

    def __init__(
        self,
        capability: Capability,
        inventory: Inventory,
        skill_path: Path,
        work_dir: Path,
        *,
        run: bool = True,
        simulate: bool = True,
        run_seconds: float = 120.0,
        sim_seconds: float = 240.0,
        cancel: threading.Event | None = None,
        isolated: bool = True,
        selection: Selection | None = None,
        scenario_file: Path | None = None,
    ) -> None:
        self.capability = capability
        self.scenario_file = scenario_file
        """The scenario file to read the scenarios from; ``None``: the shipped one for the
        capability, else scenarios derived from the model (:func:`scenarios_for`)."""
        self.isolated = isolated
        self.selection = selection or Selection()
        """The rules the run's findings are reported and repaired by (the simulation's
        verdicts all count: they come from the capability model)."""
        self.inventory = inventory
        self.skill_path = skill_path
        self.work_dir = work_dir
        self.run_enabled = run
        self.sim_enabled = simulate
        self.run_seconds = run_seconds
        self.sim_seconds = sim_seconds
        self.cancel = cancel
        self.repair_runs = 0
        self.repair_sims = 0
        self._runs: dict[str, RunResult] = {}
        self._sims: dict[str, SimResult] = {}
        self._scenarios: ScenarioSet | None = None

    @property
    def enabled(self) -> bool:
        """Whether a candidate that passes the static checks is run or simulated at all."""
        return self.run_enabled or self.sim_enabled

    def scenarios(self) -> ScenarioSet:
        """The capability's scenarios (those of :attr:`scenario_file` when given); the first is
        the default one both stages use."""
        if self._scenarios is None:
            from skillwright.sim.bindings import bind_interfaces
            from skillwright.sim.scenario import scenarios_for

            localised = bind_interfaces(self.inventory).has_localisation
            self._scenarios = scenarios_for(
                self.capability, self.scenario_file, localised=localised
            )
        return self._scenarios

    def default_scenario(self) -> Scenario:
        """The capability's default scenario."""
        return self.scenarios().scenarios[0]

    def run_budget(self, duration: float) -> float:
        """The wall seconds a run of a scenario of ``duration`` virtual seconds gets:
        :attr:`run_seconds` per :data:`~skillwright.sim.derive.DEFAULT_DURATION` of them,
        never less than :attr:`run_seconds`. A scenario's duration grows with its inputs
        (distance / speed, angle / rate, its times:
        :func:`~skillwright.sim.derive.derived_duration`), and a skill that must drive 4 m at
        0.4 m/s is not to be cut off as if it had 1 m."""
        from skillwright.sim.derive import DEFAULT_DURATION

        return self.run_seconds * max(1.0, duration / DEFAULT_DURATION)

    def sim_budget(self) -> float:
        """The wall seconds a simulation in every scenario gets: :attr:`sim_seconds` per
        :data:`SIM_REFERENCE_SECONDS` virtual seconds of the scenarios' durations together,
        never less than :attr:`sim_seconds` (see :meth:`run_budget`)."""
        total = sum(s.duration for s in self.scenarios().scenarios)
        return self.sim_seconds * max(1.0, total / SIM_REFERENCE_SECONDS)

    def _cancelled(self) -> bool:
        return self.cancel is not None and self.cancel.is_set()

    def run(self, code: str, *, repairing: bool = False) -> RunResult:
        """Runs ``code`` (once per distinct code) in the default scenario."""
        key = _digest(code)
        if key in self._runs:
            return self._runs[key]
        from skillwright.runtime.run import run_skill
        from skillwright.runtime.waits import probe_waits
        from skillwright.sim.validate import runtime_scenario

        started = time.perf_counter()
        default = self.default_scenario()
        seconds = self.run_budget(default.duration)
        budget = _Budget(seconds, self.cancel)
        try:
            scenario = runtime_scenario(default)
            deadlines = scenario.deadlines.model_copy(
                update={"run": min(scenario.deadlines.run, seconds)}
            )
            scenario = scenario.model_copy(update={"world": RUN_WORLD, "deadlines": deadlines})
            with budget.running() as cancel:

                def run(source: str) -> RunReport:
                    return run_skill(
                        self.skill_path,
                        self.inventory,
                        scenario=scenario,
                        source=source,
                        cancel=cancel,
                        isolated=self.isolated,
                    )

                report = run(code)
                try:
                    report = probe_waits(report, code, run, scenario.deadlines.state)
                except GenerationCancelledError:
                    # the budget ran out in the second run: the first one's findings stand
                    if self._cancelled() or not budget.expired:
                        raise
            report = report.model_copy(update={"findings": self.selection.filter(report.findings)})
            result = RunResult(report, time.perf_counter() - started)
        except GenerationCancelledError:
            if self._cancelled() or not budget.expired:
                raise
            result = RunResult(
                None,
                time.perf_counter() - started,
                f"stopped after its budget of {seconds:.0f} s",
            )
        except SandboxUnavailableError:
            raise
        except SkillwrightError as error:
            result = RunResult(None, time.perf_counter() - started, f"could not run: {error}")
        self._runs[key] = result
        self.repair_runs += repairing
        return result

    def simulate(self, code: str, *, repairing: bool = False) -> SimResult:
        """Validates ``code`` (once per distinct code) in MuJoCo in every scenario."""
        key = _digest(code)
        if key in self._sims:
            return self._sims[key]
        from skillwright.sim.validate import validate_skill

        started = time.perf_counter()
        seconds = self.sim_budget()
        budget = _Budget(seconds, self.cancel)
        try:
            with budget.running() as cancel:
                report = validate_skill(
                    self.skill_path,
                    self.capability,
                    self.inventory,
                    scenarios=self.scenarios(),
                    output_dir=self.work_dir / key[:16],
                    source=code,
                    cancel=cancel,
                    isolated=self.isolated,
                )
            result = SimResult(report, time.perf_counter() - started)
        except GenerationCancelledError:
            if self._cancelled() or not budget.expired:
                raise
            result = SimResult(
                None,
                time.perf_counter() - started,
                f"stopped after its budget of {seconds:.0f} s",
            )
        except SandboxUnavailableError:
            raise
        except SkillwrightError as error:
            result = SimResult(None, time.perf_counter() - started, f"could not simulate: {error}")
        self._sims[key] = result
        self.repair_sims += repairing
        return result

    def validator(self, static: Validator) -> Validator:
        """``static`` followed, for a candidate without static errors, by the run and (when
        the run found no error) the simulation; all findings go to the repair loop."""

        def validate(code: str, skeleton: Skeleton) -> list[Finding]:
            findings = static(code, skeleton)
            if _errors(findings) or not self.enabled:
                return findings
            found: list[Finding] = []
            if self.run_enabled:
                found += self.run(code, repairing=True).findings
            if self.sim_enabled and not _errors(found):
                found += self.simulate(code, repairing=True).findings
            extra = [f for f in dict.fromkeys(found) if f not in findings]
            return sorted([*findings, *extra], key=lambda f: (f.line, f.check, f.message))

        return validate

    def run_record(self, result: RunResult) -> RunRecord:
        """What ``record.json`` keeps of a run."""
        report = result.report
        if report is None:
            return RunRecord(
                passed=False,
                skipped=result.skipped,
                seconds=round(result.seconds, 3),
                repair_runs=self.repair_runs,
            )
        episodes = []
        for episode in report.trace.episodes:
            published: dict[str, int] = {}
            goals = 0
            for event in episode.events:
                if event.get("kind") == "publish":
                    topic = str(event.get("topic"))
                    published[topic] = published.get(topic, 0) + 1
                elif event.get("kind") == "goal":
                    goals += 1
            episodes.append(
                RunEpisodeRecord(
                    name=episode.name,
                    ended=episode.ended,
                    states=[
                        f"{s.name} {s.outcome}" + (f" ({s.detail})" if s.detail else "")
                        for s in episode.states
                        if s.outcome != "absent"
                    ],
                    virtual_seconds=round(episode.virtual_seconds, 3),
                    wall_seconds=round(episode.wall_seconds, 3),
                    outputs=episode.outputs,
                    published=published,
                    goals=goals,
                )
            )
        errors = _errors(report.findings)
        return RunRecord(
            passed=report.passed,
            world=report.trace.world,
            inputs=report.trace.inputs,
            errors=errors,
            warnings=len(report.findings) - errors,
            findings=report.findings,
            episodes=episodes,
            isolation=_isolation(report),
            seconds=round(result.seconds, 3),
            repair_runs=self.repair_runs,
        )

    def sim_record(
        self, result: SimResult, plot: str | None, trace: str | None = None
    ) -> SimulationRecord:
        """What ``record.json`` keeps of a simulation; ``plot`` and ``trace`` are the names
        of the plot's and the trace's files in the output folder."""
        report = result.report
        if report is None or not report.scenarios:
            return SimulationRecord(
                passed=False,
                skipped=result.skipped or "no scenario ran",
                seconds=round(result.seconds, 3),
                repair_runs=self.repair_sims,
            )
        scenario = report.scenarios[0]
        verdicts = [
            VerdictRecord(scenario=each.name, episode=episode.episode, **verdict.model_dump())
            for each in report.scenarios
            for episode in each.episodes
            for verdict in episode.verdicts
        ]
        normal = next((e for e in scenario.episodes if e.episode == "normal"), None)
        speed = None if normal is None or normal.speed is None else round(normal.speed, 1)
        return SimulationRecord(
            passed=report.passed,
            scenario=scenario.name,
            others=[each.name for each in report.scenarios[1:]],
            scenario_source=report.scenario_source,
            world=scenario.world,
            inputs=scenario.inputs,
            verdicts=verdicts,
            findings=report.findings,
            plot=plot,
            trace=trace,
            speed=speed,
            seconds=round(result.seconds, 3),
            repair_runs=self.repair_sims,
        )
