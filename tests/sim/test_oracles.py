"""Oracles from the capability model, judged on ground truth made up for each case."""

from __future__ import annotations

import math

import pytest

from skillwright.capability.model import Capability
from skillwright.sim.oracles import RunView, StateSpan, Verdict, judge
from skillwright.sim.scenario import Scenario
from skillwright.sim.truth import CommandRecord, ContactRecord, GroundTruth, Sample, Sweep

STATES = [
    StateSpan("starting", 0.0, 0.5),
    StateSpan("execute", 0.5, 5.0),
    StateSpan("completing", 5.0, 5.1),
    StateSpan("resetting", 5.1, 5.2),
]


def _truth(
    distance: float,
    *,
    speed: float = 0.4,
    heading: float = 0.0,
    final_yaw: float | None = None,
    last_command: float = 0.0,
) -> GroundTruth:
    """The base drives ``distance`` along x between 1 s and the time it needs, then rests."""
    truth = GroundTruth()
    stop = 1.0 + distance / speed if speed else 1.0
    for k in range(301):
        t = k * 0.02
        moving = 1.0 < t < stop
        x = min(max(t - 1.0, 0.0) * speed, distance)
        yaw = heading if final_yaw is None or t < 3.0 else final_yaw
        truth.add(
            Sample(
                t,
                x,
                0.0,
                yaw,
                speed if moving else 0.0,
                0.0,
                0.0,
                (0.0, 0.0, 0.0),
                (0.0, 0.0, 0.0),
            )
        )
    truth.commands = [
        CommandRecord(1.0, "/cmd_vel", speed, 0.0, 0.0),
        CommandRecord(stop, "/cmd_vel", last_command, 0.0, 0.0),
    ]
    truth.drive = [(c.t, c.vx, c.vy, c.wz, "skill") for c in truth.commands]
    return truth


def _run(outputs: dict[str, object], ended: str = "completed") -> RunView:
    return RunView(states=list(STATES), outputs=outputs, ended=ended, end_time=5.2)  # type: ignore[arg-type]


def _by_oracle(verdicts: list[Verdict]) -> dict[str, Verdict]:
    return {v.oracle: v for v in verdicts}


MOVE = Scenario(
    name="s",
    inputs={"inDistance": 1.5, "inLinearVelocity": 0.4},
    ground_truth={"outDistance": "travelled_distance", "outLinearVelocity": "linear_velocity_x"},
)


def test_a_correct_run_passes_every_oracle(mr1_capabilities: dict[str, Capability]) -> None:
    verdicts = judge(
        mr1_capabilities["move-forward"],
        MOVE,
        _run({"outDistance": 1.505, "outLinearVelocity": 0.0}),
        _truth(1.5),
        "completed",
    )
    failed = [v for v in verdicts if v.passed is False]
    assert failed == []
    assert [v.oracle for v in verdicts] == [
        "outcome",
        "precondition:distanceForward",
        "constraint:distanceCovered",
        "truth:distanceCovered",
        "assured:outLinearVelocity",
        "output:outDistance",
        "output:outLinearVelocity",
        "rest:completing",
        "limit:linearVelocity",
        "contact",
    ]


def test_a_made_up_output_fails_on_ground_truth_but_not_as_reported(
    mr1_capabilities: dict[str, Capability],
) -> None:
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5, "outLinearVelocity": 0.0}),
            _truth(0.7),
            "completed",
        )
    )
    assert verdicts["constraint:distanceCovered"].passed is True
    assert verdicts["truth:distanceCovered"].passed is False
    assert verdicts["output:outDistance"].passed is False
    assert "reported 1.5, measured 0.7" in verdicts["output:outDistance"].message
    assert verdicts["output:outDistance"].state == "execute"


def test_an_output_the_model_asserts_must_be_reported_with_that_value(
    mr1_capabilities: dict[str, Capability],
) -> None:
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5, "outLinearVelocity": 0.4}),
            _truth(1.5),
            "completed",
        )
    )
    assert verdicts["assured:outLinearVelocity"].passed is False
    assert "the model asserts 0.0" in verdicts["assured:outLinearVelocity"].message


