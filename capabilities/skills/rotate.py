"""rotate: turn the MR-1 on the spot by a signed angle, watching the heading in the map."""

import math
import time

import rclpy
from rclpy.duration import Duration
from rclpy.time import Time
from tf2_ros import Buffer, TransformException, TransformListener

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


def _wrap(angle: float) -> float:
    """Angle wrapped into [-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/rotate",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/rotate/rotate",
    description="Turn the MR-1 base on the spot by a signed angle at a requested yaw rate, and stop once the resulting heading is reached.",
)
class RotateSkill(ROS2Skill):
    """Turn by ``inAngle`` at ``inAngularVelocity``, then stop."""

    ANGULAR_VELOCITY_MAX = 1.2  # resource requirement: angularVelocity <= 1.2 rad/s
    MAP_FRAME = "map"
    BASE_FRAME = "base_link"
    TOLERANCE = 0.01  # rad

    def __init__(self) -> None:
        super().__init__("rotate")
        self.in_angle: float = 0.0
        self.in_angular_velocity: float = 0.0
        self.out_angular_velocity: float = 0.0
        self.out_heading: float = 0.0
        self.target_heading: float | None = None
        self.remaining: float = 0.0
        self.tf_buffer = None
        self.tf_listener = None
        self.cmd_vel_publisher = None
        self.odom_subscription = None
        self.odom_msg: Odometry | None = None
        self.turning = False

    @skill_parameter(is_required=True, name="inAngle", description="Signed angle to turn. Unit: rad.")
    def get_in_angle(self) -> float:
        return self.in_angle

    @skill_parameter(is_required=True, name="inAngularVelocity", description="Yaw rate. Unit: rad/s.")
    def get_in_angular_velocity(self) -> float:
        return self.in_angular_velocity

    @skill_output(is_required=True, name="outAngularVelocity", description="Final yaw rate. Unit: rad/s.")
    def get_out_angular_velocity(self) -> float:
        return self.out_angular_velocity

    @skill_output(is_required=True, name="outHeading", description="Final heading in [0, 2*pi). Unit: rad.")
    def get_out_heading(self) -> float:
        return self.out_heading

    def _on_odom(self, msg: Odometry) -> None:
        self.odom_msg = msg

    def _heading(self) -> float:
        """Yaw of base_link in the map frame, in [-pi, pi]."""
        transform = self.tf_buffer.lookup_transform(
            self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=0.5)
        )
        q = transform.transform.rotation
        return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))

    def _publish_zero(self) -> None:
        self.turning = False
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @starting
    def starting(self) -> None:
        """Make sure the heading of base_link in the map can be read (at most 2 s)."""
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self.node)
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)
        if not self.tf_buffer.can_transform(
            self.MAP_FRAME, self.BASE_FRAME, Time(), timeout=Duration(seconds=2.0)
        ):
            raise RuntimeError(f"no {self.MAP_FRAME} -> {self.BASE_FRAME} transform within 2 s")

    @execute
    def execute(self) -> None:
        """Turn towards (heading + angle) mod 2*pi, counting full turns, slowing near the end;
        stop, wait for the yaw rate to settle and store the heading and yaw rate."""
        try:
            previous = self._heading()
        except TransformException as error:
            raise RuntimeError(f"cannot read the heading: {error}") from error
        self.target_heading = (previous + self.in_angle) % (2.0 * math.pi)
        rate = abs(self.in_angular_velocity)
        if rate > self.ANGULAR_VELOCITY_MAX:
            self.node.get_logger().warning(
                f"yaw rate {rate:.2f} rad/s clipped to {self.ANGULAR_VELOCITY_MAX} rad/s"
            )
            rate = self.ANGULAR_VELOCITY_MAX
        direction = 1.0 if self.in_angle >= 0.0 else -1.0
        turned = 0.0
        self.remaining = self.in_angle
        command = Twist()
        self.turning = True
        while self.turning and abs(self.remaining) >= self.TOLERANCE:
            heading = self._heading()
            turned += _wrap(heading - previous)
            previous = heading
            self.remaining = self.in_angle - turned
            # Slow down over the last 0.3 rad so the stop lands within the tolerance.
            command.angular.z = direction * max(0.05, min(rate, abs(self.remaining) * 2.0))
            if self.remaining * direction < 0.0:
                command.angular.z = -command.angular.z
            self.cmd_vel_publisher.publish(command)
            time.sleep(0.05)
        self._publish_zero()
        deadline = time.monotonic() + 3.0
        while time.monotonic() < deadline:
            if self.odom_msg is not None and abs(self.odom_msg.twist.twist.angular.z) < 0.01:
                break
            time.sleep(0.02)
        self.out_heading = self._heading() % (2.0 * math.pi)
        self.out_angular_velocity = self.odom_msg.twist.twist.angular.z if self.odom_msg else 0.0

    @completing
    def completing(self) -> None:
        """Log the target heading, the reached heading and the remaining error."""
        error = _wrap(self.target_heading - self.out_heading)
        self.node.get_logger().info(
            f"target {self.target_heading:.3f} rad, reached {self.out_heading:.3f} rad, "
            f"error {error:+.4f} rad"
        )

    @stopping
    def stopping(self) -> None:
        """Publish a zero velocity at once."""
        self._publish_zero()

    @resetting
    def resetting(self) -> None:
        """Publish zero and clear the target and the outputs."""
        self._publish_zero()
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
        self.target_heading = None
        self.remaining = 0.0
        self.out_heading = 0.0
        self.out_angular_velocity = 0.0
