"""move_to_point: move the arm's tool centre point to a position with MoveIt."""

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
from geometry_msgs.msg import Pose
from moveit_msgs.action import MoveGroup
from moveit_msgs.msg import Constraints, MoveItErrorCodes, PositionConstraint
from shape_msgs.msg import SolidPrimitive


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/move_to_point",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/moveToPoint/moveToPoint",
    description="Move the tool centre point of the MR-1's six-axis arm to a requested x, y, z position in arm_base_link, along a path planned by MoveIt.",
)
class MoveToPointSkill(ROS2Skill):
    """Send a MoveGroup goal with a position constraint on tool0 and report where it got."""

    ARM_REACH_MAX = 0.85  # resource requirement: armReach <= 0.85 m
    GROUP = "mr1_arm"  # planning group of the MR-1's capability model
    BASE_FRAME = "arm_base_link"
    TOOL_LINK = "tool0"

    def __init__(self) -> None:
        super().__init__("move_to_point")
        self.in_position_x: float = 0.0
        self.in_position_y: float = 0.0
        self.in_position_z: float = 0.0
        self.out_position_x: float = 0.0
        self.out_position_y: float = 0.0
        self.out_position_z: float = 0.0
        self.move_action_client = None
        self.goal_handle = None
        self.tf_buffer = None
        self.tf_listener = None

    @skill_parameter(is_required=True, name="inPositionX", description="Target x in arm_base_link. Unit: m.")
    def get_in_position_x(self) -> float:
        return self.in_position_x

    @skill_parameter(is_required=True, name="inPositionY", description="Target y in arm_base_link. Unit: m.")
    def get_in_position_y(self) -> float:
        return self.in_position_y

    @skill_parameter(is_required=True, name="inPositionZ", description="Target z in arm_base_link. Unit: m.")
    def get_in_position_z(self) -> float:
        return self.in_position_z

    @skill_output(is_required=True, name="outPositionX", description="Reached x. Unit: m.")
    def get_out_position_x(self) -> float:
        return self.out_position_x

    @skill_output(is_required=True, name="outPositionY", description="Reached y. Unit: m.")
    def get_out_position_y(self) -> float:
        return self.out_position_y

    @skill_output(is_required=True, name="outPositionZ", description="Reached z. Unit: m.")
    def get_out_position_z(self) -> float:
        return self.out_position_z

    @staticmethod
    def _wait(future, timeout: float):
        deadline = time.monotonic() + timeout
        while not future.done() and time.monotonic() < deadline:
            time.sleep(0.02)
        return future.result() if future.done() else None

    @starting
    def starting(self) -> None:
        """Connect to MoveIt's move-group action (at most 5 s) and check the arm's reach."""
        reach = math.sqrt(self.in_position_x**2 + self.in_position_y**2 + self.in_position_z**2)
        if reach > self.ARM_REACH_MAX:
            raise ValueError(f"the target is {reach:.3f} m away, beyond the arm's {self.ARM_REACH_MAX} m reach")
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self.node)
        self.move_action_client = ActionClient(self.node, MoveGroup, "/move_action")
        if not self.move_action_client.wait_for_server(timeout_sec=5.0):
            raise RuntimeError("MoveIt's /move_action server is not available")

    @execute
    def execute(self) -> None:
        """Plan and execute a motion of tool0 to the point (1 cm tolerance, any orientation),
        then read where tool0 is from tf."""
        region = SolidPrimitive()
        region.type = SolidPrimitive.SPHERE
        region.dimensions = [0.01]
        target = Pose()
        target.position.x = self.in_position_x
        target.position.y = self.in_position_y
        target.position.z = self.in_position_z
        target.orientation.w = 1.0
        constraint = PositionConstraint()
        constraint.header.frame_id = self.BASE_FRAME
        constraint.link_name = self.TOOL_LINK
        constraint.constraint_region.primitives = [region]
        constraint.constraint_region.primitive_poses = [target]
        constraint.weight = 1.0
        goal = MoveGroup.Goal()
        goal.request.group_name = self.GROUP
        goal.request.goal_constraints = [Constraints(position_constraints=[constraint])]
        goal.request.allowed_planning_time = 5.0
        goal.request.num_planning_attempts = 1
        goal.request.max_velocity_scaling_factor = 0.3
        goal.request.max_acceleration_scaling_factor = 0.3
        goal.planning_options.plan_only = False
        self.goal_handle = self._wait(self.move_action_client.send_goal_async(goal), 5.0)
        if self.goal_handle is None or not self.goal_handle.accepted:
            raise RuntimeError("MoveIt rejected the motion request")
        result = self._wait(self.goal_handle.get_result_async(), 60.0)
        if result is None:
            raise RuntimeError("MoveIt did not finish the motion within 60 s")
        if result.status != GoalStatus.STATUS_SUCCEEDED or result.result.error_code.val != MoveItErrorCodes.SUCCESS:
            raise RuntimeError(f"MoveIt failed: status {result.status}, error code {result.result.error_code.val}")
        try:
            transform = self.tf_buffer.lookup_transform(
                self.BASE_FRAME, self.TOOL_LINK, Time(), timeout=Duration(seconds=2.0)
            )
        except TransformException as error:
            raise RuntimeError(f"cannot read where {self.TOOL_LINK} is: {error}") from error
        translation = transform.transform.translation
        self.out_position_x = translation.x
        self.out_position_y = translation.y
        self.out_position_z = translation.z

    @completing
    def completing(self) -> None:
        """Log the reached position and its distance to the requested point."""
        error = math.dist(
            (self.out_position_x, self.out_position_y, self.out_position_z),
            (self.in_position_x, self.in_position_y, self.in_position_z),
        )
        self.node.get_logger().info(
            f"tool0 at ({self.out_position_x:.3f}, {self.out_position_y:.3f}, "
            f"{self.out_position_z:.3f}), {error * 1000:.1f} mm from the target"
        )

    @stopping
    def stopping(self) -> None:
        """Cancel the active move-group goal so the arm halts where it is."""
        if self.goal_handle is not None and self.goal_handle.accepted:
            self._wait(self.goal_handle.cancel_goal_async(), 2.0)

    @resetting
    def resetting(self) -> None:
        """Drop the goal handle and clear the outputs."""
        self.goal_handle = None
        self.out_position_x = 0.0
        self.out_position_y = 0.0
        self.out_position_z = 0.0
