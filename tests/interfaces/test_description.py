"""The rules engine describes interfaces from their type, name and package."""

from __future__ import annotations

import pytest

from skillwright.interfaces.description import MODULES, describe_by_rules


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
            "controller manager list controllers",
        ),
        (
            "service",
            "/spawn_entity",
            "gazebo_msgs/srv/SpawnEntity",
            "simulation",
            "Simulator service (spawn entity)",
        ),
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
