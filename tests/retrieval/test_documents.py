"""What retrieval knows about each interface: its role, text and terms."""

from __future__ import annotations

from skillwright.interfaces.inventory import Interface
from skillwright.retrieval.documents import interface_role


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
