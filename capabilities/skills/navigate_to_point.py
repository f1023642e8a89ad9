"""navigate_to_point: drive the MR-1 to a map position through Nav2's NavigateToPose."""

import math
import time

import rclpy
from rclpy.action import ActionClient
from rclpy.duration import Duration
from rclpy.time import Time
from tf2_ros import Buffer, TransformException, TransformListener

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from nav2_msgs.action import NavigateToPose


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/navigate_to_point",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/navigateToPoint/navigateToPoint",
    description="Drive the MR-1 base to a goal position in the map frame, with Nav2 planning and following a collision-free path.",
)
class NavigateToPointSkill(ROS2Skill):
    """Send a NavigateToPose goal and wait for Nav2 to reach it."""

    MAP_FRAME = "map"
    BASE_FRAME = "base_link"

    def __init__(self) -> None:
        super().__init__("navigate_to_point")
        self.in_position_x: float = 0.0
        self.in_position_y: float = 0.0
        self.out_position_x: float = 0.0
        self.out_position_y: float = 0.0
        self.navigate_to_pose_client = None
        self.cmd_vel_publisher = None
        self.tf_buffer = None
        self.tf_listener = None
        self.goal_handle = None
        self.last_feedback_log = 0.0

    @skill_parameter(
        is_required=True, name="inPositionX", description="Goal x in the map frame. Unit: m."
    )
    def get_in_position_x(self) -> float:
        return self.in_position_x

    @skill_parameter(
        is_required=True, name="inPositionY", description="Goal y in the map frame. Unit: m."
    )
    def get_in_position_y(self) -> float:
        return self.in_position_y

    @skill_output(
        is_required=True, name="outPositionX", description="Reached x in the map frame. Unit: m."
    )
    def get_out_position_x(self) -> float:
        return self.out_position_x

    @skill_output(
        is_required=True, name="outPositionY", description="Reached y in the map frame. Unit: m."
    )
    def get_out_position_y(self) -> float:
        return self.out_position_y

    def _robot_pose(self) -> tuple[float, float, float]:
        try:
            transform = self.tf_buffer.lookup_transform(
                self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=1.0)
            )
        except TransformException as error:
            raise RuntimeError(
                f"cannot read the robot's pose in {self.MAP_FRAME}: {error}"
            ) from error
        t = transform.transform.translation
        q = transform.transform.rotation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        return t.x, t.y, yaw

    def _on_feedback(self, feedback_msg) -> None:
        now = time.monotonic()
        if now - self.last_feedback_log >= 1.0:
            self.last_feedback_log = now
            remaining = feedback_msg.feedback.distance_remaining
            self.node.get_logger().info(f"{remaining:.2f} m to go")

    @staticmethod
    def _wait(future, timeout: float | None = None):
        deadline = None if timeout is None else time.monotonic() + timeout
        while not future.done():
            if deadline is not None and time.monotonic() > deadline:
                return None
            time.sleep(0.02)
        return future.result()

    @starting
    def starting(self) -> None:
        """Create an action client for Nav2's navigate-to-pose action and wait at most 5 s for
        the server; abort if it is not available.
        """
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self.node)
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.navigate_to_pose_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        if not self.navigate_to_pose_client.wait_for_server(timeout_sec=5.0):
            raise RuntimeError("Nav2's /navigate_to_pose action server is not available")

    @execute
    def execute(self) -> None:
        """Send a goal at the requested x, y facing from the current position towards it; log
        progress; abort on rejection or failure; store the reached position.
        """
        x, y, yaw = self._robot_pose()
        dx = self.in_position_x - x
        dy = self.in_position_y - y
        heading = math.atan2(dy, dx) if math.hypot(dx, dy) >= 0.05 else yaw

        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = self.MAP_FRAME
        goal.pose.header.stamp = self.node.get_clock().now().to_msg()
        goal.pose.pose.position.x = self.in_position_x
        goal.pose.pose.position.y = self.in_position_y
        goal.pose.pose.orientation.z = math.sin(heading / 2.0)
        goal.pose.pose.orientation.w = math.cos(heading / 2.0)

        self.goal_handle = self._wait(
            self.navigate_to_pose_client.send_goal_async(goal, feedback_callback=self._on_feedback)
        )
        if self.goal_handle is None or not self.goal_handle.accepted:
            raise RuntimeError("Nav2 rejected the navigation goal")
        result = self._wait(self.goal_handle.get_result_async())
        if result.status != GoalStatus.STATUS_SUCCEEDED:
            raise RuntimeError(f"navigation ended with status {result.status}")
        self.out_position_x, self.out_position_y, _ = self._robot_pose()

    @completing
    def completing(self) -> None:
        """Log the reached position and its distance to the requested goal."""
        error = math.hypot(
            self.out_position_x - self.in_position_x, self.out_position_y - self.in_position_y
        )
        self.node.get_logger().info(
            f"reached ({self.out_position_x:.2f}, {self.out_position_y:.2f}), {error:.3f} m from the goal"
        )

    @stopping
    def stopping(self) -> None:
        """Cancel the active navigation goal, wait at most 2 s for the cancellation to be
        confirmed, and publish a zero velocity command to the base.
        """
        if self.goal_handle is not None:
            self._wait(self.goal_handle.cancel_goal_async(), timeout=2.0)
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @resetting
    def resetting(self) -> None:
        """Drop the goal handle and clear the stored outputs."""
        self.goal_handle = None
        self.out_position_x = 0.0
        self.out_position_y = 0.0
