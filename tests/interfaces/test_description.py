"""The rules engine describes interfaces from their type, name and package."""

from __future__ import annotations

import pytest

from skillwright.interfaces.description import MODULES, control_role, describe_by_rules


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "module", "phrase"),
    [
        (
            "topic",
            "/cmd_vel",
            "geometry_msgs/msg/Twist",
            "base motion",
            "Commands the base's linear and angular velocity",
        ),
        (
            "topic",
            "/odom",
            "nav_msgs/msg/Odometry",
            "localisation",
            "pose and velocity from odometry",
        ),
        ("topic", "/scan", "sensor_msgs/msg/LaserScan", "perception", "2-D range measurements"),
        ("topic", "/local_costmap/costmap", "nav_msgs/msg/OccupancyGrid", "navigation", "costmap"),
        ("topic", "/map", "nav_msgs/msg/OccupancyGrid", "mapping", "occupancy grid map"),
        (
            "topic",
            "/initialpose",
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            "localisation",
            "initial pose",
        ),
        (
            "topic",
            "/pose",
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            "localisation",
            "estimated pose in the map",
        ),
        (
            "action",
            "/navigate_to_pose",
            "nav2_msgs/action/NavigateToPose",
            "navigation",
            "Drives the robot to a goal pose",
        ),
        ("action", "/move_action", "moveit_msgs/action/MoveGroup", "manipulation", "MoveIt"),
        (
            "service",
            "/controller_manager/list_controllers",
            "controller_manager_msgs/srv/ListControllers",
            "controller management",
            "Lists the ros2_control controllers with their type, state",
        ),
        (
            "service",
            "/controller_manager/unload_controller",
            "controller_manager_msgs/srv/UnloadController",
            "controller management",
            "Unloads a controller",
        ),
        (
            "service",
            "/spawn_entity",
            "gazebo_msgs/srv/SpawnEntity",
            "simulation",
            "Adds a model (URDF or SDF) to the simulated world",
        ),
        ("service", "/gazebo/set_light", "gazebo_msgs/srv/SetLight", "simulation", "set light"),
        (
            "service",
            "/pause_physics",
            "std_srvs/srv/Empty",
            "simulation",
            "Pauses the simulator's physics",
        ),
        ("service", "/dock", "std_srvs/srv/Empty", "other", "Triggers dock"),
        ("topic", "/tf_static", "tf2_msgs/msg/TFMessage", "localisation", "Fixed transforms"),
        (
            "topic",
            "/tf",
            "tf2_msgs/msg/TFMessage",
            "localisation",
            "Transforms between the robot's coordinate frames",
        ),
        (
            "topic",
            "/performance_metrics",
            "gazebo_msgs/msg/PerformanceMetrics",
            "simulation",
            "real-time factor",
        ),
        ("topic", "/map_metadata", "nav_msgs/msg/MapMetaData", "mapping", "resolution and origin"),
        (
            "topic",
            "/local_costmap/published_footprint",
            "geometry_msgs/msg/PolygonStamped",
            "navigation",
            "footprint",
        ),
        ("topic", "/bond", "bond/msg/Status", "system", "Heartbeats"),
    ],
)
def test_known_types_get_specific_descriptions(
    kind: str, name: str, type_name: str, module: str, phrase: str
) -> None:
    description = describe_by_rules(kind, name, type_name)
    assert description.module == module
    assert phrase in description.purpose
    assert description.engine == "rules"


def test_twist_that_is_not_a_command_is_not_called_one() -> None:
    description = describe_by_rules("topic", "/wheel/velocity", "geometry_msgs/msg/Twist")
    assert "Commands" not in description.purpose


def test_unknown_types_are_described_plainly_without_invention() -> None:
    description = describe_by_rules("topic", "/foo/bar_baz", "acme_msgs/msg/Widget", ["a", "b"])
    assert description.purpose == "Topic /foo/bar_baz (Widget): foo bar baz."
    assert description.module == "other"
    assert description.tasks == []
    assert description.key_fields == ["a", "b"]


def test_text_joins_every_part_in_a_fixed_order() -> None:
    text = describe_by_rules("topic", "/scan", "sensor_msgs/msg/LaserScan", ["ranges"]).text()
    assert text.index("Module: perception.") < text.index("Tasks:") < text.index("Used by:")
    assert text.endswith("Key fields: ranges.")


def test_every_rule_names_a_known_module() -> None:
    from skillwright.interfaces import description

    assert {r.module for r in description._RULES} <= set(MODULES)


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "expected"),
    [
        (
            "topic",
            "/joint_trajectory_controller/joint_trajectory",
            "trajectory_msgs/msg/JointTrajectory",
            "to the controller joint_trajectory_controller, without feedback",
        ),
        (
            "topic",
            "/joint_trajectory",
            "trajectory_msgs/msg/JointTrajectory",
            "to its controller, without feedback",
        ),
        (
            "action",
            "/arm_controller/follow_joint_trajectory",
            "control_msgs/action/FollowJointTrajectory",
            "Makes the controller arm_controller follow a joint trajectory",
        ),
        (
            "service",
            "/robot/teleop/set_parameters",
            "rcl_interfaces/srv/SetParameters",
            "Sets parameters of node robot/teleop, each on its own.",
        ),
        (
            "topic",
            "/bt_navigator/transition_event",
            "lifecycle_msgs/msg/TransitionEvent",
            "Lifecycle state changes of node bt_navigator",
        ),
    ],
)
def test_the_node_is_named_only_as_the_interface_name_spells_it(
    kind: str, name: str, type_name: str, expected: str
) -> None:
    assert expected in describe_by_rules(kind, name, type_name).purpose


def test_headers_and_time_halves_are_not_key_fields_and_top_level_fields_come_first() -> None:
    paths = [
        "header",
        "header.stamp",
        "header.frame_id",
        "child_frame_id",
        "pose",
        "pose.pose",
        "poses.header",
        "time_allowance",
        "time_allowance.sec",
        "time_allowance.nanosec",
        "twist",
    ]
    description = describe_by_rules("topic", "/odom", "nav_msgs/msg/Odometry", paths)
    assert description.key_fields == [
        "child_frame_id",
        "pose",
        "time_allowance",
        "twist",
        "pose.pose",
    ]


def test_key_fields_are_capped_at_eight() -> None:
    paths = [f"f{i}" for i in range(20)]
    assert len(describe_by_rules("topic", "/x", "acme/msg/X", paths).key_fields) == 8


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "role"),
    [
        ("topic", "/cmd_vel", "geometry_msgs/msg/Twist", "command"),
        ("topic", "/wheel/velocity", "geometry_msgs/msg/Twist", "sense"),
        ("action", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose", "plan"),
        ("topic", "/rosout", "rcl_interfaces/msg/Log", None),
        ("topic", "/foo", "acme_msgs/msg/Widget", None),
    ],
)
def test_control_role_comes_from_the_matching_rule(
    kind: str, name: str, type_name: str, role: str | None
) -> None:
    assert control_role(kind, name, type_name) == role
