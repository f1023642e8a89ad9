"""Stand-in of ``tf2_ros.transform_broadcaster``."""

from __future__ import annotations

from _skillwright_child.core import core

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any


class TransformBroadcaster:
    """Publishes transforms on ``/tf``."""

    def __init__(self, node: Any, qos: Any = 100) -> None:
        self._message = core().catalog.get("tf2_msgs/msg/TFMessage")
        self.pub_tf = node.create_publisher(self._message, "/tf", qos)

    def sendTransform(self, transform: Any) -> None:
        transforms = list(transform) if isinstance(transform, (list, tuple)) else [transform]
        self.pub_tf.publish(self._message(transforms=transforms))
