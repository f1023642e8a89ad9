"""What retrieval knows about each interface: its role, text and terms."""

from __future__ import annotations

import pytest

from skillwright.interfaces.inventory import Description, Interface
from skillwright.retrieval.documents import (
    WRITTEN_WEIGHT,
    describe,
    interface_role,
    interface_terms,
)


def test_a_twist_topic_is_a_command_whatever_its_name() -> None:
    for name in ("/cmd_vel", "/key_vel", "/nav_vel"):
        twist = Interface(name=name, kind="topic", type_name="geometry_msgs/msg/Twist")
        assert interface_role(twist) == "command"
    odometry = Interface(name="/odom", kind="topic", type_name="nav_msgs/msg/Odometry")
    assert interface_role(odometry) == "measure"


def test_the_request_topic_of_a_topic_api_is_a_command_and_its_response_a_measure() -> None:
    def role(name: str) -> str | None:
        return interface_role(Interface(name=name, kind="topic", type_name="vendor/msg/Msg"))

    assert role("/api/motion/request") == "command"
    assert role("/arm_request") == "command"
    assert role("/api/motion/response") == "measure"
    assert role("/requested_speed") == "measure"


def test_a_point_clouds_points_are_cloud_not_the_point_a_capability_moves_to() -> None:
    def terms(name: str, type_name: str) -> dict[str, float]:
        interface = Interface(name=name, kind="topic", type_name=type_name)
        return interface_terms(interface, describe(interface))

    for name, type_name in (
        ("/depth_cam/depth/points", "sensor_msgs/msg/PointCloud2"),
        ("/velodyne_points", "sensor_msgs/msg/PointCloud"),
        ("/camera/PointsFiltered", "sensor_msgs/msg/PointCloud2"),
        ("/velodyne_points_encoded", "point_cloud_interfaces/msg/CompressedPointCloud2"),
    ):
        cloud = terms(name, type_name)
        assert "point" not in cloud
        assert "position" not in cloud
        assert cloud["cloud"] > 0
    goal = terms("/clicked_point", "geometry_msgs/msg/PointStamped")
    assert goal["point"] > 0  # elsewhere a point is still a point


def test_a_written_description_is_not_weighed_unless_asked_and_never_replaces_the_rules() -> None:
    backup = Interface(name="/backup", kind="action", type_name="nav2_msgs/action/BackUp")
    rules = interface_terms(backup, describe(backup))
    written = Description(
        purpose="Moves the mobile robot backwards over a given distance at a given speed.",
        module="navigation",
        tasks=["recovery"],
        engine="report",
    )
    assert WRITTEN_WEIGHT == 0.0
    assert interface_terms(backup, written) == rules
    beside = interface_terms(backup, written, written_weight=0.5)
    for term, weight in rules.items():
        assert beside[term] >= weight  # nothing of the rules' description is lost
    assert "recovery" in beside
    assert "recovery" not in rules
    alone = interface_terms(backup, written, written_weight=1.0, rules_weight=0.0)
    assert beside["recovery"] == pytest.approx(0.5 * alone["recovery"])


def test_a_description_the_rules_engine_stored_counts_once() -> None:
    odometry = Interface(name="/odom", kind="topic", type_name="nav_msgs/msg/Odometry")
    stored = describe(odometry)
    assert stored.engine == "rules"
    described = odometry.model_copy(update={"description": stored})
    assert interface_terms(described, describe(described)) == interface_terms(odometry, stored)