def test_an_output_never_set_fails_its_constraint(mr1_capabilities: dict[str, Capability]) -> None:
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": None}),
            _truth(1.5),
            "completed",
        )
    )
    assert verdicts["constraint:distanceCovered"].passed is False
    assert "never set" in verdicts["constraint:distanceCovered"].message
    assert verdicts["output:outDistance"].passed is False


def test_a_command_over_the_limit_fails_with_its_time_and_state(
    mr1_capabilities: dict[str, Capability],
) -> None:
    truth = _truth(1.5)
    truth.commands.insert(1, CommandRecord(2.0, "/cmd_vel", 1.1, 0.0, 0.0))
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5, "outLinearVelocity": 0.0}),
            truth,
            "completed",
        )
    )["limit:linearVelocity"]
    assert verdict.passed is False
    assert (verdict.time, verdict.state) == (2.0, "execute")
    assert "the skill commanded 1.1 m/s, more than 0.8 m/s" in verdict.message


def test_a_contact_fails_naming_what_was_hit(mr1_capabilities: dict[str, Capability]) -> None:
    truth = _truth(1.5)
    truth.contacts.append(ContactRecord(3.2, "obstacle", 4.0, 0.2))
    verdict = _by_oracle(
        judge(mr1_capabilities["move-forward"], MOVE, _run({}), truth, "completed")
    )["contact"]
    assert verdict.passed is False
    assert verdict.state == "execute"
    assert "hit obstacle at t=3.20 s" in verdict.message


def test_a_base_still_commanded_to_move_after_completing_fails_at_the_state_that_sent_it(
    mr1_capabilities: dict[str, Capability],
) -> None:
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5}),
            _truth(1.5, last_command=0.4),
            "completed",
        )
    )["rest:completing"]
    assert verdict.passed is False
    assert verdict.state == "execute"
    assert "still commanded to move (vx 0.4 m/s" in verdict.message


def test_a_running_goal_after_stopping_fails_rest(mr1_capabilities: dict[str, Capability]) -> None:
    truth = _truth(1.5)
    truth.goals = [{"action": "/navigate_to_pose", "accepted": 1.0, "outcome": "executing"}]
    run = RunView(
        states=[StateSpan("execute", 0.5, 2.0, "interrupted"), StateSpan("stopping", 2.0, 2.1)],
        outputs={},
        ended="stopped",
        end_time=2.1,
    )
    verdict = _by_oracle(
        judge(mr1_capabilities["navigate-to-point"], Scenario(name="s"), run, truth, "stopped")
    )["rest:stopping"]
    assert verdict.passed is False
    assert "the goal of /navigate_to_pose was still running" in verdict.message


def test_rest_after_completing_does_not_apply_when_the_capability_keeps_moving(
    mr1_capabilities: dict[str, Capability],
) -> None:
    scenario = Scenario(name="s", inputs={"inLinearVelocity": 0.4, "inAngularVelocity": 0.0})
    verdict = _by_oracle(
        judge(
            mr1_capabilities["set-velocity"],
            scenario,
            _run({"outLinearVelocity": 0.4}),
            _truth(1.5, last_command=0.4),
            "completed",
        )
    )["rest:completing"]
    assert verdict.passed is None
    assert "leaves the base moving" in verdict.message


def test_a_skill_that_completes_what_it_should_refuse_fails_the_outcome_only(
    mr1_capabilities: dict[str, Capability],
) -> None:
    scenario = MOVE.model_copy(
        update={"inputs": {"inDistance": -1.0, "inLinearVelocity": 0.4}, "expect": "aborted"}
    )
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            scenario,
            _run({"outDistance": 0.0}),
            _truth(0.0),
            "aborted",
        )
    )
    assert verdicts["outcome"].passed is False
    assert "expects it to have aborted" in verdicts["outcome"].message
    assert not any(o.startswith(("constraint:", "output:")) for o in verdicts)


