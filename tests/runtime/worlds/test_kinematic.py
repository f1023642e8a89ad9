"""The kinematic world: the base follows its command, Nav2 and MoveIt goals are served."""

from __future__ import annotations

import math
from typing import Any

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.api import GoalStatus
from skillwright.runtime.graph import GraphHost
from skillwright.runtime.worlds.kinematic import KinematicWorld
from tests.runtime.test_graph import deliveries_until, endpoint, make_graph


def _world(inventory: Inventory, **options: Any) -> GraphHost:
    graph, _ = make_graph(inventory)
    graph.attach_world(KinematicWorld(**options))
    return graph


def _last(seen: list[tuple[float, dict[str, Any]]], handle: int) -> dict[str, Any]:
    return [d["data"] for _, d in seen if d["id"] == handle][-1]


def test_the_base_follows_its_command_and_stops_when_commands_stop(
    mr1_inventory: Inventory,
) -> None:
    graph = _world(mr1_inventory, command_timeout=0.5)
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")
    cmd = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")

    for step in range(20):
        graph.child_publish(cmd, {"linear": {"x": 0.5}, "angular": {"z": 0.5}}, 1, "execute")
        deliveries_until(graph, (step + 1) * 0.05)
    moving = _last(deliveries_until(graph, 1.02), odom)
    assert moving["twist"]["twist"]["linear"]["x"] == pytest.approx(0.5)
    assert moving["twist"]["twist"]["angular"]["z"] == pytest.approx(0.5)
    stopped = _last(deliveries_until(graph, 3.0), odom)
    assert stopped["twist"]["twist"]["linear"]["x"] == 0.0
    yaw = 2 * math.atan2(
        stopped["pose"]["pose"]["orientation"]["z"], stopped["pose"]["pose"]["orientation"]["w"]
    )
    assert yaw == pytest.approx(0.5 * 1.0 + 0.5 * 0.5, abs=0.1)


