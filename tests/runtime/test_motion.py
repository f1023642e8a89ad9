"""Nav2's and MoveIt's motion servers, shared by the kinematic and the MuJoCo world, against a
world that moves the base exactly as commanded."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import pytest

from skillwright.runtime.api import ActionGoal, GoalStatus
from skillwright.runtime.motion import (
    MOVEIT_FRAME_TRANSFORM_FAILURE,
    MOVEIT_INVALID_GOAL_CONSTRAINTS,
    MOVEIT_INVALID_GROUP_NAME,
    MOVEIT_INVALID_LINK_NAME,
    MOVEIT_NO_IK_SOLUTION,
    MOVEIT_PREEMPTED,
    MOVEIT_SUCCESS,
    ArmConfig,
    ArmServer,
    BaseMotionServer,
    Command,
    NavConfig,
    duration,
    fill,
    from_duration,
    wrap_pi,
    yaw_of,
)

NAV = NavConfig(
    speed_max=0.5, yaw_rate_max=1.0, accel=1.5, yaw_accel=3.0, xy_tolerance=0.1, yaw_tolerance=0.1
)
_TIME = {"sec": 0, "nanosec": 0}
_TEMPLATES: dict[str, dict[str, Any]] = {
    "nav2_msgs/action/NavigateToPose_Result": {"error_code": 0, "total_elapsed_time": _TIME},
    "nav2_msgs/action/NavigateToPose_Feedback": {
        "current_pose": {},
        "distance_remaining": 0.0,
        "navigation_time": _TIME,
    },
    "nav2_msgs/action/Spin_Result": {"total_elapsed_time": _TIME},
    "nav2_msgs/action/Spin_Feedback": {"angular_distance_traveled": 0.0},
    "nav2_msgs/action/BackUp_Result": {"total_elapsed_time": _TIME},
    "nav2_msgs/action/BackUp_Feedback": {"distance_traveled": 0.0},
    "moveit_msgs/action/MoveGroup_Result": {"error_code": {"val": 0}, "planning_time": 0.0},
    "moveit_msgs/action/MoveGroup_Feedback": {"state": ""},
}


@dataclass
class _Sink:
    """What the skill's action client would receive."""

    feedback: list[dict[str, Any]] = field(default_factory=list)
    results: list[tuple[int, dict[str, Any] | None]] = field(default_factory=list)

    def goal_accepted(self, goal: ActionGoal, accepted: bool) -> None:
        pass

    def goal_feedback(self, goal: ActionGoal, feedback: dict[str, Any]) -> None:
        self.feedback.append(feedback)

    def goal_finished(self, goal: ActionGoal, status: int, result: dict[str, Any] | None) -> None:
        self.results.append((status, result))


@dataclass
class _World:
    """A base that moves exactly as commanded (``stuck``: not at all), in a world whose
    planner finds a straight path unless the goal lies in ``walls``."""

    now: float = 0.0
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    command: Command = field(default_factory=Command)
    stuck: bool = False
    walls: set[tuple[float, float]] = field(default_factory=set)
    goals: list[dict[str, Any]] = field(default_factory=list)
    commands: list[Command] = field(default_factory=list)

    def base_pose(self) -> tuple[float, float, float]:
        return self.pose

    def drive(self, command: Command) -> None:
        self.command = command
        self.commands.append(command)

    def plan(
        self, start: tuple[float, float], goal: tuple[float, float]
    ) -> list[tuple[float, float]] | None:
        return None if goal in self.walls else [start, goal]

    def to_map(
        self, frame: str, x: float, y: float, yaw: float
    ) -> tuple[float, float, float] | None:
        return (x, y, yaw) if frame == "map" else (x + 1.0, y, yaw) if frame == "odom" else None

    def message(self, type_name: str) -> dict[str, Any]:
        return dict(_TEMPLATES[type_name])

    def pose_stamped(self, x: float, y: float, yaw: float) -> dict[str, Any]:
        return {"header": {"frame_id": "map"}, "pose": {"position": {"x": x, "y": y}}}

    def record_goal(self, entry: dict[str, Any]) -> None:
        self.goals.append(entry)

    def run(self, server: BaseMotionServer | ArmServer, seconds: float) -> None:
        """Tick ``server`` when due and move the base, for ``seconds``."""
        end = self.now + seconds
        while self.now < end and server.next_tick is not None:
            dt = server.next_tick - self.now
            if not self.stuck:
                x, y, yaw = self.pose
                c, s = math.cos(yaw), math.sin(yaw)
                vx, vy, wz = self.command.vx, self.command.vy, self.command.wz
                self.pose = (x + (c * vx - s * vy) * dt, y + (s * vx + c * vy) * dt, yaw + wz * dt)
            self.now = server.next_tick
            server.tick()