def test_the_resource_heading_is_taken_when_execute_begins(
    mr1_capabilities: dict[str, Capability],
) -> None:
    scenario = Scenario(
        name="s",
        inputs={"inAngle": -1.0, "inAngularVelocity": 0.5},
        ground_truth={"outHeading": "heading", "outAngularVelocity": "angular_velocity"},
    )
    truth = _truth(0.0, speed=0.0, heading=0.5, final_yaw=0.5 - 1.0)
    reported = {"outHeading": 2 * math.pi - 0.5, "outAngularVelocity": 0.0}
    verdicts = _by_oracle(
        judge(mr1_capabilities["rotate"], scenario, _run(reported), truth, "completed")
    )
    assert verdicts["constraint:headingTarget"].passed is True
    assert verdicts["truth:headingTarget"].passed is True
    assert verdicts["output:outHeading"].passed is True
    wrong = _by_oracle(
        judge(
            mr1_capabilities["rotate"],
            scenario,
            _run({**reported, "outHeading": 1.5}),
            truth,
            "completed",
        )
    )
    assert wrong["constraint:headingTarget"].passed is False


def _turning(start: float, turned: float) -> GroundTruth:
    """The base turns on the spot by ``turned`` (not wrapped) during execute (1 s to 4 s)."""
    truth = GroundTruth()
    for k in range(301):
        t = k * 0.02
        share = min(max((t - 1.0) / 3.0, 0.0), 1.0)
        yaw = math.remainder(start + share * turned, 2 * math.pi)
        truth.add(Sample(t, 0.0, 0.0, yaw, 0.0, 0.0, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    return truth


@pytest.mark.parametrize(
    ("turned", "passed", "said"),
    [
        (-4.0, True, "turned -4 rad during execute for inAngle -4 (within 0.03)"),
        (2 * math.pi - 4.0, False, "turned 2.283 rad during execute for inAngle -4, the other way"),
    ],
)
def test_a_turn_asked_for_is_measured_the_way_round_it_went(
    mr1_capabilities: dict[str, Capability], turned: float, passed: bool, said: str
) -> None:
    scenario = Scenario(
        name="s",
        inputs={"inAngle": -4.0, "inAngularVelocity": 1.0},
        ground_truth={"inAngle": "turned", "outHeading": "heading"},
    )
    reported = {"outHeading": (1.0 - 4.0) % (2 * math.pi), "outAngularVelocity": 0.0}
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["rotate"], scenario, _run(reported), _turning(1.0, turned), "completed"
        )
    )
    # either way round, the heading is the one asked for
    assert verdicts["truth:headingTarget"].passed is True
    asked = verdicts["asked:inAngle"]
    assert asked.passed is passed
    assert asked.message.startswith(said)


def test_oracles_the_scenario_skips_are_left_out(mr1_capabilities: dict[str, Capability]) -> None:
    scenario = MOVE.model_copy(update={"skip": ["contact", "limit"]})
    verdicts = judge(mr1_capabilities["move-forward"], scenario, _run({}), _truth(1.5), "completed")
    assert not any(v.kind in ("contact", "limit") for v in verdicts)


@pytest.mark.parametrize(("tolerance", "passed"), [(0.05, True), (0.01, False)])
def test_a_scenario_tolerance_for_an_output_replaces_the_units(
    mr1_capabilities: dict[str, Capability], tolerance: float, passed: bool
) -> None:
    scenario = MOVE.model_copy(update={"tolerances": {"outDistance": tolerance}})
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            scenario,
            _run({"outDistance": 1.52}),
            _truth(1.5),
            "completed",
        )
    )["output:outDistance"]
    assert verdict.passed is passed
    assert verdict.tolerance == tolerance


