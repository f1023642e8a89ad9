"""Derived scenarios: each variant rule on the shipped and the paper's capability models,
and deadlines from the inputs."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from skillwright.capability.model import Capability
from skillwright.sim.derive import (
    DEFAULT_DURATION,
    derived_duration,
    derived_scenarios,
    input_roles,
    violated_preconditions,
)
from skillwright.sim.scenario import Scenario, scenarios_for


@pytest.fixture(scope="module")
def paper_capabilities(shared_data: Path) -> dict[str, Capability]:
    """The paper's nine capability models by file stem."""
    from skillwright.capability.reader import load_capability

    folder = shared_data / "cap2skill" / "capability-models"
    return {p.stem: load_capability(p).capability for p in sorted(folder.glob("*.ttl"))}


def _by_name(capability: Capability) -> dict[str, Scenario]:
    return {s.name: s for s in derived_scenarios(capability)}


def test_every_model_gets_a_few_described_scenarios_the_nominal_first(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    for name, capability in [*mr1_capabilities.items(), *paper_capabilities.items()]:
        scenarios = derived_scenarios(capability)
        assert 1 <= len(scenarios) <= 6, name
        assert scenarios[0].name == "derived"
        assert scenarios[0].start.x == scenarios[0].start.y == scenarios[0].start.heading == 0
        names = [s.name for s in scenarios]
        assert len(set(names)) == len(names), name
        assert len({s.seed for s in scenarios}) == len(scenarios), name
        for scenario in scenarios:
            assert len(scenario.description) > 40, (name, scenario.name)
            assert scenario.duration >= DEFAULT_DURATION
            # A scenario that expects completion keeps every precondition.
            broken = violated_preconditions(capability, dict(scenario.inputs))
            assert (scenario.expect == "aborted") == bool(broken), (name, scenario.name)
    moving = [c for n, c in mr1_capabilities.items() if n not in ("move-to-point",)]
    assert all(len(derived_scenarios(c)) >= 2 for c in moving)


def test_roles_come_from_units_and_names(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    assert input_roles(mr1_capabilities["rotate"]) == {
        "inAngle": "angle",
        "inAngularVelocity": "angular_rate",
    }
    roles = input_roles(mr1_capabilities["collision-avoidance"])
    assert roles["inMinObstacleDistance"] == "clearance"
    assert roles["inDuration"] == "time"
    # The paper writes an angular velocity in m/s: its name says angular.
    assert input_roles(paper_capabilities["collision-avoidance"])["inVelocityAngular"] == (
        "angular_rate"
    )
    assert input_roles(paper_capabilities["rotate"])["inDegree"] == "angle"
    assert input_roles(mr1_capabilities["navigate-to-point"])["inPositionX"] == "position"


def test_negative_turns_an_angle_or_a_velocity_only_motion_the_other_way(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    rotate = _by_name(mr1_capabilities["rotate"])
    assert rotate["negative"].inputs["inAngle"] == -rotate["derived"].inputs["inAngle"]
    # The rate's magnitude is used: the direction is the angle's.
    assert rotate["negative"].inputs["inAngularVelocity"] > 0
    paper = _by_name(paper_capabilities["rotate"])
    assert paper["derived"].inputs["inDegree"] == 90.0
    assert paper["negative"].inputs["inDegree"] == -90.0
    velocity = _by_name(mr1_capabilities["set-velocity"])["negative"].inputs
    assert float(velocity["inLinearVelocity"]) < 0
    assert float(velocity["inAngularVelocity"]) < 0
    # A distance bounds the motion and its model does not say it is signed: forward only.
    assert "negative" not in _by_name(mr1_capabilities["move-forward"])
    assert "negative" not in _by_name(paper_capabilities["move-forward"])
    assert "negative" not in _by_name(mr1_capabilities["navigate-to-point"])


def test_a_length_its_model_calls_signed_is_negated(
    mr1_capabilities: dict[str, Capability],
) -> None:
    forward = mr1_capabilities["move-forward"]
    parameters = [
        p.model_copy(update={"comment": "Distance to drive; negative drives backwards."})
        if p.name == "inDistance"
        else p
        for p in forward.inputs
    ]
    signed = forward.model_copy(update={"inputs": parameters, "constraints": []})
    negative = _by_name(signed)["negative"]
    assert float(negative.inputs["inDistance"]) < 0
    assert float(negative.inputs["inLinearVelocity"]) > 0


def test_wraps_turns_across_pi_from_a_heading_near_pi(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    wraps = _by_name(mr1_capabilities["rotate"])["wraps"]
    heading = wraps.start.heading
    angle = float(wraps.inputs["inAngle"])
    # An angle to turn by: past half a turn, across +-pi and then zero.
    assert heading < math.pi < 2 * math.pi < heading + angle
    assert math.pi < angle < 2 * math.pi
    # An angle that may be a target heading stays below half a turn.
    degrees = float(_by_name(paper_capabilities["rotate"])["wraps"].inputs["inDegree"])
    assert 90.0 < degrees < 180.0
    # Without an angle there is nothing to wrap.
    assert "wraps" not in _by_name(mr1_capabilities["set-velocity"])


def test_elsewhere_starts_away_from_the_origin_with_other_magnitudes(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    for capability in (
        mr1_capabilities["get-position"],
        mr1_capabilities["rotate"],
        paper_capabilities["get-position"],
        mr1_capabilities["get-distance-to-nearest-object"],
    ):
        scenarios = _by_name(capability)
        start = scenarios["elsewhere"].start
        assert math.hypot(start.x, start.y) > 1.0
        assert abs(start.heading) > 1.0
    forward = _by_name(mr1_capabilities["move-forward"])
    nominal, other = forward["derived"].inputs, forward["elsewhere"].inputs
    assert float(other["inDistance"]) != float(nominal["inDistance"])
    assert float(other["inLinearVelocity"]) != float(nominal["inLinearVelocity"])
    # The arm's target is in the arm's own frame: the base's start pose changes nothing.
    assert "elsewhere" not in _by_name(mr1_capabilities["move-to-point"])


def test_clipped_asks_above_the_stated_limits_only(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    clipped = _by_name(mr1_capabilities["set-velocity"])["clipped"].inputs
    assert float(clipped["inLinearVelocity"]) > 0.8
    assert float(clipped["inAngularVelocity"]) > 1.2
    rotate = _by_name(mr1_capabilities["rotate"])["clipped"].inputs
    assert float(rotate["inAngularVelocity"]) > 1.2
    # The paper's set-velocity states no limit: nothing to clip to.
    assert "clipped" not in _by_name(paper_capabilities["set-velocity"])


def test_refused_breaks_a_precondition_and_expects_an_abort(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    forward = _by_name(mr1_capabilities["move-forward"])["refused"]
    assert forward.expect == "aborted"
    assert float(forward.inputs["inDistance"]) < 0
    arm = _by_name(mr1_capabilities["move-to-point"])["refused"]
    reach = math.sqrt(sum(float(arm.inputs[f"inPosition{a}"]) ** 2 for a in "XYZ"))
    assert reach > 0.85
    assert violated_preconditions(mr1_capabilities["move-to-point"], dict(arm.inputs)) == [
        "targetInReach"
    ]
    assert "refused" not in _by_name(paper_capabilities["move-forward"])


def test_obstacle_where_a_range_is_read(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    drive = _by_name(mr1_capabilities["collision-avoidance"])["obstacle"]
    assert drive.world == "corridor"
    assert drive.inputs["inAngularVelocity"] == 0.0
    assert drive.inputs["inLinearVelocityY"] == 0.0
    speed = float(drive.inputs["inLinearVelocityX"])
    # Long enough to reach the box 4 m down the corridor: only the clearance can stop it.
    assert speed * float(drive.inputs["inDuration"]) > 4.0 - drive.start.x
    assert drive.duration >= 2 * float(drive.inputs["inDuration"])
    sense = _by_name(mr1_capabilities["get-distance-to-nearest-object"])["obstacle"]
    assert sense.world == "corridor"
    assert not isinstance(sense.noise, str)
    assert sense.noise.scan_invalid == pytest.approx(0.1)  # the model promises valid returns
    paper = _by_name(paper_capabilities["get-distance-to-nearest-object"])["obstacle"]
    assert paper.noise == "default"
    assert "obstacle" in _by_name(paper_capabilities["collision-avoidance"])
    for name in ("rotate", "mapping", "move-forward", "get-position"):
        assert "obstacle" not in _by_name(mr1_capabilities[name]), name


def test_deadlines_grow_with_distance_over_speed_and_angle_over_rate(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    forward = mr1_capabilities["move-forward"]
    assert derived_duration(forward, {"inDistance": 1.0, "inLinearVelocity": 0.3}) == 30.0
    # 8 m at 0.4 m/s is 20 s of driving: twice that and 10 s.
    assert derived_duration(forward, {"inDistance": 8.0, "inLinearVelocity": 0.4}) == 50.0
    # A speed above the limit is driven at the limit.
    assert derived_duration(forward, {"inDistance": 16.0, "inLinearVelocity": 3.0}) == 50.0
    rotate = mr1_capabilities["rotate"]
    assert derived_duration(rotate, {"inAngle": -6.0, "inAngularVelocity": 0.2}) == 70.0
    collision = mr1_capabilities["collision-avoidance"]
    inputs = {"inDuration": 40.0, "inLinearVelocityX": 0.2, "inMinObstacleDistance": 0.5}
    assert derived_duration(collision, inputs) == 90.0
    # Without a speed input, the speed a derived input would get (half the limit at most).
    navigate = mr1_capabilities["navigate-to-point"]
    far = derived_duration(navigate, {"inPositionX": 6.0, "inPositionY": 0.0})
    assert far == math.ceil(2 * (6.0 / 0.3 + math.pi / 0.5) + 10)
    # The distance counts from the start pose, not from the origin.
    from skillwright.sim.scenario import StartPose

    near = derived_duration(navigate, {"inPositionX": 6.0, "inPositionY": 0.0}, StartPose(x=5.5))
    assert near < far
    paper_forward = paper_capabilities["move-forward"]
    assert derived_duration(paper_forward, {"inDistance": 1.0, "inTime": 65.0}) > 130.0


def test_scenarios_for_a_capability_without_a_file_are_the_derived_ones(
    mr1_capabilities: dict[str, Capability],
) -> None:
    capability = mr1_capabilities["rotate"].model_copy(update={"iri": "urn:other"})
    chosen = scenarios_for(capability)
    assert [s.name for s in chosen.scenarios] == [s.name for s in derived_scenarios(capability)]
    assert "5 scenario(s) derived" in chosen.notes[0]
    for scenario in chosen.scenarios:
        assert scenario.ground_truth["outHeading"] == "heading"


def test_a_files_scenario_without_a_duration_gets_one_from_its_inputs(
    tmp_path: Path, mr1_capabilities: dict[str, Capability]
) -> None:
    path = tmp_path / "far.yaml"
    path.write_text(
        "capability: http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward\n"
        "scenarios:\n"
        "  - name: far\n    inputs: {inDistance: 4.0, inLinearVelocity: 0.2}\n"
        "  - name: given\n    inputs: {inDistance: 4.0, inLinearVelocity: 0.2}\n"
        "    duration: 25\n",
        encoding="utf-8",
    )
    chosen = scenarios_for(mr1_capabilities["move-forward"], path)
    far, given = chosen.scenarios
    assert far.duration == 50.0
    assert given.duration == 25.0
    assert any("far: no duration given; 50 s derived" in n for n in chosen.notes)


def test_an_angle_its_words_call_a_turn_is_bound_to_the_measured_turn(
    mr1_capabilities: dict[str, Capability], paper_capabilities: dict[str, Capability]
) -> None:
    # "Angle to turn by; positive turns counter-clockwise": a turn the other way round to the
    # same heading keeps the heading constraint but not the measured turn.
    for scenario in derived_scenarios(mr1_capabilities["rotate"]):
        assert scenario.ground_truth == {"inAngle": "turned"}, scenario.name
    # "the degree of any angle" may be a target heading: not bound.
    for scenario in derived_scenarios(paper_capabilities["rotate"]):
        assert "inDegree" not in scenario.ground_truth


def test_without_a_map_frame_poses_are_judged_where_odometry_and_map_coincide(
    mr1_capabilities: dict[str, Capability],
) -> None:
    # A robot without localisation knows its pose only from odometry, which starts where it
    # starts: away from the origin no skill could report the map pose the simulator measures.
    for name in ("get-position", "rotate"):
        scenarios = {s.name: s for s in derived_scenarios(mr1_capabilities[name], localised=False)}
        for scenario in scenarios.values():
            assert (scenario.start.x, scenario.start.y, scenario.start.heading) == (0, 0, 0)
        assert "elsewhere" in scenarios
    rotate = {s.name: s for s in derived_scenarios(mr1_capabilities["rotate"], localised=False)}
    nominal = _by_name(mr1_capabilities["rotate"])["derived"].inputs["inAngle"]
    assert rotate["elsewhere"].inputs["inAngle"] != nominal
    assert float(rotate["wraps"].inputs["inAngle"]) > math.pi
