"""Skill for the capability navigateToPoint of mr1.

Inputs: navigate-to-point.ttl, navigate-to-point.spec.yaml.

Skeleton written by skillwright: structure, annotations and interface handles.
States that raise NotImplementedError still need their behaviour.
"""

import rclpy
from rclpy.action import ActionClient

from pyskillup.decorators.decorators import *  # noqa: F403
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import PoseStamped
from moveit_msgs.action import MoveGroup
from nav2_msgs.action import ComputePathToPose, NavigateToPose


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/navigate_to_point",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/navigateToPoint/navigateToPoint",
    description="Drive the MR-1 base to a goal position in the map frame, with Nav2 planning and following a collision-free path.",
)
class NavigateToPointSkill(ROS2Skill):
    """Drive the MR-1 base to a goal position in the map frame, with Nav2 planning and
    following a collision-free path.
    """

    ANGULAR_VELOCITY_MAX = 1.2  # resource requirement: angularVelocity <= 1.2 rad/s
    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s

    def __init__(self) -> None:
        super().__init__("navigate_to_point")
        self.in_position_x: float = 0.0
        self.in_position_y: float = 0.0
        self.out_position_x: float = 0.0
        self.out_position_y: float = 0.0
        self.navigate_to_pose_client = None
        self.compute_path_to_pose_client = None
        self.goal_pose_publisher = None
        self.move_action_client = None

    @skill_parameter(
        is_required=True,
        name="inPositionX",
        description="One coordinate of the origin of base_link expressed in the map frame that SLAM maintains, in metres. Unit: m.",
    )
    def get_in_position_x(self) -> float:
        return self.in_position_x

    @skill_parameter(
        is_required=True,
        name="inPositionY",
        description="One coordinate of the origin of base_link expressed in the map frame that SLAM maintains, in metres. Unit: m.",
    )
    def get_in_position_y(self) -> float:
        return self.in_position_y

    @skill_output(
        is_required=True,
        name="outPositionX",
        description="One coordinate of the origin of base_link expressed in the map frame that SLAM maintains, in metres. Unit: m. Expression goal: Assurance.",
    )
    def get_out_position_x(self) -> float:
        return self.out_position_x

    @skill_output(
        is_required=True,
        name="outPositionY",
        description="One coordinate of the origin of base_link expressed in the map frame that SLAM maintains, in metres. Unit: m. Expression goal: Assurance.",
    )
    def get_out_position_y(self) -> float:
        return self.out_position_y

    @starting
    def starting(self) -> None:
        """Create an action client for Nav2's navigate-to-pose action and wait at most 5 s for
        the server; abort if it is not available.
        """
        self.navigate_to_pose_client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        self.compute_path_to_pose_client = ActionClient(self.node, ComputePathToPose, "/compute_path_to_pose")
        self.goal_pose_publisher = self.node.create_publisher(PoseStamped, "/goal_pose", 10)
        self.move_action_client = ActionClient(self.node, MoveGroup, "/move_action")
        raise NotImplementedError("starting: behaviour from the specification still to be written")

    @execute
    def execute(self) -> None:
        """Read the current pose of base_link in the map frame. Build a goal pose in the map
        frame at the requested x and y, with the orientation facing from the current
        position towards the goal (keep the current heading if the goal is closer than 0.05
        m). Send the goal and abort if Nav2 rejects it. While it runs, log the remaining
        distance from the feedback about once per second. When the result arrives, abort if
        Nav2 reports a failure or cancellation; otherwise read the final pose of base_link
        in the map frame and store its x and y as outputs.
        """
        raise NotImplementedError("execute: behaviour from the specification still to be written")

    @completing
    def completing(self) -> None:
        """Log the reached position and its distance to the requested goal."""
        raise NotImplementedError("completing: behaviour from the specification still to be written")

    @stopping
    def stopping(self) -> None:
        """Cancel the active navigation goal, wait at most 2 s for the cancellation to be
        confirmed, and publish a zero velocity command to the base.
        """
        raise NotImplementedError("stopping: behaviour from the specification still to be written")

    @resetting
    def resetting(self) -> None:
        """Drop the goal handle and clear the stored outputs."""
        if self.navigate_to_pose_client is not None:
            self.navigate_to_pose_client.destroy()
            self.navigate_to_pose_client = None
        if self.compute_path_to_pose_client is not None:
            self.compute_path_to_pose_client.destroy()
            self.compute_path_to_pose_client = None
        if self.goal_pose_publisher is not None:
            self.node.destroy_publisher(self.goal_pose_publisher)
            self.goal_pose_publisher = None
        if self.move_action_client is not None:
            self.move_action_client.destroy()
            self.move_action_client = None
        raise NotImplementedError("resetting: behaviour from the specification still to be written")
