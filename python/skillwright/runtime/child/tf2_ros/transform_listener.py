"""Stand-in of ``tf2_ros.transform_listener``."""

from __future__ import annotations

from _skillwright_child.core import core
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile

from tf2_ros.buffer import Buffer

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any


class TransformListener:
    """Subscribes ``/tf`` and ``/tf_static`` on ``node`` and fills ``buffer``."""

    def __init__(
        self,
        buffer: Buffer,
        node: Any,
        *,
        spin_thread: bool = False,
        qos: QoSProfile | int | None = None,
        static_qos: QoSProfile | int | None = None,
    ) -> None:
        if not isinstance(buffer, Buffer):
            raise TypeError("buffer must be a tf2_ros.Buffer")
        message = core().catalog.get("tf2_msgs/msg/TFMessage")
        self.buffer = buffer
        self.node = node
        self.tf_sub = node.create_subscription(
            message, "/tf", self.callback, qos if qos is not None else QoSProfile(depth=100)
        )
        self.tf_static_sub = node.create_subscription(
            message,
            "/tf_static",
            self.static_callback,
            static_qos
            if static_qos is not None
            else QoSProfile(
                depth=100,
                durability=DurabilityPolicy.TRANSIENT_LOCAL,
                history=HistoryPolicy.KEEP_LAST,
            ),
        )
        self.tf_sub._quiet_callback = self._stores_only
        self.tf_static_sub._quiet_callback = self._stores_only

    def _stores_only(self) -> bool:
        """Its callbacks only store transforms, unless the skill changed them or the buffer."""
        listener, buffer = type(self), type(self.buffer)
        return (
            listener.callback is TransformListener.callback
            and listener.static_callback is TransformListener.static_callback
            and buffer.set_transform is Buffer.set_transform
            and buffer.set_transform_static is Buffer.set_transform_static
        )

    def callback(self, data: Any) -> None:
        for transform in data.transforms:
            self.buffer.set_transform(transform, "default_authority")

    def static_callback(self, data: Any) -> None:
        for transform in data.transforms:
            self.buffer.set_transform_static(transform, "default_authority")

    def unregister(self) -> None:
        self.node.destroy_subscription(self.tf_sub)
        self.node.destroy_subscription(self.tf_static_sub)

    def __del__(self) -> None:
        return None
