"""Stand-in of ``tf2_ros.static_transform_broadcaster``."""

from __future__ import annotations

from _skillwright_child.core import core
from rclpy.qos import DurabilityPolicy, QoSProfile

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any


class StaticTransformBroadcaster:
    """Publishes transforms on ``/tf_static`` (latched)."""

    def __init__(self, node: Any, qos: Any = None) -> None:
        self._message = core().catalog.get("tf2_msgs/msg/TFMessage")
        profile = qos or QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.pub_tf = node.create_publisher(self._message, "/tf_static", profile)
        self._sent: dict[str, Any] = {}

    def sendTransform(self, transform: Any) -> None:
        for item in list(transform) if isinstance(transform, (list, tuple)) else [transform]:
            self._sent[item.child_frame_id] = item
        self.pub_tf.publish(self._message(transforms=list(self._sent.values())))
