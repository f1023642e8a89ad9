"""Skill for the capability moveForward of mr1.

Inputs: move-forward.ttl, move-forward.spec.yaml.

Skeleton written by skillwright: structure, annotations and interface handles.
States that raise NotImplementedError still need their behaviour.
"""

import rclpy
from rclpy.action import ActionClient

from pyskillup.decorators.decorators import *  # noqa: F403
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from moveit_msgs.action import MoveGroup
from nav2_msgs.action import BackUp
from nav_msgs.msg import Odometry


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/move_forward",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward",
    description="Drive the MR-1 base straight ahead over a requested distance at a requested speed, measured with wheel odometry, and stop it at the end.",
)
class MoveForwardSkill(ROS2Skill):
    """Drive the MR-1 base straight ahead over a requested distance at a requested speed,
    measured with wheel odometry, and stop it at the end.
    """

    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s

    def __init__(self) -> None:
        super().__init__("move_forward")
        self.in_distance: float = 0.0
        self.in_linear_velocity: float = 0.0
        self.out_distance: float = 0.0
        self.out_linear_velocity: float = 0.0
        self.odom_subscription = None
        self.odom_msg: Odometry | None = None
        self.cmd_vel_publisher = None
        self.move_action_client = None
        self.backup_client = None

    @skill_parameter(
        is_required=True,
        name="inDistance",
        description="A length or distance, in metres. Unit: m.",
    )
    def get_in_distance(self) -> float:
        return self.in_distance

    @skill_parameter(
        is_required=True,
        name="inLinearVelocity",
        description="Translational speed of the MR-1 base along one of its own axes (x forward, y to the left), in metres per second; negative values drive backwards or to the right. Unit: m/s.",
    )
    def get_in_linear_velocity(self) -> float:
        return self.in_linear_velocity

    @skill_output(
        is_required=True,
        name="outDistance",
        description="A length or distance, in metres. Unit: m. Expression goal: Assurance.",
    )
    def get_out_distance(self) -> float:
        return self.out_distance

    @skill_output(
        is_required=True,
        name="outLinearVelocity",
        description="Translational speed of the MR-1 base along one of its own axes (x forward, y to the left), in metres per second; negative values drive backwards or to the right. Unit: m/s. Expression goal: Assurance.",
    )
    def get_out_linear_velocity(self) -> float:
        return self.out_linear_velocity

    def _on_odom(self, msg: Odometry) -> None:
        """Keeps the latest message of /odom (nav_msgs/msg/Odometry)."""
        self.odom_msg = msg

    @starting
    def starting(self) -> None:
        """Check that the requested distance is not negative (abort otherwise), subscribe to
        wheel odometry and wait for the first message for at most 2 s.
        """
        self.odom_subscription = self.node.create_subscription(
            Odometry, "/odom", self._on_odom, 10
        )
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.move_action_client = ActionClient(self.node, MoveGroup, "/move_action")
        self.backup_client = ActionClient(self.node, BackUp, "/backup")
        raise NotImplementedError("starting: behaviour from the specification still to be written")

    @execute
    def execute(self) -> None:
        """Remember the odometry position at the start. Use the magnitude of the requested
        speed, clipped to the base's limit of 0.8 m/s, and log a warning if it was clipped.
        Publish a forward velocity command at 20 Hz (no sideways motion, no rotation) and
        compute the straight-line distance travelled from the start position on every
        odometry update. Slow down to 0.1 m/s for the last 0.1 m, and as soon as the
        travelled distance reaches the requested one, publish a zero command. Wait until the
        odometry speed is below 0.01 m/s, then store the travelled distance and the final
        speed as outputs.
        """
        raise NotImplementedError("execute: behaviour from the specification still to be written")

    @completing
    def completing(self) -> None:
        """Log the requested and travelled distance and the difference between them."""
        raise NotImplementedError("completing: behaviour from the specification still to be written")

    @stopping
    def stopping(self) -> None:
        """Stop publishing the forward command and publish a zero velocity command to halt the
        base at once.
        """
        raise NotImplementedError("stopping: behaviour from the specification still to be written")

    @resetting
    def resetting(self) -> None:
        """Publish a zero velocity command, drop the odometry subscription and clear the stored
        start position and outputs.
        """
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
        if self.cmd_vel_publisher is not None:
            self.node.destroy_publisher(self.cmd_vel_publisher)
            self.cmd_vel_publisher = None
        if self.move_action_client is not None:
            self.move_action_client.destroy()
            self.move_action_client = None
        if self.backup_client is not None:
            self.backup_client.destroy()
            self.backup_client = None
        raise NotImplementedError("resetting: behaviour from the specification still to be written")
