"""What retrieval knows about each interface: its role, text and terms."""

from __future__ import annotations

from skillwright.interfaces.inventory import Interface
from skillwright.retrieval.documents import describe, interface_role, interface_terms


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