def _goal(request: dict[str, Any], action: str = "/navigate_to_pose") -> tuple[ActionGoal, _Sink]:
    sink = _Sink()
    return ActionGoal(action=action, goal_id=1, request=request, _sink=sink), sink


def _pose(x: float, y: float, frame: str = "map", yaw: float = 0.0) -> dict[str, Any]:
    orientation = {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}
    return {
        "header": {"frame_id": frame},
        "pose": {"position": {"x": x, "y": y, "z": 0.0}, "orientation": orientation},
    }


def _navigate(world: _World, request: dict[str, Any]) -> tuple[BaseMotionServer, ActionGoal, _Sink]:
    server = BaseMotionServer(world, NAV)
    goal, sink = _goal(request)
    server.handler("navigate_to_pose", "nav2_msgs/action/NavigateToPose").on_goal(goal)
    return server, goal, sink


def test_navigation_reaches_the_goal_pose_with_feedback_and_succeeds() -> None:
    world = _World()
    server, _, sink = _navigate(world, {"pose": _pose(2.0, 1.0, yaw=math.pi / 2)})

    world.run(server, 20.0)

    [(status, result)] = sink.results
    assert status == GoalStatus.SUCCEEDED
    assert result is not None
    assert result["error_code"] == 0
    assert from_duration(result["total_elapsed_time"]) > 4.0  # 2.2 m at 0.5 m/s at most
    x, y, yaw = world.pose
    assert math.hypot(x - 2.0, y - 1.0) <= NAV.xy_tolerance
    assert abs(wrap_pi(yaw - math.pi / 2)) <= NAV.yaw_tolerance
    remaining = [f["distance_remaining"] for f in sink.feedback]
    assert remaining[0] > 2.0 > remaining[-1]
    assert world.commands[-1] == Command()
    assert [g["outcome"] for g in world.goals] == ["executing", "succeeded"]


def test_a_goal_pose_is_transformed_into_the_global_frame() -> None:
    world = _World()
    server, _, sink = _navigate(world, {"pose": _pose(1.0, 0.0, frame="odom")})
    world.run(server, 20.0)
    assert sink.results[0][0] == GoalStatus.SUCCEEDED
    assert world.pose[0] == pytest.approx(2.0, abs=NAV.xy_tolerance)


@pytest.mark.parametrize(
    ("request_", "walls", "reason"),
    [
        ({"pose": _pose(1.0, 0.0, frame="camera")}, set(), "goal frame 'camera' is unknown"),
        ({"pose": _pose(1.0, 0.0)}, {(1.0, 0.0)}, "no path to (1.00, 0.00)"),
    ],
)
def test_a_goal_that_cannot_be_done_is_accepted_then_aborted_saying_why(
    request_: dict[str, Any], walls: set[tuple[float, float]], reason: str
) -> None:
    world = _World(walls=walls)
    server, goal, sink = _navigate(world, request_)
    assert goal.status == GoalStatus.ABORTED
    [(_, result)] = sink.results
    assert result is not None
    assert result["error_code"] != 0
    assert world.goals[-1]["outcome"] == "aborted"
    assert world.goals[-1]["reason"].startswith(reason)
    assert server.next_tick is None


