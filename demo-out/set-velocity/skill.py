"""Skill for the capability setVelocity of mr1.

Inputs: set-velocity.ttl, set-velocity.spec.yaml.

Skeleton written by skillwright: structure, annotations and interface handles.
States that raise NotImplementedError still need their behaviour.
"""

import rclpy
from rclpy.action import ActionClient

from pyskillup.decorators.decorators import *  # noqa: F403
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from nav2_msgs.action import Spin
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/set_velocity",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/setVelocity/setVelocity",
    description="Bring the MR-1 base to a requested forward speed and yaw rate, clipped to the base's limits, and keep that velocity commanded until the skill is stopped or reset.",
)
class SetVelocitySkill(ROS2Skill):
    """Bring the MR-1 base to a requested forward speed and yaw rate, clipped to the base's
    limits, and keep that velocity commanded until the skill is stopped or reset.
    """

    ANGULAR_VELOCITY_MAX = 1.2  # resource requirement: angularVelocity <= 1.2 rad/s
    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s

    def __init__(self) -> None:
        super().__init__("set_velocity")
        self.in_angular_velocity: float = 0.0
        self.in_linear_velocity: float = 0.0
        self.out_angular_velocity: float = 0.0
        self.out_linear_velocity: float = 0.0
        self.cmd_vel_publisher = None
        self.odom_subscription = None
        self.odom_msg: Odometry | None = None
        self.spin_client = None
        self.imu_data_subscription = None
        self.imu_data_msg: Imu | None = None

    @skill_parameter(
        is_required=True,
        name="inAngularVelocity",
        description="Yaw rate of the MR-1 base about its vertical axis, in radians per second; positive turns counter-clockwise seen from above. Unit: rad/s.",
    )
    def get_in_angular_velocity(self) -> float:
        return self.in_angular_velocity

    @skill_parameter(
        is_required=True,
        name="inLinearVelocity",
        description="Translational speed of the MR-1 base along one of its own axes (x forward, y to the left), in metres per second; negative values drive backwards or to the right. Unit: m/s.",
    )
    def get_in_linear_velocity(self) -> float:
        return self.in_linear_velocity

    @skill_output(
        is_required=True,
        name="outAngularVelocity",
        description="Yaw rate of the MR-1 base about its vertical axis, in radians per second; positive turns counter-clockwise seen from above. Unit: rad/s. Expression goal: Assurance.",
    )
    def get_out_angular_velocity(self) -> float:
        return self.out_angular_velocity

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

    def _on_imu_data(self, msg: Imu) -> None:
        """Keeps the latest message of /imu/data (sensor_msgs/msg/Imu)."""
        self.imu_data_msg = msg

    @starting
    def starting(self) -> None:
        """Check that wheel odometry is arriving (wait at most 2 s, abort otherwise) and open
        the publisher for the base velocity command.
        """
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.odom_subscription = self.node.create_subscription(
            Odometry, "/odom", self._on_odom, 10
        )
        self.spin_client = ActionClient(self.node, Spin, "/spin")
        self.imu_data_subscription = self.node.create_subscription(
            Imu, "/imu/data", self._on_imu_data, 10
        )
        raise NotImplementedError("starting: behaviour from the specification still to be written")

    @execute
    def execute(self) -> None:
        """Clip the requested forward speed to at most 0.8 m/s and the requested yaw rate to at
        most 1.2 rad/s in magnitude, keeping their signs, and log a warning when a value had
        to be clipped. Start a 20 Hz timer on the node that publishes this command (all
        other velocity components zero) so the velocity is held after execute returns. Wait
        until the odometry twist has stayed within 0.05 m/s and 0.05 rad/s of the command
        for 0.5 s; if that has not happened after 5 s, publish zero and abort. Store the
        measured forward speed and yaw rate as outputs.
        """
        raise NotImplementedError("execute: behaviour from the specification still to be written")

    @completing
    def completing(self) -> None:
        """Log the commanded and the measured velocities; leave the 20 Hz command timer
        running.
        """
        raise NotImplementedError("completing: behaviour from the specification still to be written")

    @stopping
    def stopping(self) -> None:
        """Cancel the command timer and publish a zero velocity command three times, 50 ms
        apart.
        """
        raise NotImplementedError("stopping: behaviour from the specification still to be written")

    @resetting
    def resetting(self) -> None:
        """Make sure the command timer is cancelled and the base is commanded to zero, then
        clear the stored outputs.
        """
        if self.cmd_vel_publisher is not None:
            self.node.destroy_publisher(self.cmd_vel_publisher)
            self.cmd_vel_publisher = None
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
        if self.spin_client is not None:
            self.spin_client.destroy()
            self.spin_client = None
        if self.imu_data_subscription is not None:
            self.node.destroy_subscription(self.imu_data_subscription)
            self.imu_data_subscription = None
        raise NotImplementedError("resetting: behaviour from the specification still to be written")