def test_an_angle_in_degrees_is_measured_in_degrees() -> None:
    from skillwright.sim.oracles import measure

    truth = GroundTruth()
    truth.add(Sample(0.0, 0.0, 0.0, -math.pi / 2, 0.0, 0.0, 0.5, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    assert measure("heading", truth, 0.0, 0.0, "°") == pytest.approx(270.0)
    assert measure("heading", truth, 0.0, 0.0, "rad") == pytest.approx(3 * math.pi / 2)
    assert measure("angular_velocity", truth, 0.0, 0.0, "deg/s") == pytest.approx(math.degrees(0.5))


def _publish(t: float, state: str, vx: float) -> dict[str, object]:
    twist = {"linear": {"x": vx, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}
    return {"t": t, "kind": "publish", "state": state, "topic": "/cmd_vel", "message": twist}


def _state(t: float, name: str, phase: str) -> dict[str, object]:
    return {"t": t, "kind": "state", "name": name, "phase": phase}


def test_what_the_next_state_does_at_the_same_instant_does_not_count_for_rest(
    mr1_capabilities: dict[str, Capability],
) -> None:
    events = [
        _state(0.5, "execute", "begin"),
        _publish(1.0, "execute", 0.4),
        _state(2.0, "execute", "end"),
        _state(2.0, "stopping", "begin"),
        _state(2.1, "stopping", "end"),
        _state(2.1, "resetting", "begin"),
        _publish(2.1, "resetting", 0.0),
        _state(2.1, "resetting", "end"),
    ]
    run = RunView(
        states=[
            StateSpan("execute", 0.5, 2.0, "interrupted"),
            StateSpan("stopping", 2.0, 2.1),
            StateSpan("resetting", 2.1, 2.1),
        ],
        outputs={},
        ended="stopped",
        end_time=2.1,
        events=events,
        command_topic="/cmd_vel",
    )
    verdict = _by_oracle(
        judge(mr1_capabilities["move-forward"], MOVE, run, _truth(1.5), "stopped")
    )["rest:stopping"]
    assert verdict.passed is False
    assert "the skill's last command (t=1.00 s, in execute)" in verdict.message


def test_a_goal_the_world_finished_before_the_state_ended_leaves_the_base_at_rest(
    mr1_capabilities: dict[str, Capability],
) -> None:
    goal = {"kind": "world.goal", "action": "/navigate_to_pose", "accepted": 1.0}
    events = [
        _state(0.5, "execute", "begin"),
        {**goal, "t": 1.0, "outcome": "executing"},
        _publish(1.5, "execute", 0.3),
        {**goal, "t": 4.0, "outcome": "succeeded", "finished": 4.0},
        _state(4.5, "execute", "end"),
    ]
    run = RunView(
        states=[StateSpan("execute", 0.5, 4.5)],
        outputs={},
        ended="completed",
        end_time=4.5,
        events=events,
        command_topic="/cmd_vel",
    )
    verdict = _by_oracle(
        judge(
            mr1_capabilities["navigate-to-point"], Scenario(name="s"), run, _truth(1.5), "completed"
        )
    )["rest:execute"]
    assert verdict.passed is True


NEAREST = Scenario(
    name="s",
    ground_truth={
        "outDistance": "nearest_obstacle_distance",
        "outAngle": "nearest_obstacle_bearing",
    },
)


def _flat_wall_and_post(post: bool) -> GroundTruth:
    """A scan of one degree per beam: a flat wall 1 m to the right (nearest at -90 degrees)
    and, with ``post``, a thin post 0.9 m ahead instead, whatever else is 3 m away."""
    truth = _truth(0.0)
    angles = [math.radians(d) for d in range(-180, 180)]
    ranges = [
        1.0 / math.cos(a + math.pi / 2) if abs(a + math.pi / 2) < math.pi / 3 else 3.0
        for a in angles
    ]
    if post:
        ranges[180] = 0.9
    nearest = min(range(360), key=ranges.__getitem__)
    truth.nearest = [(4.0, ranges[nearest], angles[nearest])]
    truth.sweeps = [Sweep(4.0, -math.pi, math.radians(1.0), ranges)]
    return truth


@pytest.mark.parametrize(
    ("post", "reported", "passed"),
    [
        (False, -90.0, True),
        (False, -86.0, True),  # 0.002 m farther: the wall is as near there
        (False, -70.0, False),  # 0.064 m farther
        (False, 90.0, False),
        (True, 0.0, True),
        (True, 4.0, False),  # beside a post the next beam sees the far wall
    ],
)
def test_a_bearing_passes_where_the_nearest_obstacle_is_as_near(
    mr1_capabilities: dict[str, Capability], post: bool, reported: float, passed: bool
) -> None:
    truth = _flat_wall_and_post(post)
    verdict = _by_oracle(
        judge(
            mr1_capabilities["get-distance-to-nearest-object"],
            NEAREST,
            _run({"outDistance": 0.9 if post else 1.0, "outAngle": math.radians(reported)}),
            truth,
            "completed",
        )
    )["output:outAngle"]
    assert verdict.passed is passed
    assert ("as near" in verdict.message) is (passed and reported not in (-90.0, 0.0))


def _braking_truth(
    *, settles: bool = True, start: tuple[float, float, float] = (0, 0, 0)
) -> GroundTruth:
    """The base drives at 0.4 m/s from 1.35 s, is told to stop at 4.9 s and brakes at 1 m/s^2
    until it rests at 5.3 s, 1.5 m from where it began (``settles`` false: it never stops)."""
    truth = GroundTruth(start=start)
    x = 0.0
    for k in range(301):
        t = k * 0.02
        if t <= 1.35:
            speed = 0.0
        elif t <= 4.9 or not settles:
            speed = 0.4
        else:
            speed = max(0.4 - (t - 4.9), 0.0)
        if k:
            x += speed * 0.02
        truth.add(Sample(t, x, 0.0, 0.0, speed, 0.0, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    truth.commands = [CommandRecord(1.35, "/cmd_vel", 0.4, 0.0, 0.0)]
    if settles:
        truth.commands.append(CommandRecord(4.9, "/cmd_vel", 0.0, 0.0, 0.0))
    truth.drive = [(c.t, c.vx, c.vy, c.wz, "skill") for c in truth.commands]
    return truth


def test_a_travelled_distance_is_measured_once_the_base_has_settled(
    mr1_capabilities: dict[str, Capability],
) -> None:
    truth = _braking_truth()
    final = truth.samples[-1].x
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": final, "outLinearVelocity": 0.0}),
            truth,
            "completed",
        )
    )
    output = verdicts["output:outDistance"]
    assert output.passed is True
    assert output.measured["measured"] == pytest.approx(final)
    # Execute returned at 5.0 s while the base still braked: both are in the verdict's data.
    assert output.measured["at_return"] == pytest.approx(truth.at(5.0).x)
    assert output.measured["at_return"] < final - 0.03
    assert output.measured["settled_at"] == pytest.approx(5.3, abs=0.03)
    assert "at rest from t=5.3" in output.message
    assert verdicts["truth:distanceCovered"].passed is True


def test_a_distance_far_from_where_the_base_came_to_rest_fails(
    mr1_capabilities: dict[str, Capability],
) -> None:
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.2, "outLinearVelocity": 0.0}),
            _braking_truth(),
            "completed",
        )
    )
    assert verdicts["output:outDistance"].passed is False
    assert verdicts["truth:distanceCovered"].passed is True


