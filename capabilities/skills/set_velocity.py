"""set_velocity: hold a commanded base velocity, clipped to the MR-1's limits."""

import time

import rclpy

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/set_velocity",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/setVelocity/setVelocity",
    description="Bring the MR-1 base to a requested forward speed and yaw rate, clipped to the base's limits, and keep that velocity commanded until the skill is stopped or reset.",
)
class SetVelocitySkill(ROS2Skill):
    """Hold a requested forward speed and yaw rate on the MR-1 base."""

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
        self.command = Twist()
        self.command_timer = None

    @skill_parameter(
        is_required=True, name="inAngularVelocity", description="Requested yaw rate. Unit: rad/s."
    )
    def get_in_angular_velocity(self) -> float:
        return self.in_angular_velocity

    @skill_parameter(
        is_required=True, name="inLinearVelocity", description="Requested forward speed. Unit: m/s."
    )
    def get_in_linear_velocity(self) -> float:
        return self.in_linear_velocity

    @skill_output(
        is_required=True, name="outAngularVelocity", description="Measured yaw rate. Unit: rad/s."
    )
    def get_out_angular_velocity(self) -> float:
        return self.out_angular_velocity

    @skill_output(
        is_required=True, name="outLinearVelocity", description="Measured forward speed. Unit: m/s."
    )
    def get_out_linear_velocity(self) -> float:
        return self.out_linear_velocity

    def _on_odom(self, msg: Odometry) -> None:
        """Keeps the latest message of /odom (nav_msgs/msg/Odometry)."""
        self.odom_msg = msg

    def _publish_command(self) -> None:
        self.cmd_vel_publisher.publish(self.command)

    def _publish_zero(self) -> None:
        if self.command_timer is not None:
            self.command_timer.cancel()
            self.node.destroy_timer(self.command_timer)
            self.command_timer = None
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @staticmethod
    def _clip(value: float, limit: float) -> float:
        return max(-limit, min(limit, value))

    @starting
    def starting(self) -> None:
        """Check that wheel odometry is arriving (wait at most 2 s, abort otherwise) and
        open the publisher for the base velocity command.
        """
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)
        deadline = time.monotonic() + 2.0
        while self.odom_msg is None and time.monotonic() < deadline:
            time.sleep(0.05)
        if self.odom_msg is None:
            raise RuntimeError("no odometry on /odom within 2 s; is the base driver running?")
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)

    @execute
    def execute(self) -> None:
        """Clip the requested velocities to the limits, hold them with a 20 Hz timer and wait
        until odometry confirms them; store the measured velocities as outputs.
        """
        linear = self._clip(self.in_linear_velocity, self.LINEAR_VELOCITY_MAX)
        angular = self._clip(self.in_angular_velocity, self.ANGULAR_VELOCITY_MAX)
        if linear != self.in_linear_velocity or angular != self.in_angular_velocity:
            self.node.get_logger().warning(
                f"velocity clipped to {linear:.2f} m/s, {angular:.2f} rad/s (MR-1 limits)"
            )
        self.command = Twist()
        self.command.linear.x = linear
        self.command.angular.z = angular
        self.command_timer = self.node.create_timer(0.05, self._publish_command)

        settled_since = None
        deadline = time.monotonic() + 5.0
        while time.monotonic() < deadline:
            twist = self.odom_msg.twist.twist
            close = abs(twist.linear.x - linear) <= 0.05 and abs(twist.angular.z - angular) <= 0.05
            now = time.monotonic()
            if not close:
                settled_since = None
            elif settled_since is None:
                settled_since = now
            elif now - settled_since >= 0.5:
                self.out_linear_velocity = twist.linear.x
                self.out_angular_velocity = twist.angular.z
                return
            time.sleep(0.02)
        self._publish_zero()
        raise RuntimeError("the base did not reach the commanded velocity within 5 s")

    @completing
    def completing(self) -> None:
        """Log the commanded and the measured velocities; leave the command timer running."""
        self.node.get_logger().info(
            f"commanded {self.command.linear.x:.2f} m/s, {self.command.angular.z:.2f} rad/s; "
            f"measured {self.out_linear_velocity:.2f} m/s, {self.out_angular_velocity:.2f} rad/s"
        )

    @stopping
    def stopping(self) -> None:
        """Cancel the command timer and publish a zero velocity command three times, 50 ms apart."""
        for _ in range(3):
            self._publish_zero()
            time.sleep(0.05)

    @resetting
    def resetting(self) -> None:
        """Make sure the command timer is cancelled and the base is commanded to zero, then
        clear the stored outputs.
        """
        self._publish_zero()
        self.out_linear_velocity = 0.0
        self.out_angular_velocity = 0.0
        if self.cmd_vel_publisher is not None:
            self.node.destroy_publisher(self.cmd_vel_publisher)
            self.cmd_vel_publisher = None
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
