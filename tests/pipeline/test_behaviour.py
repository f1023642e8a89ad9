"""The run and simulate stages: a generated skill is run and simulated, and what they find
goes back to the model."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from skillwright.pipeline import GenerationRecord, run_generation
from skillwright.pipeline.events import Event, StageFinished, StageStarted
from tests.fixtures.scripted import MethodScript
from tests.pipeline.conftest import SET_VELOCITY, stems, use_model
from tests.pipeline.test_run import request


@pytest.fixture(autouse=True)
def shared_matplotlib_cache(
    tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The isolated XDG folders would make matplotlib build its font cache for every test."""
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path_factory.getbasetemp() / "matplotlib"))


MEASURED_EXECUTE = SET_VELOCITY["execute"][0].replace(
    """        twist = self.odom_msg.twist.twist
        self._wait_until(
            lambda: abs(self.odom_msg.twist.twist.linear.x - linear) <= 0.05, 5.0, "the velocity"
        )
""",
    """        self._wait_until(
            lambda: abs(self.odom_msg.twist.twist.linear.x - linear) <= 0.01
            and abs(self.odom_msg.twist.twist.angular.z - angular) <= 0.01,
            5.0,
            "the velocity",
        )
        twist = self.odom_msg.twist.twist
""",
)
"""The scripted execute, waiting until the velocity is reached and reading it then (rather
than the one before it, as the static checks' fixture does)."""


@pytest.mark.slow
def test_a_generated_skill_that_runs_clean_passes_the_run_and_the_simulation(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert SET_VELOCITY["execute"][0] != MEASURED_EXECUTE
    model = MethodScript({**SET_VELOCITY, "execute": [MEASURED_EXECUTE]}, model_id="tiny")
    use_model(monkeypatch, model)
    events: list[Event] = []
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, run=True, simulate=True),
        on_event=events.append,
    )
    assert stems(events, StageStarted)[-4:] == ["checks", "run", "simulate", "outputs"]
    assert stems(events, StageFinished) == stems(events, StageStarted)
    record = GenerationRecord.load(outcome.record_path)
    assert record.run is not None
    assert record.run.passed, record.run.findings
    assert record.run.world == "kinematic"
    assert record.run.episodes[0].states[:2] == ["starting done", "execute done"]
    assert record.run.episodes[0].published["/cmd_vel"] > 0
    assert record.simulation is not None
    assert record.simulation.passed, [v.message for v in record.simulation.verdicts]
    assert record.simulation.scenario == "arc"
    # every scenario of the capability, each verdict with its own
    assert record.simulation.others == ["clipped"]
    assert {v.scenario for v in record.simulation.verdicts} == {"arc", "clipped"}
    assert any(v.kind == "constraint" and v.passed for v in record.simulation.verdicts)
    assert record.simulation.plot == "simulation.png"
    assert (outcome.out_dir / "simulation.png").read_bytes().startswith(b"\x89PNG")
    assert "simulation.png" in record.files
    # The trace the plot is drawn from is kept too, for a terminal to draw it again.
    assert record.simulation.trace == "simulation.trace.json"
    assert "ground_truth" in (outcome.out_dir / "simulation.trace.json").read_text("utf-8")
    assert outcome.passed
    # Each stage ended with the verdict the record keeps.
    ended = {e.stage: e.verdict for e in events if isinstance(e, StageFinished)}
    assert ended == {stage: record.verdicts[stage] for stage in ended}
    assert [record.verdicts[s] for s in ("checks", "run", "simulate")] == ["passed"] * 3
    # One run and one simulation of the one file the model wrote, reused by the stages.
    assert (record.run.repair_runs, record.simulation.repair_runs) == (1, 1)


def _asks(model: MethodScript, method: str) -> list[str]:
    """The last user message of every request for ``method``."""
    return [
        prompt.messages[-1].content
        for prompt, asked in zip(model.prompts, model.asked, strict=True)
        if asked == method
    ]


RAISES_IN_COMPLETING = """        percent = int(str(self.out_linear_velocity))
        self.node.get_logger().info(f"measured {percent} m/s")
```"""
"""A completing that passes the static checks and raises ValueError when it runs."""