@pytest.mark.parametrize(("settles", "passed"), [(True, True), (False, False)])
def test_an_asserted_stop_passes_with_a_velocity_read_while_the_base_braked(
    mr1_capabilities: dict[str, Capability], settles: bool, passed: bool
) -> None:
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5, "outLinearVelocity": 0.25}),
            _braking_truth(settles=settles),
            "completed",
        )
    )["assured:outLinearVelocity"]
    assert verdict.passed is passed
    if passed:
        assert "while it braked" in verdict.message
        assert verdict.measured["settled"] == pytest.approx(0.0, abs=0.01)


@pytest.mark.parametrize(("settles", "passed"), [(True, True), (False, False)])
def test_an_asserted_output_the_skill_lacks_is_judged_by_the_promise(
    mr1_capabilities: dict[str, Capability], settles: bool, passed: bool
) -> None:
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-forward"],
            MOVE,
            _run({"outDistance": 1.5}),
            _braking_truth(settles=settles),
            "completed",
        )
    )["assured:outLinearVelocity"]
    assert verdict.passed is passed
    assert "reports no outLinearVelocity" in verdict.message


POSITION = Scenario(
    name="s", ground_truth={"outPositionX": "position_x", "outPositionY": "position_y"}
)


def _parked(start: tuple[float, float, float], localised: bool) -> GroundTruth:
    """The base stands 0.5 m ahead of where it started, facing the way it started."""
    truth = GroundTruth(start=start, localised=localised)
    x0, y0, yaw = start
    x, y = x0 + 0.5 * math.cos(yaw), y0 + 0.5 * math.sin(yaw)
    for k in range(301):
        truth.add(Sample(k * 0.02, x, y, yaw, 0.0, 0.0, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    return truth


@pytest.mark.parametrize(
    ("localised", "reported", "passed"),
    [
        (False, (0.5, 0.0), True),  # odometry: where the robot is from where it started
        (False, (2.0, 1.5), False),
        (True, (2.0, 1.5), True),  # localised: the map frame
        (True, (0.5, 0.0), False),
    ],
)
def test_a_position_is_judged_in_the_frame_the_robot_can_know(
    mr1_capabilities: dict[str, Capability],
    localised: bool,
    reported: tuple[float, float],
    passed: bool,
) -> None:
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["get-position"],
            POSITION,
            _run({"outPositionX": reported[0], "outPositionY": reported[1], "outHeading": 0.0}),
            _parked((2.0, 1.0, math.pi / 2), localised),
            "completed",
        )
    )
    for name in ("outPositionX", "outPositionY"):
        assert verdicts[f"output:{name}"].passed is passed
        assert verdicts[f"output:{name}"].measured["frame"] == ("map" if localised else "odom")
    if not localised:
        assert "odometry frame" in verdicts["output:outPositionX"].message


