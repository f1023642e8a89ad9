"""What standard interface types do: direct, auxiliary or unknown, and what they carry."""

from __future__ import annotations

import pytest

from skillwright.interfaces.inventory import Endpoints, Interface, InterfaceKind, Traffic
from skillwright.retrieval.semantics import (
    body_of,
    body_of_text,
    directness,
    merges,
    split_view,
    unreached,
)


def interface(name: str, type_name: str, kind: InterfaceKind = "topic") -> Interface:
    return Interface(name=name, kind=kind, type_name=type_name)


@pytest.mark.parametrize(
    ("kind", "type_name"),
    [
        ("topic", "geometry_msgs/msg/Twist"),
        ("topic", "geometry_msgs/msg/TwistStamped"),
        ("topic", "nav_msgs/msg/Odometry"),
        ("topic", "sensor_msgs/msg/LaserScan"),
        ("topic", "nav_msgs/msg/OccupancyGrid"),
        ("topic", "tf2_msgs/msg/TFMessage"),
        ("action", "nav2_msgs/action/NavigateToPose"),
        ("action", "moveit_msgs/action/MoveGroup"),
        ("action", "control_msgs/action/FollowJointTrajectory"),
    ],
)
def test_the_plain_interfaces_a_skill_uses_are_direct(kind: InterfaceKind, type_name: str) -> None:
    assert directness(interface("/x", type_name, kind)) == "direct"


@pytest.mark.parametrize(
    ("kind", "type_name"),
    [
        ("action", "nav2_msgs/action/BackUp"),
        ("action", "nav2_msgs/action/Spin"),
        ("action", "nav2_msgs/action/DriveOnHeading"),
        ("action", "nav2_msgs/action/AssistedTeleop"),
        ("topic", "nav2_msgs/msg/SpeedLimit"),
        ("service", "moveit_msgs/srv/GetPositionFK"),
        ("topic", "control_msgs/msg/JointTrajectoryControllerState"),
        ("service", "controller_manager_msgs/srv/ListControllers"),
        ("topic", "visualization_msgs/msg/MarkerArray"),
    ],
)
def test_composite_behaviours_and_side_channels_are_auxiliary(
    kind: InterfaceKind, type_name: str
) -> None:
    assert directness(interface("/x", type_name, kind)) == "auxiliary"


def test_a_costmap_is_auxiliary_while_the_map_of_the_same_type_is_direct() -> None:
    grid = "nav_msgs/msg/OccupancyGrid"
    assert directness(interface("/map", grid)) == "direct"
    assert directness(interface("/local_costmap/costmap", grid)) == "auxiliary"


@pytest.mark.parametrize(
    "name",
    [
        "/global_costmap/voxel_marked_cloud",
        "/slam_toolbox/scan_visualization",
        "/lidar/debug/points",
        "/planner_debug",
        "/cost_cloud",
        "/a200_0000/cost_cloud",
        "/scan_matched_points2",
    ],
)
def test_a_costmaps_layers_and_what_is_republished_for_display_are_auxiliary(name: str) -> None:
    assert directness(interface(name, "sensor_msgs/msg/PointCloud2")) == "auxiliary"


@pytest.mark.parametrize("name", ["/scan", "/front_laser/scan", "/debugger_scan"])
def test_a_scan_not_named_for_display_stays_direct(name: str) -> None:
    assert directness(interface(name, "sensor_msgs/msg/LaserScan")) == "direct"
    assert directness(interface(f"{name}_matched_points", "sensor_msgs/msg/PointCloud2")) == (
        "direct"
    )


@pytest.mark.parametrize(
    ("name", "type_name"),
    [
        ("/cmd_vel_nav", "geometry_msgs/msg/Twist"),
        ("/robot1/cmd_vel_teleop", "geometry_msgs/msg/TwistStamped"),
        ("/goal_pose", "geometry_msgs/msg/PoseStamped"),
    ],
)
def test_nav2s_own_velocities_and_rvizs_goal_topic_are_auxiliary(name: str, type_name: str) -> None:
    assert directness(interface(name, type_name)) == "auxiliary"


def test_a_base_controllers_echo_of_the_command_it_applied_is_auxiliary() -> None:
    echo = interface("/mobile_base_controller/cmd_vel_out", "geometry_msgs/msg/TwistStamped")
    assert directness(echo) == "auxiliary"
    # twist_mux's output of the same name is what a base reads: it stays direct
    assert directness(interface("/twist_mux/cmd_vel_out", "geometry_msgs/msg/Twist")) == "direct"


def test_the_velocity_the_base_takes_stays_direct() -> None:
    for name in ("/cmd_vel", "/mobile_base_controller/cmd_vel_unstamped", "/nav_vel"):
        assert directness(interface(name, "geometry_msgs/msg/Twist")) == "direct"
    assert directness(interface("/goal_pose", "nav_msgs/msg/Odometry")) == "direct"


def test_the_map_service_ranks_behind_the_map_topic_it_copies() -> None:
    assert directness(interface("/map", "nav_msgs/msg/OccupancyGrid")) == "direct"
    service = interface("/slam_toolbox/dynamic_map", "nav_msgs/srv/GetMap", "service")
    assert directness(service) == "neutral"


