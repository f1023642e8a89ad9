"""Validating skills end to end: the sandboxed runtime, the MuJoCo world, the oracles."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.capability.model import Capability
from skillwright.interfaces.inventory import Inventory
from skillwright.sim.scenario import scenarios_for
from skillwright.sim.validate import validate_skill
from tests.sim.mutants import MUTANTS as BEHAVIOUR_MUTANTS
from tests.sim.mutants import SKILLS

HERE = Path(__file__).parent
SKILL = HERE / "skills" / "move_forward.py"
SCENARIOS = HERE / "move_forward.scenarios.yaml"


def _mutant(tmp_path: Path, *edits: tuple[str, str]) -> Path:
    text = SKILL.read_text(encoding="utf-8")
    for old, new in edits:
        assert old in text, f"the mutation does not apply: {old!r}"
        text = text.replace(old, new)
    path = tmp_path / "mutant.py"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_correct_skill_passes_every_scenario_and_leaves_plots_and_traces(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], mr1_inventory: Inventory
) -> None:
    progress: list[str] = []
    report = validate_skill(
        SKILL,
        mr1_capabilities["move-forward"],
        mr1_inventory,
        scenario_file=SCENARIOS,
        output_dir=tmp_path,
        on_progress=lambda p: progress.append(p.event),
    )
    assert report.failed_oracles() == [], report.findings
    assert report.passed
    metre, fast = report.scenarios
    assert [e.episode for e in metre.episodes] == ["normal", "stop"]
    assert [e.ended for e in metre.episodes] == ["completed", "stopped"]
    assert [e.episode for e in fast.episodes] == ["normal"]
    assert metre.plot
    assert Path(metre.plot).read_bytes().startswith(b"\x89PNG")
    assert metre.trace
    assert '"ground_truth"' in Path(metre.trace).read_text()
    assert progress[0] == "scenario-start"
    assert progress[-1] == "scenario-end"
    assert metre.episodes[0].virtual_seconds > 2.0
    assert metre.episodes[0].world_seconds > 0


MUTANTS = {
    "ignores the distance, reports the request": (
        "fast",
        [
            ("self._travelled() < self.in_distance:", "self._travelled() < 0.5:"),
            ("self.out_distance = self._travelled()", "self.out_distance = self.in_distance"),
        ],
        {"truth:distanceCovered", "output:outDistance"},
    ),
    "exceeds the speed limit": (
        "fast",
        [
            (
                "top = min(abs(self.in_linear_velocity), self.SPEED_LIMIT)",
                "top = abs(self.in_linear_velocity)",
            )
        ],
        {"limit:linearVelocity"},
    ),
    "wrong sign": (
        "fast",
        [("command.linear.x = max(", "command.linear.x = -max(")],
        {"truth:distanceCovered"},
    ),
    "never stops": (
        "fast",
        [("        self.publisher.publish(Twist())\n", "        self.active = False\n")],
        {"rest:completing"},
    ),
}


@pytest.mark.parametrize("mutant", sorted(MUTANTS))
def test_a_mutant_fails_the_oracle_that_describes_its_fault(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], mr1_inventory: Inventory, mutant: str
) -> None:
    scenario, edits, oracles = MUTANTS[mutant]
    skill = _mutant(tmp_path, *edits)
    report = validate_skill(
        skill,
        mr1_capabilities["move-forward"],
        mr1_inventory,
        scenario_file=SCENARIOS,
        only=[scenario],
    )
    failed = {
        v.oracle for e in report.scenarios[0].episodes for v in e.verdicts if v.passed is False
    }
    assert oracles <= failed
    assert not report.passed
    lines = {f.line for f in report.findings if f.check.startswith("behaviour.")}
    text = skill.read_text().splitlines()
    assert all(text[line - 1].lstrip().startswith("def ") for line in lines), (
        "findings point at state methods"
    )


def test_a_heading_outside_the_interval_its_capability_promises_fails_its_constraint(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], mr1_inventory: Inventory
) -> None:
    # Angles are equal on the circle (-1.2 = 5.08), so only the capability's own bounds on
    # outHeading tell an unwrapped yaw from the [0, 2*pi) heading it promises.
    (mutant,) = [m for m in BEHAVIOUR_MUTANTS if m.id == "get_position:out-of-its-range"]
    skill = tmp_path / "get_position.py"
    skill.write_text(mutant.source(), encoding="utf-8")
    report = validate_skill(
        skill, mr1_capabilities["get-position"], mr1_inventory, only=[mutant.scenario]
    )
    failed = {
        v.oracle for e in report.scenarios[0].episodes for v in e.verdicts if v.passed is False
    }
    # what the simulator measures is wrapped; what the skill reports is not
    assert failed == {"constraint:headingNotNegative"}


def test_only_selects_scenarios_and_the_shipped_ones_are_used_by_default(
    mr1_capabilities: dict[str, Capability],
) -> None:
    chosen = scenarios_for(mr1_capabilities["move-forward"])
    assert [s.name for s in chosen.scenarios] == [
        "straight_ahead",
        "too_fast_asked",
        "backwards_refused",
    ]


def test_a_cancelled_validation_leaves_no_files_behind(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], mr1_inventory: Inventory
) -> None:
    import threading

    from skillwright.errors import GenerationCancelledError

    cancel = threading.Event()

    def stop_at_the_second_scenario(progress: object) -> None:
        if getattr(progress, "index", 0) == 1:
            cancel.set()

    with pytest.raises(GenerationCancelledError):
        validate_skill(
            SKILL,
            mr1_capabilities["move-forward"],
            mr1_inventory,
            scenario_file=SCENARIOS,
            output_dir=tmp_path,
            on_progress=stop_at_the_second_scenario,
            cancel=cancel,
        )
    assert list(tmp_path.iterdir()) == []


def test_a_turn_that_overshoots_in_mujoco_is_watched_and_told_why(
    tmp_path: Path, mr1_capabilities: dict[str, Capability], mr1_inventory: Inventory
) -> None:
    # Full speed to the end, no turning back and a band of 1 mrad: the turn goes past its
    # target and on, until the state's deadline.
    text = (SKILLS / "rotate.py").read_text(encoding="utf-8")
    edits = (
        ("TOLERANCE = 0.01", "TOLERANCE = 0.001"),
        ("max(0.05, min(rate, abs(self.remaining) * 2.0))", "rate"),
        ("if self.remaining * direction < 0.0:", "if False:"),
    )
    for old, new in edits:
        assert old in text
        text = text.replace(old, new)
    skill = tmp_path / "rotate.py"
    skill.write_text(text, encoding="utf-8")

    report = validate_skill(skill, mr1_capabilities["rotate"], mr1_inventory, only=["quarter_left"])

    [timeout] = [f for f in report.findings if f.check == "run.timeout"]
    said = timeout.message.split("; watched on every pass in a second run, ", 1)[1]
    assert said.startswith("`self.remaining` went past zero once")
    assert "so the robot steps over its goal between two checks" in said


@pytest.mark.parametrize(
    ("scanners", "passed"), [('("/scan", "/scan2")', True), ('("/scan",)', False)]
)
def test_the_papers_robot_measured_with_one_of_its_two_corner_scanners_fails(
    tmp_path: Path, shared_data: Path, scanners: str, passed: bool
) -> None:
    # Without recorded scans each of the two scanners sees one half; the derived scenario's
    # nearest wall is behind the robot, on the rear scanner's side.
    from skillwright.capability.reader import load_capability
    from skillwright.interfaces.load import load_inventory

    data = shared_data / "cap2skill"
    capability = load_capability(
        data / "capability-models" / "get-distance-to-nearest-object.ttl"
    ).capability
    inventory = load_inventory(data / "interface-reports" / "ros2_system_report.json")
    text = (HERE / "skills" / "nearest_of_two_scanners.py").read_text(encoding="utf-8")
    skill = tmp_path / "skill.py"
    skill.write_text(text.replace('SCANNERS = ("/scan", "/scan2")', f"SCANNERS = {scanners}"))
    report = validate_skill(skill, capability, inventory)
    assert report.passed is passed, report.findings
    if not passed:
        failed = set(report.failed_oracles())
        assert {"derived/normal/output:outDistance", "derived/normal/output:outDegree"} <= failed