def test_a_new_goal_pre_empts_the_running_one() -> None:
    world = _World()
    server, first, _ = _navigate(world, {"pose": _pose(3.0, 0.0)})
    world.run(server, 1.0)
    second, second_sink = _goal({"pose": _pose(0.0, 0.0)})
    server.handler("navigate_to_pose", "nav2_msgs/action/NavigateToPose").on_goal(second)

    assert first.status == GoalStatus.ABORTED
    assert world.goals[-2]["reason"] == "pre-empted by a new goal"
    world.run(server, 20.0)
    assert second_sink.results[0][0] == GoalStatus.SUCCEEDED


def test_cancelling_stops_the_base_and_only_the_running_goal_is_cancelled() -> None:
    world = _World()
    server, goal, sink = _navigate(world, {"pose": _pose(3.0, 0.0)})
    world.run(server, 1.0)
    other, _ = _goal({})

    assert server.on_cancel(other) is False
    assert server.on_cancel(goal) is True
    assert sink.results[0][0] == GoalStatus.CANCELED
    assert world.commands[-1] == Command()
    assert server.next_tick is None


def test_a_base_that_does_not_move_is_aborted_by_the_progress_checker() -> None:
    world = _World(stuck=True)
    server, goal, _ = _navigate(world, {"pose": _pose(3.0, 0.0)})
    world.run(server, 12.0)
    assert goal.status == GoalStatus.ABORTED
    assert world.goals[-1]["reason"] == "no progress: moved less than 0.5 m in 10 s"


def test_a_goal_beyond_its_time_allowance_is_aborted() -> None:
    world = _World()
    server = BaseMotionServer(world, NAV)
    goal, _ = _goal({"target_yaw": 3.0, "time_allowance": {"sec": 1, "nanosec": 0}}, "/spin")
    server.handler("spin", "nav2_msgs/action/Spin").on_goal(goal)
    world.run(server, 5.0)
    assert goal.status == GoalStatus.ABORTED
    assert world.goals[-1]["reason"] == "time allowance exceeded"


def test_spin_turns_by_the_target_yaw_and_reports_the_angle_travelled() -> None:
    world = _World()
    server = BaseMotionServer(world, NAV)
    goal, sink = _goal({"target_yaw": -1.5}, "/spin")
    server.handler("spin", "nav2_msgs/action/Spin").on_goal(goal)
    world.run(server, 10.0)
    assert goal.status == GoalStatus.SUCCEEDED
    assert world.pose[2] == pytest.approx(-1.5, abs=0.06)
    assert sink.feedback[-1]["angular_distance_traveled"] == pytest.approx(1.5, abs=0.06)


@pytest.mark.parametrize(
    ("speed", "outcome"), [(0.3, GoalStatus.SUCCEEDED), (0.0, GoalStatus.ABORTED)]
)
def test_backup_drives_backwards_whatever_the_sign_and_needs_a_speed(
    speed: float, outcome: int
) -> None:
    world = _World()
    server = BaseMotionServer(world, NAV)
    goal, _ = _goal({"target": {"x": 0.5}, "speed": speed}, "/backup")
    server.handler("backup", "nav2_msgs/action/BackUp").on_goal(goal)
    world.run(server, 10.0)
    assert goal.status == outcome
    if outcome == GoalStatus.SUCCEEDED:
        assert world.pose[0] == pytest.approx(-0.5, abs=0.02)


# --- the arm ----------------------------------------------------------------------

ARM = ArmConfig(
    group="arm",
    tip_link="tool0",
    base_frame="arm_base_link",
    reach=0.8,
    speed_max=0.5,
    home=(0.3, 0.0, 0.3),
)
_FRAMES = {"arm_base_link": (0.0, 0.0, 0.0), "base_link": (-0.1, 0.0, -0.2)}


