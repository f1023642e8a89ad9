"""Stand-in of ``pyskillup.decorator_check.decorator_check``."""

from __future__ import annotations

import rclpy


class ROS2Skill:
    """Base class of ROS 2 skills: owns ``self.node``.

    pySkillUp spins the node in a background thread; here the child's executor runs the
    node's callbacks whenever a state waits (sleep, spin, a future, a transform), which
    is when a background executor would get to run them too.
    """

    def __init__(self, node_name: str, *args: object, **kwargs: object) -> None:
        if not rclpy.ok():
            rclpy.init()
        self.node = rclpy.create_node(node_name)
