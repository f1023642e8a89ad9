"""The only module that talks to ROS 2: rclpy's answers for :mod:`.live`.

It is kept thin on purpose: rclpy cannot be installed with pip, so everything that can
be tested without it lives in :mod:`~skillwright.interfaces.sources.live`, and this
module only forwards questions. rclpy and rosidl_runtime_py are imported inside
:func:`open_graph`, never at import time, so skillwright works (and ``--help`` stays
fast) on machines without ROS 2.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from skillwright.errors import Ros2UnavailableError

__all__ = ["NODE_NAME", "RclpyGraph", "open_graph"]

NODE_NAME = "skillwright_discover"
"""Name of the short-lived introspection node."""


def _not_sourced(error: ImportError) -> Ros2UnavailableError:
    python = f"{sys.version_info.major}.{sys.version_info.minor}"
    distro = os.environ.get("ROS_DISTRO")
    if distro:
        return Ros2UnavailableError(
            f"ROS 2 {distro} is sourced, but rclpy cannot be imported into this Python "
            f"({python}): {error}. Run skillwright with the Python your ROS 2 was built for, "
            "or discover from a recording or report instead"
        )
    return Ros2UnavailableError(
        f"ROS 2 is not sourced: rclpy cannot be imported ({error}). Run "
        "`source /opt/ros/<distro>/setup.bash` (e.g. jazzy or humble) in this shell and try "
        "again, or discover from a recording (.mcap, rosbag2 folder) or a report instead"
    )


@dataclass
class RclpyGraph:
    """:class:`~skillwright.interfaces.sources.live.GraphAnswers` from an rclpy node."""

    node: Any

    @property
    def location(self) -> str:
        """``ROS 2 graph (ROS_DOMAIN_ID 0, rmw_...)``."""
        domain = os.environ.get("ROS_DOMAIN_ID", "0")
        rmw = os.environ.get("RMW_IMPLEMENTATION", "default middleware")
        return f"ROS 2 graph (ROS_DOMAIN_ID {domain}, {rmw})"

    @property
    def distro(self) -> str | None:
        """``ROS_DISTRO`` of the sourced installation."""
        return os.environ.get("ROS_DISTRO") or None

    def topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """rclpy's list, hidden topics included."""
        return [(n, list(t)) for n, t in self.node.get_topic_names_and_types()]

    def service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """rclpy's list, hidden services included."""
        return [(n, list(t)) for n, t in self.node.get_service_names_and_types()]

    def action_names_and_types(self) -> list[tuple[str, list[str]]]:
        """The node's own call where rclpy has it (newer), else rclpy.action's."""
        method = getattr(self.node, "get_action_names_and_types", None)
        if method is not None:
            return [(n, list(t)) for n, t in method()]
        from rclpy.action import (  # type: ignore[import-not-found,unused-ignore]
            get_action_names_and_types,
        )

        return [(n, list(t)) for n, t in get_action_names_and_types(self.node)]

    def count_publishers(self, topic: str) -> int:
        """Publishers on ``topic``."""
        return int(self.node.count_publishers(topic))

    def count_subscribers(self, topic: str) -> int:
        """Subscribers of ``topic``."""
        return int(self.node.count_subscribers(topic))

    def interface_text(self, type_name: str) -> str | None:
        """The installed interface file (what ``ros2 interface show`` reads)."""
        from rosidl_runtime_py import (  # type: ignore[import-not-found,unused-ignore]
            get_interface_path,
        )

        try:
            return Path(get_interface_path(type_name)).read_text(encoding="utf-8")
        except (LookupError, ValueError, OSError):
            return None


@contextmanager
def open_graph(node_name: str = NODE_NAME) -> Iterator[RclpyGraph]:
    """A node in its own rclpy context for the duration of the block, then shut down.

    The node offers no parameter services and no ``/rosout`` publisher, so it does not
    show up among the interfaces it lists.
    """
    try:
        import rclpy  # type: ignore[import-not-found,unused-ignore]
    except ImportError as error:
        raise _not_sourced(error) from None
    context = rclpy.Context()
    try:
        rclpy.init(context=context)
        node = rclpy.create_node(
            node_name, context=context, start_parameter_services=False, enable_rosout=False
        )
    except Exception as error:  # rclpy raises its own (RCLError, ...) types
        context.try_shutdown()
        raise Ros2UnavailableError(f"ROS 2 could not start node {node_name!r}: {error}") from error
    try:
        yield RclpyGraph(node)
    finally:
        node.destroy_node()
        context.try_shutdown()
