"""What the record says of a simulation over several scenarios."""

from __future__ import annotations

from skillwright.pipeline.record import SimulationRecord, VerdictRecord


def _verdict(scenario: str, passed: bool) -> VerdictRecord:
    return VerdictRecord(
        scenario=scenario,
        episode="normal",
        oracle="output:outAngle",
        kind="output",
        check="outAngle = nearest_obstacle_bearing",
        passed=passed,
        message="reported -0.2269, measured 0: off by 0.227 rad (tolerance 0.2)",
    )


def test_one_scenario_is_named_alone() -> None:
    record = SimulationRecord(
        passed=True, scenario="wall_to_the_right", verdicts=[_verdict("wall_to_the_right", True)]
    )
    assert record.where == "wall_to_the_right"
    assert record.verdict_place(record.verdicts[0]) == "normal"


def test_several_scenarios_name_the_one_of_each_verdict() -> None:
    failed = _verdict("obstacle_ahead", False)
    record = SimulationRecord(
        passed=False,
        scenario="wall_to_the_right",
        others=["obstacle_ahead"],
        verdicts=[_verdict("wall_to_the_right", True), failed],
    )
    assert record.where == "wall_to_the_right and 1 more scenario(s)"
    assert record.verdict_place(failed) == "obstacle_ahead normal"
