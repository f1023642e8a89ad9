"""Stand-in of ``pyskillup.decorator_check.decorator_check``."""

from __future__ import annotations

import rclpy


class StateMachine:
    """The skill's PackML state machine, as ``self.state_machine``: a state asks for the
    Stop or Abort transition from inside it (``self.state_machine.stop()`` when execute
    sees it must halt). The transition follows once the state that asked returns: stopping
    -> resetting for Stop, aborting -> clearing -> resetting for Abort."""

    def __init__(self) -> None:
        self._requested: str | None = None

    def stop(self) -> None:
        """The Stop command: stopping, then resetting."""
        self._requested = self._requested or "stop"

    def abort(self) -> None:
        """The Abort command: aborting, clearing, then resetting (it overrides a Stop)."""
        self._requested = "abort"


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
        self.state_machine = StateMachine()
