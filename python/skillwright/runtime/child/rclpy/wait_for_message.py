"""Stand-in of ``rclpy.wait_for_message``."""

from __future__ import annotations

from _skillwright_child.core import core

from rclpy.node import Node
from rclpy.qos import QoSProfile

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any


def wait_for_message(
    msg_type: type,
    node: Node,
    topic: str,
    *,
    qos_profile: QoSProfile | int = 1,
    time_to_wait: float = -1,
) -> tuple[bool, Any]:
    received: list[Any] = []
    subscription = node.create_subscription(msg_type, topic, received.append, qos_profile)
    c = core()
    until = None if time_to_wait < 0 else c.now + time_to_wait
    try:
        c.block(until, lambda: bool(received), f"wait_for_message {topic}")
    finally:
        node.destroy_subscription(subscription)
    return (True, received[0]) if received else (False, None)