def test_a_vendor_type_is_neutral() -> None:
    assert directness(interface("/api/sport/request", "unitree_api/msg/Request")) == "neutral"


def test_types_tell_the_base_from_the_arm() -> None:
    assert body_of(interface("/cmd_vel", "geometry_msgs/msg/Twist")) == "base"
    assert body_of(interface("/navigate_to_pose", "nav2_msgs/action/NavigateToPose")) == "base"
    assert body_of(interface("/move_action", "moveit_msgs/action/MoveGroup")) == "arm"
    assert body_of(interface("/tf", "tf2_msgs/msg/TFMessage")) is None


def test_a_capability_about_a_mobile_robots_manipulator_is_about_the_arm() -> None:
    assert body_of_text("Move the manipulator of the mobile robot to a goal point.") == "arm"
    assert body_of_text("Navigate the mobile robot to a goal point.") == "base"
    assert body_of_text("Print the current time.") is None


_TWIST, _SCAN, _NAV = (
    ("topic", "geometry_msgs/msg/Twist", "command"),
    ("topic", "sensor_msgs/msg/LaserScan", "measure"),
    ("action", "nav2_msgs/action/NavigateToPose", "command"),
)


@pytest.mark.parametrize(
    ("what", "endpoints", "traffic", "expected"),
    [
        (_TWIST, Endpoints(publishers=1, subscribers=0), 0, True),
        (_TWIST, Endpoints(publishers=0, subscribers=1), 0, False),
        (_SCAN, Endpoints(publishers=0, subscribers=2), 0, True),
        (_SCAN, Endpoints(publishers=0, subscribers=2), 40, False),
        (_SCAN, None, 0, False),
        (_NAV, Endpoints(servers=0, clients=1), 0, True),
        (_NAV, Endpoints(servers=1, clients=0), 0, False),
        (("service", "std_srvs/srv/Trigger", None), Endpoints(servers=0, clients=0), 0, False),
    ],
    ids=[
        "command nobody reads",
        "command read",
        "sensor nobody publishes",
        "sensor recorded",
        "counts unknown",
        "action without a server",
        "action served",
        "service",
    ],
)
def test_an_interface_is_unreached_only_when_the_graph_shows_nobody_at_the_other_end(
    what: tuple[InterfaceKind, str, str | None],
    endpoints: Endpoints | None,
    traffic: int,
    expected: bool,
) -> None:
    kind, type_name, role = what
    found = Interface(
        name="/x",
        kind=kind,
        type_name=type_name,
        endpoints=endpoints,
        traffic=Traffic(message_count=traffic) if traffic else None,
    )
    assert unreached(found, role) is expected


@pytest.mark.parametrize(
    ("name", "type_name", "expected"),
    [
        ("/scan_concatenated", "sensor_msgs/msg/LaserScan", True),
        ("/scan_merged", "sensor_msgs/msg/LaserScan", True),
        ("/mur620a/scan_merged_raw", "sensor_msgs/msg/LaserScan", True),
        ("/merged/points", "sensor_msgs/msg/PointCloud2", True),
        ("/scan", "sensor_msgs/msg/LaserScan", False),
        ("/emerged_scan", "sensor_msgs/msg/LaserScan", False),
        ("/map_merged", "nav_msgs/msg/OccupancyGrid", False),
    ],
)
def test_which_streams_say_they_merge_others(name: str, type_name: str, expected: bool) -> None:
    assert merges(Interface(name=name, kind="topic", type_name=type_name)) is expected


_CLOUD = "sensor_msgs/msg/PointCloud2"
_VELOCITY = "geometry_msgs/msg/Twist"


def scan(name: str, type_name: str = "sensor_msgs/msg/LaserScan") -> Interface:
    return interface(name, type_name)


@pytest.mark.parametrize(
    ("a", "b", "expected"),
    [
        # two scanners on opposite corners, or named by their side
        ("/scan", "/scan2", True),
        ("/scan", "/scan_2", True),
        ("/robot/front_laser/scan", "/robot/rear_laser/scan", True),
        ("/mur620a/f_scan", "/mur620a/b_scan", True),
        ("/lidar_1/scan", "/lidar_2/scan", True),
        # a plain name beside a side's is the whole view, not a part
        ("/mur620a/scan", "/mur620a/f_scan", False),
        # another version of one view, or another sensor
        ("/scan", "/scan_raw", False),
        ("/scan", "/scan_filtered", False),
        ("/scan", "/slam_toolbox/scan_visualization", False),
        ("/utlidar/cloud", "/utlidar/cloud_deskewed", False),
        # a stream that merges the parts is none of them
        ("/scan_2", "/scan_concatenated", False),
        ("/scan", "/scan", False),
    ],
)
def test_which_sensor_streams_are_parts_of_one_split_view(a: str, b: str, expected: bool) -> None:
    assert split_view(scan(a), scan(b)) is expected
    assert split_view(scan(b), scan(a)) is expected


def test_only_sensor_streams_of_one_type_split_a_view() -> None:
    assert split_view(scan("/points", _CLOUD), scan("/points2", _CLOUD))
    assert not split_view(scan("/scan"), scan("/scan2", _CLOUD))
    # two velocity commands are alternatives, whatever their names
    assert not split_view(scan("/front/cmd_vel", _VELOCITY), scan("/rear/cmd_vel", _VELOCITY))