def test_a_heading_without_localisation_is_the_odometry_frames(
    mr1_capabilities: dict[str, Capability],
) -> None:
    scenario = Scenario(name="s", ground_truth={"outHeading": "heading"})
    truth = _parked((0.0, 0.0, 1.0), localised=False)
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["get-position"],
            scenario,
            _run({"outPositionX": 0.5, "outPositionY": 0.0, "outHeading": 0.0}),
            truth,
            "completed",
        )
    )
    assert verdicts["output:outHeading"].passed is True


@pytest.mark.parametrize(("sigma", "passed"), [(0.01, False), (0.03, True)])
def test_a_range_is_judged_to_at_least_three_sigmas_of_the_scan_noise(
    mr1_capabilities: dict[str, Capability], sigma: float, passed: bool
) -> None:
    truth = _flat_wall_and_post(False)
    truth.noise = {"scan": sigma}
    verdicts = _by_oracle(
        judge(
            mr1_capabilities["get-distance-to-nearest-object"],
            NEAREST,
            # 0.08 m long, at a bearing whose range is 0.064 m farther than the nearest
            _run({"outDistance": 1.08, "outAngle": math.radians(-70.0)}),
            truth,
            "completed",
        )
    )
    distance, bearing = verdicts["output:outDistance"], verdicts["output:outAngle"]
    assert distance.tolerance == pytest.approx(max(0.03, 3 * sigma))
    assert distance.passed is passed
    assert bearing.passed is passed


MAP = Scenario(name="s", ground_truth={"outMap": "map_file"})


@pytest.mark.parametrize(
    ("savers", "reported", "passed", "words"),
    [
        ([], "occupancy grid 60x60 at 0.05 m", True, "has no map-saving service"),
        ([], "", False, "reported no map"),
        (["/slam_toolbox/save_map"], "map", False, "no map was saved"),
    ],
)
def test_a_saved_map_is_asked_for_only_where_the_robot_has_a_map_saver(
    mr1_capabilities: dict[str, Capability],
    savers: list[str],
    reported: str,
    passed: bool,
    words: str,
) -> None:
    truth = _truth(1.0)
    truth.map_savers = savers
    verdict = _by_oracle(
        judge(mr1_capabilities["mapping"], MAP, _run({"outMap": reported}), truth, "completed")
    )["output:outMap"]
    assert verdict.passed is passed
    assert words in verdict.message


def test_a_failed_run_says_why_the_world_aborted_its_goals(
    mr1_capabilities: dict[str, Capability],
) -> None:
    truth = _truth(0.0)
    truth.goals = [
        {
            "action": "/move_action",
            "accepted": 1.0,
            "outcome": "aborted",
            "finished": 1.0,
            "reason": "unknown planning group 'manipulator'; the robot's groups are 'mr1_arm'",
        }
    ]
    verdict = _by_oracle(
        judge(
            mr1_capabilities["move-to-point"],
            Scenario(name="s"),
            _run({}, ended="aborted"),
            truth,
            "completed",
        )
    )["outcome"]
    assert verdict.passed is False
    assert "the robot's groups are 'mr1_arm'" in verdict.message