def _arm_request(
    point: tuple[float, float, float],
    *,
    group: str = "arm",
    link: str = "tool0",
    frame: str = "arm_base_link",
    scaling: float = 0.0,
    plan_only: bool = False,
) -> dict[str, Any]:
    x, y, z = point
    constraint = {
        "header": {"frame_id": frame},
        "link_name": link,
        "constraint_region": {"primitive_poses": [{"position": {"x": x, "y": y, "z": z}}]},
    }
    return {
        "request": {
            "group_name": group,
            "max_velocity_scaling_factor": scaling,
            "goal_constraints": [{"position_constraints": [constraint]}],
        },
        "planning_options": {"plan_only": plan_only},
    }


def _arm(config: ArmConfig = ARM) -> tuple[_World, ArmServer]:
    world = _World()
    server = ArmServer(world, config, _FRAMES.get)
    server.handler("moveit_msgs/action/MoveGroup")
    return world, server


def _move(server: ArmServer, request: dict[str, Any]) -> tuple[ActionGoal, _Sink]:
    goal, sink = _goal(request, "/move_action")
    server.on_goal(goal)
    return goal, sink


def _code(sink: _Sink) -> int:
    result = sink.results[-1][1]
    assert result is not None
    return int(result["error_code"]["val"])


@pytest.mark.parametrize(
    ("request_", "code"),
    [
        (_arm_request((0.4, 0.0, 0.3), group="manipulator"), MOVEIT_INVALID_GROUP_NAME),
        (_arm_request((0.4, 0.0, 0.3), link="wrist"), MOVEIT_INVALID_LINK_NAME),
        (_arm_request((0.4, 0.0, 0.3), frame="camera"), MOVEIT_FRAME_TRANSFORM_FAILURE),
        (_arm_request((0.9, 0.0, 0.3)), MOVEIT_NO_IK_SOLUTION),
        (
            {"request": {"group_name": "arm", "goal_constraints": []}},
            MOVEIT_INVALID_GOAL_CONSTRAINTS,
        ),
    ],
)
def test_a_request_moveit_cannot_do_is_aborted_with_its_error_code(
    request_: dict[str, Any], code: int
) -> None:
    _, server = _arm()
    goal, sink = _move(server, request_)
    assert goal.status == GoalStatus.ABORTED
    assert _code(sink) == code


def test_the_tool_moves_to_the_target_in_the_arm_frame_at_the_scaled_speed() -> None:
    world, server = _arm()
    goal, sink = _move(server, _arm_request((0.2, 0.0, 0.5), frame="base_link", scaling=0.5))
    assert sink.feedback == [{"state": "MONITOR"}]

    world.run(server, 5.0)

    assert goal.status == GoalStatus.SUCCEEDED
    assert _code(sink) == MOVEIT_SUCCESS
    assert server.tcp == pytest.approx((0.1, 0.0, 0.3))
    assert (server.frame, server.link) == ("base_link", "tool0")
    # 0.2 m at 0.5 x 0.5 m/s
    assert world.now == pytest.approx(0.8, abs=0.05)


def test_an_unset_velocity_scaling_is_moveits_default() -> None:
    world, server = _arm()
    goal, _ = _move(server, _arm_request((0.3, 0.0, 0.4)))
    world.run(server, 1.5)
    assert goal.active  # 0.1 m at 0.1 x 0.5 m/s takes 2 s
    world.run(server, 1.0)
    assert goal.status == GoalStatus.SUCCEEDED


def test_plan_only_succeeds_at_once_without_moving() -> None:
    _, server = _arm()
    goal, sink = _move(server, _arm_request((0.5, 0.0, 0.3), plan_only=True))
    assert goal.status == GoalStatus.SUCCEEDED
    assert _code(sink) == MOVEIT_SUCCESS
    assert server.tcp == ARM.home


