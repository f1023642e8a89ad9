"""Stand-in of ``rclpy.action``."""

from rclpy.action.client import ActionClient, ClientGoalHandle

__all__ = ["ActionClient", "ClientGoalHandle"]