def test_a_method_that_fails_at_run_time_gets_a_run_finding_and_is_repaired(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    answers = {**SET_VELOCITY, "completing": [RAISES_IN_COMPLETING, *SET_VELOCITY["completing"]]}
    model = MethodScript(answers, model_id="tiny")
    use_model(monkeypatch, model)
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, run=True, attempts=2)
    )
    assert outcome.record.model is not None
    tries = [a for a in outcome.record.model.attempts if a.target == "completing"]
    assert [(a.number, a.errors, a.chosen) for a in tries] == [(1, 1, False), (2, 0, True)]
    assert "ValueError" in tries[1].problems[0]
    assert "int(str(self.out_linear_velocity))" in _asks(model, "completing")[1]
    run = outcome.record.run
    assert run is not None
    assert run.passed, run.findings
    assert run.repair_runs == 2
    assert outcome.record.simulation is None
    assert "int(str(" not in outcome.skill_path.read_text(encoding="utf-8")


@pytest.mark.slow
def test_a_failed_oracle_in_the_simulation_reaches_the_models_repair_prompt(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The scripted execute passes the static checks and runs, but stores the velocity read
    # before the base reached it: the simulation's ground truth shows the output is wrong.
    model = MethodScript(dict(SET_VELOCITY), model_id="tiny")
    use_model(monkeypatch, model)
    events: list[Event] = []
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, simulate=True, attempts=2),
        on_event=events.append,
    )
    assert "run" not in stems(events, StageStarted)
    simulation = outcome.record.simulation
    assert simulation is not None
    assert not simulation.passed
    failed = {v.oracle for v in simulation.verdicts if v.passed is False}
    assert any(o.startswith("output:outAngularVelocity") for o in failed), failed
    assert any(f.check.startswith("behaviour.") for f in simulation.findings)
    repair = _asks(model, "execute")[1]
    assert "scenario arc" in repair
    assert "outAngularVelocity" in repair
    assert not outcome.passed
    ended = {e.stage: e.verdict for e in events if isinstance(e, StageFinished)}
    assert (ended["checks"], ended["simulate"]) == ("passed", "failed")
    assert outcome.record.verdicts["simulate"] == "failed"
    assert outcome.record.verdicts["run"] == "skipped"  # turned off in this request
    # The repair repeated the answer: the same file is not simulated again.
    assert simulation.repair_runs == 1


def test_a_wait_that_gives_up_on_the_moving_base_gets_a_measured_timeout_without_the_model(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The velocity wait allows 0.01 s: the base is still speeding up when it gives up. A
    # second run allowing most of the state's deadline gets past it, and the fix puts a
    # number measured there in the call, which the repair loop applies without the model.
    impatient = MEASURED_EXECUTE.replace("            5.0,\n", "            0.01,\n")
    assert impatient != MEASURED_EXECUTE
    model = MethodScript({**SET_VELOCITY, "execute": [impatient]}, model_id="tiny")
    use_model(monkeypatch, model)
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, run=True, attempts=1)
    )
    assert outcome.record.model is not None
    tries = [a for a in outcome.record.model.attempts if a.target == "execute"]
    assert [(a.number, a.finish) for a in tries] == [(1, "stop"), (2, "fixed")], tries
    assert any("the wait that gave up allows 0.01 s" in p for p in tries[1].problems)
    run = outcome.record.run
    assert run is not None
    assert run.passed, run.findings
    # The skill holds the checks' own fix: its writing was fixed automatically, not failed.
    assert tries[1].chosen
    assert outcome.record.verdicts["generation"] == "fixed automatically"
    assert outcome.record.verdicts["run"] == "passed"
    code = outcome.skill_path.read_text(encoding="utf-8")
    allowed = re.search(r"<= 0\.01\n\s+and .*<= 0\.01,\n\s+([\d.]+),\n", code)
    assert allowed is not None, code
    assert float(allowed[1]) >= 1.0  # the lambda's tolerance 0.01 is not a timeout
    assert f"allows {float(allowed[1]):g} s" in tries[1].problems[0]
    assert len(_asks(model, "execute")) == 1


