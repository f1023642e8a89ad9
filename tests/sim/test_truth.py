"""Ground truth queries by virtual time."""

from __future__ import annotations

import math

import pytest

from skillwright.sim.truth import CommandRecord, GroundTruth, Sample, Sweep, wrap_two_pi


def _sample(t: float, x: float, y: float = 0.0) -> Sample:
    return Sample(t, x, y, 0.0, 0.0, 0.0, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


@pytest.mark.parametrize(
    ("angle", "wrapped"),
    [(0.0, 0.0), (3 * math.pi / 2, 3 * math.pi / 2), (-0.5, 2 * math.pi - 0.5)],
)
def test_angles_wrap_into_a_full_turn(angle: float, wrapped: float) -> None:
    assert wrap_two_pi(angle) == pytest.approx(wrapped)


def test_samples_are_found_by_time_and_distances_measured_between_times() -> None:
    truth = GroundTruth()
    for k in range(11):
        truth.add(_sample(0.1 * k, 0.1 * k, 0.05 * k if k > 5 else 0.0))
    assert truth.at(0.25).t == pytest.approx(0.2)
    assert truth.at(-1.0).t == 0.0
    assert truth.displacement(0.0, 0.5) == pytest.approx(0.5)
    assert truth.path_length(0.0, 1.0) > truth.displacement(0.0, 1.0)


def test_command_duration_runs_from_the_first_motion_to_the_zero_command() -> None:
    truth = GroundTruth()
    truth.commands = [
        CommandRecord(0.5, "/cmd_vel", 0.0, 0.0, 0.0),
        CommandRecord(1.0, "/cmd_vel", 0.3, 0.0, 0.0),
        CommandRecord(1.05, "/cmd_vel", 0.3, 0.0, 0.0),
        CommandRecord(4.0, "/cmd_vel", 0.0, 0.0, 0.0),
    ]
    assert truth.command_duration(0.0, 10.0) == pytest.approx(3.0)
    assert truth.command_duration(0.0, 2.0) == pytest.approx(1.0)


def test_a_goal_is_active_from_acceptance_until_it_finishes() -> None:
    truth = GroundTruth()
    truth.goals = [
        {"action": "/navigate_to_pose", "accepted": 1.0, "outcome": "executing"},
        {"action": "/navigate_to_pose", "accepted": 1.0, "outcome": "succeeded", "finished": 5.0},
        {"action": "/spin", "accepted": 6.0, "outcome": "executing"},
    ]
    assert truth.goals_active_at(0.5) == []
    assert truth.goals_active_at(3.0) == ["/navigate_to_pose"]
    assert truth.goals_active_at(5.5) == []
    assert truth.goals_active_at(7.0) == ["/spin"]


def test_a_sweep_gives_the_range_of_the_beam_nearest_a_bearing() -> None:
    # A whole turn of 4 beams from -pi: the one at 3*pi/4 rounds up to the first beam.
    turn = Sweep(0.0, -math.pi, math.pi / 2, [1.0, 2.0, 3.0, 4.0])
    assert turn.toward(-math.pi / 2) == 2.0
    assert turn.toward(0.1) == 3.0
    assert turn.toward(3 * math.pi / 4 + 0.01) == 1.0
    # A 90-degree fan looks nowhere behind.
    fan = Sweep(0.0, -math.pi / 4, math.pi / 4, [1.0, 2.0, 3.0])
    assert fan.toward(math.pi / 4) == 3.0
    assert fan.toward(math.pi) is None


def test_the_range_toward_a_bearing_is_read_from_the_last_scan_by_then() -> None:
    truth = GroundTruth()
    assert truth.range_toward(1.0, 0.0) is None
    truth.sweeps = [
        Sweep(0.0, -math.pi, math.pi, [1.0, 5.0]),
        Sweep(1.0, -math.pi, math.pi, [2.0, 6.0]),
    ]
    assert truth.range_toward(0.5, 0.0) == 5.0
    assert truth.range_toward(1.0, 0.0) == 6.0


def test_the_base_settles_when_it_stays_slow_for_a_while() -> None:
    truth = GroundTruth()
    speeds = [0.4] * 10 + [0.2, 0.005, 0.3, 0.1] + [0.001] * 20
    for k, speed in enumerate(speeds):
        truth.add(Sample(0.02 * k, 0.0, 0.0, 0.0, speed, 0.0, 0.0, (0, 0, 0), (0, 0, 0)))
    # A moment slower than the threshold (0.005 at 0.22 s) is not rest: it sped up again.
    assert truth.settled(0.0, 1.0, 0.01, 0.02) == pytest.approx(0.28)
    assert truth.settled(0.0, 0.25, 0.01, 0.02) is None
    assert truth.settled(0.0, 0.2, 0.01, 0.02) is None


def test_the_stop_the_skill_commanded_follows_a_motion() -> None:
    truth = GroundTruth()
    truth.commands = [
        CommandRecord(0.1, "/cmd_vel", 0.0, 0.0, 0.0),
        CommandRecord(1.0, "/cmd_vel", 0.3, 0.0, 0.0),
        CommandRecord(3.0, "/cmd_vel", 0.0, 0.0, 0.0),
        CommandRecord(3.1, "/cmd_vel", 0.0, 0.0, 0.0),
    ]
    assert truth.stop_commanded(0.0, 5.0) == pytest.approx(3.0)
    assert truth.stop_commanded(0.0, 2.0) is None


def test_a_pose_in_the_odometry_frame_is_from_where_the_robot_started() -> None:
    truth = GroundTruth(start=(2.0, 1.0, math.pi / 2))
    sample = Sample(0.0, 2.0, 1.5, math.pi / 2 + 0.25, 0.0, 0.0, 0.0, (0, 0, 0), (0, 0, 0))
    x, y, yaw = truth.in_odometry_frame(sample)
    assert (x, y, yaw) == pytest.approx((0.5, 0.0, 0.25))


def test_the_range_toward_a_bearing_comes_from_the_last_scan_that_looks_that_way() -> None:
    # Two corner scanners, each a half turn: the front one, then the rear one.
    truth = GroundTruth()
    truth.sweeps = [
        Sweep(0.0, -math.pi / 2, math.pi / 4, [1.0, 1.5, 2.0, 2.5]),
        Sweep(0.05, math.pi / 2, math.pi / 4, [3.0, 3.5, 4.0, 4.5]),
    ]
    assert truth.range_toward(0.1, 0.0) == 2.0
    assert truth.range_toward(0.1, math.pi) == 4.0
    assert truth.range_toward(0.01, math.pi) is None