def test_navigation_drives_to_the_goal_and_succeeds(mr1_inventory: Inventory) -> None:
    graph = _world(mr1_inventory, start=(1.0, 0.0, 0.0))
    nav = endpoint(graph, "action_client", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    tf = endpoint(graph, "subscription", "/tf", "tf2_msgs/msg/TFMessage", reliability="reliable")
    goal = {"pose": {"header": {"frame_id": "map"}, "pose": {"position": {"x": 2.0, "y": 1.0}}}}

    graph.child_goal(nav, 1, goal, True, 3)
    seen = deliveries_until(graph, 15.0)

    outcome = [d for _, d in seen if d["id"] == nav and d.get("kind") == "result"]
    assert [r["status"] for r in outcome] == [GoalStatus.SUCCEEDED]
    feedback = [d["data"]["distance_remaining"] for _, d in seen if d.get("kind") == "feedback"]
    assert feedback[0] > feedback[-1]
    base = next(t for t in _last(seen, tf)["transforms"] if t["child_frame_id"] == "base_link")
    position = base["transform"]["translation"]
    assert math.hypot(position["x"] - 2.0, position["y"] - 1.0) <= 0.06


def _outcomes(seen: list[tuple[float, dict[str, Any]]], handle: int) -> dict[int, int]:
    return {
        d["goal"]: d["status"] for _, d in seen if d["id"] == handle and d.get("kind") == "result"
    }


def test_a_goal_in_a_frame_tf_cannot_transform_is_accepted_then_aborted(
    mr1_inventory: Inventory,
) -> None:
    # Nav2's navigators accept every goal and abort one whose pose they cannot transform
    # into the global frame; a goal in odom is transformed (map -> odom is known).
    graph = _world(mr1_inventory)
    nav = endpoint(graph, "action_client", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")

    graph.child_goal(nav, 1, {"pose": {"header": {"frame_id": "camera_link"}}}, False, 3)
    graph.child_goal(nav, 2, {"pose": {"header": {"frame_id": "odom"}}}, False, 4)

    seen = deliveries_until(graph, 1.0)
    assert [d["accepted"] for _, d in seen if d["id"] == nav and "accepted" in d] == [True, True]
    assert _outcomes(seen, nav) == {1: GoalStatus.ABORTED, 2: GoalStatus.SUCCEEDED}


def _without_localisation(inventory: Inventory) -> Inventory:
    """The MR-1 with neither its map nor its map pose: odometry is all it knows."""
    kept = [i for i in inventory.interfaces if i.name not in {"/map", "/pose"}]
    return inventory.model_copy(update={"interfaces": kept})


def _frames(graph: GraphHost, tf: int, until: float) -> set[tuple[str, str]]:
    return {
        (t["header"]["frame_id"], t["child_frame_id"])
        for _, d in deliveries_until(graph, until)
        if d["id"] == tf
        for t in d["data"]["transforms"]
    }


@pytest.mark.parametrize(
    ("localised", "options", "frames"),
    [
        (True, {}, {("map", "odom"), ("odom", "base_link")}),
        (False, {}, {("odom", "base_link")}),
        (False, {"localised": True}, {("map", "odom"), ("odom", "base_link")}),
        (True, {"localised": False}, {("odom", "base_link")}),
    ],
)
def test_the_map_frame_is_there_only_for_a_robot_with_localisation(
    mr1_inventory: Inventory, localised: bool, options: dict[str, Any], frames: set[Any]
) -> None:
    inventory = mr1_inventory if localised else _without_localisation(mr1_inventory)
    graph = _world(inventory, **options)
    tf = endpoint(graph, "subscription", "/tf", "tf2_msgs/msg/TFMessage", reliability="reliable")
    assert _frames(graph, tf, 0.5) == frames


def test_without_localisation_navigation_goals_are_taken_in_odom(
    mr1_inventory: Inventory,
) -> None:
    graph = _world(_without_localisation(mr1_inventory))
    nav = endpoint(graph, "action_client", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")

    graph.child_goal(nav, 1, {"pose": {"header": {"frame_id": "map"}}}, False, 3)
    graph.child_goal(nav, 2, {"pose": {"header": {"frame_id": "odom"}}}, False, 4)

    assert _outcomes(deliveries_until(graph, 1.0), nav) == {
        1: GoalStatus.ABORTED,
        2: GoalStatus.SUCCEEDED,
    }


def test_the_behaviour_servers_spin_is_served_by_turning_the_base(
    mr1_inventory: Inventory,
) -> None:
    graph = _world(mr1_inventory)
    spin = endpoint(graph, "action_client", "/spin", "nav2_msgs/action/Spin")
    odom = endpoint(graph, "subscription", "/odom", "nav_msgs/msg/Odometry", reliability="reliable")

    graph.child_goal(spin, 1, {"target_yaw": 1.0}, True, 3)
    seen = deliveries_until(graph, 6.0)

    assert _outcomes(seen, spin) == {1: GoalStatus.SUCCEEDED}
    turned = [
        d["data"]["angular_distance_traveled"] for _, d in seen if d.get("kind") == "feedback"
    ]
    assert turned == sorted(turned)
    orientation = _last(seen, odom)["pose"]["pose"]["orientation"]
    assert 2 * math.atan2(orientation["z"], orientation["w"]) == pytest.approx(1.0, abs=0.05)


def _arm_goal(x: float, y: float, z: float) -> dict[str, Any]:
    constraint = {
        "header": {"frame_id": "arm_base_link"},
        "link_name": "tool0",
        "constraint_region": {"primitive_poses": [{"position": {"x": x, "y": y, "z": z}}]},
    }
    return {"request": {"goal_constraints": [{"position_constraints": [constraint]}]}}


def test_the_arm_moves_its_link_to_the_target_or_fails_beyond_reach(
    mr1_inventory: Inventory,
) -> None:
    graph = _world(mr1_inventory)
    arm = endpoint(graph, "action_client", "/move_action", "moveit_msgs/action/MoveGroup")
    tf = endpoint(graph, "subscription", "/tf", "tf2_msgs/msg/TFMessage", reliability="reliable")

    graph.child_goal(arm, 1, _arm_goal(0.5, 0.1, 0.4), False, 3)
    graph.child_goal(arm, 2, _arm_goal(1.0, 0.5, 0.5), False, 4)
    seen = deliveries_until(graph, 3.0)

    results = {d["goal"]: d for _, d in seen if d["id"] == arm and d.get("kind") == "result"}
    assert results[1]["status"] == GoalStatus.SUCCEEDED
    assert results[1]["data"]["error_code"]["val"] == 1
    assert results[2]["status"] == GoalStatus.ABORTED
    assert results[2]["data"]["error_code"]["val"] == -31
    tool = next(t for t in _last(seen, tf)["transforms"] if t["child_frame_id"] == "tool0")
    assert tool["header"]["frame_id"] == "arm_base_link"
    assert tool["transform"]["translation"] == pytest.approx({"x": 0.5, "y": 0.1, "z": 0.4})


def _scans(graph: GraphHost, until: float) -> list[dict[str, Any]]:
    scan = endpoint(graph, "subscription", "/scan", "sensor_msgs/msg/LaserScan")
    return [d["data"] for _, d in deliveries_until(graph, until) if d["id"] == scan]


def test_without_a_recorded_scan_the_world_scans_the_walls_of_its_room(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory, replay="off")
    graph.attach_world(KinematicWorld(room=(8.0, 6.0), start=(1.0, 0.0, math.pi / 2)))
    cmd = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")
    [first, *_] = _scans(graph, 0.05)
    assert len(first["ranges"]) == 360
    assert first["angle_min"] == pytest.approx(-math.pi)
    assert first["angle_increment"] == pytest.approx(2 * math.pi / 360)
    # Facing +y from the room's centre: 3 m ahead, 4 m to either side, 3 m behind.
    assert first["ranges"][180] == pytest.approx(3.0)
    assert first["ranges"][90] == pytest.approx(4.0)
    assert first["ranges"][270] == pytest.approx(4.0)
    assert first["ranges"][0] == pytest.approx(3.0)
    assert min(first["ranges"]) == pytest.approx(3.0)
    for step in range(40):  # drive 1 m ahead (0.5 m/s for 2 s)
        graph.child_publish(cmd, {"linear": {"x": 0.5}}, 1, "execute")
        deliveries_until(graph, 0.05 + (step + 1) * 0.05)
    ahead = _scans(graph, 4.0)[-1]["ranges"][180]
    assert 1.7 < ahead < 2.3  # about a metre closer, give or take the acceleration


def test_a_beam_beyond_the_scanners_range_reads_inf(mr1_inventory: Inventory) -> None:
    graph, _ = make_graph(mr1_inventory, replay="off")
    graph.attach_world(KinematicWorld(room=(40.0, 6.0), scan_range=(0.05, 12.0)))
    [first, *_] = _scans(graph, 0.05)
    assert first["ranges"][180] == math.inf  # 20 m to the wall ahead
    assert first["ranges"][270] == pytest.approx(3.0)


def test_a_recorded_or_scripted_scan_is_left_to_the_recording_or_the_script(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory)
    graph.attach_world(KinematicWorld())
    recorded = _scans(graph, 1.0)
    assert recorded
    assert {s["header"]["frame_id"] for s in recorded} == {"laser_link"}  # the MR-1's lidar
    scripted, _ = make_graph(
        mr1_inventory,
        replay="off",
        topics={"/scan": {"rate_hz": 10.0, "message": {"ranges": [0.4, 0.5]}}},
    )
    scripted.attach_world(KinematicWorld())
    assert {tuple(s["ranges"]) for s in _scans(scripted, 1.0)} == {(0.4, 0.5)}


def test_a_wall_nearer_than_the_scanner_can_measure_reads_minus_inf(
    mr1_inventory: Inventory,
) -> None:
    graph, _ = make_graph(mr1_inventory, replay="off")
    graph.attach_world(KinematicWorld(room=(0.06, 6.0), scan_range=(0.05, 12.0)))
    [first, *_] = _scans(graph, 0.05)
    assert first["ranges"][180] == -math.inf  # 3 cm to the wall ahead
    assert first["ranges"][270] == pytest.approx(3.0)


def _poses(graph: GraphHost, until: float) -> list[dict[str, Any]]:
    pose = endpoint(graph, "subscription", "/pose", "geometry_msgs/msg/PoseWithCovarianceStamped")
    return [d["data"] for _, d in deliveries_until(graph, until) if d["id"] == pose]


def test_the_recorded_map_pose_is_taken_over_and_follows_the_base(
    mr1_inventory: Inventory,
) -> None:
    graph = _world(mr1_inventory, start=(1.0, 2.0, 0.0))  # the MR-1's recording has /pose
    cmd = endpoint(graph, "publisher", "/cmd_vel", "geometry_msgs/msg/Twist")
    [first, *_] = _poses(graph, 0.05)
    assert first["header"]["frame_id"] == "map"
    assert first["pose"]["pose"]["position"]["x"] == pytest.approx(1.0)
    assert first["pose"]["pose"]["position"]["y"] == pytest.approx(2.0)
    for step in range(40):  # turn for 2 s at 0.5 rad/s, then 0.5 s until the command times out
        graph.child_publish(cmd, {"angular": {"z": 0.5}}, 1, "execute")
        deliveries_until(graph, 0.05 + (step + 1) * 0.05)
    turned = _poses(graph, 3.0)[-1]["pose"]["pose"]["orientation"]
    assert 2 * math.atan2(turned["z"], turned["w"]) == pytest.approx(1.25, abs=0.1)


def test_a_scripted_map_pose_is_left_to_the_script(mr1_inventory: Inventory) -> None:
    graph, _ = make_graph(
        mr1_inventory,
        topics={
            "/pose": {
                "rate_hz": 10.0,
                "message": {"header": {"frame_id": "scripted"}, "pose": {"pose": {}}},
            }
        },
    )
    graph.attach_world(KinematicWorld())
    assert {p["header"]["frame_id"] for p in _poses(graph, 1.0)} == {"scripted"}


def test_a_robot_with_its_own_names_is_driven_on_them() -> None:
    # A Husarion Panther: the command is /panther/cmd_vel, the odometry
    # /panther/odometry/{wheels,filtered}; a fixed /cmd_vel left it standing.
    from skillwright.runtime.recorder import Recorder
    from skillwright.runtime.scenario import RunScenario
    from skillwright.runtime.typesys import TypeRegistry
    from tests.retrieval.robots import robot_inventory

    inventory = robot_inventory("panther")
    graph = GraphHost(inventory, TypeRegistry(inventory), Recorder(), RunScenario())
    graph.attach_world(KinematicWorld())
    odom = endpoint(graph, "subscription", "/panther/odometry/filtered", "nav_msgs/msg/Odometry")
    cmd = endpoint(graph, "publisher", "/panther/cmd_vel", "geometry_msgs/msg/Twist")
    for step in range(20):
        graph.child_publish(cmd, {"linear": {"x": 0.5}}, 1, "execute")
        deliveries_until(graph, (step + 1) * 0.05)
    moving = _last(deliveries_until(graph, 1.02), odom)
    assert moving["twist"]["twist"]["linear"]["x"] == pytest.approx(0.5)
    assert moving["pose"]["pose"]["position"]["x"] > 0.3