def test_a_new_arm_goal_pre_empts_and_a_cancel_stops_the_tool_where_it_is() -> None:
    world, server = _arm()
    first, first_sink = _move(server, _arm_request((0.3, 0.0, 0.6), scaling=1.0))
    world.run(server, 0.2)
    second, _ = _move(server, _arm_request((0.3, 0.2, 0.3), scaling=1.0))
    assert first.status == GoalStatus.ABORTED
    assert _code(first_sink) == MOVEIT_PREEMPTED
    world.run(server, 0.1)
    where = server.tcp
    assert server.on_cancel(first) is False
    assert server.on_cancel(second) is True
    assert second.status == GoalStatus.CANCELED
    world.run(server, 1.0)
    assert server.tcp == where


def test_a_world_without_the_robots_srdf_takes_any_group_link_and_reach() -> None:
    config = ArmConfig(
        group=None,
        tip_link=None,
        base_frame="arm_base_link",
        reach=None,
        speed_max=0.5,
        home=(0.3, 0.0, 0.3),
        default_velocity_scaling=1.0,
    )
    world, server = _arm(config)
    goal, _ = _move(server, _arm_request((1.3, 0.0, 0.3), group="any", link="gripper"))
    world.run(server, 3.0)
    assert goal.status == GoalStatus.SUCCEEDED
    assert server.link == "gripper"


# --- message helpers -----------------------------------------------------------------


def test_fill_keeps_the_fields_a_type_has_and_drops_the_others() -> None:
    template = {"error_code": 0, "total_elapsed_time": {"sec": 0, "nanosec": 0}}
    filled = fill(
        template, {"error_code": 9000, "error_msg": "x", "total_elapsed_time": {"sec": 3}}
    )
    assert filled == {"error_code": 9000, "total_elapsed_time": {"sec": 3, "nanosec": 0}}
    assert template["error_code"] == 0


@pytest.mark.parametrize("seconds", [0.0, 1.5, 12.000000001, 59.999])
def test_durations_round_trip(seconds: float) -> None:
    assert from_duration(duration(seconds)) == pytest.approx(seconds, abs=1e-9)
    assert from_duration("bad") == 0.0


@pytest.mark.parametrize(
    ("orientation", "yaw"),
    [
        ({"x": 0.0, "y": 0.0, "z": math.sin(0.4), "w": math.cos(0.4)}, 0.8),
        ({"x": 0.0, "y": 0.0, "z": 0.0, "w": 0.0}, 0.0),
        (None, 0.0),
    ],
)
def test_the_yaw_of_a_quaternion(orientation: object, yaw: float) -> None:
    assert yaw_of(orientation) == pytest.approx(yaw)


@pytest.mark.parametrize(
    ("angle", "wrapped"),
    [(0.0, 0.0), (3 * math.pi / 2, -math.pi / 2), (-0.5, -0.5), (math.pi, -math.pi)],
)
def test_angles_wrap_into_half_a_turn_either_way(angle: float, wrapped: float) -> None:
    assert wrap_pi(angle) == pytest.approx(wrapped)


def test_the_robots_srdf_groups_are_served_each_with_its_tip_and_others_named() -> None:
    config = dataclasses.replace(ARM, group="mr1_arm", groups={"arm": "tool0", "wrist": "flange"})
    world, server = _arm(config)
    goal, _ = _move(server, _arm_request((0.4, 0.0, 0.3), group="wrist", link="flange"))
    world.run(server, 3.0)
    assert goal.status == GoalStatus.SUCCEEDED
    _, sink = _move(server, _arm_request((0.4, 0.0, 0.3), group="wrist", link="tool0"))
    assert _code(sink) == MOVEIT_INVALID_LINK_NAME
    _, sink = _move(server, _arm_request((0.4, 0.0, 0.3), group="mr1_arm"))
    assert _code(sink) == MOVEIT_INVALID_GROUP_NAME
    reasons = [g["reason"] for g in world.goals if g.get("outcome") == "aborted"]
    assert "the robot's groups are 'arm', 'wrist'" in reasons[-1]
    assert "'flange'" in reasons[0]