def test_the_scenarios_come_from_the_file_the_request_names_else_the_shipped_one(
    tmp_path: Path,
) -> None:
    from skillwright.capability.reader import load_capability
    from skillwright.errors import FileFormatError
    from skillwright.interfaces.inventory import Inventory, Resource
    from skillwright.pipeline.behaviour import Behaviour
    from skillwright.sim.assets import sim_dir
    from tests.conftest import SHIPPED_CAPABILITIES

    capability = load_capability(SHIPPED_CAPABILITIES / "set-velocity.ttl").capability
    inventory = Inventory(resource=Resource(name="mr1"))
    own = tmp_path / "own.scenario.yaml"
    own.write_text(
        f"capability: {capability.iri}\n"
        "scenarios:\n"
        "  - name: slow\n"
        "    inputs: {inLinearVelocity: 0.1, inAngularVelocity: 0.0}\n",
        encoding="utf-8",
    )

    def behaviour(scenario_file: Path | None) -> Behaviour:
        return Behaviour(
            capability, inventory, tmp_path / "skill.py", tmp_path, scenario_file=scenario_file
        )

    chosen = behaviour(own).scenarios()
    assert chosen.source == str(own)
    assert [s.name for s in chosen.scenarios] == ["slow"]
    assert behaviour(own).default_scenario().inputs["inLinearVelocity"] == 0.1
    shipped = behaviour(None).scenarios()
    assert shipped.source == str(sim_dir() / "scenarios" / "set-velocity.yaml")
    other = tmp_path / "other.scenario.yaml"
    other.write_text(
        "capability: http://example.org/other\nscenarios:\n  - name: x\n", encoding="utf-8"
    )
    with pytest.raises(FileFormatError, match="not for"):
        behaviour(other).scenarios()


def test_best_of_n_judges_each_candidate_by_its_run_and_repairs_from_the_winner(
    tmp_path: Path, models_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The greedy candidate's completing raises at run time, the sampled one does not: only
    # running tells them apart (both pass the static checks).
    answers = {**SET_VELOCITY, "completing": [RAISES_IN_COMPLETING, *SET_VELOCITY["completing"]]}
    model = MethodScript(answers, model_id="tiny")
    use_model(monkeypatch, model)
    outcome = run_generation(
        request(tmp_path / "out", models_file=models_file, run=True, attempts=2, candidates=2)
    )
    record = outcome.record.model
    assert record is not None
    assert record.candidates_asked == 2
    first, second = record.candidates
    assert first.errors == 0
    assert first.behaviour_errors
    assert not first.won
    assert second.won
    assert second.behaviour_errors == 0
    assert model.asked.count("completing") == 2  # both candidates, no repair needed
    assert outcome.record.run is not None
    assert outcome.record.run.passed, outcome.record.run.findings
    assert "int(str(" not in outcome.skill_path.read_text(encoding="utf-8")


def test_the_stage_budgets_grow_with_the_scenarios_durations(tmp_path: Path) -> None:
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.inventory import Inventory, Resource
    from skillwright.pipeline.behaviour import Behaviour
    from tests.conftest import SHIPPED_CAPABILITIES

    capability = load_capability(SHIPPED_CAPABILITIES / "move-forward.ttl").capability
    far = tmp_path / "far.scenario.yaml"
    # 8 m at 0.2 m/s: 40 s of driving, a 90 s scenario (twice that and 10 s).
    far.write_text(
        f"capability: {capability.iri}\n"
        "scenarios:\n"
        "  - name: far\n    inputs: {inDistance: 8.0, inLinearVelocity: 0.2}\n"
        "  - name: near\n    inputs: {inDistance: 0.5, inLinearVelocity: 0.4}\n",
        encoding="utf-8",
    )
    behaviour = Behaviour(
        capability,
        Inventory(resource=Resource(name="mr1")),
        tmp_path / "skill.py",
        tmp_path,
        run_seconds=100.0,
        sim_seconds=200.0,
        scenario_file=far,
    )
    assert behaviour.default_scenario().duration == 90.0
    assert behaviour.run_budget(90.0) == pytest.approx(300.0)
    # A scenario of the default length keeps the budget as given, never less.
    assert behaviour.run_budget(30.0) == behaviour.run_budget(10.0) == 100.0
    # 90 + 30 virtual seconds in all: the budget for 120 s of scenarios, as given.
    assert behaviour.sim_budget() == 200.0
