"""Stand-in of ``rclpy.topic_endpoint_info``: what ``get_publishers_info_by_topic`` and
``get_subscriptions_info_by_topic`` give, one entry per endpoint of a topic."""

from __future__ import annotations

from enum import IntEnum

TYPE_CHECKING = False
if TYPE_CHECKING:
    from rclpy.qos import QoSProfile


class TopicEndpointTypeEnum(IntEnum):
    """The kind of a topic endpoint (rmw's ``rmw_endpoint_type_t``)."""

    INVALID = 0
    PUBLISHER = 1
    SUBSCRIPTION = 2


class TopicEndpointInfo:
    """One publisher or subscription of a topic: its node, type, kind, gid and QoS."""

    def __init__(
        self,
        node_name: str = "",
        node_namespace: str = "",
        topic_type: str = "",
        endpoint_type: TopicEndpointTypeEnum = TopicEndpointTypeEnum.INVALID,
        endpoint_gid: list[int] | None = None,
        qos_profile: QoSProfile | None = None,
    ) -> None:
        self.node_name = node_name
        self.node_namespace = node_namespace
        self.topic_type = topic_type
        self.endpoint_type = TopicEndpointTypeEnum(endpoint_type)
        self.endpoint_gid = list(endpoint_gid or [])
        self.qos_profile = qos_profile

    def __repr__(self) -> str:
        return (
            f"TopicEndpointInfo(node_name={self.node_name!r}, node_namespace="
            f"{self.node_namespace!r}, topic_type={self.topic_type!r}, endpoint_type="
            f"{self.endpoint_type.name})"
        )
