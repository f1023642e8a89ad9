"""move_forward: drive the MR-1 straight ahead over a distance, measured with odometry."""

import math
import time

import rclpy

from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


@skill(
    skill_interface=SkillInterface.REST,
    skill_iri="http://skillwright.dev/robots/mr1/skills/move_forward",
    module_iri="http://skillwright.dev/robots/mr1/mr1",
    capability_iri="http://skillwright.dev/robots/mr1/capabilities/moveForward/moveForward",
    description="Drive the MR-1 base straight ahead over a requested distance at a requested speed, measured with wheel odometry, and stop it at the end.",
)
class MoveForwardSkill(ROS2Skill):
    """Drive straight ahead until odometry shows the requested distance, then stop."""

    LINEAR_VELOCITY_MAX = 0.8  # resource requirement: linearVelocity <= 0.8 m/s
    FINAL_APPROACH = 0.1  # m: the last stretch is driven slowly so the stop is precise
    FINAL_SPEED = 0.1  # m/s
    DECELERATION = 0.8  # m/s^2: below what the base can brake, so the profile is always kept

    def __init__(self) -> None:
        super().__init__("move_forward")
        self.in_distance: float = 0.0
        self.in_linear_velocity: float = 0.0
        self.out_distance: float = 0.0
        self.out_linear_velocity: float = 0.0
        self.cmd_vel_publisher = None
        self.odom_subscription = None
        self.odom_msg: Odometry | None = None
        self.start_position: tuple[float, float] | None = None
        self.moving = False

    @skill_parameter(is_required=True, name="inDistance", description="Distance to drive. Unit: m.")
    def get_in_distance(self) -> float:
        return self.in_distance

    @skill_parameter(is_required=True, name="inLinearVelocity", description="Requested speed. Unit: m/s.")
    def get_in_linear_velocity(self) -> float:
        return self.in_linear_velocity

    @skill_output(is_required=True, name="outDistance", description="Distance travelled. Unit: m.")
    def get_out_distance(self) -> float:
        return self.out_distance

    @skill_output(is_required=True, name="outLinearVelocity", description="Final speed. Unit: m/s.")
    def get_out_linear_velocity(self) -> float:
        return self.out_linear_velocity

    def _on_odom(self, msg: Odometry) -> None:
        self.odom_msg = msg

    def _travelled(self) -> float:
        position = self.odom_msg.pose.pose.position
        return math.hypot(position.x - self.start_position[0], position.y - self.start_position[1])

    def _publish_zero(self) -> None:
        self.moving = False
        if self.cmd_vel_publisher is not None:
            self.cmd_vel_publisher.publish(Twist())

    @starting
    def starting(self) -> None:
        """Check the distance, subscribe to wheel odometry and wait at most 2 s for it."""
        if self.in_distance < 0.0:
            raise ValueError(f"the distance must not be negative, got {self.in_distance} m")
        self.cmd_vel_publisher = self.node.create_publisher(Twist, "/cmd_vel", 10)
        self.odom_subscription = self.node.create_subscription(Odometry, "/odom", self._on_odom, 10)
        deadline = time.monotonic() + 2.0
        while self.odom_msg is None and time.monotonic() < deadline:
            time.sleep(0.05)
        if self.odom_msg is None:
            raise RuntimeError("no odometry on /odom within 2 s; is the base driver running?")

    @execute
    def execute(self) -> None:
        """Drive at the clipped speed, slowly over the last 0.1 m, stop at the distance and
        wait until odometry shows the base standing."""
        position = self.odom_msg.pose.pose.position
        self.start_position = (position.x, position.y)
        speed = abs(self.in_linear_velocity)
        if speed > self.LINEAR_VELOCITY_MAX:
            self.node.get_logger().warning(
                f"speed {speed:.2f} m/s clipped to the MR-1's {self.LINEAR_VELOCITY_MAX} m/s"
            )
            speed = self.LINEAR_VELOCITY_MAX
        command = Twist()
        self.moving = True
        while self.moving and self._travelled() < self.in_distance:
            remaining = self.in_distance - self._travelled()
            # Brake early enough for the base to reach the final speed by the last stretch.
            braking = math.sqrt(2.0 * self.DECELERATION * max(remaining - self.FINAL_APPROACH, 0.0))
            command.linear.x = min(speed, max(braking, self.FINAL_SPEED))
            self.cmd_vel_publisher.publish(command)
            time.sleep(0.05)
        self._publish_zero()
        deadline = time.monotonic() + 5.0
        while abs(self.odom_msg.twist.twist.linear.x) >= 0.01 and time.monotonic() < deadline:
            time.sleep(0.02)
        self.out_distance = self._travelled()
        self.out_linear_velocity = self.odom_msg.twist.twist.linear.x

    @completing
    def completing(self) -> None:
        """Log the requested and the travelled distance and their difference."""
        self.node.get_logger().info(
            f"asked {self.in_distance:.3f} m, travelled {self.out_distance:.3f} m, "
            f"difference {self.out_distance - self.in_distance:+.3f} m"
        )

    @stopping
    def stopping(self) -> None:
        """Stop the forward command and publish a zero velocity at once."""
        self._publish_zero()

    @resetting
    def resetting(self) -> None:
        """Publish zero, drop the odometry subscription, clear the start and the outputs."""
        self._publish_zero()
        if self.odom_subscription is not None:
            self.node.destroy_subscription(self.odom_subscription)
            self.odom_subscription = None
        self.odom_msg = None
        self.start_position = None
        self.out_distance = 0.0
        self.out_linear_velocity = 0.0
